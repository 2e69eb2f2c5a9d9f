// The stock as an obstacle for the non-cutting part of the tool (see stock_obstacle in replan.hpp).
#include <nanoflann.hpp>

#include <cmath>

#include "tiltfield/replan/replan.hpp"

namespace tf {

namespace {

struct PointCloud {
  const std::vector<CLPoint>* rows;
  size_t kdtree_get_point_count() const { return rows->size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return (*rows)[i].p[static_cast<int>(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>, PointCloud, 3>;

// Splits a triangle in four until no edge is longer than `edge`; appends the pieces.
void split(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double edge, int depth,
           std::vector<std::array<Eigen::Vector3d, 3>>& out) {
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  if (longest <= edge || depth > 12) {
    out.push_back({a, b, c});
    return;
  }
  const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  split(a, ab, ca, edge, depth + 1, out);
  split(ab, b, bc, edge, depth + 1, out);
  split(ca, bc, c, edge, depth + 1, out);
  split(ab, bc, ca, edge, depth + 1, out);
}

}  // namespace

Mesh stock_obstacle(const Mesh& stock, const ToolPath& path, const Tool& tool, const PlannerBasics& basics,
                    double edge_mm, double margin_mm) {
  // The farthest a point of the ball or flutes gets from the cutter location.
  const double above = std::max(0.0, tool.flute_length - tool.cl_height());
  const double below = tool.cl_height();
  const double reach = std::max(std::hypot(above, tool.radius()), std::hypot(below, tool.radius())) +
                       basics.safety_distance + margin_mm;
  // Only the neighbourhood the tool can reach at all needs fine triangles.
  Eigen::AlignedBox3d near;
  for (const auto& r : path.rows) near.extend(r.p);
  near.min().array() -= tool.total_length();
  near.max().array() += tool.total_length();

  PointCloud cloud{&path.rows};
  KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();

  std::vector<Eigen::Vector3d> V;
  std::vector<std::array<Eigen::Vector3d, 3>> pieces;
  for (auto f : stock.faces()) {
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : stock.fv_range(f)) p[k++] = to_eigen(stock.point(v));
    Eigen::AlignedBox3d box;
    for (const auto& q : p) box.extend(q);
    pieces.clear();
    if (box.intersects(near)) split(p[0], p[1], p[2], edge_mm, 0, pieces);
    else pieces.push_back({p[0], p[1], p[2]});
    for (const auto& t : pieces) {
      const Eigen::Vector3d centre = (t[0] + t[1] + t[2]) / 3.0;
      const double spread = std::max({(t[0] - centre).norm(), (t[1] - centre).norm(), (t[2] - centre).norm()});
      size_t idx = 0;
      double d2 = 0;
      nanoflann::KNNResultSet<double> rs(1);
      rs.init(&idx, &d2);
      tree.findNeighbors(rs, centre.data(), nanoflann::SearchParams());
      // Every point of the triangle is at least (centre distance - spread) from every cutter location.
      if (std::sqrt(d2) - spread < reach) continue;
      V.insert(V.end(), t.begin(), t.end());
    }
  }
  // Separate vertices per triangle: a triangle soup is all the distance queries need.
  Eigen::MatrixX3d VM(static_cast<Eigen::Index>(V.size()), 3);
  Eigen::MatrixX3i FM(static_cast<Eigen::Index>(V.size() / 3), 3);
  for (size_t i = 0; i < V.size(); ++i) VM.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
  for (Eigen::Index i = 0; i < FM.rows(); ++i) FM.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  return mesh_from_arrays(VM, FM);
}

}  // namespace tf
