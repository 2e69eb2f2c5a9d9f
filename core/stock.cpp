#include <cmath>
#include <numbers>

#include "tiltfield/core/scene.hpp"

namespace tf {

namespace {
Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Eigen::MatrixX3d V(8, 3);
  for (int i = 0; i < 8; ++i) V.row(i) << (i & 1 ? hi.x() : lo.x()), (i & 2 ? hi.y() : lo.y()), (i & 4 ? hi.z() : lo.z());
  Eigen::MatrixX3i F(12, 3);
  F << 0, 2, 1, 1, 2, 3,  // z = lo
      4, 5, 6, 5, 7, 6,   // z = hi
      0, 1, 4, 1, 5, 4,   // y = lo
      2, 6, 3, 3, 6, 7,   // y = hi
      0, 4, 2, 2, 4, 6,   // x = lo
      1, 3, 5, 3, 7, 5;   // x = hi
  return mesh_from_arrays(V, F);
}

Mesh cylinder_mesh(const StockCylinder& c, int segments) {
  const Eigen::Vector3d a = c.axis.normalized();
  Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
  const int n = std::max(3, segments);
  Eigen::MatrixX3d V(2 * n + 2, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * std::numbers::pi * i / n;
    const Eigen::Vector3d r = c.radius * (std::cos(t) * u + std::sin(t) * v);
    V.row(i) = (c.base + r).transpose();
    V.row(n + i) = (c.base + r + c.height * a).transpose();
  }
  V.row(2 * n) = c.base.transpose();
  V.row(2 * n + 1) = (c.base + c.height * a).transpose();
  Eigen::MatrixX3i F(4 * n, 3);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    F.row(4 * i) << i, j, n + j;
    F.row(4 * i + 1) << i, n + j, n + i;
    F.row(4 * i + 2) << 2 * n, j, i;              // bottom faces -a
    F.row(4 * i + 3) << 2 * n + 1, n + i, n + j;  // top faces +a
  }
  return mesh_from_arrays(V, F);
}
}  // namespace

Mesh stock_to_mesh(const Stock& stock, int segments) {
  switch (stock.kind) {
    case Stock::Kind::Mesh: return stock.mesh;
    case Stock::Kind::Box: return box_mesh(stock.box.min, stock.box.max);
    case Stock::Kind::Cylinder: return cylinder_mesh(stock.cylinder, segments);
  }
  return {};
}

Eigen::AlignedBox3d scene_bounds(const Scene& scene) {
  Eigen::AlignedBox3d box = bounding_box(scene.design);
  for (const Mesh& m : scene.check_surfaces) box.extend(bounding_box(m));
  for (const Mesh& m : scene.fixtures) box.extend(bounding_box(m));
  if (scene.stock.kind == Stock::Kind::Box) {
    box.extend(scene.stock.box.min);
    box.extend(scene.stock.box.max);
  } else {
    box.extend(bounding_box(stock_to_mesh(scene.stock, 64)));
  }
  return box;
}

}  // namespace tf
