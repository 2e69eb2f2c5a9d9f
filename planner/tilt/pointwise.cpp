// The classic baseline: at each row, independently of its neighbours, the smallest tilt away from the
// nominal axis that clears (a ring search around the nominal axis, refined by bisection).
#include <tbb/parallel_for.h>

#include <numbers>

#include "dynamics.hpp"
#include "plan_context.hpp"

namespace tf {
using Eigen::Vector3d;

std::vector<Vector3d> pointwise_axes(const PlanContext& ctx, const Progress& progress) {
  const size_t n = ctx.nominal.size();
  std::vector<Vector3d> axes(n);
  const double step = ctx.options.pointwise_step_deg * std::numbers::pi / 180.0;
  report(progress, "plan", 0.1);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Vector3d a0 = clamp_to_cone(ctx.nominal[i], ctx.frames[i].n, ctx.cos_max_tilt);
      Vector3d turn;
      // Aim for the same margin above the required clearance as the dynamic method's corrections.
      const bool found = smallest_clearing_turn(ctx, i, a0, ctx.options.correction_margin_mm, step, turn);
      axes[i] = found ? rotate_axis(a0, turn) : a0;
    }
  });
  report(progress, "plan", 0.7);
  return axes;
}

}  // namespace tf
