// tiltfield report: meshes for the 3-D view (decimated to a triangle budget by core's mesh_decimate)
// packed compactly (quantised Uint16 positions, Uint16/Uint32 indices, Float32 per-vertex values,
// base64) for the embedded JSON that the viewer script decodes.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/mesh_decimate.hpp"

namespace tf::reporting {

// A shared-vertex triangle mesh in single precision with an optional scalar per vertex.
struct IndexedMesh {
  std::vector<Eigen::Vector3f> V;             // mm
  std::vector<std::array<uint32_t, 3>> F;     // counter-clockwise from outside
  std::vector<float> values;                  // empty, or one per vertex (e.g. deviation, mm)
  std::vector<uint32_t> labels;               // empty, or one per vertex (e.g. the block that cut there)
};

// Single-precision copies for packing. `values` (may be null) must hold one entry per vertex.
IndexedMesh to_indexed(const IndexedTriangles& mesh);
IndexedMesh to_indexed(const Mesh& mesh, const std::vector<double>* values);

// Standard base64 (RFC 4648, with padding) of raw bytes.
std::string base64(const void* data, size_t bytes);

// The viewer's mesh record: {"positions": b64 Uint16 x3, "origin": [..], "scale": [..] (mm per unit),
// "indices": b64, "index_bits": 16|32, "values": b64 Float32 and "labels": b64 Uint32 (only when present),
// "triangles": n}.
// Quantisation error is at most half a unit: bounding-box size / 131070 per axis.
nlohmann::json encode_mesh(const IndexedMesh& mesh);

// Float32 array as base64 (line segments, points).
std::string base64_floats(const std::vector<float>& v);

}  // namespace tf::reporting
