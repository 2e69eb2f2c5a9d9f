// tiltfield core: exact nearest-point queries against a triangle soup.
//
// A bounding-volume hierarchy of axis-aligned boxes (median split) over the triangles of one or more
// meshes. In: meshes or triangles, mm. Out: exact point-to-triangle distances and closest points (the
// boxes only prune the search), so they do not depend on how a flat region is tessellated. Used by the
// re-planner's clearances, the report's stock deviation and the scene generators; the planner's own
// clearance queries use a tighter oriented-box hierarchy with the same search.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <vector>

#include "tiltfield/core/internal/best_first.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/triangle.hpp"

namespace tf {

class TriangleBvh {
 public:
  TriangleBvh() = default;
  // Takes every triangle of every mesh. Degenerate (zero-area) triangles are kept: they still bound the
  // surface's distance correctly.
  explicit TriangleBvh(const std::vector<const Mesh*>& meshes);
  explicit TriangleBvh(std::vector<Triangle> triangles);

  size_t size() const { return tris_.size(); }
  bool empty() const { return tris_.empty(); }
  const Triangle& triangle(int i) const { return tris_[static_cast<size_t>(i)]; }
  const std::vector<Triangle>& triangles() const { return tris_; }  // in leaf order, not input order
  // The position of triangle `i` among the triangles taken (the meshes' triangles in order, deleted faces
  // skipped, or the triangles given).
  int input_index(int i) const { return input_index_[static_cast<size_t>(i)]; }
  Eigen::AlignedBox3d bounds() const;

  // The nearest surface point to p within max_distance (exclusive). `hint` (a triangle index or -1) seeds
  // the search with that triangle's distance, which prunes most of the tree when queries are coherent.
  ClosestHit closest(const Eigen::Vector3d& p, double max_distance = std::numeric_limits<double>::infinity(),
                     int hint = -1) const;

  // Best-first minimum of a quantity over the triangles: `box_bound(lo, hi)` returns a lower bound of it
  // over a box of triangles, `leaf(i, best)` its value for triangle i (it may return any value >= best
  // when it can prove the triangle cannot beat `best`). Returns the minimum below `start` (or `start`).
  // `stop_below`: return as soon as the minimum is known to be below it (a yes/no query).
  template <class BoxBound, class Leaf>
  double minimum(const BoxBound& box_bound, const Leaf& leaf, double start,
                 double stop_below = -std::numeric_limits<double>::infinity()) const {
    return internal::best_first_minimum(
        nodes_, [&](const Node& n) { return box_bound(n.lo, n.hi); }, leaf, start, stop_below);
  }

  struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    int32_t first = 0;   // leaf: first triangle; inner: index of the right child (the left one follows)
    int32_t count = 0;   // leaf: number of triangles; inner: 0
  };

 private:
  void build();
  int build_range(int begin, int end, std::vector<int>& perm, const std::vector<Eigen::Vector3d>& centroid);

  std::vector<Triangle> tris_;  // reordered so that every leaf is a contiguous range
  std::vector<int> input_index_;  // per triangle of tris_
  std::vector<Node> nodes_;
};

// In: a hierarchy over a closed, outward-oriented mesh and a point, mm. Out: whether the point lies in
// the solid the mesh bounds: the winding number along three rays in unrelated directions (crossings
// counted with their sign), the majority of them (a ray through an edge or a vertex counts a crossing
// twice or not at all). Shared by the post's transit checks and the planner's rows.
bool inside_solid(const TriangleBvh& bvh, const Eigen::Vector3d& p);

}  // namespace tf
