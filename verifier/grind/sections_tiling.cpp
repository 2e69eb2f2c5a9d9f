// Surface tiling between consecutive sections (the correspondence and branching problems of contour tiling).
//
// Branching problem: the contours of two consecutive sections are related by the overlap of their regions.
// A component (outer contour + its holes) that overlaps exactly one component of the next section, whose
// holes also pair up one to one, is tiled; every other group (splits, merges, appearing or vanishing
// contours) is closed by an exact stair step at the slab's mid-plane (sections_stairs.cpp).
// Correspondence problem: two paired contours are cut into runs of edges made by the same operation; when
// both show the same cyclic sequence of operations, run k is tiled with run k (operations correspond across sections), else
// the whole contours are tiled from their nearest vertices. Within a run, the vertex with the smaller
// normalised arc length advances (no drift between contours of different vertex counts).
// Every slab whose contours changed is checked for self-intersection (CGAL); one that intersects is rebuilt
// as a single stair step, which cannot intersect itself.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <cmath>
#include <numeric>
#include <polyclipping/clipper.hpp>

#include "sections_mesh.hpp"

namespace tf::grind {
namespace {

using detail::PlacedContour;
using detail::SlabMesh;

struct Component {
  int outer = -1;
  std::vector<int> holes;
};

// A section with its global vertex ids and its components.
struct PlacedSection {
  const Section* section;
  std::vector<std::vector<int>> ids;
  std::vector<Component> components;
};

bool inside(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

double area(const std::vector<Eigen::Vector2d>& poly) {
  double s = 0.0;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    s += poly[j].x() * poly[i].y() - poly[i].x() * poly[j].y();
  return 0.5 * s;
}

std::vector<Component> components(const Section& s) {
  std::vector<Component> out;
  std::vector<int> outer_of(s.contours.size(), -1);
  for (size_t i = 0; i < s.contours.size(); ++i)
    if (!s.contours[i].hole) out.push_back({static_cast<int>(i), {}});
  for (size_t i = 0; i < s.contours.size(); ++i) {
    if (!s.contours[i].hole) continue;
    int best = -1;
    double best_area = 1e300;
    for (size_t k = 0; k < out.size(); ++k) {
      const auto& o = s.contours[out[k].outer].points;
      const double a = area(o);
      if (a < best_area && inside(o, s.contours[i].points.front())) best = static_cast<int>(k), best_area = a;
    }
    if (best >= 0) out[best].holes.push_back(static_cast<int>(i));
  }
  return out;
}

ClipperLib::Path to_path(const Contour& c) {
  ClipperLib::Path p;
  for (const auto& q : c.points) p.push_back({std::llround(q.x() * 1e6), std::llround(q.y() * 1e6)});
  return p;
}

// Whether the regions bounded by two contours (filled, orientation ignored) overlap.
bool overlap(const Contour& a, const Contour& b) {
  Eigen::AlignedBox2d ba, bb;
  for (const auto& p : a.points) ba.extend(p);
  for (const auto& p : b.points) bb.extend(p);
  if (!ba.intersects(bb)) return false;
  ClipperLib::Clipper c;
  c.AddPath(to_path(a), ClipperLib::ptSubject, true);
  c.AddPath(to_path(b), ClipperLib::ptClip, true);
  ClipperLib::Paths r;
  c.Execute(ClipperLib::ctIntersection, r, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  double s = 0.0;
  for (const auto& p : r) s += std::abs(ClipperLib::Area(p));
  return s > 0.0;
}

// Tiles the open chains A[ia[0..]] (at the lower section) and B[ib[0..]] (upper) into triangles whose
// normals point to the material's outside (contours keep material on their left).
void tile_chains(const Contour& A, const std::vector<int>& idA, const std::vector<int>& ia, const Contour& B,
                 const std::vector<int>& idB, const std::vector<int>& ib, SlabMesh& out) {
  auto params = [](const Contour& c, const std::vector<int>& idx) {
    std::vector<double> s(idx.size(), 0.0);
    for (size_t k = 1; k < idx.size(); ++k) s[k] = s[k - 1] + (c.points[idx[k]] - c.points[idx[k - 1]]).norm();
    const double total = s.back();
    for (size_t k = 0; k < s.size(); ++k) s[k] = total > 0 ? s[k] / total : double(k) / (s.size() - 1);
    return s;
  };
  const std::vector<double> sa = params(A, ia), sb = params(B, ib);
  size_t i = 0, j = 0;
  const size_t p = ia.size() - 1, q = ib.size() - 1;
  while (i < p || j < q) {
    const bool advance_a = j == q || (i < p && sa[i + 1] <= sb[j + 1]);
    if (advance_a) {
      out.F.push_back({idA[ia[i]], idA[ia[i + 1]], idB[ib[j]]});
      ++i;
    } else {
      out.F.push_back({idA[ia[i]], idB[ib[j + 1]], idB[ib[j]]});
      ++j;
    }
  }
}

std::vector<int> run_starts(const Contour& c) {
  std::vector<int> s;
  const int n = static_cast<int>(c.labels.size());
  for (int i = 0; i < n; ++i)
    if (c.labels[i] != c.labels[(i + n - 1) % n]) s.push_back(i);
  return s;
}

std::vector<int> cyclic_range(int from, int to, int n) {  // from .. to inclusive, wrapping; full loop if equal
  std::vector<int> r{from};
  int i = from;
  do {
    i = (i + 1) % n;
    r.push_back(i);
  } while (i != to);
  return r;
}

// Tiles a band between paired contours A (lower) and B (upper). Returns whether runs were matched by label.
bool tile_band(const Contour& A, const std::vector<int>& idA, const Contour& B, const std::vector<int>& idB,
               SlabMesh& out) {
  const int na = static_cast<int>(A.points.size()), nb = static_cast<int>(B.points.size());
  const std::vector<int> ra = run_starts(A), rb = run_starts(B);
  const int runs = static_cast<int>(ra.size());
  if (runs >= 2 && ra.size() == rb.size()) {
    int best = -1;
    double best_d = 1e300;
    for (int r = 0; r < runs; ++r) {
      bool same = true;
      double d = 0.0;
      for (int t = 0; t < runs && same; ++t) {
        same = A.labels[ra[t]] == B.labels[rb[(t + r) % runs]];
        d += (A.points[ra[t]] - B.points[rb[(t + r) % runs]]).norm();
      }
      if (same && d < best_d) best = r, best_d = d;
    }
    if (best >= 0) {
      for (int t = 0; t < runs; ++t)
        tile_chains(A, idA, cyclic_range(ra[t], ra[(t + 1) % runs], na), B, idB,
                    cyclic_range(rb[(t + best) % runs], rb[(t + best + 1) % runs], nb), out);
      return true;
    }
  }
  int jb = 0;
  double best = 1e300;
  for (int j = 0; j < nb; ++j)
    if (const double d = (B.points[j] - A.points[0]).squaredNorm(); d < best) best = d, jb = j;
  tile_chains(A, idA, cyclic_range(0, 0, na), B, idB, cyclic_range(jb, jb, nb), out);
  return false;
}

bool same_contours(const Section& a, const Section& b) {
  if (a.contours.size() != b.contours.size()) return false;
  for (size_t i = 0; i < a.contours.size(); ++i)
    if (a.contours[i].points != b.contours[i].points) return false;
  return true;
}

// Whether the slab's triangles intersect each other anywhere but at shared vertices and edges.
bool self_intersects(const SlabMesh& slab, const std::vector<Eigen::Vector3d>& V) {
  using SM = CGAL::Surface_mesh<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>;
  SM sm;
  std::unordered_map<int, SM::Vertex_index> map;
  auto vid = [&](int i) {
    auto [it, fresh] = map.try_emplace(i);
    if (fresh) {
      const Eigen::Vector3d& p = i >= 0 ? V[i] : slab.V[-1 - i];
      it->second = sm.add_vertex({p.x(), p.y(), p.z()});
    }
    return it->second;
  };
  for (const auto& f : slab.F)
    if (sm.add_face(vid(f[0]), vid(f[1]), vid(f[2])) == SM::null_face()) return true;  // non-manifold
  return CGAL::Polygon_mesh_processing::does_self_intersect(sm);
}

std::vector<PlacedContour> placed(const PlacedSection& s, const std::vector<int>& contour_indices) {
  std::vector<PlacedContour> out;
  for (int c : contour_indices) out.push_back({&s.section->contours[c], &s.ids[c], s.section->z});
  return out;
}

std::vector<int> all_contours(const PlacedSection& s) {
  std::vector<int> r(s.section->contours.size());
  std::iota(r.begin(), r.end(), 0);
  return r;
}

struct SlabCounts {
  int tiled = 0, matched = 0, groups = 0;
};

// Tiles one slab by components; false when a group had to be stair-stepped is not a failure.
SlabMesh tile_slab(const PlacedSection& P, const PlacedSection& Q, SlabCounts& counts) {
  SlabMesh out;
  const double z_mid = 0.5 * (P.section->z + Q.section->z);
  const size_t np = P.components.size(), nq = Q.components.size();
  // Bipartite overlap graph of components, grouped by union-find.
  std::vector<int> parent(np + nq);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<int> degree(np + nq, 0);
  for (size_t i = 0; i < np; ++i)
    for (size_t j = 0; j < nq; ++j) {
      const bool ov = (np == 1 && nq == 1) ||
                      overlap(P.section->contours[P.components[i].outer], Q.section->contours[Q.components[j].outer]);
      if (!ov) continue;
      ++degree[i], ++degree[np + j];
      parent[find(static_cast<int>(i))] = find(static_cast<int>(np + j));
    }
  std::vector<std::vector<int>> groups(np + nq);
  for (size_t k = 0; k < np + nq; ++k) groups[find(static_cast<int>(k))].push_back(static_cast<int>(k));
  for (const auto& g : groups) {
    if (g.empty()) continue;
    std::vector<int> pc, qc;  // contour indices of the group's lower and upper sides
    std::vector<int> pcomp, qcomp;
    for (int k : g) {
      const bool lower = k < static_cast<int>(np);
      const Component& c = lower ? P.components[k] : Q.components[k - np];
      auto& dst = lower ? pc : qc;
      (lower ? pcomp : qcomp).push_back(lower ? k : k - static_cast<int>(np));
      dst.push_back(c.outer);
      dst.insert(dst.end(), c.holes.begin(), c.holes.end());
    }
    if (pcomp.size() == 1 && qcomp.size() == 1) {
      const Component &a = P.components[pcomp[0]], &b = Q.components[qcomp[0]];
      // Holes must pair one to one by overlap.
      std::vector<int> pair(a.holes.size(), -1);
      bool ok = a.holes.size() == b.holes.size();
      std::vector<int> used(b.holes.size(), 0);
      for (size_t h = 0; ok && h < a.holes.size(); ++h) {
        int hits = 0;
        for (size_t k = 0; k < b.holes.size(); ++k)
          if (overlap(P.section->contours[a.holes[h]], Q.section->contours[b.holes[k]])) ++hits, pair[h] = int(k);
        ok = hits == 1 && used[pair[h]]++ == 0;
      }
      if (ok) {
        auto band = [&](int ca, int cb) {
          ++counts.tiled;
          counts.matched += tile_band(P.section->contours[ca], P.ids[ca], Q.section->contours[cb], Q.ids[cb], out);
        };
        band(a.outer, b.outer);
        for (size_t h = 0; h < a.holes.size(); ++h) band(a.holes[h], b.holes[pair[h]]);
        continue;
      }
    }
    ++counts.groups;
    detail::stair_step(placed(P, pc), placed(Q, qc), z_mid, out);
  }
  return out;
}

// Face (v, a, b) and a face (v, b, c) share the edge v-b. Where an edge has more than two faces (two sheets
// of the surface meeting along it: a stair step whose lower and upper contours share an edge, with the
// material on opposite sides), the face that continues (v, a, b)'s sheet is the first one met turning about
// the edge from (v, a, b) into its material (behind its outward normal). Returns that turn, rad in (0, 2 pi].
double turn_into_material(const Eigen::Vector3d& v, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
  const Eigen::Vector3d e = (b - v).normalized();
  auto across = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - v;
    return Eigen::Vector3d(d - d.dot(e) * e);
  };
  const Eigen::Vector3d da = across(a), inward = -(a - v).cross(b - v), dc = across(c);
  const double t = std::atan2(dc.dot(inward.normalized()), dc.dot(da.normalized()));
  return t > 0 ? t : t + 2 * M_PI;
}

// Gives every fan of faces round a vertex beyond the first a vertex of its own (at the same place). Two
// contours of a section that touch at a point meet a stair step's mid-plane in one vertex of the exact
// triangulation, which two wall strips then share: a vertex no half-edge mesh holds, whose faces it drops
// (the end mill at --step 0.2 came out open, black-box testing). The surface touches itself there, as the
// sections do; every edge keeps its two faces.
void split_pinched_vertices(std::vector<Eigen::Vector3d>& V, std::vector<std::array<int, 3>>& F) {
  // Per vertex, its corners: (face, position in the face).
  std::vector<std::vector<std::pair<int, int>>> corners(V.size());
  for (size_t f = 0; f < F.size(); ++f)
    for (int c = 0; c < 3; ++c) corners[static_cast<size_t>(F[f][c])].push_back({static_cast<int>(f), c});
  std::vector<size_t> next;
  std::vector<char> done, has_prev;
  for (size_t v = 0; v < corners.size(); ++v) {
    const auto& cs = corners[v];
    if (cs.size() < 2) continue;
    // Round the vertex a face (v, a, b) leads from a to b; a fan is a chain of such steps (a cycle on a
    // closed surface; an open one is walked from its first corner, so that it stays one fan).
    const size_t k_end = cs.size();
    next.assign(k_end, k_end);
    has_prev.assign(k_end, 0);
    for (size_t k = 0; k < k_end; ++k) {
      const std::array<int, 3>& fk = F[static_cast<size_t>(cs[k].first)];
      const int a = fk[(cs[k].second + 1) % 3], b = fk[(cs[k].second + 2) % 3];
      double best = 1e300;
      int found = 0;
      for (size_t m = 0; m < k_end; ++m) {
        const std::array<int, 3>& fm = F[static_cast<size_t>(cs[m].first)];
        if (fm[(cs[m].second + 1) % 3] != b) continue;
        if (found++ == 0) {  // the turns are needed only where the edge has more than two faces
          next[k] = m;
          continue;
        }
        if (found == 2) {
          const std::array<int, 3>& f0 = F[static_cast<size_t>(cs[next[k]].first)];
          best = turn_into_material(V[v], V[static_cast<size_t>(a)], V[static_cast<size_t>(b)],
                                    V[static_cast<size_t>(f0[(cs[next[k]].second + 2) % 3])]);
        }
        const double turn = turn_into_material(V[v], V[static_cast<size_t>(a)], V[static_cast<size_t>(b)],
                                               V[static_cast<size_t>(fm[(cs[m].second + 2) % 3])]);
        if (turn < best) best = turn, next[k] = m;
      }
      if (next[k] < k_end) has_prev[next[k]] = 1;
    }
    done.assign(k_end, 0);
    int fans = 0;
    for (int pass = 0; pass < 2; ++pass)
      for (size_t start = 0; start < k_end; ++start) {
        if (done[start] || (pass == 0 && has_prev[start])) continue;
        int id = static_cast<int>(v);
        if (fans++ > 0) {
          id = static_cast<int>(V.size());
          V.push_back(V[v]);
        }
        for (size_t k = start; k < k_end && !done[k]; k = next[k]) {
          done[k] = 1;
          F[static_cast<size_t>(cs[k].first)][cs[k].second] = id;
        }
      }
  }
}

}  // namespace

Mesh tile_sections(const SectionStack& stack, const TilingOptions& options, TilingStats* stats) {
  const auto& secs = stack.sections;
  std::vector<Eigen::Vector3d> V;
  std::vector<PlacedSection> placed_sections(secs.size());
  for (size_t k = 0; k < secs.size(); ++k) {
    PlacedSection& ps = placed_sections[k];
    ps.section = &secs[k];
    for (const Contour& c : secs[k].contours) {
      std::vector<int> ids;
      for (const auto& p : c.points) {
        ids.push_back(static_cast<int>(V.size()));
        V.emplace_back(p.x(), p.y(), secs[k].z);
      }
      ps.ids.push_back(std::move(ids));
    }
    ps.components = components(secs[k]);
  }
  const size_t slabs = secs.empty() ? 0 : secs.size() - 1;
  std::vector<SlabMesh> parts(slabs + 2);
  std::atomic<int> tiled{0}, matched{0}, groups{0}, fallbacks{0};
  tbb::parallel_for(size_t(0), slabs, [&](size_t k) {
    const PlacedSection &P = placed_sections[k], &Q = placed_sections[k + 1];
    SlabCounts counts;
    SlabMesh slab = tile_slab(P, Q, counts);
    if (options.check_slabs && !same_contours(*P.section, *Q.section) && self_intersects(slab, V)) {
      ++fallbacks;
      slab = SlabMesh{};
      counts = SlabCounts{};
      detail::stair_step(placed(P, all_contours(P)), placed(Q, all_contours(Q)),
                         0.5 * (P.section->z + Q.section->z), slab);
    }
    tiled += counts.tiled, matched += counts.matched, groups += counts.groups;
    parts[k] = std::move(slab);
  });
  if (!secs.empty()) {
    detail::end_cap(placed(placed_sections.front(), all_contours(placed_sections.front())), false, parts[slabs]);
    detail::end_cap(placed(placed_sections.back(), all_contours(placed_sections.back())), true, parts[slabs + 1]);
  }
  // Merge: slab-local vertices get global ids after the section vertices.
  std::vector<std::array<int, 3>> F;
  for (const SlabMesh& part : parts) {
    const int base = static_cast<int>(V.size());
    V.insert(V.end(), part.V.begin(), part.V.end());
    for (const auto& f : part.F) {
      std::array<int, 3> g;
      for (int c = 0; c < 3; ++c) g[c] = f[c] >= 0 ? f[c] : base + (-1 - f[c]);
      F.push_back(g);
    }
  }
  split_pinched_vertices(V, F);
  if (stats) *stats = {static_cast<int>(slabs), tiled, matched, groups, fallbacks};
  Eigen::MatrixX3d Vm(V.size(), 3);
  for (size_t i = 0; i < V.size(); ++i) Vm.row(i) = V[i].transpose();
  Eigen::MatrixX3i Fm(F.size(), 3);
  for (size_t i = 0; i < F.size(); ++i) Fm.row(i) << F[i][0], F[i][1], F[i][2];
  return mesh_from_arrays(Vm, Fm);
}

}  // namespace tf::grind
