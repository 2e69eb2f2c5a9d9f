// Global smoothing with Ceres: minimise the axis' second differences plus the deviation from the dynamic
// result, the clearance kept by a barrier on its linearisation, then checked exactly.
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>

#include "dynamics.hpp"
#include "plan_context.hpp"

namespace tf {
using Eigen::Vector3d;

namespace {

// Each row's unknown is a rotation (alpha about f, beta about t) applied to its dynamic axis a0.
template <class T>
void turned_axis(const Vector3d& a0, const Vector3d& f, const Vector3d& t, const T* ab, T* out) {
  const T w[3] = {ab[0] * f.x() + ab[1] * t.x(), ab[0] * f.y() + ab[1] * t.y(), ab[0] * f.z() + ab[1] * t.z()};
  const T p[3] = {T(a0.x()), T(a0.y()), T(a0.z())};
  ceres::AngleAxisRotatePoint(w, p, out);
}

struct SecondDifference {
  Vector3d a[3], f[3], t[3];
  double weight;
  template <class T>
  bool operator()(const T* x0, const T* x1, const T* x2, T* r) const {
    T p0[3], p1[3], p2[3];
    turned_axis(a[0], f[0], t[0], x0, p0);
    turned_axis(a[1], f[1], t[1], x1, p1);
    turned_axis(a[2], f[2], t[2], x2, p2);
    for (int k = 0; k < 3; ++k) r[k] = weight * (p0[k] - 2.0 * p1[k] + p2[k]);
    return true;
  }
};

struct Deviation {
  double weight;
  template <class T>
  bool operator()(const T* x, T* r) const {
    r[0] = weight * x[0];
    r[1] = weight * x[1];
    return true;
  }
};

// Hinge on the linearised margin m0 + g.x >= target.
struct Barrier {
  double m0, gf, gt, target, weight;
  template <class T>
  bool operator()(const T* x, T* r) const {
    const T m = m0 + gf * x[0] + gt * x[1];
    r[0] = m < T(target) ? weight * (T(target) - m) : T(0.0);
    return true;
  }
};

}  // namespace

bool smooth_axes(const PlanContext& ctx, std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear) {
  const size_t n = axes.size();
  if (n < 3) return true;
  const double eps = 0.1 * std::numbers::pi / 180.0;
  const double bound = 5.0 * std::numbers::pi / 180.0;  // keeps the linearised clearance meaningful
  const double target = ctx.options.correction_margin_mm;
  const double band = ctx.options.influence_mm;
  // Margin gradients (exact clearance, finite differences) where the barrier may act.
  std::vector<Eigen::Vector2d> grad(n, Eigen::Vector2d::Zero());
  std::vector<char> watched(n, 0);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    if (!(clear[i].margin < band)) return;
    watched[i] = 1;
    const auto& fr = ctx.frames[i];
    const double m0 = clear[i].margin;
    grad[i].x() = (ctx.clearance(i, rotate_axis(axes[i], eps * fr.f)).margin - m0) / eps;
    grad[i].y() = (ctx.clearance(i, rotate_axis(axes[i], eps * fr.t)).margin - m0) / eps;
  });
  std::vector<double> x(2 * n, 0.0);
  ceres::Problem problem;
  const double w2 = std::sqrt(ctx.options.smooth_weight), wd = std::sqrt(ctx.options.smooth_deviation_weight);
  for (size_t i = 0; i < n; ++i) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Deviation, 2, 2>(new Deviation{wd}), nullptr, &x[2 * i]);
    if (watched[i])
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Barrier, 1, 2>(
                                   new Barrier{clear[i].margin, grad[i].x(), grad[i].y(), target, 100.0 * w2}),
                               nullptr, &x[2 * i]);
  }
  for (size_t i = 1; i + 1 < n; ++i) {
    SecondDifference* sd = new SecondDifference;
    for (int k = 0; k < 3; ++k) {
      sd->a[k] = axes[i - 1 + static_cast<size_t>(k)];
      sd->f[k] = ctx.frames[i - 1 + static_cast<size_t>(k)].f;
      sd->t[k] = ctx.frames[i - 1 + static_cast<size_t>(k)].t;
    }
    sd->weight = w2;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SecondDifference, 3, 2, 2, 2>(sd), nullptr,
                             &x[2 * (i - 1)], &x[2 * i], &x[2 * (i + 1)]);
  }
  for (size_t i = 0; i < 2 * n; ++i) {
    problem.SetParameterLowerBound(&x[i & ~size_t{1}], static_cast<int>(i & 1), -bound);
    problem.SetParameterUpperBound(&x[i & ~size_t{1}], static_cast<int>(i & 1), bound);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.max_num_iterations = ctx.options.smooth_iterations;
  so.num_threads = 2;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable()) return false;

  std::vector<Vector3d> out(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& fr = ctx.frames[i];
    out[i] = clamp_to_cone(rotate_axis(axes[i], x[2 * i] * fr.f + x[2 * i + 1] * fr.t), fr.n, ctx.cos_max_tilt);
  }
  std::vector<BodyClearance> c2 = all_clearances(ctx, out);
  // Exact check: a row the smoothing pushed below its clearance (the linearisation was off) keeps the
  // dynamic axis; rows that were already uncleared may only improve.
  for (size_t i = 0; i < n; ++i) {
    const bool worse = c2[i].margin < 0 && c2[i].margin < clear[i].margin;
    if (worse) continue;
    axes[i] = out[i];
    clear[i] = c2[i];
  }
  return true;
}

}  // namespace tf
