// Stair steps and end caps of the section tiling, on an exact constrained Delaunay triangulation (CGAL), so
// that the horizontal faces meet the walls edge to edge (watertight) and never overlap them.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <cmath>
#include <map>
#include <queue>
#include <unordered_map>

#include "sections_mesh.hpp"

namespace tf::grind::detail {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<int, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_intersections_tag>;
using CDTP = CGAL::Constrained_triangulation_plus_2<CDT>;
using VH = CDTP::Vertex_handle;

constexpr int kInLower = 1, kInUpper = 2, kVisited = 4;

// The triangulation of all contour edges of both sides, and for each contour edge its constraint.
struct Arrangement {
  CDTP cdt;
  std::vector<std::vector<CDTP::Constraint_id>> edges[2];  // [side][contour][edge]
  std::map<const void*, int> side_of;                     // constraint -> side bit (kInLower/kInUpper)
};

void insert_side(Arrangement& ar, const std::vector<PlacedContour>& contours, int side) {
  const int bit = side == 0 ? kInLower : kInUpper;
  for (const PlacedContour& pc : contours) {
    const auto& pts = pc.contour->points;
    std::vector<CDTP::Constraint_id> ids;
    for (size_t i = 0; i < pts.size(); ++i) {
      const auto& a = pts[i];
      const auto& b = pts[(i + 1) % pts.size()];
      if (a == b) {
        ids.emplace_back();
        continue;
      }
      const CDTP::Constraint_id cid = ar.cdt.insert_constraint(K::Point_2(a.x(), a.y()), K::Point_2(b.x(), b.y()));
      ar.side_of[cid.vl_ptr()] = bit;
      ids.push_back(cid);
    }
    ar.edges[side].push_back(std::move(ids));
  }
}

// Parity of being inside each side's region, by a walk over the faces that toggles a side's bit whenever it
// crosses one of that side's constraints (overlapping constraints of both sides toggle both).
void classify(Arrangement& ar) {
  CDTP& cdt = ar.cdt;
  // No contours (a section ground away whole) or only collinear points: no face, nothing inside.
  if (cdt.dimension() < 2) return;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = 0;
  std::queue<CDTP::Face_handle> queue;
  cdt.infinite_face()->info() = kVisited;
  queue.push(cdt.infinite_face());
  while (!queue.empty()) {
    const CDTP::Face_handle f = queue.front();
    queue.pop();
    for (int i = 0; i < 3; ++i) {
      const CDTP::Face_handle g = f->neighbor(i);
      if (g->info() & kVisited) continue;
      int state = f->info() & (kInLower | kInUpper);
      if (cdt.is_constrained(CDTP::Edge(f, i))) {
        const VH va = f->vertex(CDTP::cw(i)), vb = f->vertex(CDTP::ccw(i));
        for (auto ctx : cdt.contexts(va, vb)) state ^= ar.side_of[ctx.id().vl_ptr()];
      }
      g->info() = state | kVisited;
      queue.push(g);
    }
  }
}

// The chain of triangulation vertices along a contour edge's constraint, from the edge's start to its end.
std::vector<VH> chain(const CDTP& cdt, CDTP::Constraint_id cid, const Eigen::Vector2d& start) {
  std::vector<VH> out(cdt.vertices_in_constraint_begin(cid), cdt.vertices_in_constraint_end(cid));
  if (!out.empty() && out.front()->point() != K::Point_2(start.x(), start.y())) std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace

void stair_step(const std::vector<PlacedContour>& lower, const std::vector<PlacedContour>& upper, double z_mid,
                SlabMesh& out) {
  Arrangement ar;
  insert_side(ar, lower, 0);
  insert_side(ar, upper, 1);
  classify(ar);
  std::unordered_map<const void*, int> mid;  // triangulation vertex -> new vertex at z_mid
  auto mid_id = [&](VH v) {
    auto [it, fresh] = mid.try_emplace(&*v, 0);
    if (fresh) it->second = out.add({CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()), z_mid});
    return it->second;
  };
  for (auto f = ar.cdt.finite_faces_begin(); f != ar.cdt.finite_faces_end(); ++f) {
    const int s = f->info() & (kInLower | kInUpper);
    if (s == kInLower) out.F.push_back({mid_id(f->vertex(0)), mid_id(f->vertex(1)), mid_id(f->vertex(2))});
    if (s == kInUpper) out.F.push_back({mid_id(f->vertex(0)), mid_id(f->vertex(2)), mid_id(f->vertex(1))});
  }
  for (int side = 0; side < 2; ++side) {
    const auto& contours = side == 0 ? lower : upper;
    for (size_t c = 0; c < contours.size(); ++c) {
      const auto& pts = contours[c].contour->points;
      const auto& ids = *contours[c].ids;
      for (size_t i = 0; i < pts.size(); ++i) {
        const CDTP::Constraint_id cid = ar.edges[side][c][i];
        if (cid.vl_ptr() == nullptr) continue;
        const std::vector<VH> ch = chain(ar.cdt, cid, pts[i]);
        std::vector<int> m;
        for (VH v : ch) m.push_back(mid_id(v));
        const int a = ids[i], b = ids[(i + 1) % pts.size()], s = static_cast<int>(m.size()) - 1;
        if (side == 0) {  // wall from the lower contour up to the chain at z_mid
          for (int j = 0; j < s; ++j) out.F.push_back({a, m[j + 1], m[j]});
          out.F.push_back({a, b, m[s]});
        } else {  // wall from the chain at z_mid up to the upper contour
          for (int j = 0; j < s; ++j) out.F.push_back({m[j], m[j + 1], a});
          out.F.push_back({m[s], b, a});
        }
      }
    }
  }
}

namespace {

// A contour vertex at a triangulation vertex: its id and the directions of its next and previous
// neighbours. The material lies left of every contour edge, so the vertex's corner of material is the
// turn counter-clockwise from the next neighbour's direction to the previous one's.
struct Corner {
  int id = 0;
  double to_next = 0, to_prev = 0;  // rad
  bool holds(double dir) const {
    const double span = std::remainder(to_prev - to_next, 2 * M_PI), at = std::remainder(dir - to_next, 2 * M_PI);
    return (at >= 0 ? at : at + 2 * M_PI) <= (span > 0 ? span : span + 2 * M_PI);
  }
};

}  // namespace

void end_cap(const std::vector<PlacedContour>& contours, bool up, SlabMesh& out) {
  Arrangement ar;
  insert_side(ar, contours, 0);
  if (ar.cdt.dimension() < 2) return;  // nothing left at this end: no cap
  classify(ar);
  // Contours that touch at a point share its triangulation vertex: each face there takes the id of the
  // contour vertex whose corner of material holds it (one id for all had left one contour's walls without
  // their cap, black-box testing).
  std::unordered_map<const void*, std::vector<Corner>> corners;
  for (size_t c = 0; c < contours.size(); ++c) {
    const auto& pts = contours[c].contour->points;
    const size_t n = pts.size();
    for (size_t i = 0; i < n; ++i) {
      const CDTP::Constraint_id cid = ar.edges[0][c][i];
      if (cid.vl_ptr() == nullptr) continue;
      const std::vector<VH> ch = chain(ar.cdt, cid, pts[i]);
      const Eigen::Vector2d to_next = pts[(i + 1) % n] - pts[i], to_prev = pts[(i + n - 1) % n] - pts[i];
      corners[&*ch.front()].push_back({(*contours[c].ids)[i], std::atan2(to_next.y(), to_next.x()),
                                       std::atan2(to_prev.y(), to_prev.x())});
    }
  }
  const double z = contours.empty() ? 0.0 : contours.front().z;
  std::unordered_map<const void*, int> fresh_ids;
  auto vid = [&](CDTP::Face_handle f, int k) {
    const VH v = f->vertex(k);
    const auto c = corners.find(&*v);
    if (c != corners.end()) {
      if (c->second.size() == 1) return c->second.front().id;
      Eigen::Vector2d centre = Eigen::Vector2d::Zero(), at(CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()));
      for (int j = 0; j < 3; ++j)
        centre += Eigen::Vector2d(CGAL::to_double(f->vertex(j)->point().x()), CGAL::to_double(f->vertex(j)->point().y())) / 3.0;
      const double dir = std::atan2(centre.y() - at.y(), centre.x() - at.x());
      for (const Corner& corner : c->second)
        if (corner.holds(dir)) return corner.id;
      return c->second.front().id;
    }
    auto [it, fresh] = fresh_ids.try_emplace(&*v, 0);
    if (fresh) it->second = out.add({CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()), z});
    return it->second;
  };
  for (auto f = ar.cdt.finite_faces_begin(); f != ar.cdt.finite_faces_end(); ++f) {
    if ((f->info() & kInLower) == 0) continue;
    if (up) out.F.push_back({vid(f, 0), vid(f, 1), vid(f, 2)});
    else out.F.push_back({vid(f, 0), vid(f, 2), vid(f, 1)});
  }
}

}  // namespace tf::grind::detail
