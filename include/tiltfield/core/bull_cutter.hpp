// tiltfield: bull-nose (toroidal) cutter. Tool frame: tip at the origin, axis +z toward the spindle, mm.
#pragma once
#include <algorithm>
#include <cmath>

namespace tf {

struct BullCutter {
  double radius = 3.0;         // outer radius, mm
  double corner_radius = 1.0;  // torus tube radius, mm, 0 < corner_radius <= radius

  // The cutter location is the centre of the tool at the height of the torus' centre circle.
  double cl_height() const { return corner_radius; }
  double end_height() const { return corner_radius; }
  double end_radius_at(double h) const {
    const double d = corner_radius - std::clamp(h, 0.0, corner_radius);
    return radius - corner_radius + std::sqrt(std::max(0.0, corner_radius * corner_radius - d * d));
  }
};

}  // namespace tf
