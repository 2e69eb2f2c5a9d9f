// Vertex-clustering decimation: budgets, averaged values, orientation, thin walls and sharp edges.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>

#include "tiltfield/core/mesh_decimate.hpp"
#include "tiltfield/core/scene.hpp"

namespace {

using tf::IndexedTriangles;

double wave(double x, double y) { return 2.0 * std::sin(x / 9.0) * std::cos(y / 13.0); }

// Grid surface z = wave(x, y) over [0, 60] x [0, 40], nx by ny cells, two triangles each.
IndexedTriangles wavy_surface(int nx, int ny) {
  IndexedTriangles m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = 60.0 * i / nx, y = 40.0 * j / ny;
      m.V.emplace_back(x, y, wave(x, y));
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const auto a = uint32_t(j * (nx + 1) + i), b = a + 1, c = a + uint32_t(nx) + 1, d = c + 1;
      m.F.push_back({a, b, d});
      m.F.push_back({a, d, c});
    }
  return m;
}

// The cube [0, side]^3 with every face an n by n grid, vertices shared along the edges (so edge
// vertices see both faces, as in a real closed mesh), faces outward.
IndexedTriangles grid_cube(double side, int n) {
  IndexedTriangles m;
  std::map<std::array<int, 3>, uint32_t> index;
  auto vertex = [&](std::array<int, 3> g) {
    auto [it, fresh] = index.try_emplace(g, uint32_t(m.V.size()));
    if (fresh) m.V.emplace_back(side * g[0] / n, side * g[1] / n, side * g[2] / n);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int at : {0, n}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<uint32_t, 4> q;
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> g{};
            g[axis] = at;
            g[u] = i + (k == 1 || k == 2);
            g[v] = j + (k >= 2);
            q[k] = vertex(g);
          }
          // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
          if (at == n) {
            m.F.push_back({q[0], q[1], q[2]});
            m.F.push_back({q[0], q[2], q[3]});
          } else {
            m.F.push_back({q[0], q[2], q[1]});
            m.F.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return m;
}

double signed_volume(const IndexedTriangles& m) {
  double v = 0.0;
  for (const auto& f : m.F) v += m.V[f[0]].dot(m.V[f[1]].cross(m.V[f[2]])) / 6.0;
  return v;
}

TEST(MeshDecimate, MeetsTheBudgetKeepsTheShapeAndAveragesValues) {
  IndexedTriangles m = wavy_surface(200, 150);  // 60k triangles
  m.values.assign(m.V.size(), 0.25);
  const IndexedTriangles d = tf::decimate_to_budget(m, 6000);
  EXPECT_LE(d.F.size(), 6000u);
  EXPECT_GE(d.F.size(), 1500u) << "not far below the budget";
  ASSERT_EQ(d.values.size(), d.V.size());
  for (size_t i = 0; i < d.V.size(); ++i) {
    EXPECT_NEAR(d.V[i].z(), wave(d.V[i].x(), d.V[i].y()), 0.05) << "cluster points stay on the surface";
    EXPECT_NEAR(d.values[i], 0.25, 1e-12);
  }
  EXPECT_EQ(tf::decimate_to_budget(m, m.F.size()).F.size(), m.F.size()) << "within budget: unchanged";
  EXPECT_TRUE(tf::decimate_to_budget(m, 0).F.empty());
}

TEST(MeshDecimate, ValuesAreTheClusterMeans) {
  // value = x: a cluster's value is the mean x of its vertices, which on a smooth surface is where the
  // quadric puts the cluster point (up to the bending within a cell).
  IndexedTriangles m = wavy_surface(120, 80);
  for (const auto& p : m.V) m.values.push_back(p.x());
  const double cell = 2.0;
  const IndexedTriangles d = tf::cluster_decimate(m, cell);
  ASSERT_EQ(d.values.size(), d.V.size());
  ASSERT_GT(d.F.size(), 0u);
  for (size_t i = 0; i < d.V.size(); ++i) EXPECT_NEAR(d.values[i], d.V[i].x(), 0.05 * cell);
}

TEST(MeshDecimate, KeepsOrientationAndReducesCount) {
  tf::Stock s;
  s.kind = tf::Stock::Kind::Cylinder;
  s.cylinder = {{0, 0, 0}, {0, 0, 1}, 30.0, 10.0};
  const IndexedTriangles fine = tf::indexed_triangles(tf::stock_to_mesh(s, 600));
  const IndexedTriangles coarse = tf::cluster_decimate(fine, 2.0);
  EXPECT_LT(coarse.F.size(), fine.F.size() / 4);
  EXPECT_GT(signed_volume(coarse), 0.8 * signed_volume(fine));
}

TEST(MeshDecimate, KeepsBothSidesOfAThinWall) {
  tf::Stock s;
  s.kind = tf::Stock::Kind::Box;
  s.box = {{0, 0, 0}, {20, 0.2, 10}};  // a 0.2 mm wall, clustered on 2 mm cells
  const IndexedTriangles d = tf::cluster_decimate(tf::indexed_triangles(tf::stock_to_mesh(s)), 2.0);
  int plus = 0, minus = 0;
  for (const auto& f : d.F) {
    const Eigen::Vector3d n = (d.V[f[1]] - d.V[f[0]]).cross(d.V[f[2]] - d.V[f[0]]);
    plus += n.y() > 0.9 * n.norm();
    minus += n.y() < -0.9 * n.norm();
  }
  EXPECT_GT(plus, 0);
  EXPECT_GT(minus, 0);
}

TEST(MeshDecimate, SharpEdgesStayStraight) {
  // The cluster point solves for the planes around it: clusters at a cube's edges land on the edge
  // (their vertices' mean would lie inside a face, cutting the edge off).
  const IndexedTriangles cube = grid_cube(10.0, 40);
  const IndexedTriangles d = tf::cluster_decimate(cube, 1.3);
  ASSERT_GT(d.F.size(), 100u);
  int on_edges = 0;
  for (const auto& p : d.V) {
    int at_faces = 0;
    for (int a = 0; a < 3; ++a) {
      const double to_face = std::min(std::abs(p[a]), std::abs(p[a] - 10.0));
      EXPECT_GT(p[a], -1e-9);
      EXPECT_LT(p[a], 10.0 + 1e-9);
      at_faces += to_face < 0.02;
    }
    EXPECT_GE(at_faces, 1) << "on the surface";
    on_edges += at_faces >= 2;
  }
  EXPECT_GE(on_edges, 12 * 6) << "most cells along each of the 12 edges";
  EXPECT_NEAR(signed_volume(d), 1000.0, 5.0);
}

TEST(MeshDecimate, DegenerateInputs) {
  const IndexedTriangles m = wavy_surface(4, 3);
  EXPECT_EQ(tf::cluster_decimate(m, 0.0).F.size(), m.F.size()) << "no cell: a copy";
  EXPECT_EQ(tf::cluster_decimate(m, 1e-9).F.size(), m.F.size()) << "a grid too fine to key: a copy";
  EXPECT_TRUE(tf::cluster_decimate(IndexedTriangles{}, 1.0).F.empty());
  IndexedTriangles bad = m;
  bad.values.assign(m.V.size() - 1, 0.0);
  EXPECT_THROW(tf::cluster_decimate(bad, 1.0), std::invalid_argument);
  const std::vector<double> short_values(3, 0.0);
  tf::Stock s;
  s.box = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(tf::indexed_triangles(tf::stock_to_mesh(s), &short_values), std::invalid_argument);
  const std::vector<uint32_t> short_labels(3, 0);
  EXPECT_THROW(tf::indexed_triangles(tf::stock_to_mesh(s), nullptr, &short_labels), std::invalid_argument);
  bad = m;
  bad.labels.assign(m.V.size() + 1, 0);
  EXPECT_THROW(tf::cluster_decimate(bad, 1.0), std::invalid_argument);
}

TEST(MeshDecimate, LabelsAreTakenNotMixed) {
  // Labels 7 left of x = 30 and 9 right of it: a cluster takes one of its own vertices' labels, so the
  // output has no third value, and clusters away from the line keep their side's.
  IndexedTriangles m = wavy_surface(120, 80);
  for (const auto& p : m.V) m.labels.push_back(p.x() < 30.0 ? 7u : 9u);
  const IndexedTriangles d = tf::cluster_decimate(m, 2.0);
  ASSERT_EQ(d.labels.size(), d.V.size());
  for (size_t i = 0; i < d.V.size(); ++i) {
    ASSERT_TRUE(d.labels[i] == 7u || d.labels[i] == 9u) << d.labels[i];
    const uint32_t side = d.V[i].x() < 30.0 ? 7u : 9u;
    if (std::abs(d.V[i].x() - 30.0) > 3.0) {
      EXPECT_EQ(d.labels[i], side);
    }
  }
}

}  // namespace
