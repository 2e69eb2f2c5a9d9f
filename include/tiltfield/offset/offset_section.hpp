// tiltfield offset: a profile from a part mesh: plane section, chaining, and line/arc fitting.
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/offset/offset.hpp"

namespace tf::offset {

struct SectionOptions {
  double tolerance = 0.01;  // largest distance of a section point from its fitted line or arc, mm
  int loop = 1;             // which loop of the section, by area: 1 the largest, 2 the next, ...
};

// A loop of the section other than the one taken: its polygon (mm), its area (mm2) and whether it lies
// inside the loop taken (a hole of it, such as a bore) or outside (another island).
struct SectionLoop {
  std::vector<Eigen::Vector2d> points;
  double area = 0;
  bool inside = false;
};

// "z=H" (spaces allowed) -> H in mm. Throws InputError(field "plane") otherwise.
double parse_plane(const std::string& text);

// Closed section polygons of a mesh with the plane z = z0, oriented counter-clockwise around material
// (seen from +z). Edges are split where they cross the plane; vertices exactly on the plane count as
// above it, so every crossing lies on an edge with one end strictly below.
std::vector<std::vector<Eigen::Vector2d>> section_loops(const Mesh& mesh, double z0);

// Lines and arcs through a closed polygon's points: each element is the longest run of consecutive points
// that a line (preferred) or a circular arc passes within `tolerance` of. Vertices only are checked; a
// coarsely faceted mesh therefore gives arcs through its facet corners.
Profile fit_profile(const std::vector<Eigen::Vector2d>& loop, double tolerance, const std::string& file);

// load_mesh, section at z0, the options.loop-th loop by area, fit_profile, validate_profile; the other
// loops in `left_out` (largest first) when given. Throws InputError naming the mesh when the plane misses
// it, when it has fewer loops than options.loop, and when the fitted profile is not valid (a section
// thinner than the tolerance).
Profile profile_from_mesh(const std::filesystem::path& mesh_file, double z0, const SectionOptions& options,
                          std::vector<SectionLoop>* left_out = nullptr);

}  // namespace tf::offset
