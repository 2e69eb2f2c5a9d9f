// Cleaning a section's contours without letting them cross (see section_contours.hpp).
#include "section_contours.hpp"

#include <algorithm>
#include <cmath>

namespace tf::grind::detail {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;

bool edges_cross(const Paths& paths) {
  struct Edge {
    IntPoint a, b;
    cInt x0, x1;
  };
  std::vector<Edge> edges;
  for (const Path& p : paths)
    for (size_t i = 0; i < p.size(); ++i) {
      const IntPoint &a = p[i], &b = p[(i + 1) % p.size()];
      if (a == b) continue;
      edges.push_back({a, b, std::min(a.X, b.X), std::max(a.X, b.X)});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& l, const Edge& r) { return l.x0 < r.x0; });
  auto orient = [](const IntPoint& a, const IntPoint& b, const IntPoint& c) {
    // Exact in 128-bit integers: a product of two coordinate differences (below 2^62 nm) cannot overflow.
    __extension__ typedef __int128 Wide;
    const Wide v = static_cast<Wide>(b.X - a.X) * (c.Y - a.Y) - static_cast<Wide>(b.Y - a.Y) * (c.X - a.X);
    return v > 0 ? 1 : v < 0 ? -1 : 0;
  };
  auto between = [](const IntPoint& a, const IntPoint& b, const IntPoint& q) {  // q on the open segment, collinear
    return std::min(a.X, b.X) <= q.X && q.X <= std::max(a.X, b.X) && std::min(a.Y, b.Y) <= q.Y &&
           q.Y <= std::max(a.Y, b.Y) && !(q == a) && !(q == b);
  };
  for (size_t i = 0; i < edges.size(); ++i)
    for (size_t j = i + 1; j < edges.size() && edges[j].x0 <= edges[i].x1; ++j) {
      const Edge &e = edges[i], &f = edges[j];
      if (std::max(e.a.Y, e.b.Y) < std::min(f.a.Y, f.b.Y) || std::max(f.a.Y, f.b.Y) < std::min(e.a.Y, e.b.Y)) continue;
      const int o1 = orient(e.a, e.b, f.a), o2 = orient(e.a, e.b, f.b), o3 = orient(f.a, f.b, e.a),
                o4 = orient(f.a, f.b, e.b);
      if (o1 * o2 < 0 && o3 * o4 < 0) return true;
      if (o1 == 0 && o2 == 0) {  // collinear: overlapping along a length?
        const int inside = between(e.a, e.b, f.a) + between(e.a, e.b, f.b) + between(f.a, f.b, e.a) +
                           between(f.a, f.b, e.b);
        if (inside >= 2 || (inside == 1 && (e.a == f.a || e.a == f.b || e.b == f.a || e.b == f.b))) return true;
        if ((e.a == f.a && e.b == f.b) || (e.a == f.b && e.b == f.a)) return true;
      }
    }
  return false;
}

namespace {
// Distance (nm) from q to the segment a-b.
double segment_distance(const IntPoint& q, const IntPoint& a, const IntPoint& b) {
  const double ux = double(b.X - a.X), uy = double(b.Y - a.Y), qx = double(q.X - a.X), qy = double(q.Y - a.Y);
  const double len2 = ux * ux + uy * uy;
  const double f = len2 > 0.0 ? std::clamp((qx * ux + qy * uy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(qx - f * ux, qy - f * uy);
}

// Without needles: a vertex where the contour turns back on itself, within `clean` of the line through
// its neighbours. It bounds no area (Clipper's unions leave such spikes where hulls touch), and the tiling
// between sections cannot follow it.
Path without_needles(Path p, double clean) {
  bool dropped = true;
  while (dropped && p.size() >= 3) {
    dropped = false;
    Path out;
    out.reserve(p.size());
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
      const IntPoint& a = out.empty() ? p[n - 1] : out.back();
      const IntPoint &b = p[i], &c = p[(i + 1) % n];
      const double ux = double(c.X - a.X), uy = double(c.Y - a.Y), len = std::hypot(ux, uy);
      const double bx = double(b.X - a.X), by = double(b.Y - a.Y);
      const bool back = bx * double(c.X - b.X) + by * double(c.Y - b.Y) < 0.0;
      const double off = len > 0.0 ? std::abs(ux * by - uy * bx) / len : std::hypot(bx, by);
      if (back && off <= clean) {
        dropped = true;
        continue;
      }
      out.push_back(b);
    }
    p = std::move(out);
  }
  return p;
}
}  // namespace

Path clean_contour(const Path& in, double clean) {
  // Without points within `clean` of the one kept before (and of the first, at the end).
  Path p;
  p.reserve(in.size());
  for (const IntPoint& q : in)
    if (p.empty() || std::hypot(double(q.X - p.back().X), double(q.Y - p.back().Y)) > clean) p.push_back(q);
  while (p.size() > 1 && std::hypot(double(p.back().X - p.front().X), double(p.back().Y - p.front().Y)) <= clean)
    p.pop_back();
  const size_t n = p.size();
  if (n < 4) return p;
  // Start at the lowest-leftmost vertex, a corner of the hull that stays.
  const size_t first = static_cast<size_t>(std::min_element(p.begin(), p.end(), [](const IntPoint& a, const IntPoint& b) {
                                             return a.X < b.X || (a.X == b.X && a.Y < b.Y);
                                           }) - p.begin());
  auto at = [&](size_t k) -> const IntPoint& { return p[(first + k) % n]; };
  // From each kept vertex the edge runs as far as every vertex it skips stays within `clean` of it (a run
  // is capped so that a long straight stretch costs no more than linear time times the cap).
  constexpr size_t kMaxRun = 64;
  Path out{at(0)};
  size_t anchor = 0;
  while (anchor < n) {
    size_t end = anchor + 1;
    while (end < n && end - anchor < kMaxRun) {
      const size_t next = end + 1;  // n: back to the first vertex
      bool within = true;
      for (size_t k = anchor + 1; k < next && within; ++k) within = segment_distance(at(k), at(anchor), at(next)) <= clean;
      if (!within) break;
      end = next;
    }
    if (end >= n) break;
    out.push_back(at(end));
    anchor = end;
  }
  return without_needles(std::move(out), clean);
}

void clean_contours(Paths& paths, double clean) {
  for (Path& p : paths) p = clean_contour(p, clean);
}

Paths tidy_contours(Paths paths, double clean) {
  // A contour narrower than `clean` on average (twice its area over its perimeter) goes too: a sliver of
  // air or material 0.4 um wide that one section holds and its neighbours do not had the tiling stair-step
  // the whole slab on both sides of it (the end mill at --step 0.15, 39 slabs).
  auto without_slivers = [clean](Paths out) {
    out.erase(std::remove_if(out.begin(), out.end(),
                             [clean](const Path& p) {
                               if (p.size() < 3) return true;
                               double perimeter = 0.0;
                               for (size_t i = 0; i < p.size(); ++i) {
                                 const IntPoint &a = p[i], &b = p[(i + 1) % p.size()];
                                 perimeter += std::hypot(double(b.X - a.X), double(b.Y - a.Y));
                               }
                               return 2.0 * std::abs(ClipperLib::Area(p)) < clean * perimeter;
                             }),
              out.end());
    return out;
  };
  auto cleaned = [&](const Paths& in) {
    Paths out = in;
    clean_contours(out, clean);
    return without_slivers(std::move(out));
  };
  if (Paths c = cleaned(paths); !edges_cross(c)) return c;
  Paths united;
  ClipperLib::SimplifyPolygons(paths, united, ClipperLib::pftNonZero);
  if (Paths c = cleaned(united); !edges_cross(c)) return c;
  return without_slivers(std::move(united));
}

}  // namespace tf::grind::detail
