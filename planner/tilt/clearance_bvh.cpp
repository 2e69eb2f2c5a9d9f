// The planner's triangle hierarchy: oriented boxes, parallel build, nearest-point query.
#include "clearance_bvh.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace tf {
using Eigen::Vector3d;

namespace {

constexpr int kLeaf = 4;
// Below this many triangles a subtree is built by one thread.
constexpr int kParallelGrain = 16384;
// Nodes of up to this many triangles get an oriented box (above, the axis-aligned one); up to kScanMax
// its extents come from the vertices, above from the children's boxes.
constexpr int kOrientedMax = 4096;
constexpr int kScanMax = 64;

struct Aabb {
  Vector3d lo, hi;
};

// Nodes of the subtree over n triangles (median split, leaves of at most kLeaf): memoised per size, and
// filled in before the parallel build, which only reads it.
int subtree_nodes(int n, std::map<int, int>& memo) {
  if (n <= kLeaf) return 1;
  const auto it = memo.find(n);
  if (it != memo.end()) return it->second;
  const int c = 1 + subtree_nodes(n / 2, memo) + subtree_nodes(n - n / 2, memo);
  memo[n] = c;
  return c;
}

// A triangle's centroid (single precision: it only steers the splits) and index, moved as one so that
// the splits read memory in order.
struct Centroid {
  float c[3];
  int32_t index;
};

struct Builder {
  std::vector<Centroid>& items;
  std::vector<ClearanceBvh::Node>& nodes;
  std::vector<std::pair<int, int>>& range;
  const std::map<int, int>& memo;

  int count(int n) const { return n <= kLeaf ? 1 : memo.at(n); }

  void run(int begin, int end, int index) {
    range[static_cast<size_t>(index)] = {begin, end};
    ClearanceBvh::Node& nd = nodes[static_cast<size_t>(index)];
    if (end - begin <= kLeaf) {
      nd.first = begin;
      nd.count = end - begin;
      return;
    }
    float clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = begin; i < end; ++i) {
      const float* c = items[static_cast<size_t>(i)].c;
      for (int k = 0; k < 3; ++k) {
        clo[k] = std::min(clo[k], c[k]);
        chi[k] = std::max(chi[k], c[k]);
      }
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    const int mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                     [axis](const Centroid& x, const Centroid& y) { return x.c[axis] < y.c[axis]; });
    const int left = index + 1, right = index + 1 + count(mid - begin);
    if (end - begin > kParallelGrain)
      tbb::parallel_invoke([&] { run(begin, mid, left); }, [&] { run(mid, end, right); });
    else {
      run(begin, mid, left);
      run(mid, end, right);
    }
    nd.first = right;
    nd.count = 0;
  }
};

// Additive statistics of a node's triangles: area vector (sum of the cross products), area, and the
// first and second moments of the vertices about a common reference point.
struct Stats {
  Vector3d area_vec = Vector3d::Zero(), sum = Vector3d::Zero();
  Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
  double area = 0, count = 0;
};

// Fits every node's box, children first (post-order, in parallel over large subtrees), on the
// triangles already in leaf order.
struct Fitter {
  const std::vector<Triangle>& tris;
  std::vector<ClearanceBvh::Node>& nodes;
  const std::vector<std::pair<int, int>>& range;
  std::vector<Aabb>& box;
  Vector3d ref;

  Stats fit(int index) {
    ClearanceBvh::Node& nd = nodes[static_cast<size_t>(index)];
    const auto [b, e] = range[static_cast<size_t>(index)];
    Aabb bx{Vector3d::Constant(std::numeric_limits<double>::infinity()),
            Vector3d::Constant(-std::numeric_limits<double>::infinity())};
    const Stats st = nd.count > 0 ? leaf_stats(b, e, bx) : children_stats(index, b, e, bx);
    box[static_cast<size_t>(index)] = bx;
    // The axis-aligned box first; half extents get a rounding allowance so that the bounds stay bounds
    // in floating point.
    const double pad = 1e-12 * (1 + bx.lo.cwiseAbs().cwiseMax(bx.hi.cwiseAbs()).maxCoeff());
    nd.axes.setIdentity();
    nd.centre = 0.5 * (bx.lo + bx.hi);
    nd.half = 0.5 * (bx.hi - bx.lo) + Vector3d::Constant(pad);
    // Nodes whose normals largely cancel (both faces of a thin blade, a sharp edge) keep the axis-aligned
    // box, and so do large nodes (curved patches: neither box is tight).
    if (e - b > kOrientedMax || !(st.area > 0) || st.area_vec.norm() < 0.5 * st.area) return st;
    fit_oriented_box(index, b, e, st, bx, pad);
    return st;
  }

 private:
  // Statistics and axis-aligned box of the leaf's triangles [b, e).
  Stats leaf_stats(int b, int e, Aabb& bx) const {
    Stats st;
    for (int i = b; i < e; ++i) {
      const Triangle& t = tris[static_cast<size_t>(i)];
      const Vector3d c = (t.b - t.a).cross(t.c - t.a);
      st.area_vec += c;
      st.area += c.norm();
      for (const Vector3d* v : {&t.a, &t.b, &t.c}) {
        const Vector3d d = *v - ref;
        st.sum += d;
        st.sq += d * d.transpose();
        bx.lo = bx.lo.cwiseMin(*v);
        bx.hi = bx.hi.cwiseMax(*v);
      }
    }
    st.count = 3.0 * (e - b);
    return st;
  }

  // Fits both children of an inner node over [b, e), then sums their statistics and joins their boxes.
  Stats children_stats(int index, int b, int e, Aabb& bx) {
    const int left = index + 1, right = nodes[static_cast<size_t>(index)].first;
    Stats st, l, r;
    if (e - b > kParallelGrain)
      tbb::parallel_invoke([&] { l = fit(left); }, [&] { r = fit(right); });
    else {
      l = fit(left);
      r = fit(right);
    }
    st.area_vec = l.area_vec + r.area_vec;
    st.sum = l.sum + r.sum;
    st.sq = l.sq + r.sq;
    st.area = l.area + r.area;
    st.count = l.count + r.count;
    const Aabb& bl = box[static_cast<size_t>(left)];
    const Aabb& br = box[static_cast<size_t>(right)];
    bx = {bl.lo.cwiseMin(br.lo), bl.hi.cwiseMax(br.hi)};
    return st;
  }

  // The oriented box's axes (rows): the area-weighted mean normal, then in its plane the principal
  // direction of the vertices. Not finite when the statistics are degenerate.
  static Eigen::Matrix3d principal_axes(const Stats& st) {
    const Vector3d nrm = st.area_vec.normalized();
    const Eigen::Matrix3d cov = st.sq - st.sum * st.sum.transpose() / st.count;
    const Vector3d b1 = nrm.unitOrthogonal(), b2 = nrm.cross(b1);
    const double cxx = b1.dot(cov * b1), cyy = b2.dot(cov * b2), cxy = b1.dot(cov * b2);
    const double th = 0.5 * std::atan2(2 * cxy, cxx - cyy);
    Eigen::Matrix3d axes;
    axes.row(0) = nrm;
    axes.row(1) = (std::cos(th) * b1 + std::sin(th) * b2).normalized();
    axes.row(2) = nrm.cross(Vector3d(axes.row(1))).normalized();
    return axes;
  }

  // Extents [lo, hi] of node `index` (triangles [b, e)) along `axes`: exact from the vertices for small
  // nodes, else from the children's boxes projected on the axes.
  void oriented_extents(int index, int b, int e, const Eigen::Matrix3d& axes, Vector3d& lo, Vector3d& hi) const {
    if (e - b <= kScanMax) {
      for (int i = b; i < e; ++i) {
        const Triangle& t = tris[static_cast<size_t>(i)];
        for (const Vector3d* v : {&t.a, &t.b, &t.c}) {
          const Vector3d l = axes * (*v);
          lo = lo.cwiseMin(l);
          hi = hi.cwiseMax(l);
        }
      }
    } else {
      for (int child : {index + 1, nodes[static_cast<size_t>(index)].first}) {
        const ClearanceBvh::Node& c = nodes[static_cast<size_t>(child)];
        const Vector3d mid = axes * c.centre;
        const Vector3d h = (axes * c.axes.transpose()).cwiseAbs() * c.half;
        lo = lo.cwiseMin(mid - h);
        hi = hi.cwiseMax(mid + h);
      }
    }
  }

  // Gives node `index` the oriented box when it is smaller than its axis-aligned box bx.
  void fit_oriented_box(int index, int b, int e, const Stats& st, const Aabb& bx, double pad) {
    const Eigen::Matrix3d axes = principal_axes(st);
    if (!axes.allFinite()) return;
    Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    oriented_extents(index, b, e, axes, lo, hi);
    const Vector3d half = 0.5 * (hi - lo);
    if (half.prod() >= (0.5 * (bx.hi - bx.lo)).prod()) return;  // the axis-aligned box is the smaller
    ClearanceBvh::Node& nd = nodes[static_cast<size_t>(index)];
    nd.axes = axes;
    nd.centre = axes.transpose() * (0.5 * (lo + hi));
    // The centre went through a rotation and back: allow for its rounding too.
    nd.half = half + Vector3d::Constant(pad + 1e-12 * (1 + nd.centre.cwiseAbs().maxCoeff()));
  }
};

}  // namespace

ClearanceBvh::ClearanceBvh(const std::vector<const Mesh*>& meshes) : ClearanceBvh(mesh_triangles(meshes)) {}

ClearanceBvh::ClearanceBvh(std::vector<Triangle> triangles) : tris_(std::move(triangles)) { build(); }

Eigen::AlignedBox3d ClearanceBvh::bounds() const { return bounds_; }

void ClearanceBvh::build() {
  nodes_.clear();
  if (tris_.empty()) return;
  const int n = static_cast<int>(tris_.size());
  std::vector<Centroid> items(tris_.size());
  tbb::parallel_for(size_t{0}, tris_.size(), [&](size_t i) {
    const Vector3d c = (tris_[i].a + tris_[i].b + tris_[i].c) / 3.0;
    items[i] = {{static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z())}, static_cast<int32_t>(i)};
  });
  std::map<int, int> memo;
  const int total = subtree_nodes(n, memo);
  nodes_.assign(static_cast<size_t>(total), Node{});
  std::vector<std::pair<int, int>> range(static_cast<size_t>(total));
  Builder{items, nodes_, range, memo}.run(0, n, 0);
  // Leaves address contiguous ranges of the permuted order: store the triangles in that order.
  {
    std::vector<Triangle> sorted(tris_.size());
    tbb::parallel_for(size_t{0}, items.size(), [&](size_t i) { sorted[i] = tris_[static_cast<size_t>(items[i].index)]; });
    tris_ = std::move(sorted);
  }
  std::vector<Aabb> box(static_cast<size_t>(total));
  Fitter{tris_, nodes_, range, box, tris_[0].a}.fit(0);
  bounds_ = Eigen::AlignedBox3d(box[0].lo, box[0].hi);
}

ClosestHit ClearanceBvh::closest(const Vector3d& p, double max_distance, int hint) const {
  return internal::closest_triangle_point(tris_, p, max_distance, hint, [&](const auto& leaf, double start) {
    minimum([&](const Node& nd) { return point_node_bound_squared(nd, p); }, leaf, start);
  });
}

}  // namespace tf
