// tiltfield tilt (internal): which cutter locations lie inside a solid obstacle.
//
// The planner's clearances are distances to triangles, which are the same inside a solid as outside it:
// a path buried in a closed check surface read as clear by 28 mm (found by black-box testing). The tool
// body is connected, so when it keeps a positive distance from a solid's surface it lies wholly on the side
// of any one of its points; the cutter location decides.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "tiltfield/core/mesh.hpp"

namespace tf {

// In: obstacle sets (each a list of meshes) and points (mm). A mesh is a solid when it is closed and
// outward oriented (signed volume > 0), as the verifier counts one. Out: per point, the index of the first
// set with a solid that contains it, or -1 (core's inside_solid: the winding number along three rays).
std::vector<int8_t> points_inside_solids(const std::vector<std::vector<const Mesh*>>& sets,
                                         const std::vector<Eigen::Vector3d>& points);

}  // namespace tf
