// The last resorts of the guarantee pass.
//
// Where the corrections could not clear the dynamics' axes, or the axis whips round between rows, the
// point-by-point baseline's axes are blended in around those rows and the corrections run again. Why: in
// a narrow channel the potential field can carry the axis round the wrong side of a blade, or swing it
// from one edge of the max-tilt cone to the other within a row (found on 9-blade impellers with a radius-1
// ball 0.3 mm from the blades: 98 degrees between two rows 1 mm apart). The smallest turn that clears such
// a row may be tens of degrees, and spread over the correction window it pushes the rows before it into
// the blade, round after round (one row at first, 16 after eight rounds, while the baseline cleared every
// row). The baseline's axes start from the nominal axis at every row, so they do not inherit the detour.
//
// Where a motion between two clear rows fails (the axis passes from one side of an obstacle to the
// other), one side's clear region is followed row by row until the motion back is proven.
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

#include "dynamics.hpp"
#include "plan_context.hpp"
#include "tiltfield/core/angles.hpp"
#include "tiltfield/core/local_frame.hpp"

namespace tf {
using Eigen::Vector3d;

namespace {

// Rounds in which the blend may move out past rows it made fail.
constexpr int kFallbackRounds = 16;
// A turn faster than this per response length (the path over which the attraction answers) is a whip:
// a critically damped body answering the field turns far less, so the field drove it there in a row or two.
constexpr double kWhipDegPerResponse = 45.0;

// Rows below their clearance, without a joint solution, or at either end of a motion that fails.
std::vector<char> failing_rows(const PlanContext& ctx, const std::vector<Vector3d>& axes,
                               const std::vector<BodyClearance>& clear, const std::vector<SegmentCheck>& segments) {
  const size_t n = axes.size();
  std::vector<char> bad(n, 0);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) { bad[i] = clear[i].margin < 0 || !ctx.reachable(i, axes[i]); });
  for (size_t i = 0; i < segments.size(); ++i)
    if (segments[i].failed) bad[i] = bad[i + 1] = 1;
  return bad;
}

size_t count(const std::vector<char>& flags) { return static_cast<size_t>(std::count(flags.begin(), flags.end(), 1)); }

// Rows at either end of a turn faster than kWhipDegPerResponse (and more than 5 degrees) within a cutting
// motion.
std::vector<char> whipping_rows(const PlanContext& ctx, const std::vector<Vector3d>& axes) {
  const size_t n = axes.size();
  std::vector<char> whip(n, 0);
  const double rate = kWhipDegPerResponse * std::numbers::pi / 180.0 / ctx.options.response_length_mm;
  for (size_t i = 0; i + 1 < n; ++i) {
    if (ctx.linked(i, axes[i], axes[i + 1])) continue;  // a linked jump may turn as it likes
    const double turn = angle_between(axes[i], axes[i + 1]);
    if (turn > std::max(5.0 * std::numbers::pi / 180.0, rate * (ctx.arc[i + 1] - ctx.arc[i])))
      whip[i] = whip[i + 1] = 1;
  }
  return whip;
}

// Failing rows first, whips second; a blend is kept only when it is better by this order and leaves no
// row or motion deeper below its clearance than before (one row deep in a blade is no gain on two a hair
// below).
struct Quality {
  size_t failing = 0, whips = 0;
  double worst = 0;  // the lowest margin of a row or a motion, mm (0 when none is below)
  // As many failing and whipping, and less deep, is better too: rows beside a clamp no axis clears had
  // kept a holder 12 mm in a wall where the cone search's axes came 0.9 mm short (black-box testing).
  bool better_than(const Quality& o) const {
    if (worst < o.worst - 1e-9) return false;
    if (failing != o.failing) return failing < o.failing;
    return whips != o.whips ? whips < o.whips : worst > o.worst + 1e-6;
  }
};

Quality quality(const PlanContext& ctx, const std::vector<Vector3d>& axes, const std::vector<BodyClearance>& clear,
                const std::vector<SegmentCheck>& segments) {
  Quality q{count(failing_rows(ctx, axes, clear, segments)), count(whipping_rows(ctx, axes)), 0.0};
  for (const BodyClearance& c : clear) q.worst = std::min(q.worst, c.margin);
  for (const SegmentCheck& s : segments)
    if (s.failed) q.worst = std::min(q.worst, -s.deficit);
  // A motion beside a failing row is checked too: unchecked, a flip between rows leaning back and forward
  // beside rows 0.3 mm short read -0.3 as the worst, and the cone search, which cleared the rows and left
  // only the flip (-1 either way), was refused as worse (black-box testing: a channel cleared at 58 degrees).
  tbb::combinable<double> beside([] { return 0.0; });
  tbb::parallel_for(size_t{0}, segments.size(), [&](size_t i) {
    if (segments[i].failed || (clear[i].margin >= 0 && clear[i + 1].margin >= 0)) return;
    const SegmentCheck s = check_segment_beside_failing_rows(ctx, i, axes[i], axes[i + 1], clear[i], clear[i + 1]);
    if (s.failed) beside.local() = std::min(beside.local(), -s.deficit);
  });
  q.worst = std::min(q.worst, beside.combine([](double a, double b) { return std::min(a, b); }));
  return q;
}

// 1 on the failing rows, falling smoothly (C1) to 0 at the correction window's distance from them.
std::vector<double> blend_weights(const PlanContext& ctx, const std::vector<char>& bad) {
  const size_t n = bad.size();
  const double W = ctx.options.correction_window_mm;
  std::vector<double> w(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (!bad[i]) continue;
    w[i] = 1.0;
    for (size_t j = i; j-- > 0 && !bad[j] && ctx.arc[i] - ctx.arc[j] < W;)
      w[j] = std::max(w[j], 0.5 * (1 + std::cos(std::numbers::pi * (ctx.arc[i] - ctx.arc[j]) / W)));
    for (size_t j = i + 1; j < n && !bad[j] && ctx.arc[j] - ctx.arc[i] < W; ++j)
      w[j] = std::max(w[j], 0.5 * (1 + std::cos(std::numbers::pi * (ctx.arc[j] - ctx.arc[i]) / W)));
  }
  return w;
}

// Runs a last resort (`resort(bad, axes, clear)`, which changes copies and returns their motions' checks)
// on the rows still failing or whipping; keeps what it made only when that is better by Quality: fewer
// rows failing, or as many and fewer whipping, none deeper below its clearance than before.
template <class Resort>
FallbackResult keep_if_better(const PlanContext& ctx, std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear,
                              std::vector<SegmentCheck>& segments, const Resort& resort) {
  std::vector<char> bad = failing_rows(ctx, axes, clear, segments);
  const std::vector<char> whips = whipping_rows(ctx, axes);
  if (count(bad) == 0 && count(whips) == 0) return {};
  const Quality before = quality(ctx, axes, clear, segments);
  for (size_t i = 0; i < bad.size(); ++i) bad[i] |= whips[i];
  std::vector<Vector3d> candidate = axes;
  std::vector<BodyClearance> candidate_clear = clear;
  std::vector<SegmentCheck> candidate_segments = resort(bad, candidate, candidate_clear);
  if (!quality(ctx, candidate, candidate_clear, candidate_segments).better_than(before)) return {};
  axes = std::move(candidate);
  clear = std::move(candidate_clear);
  segments = std::move(candidate_segments);
  return {before.failing, before.whips};
}

}  // namespace

FallbackResult fall_back_to_pointwise(const PlanContext& ctx, std::vector<Vector3d>& axes,
                                      std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments) {
  const std::vector<Vector3d> planned = axes;
  const std::vector<BodyClearance> planned_clear = clear;
  return keep_if_better(ctx, axes, clear, segments, [&](std::vector<char>& bad, std::vector<Vector3d>& candidate,
                                                         std::vector<BodyClearance>& candidate_clear) {
    const size_t n = planned.size();
    std::vector<Vector3d> baseline(n);
    std::vector<char> known(n, 0), found(n, 0);
    const double step = ctx.options.pointwise_step_deg * std::numbers::pi / 180.0;
    // The blend between a detour and the baseline can itself cross the blade; its failing rows then join
    // the rows taken whole from the baseline, and the blend moves out, until it clears or stops growing.
    for (int round = 0; round < kFallbackRounds; ++round) {
      const std::vector<double> w = blend_weights(ctx, bad);
      std::vector<size_t> rows;
      for (size_t i = 0; i < n; ++i)
        if (w[i] > 0) rows.push_back(i);
      candidate = planned;
      candidate_clear = planned_clear;
      tbb::parallel_for(size_t{0}, rows.size(), [&](size_t k) {
        const size_t i = rows[k];
        if (!known[i]) {
          const Vector3d a0 = clamp_to_cone(ctx.nominal[i], ctx.frames[i].n, ctx.cos_max_tilt);
          Vector3d turn;
          found[i] = smallest_clearing_turn(ctx, i, a0, ctx.options.correction_margin_mm, step, turn) ? 1 : 0;
          baseline[i] = rotate_axis(a0, turn);
          known[i] = 1;
        }
        if (!found[i]) return;
        candidate[i] = slerp_axis(planned[i], baseline[i], w[i]).normalized();
        candidate_clear[i] = ctx.clearance(i, candidate[i]);
      });
      const std::vector<char> now =
          failing_rows(ctx, candidate, candidate_clear, check_segments(ctx, candidate, candidate_clear));
      bool grew = false;
      for (size_t i = 0; i < n; ++i)
        if (now[i] && !bad[i]) bad[i] = 1, grew = true;
      if (!grew) break;
    }
    // No progress reported from this pass: the bar would go back to where the first corrections were.
    std::vector<SegmentCheck> candidate_segments = enforce_clearance(ctx, candidate, candidate_clear, Progress{});
    bridge_failing_motions(ctx, candidate, candidate_clear, candidate_segments);
    return candidate_segments;
  });
}

FallbackResult fall_back_to_cone_search(const PlanContext& ctx, std::vector<Vector3d>& axes,
                                        std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments) {
  return keep_if_better(ctx, axes, clear, segments, [&](std::vector<char>& bad, std::vector<Vector3d>& candidate,
                                                         std::vector<BodyClearance>& candidate_clear) {
    if (search_cone(ctx, bad, candidate, candidate_clear) == 0) return segments;  // nothing searched: no change
    std::vector<SegmentCheck> candidate_segments = check_segments(ctx, candidate, candidate_clear);
    bridge_failing_motions(ctx, candidate, candidate_clear, candidate_segments);
    return candidate_segments;
  });
}

namespace {

// Follows the clear region the axis is in from row `from` on, one row at a time in direction `dir` (the
// smallest turn from the previous axis that clears, zero when it still clears), until a motion from the
// followed axis back to the planned one is proven. Returns the rows it sets (empty when it fails: the
// region ends, a motion on the way fails, or it runs past twice the correction window).
struct FollowedRow {
  size_t row;
  Vector3d axis;
  BodyClearance clear;
};

std::vector<FollowedRow> follow_region(const PlanContext& ctx, const std::vector<Vector3d>& axes,
                                       const std::vector<BodyClearance>& clear, size_t from, int dir) {
  const auto n = static_cast<std::ptrdiff_t>(axes.size());
  const double step = ctx.options.pointwise_step_deg * std::numbers::pi / 180.0;
  // The motion between rows a and b = a + dir, in the order the path runs.
  auto motion_fails = [&](std::ptrdiff_t a, const Vector3d& axis_a, const BodyClearance& clear_a, std::ptrdiff_t b,
                          const Vector3d& axis_b, const BodyClearance& clear_b) {
    if (dir < 0) return check_segment(ctx, static_cast<size_t>(b), axis_b, axis_a, clear_b, clear_a).failed;
    return check_segment(ctx, static_cast<size_t>(a), axis_a, axis_b, clear_a, clear_b).failed;
  };
  std::vector<FollowedRow> set;
  auto prev = static_cast<std::ptrdiff_t>(from);
  Vector3d prev_axis = axes[from];
  BodyClearance prev_clear = clear[from];
  for (std::ptrdiff_t j = prev + dir; j >= 0 && j < n; j += dir) {
    const auto row = static_cast<size_t>(j);
    if (std::abs(ctx.arc[row] - ctx.arc[from]) > 2 * ctx.options.correction_window_mm) return {};
    // The axis carried on must stay in this row's max-tilt cone (the surface normal turns along the way).
    const Vector3d start = clamp_to_cone(prev_axis, ctx.frames[row].n, ctx.cos_max_tilt);
    Vector3d turn;
    if (!smallest_clearing_turn(ctx, row, start, ctx.options.correction_margin_mm, step, turn)) return {};
    const Vector3d a = rotate_axis(start, turn);
    const BodyClearance c = ctx.clearance(row, a);
    if (c.margin < 0 || motion_fails(prev, prev_axis, prev_clear, j, a, c)) return {};
    set.push_back({row, a, c});
    const std::ptrdiff_t k = j + dir;
    if (k < 0 || k >= n) return set;  // followed to the end of the path
    const auto next = static_cast<size_t>(k);
    if (clear[next].margin >= 0 && !motion_fails(j, a, c, k, axes[next], clear[next])) return set;
    prev = j;
    prev_axis = a;
    prev_clear = c;
  }
  return {};
}

}  // namespace

size_t bridge_failing_motions(const PlanContext& ctx, std::vector<Vector3d>& axes,
                              std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments) {
  size_t bridged = 0;
  for (size_t i = 0; i < segments.size(); ++i) {
    if (!segments[i].failed || clear[i].margin < 0 || clear[i + 1].margin < 0) continue;
    auto ahead = follow_region(ctx, axes, clear, i, +1);
    auto back = follow_region(ctx, axes, clear, i + 1, -1);
    const auto* best = &ahead;
    if (ahead.empty() || (!back.empty() && back.size() < ahead.size())) best = &back;
    if (best->empty()) continue;
    for (const FollowedRow& f : *best) {
      axes[f.row] = f.axis;
      clear[f.row] = f.clear;
    }
    // The motions next to the rows set (an earlier one of them may be mended too, or a later one spoilt).
    for (const FollowedRow& f : *best)
      for (size_t k = f.row > 0 ? f.row - 1 : 0; k <= f.row && k < segments.size(); ++k)
        segments[k] = check_segment(ctx, k, axes[k], axes[k + 1], clear[k], clear[k + 1]);
    ++bridged;
  }
  return bridged;
}

}  // namespace tf
