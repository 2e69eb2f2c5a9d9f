// tiltfield tilt (internal): the triangle hierarchy behind the planner's exact clearances and its distance field.
//
// A bounding-volume hierarchy over a triangle soup (median split, built in parallel) whose nodes are
// oriented boxes. On a smooth surface a patch of size L lies in a box about L^2 / (8 rho) thin along
// its normal (rho the radius of curvature), so the distance bound of a node near a cylinder lying along
// a dense face is within a hair of the exact distance of its triangles; an axis-aligned box is off by up
// to its half diagonal whenever the face is oblique to the axes, and then a best-first search has to
// open thousands of triangles around the minimum.
//
// The bounds are only ever used to skip nodes, never as results: every distance returned is computed on
// the triangles themselves (exact point/segment-to-triangle distance, GJK for cylinder caps). Units: mm.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tool_body.hpp"
#include "tiltfield/core/internal/best_first.hpp"
#include "tiltfield/core/triangle.hpp"

namespace tf {

class ClearanceBvh {
 public:
  // A node bounds its triangles by an oriented box: the first axis their area-weighted normal, the second
  // the principal direction of their vertices in that plane; or the coordinate axes when those give the
  // smaller box, when the normals largely cancel (both faces of a thin blade), or for nodes of many
  // triangles (whose patches curve too much for either box to be tight).
  struct Node {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // rows: orthonormal axes
    Eigen::Vector3d half = Eigen::Vector3d::Zero();      // half extents along them, mm
    int32_t first = 0;  // leaf: first triangle; inner: index of the right child (the left one follows)
    int32_t count = 0;  // leaf: number of triangles; inner: 0
  };

  ClearanceBvh() = default;
  // Every triangle of every mesh (degenerate ones kept: they still bound the distance correctly).
  explicit ClearanceBvh(const std::vector<const Mesh*>& meshes);
  explicit ClearanceBvh(std::vector<Triangle> triangles);

  size_t size() const { return tris_.size(); }
  bool empty() const { return tris_.empty(); }
  const Triangle& triangle(int i) const { return tris_[static_cast<size_t>(i)]; }
  const std::vector<Triangle>& triangles() const { return tris_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  Eigen::AlignedBox3d bounds() const;

  // The nearest surface point to p within max_distance (exclusive); `hint` (a triangle or -1) seeds the
  // search. Same contract as TriangleBvh::closest.
  ClosestHit closest(const Eigen::Vector3d& p, double max_distance = std::numeric_limits<double>::infinity(),
                     int hint = -1) const;

  // Best-first minimum, as TriangleBvh::minimum, but `node_bound(node)` receives the whole node.
  template <class NodeBound, class Leaf>
  double minimum(const NodeBound& node_bound, const Leaf& leaf, double start,
                 double stop_below = -std::numeric_limits<double>::infinity()) const {
    return internal::best_first_minimum(nodes_, node_bound, leaf, start, stop_below);
  }

 private:
  void build();

  std::vector<Triangle> tris_;  // in leaf order: every leaf is a contiguous range
  std::vector<Node> nodes_;
  Eigen::AlignedBox3d bounds_;
};

// Lower bound of the squared distance from p to every triangle of a node (the box's exact one), mm^2.
[[gnu::always_inline]] inline double point_node_bound_squared(const ClearanceBvh::Node& nd, const Eigen::Vector3d& p) {
  const Eigen::Vector3d l = nd.axes * (p - nd.centre);
  return (l.cwiseAbs() - nd.half).cwiseMax(0.0).squaredNorm();
}

// Lower bound of the distance from segment [p0, p1] to every triangle of a node, mm (0 when they may
// touch): the largest gap along a few separating directions, in the box's frame (centre at the origin).
[[gnu::always_inline]] inline double segment_node_bound(const ClearanceBvh::Node& nd, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1) {
  const Eigen::Vector3d l0 = nd.axes * (p0 - nd.centre), l1 = nd.axes * (p1 - nd.centre);
  // The box axes: gap between the segment's interval and [-half, half],
  const Eigen::Vector3d lmin = l0.cwiseMin(l1), lmax = l0.cwiseMax(l1);
  double g = std::max(0.0, std::max((lmin - nd.half).maxCoeff(), (-nd.half - lmax).maxCoeff()));
  // and u, from the segment's point q nearest to the centre toward the centre: -q.(x - q) <= 0 for every
  // x on the segment, so the segment's largest offset along u = -q/|q| is u.q = -|q|, and the box's
  // least is -sum |u_k| half_k.
  const Eigen::Vector3d d = l1 - l0;
  const double dd = d.squaredNorm();
  const double t = dd > 0 ? std::clamp(-l0.dot(d) / dd, 0.0, 1.0) : 0.0;
  const Eigen::Vector3d q = l0 + t * d;
  const double L = q.norm();
  if (L > 0) g = std::max(g, L - q.cwiseAbs().dot(nd.half) / L);
  return g;
}

// Lower bound of the distance from a node's box to the cylinder of radius R about [p0, p1] (`out`: the
// unit direction from p1 to p0): the capsule's bound, and the box's height beyond the plane of either cap
// when it lies wholly beyond it. For a wide holder the capsule's hemisphere reaches R past its face, and
// its bound alone opened every node within R of it.
[[gnu::always_inline]] inline double cylinder_node_bound(const ClearanceBvh::Node& nd, const Eigen::Vector3d& p0,
                                                         const Eigen::Vector3d& p1, double R,
                                                         const Eigen::Vector3d& out) {
  const double reach = (nd.axes * out).cwiseAbs().dot(nd.half);  // the box's half extent along out
  const double beyond0 = (nd.centre - p0).dot(out) - reach;       // beyond p0's cap
  const double beyond1 = (p1 - nd.centre).dot(out) - reach;       // beyond p1's cap
  return std::max({segment_node_bound(nd, p0, p1) - R, beyond0, beyond1});
}

// The same exact queries as piece_distance / body_clearance (tool_body.hpp) on a ClearanceBvh. `hint`
// (per call one triangle index, or -1) seeds the search with that triangle's distance and receives the
// triangle that set the result: queries of nearby poses (consecutive rows) then prune almost the whole
// tree at once. Hints only speed the search up; results do not depend on them.
double piece_distance(const ClearanceBvh& bvh, const BodyPiece& piece, const Pose& pose, double limit,
                      bool first_below = false, int* hint = nullptr);
// Joins adjacent coaxial cylinders of the same radius that must keep the same clearance into one longer
// cylinder (a usual end mill's flutes and shank): they are exactly that cylinder, so the body's
// distance and margin stay the same, and one query replaces two. `required` follows the pieces. The
// joined piece keeps the lower one's component.
void merge_coaxial_pieces(std::vector<BodyPiece>& pieces, std::vector<double>& required);

// The order in which to query the pieces of body_pieces() (k-th query -> piece index). Results do not
// depend on it, only the pruning: the ball first, then the cylinders from the top down. A capsule
// encloses its cylinder with a hemisphere at each end; the upper one lies inside the next piece up
// whenever that one is at least as wide (flute under shank, shank under holder), so once the piece above
// is known (or known to clear), the triangles near the junction are pruned on the capsule bound instead
// of each needing the exact (GJK) cylinder distance.
size_t piece_query_order(const std::vector<BodyPiece>& pieces, size_t k);
// `hints`, when given, holds one hint per piece (resized as needed). `below`, when given, is a result
// already known (another obstacle set's): only distances and margins below it are searched for, and it
// is returned unchanged where none is found.
BodyClearance body_clearance(const ClearanceBvh& bvh, const std::vector<BodyPiece>& pieces,
                             const std::vector<double>& required, const Pose& pose, std::vector<int>* hints = nullptr,
                             const BodyClearance* below = nullptr);

}  // namespace tf
