// Internal to the offset module: a static bounding-box hierarchy over 2-D boxes, for the pair and
// nearest-element queries of loop removal, validation and clearance (O(log n) instead of O(n)).
#pragma once
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace tf::offset::detail {

class BoxTree {
 public:
  BoxTree() = default;
  // boxes: one per item; the item's id is its index.
  explicit BoxTree(std::vector<Eigen::AlignedBox2d> boxes) : boxes_(std::move(boxes)) {
    order_.resize(boxes_.size());
    for (size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
    if (!order_.empty()) build(0, static_cast<int>(order_.size()));
  }

  // Calls visit(id) for every item whose box intersects `query`.
  template <class Visit>
  void query(const Eigen::AlignedBox2d& query, Visit&& visit) const {
    any(query, [&](int id) {
      visit(id);
      return false;
    });
  }

  // True when pred(id) holds for some item whose box intersects `query`; stops at the first.
  template <class Pred>
  bool any(const Eigen::AlignedBox2d& query, Pred&& pred) const {
    if (nodes_.empty()) return false;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!n.box.intersects(query)) continue;
      if (n.left < 0) {
        for (int k = n.begin; k < n.end; ++k)
          if (boxes_[order_[k]].intersects(query) && pred(order_[k])) return true;
      } else {
        stack[top++] = n.left;
        stack[top++] = n.right;
      }
    }
    return false;
  }

  // Nearest-item search: calls eval(id) -> a value (e.g. a distance) for items whose box lies closer to q
  // than the best value found so far plus `slack` (slack >= 0 widens the search for values that may be
  // below the box distance). Depth-first, nearer child first, no allocation. Returns the best value;
  // `best_id` receives its item.
  template <class Eval>
  double nearest(const Eigen::Vector2d& q, double slack, Eval&& eval, int* best_id = nullptr) const {
    double best = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return best;
    struct Entry {
      double d;
      int node;
    };
    Entry stack[128];
    int top = 0;
    stack[top++] = {0.0, 0};
    while (top > 0) {
      const Entry e = stack[--top];
      if (e.d - slack >= best) continue;
      const Node& n = nodes_[e.node];
      if (n.left < 0) {
        for (int k = n.begin; k < n.end; ++k) {
          if (std::sqrt(boxes_[order_[k]].squaredExteriorDistance(q)) - slack >= best) continue;
          const double v = eval(order_[k]);
          if (v < best) {
            best = v;
            if (best_id) *best_id = order_[k];
          }
        }
      } else {
        const double dl = std::sqrt(nodes_[n.left].box.squaredExteriorDistance(q));
        const double dr = std::sqrt(nodes_[n.right].box.squaredExteriorDistance(q));
        // Push the farther child first so the nearer one is searched first.
        if (dl <= dr) {
          stack[top++] = {dr, n.right};
          stack[top++] = {dl, n.left};
        } else {
          stack[top++] = {dl, n.left};
          stack[top++] = {dr, n.right};
        }
      }
    }
    return best;
  }

  size_t size() const { return boxes_.size(); }
  const Eigen::AlignedBox2d& box(int id) const { return boxes_[id]; }

 private:
  struct Node {
    Eigen::AlignedBox2d box;
    int left = -1, right = -1, begin = 0, end = 0;
  };

  int build(int begin, int end) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    Eigen::AlignedBox2d box;
    box.setEmpty();
    for (int k = begin; k < end; ++k) box.extend(boxes_[order_[k]]);
    nodes_[id].box = box;
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    if (end - begin <= 4) return id;
    const int axis = box.sizes().x() >= box.sizes().y() ? 0 : 1;
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int x, int y) {
      return boxes_[x].center()[axis] < boxes_[y].center()[axis];
    });
    const int l = build(begin, mid);
    const int r = build(mid, end);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }

  std::vector<Eigen::AlignedBox2d> boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace tf::offset::detail
