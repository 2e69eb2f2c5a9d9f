// An independent model of a bull end for FCL: the convex polytope inscribed in the rounded disc (radius R,
// corner radius r < R, centre at the torus' centre circle, axis +z), `around` segments in azimuth and
// `over` across the tube from the tip's face to the top face. Its vertices lie on the true surface, so
// FCL's distances to it are at least the true ones, by at most R (1 - cos(pi / around)) + r (1 - cos(pi /
// (2 over))).
#pragma once
#include <fcl/fcl.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

namespace tf::test {

inline std::shared_ptr<fcl::Convexd> bull_end_convex(double R, double r, int around, int over) {
  auto v = std::make_shared<std::vector<fcl::Vector3d>>();
  auto f = std::make_shared<std::vector<int>>();
  const double pi = std::numbers::pi;
  // Rings from theta = -pi/2 (the tip's face rim) to +pi/2 (the top face rim).
  for (int i = 0; i <= over; ++i) {
    const double th = -0.5 * pi + pi * i / over;
    const double rho = (R - r) + r * std::cos(th), z = r * std::sin(th);
    for (int j = 0; j < around; ++j) {
      const double ph = 2 * pi * j / around;
      v->emplace_back(rho * std::cos(ph), rho * std::sin(ph), z);
    }
  }
  auto at = [&](int i, int j) { return i * around + (j % around); };
  int faces = 0;
  for (int i = 0; i < over; ++i)
    for (int j = 0; j < around; ++j) {
      f->insert(f->end(), {3, at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      f->insert(f->end(), {3, at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      faces += 2;
    }
  // The flat faces: the tip's (seen from below, clockwise from above) and the top.
  f->push_back(around);
  for (int j = around - 1; j >= 0; --j) f->push_back(at(0, j));
  f->push_back(around);
  for (int j = 0; j < around; ++j) f->push_back(at(over, j));
  faces += 2;
  return std::make_shared<fcl::Convexd>(v, faces, f);
}

}  // namespace tf::test
