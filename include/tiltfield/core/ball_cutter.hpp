// tiltfield: ball-end cutter. Tool frame: tip at the origin, axis +z toward the spindle, mm.
#pragma once
#include <algorithm>
#include <cmath>

namespace tf {

struct BallCutter {
  double radius = 3.0;  // ball radius, mm

  // Height of the cutter location (the ball centre) above the tip.
  double cl_height() const { return radius; }
  // Height above the tip where the end form meets the cylindrical flutes.
  double end_height() const { return radius; }
  // Radius of the end form at height h in [0, end_height()].
  double end_radius_at(double h) const {
    const double d = radius - std::clamp(h, 0.0, radius);
    return std::sqrt(std::max(0.0, radius * radius - d * d));
  }
};

}  // namespace tf
