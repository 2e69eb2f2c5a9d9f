// The raw offset of a profile: every piece offset exactly (lines to lines, arcs to arcs with R -/+ D) or,
// where the gap varies along an arc, approximated by arcs; then the joins at the vertices (Gawlik,
// Karbowski, Ruszaj, section 3.1): intersection of the neighbouring offsets where they overlap, an arc of
// radius D about the vertex where they part. Sharp corners are made afterwards from these arcs (sharp.cpp),
// once the loops are gone.
#include <algorithm>
#include <cmath>

#include "offset_internal.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;

// Circle through three points; false when they are (nearly) collinear.
bool circle_through(const Vector2d& p, const Vector2d& q, const Vector2d& r, Vector2d* c) {
  const Vector2d b = q - p, d = r - p;
  const double den = 2 * cross(b, d);
  if (std::abs(den) <= 1e-14 * b.squaredNorm() * d.norm() / std::max(b.norm(), 1e-300) + 1e-300) return false;
  const double b2 = b.squaredNorm(), d2 = d.squaredNorm();
  *c = p + Vector2d(d.y() * b2 - b.y() * d2, b.x() * d2 - d.x() * b2) / den;
  return true;
}

struct OffsetCurve {
  const Piece& piece;
  const GapLaw& law;
  double sigma;
  Vector2d at(double t) const {
    const double g = gap_at(law, piece.s0 + t * (piece.s1 - piece.s0));
    return point_at(piece.seg, t) + sigma * g * left_normal_at(piece.seg, t);
  }
};

// Arcs through q(t0), q(tm), q(t1), bisected until every probe is within tol of its arc.
void fit_arcs(const OffsetCurve& q, double t0, double t1, const Vector2d& a, const Vector2d& b, double tol, int depth,
              std::vector<Segment>& out) {
  const double tm = 0.5 * (t0 + t1);
  const Vector2d m = q.at(tm);
  Vector2d c;
  Segment s;
  bool ok = false;
  if (circle_through(a, m, b, &c) && (c - a).norm() < 1e6) {
    s = make_arc_to(a, b, c, cross(m - a, b - m) > 0);
    ok = true;
    for (int k = 1; k < 16 && ok; ++k) {
      if (k == 8) continue;
      const Vector2d p = q.at(t0 + (t1 - t0) * k / 16.0);
      ok = distance(s, p) <= tol;
    }
  } else {
    s = make_line(a, b);
    ok = true;
    for (int k = 1; k < 16 && ok; ++k) ok = distance(s, q.at(t0 + (t1 - t0) * k / 16.0)) <= tol;
  }
  if (ok || depth >= 40 || (b - a).norm() <= tol) {
    s.kind = SegmentKind::Fitted;
    s.g0 = gap_at(q.law, q.piece.s0 + t0 * (q.piece.s1 - q.piece.s0));
    s.g1 = gap_at(q.law, q.piece.s0 + t1 * (q.piece.s1 - q.piece.s0));
    s.line = q.piece.seg.line;
    out.push_back(s);
    return;
  }
  fit_arcs(q, t0, tm, a, m, tol, depth + 1, out);
  fit_arcs(q, tm, t1, m, b, tol, depth + 1, out);
}

// The offset of one piece at side sigma.
std::vector<Segment> offset_piece(const Piece& p, const GapLaw& law, double sigma, double arc_tol, double tol) {
  std::vector<Segment> out;
  const Segment& e = p.seg;
  if (!e.is_arc() && p.linear) {
    // A line with a linear gap stays a line: its points are p(s) + gap(s) n.
    const Vector2d n = left_normal_at(e, 0);
    Segment s = make_line(e.a + sigma * p.g0 * n, e.b + sigma * p.g1 * n);
    s.g0 = p.g0, s.g1 = p.g1, s.line = e.line;
    out.push_back(s);
    return out;
  }
  if (p.constant) {
    // Line-arc joins (Gawlik, Karbowski, Ruszaj: cases 1.B, 2.A): R' = R - D on the arc's concave side, R + D
    // on its convex side.
    const double r2 = e.r - sigma * (e.sweep > 0 ? 1.0 : -1.0) * p.g0;
    const Vector2d a2 = e.c + (r2 / e.r) * (e.a - e.c), b2 = e.c + (r2 / e.r) * (e.b - e.c);
    Segment s;
    if (r2 > tol) {
      s = e;
      s.a = a2, s.b = b2, s.r = r2;
    } else if (r2 < -tol) {
      s = make_line(a2, b2);  // the arc vanished (R - D < 0): this piece is always inside, cut away later
    } else {
      // R - D == 0: the offset is the centre point. It is kept as a point so that each neighbour joins it
      // about its own vertex; dropped, the neighbours were joined by one arc about the wrong vertex (an arc
      // rs274 refuses and a gouge) or not at all ("empty"), black-box testing.
      s = make_line(e.c, e.c);
    }
    s.kind = SegmentKind::Element;
    s.g0 = s.g1 = p.g0, s.line = e.line;
    out.push_back(s);
    return out;
  }
  OffsetCurve q{p, law, sigma};
  fit_arcs(q, 0.0, 1.0, q.at(0.0), q.at(1.0), arc_tol, 0, out);
  return out;
}

// `out` continued backward from its start by `reach` mm along its line or circle (a half turn at most).
Segment extended_back(const Segment& out, double reach) {
  if (!out.is_arc()) return make_line(out.a - reach * tangent_at(out, 0.0), out.a);
  const double sign = out.sweep > 0 ? 1.0 : -1.0;
  const double back = std::min({reach / out.r, 2.0 * M_PI - std::abs(out.sweep) - 1e-3, M_PI});
  Segment e = make_arc(out.c, out.r, start_angle(out) - sign * back, sign * back);
  e.b = out.a;
  return e;
}

// Whether every point of `bridge` (sampled) keeps the gap of its nearest profile point, within tol.
bool keeps_gap(const Segment& bridge, const std::vector<Piece>& pieces, const GapLaw& law, double tol) {
  for (int k = 0; k <= 32; ++k) {
    const Vector2d q = point_at(bridge, k / 32.0);
    double best = INFINITY, s = 0.0;
    for (const Piece& p : pieces) {
      double t = 0.0;
      const double d = distance(p.seg, q, &t);
      if (d < best) best = d, s = p.s0 + t * (p.s1 - p.s0);
    }
    if (best < gap_at(law, s) - tol) return false;
  }
  return true;
}

// Under a gap law an overlapping join may find no crossing of its two offsets: a law rising steeply into
// the vertex tilts the incoming offset into the outgoing one's gap without meeting it (a rise of 0.5 mm
// over the last millimetre before a 37-degree corner). The outgoing offset, continued back, then meets an
// earlier offset: the chain is cut there, what lies between is dropped, and the continuation joins the
// two (marked Transition: its nearest profile point is the earlier element's, and it lies farther from it
// than that element's gap). An arc about the vertex had closed the chain instead, a fold with no crossing
// that loop removal left in place: the contour came 0.46 mm inside the law's gap, or the offset was
// found "empty" (black-box testing). Only the incoming offset and earlier pieces of this pass are searched.
bool join_back(std::vector<std::vector<Segment>>& off, std::vector<std::vector<Segment>>& joins, size_t i, size_t j,
               double reach, const std::vector<Piece>& pieces, const GapLaw& law, double tol) {
  const Segment& out = off[j].front();
  const Segment ext = extended_back(out, reach);
  double walked = 0.0;
  const size_t stop = j < i ? j + 1 : 0;
  for (size_t k = i + 1; k-- > stop && walked <= reach;) {
    // The pieces of k in chain order are off[k] then joins[k], walked from the end: first `in` itself (off[i].back()),
    // which the continuation may meet where `out` could not.
    std::vector<std::pair<std::vector<Segment>*, size_t>> segs;
    for (size_t m = 0; m < off[k].size(); ++m) segs.emplace_back(&off[k], m);
    if (k < i)
      for (size_t m = 0; m < joins[k].size(); ++m) segs.emplace_back(&joins[k], m);
    for (size_t q = segs.size(); q-- > 0;) {
      auto& [vec, m] = segs[q];
      const Segment& seg = (*vec)[m];
      const Crossing* best = nullptr;
      const auto xs = intersect(seg, ext, tol);
      for (const auto& c : xs)
        if (c.t1 > 1e-12 && c.t2 < 1 - 1e-12 && (!best || c.t2 > best->t2)) best = &c;
      if (best) {
        Segment bridge = sub_segment(ext, best->t2, 1.0);
        bridge.a = best->p;
        bridge.b = out.a;
        // A crossing with an offset farther off (across a neck) bridges past other elements: not a join.
        if (!keeps_gap(bridge, pieces, law, 1e3 * tol)) return false;
        const Crossing c = *best;
        Segment& cut = (*vec)[m];
        cut = sub_segment(cut, 0.0, c.t1);
        cut.b = c.p;
        vec->resize(m + 1);
        if (vec == &off[k]) joins[k].clear();
        for (size_t later = k + 1; later <= i; ++later) off[later].clear(), joins[later].clear();
        bridge.kind = SegmentKind::Transition;
        bridge.g0 = bridge.g1 = out.g0;
        bridge.line = out.line;
        joins[i].push_back(bridge);
        return true;
      }
      walked += length(seg);
    }
  }
  return false;
}

// The mirror of join_back, for a law falling steeply out of the vertex: the outgoing offset tilts toward
// the profile inside the incoming one's gap, and the incoming offset, continued forward, meets it or an
// offset after it (a square's inside offset had been found "empty", a hexagon's folded 0.6 mm inside the
// gap; black-box testing). Pieces not yet joined (after j, before i when wrapped) are searched.
bool join_forward(std::vector<std::vector<Segment>>& off, std::vector<std::vector<Segment>>& joins, size_t i, size_t j,
                  double reach, const std::vector<Piece>& pieces, const GapLaw& law, double tol) {
  Segment& in = off[i].back();
  const size_t last = j > i ? off.size() - 1 : i - 1;
  // First the incoming offset itself against the pieces after the outgoing one (a fall of 0.9 mm over
  // 1 mm after a square's corner: the incoming offset meets the flat one after the fall).
  {
    double walked = 0.0;
    for (size_t k = j; k <= last && walked <= reach; ++k)
      for (size_t m = (k == j ? 1 : 0); m < off[k].size(); ++m) {
        Segment& seg = off[k][m];
        const Crossing* best = nullptr;
        const auto xs = intersect(in, seg, tol);
        for (const auto& c : xs)
          if (c.t1 > 1e-12 && c.t1 < 1 - 1e-12 && c.t2 < 1 - 1e-12 && (!best || c.t1 < best->t1)) best = &c;
        walked += length(seg);
        if (!best) continue;
        const Crossing c = *best;
        in = sub_segment(in, 0.0, c.t1);
        in.b = c.p;
        seg = sub_segment(seg, c.t2, 1.0);
        seg.a = c.p;
        off[k].erase(off[k].begin(), off[k].begin() + static_cast<long>(m));
        for (size_t before = j; before < k; ++before) off[before].clear(), joins[before].clear();
        return true;
      }
  }
  const Segment ext = reversed(extended_back(reversed(in), reach));
  double walked = 0.0;
  for (size_t k = j; k <= last && walked <= reach; ++k) {
    for (size_t m = 0; m < off[k].size(); ++m) {
      const Segment& seg = off[k][m];
      const Crossing* best = nullptr;
      const auto xs = intersect(ext, seg, tol);
      for (const auto& c : xs)
        if (c.t1 > 1e-12 && c.t2 < 1 - 1e-12 && (!best || c.t1 < best->t1)) best = &c;
      if (!best) {
        walked += length(seg);
        continue;
      }
      Segment bridge = sub_segment(ext, 0.0, best->t1);
      bridge.a = in.b;
      bridge.b = best->p;
      if (!keeps_gap(bridge, pieces, law, 1e3 * tol)) return false;
      const Crossing c = *best;
      Segment& cut = off[k][m];
      cut = sub_segment(cut, c.t2, 1.0);
      cut.a = c.p;
      off[k].erase(off[k].begin(), off[k].begin() + static_cast<long>(m));
      for (size_t before = j; before < k; ++before) off[before].clear(), joins[before].clear();
      bridge.kind = SegmentKind::Transition;
      bridge.g0 = bridge.g1 = in.g1;
      bridge.line = in.line;
      joins[i].push_back(bridge);
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<Segment> raw_offset(const Profile& profile, const GapLaw& law, const OffsetOptions& options, double sigma,
                                double tol) {
  const auto pieces = profile_pieces(profile, law);
  const size_t n = pieces.size();
  std::vector<std::vector<Segment>> off(n);
  for (size_t i = 0; i < n; ++i) off[i] = offset_piece(pieces[i], law, sigma, options.arc_tolerance, tol);
  std::vector<std::vector<Segment>> joins(n);  // joins[i]: between piece i and the next non-empty one
  const bool varying = !is_constant(law);
  double g_max = 0.0;
  for (const Piece& p : pieces) g_max = std::max({g_max, p.g0, p.g1});

  for (size_t i = 0; i < n; ++i) {
    if (off[i].empty()) continue;
    size_t j = (i + 1) % n;
    while (off[j].empty() && j != i) j = (j + 1) % n;
    Segment& in = off[i].back();
    Segment& out = off[j].front();
    const Vector2d E = in.b, S = out.a;
    if ((E - S).norm() <= tol) {
      out.a = E;  // tangent join or a gap-law break inside an element: continuous already
      continue;
    }
    const Vector2d V = pieces[i].seg.b;  // the profile vertex
    const double g = pieces[i].g1;
    const Vector2d tin = tangent_at(pieces[i].seg, 1.0), tout = tangent_at(pieces[j].seg, 0.0);
    const double turn = std::atan2(cross(tin, tout), tin.dot(tout));
    auto round_join = [&] {
      Segment arc = make_arc_to(E, S, V, turn > 0);
      arc.kind = SegmentKind::RoundJoin;
      arc.g0 = arc.g1 = g;
      arc.line = pieces[j].seg.line;
      joins[i].push_back(arc);
    };
    if (sigma * turn < 0) {  // the offsets part: convex corner seen from the offset side
      round_join();
      continue;
    }
    // The offsets overlap: cut both at their crossing nearest the vertex (no local loop). Without one
    // (a neighbour too short), an arc about the vertex closes the chain; the loop it makes is removed later.
    const bool points = length(in) <= tol || length(out) <= tol;  // a point has no crossing to cut at
    const auto xs = points ? std::vector<Crossing>{} : intersect(in, out, tol);
    const Crossing* best = nullptr;
    for (const auto& c : xs)
      if (c.t1 > 1e-12 && c.t2 < 1 - 1e-12 && (!best || c.t1 > best->t1)) best = &c;
    // Under a law the two offsets can run along one line (a peak of the law at the vertex, rising and
    // falling at the corner's slope): they overlap up to the outgoing one's end, which is the crossing.
    if (!best && varying)
      for (const auto& c : xs)
        if (c.t1 > 1e-12 && c.t1 < 1 - 1e-12 && c.t2 >= 1 - 1e-12 && (!best || c.t1 > best->t1)) best = &c;
    if (best) {
      const Crossing c = *best;
      in = sub_segment(in, 0.0, c.t1);
      out = sub_segment(out, c.t2, 1.0);
      in.b = c.p;
      out.a = c.p;
      continue;
    }
    // Searched back over the incoming offset and a few gaps before it.
    const double reach = 4.0 * g_max + length(in);
    if (varying && !points && join_back(off, joins, i, j, reach, pieces, law, tol)) continue;
    const double reach_on = 4.0 * g_max + length(out);
    if (varying && !points && join_forward(off, joins, i, j, reach_on, pieces, law, tol)) continue;
    round_join();
  }

  std::vector<Segment> chain;
  for (size_t i = 0; i < n; ++i) {
    for (const auto& s : off[i]) chain.push_back(s);
    for (const auto& s : joins[i]) chain.push_back(s);
  }
  // Drop degenerate pieces and make the chain bit-exactly continuous.
  std::vector<Segment> clean;
  for (const auto& s : chain)
    if (length(s) > tol) clean.push_back(s);
  for (size_t k = 0; k < clean.size(); ++k) clean[(k + 1) % clean.size()].a = clean[k].b;
  return clean;
}

}  // namespace tf::offset
