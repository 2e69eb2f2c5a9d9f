// The verification report's small pieces of logic: names, the engagement angle, the blocks.csv row.
#include <cmath>
#include <limits>

#include "tiltfield/core/report.hpp"

namespace tf {

std::string_view to_string(HitWith w) {
  switch (w) {
    case HitWith::Stock: return "stock";
    case HitWith::Check: return "check";
    case HitWith::Fixture: return "fixture";
  }
  return "?";
}

double Engagement::angle_deg() const {
  if (!engaged()) return 0.0;
  const double a = std::fmod(exit_deg - entry_deg + 360.0, 360.0);
  return a <= 1e-9 ? 360.0 : a;
}

BlockRow block_row(const BlockResult& b) {
  const Engagement& e = b.engagement;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  BlockRow r;
  r.block = b.block;
  r.line = b.line;
  r.removed_mm3 = b.removed_mm3;
  // MRR is removed volume over block time: none when the block takes no time.
  r.mrr_mm3_min = b.minutes > 0 ? b.mrr() : nan;
  // Angles are empty where nothing is engaged (air moves, rapids): there is no angle to give.
  r.entry_deg = e.engaged() ? e.entry_deg : nan;
  r.exit_deg = e.engaged() ? e.exit_deg : nan;
  r.collision = b.collision;
  // A rapid is not measured (it does not cut by intent): its cells are empty, not a measured 0.
  if (!b.rapid) {
    r.engaged_area_mm2 = e.area_mm2;
    r.axial_depth_mm = e.axial_depth_mm;
    r.radial_width_mm = e.radial_width_mm;
    r.pairs = e.max_pairs;
  }
  r.tool = b.tool;
  return r;
}

}  // namespace tf
