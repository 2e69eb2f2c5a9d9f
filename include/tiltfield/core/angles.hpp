// tiltfield core: the degree. Interfaces take and give angles in degrees (lead, tilt, A B C); the
// geometry inside works in radians: x_deg * kDeg is in radians, x_rad / kDeg in degrees.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace tf {

inline constexpr double kDeg = std::numbers::pi / 180.0;  // radians per degree

// The angle between two vectors of any non-zero length, radians in [0, pi]; accurate near 0 and pi,
// where acos of the dot product is not.
inline double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace tf
