// Sharp corners (Gawlik, Karbowski, Ruszaj, cases 1.A/1.B/2.A: the join is the intersection of the neighbouring offsets). They are
// made from the round result: each complete round join (an arc of radius gap about a profile vertex,
// tangent to both neighbours) is replaced by the extensions of the neighbours up to their intersection,
// unless that miter would come closer than the gap to the profile or cross the path; there the round
// join stays. Working on the loop-free round result keeps loop removal exact (a miter hides the disc
// about its vertex from the raw curve).
#include <cmath>
#include <numbers>

#include "segment_bvh.hpp"
#include "offset_internal.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;

// Points where the supporting line/circle of `in` (continued past its end) meets that of `out`
// (continued before its start). Lines are given as a point and a direction.
std::vector<Vector2d> support_crossings(const Segment& s1, const Segment& s2) {
  std::vector<Vector2d> pts;
  auto line_circle = [&](const Vector2d& a, const Vector2d& d, const Vector2d& c, double r) {
    const double A = d.squaredNorm(), t0 = -(a - c).dot(d) / A;
    const Vector2d f = a + t0 * d;
    const double h2 = r * r - (f - c).squaredNorm();
    if (h2 < 0) return;
    const double dt = std::sqrt(h2 / A);
    pts.push_back(a + (t0 - dt) * d);
    pts.push_back(a + (t0 + dt) * d);
  };
  if (!s1.is_arc() && !s2.is_arc()) {
    const Vector2d d1 = s1.b - s1.a, d2 = s2.b - s2.a;
    const double den = cross(d1, d2);
    if (std::abs(den) > 1e-14 * d1.norm() * d2.norm()) pts.push_back(s1.a + cross(s2.a - s1.a, d2) / den * d1);
  } else if (!s1.is_arc()) {
    line_circle(s1.a, s1.b - s1.a, s2.c, s2.r);
  } else if (!s2.is_arc()) {
    line_circle(s2.a, s2.b - s2.a, s1.c, s1.r);
  } else {
    const Vector2d dc = s2.c - s1.c;
    const double d = dc.norm();
    if (d > 0 && d <= s1.r + s2.r && d >= std::abs(s1.r - s2.r)) {
      const double x = (d * d + s1.r * s1.r - s2.r * s2.r) / (2 * d);
      const double h = std::sqrt(std::max(0.0, s1.r * s1.r - x * x));
      const Vector2d e = dc / d, n(-e.y(), e.x());
      pts.push_back(s1.c + x * e + h * n);
      pts.push_back(s1.c + x * e - h * n);
    }
  }
  return pts;
}

// The piece of s's supporting line or circle from p to q, in s's direction of travel.
Segment extension(const Segment& s, const Vector2d& p, const Vector2d& q) {
  Segment e = s.is_arc() ? make_arc_to(p, q, s.c, s.sweep > 0) : make_line(p, q);
  e.kind = SegmentKind::SharpJoin;
  e.line = s.line;
  e.g0 = e.g1 = s.is_arc() ? s.g1 : s.g1;
  return e;
}

// Sharp join: extensions of `in` and `out` up to the crossing of their supports nearest the vertex V.
bool sharp_join(const Segment& in, const Segment& out, const Vector2d& V, double g, double miter_limit,
                std::vector<Segment>& join) {
  const Vector2d E = in.b, S = out.a;
  const Vector2d tin = tangent_at(in, 1.0), tout = tangent_at(out, 0.0);
  double best = miter_limit * g;
  bool found = false;
  Vector2d X;
  for (const Vector2d& p : support_crossings(in, out)) {
    if ((p - E).dot(tin) < 0 || (S - p).dot(tout) < 0) continue;  // must lie ahead of E and behind S
    const double d = (p - V).norm();
    if (d <= best) best = d, X = p, found = true;
  }
  if (!found) return false;
  Segment e1 = extension(in, E, X), e2 = extension(out, X, S);
  for (const Segment* e : {&e1, &e2})
    if (e->is_arc() && std::abs(e->sweep) > std::numbers::pi / 2) return false;
  e1.g0 = e1.g1 = e2.g0 = e2.g1 = g;
  if ((X - E).norm() > 0) join.push_back(e1);
  if ((S - X).norm() > 0) join.push_back(e2);
  return true;
}

// The neighbour's support at the join end point P: its own circle when it is an exact offset arc (the
// paper's R -/+ D), else the line through P perpendicular to P - V (the tangent of the join circle, along
// which the distance to V only grows). ends_at_p: the support ends at P (incoming neighbour), else it
// starts there (outgoing neighbour).
Segment support_at(const Segment& s, const Vector2d& P, const Vector2d& V, const Vector2d& travel, bool ends_at_p) {
  if (s.is_arc() && s.kind == SegmentKind::Element) return s;
  Vector2d d(-(P - V).y(), (P - V).x());
  if (d.dot(travel) < 0) d = -d;
  Segment l = ends_at_p ? make_line(P - d, P) : make_line(P, P + d);
  l.kind = s.kind;
  l.line = s.line;
  return l;
}
// Whether a round join is complete: from the incoming element's offset point at its vertex to the outgoing
// one's (a join cut by loop removal is not). Its ends' directions from the vertex are the elements'
// normals there. Under a gap law the neighbours' offsets are not parallel to the elements, so the old
// test, the join tangent to both neighbours, had kept every join beside a varying gap round (black-box
// testing).
bool complete_join(const std::vector<Piece>& pieces, const Segment& arc) {
  const Vector2d V = arc.c;
  const double tol = 1e-9 * std::max(1.0, V.norm() + arc.r);
  bool at_start = false, at_end = false;
  for (const Piece& p : pieces) {
    if ((p.seg.b - V).norm() <= tol) {
      const Vector2d n = left_normal_at(p.seg, 1.0);
      at_start = at_start || (arc.a - (V + arc.r * n)).norm() <= 1e-6 * arc.r || (arc.a - (V - arc.r * n)).norm() <= 1e-6 * arc.r;
    }
    if ((p.seg.a - V).norm() <= tol) {
      const Vector2d n = left_normal_at(p.seg, 0.0);
      at_end = at_end || (arc.b - (V + arc.r * n)).norm() <= 1e-6 * arc.r || (arc.b - (V - arc.r * n)).norm() <= 1e-6 * arc.r;
    }
  }
  return at_start && at_end;
}
}  // namespace

void apply_sharp_corners(std::vector<std::vector<Segment>>& contours, const ClearanceField& field,
                         double miter_limit, double eps) {
  std::vector<Eigen::AlignedBox2d> boxes;
  std::vector<std::pair<int, int>> ids;
  for (size_t c = 0; c < contours.size(); ++c)
    for (size_t k = 0; k < contours[c].size(); ++k) {
      boxes.push_back(bounding_box(contours[c][k]));
      ids.emplace_back(static_cast<int>(c), static_cast<int>(k));
    }
  const detail::BoxTree tree(boxes);
  std::vector<Segment> placed;  // miters accepted so far (they are not in the tree)
  for (size_t c = 0; c < contours.size(); ++c) {
    const auto& chain = contours[c];
    const size_t n = chain.size();
    std::vector<Segment> out;
    for (size_t k = 0; k < n; ++k) {
      const Segment& arc = chain[k];
      const Segment& prev = chain[(k + n - 1) % n];
      const Segment& next = chain[(k + 1) % n];
      bool done = false;
      if (arc.kind == SegmentKind::RoundJoin && n >= 3) {
        const Vector2d V = arc.c, E = arc.a, S = arc.b;
        const Vector2d tin = tangent_at(prev, 1.0), tout = tangent_at(next, 0.0);
        const bool complete = complete_join(field_pieces(field), arc);
        std::vector<Segment> miter;
        if (complete && sharp_join(support_at(prev, E, V, tin, true), support_at(next, S, V, tout, false), V, arc.r, miter_limit,
                                   miter)) {
          bool ok = true;
          for (auto& m : miter) {
            m.g0 = arc.g0, m.g1 = arc.g1;
            for (int t = 1; t < 16 && ok; ++t) ok = clearance(field, point_at(m, t / 16.0)) >= -eps;
            if (!ok) break;
            // The miter must not cross the path anywhere but at its own ends.
            auto b = bounding_box(m);
            tree.query(b, [&](int id) {
              if (!ok) return;
              const auto [cc, kk] = ids[id];
              if (cc == static_cast<int>(c) && (kk == static_cast<int>(k))) return;
              for (const auto& x : intersect(m, contours[cc][kk], 1e-9)) {
                if ((x.p - E).norm() < 1e-9 || (x.p - S).norm() < 1e-9) continue;
                ok = false;
              }
            });
          }
          // ... nor another miter already placed.
          for (const auto& m : miter)
            for (const auto& a : placed)
              if (ok && bounding_box(m).intersects(bounding_box(a)))
                for (const auto& x : intersect(m, a, 1e-9))
                  if ((x.p - E).norm() >= 1e-9 && (x.p - S).norm() >= 1e-9) ok = false;
          if (ok) {
            for (auto& m : miter) out.push_back(m), placed.push_back(m);
            done = true;
          }
        }
      }
      if (!done) out.push_back(arc);
    }
    for (size_t k = 0; k < out.size(); ++k) out[(k + 1) % out.size()].a = out[k].b;
    contours[c] = std::move(out);
  }
}

}  // namespace tf::offset
