// tiltfield core: the degree. Interfaces take and give angles in degrees (lead, tilt, A B C); the
// geometry inside works in radians: x_deg * kDeg is in radians, x_rad / kDeg in degrees.
#pragma once
#include <numbers>

namespace tf {

inline constexpr double kDeg = std::numbers::pi / 180.0;  // radians per degree

}  // namespace tf
