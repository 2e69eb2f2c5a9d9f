// Sub-steps of one block, per tool part (see sweep.hpp for the bound). Each part gets as many sub-steps as
// its own pieces and its own tolerance need. A long cylinder is a body of pieces sharing sub-steps plus a
// cap at each end that is a face of the tool: inside the body a piece's ends are covered by its
// neighbours, so only the tilt of its length counts (phi * length / 2), while a real end face also tilts
// by phi * radius and needs more sub-steps, which the short cap takes alone. A 3-axis line is one exact
// step of whole parts.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>

#include "tiltfield/core/angles.hpp"
#include "tiltfield/dexel/sweep.hpp"

namespace tf {
namespace {

constexpr int kProbe = 16;      // poses sampling the block's rotation before any sub-step is chosen
constexpr double kStart = 0.85;  // share of the tolerance the first sub-step guess spends on rotation

// Sub-steps for a block turning the axis by theta (rad) to keep points `reach` from the pivot within
// kStart * tol: the held axis is the sub-step's middle one, so a point turns at most theta / (2 n) away
// from it.
double rotation_substeps(double theta, double reach, double tol) { return theta * reach / (2.0 * kStart * tol); }
constexpr double kAim = 0.9;    // share of the tolerance a refinement aims at
// phi r + dev is sampled at a sub-step's ends and quarter times. For a steady turn phi is |t - 1/2| times
// the sub-step's turn and dev a parabola 4 D t (1 - t); their sum peaks between the samples at D (1 + u^2),
// u = phi_end r / (2 D), against the samples' largest max(D, D (u + 3/4), 2 D u): at most 17/16 of it
// (u = 1/4). The sampled value times that is the bound.
constexpr double kBetweenSamples = 17.0 / 16.0;


// A piece as swept: a sphere about its centre, or a cylinder about its mid-point, `height` above the tip
// on the axis (plus `offset` sideways for a torus' ring sphere). `reach` is the factor of phi in its
// bound: 0 for a sphere, half its length inside a body, the distance to its rim with a real end face.
struct Piece {
  ToolPart centred;  // the part with its pivot at the origin of the tool frame
  double height = 0.0, offset = 0.0, angle = 0.0;
  double reach = 0.0;
};

struct Bound {
  double value = 0.0;    // largest phi * reach + dev, mm
  double phi_max = 0.0;  // largest phi, rad
};

Piece sphere_piece(const ToolPart& part) {
  Piece p{part, part.h0, part.offset, part.angle, 0.0};
  p.centred.h0 = 0.0;
  p.centred.offset = 0.0;
  return p;
}

Piece cylinder_piece(const ToolPart& part, double a, double b, bool ends_covered) {
  Piece p{part, (a + b) / 2, 0.0, 0.0, ends_covered ? (b - a) / 2 : std::hypot((b - a) / 2, part.radius)};
  p.centred.h0 = -(b - a) / 2;
  p.centred.h1 = (b - a) / 2;
  return p;
}

Eigen::Vector3d side_of(const Eigen::Vector3d& axis, const Eigen::Vector3d& ref, double angle) {
  const Eigen::Vector3d r = (ref - axis * axis.dot(ref)).normalized();
  return r * std::cos(angle) + axis.cross(r) * std::sin(angle);
}

Eigen::Vector3d pivot_at(const Piece& p, const ToolPose& pose, const Eigen::Vector3d& ref) {
  Eigen::Vector3d c = pose.tip + p.height * pose.axis;
  if (p.offset != 0.0) c += p.offset * side_of(pose.axis, ref, p.angle);
  return c;
}

// Poses at tau = j / (4 n), j = 0 .. 4n: the sub-step ends and their quarter points (cached per n).
const std::vector<ToolPose>& poses_for(const PoseAt& pose_at, int n, BlockSweep& cache) {
  for (size_t i = 0; i < cache.pose_sets_used; ++i)
    if (cache.pose_sets[i].first == n) return cache.pose_sets[i].second;
  if (cache.pose_sets_used == cache.pose_sets.size()) cache.pose_sets.emplace_back();
  auto& [count, poses] = cache.pose_sets[cache.pose_sets_used++];
  count = n;
  poses.resize(size_t(4 * n + 1));
  for (int j = 0; j <= 4 * n; ++j) {
    poses[j] = pose_at(double(j) / (4.0 * n));
    poses[j].axis.normalize();
  }
  return poses;
}

Bound substep_bound(const std::vector<ToolPose>& poses, int n, const std::vector<Piece>& pieces) {
  Bound b;
  for (int k = 0; k < n; ++k) {
    const ToolPose* q = &poses[size_t(4 * k)];
    const Eigen::Vector3d& held = q[2].axis;
    const Eigen::Vector3d ref = held.unitOrthogonal();
    double phi[5];
    for (int j = 0; j < 5; ++j) b.phi_max = std::max(b.phi_max, phi[j] = angle_between(q[j].axis, held));
    for (const Piece& p : pieces) {
      const Eigen::Vector3d c0 = pivot_at(p, q[0], ref), c4 = pivot_at(p, q[4], ref);
      for (int j = 0; j < 5; ++j) {
        const double dev = j == 0 || j == 4 ? 0.0 : (pivot_at(p, q[j], ref) - (c0 + (c4 - c0) * (j / 4.0))).norm();
        b.value = std::max(b.value, phi[j] * p.reach + dev);
      }
    }
  }
  b.value *= kBetweenSamples;
  return b;
}

struct Context {
  const PoseAt& pose_at;
  double theta;  // the block's total axis rotation, rad
  const SweepOptions& options;
  BlockSweep& out;
  int least_n;  // sub-steps at least (a quarter turn of the rotary joints each)
  bool exact_end;  // the cutting parts at the exact end pose too (sweep_block)
};

// Sub-steps of a group of pieces: from the rotation estimate, grown until the measured bound holds. The
// swept pieces go to out.parts.
Bound sweep_group(const Context& cx, const std::vector<Piece>& pieces, double tol, int& n) {
  double reach = 0.0;
  for (const Piece& p : pieces) reach = std::max(reach, p.reach);
  const int max_n = std::max(1, cx.options.max_substeps);
  n = std::clamp(std::max(cx.least_n, static_cast<int>(std::ceil(rotation_substeps(cx.theta, reach, tol)))), 1, max_n);
  Bound b;
  for (;;) {
    b = substep_bound(poses_for(cx.pose_at, n, cx.out), n, pieces);
    if (b.value <= tol || n >= max_n) break;
    // The rotation term falls with the step, the pivot's deviation with its square.
    n = std::min(max_n, std::max(n + 1, static_cast<int>(std::ceil(n * std::min(4.0, b.value / (kAim * tol))))));
  }
  const std::vector<ToolPose>& poses = poses_for(cx.pose_at, n, cx.out);
  auto add = [&](const Piece& p, const Eigen::Vector3d& c0, const Eigen::Vector3d& axis, const Eigen::Vector3d& ref,
                 const Eigen::Vector3d& d) {
    cx.out.parts.push_back(sweep_part(p.centred, c0, axis, ref, d));
    cx.out.parts.back().on_axis = p.offset == 0.0;
    cx.out.box.extend(cx.out.parts.back().box);
  };
  for (int k = 0; k < n; ++k) {
    const ToolPose* q = &poses[size_t(4 * k)];
    const Eigen::Vector3d& held = q[2].axis;
    const Eigen::Vector3d ref = held.unitOrthogonal();
    for (const Piece& p : pieces) {
      const Eigen::Vector3d c0 = pivot_at(p, q[0], ref), c4 = pivot_at(p, q[4], ref);
      add(p, c0, held, ref, c4 - c0);
    }
  }
  // A sub-step holds its part at the middle axis: within the bound of the true motion, but not through
  // the block's exact end pose, where the next block starts; a rapid from there met the sliver of material
  // the held axis left in the tool (found in review). On request, the cutting parts at the exact end pose
  // are parts of their own, not moving.
  if (cx.exact_end && cx.theta > 0.0) {
    const ToolPose& q = poses.back();
    const Eigen::Vector3d ref = q.axis.unitOrthogonal();
    for (const Piece& p : pieces)
      if (p.centred.cutting) add(p, pivot_at(p, q, ref), q.axis, ref, Eigen::Vector3d::Zero());
  }
  return b;
}

// Is the bottom face of cylinder `c` covered by a sphere of the same kind centred there on the axis with
// at least its radius (a ball end's equator)? Then its tilt moves the rim only inside that sphere.
bool bottom_covered(const ToolPart& c, const std::vector<ToolPart>& parts) {
  for (const ToolPart& s : parts)
    if (s.kind == ToolPart::Kind::Sphere && s.cutting == c.cutting && s.offset == 0.0 && std::abs(s.h0 - c.h0) < 1e-9 &&
        s.radius >= c.radius)
      return true;
  return false;
}

// The number of body pieces that makes the block cheapest: a sub-step of the pieces crosses rays in
// proportion to their total length plus an end overlap each; the sub-steps grow with a piece's length.
int cheapest_pieces(double length, double radius, double theta, double tol, int max_pieces) {
  int best = 1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int m = 1; m <= max_pieces; ++m) {
    const double n = std::max(1.0, std::ceil(rotation_substeps(theta, length / (2 * m), tol)));
    const double cost = n * (length + 3.0 * radius * m);
    if (cost < best_cost) {
      best_cost = cost;
      best = m;
    }
  }
  return best;
}

// A cylinder part: whole when it does not turn (exact) or is short; otherwise a body of pieces and a cap
// at each real end face, overlapping the body by delta >= radius * (phi_body + phi_cap), the most the
// two can open at their joint, so that no point between them is missed.
void sweep_cylinder(const Context& cx, const ToolPart& part, bool covered_below, double tol, Bound& bound, int& most_n) {
  const double r = part.radius;
  const double cap = r;  // cap length outside the overlap
  const double a = part.h0 + (covered_below ? 0.0 : cap), b = part.h1 - cap;
  std::vector<Piece> pieces;
  int n = 1;
  if (cx.theta <= 0.0 || b - a < 2 * r) {
    pieces.push_back(cylinder_piece(part, part.h0, part.h1, false));
    const Bound w = sweep_group(cx, pieces, tol, n);
    bound.value = std::max(bound.value, w.value);
    most_n = std::max(most_n, n);
    return;
  }
  const int m = cheapest_pieces(b - a, r, cx.theta, tol, std::max(1, cx.options.max_pieces));
  for (int i = 0; i < m; ++i) pieces.push_back(cylinder_piece(part, a + (b - a) * i / m, a + (b - a) * (i + 1) / m, true));
  const Bound body = sweep_group(cx, pieces, tol, n);
  bound.value = std::max(bound.value, body.value);
  most_n = std::max(most_n, n);
  for (int end = 0; end < 2; ++end) {
    if (end == 0 && covered_below) continue;
    const size_t mark = cx.out.parts.size();
    double delta = std::max(2.0 * r * body.phi_max, 1e-3);
    for (int attempt = 0;; ++attempt) {
      cx.out.parts.resize(mark);
      pieces.assign(1, end == 0 ? cylinder_piece(part, part.h0, a + delta, false)
                                : cylinder_piece(part, b - delta, part.h1, false));
      const Bound c = sweep_group(cx, pieces, tol, n);
      const double need = r * (body.phi_max + c.phi_max);
      if (need <= delta || attempt == 3) {
        bound.value = std::max(bound.value, need <= delta ? c.value : std::max(c.value, need - delta));
        most_n = std::max(most_n, n);
        break;
      }
      delta = 2.0 * need;
    }
  }
}

}  // namespace

void sweep_block(const PoseAt& pose_at, const std::vector<ToolPart>& parts, const SweepOptions& options,
                 BlockSweep& out, bool rapid, double rotary_turn_deg, bool exact_end) {
  out.parts.clear();
  out.box.setEmpty();
  out.substeps = 1;
  out.swept_parts_cutting = 0;
  out.cutting_error = out.holder_error = 0.0;
  out.pose_sets_used = 0;
  double theta = 0.0, off_chord = 0.0;  // the axis' turn (rad), the tip's largest distance from its chord
  {
    const ToolPose first = pose_at(0.0), last = pose_at(1.0);
    const Eigen::Vector3d chord = last.tip - first.tip;
    ToolPose prev = first;
    for (int i = 1; i <= kProbe; ++i) {
      const ToolPose p = i == kProbe ? last : pose_at(double(i) / kProbe);
      theta += angle_between(prev.axis.normalized(), p.axis.normalized());
      off_chord = std::max(off_chord, (p.tip - first.tip - chord * (double(i) / kProbe)).norm());
      prev = p;
    }
  }
  // A tool that does not turn, carried along a circle across its axis: exact arc sweeps, no sub-steps.
  PlanarArc arc;
  if (theta == 0.0 && off_chord > 1e-9 && planar_arc(pose_at, arc)) {
    // The arc is found from five poses, which cannot tell a turn from that turn plus whole turns: a rotary
    // joint turning a full turn or more carries the tool round the whole circle (found in review: a table
    // turning 4.25 turns in one block was swept as a quarter turn).
    const bool whole_turns = std::abs(rotary_turn_deg) >= 360.0;
    if (whole_turns) arc.sweep = std::copysign(2.0 * std::numbers::pi, arc.sweep);
    sweep_arc(arc, pose_at(0.0), parts, out);
    // The tool's axis stays parallel to the turning joint's, so the tip turns with it.
    if (whole_turns) out.tip_length = arc.radius * std::abs(rotary_turn_deg) * std::numbers::pi / 180.0;
    return;
  }
  const double turn = std::abs(rotary_turn_deg), most = std::max(1, options.max_substeps);
  const double quarters = turn > 0.0 ? std::clamp(std::ceil(turn / 90.0 - 1e-9), 1.0, most) : 1.0;  // NaN: 1
  const Context cx{pose_at, theta, options, out, static_cast<int>(quarters), exact_end && !rapid};
  // Cutting parts first: they are the ones removing material.
  for (int pass = 0; pass < 2; ++pass)
    for (const ToolPart& part : parts) {
      if (part.cutting != (pass == 0)) continue;
      // In a rapid nothing cuts: every part only collides, and gets the collision-only bound.
      const bool cuts = part.cutting && !rapid;
      const double tol = std::max(cuts ? options.tolerance : options.holder_tolerance, 1e-6);
      Bound bound;
      int n = 1;
      if (part.kind == ToolPart::Kind::Sphere) {
        const std::vector<Piece> one{sphere_piece(part)};
        bound = sweep_group(cx, one, tol, n);
      } else {
        sweep_cylinder(cx, part, bottom_covered(part, parts), tol, bound, n);
      }
      if (part.cutting) out.swept_parts_cutting = static_cast<int>(out.parts.size());
      if (cuts) {
        out.cutting_error = std::max(out.cutting_error, bound.value);
        out.substeps = std::max(out.substeps, n);
      } else {
        out.holder_error = std::max(out.holder_error, bound.value);
      }
    }
  // The tip path's length on the finest sampling made.
  const std::vector<ToolPose>* finest = nullptr;
  for (size_t i = 0; i < out.pose_sets_used; ++i)
    if (!finest || out.pose_sets[i].second.size() > finest->size()) finest = &out.pose_sets[i].second;
  out.tip_length = 0.0;
  if (finest)
    for (size_t j = 1; j < finest->size(); ++j) out.tip_length += ((*finest)[j].tip - (*finest)[j - 1].tip).norm();
}

}  // namespace tf
