// Variable gap: where two offsets meet, the closest profile point jumps from one element to the other and
// with it the gap law's value, so the exact locus (distance == gap(s*)) is discontinuous there. The kept
// path (the intersection join) is never closer than the law; this pass marks those stretches.
#include <algorithm>
#include <cmath>
#include <vector>

#include "offset_internal.hpp"

namespace tf::offset {
namespace {

bool on_law(const Segment& s, double t, const ClearanceField& field, double thr) {
  return std::abs(clearance(field, point_at(s, t))) <= thr;
}

// The parameter in [lo, hi] where on_law flips, by bisection (on_law(lo) != on_law(hi)). Returns the
// bound on the exact side: the flip itself lies on the medial axis, where both closest points tie.
double flip_point(const Segment& s, double lo, double hi, const ClearanceField& field, double thr) {
  const bool at_lo = on_law(s, lo, field, thr);
  for (int it = 0; it < 44; ++it) {
    const double mid = 0.5 * (lo + hi);
    (on_law(s, mid, field, thr) == at_lo ? lo : hi) = mid;
  }
  return at_lo ? lo : hi;
}
}  // namespace

void mark_transitions(std::vector<std::vector<Segment>>& contours, const ClearanceField& field, double thr) {
  // Uniform samples, and geometric ones toward both ends: a node is on both offsets (exact either way)
  // and the stretch off the law starts right next to it.
  std::vector<double> ts;
  for (int k = 0; k <= 64; ++k) ts.push_back(k / 64.0);
  for (int j = 5; j <= 36; ++j) ts.push_back(std::ldexp(1.0, -j)), ts.push_back(1.0 - std::ldexp(1.0, -j));
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
  const size_t n = ts.size();
  for (auto& contour : contours) {
    std::vector<Segment> out;
    for (const Segment& s : contour) {
      if (s.kind == SegmentKind::SharpJoin) {
        out.push_back(s);
        continue;
      }
      std::vector<char> flags(n);
      bool all = true;
      for (size_t k = 0; k < n; ++k) {
        flags[k] = on_law(s, ts[k], field, thr);
        all = all && flags[k];
      }
      if (all) {
        out.push_back(s);
        continue;
      }
      // Split at every flip between samples; a flip next to an end merges into the end's part.
      std::vector<double> cuts = {0.0};
      std::vector<char> exact = {flags[0]};
      for (size_t k = 0; k + 1 < n; ++k)
        if (flags[k] != flags[k + 1]) {
          const double t = flip_point(s, ts[k], ts[k + 1], field, thr);
          if (t * length(s) <= 1e-7) {  // a sliver at an end joins the end part
            exact.back() = flags[k + 1];
            continue;
          }
          if ((1 - t) * length(s) <= 1e-7) break;
          cuts.push_back(t);
          exact.push_back(flags[k + 1]);
        }
      cuts.push_back(1.0);
      const size_t first = out.size();
      for (size_t k = 0; k + 1 < cuts.size(); ++k) {
        Segment part = sub_segment(s, cuts[k], cuts[k + 1]);
        // A part between flips judged exact from its end samples is checked once more inside; a sliver
        // (< 10 nm) between flips goes with the transition it borders.
        for (int j = 0; j <= 8 && exact[k]; ++j) exact[k] = on_law(part, j / 8.0, field, thr);
        if (length(part) < 1e-5) exact[k] = false;
        if (!exact[k]) part.kind = SegmentKind::Transition;
        if (out.size() > first) part.a = out.back().b;
        out.push_back(part);
      }
      out[first].a = s.a;
      out.back().b = s.b;
    }
    contour = std::move(out);
  }
}

}  // namespace tf::offset
