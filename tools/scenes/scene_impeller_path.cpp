// The impeller's hub-finishing path: a zig-zag in one channel, kept clear of the blades by exact
// distances to the blade mesh.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "scene_distance.hpp"
#include "scene_impeller.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::scenes {

namespace {
constexpr double kPi = std::numbers::pi;
// Width of the blend (in m) over which the passes narrow from the full channel to the channel between
// blade 0 and its splitter, upstream of the splitter's leading edge.
constexpr double kSplitterBlend = 0.15;
// The channel edges are placed this much beyond the required ball clearance, so that the interpolation
// between knots does not dip below it.
constexpr double kSlack = 0.01;

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// Catmull-Rom through equally spaced knots v over [x0, x1].
double interpolate(const std::vector<double>& v, double x0, double x1, double x) {
  const int n = static_cast<int>(v.size());
  const double t = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0) * (n - 1);
  const int i = std::min(n - 2, static_cast<int>(std::floor(t)));
  const double u = t - i;
  const double p0 = v[std::max(0, i - 1)], p1 = v[i], p2 = v[i + 1], p3 = v[std::min(n - 1, i + 2)];
  return 0.5 * (2 * p1 + (-p0 + p2) * u + (2 * p0 - 5 * p1 + 4 * p2 - p3) * u * u + (-p0 + 3 * p1 - 3 * p2 + p3) * u * u * u);
}

struct Channel {
  const ImpellerModel& model;
  const MeshDistance& blades;
  double R, target;

  double theta0(double m) const { return model.camber_theta(0, m, 0.0); }
  // Angular width from blade 0's camber line to the far side's camber line (blade 1, or the splitter
  // blended in upstream of its leading edge).
  double width(double m) const {
    const ImpellerOptions& o = model.options();
    const double pitch = 2.0 * kPi / o.blades;
    if (!o.splitters) return pitch;
    const double b = smoothstep((m - (o.splitter_start - kSplitterBlend)) / kSplitterBlend);
    return pitch - 0.5 * pitch * b;
  }
  Eigen::Vector3d ball(double m, double theta) const {
    return model.hub_point(m, theta) + R * model.hub_normal(m, theta);
  }
  double clearance(double m, double theta) const { return blades.distance(ball(m, theta), R + 10.0) - R; }
  // Angular half-width a blade takes at the hub plus the ball's room, estimated from the blade angle.
  double margin_estimate(double m) const {
    const ImpellerOptions& o = model.options();
    const double r = model.hub_rz(m).x();
    const double dtheta = (model.camber_theta(0, m + 1e-6, 0.0) - model.camber_theta(0, m - 1e-6, 0.0)) / 2e-6;
    const double cos_beta = model.hub_tangent_rz(m).norm() / std::hypot(model.hub_tangent_rz(m).norm(), r * dtheta);
    return (R + target + 0.5 * o.thickness_hub) / (r * cos_beta);
  }
  // Walking from `from` (where the ball is clear by `target`, as the caller checked) toward `to` at
  // fixed m: the last angle before the clearance first drops below `target` (bisected to ~1e-12 rad),
  // or `to` when it never does.
  double edge(double m, double from, double to) const {
    const int n = 48;
    double good = from;
    for (int k = 1; k <= n; ++k) {
      const double t = from + (to - from) * k / n;
      if (clearance(m, t) < target) {
        double lo = good, hi = t;  // lo clear, hi not
        for (int it = 0; it < 40; ++it) {
          const double mid = 0.5 * (lo + hi);
          (clearance(m, mid) < target ? hi : lo) = mid;
        }
        return lo;
      }
      good = t;
    }
    return to;
  }
};

}  // namespace

ToolPath impeller_path(const ImpellerModel& model, const Mesh& blade_mesh, ImpellerPathReport* report) {
  const ImpellerOptions& o = model.options();
  const MeshDistance blades(blade_mesh);
  const Channel ch{model, blades, o.tool_radius, o.ball_clearance + kSlack};

  // Channel edges at knots, as angles relative to blade 0's camber line.
  const int K = 61;
  std::vector<double> lo(K), hi(K);
  auto knot_m = [&](int k) { return o.m_start + (o.m_end - o.m_start) * k / (K - 1); };
  for (int k = 0; k < K; ++k) {
    const double m = knot_m(k), t0 = ch.theta0(m), w = ch.width(m), est = ch.margin_estimate(m);
    const double mid = t0 + 0.5 * w;
    if (ch.clearance(m, mid) < ch.target)
      throw InputError("scene impeller", 0, "--tool-radius",
                       "the channel is too narrow for a ball of radius " + fixed(o.tool_radius, 3) + " mm at m = " +
                           fixed(m, 3) + " (use a smaller tool, fewer blades or no splitters)");
    lo[k] = std::max(ch.edge(m, mid, t0), t0 + est) - t0;
    hi[k] = std::min(ch.edge(m, mid, t0 + w + est), t0 + w - est) - t0;
    if (hi[k] < lo[k]) lo[k] = hi[k] = 0.5 * (lo[k] + hi[k]);
  }

  const int P = o.passes;
  auto pass_theta = [&](int j, double m) {
    const double u = P == 1 ? 0.5 : static_cast<double>(j) / (P - 1);
    const double a = interpolate(lo, o.m_start, o.m_end, m), b = interpolate(hi, o.m_start, o.m_end, m);
    return ch.theta0(m) + a + u * (b - a);
  };
  auto row = [&](double m, double theta) {
    CLPoint p;
    p.p = ch.ball(m, theta);
    p.n = model.hub_normal(m, theta);
    return p;
  };

  ToolPath path;
  double min_clear = 0.0;
  for (int attempt = 0;; ++attempt) {
    path.rows.clear();
    std::vector<double> row_m;
    for (int j = 0; j < P; ++j) {
      // Arc length of the ball centres along the pass, on a dense table, inverted for equal spacing.
      const int dense = 2000;
      std::vector<double> s(dense + 1, 0.0);
      Eigen::Vector3d prev = row(o.m_start, pass_theta(j, o.m_start)).p;
      for (int i = 1; i <= dense; ++i) {
        const double m = o.m_start + (o.m_end - o.m_start) * i / dense;
        const Eigen::Vector3d p = row(m, pass_theta(j, m)).p;
        s[i] = s[i - 1] + (p - prev).norm();
        prev = p;
      }
      const int n = std::max(1, static_cast<int>(std::ceil(s.back() / o.step - 1e-9)));
      std::vector<double> ms;
      for (int k = 0; k <= n; ++k) {
        const double target = s.back() * k / n;
        const size_t i = std::min<size_t>(dense, std::lower_bound(s.begin(), s.end(), target) - s.begin());
        const double s0 = i == 0 ? 0.0 : s[i - 1], s1 = s[i];
        const double f = i == 0 || s1 <= s0 ? 0.0 : (target - s0) / (s1 - s0);
        ms.push_back(o.m_start + (o.m_end - o.m_start) * ((i == 0 ? 0.0 : i - 1 + f) / dense));
      }
      if (j % 2 == 1) std::reverse(ms.begin(), ms.end());
      if (j > 0) {  // link across the channel at the end where the previous pass stopped
        const double m = ms.front(), ta = pass_theta(j - 1, m), tb = pass_theta(j, m);
        const Eigen::Vector2d rz = model.hub_rz(m), nz = model.hub_normal_rz(m);
        const double arc = (rz.x() + o.tool_radius * nz.x()) * std::abs(tb - ta);
        const int nl = std::max(1, static_cast<int>(std::ceil(arc / o.step - 1e-9)));
        for (int k = 1; k < nl; ++k) {
          path.rows.push_back(row(m, ta + (tb - ta) * k / nl));
          row_m.push_back(m);
        }
      }
      for (double m : ms) {
        path.rows.push_back(row(m, pass_theta(j, m)));
        row_m.push_back(m);
      }
    }
    // Exact check of every row against the blade mesh; push the edges in around any row that is short.
    min_clear = std::numeric_limits<double>::infinity();
    bool ok = true;
    for (size_t i = 0; i < path.rows.size(); ++i) {
      const double d = blades.distance(path.rows[i].p, o.tool_radius + 10.0) - o.tool_radius;
      min_clear = std::min(min_clear, d);
      if (d >= o.ball_clearance) continue;
      ok = false;
      const double m = row_m[i];
      const double rel = std::atan2(path.rows[i].p.y(), path.rows[i].p.x()) - ch.theta0(m);
      const double a = interpolate(lo, o.m_start, o.m_end, m), b = interpolate(hi, o.m_start, o.m_end, m);
      const double push = (o.ball_clearance - d + kSlack) / model.hub_rz(m).x();
      const double t = (m - o.m_start) / (o.m_end - o.m_start) * (K - 1);
      const bool low_side = std::remainder(rel - a, 2 * kPi) < std::remainder(b - rel, 2 * kPi);
      for (int k = std::max(0, static_cast<int>(t) - 1); k <= std::min(K - 1, static_cast<int>(t) + 2); ++k) {
        if (low_side) lo[k] = std::min(lo[k] + push, hi[k]);
        else hi[k] = std::max(hi[k] - push, lo[k]);
      }
    }
    if (ok) break;
    if (attempt >= 30) throw JobError("scene impeller: could not keep the ball clear of the blades");
  }

  if (report) {
    report->min_ball_clearance = min_clear;
    report->passes = P;
    report->nominal_axis_hits = 0;
    const Tool tool = ball_tool(o.tool_radius);
    for (const auto& r : path.rows) report->nominal_axis_hits += tool_axis_hits(tool, blades, r.p, r.n);
  }
  return path;
}

}  // namespace tf::scenes
