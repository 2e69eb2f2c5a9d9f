// Loop removal: the raw offset is cut at all its self-intersections into slices; a slice whose points come
// closer to the profile than the gap (an invalid local or global loop, or an arc that vanished) is dropped;
// the remaining slices are stitched into closed contours. A narrow neck thus splits the result.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>
#include <numeric>
#include <optional>

#include "segment_bvh.hpp"
#include "offset_internal.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;

struct Event {
  int seg;
  double t;
  int node;
};

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Merges intersection nodes closer than tol (tangencies and crossings through a joint give several).
std::vector<int> cluster_nodes(const std::vector<Vector2d>& pts, double tol) {
  std::vector<int> parent(pts.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> order(pts.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return pts[a].x() < pts[b].x(); });
  for (size_t i = 0; i < order.size(); ++i)
    for (size_t j = i + 1; j < order.size() && pts[order[j]].x() - pts[order[i]].x() <= tol; ++j)
      if ((pts[order[i]] - pts[order[j]]).norm() <= tol)
        parent[find_root(parent, order[i])] = find_root(parent, order[j]);
  std::vector<int> root(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) root[i] = find_root(parent, static_cast<int>(i));
  return root;
}

struct Slice {
  std::vector<Segment> segs;
  int from = -1, to = -1;  // node ids (cluster roots), -1 for the whole raw curve
  int first_seg = -1, last_seg = -1;  // raw segments it starts and ends on
};

void append_piece(Slice& sl, const Segment& s, double t0, double t1, double tol) {
  if (t1 <= t0) return;
  Segment p = (t0 <= 0 && t1 >= 1) ? s : sub_segment(s, t0, t1);
  if (length(p) <= tol) return;
  if (!sl.segs.empty()) p.a = sl.segs.back().b;
  sl.segs.push_back(p);
}

// Slice validity from the midpoints of up to 9 of its pieces spread along it (quarter points too for a
// slice of one or two pieces): a slice lies wholly inside or wholly outside the region closer than the
// gap, up to its ends, so a few samples decide it.
bool slice_valid(const Slice& sl, const ClearanceField& field, double eps) {
  const size_t n = sl.segs.size();
  const size_t samples = std::min<size_t>(n, 9);
  for (size_t k = 0; k < samples; ++k) {
    const Segment& s = sl.segs[(2 * k + 1) * n / (2 * samples)];
    for (double t : {0.25, 0.5, 0.75}) {
      if (t != 0.5 && n > 2) continue;
      if (closer_than_gap(field, point_at(s, t), eps)) return false;
    }
  }
  return true;
}

// A point of an invalid slice that lies clearly farther than the gap (more than `margin`), if any.
std::optional<Vector2d> farther_point(const Slice& sl, const ClearanceField& field, double margin) {
  for (const Segment& s : sl.segs)
    for (double t : {0.25, 0.5, 0.75})
      if (const Vector2d q = point_at(s, t); clearance(field, q) > margin) return q;
  return std::nullopt;
}

// Crossing number of the ray from q toward +x with a chain polygonised finely (only used to tell
// nesting, where contours are apart by much more than the chord error).
bool inside_chain(const std::vector<Segment>& chain, const Vector2d& q) {
  bool in = false;
  auto edge = [&](const Vector2d& a, const Vector2d& b) {
    if ((a.y() > q.y()) != (b.y() > q.y())) {
      const double x = a.x() + (q.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      if (x > q.x()) in = !in;
    }
  };
  for (const auto& s : chain) {
    const int n = s.is_arc() ? std::max(2, static_cast<int>(std::ceil(std::abs(s.sweep) / 0.01))) : 1;
    Vector2d prev = s.a;
    for (int k = 1; k <= n; ++k) {
      const Vector2d p = point_at(s, static_cast<double>(k) / n);
      edge(prev, p);
      prev = p;
    }
  }
  return in;
}

// A contour inside another of the same orientation bounds a doubly covered region (overlapping sharp
// spikes); it is no boundary of the offset region.
void drop_nested_same_orientation(std::vector<std::vector<Segment>>& contours) {
  if (contours.size() < 2) return;
  std::vector<double> area(contours.size());
  std::vector<Eigen::AlignedBox2d> box(contours.size());
  for (size_t k = 0; k < contours.size(); ++k) {
    area[k] = signed_area(contours[k]);
    box[k].setEmpty();
    for (const auto& s : contours[k]) box[k].extend(bounding_box(s));
  }
  std::vector<char> drop(contours.size(), 0);
  for (size_t k = 0; k < contours.size(); ++k)
    for (size_t j = 0; j < contours.size(); ++j) {
      if (j == k || (area[j] > 0) != (area[k] > 0) || std::abs(area[j]) <= std::abs(area[k])) continue;
      if (!box[j].contains(box[k])) continue;
      if (inside_chain(contours[j], point_at(contours[k][0], 0.5))) {
        drop[k] = 1;
        break;
      }
    }
  std::vector<std::vector<Segment>> kept;
  for (size_t k = 0; k < contours.size(); ++k)
    if (!drop[k]) kept.push_back(std::move(contours[k]));
  contours = std::move(kept);
}

// All self-intersections of the raw offset, except the shared joint of neighbours: the nodes, and for
// each node one event on either segment.
void self_intersections(const std::vector<Segment>& raw, double tol, std::vector<Event>& events,
                        std::vector<Vector2d>& nodes) {
  const int m = static_cast<int>(raw.size());
  const double vertex_tol = 1e3 * tol;
  std::vector<Eigen::AlignedBox2d> boxes;
  boxes.reserve(m);
  for (const auto& s : raw) {
    auto b = bounding_box(s);
    boxes.emplace_back(b.min().array() - tol, b.max().array() + tol);
  }
  detail::BoxTree tree(boxes);
  for (int i = 0; i < m; ++i) {
    tree.query(boxes[i], [&](int j) {
      if (j <= i) return;
      const bool next = j == i + 1, wrap = i == 0 && j == m - 1;
      for (const auto& c : intersect(raw[i], raw[j], tol)) {
        if (next && (c.p - raw[i].b).norm() <= vertex_tol && c.t1 > 0.5 && c.t2 < 0.5) continue;
        if (wrap && (c.p - raw[i].a).norm() <= vertex_tol && c.t1 < 0.5 && c.t2 > 0.5) continue;
        const int id = static_cast<int>(nodes.size());
        nodes.push_back(c.p);
        events.push_back({i, c.t1, id});
        events.push_back({j, c.t2, id});
      }
    });
  }
}

// The raw curve from event cur to the next event nxt along it (cur the k-th of K sorted events).
Slice slice_between(const std::vector<Segment>& raw, const Event& cur, const Event& nxt, size_t k, size_t K,
                    double tol) {
  const int m = static_cast<int>(raw.size());
  Slice sl;
  sl.from = cur.node;
  sl.first_seg = cur.seg;
  sl.last_seg = nxt.seg;
  sl.to = nxt.node;
  if (k + 1 < K && nxt.seg == cur.seg) {
    append_piece(sl, raw[cur.seg], cur.t, nxt.t, tol);
  } else {
    append_piece(sl, raw[cur.seg], cur.t, 1.0, tol);
    for (int s = (cur.seg + 1) % m; s != nxt.seg; s = (s + 1) % m) append_piece(sl, raw[s], 0.0, 1.0, tol);
    if (K == 1 || nxt.seg != cur.seg || k + 1 == K) append_piece(sl, raw[nxt.seg], 0.0, nxt.t, tol);
  }
  return sl;
}

// The raw curve cut at its (clustered) crossing nodes into slices from node to node; the whole curve when
// it does not cross itself.
std::vector<Slice> cut_into_slices(const std::vector<Segment>& raw, std::vector<Event> events,
                                   const std::vector<Vector2d>& nodes, double tol) {
  std::vector<Slice> slices;
  if (events.empty()) {
    Slice sl;
    sl.segs = raw;
    slices.push_back(sl);
    return slices;
  }
  const auto root = cluster_nodes(nodes, 10 * tol);
  for (auto& e : events) e.node = root[e.node];
  std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    return a.seg != b.seg ? a.seg < b.seg : a.t < b.t;
  });
  const size_t K = events.size();
  for (size_t k = 0; k < K; ++k) {
    Slice sl = slice_between(raw, events[k], events[(k + 1) % K], k, K, tol);
    if (sl.from == sl.to && chain_length(sl.segs) <= 100 * tol) continue;  // between two merged nodes
    if (sl.segs.empty()) continue;
    sl.segs.front().a = nodes[sl.from];
    sl.segs.back().b = nodes[sl.to];
    slices.push_back(std::move(sl));
  }
  return slices;
}

// Follows unused slices, end node to start node, from slice k into `chain`; true when it closes on k's
// start node, and then the slices it took are marked used. Where two valid pieces cross (sharp-join spikes)
// it turns onto the other curve first: going straight would make the contour cross itself. Where that
// choice leads to a node with no way on, the other ways are tried (a depth-first search with a budget):
// under a gap law a sliver of three valid slices at a peak of the law had taken the turn into itself and
// left the contour open, so the offset was reported empty (black-box testing).
bool follow_chain(const std::vector<Slice>& slices, const std::multimap<int, int>& by_start, size_t k,
                  std::vector<char>& used, std::vector<Segment>& chain) {
  const int start = slices[k].from;
  // The ways on from slice `cur`'s end: the turns first, then the others, unused only.
  auto ways_on = [&](int cur) {
    std::vector<int> turns, straight;
    for (auto [it, last] = by_start.equal_range(slices[cur].to); it != last; ++it)
      if (!used[it->second]) (slices[it->second].first_seg != slices[cur].last_seg ? turns : straight).push_back(it->second);
    turns.insert(turns.end(), straight.begin(), straight.end());
    return turns;
  };
  std::vector<int> path{static_cast<int>(k)};
  std::vector<std::pair<std::vector<int>, size_t>> ways;  // per slice of the path: its ways on, the next to try
  used[k] = 1;
  bool closed = slices[k].to == start;
  if (!closed) ways.emplace_back(ways_on(static_cast<int>(k)), 0);
  for (size_t budget = 64 * slices.size() + 256; !closed && !ways.empty() && budget > 0; --budget) {
    auto& [options, next] = ways.back();
    if (next == options.size()) {  // a dead end: step back
      used[path.back()] = 0;
      path.pop_back();
      ways.pop_back();
      continue;
    }
    const int s = options[next++];
    if (used[s]) continue;  // taken deeper in the path since the options were listed
    used[s] = 1;
    path.push_back(s);
    if (slices[s].to == start) {
      closed = true;
    } else {
      ways.emplace_back(ways_on(s), 0);
    }
  }
  if (!closed) {
    for (int s : path) used[s] = 0;
    used[k] = 1;  // no contour starts here
    return false;
  }
  for (int s : path)
    for (const auto& seg : slices[s].segs) chain.push_back(seg);
  return true;
}

// Whether b runs straight back over a from a's end: the same line or circle, the other way. Where the
// region narrows to zero width (a neck exactly twice the gap wide) the offsets of the two sides coincide
// and both are valid, so the contour went out along the neck and back (found by black-box testing).
bool retraces(const Segment& a, const Segment& b, double tol) {
  if (a.is_arc() != b.is_arc() || (b.a - a.b).norm() > tol) return false;
  if (a.is_arc()) return (a.c - b.c).norm() <= tol && std::abs(a.r - b.r) <= tol && a.sweep * b.sweep < 0;
  const Vector2d da = a.b - a.a, db = b.b - b.a;
  if (da.dot(db) >= 0) return false;
  const double cross = da.x() * db.y() - da.y() * db.x();
  return std::abs(cross) <= tol * std::min(da.norm(), db.norm());  // both ends within tol of the other's line
}

// The contour without its zero-width spikes: a piece followed by its own retrace cancels (the longer of
// the two keeps what the shorter does not cover), as often as that happens, across the contour's start too.
std::vector<Segment> without_spikes(const std::vector<Segment>& chain, double tol) {
  std::vector<Segment> out;
  auto push = [&](Segment s) {
    while (!out.empty() && retraces(out.back(), s, tol)) {
      const double la = length(out.back()), lb = length(s);
      if (std::abs(la - lb) <= tol) {
        out.pop_back();
        return;
      }
      if (lb < la) {
        const Vector2d end = s.b;
        out.back() = sub_segment(out.back(), 0.0, 1.0 - lb / la);
        out.back().b = end;
        return;
      }
      const Vector2d start = out.back().a;
      out.pop_back();
      s = sub_segment(s, la / lb, 1.0);
      s.a = start;
    }
    out.push_back(s);
  };
  for (const Segment& s : chain) push(s);
  // A spike across the start: its first half ends the list, its second half begins it.
  size_t front = 0;
  while (front < out.size() && out.size() - front >= 2 && retraces(out.back(), out[front], tol)) {
    const Segment first = out[front++];
    std::vector<Segment> rest(out.begin() + long(front), out.end());
    out.swap(rest);
    front = 0;
    push(first);
  }
  return out;
}

// Whether b is a, the other way round (the same line or arc between the same points).
bool reversed_of(const Segment& a, const Segment& b, double tol) {
  if (a.is_arc() != b.is_arc() || (a.a - b.b).norm() > tol || (a.b - b.a).norm() > tol) return false;
  return !a.is_arc() || ((a.c - b.c).norm() <= tol && std::abs(a.r - b.r) <= tol && a.sweep * b.sweep < 0);
}

// A contour that runs along a zero-width bridge and later back along it (a neck exactly twice the gap
// wide between two pockets of the region, each traced in between) is two loops touching through the
// bridge: split there, the bridge dropped, each loop in turn; then without_spikes. A bridge's two pieces
// run between the same crossing nodes (cut_into_slices sets their ends to the node's point), so a
// piece's reverse is found by its ends' exact values.
void split_at_bridges(std::vector<Segment> chain, double tol, std::vector<std::vector<Segment>>& out) {
  using Ends = std::array<double, 4>;
  struct EndsHash {
    size_t operator()(const Ends& e) const {
      size_t h = 0;
      for (double v : e) h = h * 1000003u ^ std::hash<double>()(v);
      return h;
    }
  };
  std::vector<std::vector<Segment>> work{std::move(chain)};
  while (!work.empty()) {
    std::vector<Segment> c = std::move(work.back());
    work.pop_back();
    const size_t n = c.size();
    std::unordered_map<Ends, size_t, EndsHash> by_ends;
    bool split = false;
    for (size_t j = 0; j < n && !split; ++j) {
      const auto it = by_ends.find(Ends{c[j].b.x(), c[j].b.y(), c[j].a.x(), c[j].a.y()});
      if (it != by_ends.end()) {
        const size_t i = it->second;
        if (j != i + 1 && !(i == 0 && j + 1 == n) && reversed_of(c[i], c[j], tol)) {
          work.emplace_back(c.begin() + long(i) + 1, c.begin() + long(j));
          std::vector<Segment> rest(c.begin() + long(j) + 1, c.end());
          rest.insert(rest.end(), c.begin(), c.begin() + long(i));
          work.push_back(std::move(rest));
          split = true;
        }
      }
      by_ends.emplace(Ends{c[j].a.x(), c[j].a.y(), c[j].b.x(), c[j].b.y()}, j);
    }
    if (!split) out.push_back(without_spikes(c, tol));
  }
}

// Stitches the valid slices end node to start node into closed contours.
// A loop narrower than eps (its area below eps times half its length) is a sliver, not a contour: the
// reversed piece of an arc whose radius the gap exceeds by less than eps closed two zero-area loops
// beside the real contour (black-box testing).
std::vector<std::vector<Segment>> stitch_slices(const std::vector<Slice>& slices, const std::vector<char>& valid,
                                                double tol, double eps) {
  std::vector<std::vector<Segment>> contours;
  std::multimap<int, int> by_start;
  for (size_t k = 0; k < slices.size(); ++k)
    if (valid[k]) by_start.emplace(slices[k].from, static_cast<int>(k));
  std::vector<char> used(slices.size(), 0);
  for (size_t k = 0; k < slices.size(); ++k) {
    if (!valid[k] || used[k]) continue;
    std::vector<Segment> chain;
    const bool closed = follow_chain(slices, by_start, k, used, chain);
    if (!closed || chain.empty()) continue;  // an open chain: pieces of a loop judged inconsistently
    std::vector<std::vector<Segment>> loops;
    split_at_bridges(chain, tol, loops);
    for (auto& loop : loops) {
      if (loop.size() < 2) continue;
      for (size_t s = 0; s < loop.size(); ++s) loop[(s + 1) % loop.size()].a = loop[s].b;
      if (std::abs(signed_area(loop)) <= std::max(tol * tol, 0.5 * eps * chain_length(loop))) continue;
      contours.push_back(std::move(loop));
    }
  }
  return contours;
}
}  // namespace

std::vector<std::vector<Segment>> remove_loops(const std::vector<Segment>& raw, const ClearanceField& field, double tol,
                                               double eps, int* crossings, int* unresolved, Eigen::Vector2d* unresolved_at) {
  if (raw.empty()) return {};
  std::vector<Event> events;
  std::vector<Vector2d> nodes;
  self_intersections(raw, tol, events, nodes);
  if (crossings) *crossings = static_cast<int>(nodes.size());
  const std::vector<Slice> slices = cut_into_slices(raw, std::move(events), nodes, tol);
  std::vector<char> valid(slices.size());
  for (size_t k = 0; k < slices.size(); ++k) {
    valid[k] = slice_valid(slices[k], field, eps);
    if (valid[k] || !unresolved) continue;
    if (const auto q = farther_point(slices[k], field, 10 * eps)) {
      if ((*unresolved)++ == 0 && unresolved_at) *unresolved_at = *q;
    }
  }
  std::vector<std::vector<Segment>> contours = stitch_slices(slices, valid, tol, eps);
  drop_nested_same_orientation(contours);
  return contours;
}

OffsetResult offset_profile(const Profile& profile, const GapLaw& law, const OffsetOptions& options) {
  OffsetResult result;
  if (profile.elements.empty()) return result;
  const double L = chain_length(profile.elements);
  // Within the closure's own snap (1e-6 mm): a law ending at s = 302.832 on a profile 302.8318531 long had
  // been refused for 4.8e-7 mm, in a message that printed both gaps as 1 (black-box testing).
  if (const double jump = gap_at(law, L) - gap_at(law, 0.0); std::abs(jump) > 1e-6) {
    char difference[32];
    std::snprintf(difference, sizeof difference, "%.3g", jump);
    throw InputError(law.file, 0, "gap",
                     "the gap at s = 0 (" + fixed(gap_at(law, 0.0), 6) + ") differs from the gap at the profile's end s = " +
                         fixed(L, 6) + " (" + fixed(gap_at(law, L), 6) + ") by " + difference +
                         " mm; a closed profile needs equal gaps there");
  }
  Eigen::AlignedBox2d box;
  box.setEmpty();
  for (const auto& e : profile.elements) box.extend(bounding_box(e));
  double gmax = 0;
  for (double g : law.gap) gmax = std::max(gmax, g);
  const double scale = std::max(1.0, box.diagonal().norm() + 2 * gmax);
  const double tol = 1e-10 * scale;
  const double sigma = (signed_area(profile.elements) > 0 ? 1.0 : -1.0) * (options.side == Side::Inside ? 1.0 : -1.0);
  const double eps = 1e-8 * scale + (is_constant(law) ? 0.0 : 5 * options.arc_tolerance);
  const auto raw = raw_offset(profile, law, options, sigma, tol);
  result.raw_segments = static_cast<int>(raw.size());
  const auto field = make_clearance_field(profile, law);
  const bool varying = !is_constant(law);
  result.contours = remove_loops(raw, *field, tol, eps, &result.crossings, varying ? &result.unresolved : nullptr,
                                 &result.unresolved_at);
  if (options.corner == Corner::Sharp) apply_sharp_corners(result.contours, *field, options.miter_limit, eps);
  if (!is_constant(law)) mark_transitions(result.contours, *field, std::max(2.5 * options.arc_tolerance, 1e-9 * scale));
  return result;
}

}  // namespace tf::offset
