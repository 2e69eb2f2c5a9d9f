// Shared fixtures for the verifier tests: scenes built in memory, simple meshes.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf::test {

// An icosphere of radius r about c, `levels` subdivisions (20 * 4^levels triangles), outward faces.
inline Mesh icosphere(double r, int levels, const Eigen::Vector3d& c = Eigen::Vector3d::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> V = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Eigen::Vector3i> F = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& v : V) v.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      V.push_back((V[a] + V[b]).normalized());
      return mid[key] = static_cast<int>(V.size()) - 1;
    };
    std::vector<Eigen::Vector3i> G;
    for (const auto& f : F) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), cc = midpoint(f[2], f[0]);
      G.push_back({f[0], a, cc});
      G.push_back({f[1], b, a});
      G.push_back({f[2], cc, b});
      G.push_back({a, b, cc});
    }
    F = G;
  }
  Eigen::MatrixX3d MV(V.size(), 3);
  Eigen::MatrixX3i MF(F.size(), 3);
  for (size_t i = 0; i < V.size(); ++i) MV.row(i) = (c + r * V[i]).transpose();
  for (size_t i = 0; i < F.size(); ++i) MF.row(i) = F[i].transpose();
  return mesh_from_arrays(MV, MF);
}

// A closed box mesh.
inline Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Stock s;
  s.kind = Stock::Kind::Box;
  s.box = {lo, hi};
  return stock_to_mesh(s);
}

inline Tool ball_tool(double r, double flute, double shank_r, double length, std::vector<HolderSegment> holder) {
  Tool t;
  t.cutter = BallCutter{r};
  t.flute_length = flute;
  t.shank_radius = shank_r;
  t.length = length;
  t.holder = std::move(holder);
  return t;
}

inline Tool bull_tool(double r, double corner, double flute, double shank_r, double length) {
  Tool t;
  t.cutter = BullCutter{r, corner};
  t.flute_length = flute;
  t.shank_radius = shank_r;
  t.length = length;
  return t;
}

// A scene with a box stock and the given tool; no design, no machine (3-axis).
inline Scene box_scene(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Tool& tool) {
  Scene s;
  s.stock.kind = Stock::Kind::Box;
  s.stock.box = {lo, hi};
  s.tool = tool;
  return s;
}

}  // namespace tf::test
