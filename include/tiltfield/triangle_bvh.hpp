// tiltfield planner: exact distance queries against a triangle soup (the check surfaces).
//
// A bounding-volume hierarchy (axis-aligned boxes, median split) over the triangles. Distances are exact
// point-to-triangle distances, so they do not depend on how a flat region is tessellated. Units: mm.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "tiltfield/mesh.hpp"

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

struct ClosestHit {
  double distance = std::numeric_limits<double>::infinity();  // mm; infinity when nothing within the limit
  int triangle = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // closest point on the surface
};

// The nearest-point query both triangle hierarchies share: triangle `hint` (or -1) seeds the bound, then
// `search(leaf, best2)` runs the hierarchy's best-first minimum over squared distances with `leaf(i, best)`.
template <class Search>
ClosestHit closest_triangle_point(const std::vector<Triangle>& tris, const Eigen::Vector3d& p, double max_distance,
                                  int hint, const Search& search) {
  ClosestHit hit;
  double best2 = std::isinf(max_distance) ? std::numeric_limits<double>::infinity() : max_distance * max_distance;
  if (hint >= 0 && hint < static_cast<int>(tris.size())) {
    const Eigen::Vector3d q = closest_point_on_triangle(p, tris[static_cast<size_t>(hint)]);
    const double d2 = (q - p).squaredNorm();
    if (d2 < best2) {
      best2 = d2;
      hit = {std::sqrt(d2), hint, q};
    }
  }
  search(
      [&](int i, double best) {
        const Eigen::Vector3d q = closest_point_on_triangle(p, tris[static_cast<size_t>(i)]);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best) hit = {0.0, i, q}, best2 = d2;
        return d2;
      },
      best2);
  if (hit.triangle >= 0) hit.distance = std::sqrt(best2);
  return hit;
}

class TriangleBvh {
 public:
  TriangleBvh() = default;
  // Takes every triangle of every mesh. Degenerate (zero-area) triangles are kept: they still bound the
  // surface's distance correctly. Parallel build (TBB).
  explicit TriangleBvh(const std::vector<const Mesh*>& meshes);
  explicit TriangleBvh(std::vector<Triangle> triangles);

  size_t size() const { return tris_.size(); }
  bool empty() const { return tris_.empty(); }
  const Triangle& triangle(int i) const { return tris_[static_cast<size_t>(i)]; }
  const std::vector<Triangle>& triangles() const { return tris_; }
  Eigen::AlignedBox3d bounds() const;

  // The nearest surface point to p within max_distance (exclusive). `hint` (a triangle index or -1) seeds
  // the search with that triangle's distance, which prunes most of the tree when queries are coherent.
  ClosestHit closest(const Eigen::Vector3d& p, double max_distance = std::numeric_limits<double>::infinity(),
                     int hint = -1) const;

  // Generic best-first minimum: `box_bound(lo, hi)` returns a lower bound of the quantity over a box of
  // triangles, `leaf(i, best)` the quantity for triangle i (it may return any value >= best when it can
  // prove the triangle cannot beat `best`). Returns the minimum below `start` (or `start`).
  // `stop_below`: return as soon as the minimum is known to be below it (a yes/no query).
  template <class BoxBound, class Leaf>
  double minimum(const BoxBound& box_bound, const Leaf& leaf, double start,
                 double stop_below = -std::numeric_limits<double>::infinity()) const;

  struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    int32_t first = 0;   // leaf: first triangle in order_; inner: index of the right child
    int32_t count = 0;   // leaf: number of triangles; inner: 0 (left child follows the node)
  };

 private:
  void build();
  int build_range(int begin, int end, std::vector<int>& perm, const std::vector<Eigen::Vector3d>& centroid);

  std::vector<Triangle> tris_;  // reordered so that every leaf is a contiguous range
  std::vector<Node> nodes_;
};

template <class BoxBound, class Leaf>
double TriangleBvh::minimum(const BoxBound& box_bound, const Leaf& leaf, double start, double stop_below) const {
  double best = start;
  if (nodes_.empty()) return best;
  struct Item {
    int node;
    double bound;
  };
  Item stack[128];
  int top = 0;
  stack[top++] = {0, box_bound(nodes_[0].lo, nodes_[0].hi)};
  while (top > 0) {
    const Item it = stack[--top];
    if (it.bound >= best) continue;
    const Node& n = nodes_[static_cast<size_t>(it.node)];
    if (n.count > 0) {
      for (int i = n.first; i < n.first + n.count; ++i) best = std::min(best, leaf(i, best));
      if (best < stop_below) return best;
      continue;
    }
    const int l = it.node + 1, r = n.first;
    const double bl = box_bound(nodes_[static_cast<size_t>(l)].lo, nodes_[static_cast<size_t>(l)].hi);
    const double br = box_bound(nodes_[static_cast<size_t>(r)].lo, nodes_[static_cast<size_t>(r)].hi);
    // Push the farther child first so the nearer one is explored first.
    if (bl < br) {
      if (br < best) stack[top++] = {r, br};
      if (bl < best) stack[top++] = {l, bl};
    } else {
      if (bl < best) stack[top++] = {l, bl};
      if (br < best) stack[top++] = {r, br};
    }
  }
  return best;
}

// Squared distance from p to the box [lo, hi].
inline double box_distance_squared(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.squaredNorm();
}

}  // namespace tf
