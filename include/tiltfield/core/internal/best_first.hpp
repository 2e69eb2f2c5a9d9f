// tiltfield core (internal): the best-first minimum over a bounding-volume hierarchy, shared by the
// core's axis-aligned TriangleBvh and the planner's oriented-box ClearanceBvh.
//
// Nodes are stored depth first: an inner node's left child follows it and `first` indexes its right
// child; a leaf holds triangles [first, first + count). Not part of the API: the hierarchies wrap it.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "tiltfield/core/triangle.hpp"

namespace tf::internal {

// The minimum of a quantity over the triangles under nodes[0], below `start` (or `start`).
// `node_bound(node)` is a lower bound of the quantity over a node's triangles; `leaf(i, best)` the quantity
// for triangle i (it may return any value >= best when it can prove triangle i cannot beat `best`).
// `stop_below`: return as soon as the minimum is known to be below it (a yes/no query).
template <class Node, class NodeBound, class Leaf>
double best_first_minimum(const std::vector<Node>& nodes, const NodeBound& node_bound, const Leaf& leaf, double start,
                          double stop_below) {
  double best = start;
  if (nodes.empty()) return best;
  struct Item {
    int node;
    double bound;
  };
  Item stack[128];  // the trees are balanced (median split): depth ~ log2(n / 4) + 1
  int top = 0;
  stack[top++] = {0, node_bound(nodes[0])};
  while (top > 0) {
    const Item it = stack[--top];
    if (it.bound >= best) continue;
    const Node& n = nodes[static_cast<size_t>(it.node)];
    if (n.count > 0) {
      for (int i = n.first; i < n.first + n.count; ++i) best = std::min(best, leaf(i, best));
      if (best < stop_below) return best;
      continue;
    }
    const int l = it.node + 1, r = n.first;
    const double bl = node_bound(nodes[static_cast<size_t>(l)]);
    const double br = node_bound(nodes[static_cast<size_t>(r)]);
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

// The nearest point of the triangles `tris` to p within max_distance (exclusive), for a hierarchy over
// them: triangle `hint` (or -1) seeds the bound, then `search(leaf, best2)` runs the hierarchy's
// best_first_minimum over squared distances with `leaf(i, best)`.
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

}  // namespace tf::internal
