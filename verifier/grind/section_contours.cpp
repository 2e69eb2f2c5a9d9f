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
    Paths out;
    ClipperLib::CleanPolygons(in, out, clean);
    return without_slivers(std::move(out));
  };
  if (Paths c = cleaned(paths); !edges_cross(c)) return c;
  Paths united;
  ClipperLib::SimplifyPolygons(paths, united, ClipperLib::pftNonZero);
  if (Paths c = cleaned(united); !edges_cross(c)) return c;
  return without_slivers(std::move(united));
}

}  // namespace tf::grind::detail
