// The impeller's hub-finishing path: a zig-zag in one channel, kept clear of the blades by exact
// distances to the blade mesh.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "scene_distance.hpp"
#include "scene_geometry.hpp"
#include "scene_impeller.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::scenes {

namespace {
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
  return 0.5 * (2 * p1 + (-p0 + p2) * u + (2 * p0 - 5 * p1 + 4 * p2 - p3) * u * u +
                (-p0 + 3 * p1 - 3 * p2 + p3) * u * u * u);
}

struct Channel {
  const ImpellerModel& model;
  const TriangleBvh& blades;
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
  double clearance(double m, double theta) const { return blades.closest(ball(m, theta), R + 10.0).distance - R; }
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

constexpr int kKnots = 61;

// Channel edges at kKnots knots over [m_start, m_end], as angles relative to blade 0's camber line.
struct ChannelEdges {
  std::vector<double> lo, hi;
};

ChannelEdges channel_edges(const Channel& ch) {
  const ImpellerOptions& o = ch.model.options();
  ChannelEdges e{std::vector<double>(kKnots), std::vector<double>(kKnots)};
  for (int k = 0; k < kKnots; ++k) {
    const double m = o.m_start + (o.m_end - o.m_start) * k / (kKnots - 1);
    const double t0 = ch.theta0(m), w = ch.width(m), est = ch.margin_estimate(m);
    const double mid = t0 + 0.5 * w;
    if (ch.clearance(m, mid) < ch.target)
      throw InputError("scene impeller", 0, "--tool-radius",
                       "the channel is too narrow for a ball of radius " + fixed(o.tool_radius, 3) + " mm at m = " +
                           fixed(m, 3) + " (use a smaller tool, fewer blades or no splitters)");
    e.lo[k] = std::max(ch.edge(m, mid, t0), t0 + est) - t0;
    e.hi[k] = std::min(ch.edge(m, mid, t0 + w + est), t0 + w - est) - t0;
    if (e.hi[k] < e.lo[k]) e.lo[k] = e.hi[k] = 0.5 * (e.lo[k] + e.hi[k]);
  }
  return e;
}

// The passes spread evenly between the channel edges: pass j of P at the fraction j / (P - 1) across.
struct Passes {
  const Channel& ch;
  const ChannelEdges& edges;

  double theta(int j, double m) const {
    const ImpellerOptions& o = ch.model.options();
    const int P = o.passes;
    const double u = P == 1 ? 0.5 : static_cast<double>(j) / (P - 1);
    const double a = interpolate(edges.lo, o.m_start, o.m_end, m), b = interpolate(edges.hi, o.m_start, o.m_end, m);
    return ch.theta0(m) + a + u * (b - a);
  }
  CLPoint row(double m, double theta) const {
    CLPoint p;
    p.p = ch.ball(m, theta);
    p.n = ch.model.hub_normal(m, theta);
    return p;
  }
};

// The meridional parameters of pass j's rows, equally spaced (<= step) in arc length of the ball centres
// (a dense table inverted), in the pass's direction of travel (odd passes run backward).
std::vector<double> pass_parameters(const Passes& passes, int j) {
  const ImpellerOptions& o = passes.ch.model.options();
  const int dense = 2000;
  std::vector<double> s(dense + 1, 0.0);
  Eigen::Vector3d prev = passes.row(o.m_start, passes.theta(j, o.m_start)).p;
  for (int i = 1; i <= dense; ++i) {
    const double m = o.m_start + (o.m_end - o.m_start) * i / dense;
    const Eigen::Vector3d p = passes.row(m, passes.theta(j, m)).p;
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
  return ms;
}

// The rows with the meridional parameter each was made at.
struct ZigzagRows {
  ToolPath path;
  std::vector<double> m;
  void add(const CLPoint& row, double at) {
    path.rows.push_back(row);
    m.push_back(at);
  }
};

// All passes in order, each linked to the previous one across the channel at the end where that stopped.
ZigzagRows zigzag_rows(const Passes& passes) {
  const ImpellerModel& model = passes.ch.model;
  const ImpellerOptions& o = model.options();
  ZigzagRows rows;
  for (int j = 0; j < o.passes; ++j) {
    const std::vector<double> ms = pass_parameters(passes, j);
    if (j > 0) {
      const double m = ms.front(), ta = passes.theta(j - 1, m), tb = passes.theta(j, m);
      const Eigen::Vector2d rz = model.hub_rz(m), nz = model.hub_normal_rz(m);
      const double arc = (rz.x() + o.tool_radius * nz.x()) * std::abs(tb - ta);
      const int nl = std::max(1, static_cast<int>(std::ceil(arc / o.step - 1e-9)));
      for (int k = 1; k < nl; ++k) rows.add(passes.row(m, ta + (tb - ta) * k / nl), m);
    }
    for (double m : ms) rows.add(passes.row(m, passes.theta(j, m)), m);
  }
  return rows;
}

struct ClearanceCheck {
  double min_clearance = std::numeric_limits<double>::infinity();  // of the ball to the blades, mm
  bool clear = true;                                               // every row at least ball_clearance
};

// Exact check of every row against the blade mesh; around each row that is short of ball_clearance the
// nearer channel edge moves in (at the knots about it) by the shortfall: the largest of the rows about a
// knot, not their sum (at a step of 0.011 mm some forty rows a knot added up their shortfalls and threw
// the edges about, attempt after attempt).
ClearanceCheck push_edges_in(const Channel& ch, const ZigzagRows& rows, ChannelEdges& edges) {
  const ImpellerOptions& o = ch.model.options();
  ClearanceCheck check;
  std::vector<double> push_lo(kKnots, 0.0), push_hi(kKnots, 0.0);
  for (size_t i = 0; i < rows.path.rows.size(); ++i) {
    const Eigen::Vector3d& p = rows.path.rows[i].p;
    // Unbounded: a pass down the middle of a wide channel (two blades, one pass) is farther than any
    // bound from the blades, and its clearance had been infinite (black-box testing).
    const double d = ch.blades.closest(p).distance - o.tool_radius;
    check.min_clearance = std::min(check.min_clearance, d);
    if (d >= o.ball_clearance) continue;
    check.clear = false;
    const double m = rows.m[i];
    const double rel = std::atan2(p.y(), p.x()) - ch.theta0(m);
    const double a = interpolate(edges.lo, o.m_start, o.m_end, m), b = interpolate(edges.hi, o.m_start, o.m_end, m);
    const double push = (o.ball_clearance - d + kSlack) / ch.model.hub_rz(m).x();
    const double t = (m - o.m_start) / (o.m_end - o.m_start) * (kKnots - 1);
    const bool low_side = std::remainder(rel - a, 2 * kPi) < std::remainder(b - rel, 2 * kPi);
    for (int k = std::max(0, static_cast<int>(t) - 1); k <= std::min(kKnots - 1, static_cast<int>(t) + 2); ++k)
      (low_side ? push_lo : push_hi)[k] = std::max((low_side ? push_lo : push_hi)[k], push);
  }
  for (int k = 0; k < kKnots; ++k) {
    edges.lo[k] = std::min(edges.lo[k] + push_lo[k], edges.hi[k]);
    edges.hi[k] = std::max(edges.hi[k] - push_hi[k], edges.lo[k]);
  }
  return check;
}

}  // namespace

ToolPath impeller_path(const ImpellerModel& model, const Mesh& blade_mesh, ImpellerPathReport* report) {
  const ImpellerOptions& o = model.options();
  const TriangleBvh blades({&blade_mesh});
  const Channel ch{model, blades, o.tool_radius, o.ball_clearance + kSlack};
  ChannelEdges edges = channel_edges(ch);
  const Passes passes{ch, edges};

  ZigzagRows rows;
  ClearanceCheck check;
  for (int attempt = 0;; ++attempt) {
    rows = zigzag_rows(passes);
    check = push_edges_in(ch, rows, edges);
    if (check.clear) break;
    if (attempt >= 30) throw JobError("scene impeller: could not keep the ball clear of the blades");
  }

  if (report) {
    report->min_ball_clearance = check.min_clearance;
    report->passes = o.passes;
    report->nominal_axis_hits = 0;
    const Tool tool = ball_tool(o.tool_radius);
    for (const auto& r : rows.path.rows) report->nominal_axis_hits += tool_axis_hits(tool, blades, r.p, r.n);
  }
  return std::move(rows.path);
}

}  // namespace tf::scenes
