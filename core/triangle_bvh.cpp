// The axis-aligned triangle hierarchy (median split) and its nearest-point query.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {
using Eigen::Vector3d;

TriangleBvh::TriangleBvh(const std::vector<const Mesh*>& meshes) : TriangleBvh(mesh_triangles(meshes)) {}

TriangleBvh::TriangleBvh(std::vector<Triangle> triangles) : tris_(std::move(triangles)) { build(); }

Eigen::AlignedBox3d TriangleBvh::bounds() const {
  if (nodes_.empty()) return {};
  return {nodes_[0].lo, nodes_[0].hi};
}

void TriangleBvh::build() {
  nodes_.clear();
  input_index_.clear();
  if (tris_.empty()) return;
  std::vector<Vector3d> centroid(tris_.size());
  for (size_t i = 0; i < tris_.size(); ++i) centroid[i] = (tris_[i].a + tris_[i].b + tris_[i].c) / 3.0;
  std::vector<int> perm(tris_.size());
  std::iota(perm.begin(), perm.end(), 0);
  nodes_.reserve(tris_.size() / 2 + 16);
  build_range(0, static_cast<int>(tris_.size()), perm, centroid);
  // Leaves address contiguous ranges of the permuted order: store the triangles in that order.
  std::vector<Triangle> sorted(tris_.size());
  for (size_t i = 0; i < perm.size(); ++i) sorted[i] = tris_[static_cast<size_t>(perm[i])];
  tris_ = std::move(sorted);
  input_index_ = std::move(perm);
}

int TriangleBvh::build_range(int begin, int end, std::vector<int>& perm, const std::vector<Vector3d>& centroid) {
  constexpr int kLeaf = 4;
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Vector3d clo = lo, chi = hi;
  for (int i = begin; i < end; ++i) {
    const size_t k = static_cast<size_t>(perm[static_cast<size_t>(i)]);
    const Triangle& t = tris_[k];
    lo = lo.cwiseMin(t.a).cwiseMin(t.b).cwiseMin(t.c);
    hi = hi.cwiseMax(t.a).cwiseMax(t.b).cwiseMax(t.c);
    clo = clo.cwiseMin(centroid[k]);
    chi = chi.cwiseMax(centroid[k]);
  }
  nodes_[static_cast<size_t>(index)].lo = lo;
  nodes_[static_cast<size_t>(index)].hi = hi;
  if (end - begin <= kLeaf) {
    nodes_[static_cast<size_t>(index)].first = begin;
    nodes_[static_cast<size_t>(index)].count = end - begin;
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(perm.begin() + begin, perm.begin() + mid, perm.begin() + end, [&](int x, int y) {
    return centroid[static_cast<size_t>(x)][axis] < centroid[static_cast<size_t>(y)][axis];
  });
  build_range(begin, mid, perm, centroid);
  const int right = build_range(mid, end, perm, centroid);
  nodes_[static_cast<size_t>(index)].first = right;
  nodes_[static_cast<size_t>(index)].count = 0;
  return index;
}

ClosestHit TriangleBvh::closest(const Vector3d& p, double max_distance, int hint) const {
  return internal::closest_triangle_point(tris_, p, max_distance, hint, [&](const auto& leaf, double start) {
    minimum([&](const Vector3d& lo, const Vector3d& hi) { return box_distance_squared(p, lo, hi); }, leaf, start);
  });
}

}  // namespace tf
