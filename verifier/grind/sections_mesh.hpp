// tiltfield (internal): building blocks of the section tiling (sections_tiling.cpp, sections_stairs.cpp).
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "tiltfield/grind/sections.hpp"

namespace tf::grind::detail {

// Triangles of one slab. Vertex index >= 0: a section vertex (global id); < 0: new vertex -1 - i of `V`.
struct SlabMesh {
  std::vector<Eigen::Vector3d> V;
  std::vector<std::array<int, 3>> F;
  int add(const Eigen::Vector3d& p) {
    V.push_back(p);
    return -static_cast<int>(V.size());
  }
};

// A contour placed in space: its points, labels and the global ids of its vertices at height z.
struct PlacedContour {
  const Contour* contour;
  const std::vector<int>* ids;
  double z;
};

// Horizontal faces at z_mid closing the stair step between the regions bounded by `lower` (at z below) and
// `upper` (at z above): vertical walls from each lower contour up to z_mid and from z_mid up to each upper
// contour, and the exact triangulation of (lower XOR upper) at z_mid (lower-only faces up, upper-only faces
// down). Either side may be empty (a contour that vanishes or appears). Appends to `out`.
void stair_step(const std::vector<PlacedContour>& lower, const std::vector<PlacedContour>& upper, double z_mid,
                SlabMesh& out);

// The end cap of a section: triangulates the region bounded by `contours` at their height, facing down
// (`up` false, the z = 0 end) or up. Appends to `out`.
void end_cap(const std::vector<PlacedContour>& contours, bool up, SlabMesh& out);

}  // namespace tf::grind::detail
