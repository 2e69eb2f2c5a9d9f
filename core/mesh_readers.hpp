// tiltfield (internal): our own readers for STL, OBJ and OFF. OpenMesh's readers abort on malformed
// input (assertions in the Debian build), and a parser must never crash on a user's file.
#pragma once
#include <filesystem>

#include "tiltfield/core/mesh.hpp"

namespace tf::detail {

// Each throws InputError(file, line, field, ...) on malformed input; vertices shared by index (OBJ,
// OFF) or by identical coordinates (STL) are welded.
Mesh read_stl(const std::filesystem::path& file);
Mesh read_obj(const std::filesystem::path& file);
Mesh read_off(const std::filesystem::path& file);
Mesh read_ply(const std::filesystem::path& file);

// Builds a mesh from a triangle list. A triangle that OpenMesh cannot add to the half-edge structure
// (a non-manifold edge or vertex) is kept with its own copies of its vertices, so no geometry is lost.
// Degenerate triangles (repeated index) are dropped.
Mesh mesh_from_triangles(const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3i>& triangles);

}  // namespace tf::detail
