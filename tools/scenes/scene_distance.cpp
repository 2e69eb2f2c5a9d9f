#include "scene_distance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace tf::scenes {

MeshDistance::MeshDistance(const Mesh& mesh) {
  for (auto f : mesh.faces()) {
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = to_eigen(mesh.point(v));
    tri_.push_back({p[0], p[1], p[2]});
    centroid_.push_back((p[0] + p[1] + p[2]) / 3.0);
  }
  order_.resize(tri_.size());
  for (size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
  nodes_.reserve(2 * tri_.size() / 4 + 2);
  if (!tri_.empty()) build(0, static_cast<int>(tri_.size()));
}

int MeshDistance::build(int begin, int end) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Eigen::AlignedBox3d box, cbox;
  for (int i = begin; i < end; ++i) {
    const Tri& t = tri_[order_[i]];
    box.extend(t.a).extend(t.b).extend(t.c);
    cbox.extend(centroid_[order_[i]]);
  }
  nodes_[id].box = box;
  if (end - begin <= 4) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  int axis = 0;
  (cbox.max() - cbox.min()).maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int x, int y) { return centroid_[x][axis] < centroid_[y][axis]; });
  const int l = build(begin, mid);
  const int r = build(mid, end);
  nodes_[id].left = l;
  nodes_[id].right = r;
  return id;
}

double MeshDistance::nearest(const Eigen::Vector3d& p, double stop_above, Eigen::Vector3d* where) const {
  double best2 = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best2;
  const double stop2 = stop_above * stop_above;
  std::vector<std::pair<double, int>> stack;
  stack.reserve(64);
  stack.emplace_back(nodes_[0].box.squaredExteriorDistance(p), 0);
  while (!stack.empty()) {
    const auto [d2, id] = stack.back();
    stack.pop_back();
    if (d2 >= best2 || d2 > stop2) continue;
    const Node& n = nodes_[id];
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const Tri& t = tri_[order_[i]];
        const Eigen::Vector3d q = closest_point_on_triangle(p, t.a, t.b, t.c);
        const double e2 = (q - p).squaredNorm();
        if (e2 < best2) {
          best2 = e2;
          if (where) *where = q;
        }
      }
      continue;
    }
    const double dl = nodes_[n.left].box.squaredExteriorDistance(p);
    const double dr = nodes_[n.right].box.squaredExteriorDistance(p);
    // Nearer child last so it is popped first.
    if (dl < dr) {
      stack.emplace_back(dr, n.right);
      stack.emplace_back(dl, n.left);
    } else {
      stack.emplace_back(dl, n.left);
      stack.emplace_back(dr, n.right);
    }
  }
  return std::sqrt(best2);
}

double MeshDistance::distance(const Eigen::Vector3d& p, double stop_above) const {
  return nearest(p, stop_above, nullptr);
}

Eigen::Vector3d MeshDistance::closest_point(const Eigen::Vector3d& p) const {
  Eigen::Vector3d q = p;
  nearest(p, std::numeric_limits<double>::infinity(), &q);
  return q;
}

bool tool_axis_hits(const Tool& tool, const MeshDistance& obstacles, const Eigen::Vector3d& cl,
                    const Eigen::Vector3d& axis) {
  const double total = tool.total_length(), c = tool.cl_height();
  for (double h = c + 0.25; h <= total; h += 0.25) {
    const double rho = tool.radius_at(h);
    // The sphere of radius rho at height h lies in the body when the body's radius covers the sphere's
    // section at every height it spans (checked at 21 heights).
    bool inside = rho > 0;
    for (int k = -10; k <= 10 && inside; ++k) {
      const double hh = h + rho * k / 10.0;
      inside = tool.radius_at(hh) >= std::sqrt(std::max(0.0, rho * rho - (hh - h) * (hh - h))) - 1e-9;
    }
    if (inside && obstacles.distance(cl + (h - c) * axis, rho) < rho) return true;
  }
  return false;
}

}  // namespace tf::scenes
