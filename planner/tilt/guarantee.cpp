// Clearance guarantees: exact clearance of every row, and the smallest smooth correction of the rows the
// dynamics left too close.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dynamics.hpp"
#include "plan_context.hpp"

namespace tf {
using Eigen::Vector3d;

namespace {
std::vector<int>* set_hints(ClearanceHints* hints, size_t set, size_t pieces) {
  if (!hints) return nullptr;
  if (hints->size() <= set) hints->resize(set + 1);
  std::vector<int>& h = (*hints)[set];
  if (h.size() != pieces) h.assign(pieces, -1);
  return &h;
}
}  // namespace

BodyClearance PlanContext::clearance(size_t row, const Vector3d& axis, ClearanceHints* hints) const {
  BodyClearance out;
  out.distance = out.margin = std::numeric_limits<double>::infinity();
  const Pose p = pose(row, axis);
  const int solid = row < inside_solid.size() ? inside_solid[row] : -1;
  double solid_distance = 0.0;
  for (size_t s = 0; s < obstacles.size(); ++s) {
    const ObstacleSet& set = obstacles[s];
    if (set.bvh.empty()) continue;
    if (static_cast<int>(s) == solid) {  // the containing set's own distance, not the bounded search's
      solid_distance = body_clearance(set.bvh, pieces, set.required, p).distance;
      if (!std::isfinite(solid_distance)) solid_distance = 0.0;
    }
    // Searched only below what the sets before found: a far fixture costs a node or two.
    const BodyClearance c = body_clearance(set.bvh, pieces, set.required, p, set_hints(hints, s, pieces.size()), &out);
    if (c.distance < out.distance) out.nearest_set = static_cast<int>(s);
    if (c.margin < out.margin) out.margin_set = static_cast<int>(s);
    out.distance = c.distance;
    out.margin = c.margin;
    out.piece = c.piece;
  }
  if (solid >= 0) {
    // Inside a solid by at least the body's distance to its surface (0 - d: a body touching a face writes
    // 0, not -0).
    const auto s = static_cast<size_t>(solid);
    out.distance = 0.0 - solid_distance;
    out.margin = out.distance - *std::max_element(obstacles[s].required.begin(), obstacles[s].required.end()) - 1e-9;
    out.nearest_set = out.margin_set = solid;
    out.piece = 0;
  }
  return out;
}

bool PlanContext::clears(size_t row, const Vector3d& axis, double extra, ClearanceHints* hints,
                         double ball_extra) const {
  if (row < inside_solid.size() && inside_solid[row] >= 0) return false;
  const Pose p = pose(row, axis);
  // A ball cutter's flutes start on its equator: along a face the ball lies within the margin of, they
  // can come no farther from it than the ball, so they are asked no more (black-box testing: flutes
  // asked for the whole margin beside an overhanging wall the ball sat 0.41 mm from found no axis in
  // the band that clears both walls, and the plan flipped the lead by 73 deg between two rows).
  const bool ball_cutter = std::any_of(pieces.begin(), pieces.end(), [](const BodyPiece& b) { return b.sphere && b.h0 == 0.0; });
  for (size_t s = 0; s < obstacles.size(); ++s) {
    const ObstacleSet& set = obstacles[s];
    if (set.bvh.empty()) continue;
    std::vector<int>* h = set_hints(hints, s, pieces.size());
    for (size_t k = 0; k < pieces.size(); ++k) {
      const size_t i = piece_query_order(pieces, k);
      const bool ball = pieces[i].h0 == 0.0 && (pieces[i].sphere || ball_cutter);
      const double need = set.required[i] + (ball ? std::min(extra, ball_extra) : extra);
      if (piece_distance(set.bvh, pieces[i], p, need, true, h ? &(*h)[i] : nullptr) < need) return false;
    }
  }
  return true;
}

double PlanContext::max_required() const {
  double m = 0;
  for (const ObstacleSet& set : obstacles)
    for (double r : set.required) m = std::max(m, r);
  return m;
}

void clearances(const PlanContext& ctx, const std::vector<Vector3d>& axes, size_t begin, size_t end,
                std::vector<BodyClearance>& out) {
  if (begin >= end) return;
  tbb::parallel_for(tbb::blocked_range<size_t>(begin, end, 64), [&](const tbb::blocked_range<size_t>& r) {
    ClearanceHints hints;  // consecutive rows are close: each row's nearest triangles seed the next
    for (size_t i = r.begin(); i != r.end(); ++i) out[i] = ctx.clearance(i, axes[i], &hints);
  });
}

std::vector<BodyClearance> all_clearances(const PlanContext& ctx, const std::vector<Vector3d>& axes) {
  std::vector<BodyClearance> out(axes.size());
  clearances(ctx, axes, 0, axes.size(), out);
  return out;
}

double ball_extra_at(const PlanContext& ctx, size_t row, const Vector3d& axis, double extra) {
  double ball_extra = extra;
  for (size_t i = 0; i < ctx.pieces.size(); ++i)
    if (ctx.pieces[i].sphere && ctx.pieces[i].h0 == 0.0)
      for (const ObstacleSet& set : ctx.obstacles) {
        if (set.bvh.empty()) continue;
        const double need = set.required[i] + extra;
        const double left = piece_distance(set.bvh, ctx.pieces[i], ctx.pose(row, axis), need) - set.required[i];
        // Below its clearance: what it leaves is negative, and the other pieces are still asked for theirs.
        ball_extra = std::min(ball_extra, left < 0 ? left - 1e-9 : std::max(0.0, left - 1e-9));
      }
  return ball_extra;
}

bool smallest_clearing_turn(const PlanContext& ctx, size_t row, const Vector3d& axis, double extra, double step,
                            Vector3d& turn) {
  turn.setZero();
  ClearanceHints hints;  // every query below is at this row, at nearby axes
  const LocalFrame& fr = ctx.frames[row];
  auto usable = [&](const Vector3d& a) { return a.dot(fr.n) >= ctx.cos_max_tilt - 1e-12 && ctx.reachable(row, a); };
  const bool clear_now = ctx.clears(row, axis, extra, &hints);
  if (clear_now && usable(axis)) return true;
  // Asking the ball for more than it leaves had failed rows whose every other piece could be cleared.
  const double ball_extra = ball_extra_at(ctx, row, axis, extra);
  if (ball_extra < 0) return false;
  if (ball_extra < extra && ctx.clears(row, axis, extra, &hints, ball_extra) && usable(axis)) return true;
  // Directions: 16 round, plus the ascent direction of the margin (finite differences), tried first.
  std::vector<Vector3d> dirs;
  {
    const double eps = 0.2 * std::numbers::pi / 180.0;
    const double m0 = ctx.clearance(row, axis, &hints).margin;
    const double gf = ctx.clearance(row, rotate_axis(axis, eps * fr.f), &hints).margin - m0;
    const double gt = ctx.clearance(row, rotate_axis(axis, eps * fr.t), &hints).margin - m0;
    if (std::hypot(gf, gt) > 1e-9) dirs.push_back((gf * fr.f + gt * fr.t).normalized());
  }
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * std::numbers::pi * k / 16;
    dirs.push_back(std::cos(a) * fr.f + std::sin(a) * fr.t);
  }
  const double max_angle = 2.0 * std::acos(std::clamp(ctx.cos_max_tilt, -1.0, 1.0)) + step;
  auto ok = [&](const Vector3d& w) {
    const Vector3d a = rotate_axis(axis, w);
    // The cheap tests first: the closed-form joint solution before the clearance query (on a 3-axis
    // machine no turn is reachable, and the search cost 45 times the plan).
    return usable(a) && ctx.clears(row, a, extra, &hints, ball_extra);
  };
  for (double ang = step; ang <= max_angle; ang += step) {
    int best = -1;
    double best_margin = -std::numeric_limits<double>::infinity();
    for (size_t d = 0; d < dirs.size(); ++d) {
      if (!ok(ang * dirs[d])) continue;
      const double m = ctx.clearance(row, rotate_axis(axis, ang * dirs[d]), &hints).margin;
      if (m > best_margin) best_margin = m, best = static_cast<int>(d);
      if (d == 0 && dirs.size() == 17) break;  // the ascent direction wins ties: keep it
    }
    if (best < 0) continue;
    // Bisect the angle along the chosen direction down to step/64.
    double lo = ang - step, hi = ang;
    for (int k = 0; k < 6; ++k) {
      const double mid = 0.5 * (lo + hi);
      (ok(mid * dirs[static_cast<size_t>(best)]) ? hi : lo) = mid;
    }
    turn = hi * dirs[static_cast<size_t>(best)];
    return true;
  }
  return false;
}

namespace {
double bump(double u, double w) {  // 1 at 0, smoothly (C1) down to 0 at |u| = w
  if (w <= 0) return u == 0 ? 1.0 : 0.0;
  const double x = std::abs(u) / w;
  return x >= 1 ? 0.0 : 0.5 * (1 + std::cos(std::numbers::pi * x));
}
}  // namespace

std::vector<SegmentCheck> enforce_clearance(const PlanContext& ctx, std::vector<Vector3d>& axes,
                                            std::vector<BodyClearance>& clear, const Progress& progress) {
  const size_t n = axes.size();
  const double W = ctx.options.correction_window_mm;
  const double step = 0.5 * std::numbers::pi / 180.0;
  for (int iter = 0; iter < ctx.options.correction_iterations; ++iter) {
    // A row whose motion to a neighbour comes too close (the row itself clear) must gain what it lacked.
    std::vector<SegmentCheck> segments = check_segments(ctx, axes, clear);
    std::vector<double> lacks(n, 0.0);
    for (size_t i = 0; i < segments.size(); ++i)
      if (segments[i].failed) {
        lacks[i] = std::max(lacks[i], segments[i].deficit);
        lacks[i + 1] = std::max(lacks[i + 1], segments[i].deficit);
      }
    std::vector<size_t> failing;
    std::vector<char> bad(n, 0);
    tbb::parallel_for(size_t{0}, n, [&](size_t i) {
      bad[i] = clear[i].margin < 0 || lacks[i] > 0 || !ctx.reachable(i, axes[i]);
    });
    for (size_t i = 0; i < n; ++i)
      if (bad[i]) failing.push_back(i);
    if (failing.empty()) return segments;
    // Later rounds aim a little higher, so rows pulled back by their neighbours' blend converge.
    const double extra = ctx.options.correction_margin_mm * (1 + iter);
    std::vector<Vector3d> turn(failing.size(), Vector3d::Zero());
    std::vector<char> found(failing.size(), 0);
    tbb::parallel_for(size_t{0}, failing.size(), [&](size_t k) {
      const size_t i = failing[k];
      const double aim = lacks[i] > 0 ? std::max(extra, clear[i].margin + lacks[i] + extra) : extra;
      found[k] = smallest_clearing_turn(ctx, i, axes[i], aim, step, turn[k]) ? 1 : 0;
    });
    // Spread each turn over the window with a smooth bump; where windows overlap take, per component,
    // the largest push each way (an envelope, so no row gets less than its own correction).
    std::vector<Vector3d> pos(n, Vector3d::Zero()), neg(n, Vector3d::Zero());
    std::vector<char> touched(n, 0);
    for (size_t k = 0; k < failing.size(); ++k) {
      if (!found[k]) continue;
      const size_t i = failing[k];
      size_t lo = i, hi = i;
      while (lo > 0 && ctx.arc[i] - ctx.arc[lo - 1] < W) --lo;
      while (hi + 1 < n && ctx.arc[hi + 1] - ctx.arc[i] < W) ++hi;
      for (size_t j = lo; j <= hi; ++j) {
        const Vector3d w = bump(ctx.arc[j] - ctx.arc[i], W) * turn[k];
        pos[j] = pos[j].cwiseMax(w);
        neg[j] = neg[j].cwiseMin(w);
        touched[j] = 1;
      }
    }
    std::vector<size_t> rows;
    for (size_t j = 0; j < n; ++j) {
      if (!touched[j]) continue;
      const LocalFrame& fr = ctx.frames[j];
      Vector3d w = pos[j] + neg[j];
      w = w.dot(fr.f) * fr.f + w.dot(fr.t) * fr.t;
      if (w.norm() < 1e-12) continue;
      axes[j] = clamp_to_cone(rotate_axis(axes[j], w), fr.n, ctx.cos_max_tilt);
      rows.push_back(j);
    }
    tbb::parallel_for(size_t{0}, rows.size(), [&](size_t k) { clear[rows[k]] = ctx.clearance(rows[k], axes[rows[k]]); });
    report(progress, "plan", 0.8 + 0.1 * (iter + 1) / ctx.options.correction_iterations);
  }
  return check_segments(ctx, axes, clear);
}

}  // namespace tf
