#include "scene_distance.hpp"

#include <algorithm>
#include <cmath>

namespace tf::scenes {

bool tool_axis_hits(const Tool& tool, const TriangleBvh& obstacles, const Eigen::Vector3d& cl,
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
    if (inside && obstacles.closest(cl + (h - c) * axis, rho).distance < rho) return true;
  }
  return false;
}

}  // namespace tf::scenes
