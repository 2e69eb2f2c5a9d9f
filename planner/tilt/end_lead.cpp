// The lead that keeps a flat or bull end out of the design surface (end_form.hpp): raised on the nominal
// axis before the stages that follow it, and checked again on the axes they leave.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>

#include "plan_context.hpp"
#include "tiltfield/core/angles.hpp"

namespace tf {
using Eigen::Vector3d;

bool end_dips(const PlanContext& ctx, size_t row, const Vector3d& axis) {
  if (ctx.contact_dip.size() <= row) return false;  // no end form set up (a ball, or no design)
  const double limit = ctx.options.end_dip_tolerance_mm + ctx.contact_dip[row];
  return end_dip(ctx.end_form, ctx.tip(row, axis), axis, ctx.design_side[row], limit) > limit;
}

namespace {

constexpr double kLeadStepDeg = 0.5;
constexpr double kMaxChangeDeg = 45.0;  // a lead changed more than this is no lead any more
constexpr int kBisections = 5;  // to 0.5 / 32 deg

// The end's dip below the design beyond the contact's own: a contact on a tessellated concave surface
// lies below the chords by their sagitta, which no axis changes.
double dip_at(const PlanContext& ctx, size_t row, const Vector3d& axis) {
  const double dip = end_dip(ctx.end_form, ctx.tip(row, axis), axis, ctx.design_side[row]);
  return std::max(0.0, dip - ctx.contact_dip[row]);
}

// The least lead from `lead` onward in direction `sign` (+1 more lead, -1 less) at which the end does not
// dip, within the max-tilt cone and, when `clear` is set, clear of the obstacles and reachable. NaN when
// none.
double least_lifting_lead(const PlanContext& ctx, size_t row, double lead, double tilt, int sign, bool clear) {
  const LocalFrame& f = ctx.frames[row];
  auto axis = [&](double l) { return axis_from_lead_tilt(f, l, tilt); };
  auto acceptable = [&](const Vector3d& a) { return !clear || (ctx.clears(row, a, 0.0) && ctx.reachable(row, a)); };
  double below = lead;  // dips
  for (int k = 1; k * kLeadStepDeg <= kMaxChangeDeg; ++k) {
    const double l = lead + sign * k * kLeadStepDeg;
    const Vector3d a = axis(l);
    if (a.dot(f.n) < ctx.cos_max_tilt) return NAN;
    if (end_dips(ctx, row, a)) {
      below = l;
      continue;
    }
    if (!acceptable(a)) continue;
    double above = l;
    for (int b = 0; b < kBisections; ++b) {
      const double m = 0.5 * (below + above);
      const Vector3d am = axis(m);
      (end_dips(ctx, row, am) ? below : above) = m;
    }
    return acceptable(axis(above)) ? above : l;
  }
  return NAN;
}

// Each row's raise spread along the path: the largest raise within `w` mm of arc either side, averaged
// over w / 2 either side, so the axis leans before the dip and no row gets less than it needs.
std::vector<double> spread_raise(const std::vector<double>& raise, const std::vector<double>& arc, double w) {
  const size_t n = raise.size();
  std::vector<double> wide(n, 0.0), out(n, 0.0);
  // The window's largest by a deque of candidates (indices, raises decreasing): linear in the rows, as a
  // fine path holds a thousand rows or more within w.
  std::deque<size_t> best;
  size_t next = 0;  // the first row not yet in the window
  for (size_t j = 0; j < n; ++j) {
    for (; next < n && arc[next] - arc[j] <= w; ++next) {
      while (!best.empty() && raise[best.back()] <= raise[next]) best.pop_back();
      best.push_back(next);
    }
    while (arc[j] - arc[best.front()] > w) best.pop_front();  // j itself stays in: never empty
    wide[j] = raise[best.front()];
  }
  std::vector<double> prefix(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + wide[i];
  size_t lo = 0, hi = 0;
  for (size_t i = 0; i < n; ++i) {
    while (arc[i] - arc[lo] > 0.5 * w) ++lo;
    while (hi < n && arc[hi] - arc[i] <= 0.5 * w) ++hi;
    out[i] = (prefix[hi] - prefix[lo]) / static_cast<double>(hi - lo);
  }
  return out;
}

}  // namespace

void set_up_end_form(PlanContext& ctx, const std::vector<const Mesh*>& design) {
  ctx.end_form = make_end_form(*ctx.tool, design);
  const size_t n = ctx.path->rows.size();
  ctx.design_side.assign(n, 0);
  ctx.contact_dip.assign(n, 0.0f);
  if (!ctx.end_form.active()) return;
  const double corner = ctx.tool->cl_height();  // the row point lies r along the normal from the contact
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    const CLPoint& row = ctx.path->rows[i];
    const Vector3d nrm = row.contact_normal();
    const Vector3d contact = row.p - corner * nrm;
    const int side = design_side(ctx.end_form, contact, nrm);
    ctx.design_side[i] = static_cast<int8_t>(side);
    ctx.contact_dip[i] = static_cast<float>(point_dip(ctx.end_form, contact, side));
  });
}

size_t lead_nominal_out_of_design(PlanContext& ctx, std::vector<std::string>& notes) {
  if (!ctx.end_form.active()) return 0;
  const size_t n = ctx.nominal.size();
  const double lead = ctx.basics.lead_deg, tilt = ctx.basics.tilt_deg;
  // Signed raise per row (deg of lead): forward first, the other way only where forward finds none.
  std::vector<double> up(n, 0.0), down(n, 0.0);
  std::vector<char> stuck(n, 0);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    if (!end_dips(ctx, i, ctx.nominal[i])) return;
    const int sign = lead >= 0 ? 1 : -1;
    double l = least_lifting_lead(ctx, i, lead, tilt, sign, false);
    if (std::isfinite(l)) {
      (sign > 0 ? up[i] : down[i]) = std::abs(l - lead);
      return;
    }
    l = least_lifting_lead(ctx, i, lead, tilt, -sign, false);
    if (std::isfinite(l))
      (sign > 0 ? down[i] : up[i]) = std::abs(l - lead);
    else
      stuck[i] = 1;
  });
  const std::vector<double> ups = spread_raise(up, ctx.arc, ctx.options.response_length_mm);
  const std::vector<double> downs = spread_raise(down, ctx.arc, ctx.options.response_length_mm);
  // The first way tried (away from a lead of 0) wherever its raise reaches the row, the other elsewhere:
  // a difference of the two spreads had left rows between a forward and a backward need short of both
  // (found in review).
  const bool forward_up = lead >= 0;
  auto either = [forward_up](double u, double d) { return forward_up ? (u > 0.0 ? u : -d) : (d > 0.0 ? -d : u); };
  std::vector<double> change(n, 0.0);
  for (size_t i = 0; i < n; ++i) change[i] = either(ups[i], downs[i]);
  // A row the spread leans where its own least change would not (a wall of the design behind it)
  // keeps its own.
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    if (change[i] == 0.0) return;
    const double own = either(up[i], down[i]);
    if (own != change[i] && end_dips(ctx, i, axis_from_lead_tilt(ctx.frames[i], lead + change[i], tilt)) &&
        !end_dips(ctx, i, axis_from_lead_tilt(ctx.frames[i], lead + own, tilt)))
      change[i] = own;
  });
  size_t raised = 0;
  double most = 0;
  for (size_t i = 0; i < n; ++i) {
    if (change[i] == 0.0) continue;
    ctx.nominal[i] = axis_from_lead_tilt(ctx.frames[i], lead + change[i], tilt);
    ++raised;
    most = std::max(most, std::abs(change[i]));
  }
  size_t count = 0, first = 0;
  for (size_t i = n; i-- > 0;)
    if (stuck[i]) ++count, first = i;
  if (raised > 0)
    notes.push_back(std::to_string(raised) + " row(s): the nominal lead was changed by up to " +
                    std::to_string(most) + " deg so that the end does not dip below the design surface");
  if (count > 0)
    notes.push_back(std::to_string(count) + " row(s) dip the end below the design surface at every lead within 45 deg of "
                    "the nominal one and max_tilt_deg (first: row " + std::to_string(first) + ")");
  return raised;
}

EndDips settle_end_dips(const PlanContext& ctx, std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear,
                        bool may_turn) {
  EndDips out;
  if (!ctx.end_form.active()) return out;
  const size_t n = axes.size();
  const double tol = ctx.options.end_dip_tolerance_mm;
  std::vector<double> dip(n, 0.0);
  std::vector<char> turned(n, 0);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    dip[i] = dip_at(ctx, i, axes[i]);
    if (dip[i] <= tol || !may_turn) return;
    const Eigen::Vector2d lt = lead_tilt_from_axis(ctx.frames[i], axes[i].normalized());
    // Both ways, and the nearer: the first clear lead one way can lie far beyond an obstacle the other way
    // does not meet (a row of a flat end between blades went from 1.5 to 27 deg where -3 deg was clear and
    // its neighbours took it; the swing gouged between the rows, black-box testing).
    const double up = least_lifting_lead(ctx, i, lt.x(), lt.y(), 1, true);
    const double down = least_lifting_lead(ctx, i, lt.x(), lt.y(), -1, true);
    double l = up;
    if (!std::isfinite(up) || (std::isfinite(down) && lt.x() - down < up - lt.x())) l = down;
    if (!std::isfinite(l)) return;
    axes[i] = axis_from_lead_tilt(ctx.frames[i], l, lt.y());
    clear[i] = ctx.clearance(i, axes[i]);
    dip[i] = dip_at(ctx, i, axes[i]);
    turned[i] = 1;
  });
  for (size_t i = 0; i < n; ++i) {
    out.turned += turned[i] ? 1 : 0;
    if (dip[i] > tol) {
      if (out.dipping == 0) out.first = i;
      ++out.dipping;
    }
    out.max_dip_mm = std::max(out.max_dip_mm, dip[i]);
  }
  return out;
}

}  // namespace tf
