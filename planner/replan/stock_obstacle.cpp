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

using Triangle = std::array<Eigen::Vector3d, 3>;

// Appends the parts of the triangle beyond `reach` of every cutter location: a triangle wholly beyond it
// is kept whole and one wholly within the reach of one location is dropped; one across it is split in four
// until its pieces' edges are at most `edge` long, and such a piece is dropped when it may come within
// reach. Only the pieces along the reach's boundary are small, so the soup grows with the boundary's length
// over the edge, not with the stock's area over its square (that took 10.7 GB for a tool of radius 0.5).
void crop(const Triangle& t, double edge, double reach, const KdTree& tree, int depth, std::vector<Triangle>& out) {
  const Eigen::Vector3d centre = (t[0] + t[1] + t[2]) / 3.0;
  const double spread = std::max({(t[0] - centre).norm(), (t[1] - centre).norm(), (t[2] - centre).norm()});
  size_t idx = 0;
  double d2 = 0;
  nanoflann::KNNResultSet<double> rs(1);
  rs.init(&idx, &d2);
  tree.findNeighbors(rs, centre.data(), nanoflann::SearchParams());
  const double d = std::sqrt(d2);
  // Every point of the triangle lies within `spread` of its centre.
  if (d - spread >= reach) {
    out.push_back(t);
    return;
  }
  const double longest = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
  if (d + spread < reach || longest <= edge || depth > 12) return;
  const Eigen::Vector3d ab = 0.5 * (t[0] + t[1]), bc = 0.5 * (t[1] + t[2]), ca = 0.5 * (t[2] + t[0]);
  for (const Triangle& piece : {Triangle{t[0], ab, ca}, Triangle{ab, t[1], bc}, Triangle{ca, bc, t[2]}, Triangle{ab, bc, ca}})
    crop(piece, edge, reach, tree, depth + 1, out);
}

}  // namespace

Mesh stock_obstacle(const Mesh& stock, const ToolPath& path, const Tool& tool, const PlannerBasics& basics,
                    double edge_mm, double margin_mm) {
  // The farthest a point of the ball or flutes gets from the cutter location.
  const double above = std::max(0.0, tool.flute_length - tool.cl_height());
  const double below = tool.cl_height();
  const double reach = std::max(std::hypot(above, tool.radius()), std::hypot(below, tool.radius())) +
                       basics.safety_distance + margin_mm;
  PointCloud cloud{&path.rows};
  KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();

  std::vector<Triangle> kept;
  for (auto f : stock.faces()) {
    Triangle t;
    int k = 0;
    for (auto v : stock.fv_range(f)) t[k++] = to_eigen(stock.point(v));
    crop(t, edge_mm, reach, tree, 0, kept);
  }
  std::vector<Eigen::Vector3d> V;
  V.reserve(3 * kept.size());
  for (const Triangle& t : kept) V.insert(V.end(), t.begin(), t.end());
  // Separate vertices per triangle: a triangle soup is all the distance queries need.
  Eigen::MatrixX3d VM(static_cast<Eigen::Index>(V.size()), 3);
  Eigen::MatrixX3i FM(static_cast<Eigen::Index>(V.size() / 3), 3);
  for (size_t i = 0; i < V.size(); ++i) VM.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
  for (Eigen::Index i = 0; i < FM.rows(); ++i) FM.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  return mesh_from_arrays(VM, FM);
}

}  // namespace tf
