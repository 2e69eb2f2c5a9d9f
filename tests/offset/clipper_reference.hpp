// The profile as Clipper sees it (no GoogleTest here: the offset benchmark includes it too).
#pragma once
#include <algorithm>
#include <cmath>
#include <polyclipping/clipper.hpp>

#include "tiltfield/offset/offset.hpp"

namespace tf::offset::test {

// The profile as a polygon whose chords stay within `sagitta` of the arcs (points on the arcs), in
// Clipper's integer units of 1 / scale mm.
inline ClipperLib::Path polygonise(const Profile& p, double sagitta, double scale) {
  ClipperLib::Path path;
  for (const auto& s : p.elements) {
    int n = 1;
    if (s.is_arc()) {
      const double step = 2 * std::acos(std::max(-1.0, 1 - sagitta / s.r));
      n = std::max(1, static_cast<int>(std::ceil(std::abs(s.sweep) / step)));
    }
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d q = point_at(s, static_cast<double>(k) / n);
      path.emplace_back(static_cast<ClipperLib::cInt>(std::llround(q.x() * scale)),
                        static_cast<ClipperLib::cInt>(std::llround(q.y() * scale)));
    }
  }
  return path;
}

}  // namespace tf::offset::test
