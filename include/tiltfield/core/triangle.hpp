// tiltfield core: exact distances between points, segments and triangles, shared by the planner's
// clearances, the verifier's ray meshes and the scene generators.
//
// In: points and segment ends in mm (any frame, the same for all arguments). Out: distances in mm and
// closest points. Exact in double precision: no sampling, so results do not depend on how finely a
// flat region is tessellated. Degenerate (zero-area) triangles are handled as their edges.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "tiltfield/core/mesh.hpp"

namespace tf {

struct Triangle {
  Eigen::Vector3d a, b, c;
};

// Every triangle of every mesh, in order (faces with more than three vertices are skipped).
std::vector<Triangle> mesh_triangles(const std::vector<const Mesh*>& meshes);

// Closest point of triangle t to p (Ericson, Real-Time Collision Detection 5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Triangle& t);
// Smallest distance between segment [p0, p1] and triangle t (0 when they intersect), mm. `s`, when given,
// receives the parameter in [0, 1] on the segment of a closest point.
double segment_triangle_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Triangle& t,
                                 double* s = nullptr);
// Smallest distance between segments [p0, p1] and [q0, q1], mm; `s` as above for [p0, p1].
double segment_segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                                const Eigen::Vector3d& q1, double* s = nullptr);

// The nearest surface point found by a hierarchy's query.
struct ClosestHit {
  double distance = std::numeric_limits<double>::infinity();  // mm; infinity when nothing within the limit
  int triangle = -1;                                           // index in the hierarchy's triangles()
  Eigen::Vector3d point = Eigen::Vector3d::Zero();             // closest point on the surface
};

// Squared distance from p to the axis-aligned box [lo, hi], mm^2 (0 inside).
inline double box_distance_squared(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.squaredNorm();
}

}  // namespace tf
