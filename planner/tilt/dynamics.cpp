// The rigid-body model: J dOmega/dt = repulsion + attraction - damping, integrated along the path.
#include "dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "tiltfield/core/angles.hpp"

namespace tf {
using Eigen::Vector3d;

Vector3d rotate_axis(const Vector3d& a, const Vector3d& w) {
  const double th = w.norm();
  if (th < 1e-15) return a;
  const Vector3d k = w / th;
  const Vector3d r = a * std::cos(th) + k.cross(a) * std::sin(th) + k * k.dot(a) * (1 - std::cos(th));
  return r.normalized();
}

Vector3d clamp_to_cone(const Vector3d& a, const Vector3d& n, double cos_max) {
  const double c = a.dot(n);
  if (c >= cos_max) return a;
  Vector3d perp = a - c * n;
  if (perp.norm() < 1e-12) perp = n.unitOrthogonal();
  perp.normalize();
  const double s = std::sqrt(std::max(0.0, 1 - cos_max * cos_max));
  return (cos_max * n + s * perp).normalized();
}

BodySamples make_body_samples(const Tool& tool, const PlannerBasics& basics, double spacing) {
  BodySamples out;
  const double cl = tool.cl_height();
  const bool ball = std::holds_alternative<BallCutter>(tool.cutter);
  // One spacing per piece: holder segments get at least 24 points round.
  auto spacing_for = [&](const ToolSample& s) {
    if (s.component != ToolComponent::Holder || s.holder_segment < 0) return spacing;
    const double r = tool.holder[static_cast<size_t>(s.holder_segment)].radius;
    return std::max(spacing, 2 * std::numbers::pi * r / 24.0);
  };
  std::map<double, std::vector<ToolSample>> by_spacing;
  by_spacing[spacing] = tool.sample_surface(spacing);
  for (const auto& h : tool.holder) {
    const double s = std::max(spacing, 2 * std::numbers::pi * h.radius / 24.0);
    if (!by_spacing.count(s)) by_spacing[s] = tool.sample_surface(s);
  }
  struct Raw {
    Vector3d p;
    double w, req;
  };
  std::vector<Raw> raw;
  for (const auto& [s, list] : by_spacing)
    for (const ToolSample& ts : list) {
      if (ball && ts.component == ToolComponent::Ball) continue;
      if (spacing_for(ts) != s) continue;
      raw.push_back({ts.p - Vector3d(0, 0, cl), s * s, required_clearance(basics, ts.component)});
    }
  std::sort(raw.begin(), raw.end(), [](const Raw& a, const Raw& b) { return a.p.z() < b.p.z(); });
  // Chunks: consecutive heights, no longer than about the local radius (at least 2 spacings).
  size_t i = 0;
  while (i < raw.size()) {
    const double z0 = raw[i].p.z();
    const double r0 = std::max(std::hypot(raw[i].p.x(), raw[i].p.y()), 2 * spacing);
    size_t j = i;
    while (j < raw.size() && raw[j].p.z() - z0 <= std::max(1.5 * r0, 2 * spacing)) ++j;
    BodySamples::Chunk c;
    c.begin = static_cast<int>(out.p.size());
    double zmin = raw[i].p.z(), zmax = raw[j - 1].p.z();
    c.hc = 0.5 * (zmin + zmax);
    for (size_t k = i; k < j; ++k) {
      out.p.push_back(raw[k].p);
      out.weight.push_back(raw[k].w);
      out.required.push_back(raw[k].req);
      c.rho = std::max(c.rho, (raw[k].p - Vector3d(0, 0, c.hc)).norm());
      c.required = std::max(c.required, raw[k].req);
    }
    c.end = static_cast<int>(out.p.size());
    out.chunks.push_back(c);
    i = j;
  }
  return out;
}

BodySamples with_clearance(BodySamples samples, double required) {
  std::fill(samples.required.begin(), samples.required.end(), required);
  for (auto& c : samples.chunks) c.required = required;
  return samples;
}

DynamicsParams dynamics_params(const PlanOptions& o, const Tool& tool, const PlannerBasics& basics) {
  DynamicsParams p;
  p.inertia = o.inertia;
  p.attraction = o.attraction;
  p.damping = o.damping;
  p.influence = o.influence_mm;
  p.min_gap = o.min_gap_mm;
  // A patch of R^2 at the far end of the tool, halfway into the influence zone, pushes with
  // repulsion_gain x (attraction at 1 rad): the gain is relative to the attraction, whatever the units.
  const double R = tool.radius();
  const double lever = std::max(tool.total_length() - tool.cl_height(), R);
  p.force_scale = o.repulsion_gain * o.attraction / (R * R * lever);
  p.max_substep_rad = o.max_substep_deg * kDeg;
  p.cos_max_tilt = std::cos(basics.max_tilt_deg * kDeg);
  return p;
}

namespace {

// Temporal coherence for the chunk culling: a chunk's distance lower bound stays valid while the chunk
// centre moves less than the slack it had.
struct ChunkCache {
  std::vector<Vector3d> centre;
  std::vector<double> bound;  // distance lower bound of the chunk's sphere at `centre`
  std::vector<int> hint;
};

class Repulsion {
 public:
  Repulsion(const PotentialSource& source, const DynamicsParams& p)
      : bvh_(*source.bvh), field_(*source.field), s_(*source.samples), p_(p),
        // A small set (a few fixtures) is cheap to query without a limit, and its exact distance keeps a
        // chunk's bound valid far longer than the limited query's.
        unlimited_(source.bvh->size() <= 4096) {
    cache_.centre.assign(s_.chunks.size(), Vector3d::Constant(std::numeric_limits<double>::infinity()));
    cache_.bound.assign(s_.chunks.size(), -1.0);
    cache_.hint.assign(s_.chunks.size(), -1);
  }

  // Total repulsive torque about c for the axis a (e1 fixes the azimuth of the samples).
  Vector3d torque(const Vector3d& c, const Vector3d& a, const Vector3d& e1_hint) {
    Vector3d e1 = e1_hint - e1_hint.dot(a) * a;
    if (e1.norm() < 1e-9) e1 = a.unitOrthogonal();
    e1.normalize();
    const Vector3d e2 = a.cross(e1);
    Vector3d tau = Vector3d::Zero();
    for (size_t k = 0; k < s_.chunks.size(); ++k) {
      const auto& ch = s_.chunks[k];
      const Vector3d cc = c + ch.hc * a;
      const double reach = p_.influence + ch.required;
      double lb = cache_.bound[k] - (cc - cache_.centre[k]).norm();
      bool fresh = false;
      if (lb < reach) {
        // Near the surfaces the field answers (its trilinear value is within sqrt(3) cells of the exact
        // distance); far away (or off the grid) an exact query gives a bound that stays valid longer.
        const double df = field_.sample(cc, nullptr);
        if (df < field_.band()) {
          cache_.centre[k] = cc;
          cache_.bound[k] = df - std::sqrt(3.0) * field_.cell() - ch.rho;
          lb = cache_.bound[k];
          fresh = true;
        }
      }
      if (lb < reach && !fresh) {
        const double limit = unlimited_ ? std::numeric_limits<double>::infinity() : 2 * (reach + ch.rho);
        const ClosestHit h = bvh_.closest(cc, limit, cache_.hint[k]);
        cache_.hint[k] = h.triangle;
        cache_.centre[k] = cc;
        cache_.bound[k] = (h.triangle >= 0 ? h.distance : limit) - ch.rho;
        lb = cache_.bound[k];
      }
      if (lb >= reach) continue;
      for (int i = ch.begin; i < ch.end; ++i) {
        const Vector3d& q = s_.p[static_cast<size_t>(i)];
        const Vector3d r = q.x() * e1 + q.y() * e2 + q.z() * a;
        Vector3d grad;
        const double d = field_.sample(c + r, &grad);
        const double gap = d - s_.required[static_cast<size_t>(i)];
        if (gap >= p_.influence) continue;
        // Khatib: psi(x) = 1/2 (1/x - 1)^2 with x = gap / influence; the slope is capped below min_gap.
        const double x = std::max(gap, p_.min_gap) / p_.influence;
        const double slope = (1.0 / x - 1.0) / (x * x);
        const Vector3d force = p_.force_scale * s_.weight[static_cast<size_t>(i)] * slope * grad;
        tau += r.cross(force);
      }
    }
    return tau;
  }

 private:
  const ClearanceBvh& bvh_;
  DistanceField& field_;
  const BodySamples& s_;
  const DynamicsParams& p_;
  bool unlimited_;
  ChunkCache cache_;
};

PathState lerp_state(const PathState& a, const PathState& b, double u) {
  PathState s;
  s.c = a.c + u * (b.c - a.c);
  s.n = (a.n + u * (b.n - a.n)).normalized();
  s.f = a.f + u * (b.f - a.f);
  s.f = (s.f - s.f.dot(s.n) * s.n);
  s.f = s.f.norm() > 1e-9 ? s.f.normalized() : a.f;
  s.t = s.f.cross(s.n);
  s.nominal = (a.nominal + u * (b.nominal - a.nominal));
  s.nominal = s.nominal.norm() > 1e-9 ? s.nominal.normalized() : a.nominal;
  return s;
}

struct Body {
  Vector3d axis, omega;
};

// One semi-implicit step: attraction and damping implicit (unconditionally stable), repulsion explicit.
Body step(const Body& b, const PathState& s, double dt, std::vector<Repulsion>& reps, const DynamicsParams& p) {
  Vector3d tau_rep = Vector3d::Zero();
  for (Repulsion& rep : reps) tau_rep += rep.torque(s.c, b.axis, s.f);
  const Vector3d cr = b.axis.cross(s.nominal);
  const double ang = std::atan2(cr.norm(), b.axis.dot(s.nominal));
  const Vector3d tau_att = cr.norm() > 1e-15 ? Vector3d(p.attraction * ang * cr / cr.norm()) : Vector3d::Zero();
  Vector3d tau = tau_rep + tau_att;
  // Only roll about f and pitch about t are controlled.
  tau = tau.dot(s.f) * s.f + tau.dot(s.t) * s.t;
  Vector3d omega = b.omega.dot(s.f) * s.f + b.omega.dot(s.t) * s.t;
  omega = (p.inertia * omega + dt * tau) / (p.inertia + p.damping * dt + p.attraction * dt * dt);
  Body out{rotate_axis(b.axis, omega * dt), omega};
  if (out.axis.dot(s.n) < p.cos_max_tilt) {
    out.axis = clamp_to_cone(out.axis, s.n, p.cos_max_tilt);
    Vector3d m = out.axis.cross(s.n);
    if (m.norm() > 1e-12) {
      m.normalize();
      const double w = out.omega.dot(m);
      if (w < 0) out.omega -= w * m;
    }
  }
  return out;
}

// Advances b over a stretch of duration T from state s0 to s1, halving the sub-step while the axis
// would turn more than max_substep_rad in one.
Body advance(Body b, const PathState& s0, const PathState& s1, double T, std::vector<Repulsion>& rep,
             const DynamicsParams& p) {
  double done = 0, dt = T;
  int guard = 0;
  while (done < T - 1e-15 && guard++ < 4096) {
    dt = std::min(dt, T - done);
    const PathState s = lerp_state(s0, s1, (done + dt) / T);
    const Body nb = step(b, s, dt, rep, p);
    const double turn = std::acos(std::clamp(nb.axis.dot(b.axis), -1.0, 1.0));
    if (turn > p.max_substep_rad && dt > T / 1024) {
      dt *= 0.5;
      continue;
    }
    b = nb;
    done += dt;
    if (turn < 0.5 * p.max_substep_rad) dt *= 1.5;
  }
  return b;
}

}  // namespace

bool restarts_at(const ToolPath& path, const std::vector<Vector3d>& nominal, size_t i) {
  if (i == 0 || i >= path.rows.size()) return false;
  if (path.rows[i].approach == Approach::Link) return true;
  if (i < 2 || i + 1 >= path.rows.size()) return false;
  const Vector3d in = path.rows[i - 1].p - path.rows[i - 2].p, out = path.rows[i + 1].p - path.rows[i].p;
  const double scale = in.norm() * out.norm();
  if (!(scale > 1e-18 && in.dot(out) < kReversalCos * scale)) return false;
  // The nominal's turn over the reversal (from the row before it to the row after: the frames of the two
  // rows at the step-over already blend both directions) beyond the normal's own turn: a lead or tilt
  // that flips with the feed.
  // (APT's rows carry the axis itself in n: the whole turn counts.)
  const bool normals = path.rows[i - 2].normal_known && path.rows[i + 1].normal_known;
  const double jump = angle_between(nominal[i - 2], nominal[i + 1]) -
                       (normals ? angle_between(path.rows[i - 2].n, path.rows[i + 1].n) : 0.0);
  return jump > kRestartJumpRad;
}

void integrate_axes(const ToolPath& path, const std::vector<LocalFrame>& frames, const std::vector<Vector3d>& nominal,
                    const std::vector<double>& feed, const std::vector<PotentialSource>& sources,
                    const DynamicsParams& p, const Progress& progress, std::vector<Vector3d>& axes,
                    std::atomic<size_t>* published) {
  const size_t n = path.rows.size();
  axes.resize(n);
  if (n == 0) return;
  std::vector<Repulsion> rep;
  for (const PotentialSource& s : sources) rep.emplace_back(s, p);
  auto state = [&](size_t i) {
    return PathState{path.rows[i].p, frames[i].f, frames[i].n, frames[i].t, nominal[i]};
  };
  // Starts at row i from its nominal axis, settled with the path standing still, so the run starts in
  // equilibrium, not with a jolt.
  auto start_at = [&](size_t i) {
    Body b{clamp_to_cone(nominal[i], frames[i].n, p.cos_max_tilt), Vector3d::Zero()};
    const PathState s = state(i);
    const double wn = std::sqrt(p.attraction / p.inertia);
    const double settle = 8.0 / std::max(wn, 1e-9);
    for (int k = 0; k < 32; ++k) b = advance(b, s, s, settle / 32, rep, p);
    b.omega.setZero();
    return b;
  };
  Body b = start_at(0);
  axes[0] = b.axis;
  for (size_t i = 1; i < n; ++i) {
    const double ds = (path.rows[i].p - path.rows[i - 1].p).norm();
    const double v = std::max(feed[i], 1e-6) / 60.0;  // mm/s
    if (restarts_at(path, nominal, i)) {
      b = start_at(i);
    } else if (ds > 1e-12) {
      b = advance(b, state(i - 1), state(i), ds / v, rep, p);
    }
    axes[i] = b.axis;
    if ((i & 255) == 0 && published) published->store(i + 1, std::memory_order_release);
    if ((i & 1023) == 0) report(progress, "plan", 0.1 + 0.6 * static_cast<double>(i) / static_cast<double>(n));
  }
  if (published) published->store(n, std::memory_order_release);
}

}  // namespace tf
