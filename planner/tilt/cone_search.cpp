// The last resort of the guarantee pass: where rows still fail or the axis still whips after the
// corrections, the bridges and the fall-back, the smoothest clear axes over a window around them are
// searched for globally, by dynamic programming over a fixed set of axes in each row's max-tilt cone.
//
// Why: every earlier stage is local. The field, the corrections and the baseline each take the nearest
// way round an obstacle from where they stand, and a path that meets an obstacle head on is cleared
// leaning back before it and leaning forward after it, with a flip between two rows (black-box testing:
// a holder of radius 40 under a 4 mm sheet, 110 degrees between rows 0.5 mm apart, the plan failed)
// where one constant axis tilted 58 degrees sideways cleared every row and motion.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dynamics.hpp"
#include "plan_context.hpp"
#include "tiltfield/core/angles.hpp"

namespace tf {
using Eigen::Vector3d;

namespace {

constexpr double kRingStepDeg = 5.0;  // the axes searched: rings this far apart, as many around each
constexpr size_t kMaxRows = 1500;     // rows searched in all (about 400 clearance tests a row)
constexpr double kInf = std::numeric_limits<double>::infinity();

double angle(const Vector3d& a, const Vector3d& b) { return angle_between(a, b); }

// The axes searched at a row: the row's own and its nominal axis, the surface normal, rings about it at 1
// and 2.5 deg (8 axes each), then every kRingStepDeg up to the max-tilt cone, about kRingStepDeg apart
// around each.
std::vector<Vector3d> cone_axes(const PlanContext& ctx, size_t row, const Vector3d& current) {
  const LocalFrame& fr = ctx.frames[row];
  std::vector<Vector3d> out{current, clamp_to_cone(ctx.nominal[row], fr.n, ctx.cos_max_tilt)};
  const double step = kRingStepDeg * std::numbers::pi / 180.0;
  const double max_tilt = std::acos(std::clamp(ctx.cos_max_tilt, -1.0, 1.0));
  out.push_back(fr.n);
  // Two finer rings inside the first: a flat end's body swings by its radius across the contact with the
  // first degrees of tilt, and beside a post the clear axes of a flat R3 were a band from 0.02 to 3.8 deg
  // that the normal and the 5-degree ring both missed (black-box testing: 12 rows left failing). Where
  // such a small tilt dips the end into a curved design, the end's lift would turn the row again after
  // the search (a 12-degree step on an impeller's hub): those are not offered.
  for (const double fine : {1.0, 2.5}) {
    const double tilt = fine * std::numbers::pi / 180.0;
    if (tilt > max_tilt) break;  // beyond the max-tilt cone
    for (int k = 0; k < 8; ++k) {
      const double phi = 2 * std::numbers::pi * k / 8;
      const Vector3d a = std::cos(tilt) * fr.n + std::sin(tilt) * (std::cos(phi) * fr.f + std::sin(phi) * fr.t);
      if (!end_dips(ctx, row, a)) out.push_back(a);
    }
  }
  for (double tilt = step; tilt <= max_tilt + 1e-9; tilt += step) {
    const int around = std::max(6, static_cast<int>(std::round(2 * std::numbers::pi * std::sin(tilt) / step)));
    for (int k = 0; k < around; ++k) {
      const double phi = 2 * std::numbers::pi * k / around;
      out.push_back(std::cos(tilt) * fr.n + std::sin(tilt) * (std::cos(phi) * fr.f + std::sin(phi) * fr.t));
    }
  }
  return out;
}

// Windows of rows to search: the runs of `bad` rows, grown by the correction window on each side.
std::vector<std::pair<size_t, size_t>> windows_around(const PlanContext& ctx, const std::vector<char>& bad) {
  const size_t n = bad.size();
  const double pad = ctx.options.correction_window_mm;
  std::vector<char> in(n, 0);
  for (size_t i = 0; i < n; ++i) {
    if (!bad[i]) continue;
    for (size_t j = i; j-- > 0 && ctx.arc[i] - ctx.arc[j] <= pad;) in[j] = 1;
    for (size_t j = i; j < n && ctx.arc[j] - ctx.arc[i] <= pad; ++j) in[j] = 1;
  }
  std::vector<std::pair<size_t, size_t>> out;
  for (size_t i = 0; i < n; ++i) {
    if (!in[i]) continue;
    size_t e = i;
    while (e + 1 < n && in[e + 1]) ++e;
    out.emplace_back(i, e);
    i = e;
  }
  return out;
}

// The smoothest clear axes over rows [w0, w1], from the axis of row w0 - 1 and to that of row w1 + 1
// (where they exist, unchanged). Cost: the squared turn between neighbours over the path between them,
// plus the squared deviation from the nominal axis over the response length squared (so that a deviation
// held over one response length costs as much as turning by it there and back). A row without a clear
// axis keeps its own.
void search_window(const PlanContext& ctx, size_t w0, size_t w1, std::vector<Vector3d>& axes) {
  const size_t m = w1 - w0 + 1;
  std::vector<std::vector<Vector3d>> cand(m);
  std::vector<double> ball(m, 0.0);  // per row: what the ball is asked for beyond its clearance
  tbb::parallel_for(size_t{0}, m, [&](size_t k) {
    const size_t row = w0 + k;
    ClearanceHints hints;
    std::vector<Vector3d> clear;
    // The ball is asked only for what it leaves: where the ball alone lies within the margin of a blade
    // (its distance the same at every axis), asking it for the margin had found no candidate, and the
    // rows kept the jumps they were searched for (15.7 deg between rows 0.5 mm apart, black-box testing).
    // Where the ball is below its clearance (no axis clears the row), the other pieces are still searched
    // clear: a ball 0.5 mm short of a clamp had left the row's axis with the holder through a wall, where
    // a tilt away cleared it (black-box testing).
    const double margin = ctx.options.correction_margin_mm, ball_extra = ball_extra_at(ctx, row, axes[row], margin);
    ball[k] = ball_extra;
    const std::vector<Vector3d> offered = cone_axes(ctx, row, axes[row]);
    for (const Vector3d& a : offered)
      if (ctx.reachable(row, a) && ctx.clears(row, a, margin, &hints, ball_extra)) clear.push_back(a);
    // No axis clears: the axes that come least below the clearance, in steps of the largest clearance
    // (the row stays reported). The row's own axis had been kept whatever it hit: 12 mm of holder in a
    // wall where a tilt away came 0.86 mm short (black-box testing). The distances are unsigned, so the
    // steps stop short of touching: an axis through an obstacle is no better than the row's own.
    const double required = ctx.max_required();
    for (const double below : {0.0, 0.25, 0.5, 0.75, 0.95}) {
      if (!clear.empty() || !(required > 0.0)) break;
      const double extra = -below * required;
      for (const Vector3d& a : offered)
        if (ctx.reachable(row, a) && ctx.clears(row, a, extra, &hints, std::min(extra, ball_extra))) clear.push_back(a);
    }
    if (clear.empty()) clear.push_back(axes[row]);
    cand[k] = std::move(clear);
  });
  const double L = std::max(ctx.options.response_length_mm, 1e-6);
  auto deviation = [&](size_t row, const Vector3d& a) {
    const double d = angle(a, ctx.nominal[row]);
    const double ds = 0.5 * ((row > 0 ? ctx.arc[row] - ctx.arc[row - 1] : 0.0) +
                             (row + 1 < ctx.arc.size() ? ctx.arc[row + 1] - ctx.arc[row] : 0.0));
    return d * d * std::max(ds, 1e-6) / (L * L);
  };
  // Which moves the post links is taken from the axes as they are, not from the candidates: a candidate
  // whose tip moved past the link gap would otherwise turn for free, and make a link in mid-cut.
  std::vector<char> linked(m + 1, 0);
  for (size_t k = 0; k <= m; ++k) {
    const size_t row = w0 + k;  // the move row - 1 -> row
    if (row > 0 && row < axes.size()) linked[k] = ctx.linked(row - 1, axes[row - 1], axes[row]) ? 1 : 0;
  }
  // The squared turn t^2 as 2 (1 - cos t) = 4 sin^2(t / 2): the same for small turns, monotone up to half a
  // turn, and a dot product where atan2 was most of the programme's time (rows x candidates^2 of them).
  auto turn = [&](size_t row, const Vector3d& a, const Vector3d& b) {  // row -> row + 1
    if (linked[row + 1 - w0]) return 0.0;
    return 2.0 * (1.0 - a.dot(b)) / std::max(ctx.arc[row + 1] - ctx.arc[row], 1e-6);
  };
  std::vector<std::vector<double>> cost(m);
  std::vector<std::vector<int>> from(m);
  for (size_t k = 0; k < m; ++k) {
    const size_t row = w0 + k;
    cost[k].assign(cand[k].size(), kInf);
    from[k].assign(cand[k].size(), -1);
    tbb::parallel_for(size_t{0}, cand[k].size(), [&](size_t s) {
      const Vector3d& a = cand[k][s];
      double best = kInf;
      int arg = -1;
      if (k == 0) {
        best = row > 0 ? turn(row - 1, axes[row - 1], a) : 0.0;
      } else {
        for (size_t p = 0; p < cand[k - 1].size(); ++p) {
          const double v = cost[k - 1][p] + turn(row - 1, cand[k - 1][p], a);
          if (v < best) best = v, arg = static_cast<int>(p);
        }
      }
      if (k + 1 == m && row + 1 < axes.size()) best += turn(row, a, axes[row + 1]);
      cost[k][s] = best + deviation(row, a);
      from[k][s] = arg;
    });
  }
  int s = static_cast<int>(std::min_element(cost[m - 1].begin(), cost[m - 1].end()) - cost[m - 1].begin());
  if (!std::isfinite(cost[m - 1][static_cast<size_t>(s)])) return;  // NaN in a frame: leave the window
  for (size_t k = m; k-- > 0 && s >= 0;) {
    axes[w0 + k] = cand[k][static_cast<size_t>(s)];
    s = from[k][static_cast<size_t>(s)];
  }
  // The axes found lie on the rings: relax the steps between them, a row at a time, where the relaxed
  // axis still clears.
  for (int round = 0; round < 8; ++round)
    for (size_t row = std::max<size_t>(w0, 1); row <= w1 && row + 1 < axes.size(); ++row) {
      const Vector3d sum = axes[row - 1] + 2 * axes[row] + axes[row + 1];
      if (sum.norm() < 1e-9) continue;
      const Vector3d a = clamp_to_cone(sum.normalized(), ctx.frames[row].n, ctx.cos_max_tilt);
      if (ctx.reachable(row, a) && ctx.clears(row, a, ctx.options.correction_margin_mm, nullptr, ball[row - w0])) axes[row] = a;
    }
}

}  // namespace

size_t search_cone(const PlanContext& ctx, const std::vector<char>& bad, std::vector<Vector3d>& axes,
                   std::vector<BodyClearance>& clear) {
  // Rows inside a solid: no axis clears them, and a long buried run would take the whole budget.
  std::vector<char> wanted = bad;
  for (size_t i = 0; i < wanted.size() && i < ctx.inside_solid.size(); ++i)
    if (ctx.inside_solid[i] >= 0) wanted[i] = 0;
  size_t rows = 0;
  for (const auto& [w0, w1] : windows_around(ctx, wanted)) {
    // A last resort, not a planner: a window past the budget stays as the stages left it.
    if (rows + (w1 - w0 + 1) > kMaxRows) continue;
    rows += w1 - w0 + 1;
    search_window(ctx, w0, w1, axes);
    clearances(ctx, axes, w0, w1 + 1, clear);
  }
  return rows;
}

}  // namespace tf
