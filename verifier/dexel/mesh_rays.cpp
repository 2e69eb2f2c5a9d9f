// Scan conversion of a triangle mesh onto the rays of one lattice grid (mesh_rays.hpp: why, and the rule
// that makes it watertight).
#include "mesh_rays.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace tf {
namespace {

constexpr int kBandRows = 16;  // rows of rays a task collects and sorts at once

// Sign of the side test of node x against the edge p -> q, evaluated in the canonical order p < q
// (lexicographic in (u, v)) so that both triangles of an edge compute the same number. A zero is decided
// by moving x to (u + eps, v + eps^2): the test's change is -(q_v - p_v) eps + (q_u - p_u) eps^2.
int canonical_side(double pu, double pv, double qu, double qv, double xu, double xv) {
  const double e = (qu - pu) * (xv - pv) - (qv - pv) * (xu - pu);
  if (e > 0.0) return 1;
  if (e < 0.0) return -1;
  if (qv != pv) return qv > pv ? -1 : 1;
  return qu > pu ? 1 : -1;
}

bool before(double au, double av, double bu, double bv) { return au < bu || (au == bu && av < bv); }

// The side of x against the triangle's edge a -> b: +1 left, -1 right (never 0).
int side(const double* a, const double* b, double xu, double xv) {
  return before(a[0], a[1], b[0], b[1]) ? canonical_side(a[0], a[1], b[0], b[1], xu, xv)
                                       : -canonical_side(b[0], b[1], a[0], a[1], xu, xv);
}

// One triangle in the grid's frame: vertices as (u, v, d), its normal's components in the same order.
struct Projected {
  double p[3][3];
  double n[3];
  double inv_nd, cos;
  int orient;  // sign of the projected area: +1 counter-clockwise in (u, v)
};

bool project(const TriangleArrays& a, int f, int u, int v, int d, Projected& t) {
  Eigen::Vector3d q[3];
  for (int k = 0; k < 3; ++k) {
    q[k] = a.V.row(a.F(f, k)).transpose();
    t.p[k][0] = q[k][u];
    t.p[k][1] = q[k][v];
    t.p[k][2] = q[k][d];
  }
  const Eigen::Vector3d n = (q[1] - q[0]).cross(q[2] - q[0]);
  // The projected area, from the projected coordinates (the same numbers the side tests use).
  const double area = (t.p[1][0] - t.p[0][0]) * (t.p[2][1] - t.p[0][1]) - (t.p[1][1] - t.p[0][1]) * (t.p[2][0] - t.p[0][0]);
  if (area == 0.0 || !std::isfinite(area) || n.norm() == 0.0) return false;
  t.n[0] = n[u];
  t.n[1] = n[v];
  t.n[2] = n[d];
  if (t.n[2] == 0.0) return false;
  t.inv_nd = 1.0 / t.n[2];
  t.cos = t.n[2] / n.norm();
  t.orient = area > 0.0 ? 1 : -1;
  return true;
}

// Lattice indices of the nodes in [lo, hi] along an axis with n nodes; empty when i1 < i0.
void node_range(double lo, double hi, double origin, double h, int n, int& i0, int& i1) {
  i0 = static_cast<int>(std::clamp(std::ceil((lo - origin) / h), 0.0, double(n)));
  i1 = static_cast<int>(std::clamp(std::floor((hi - origin) / h), -1.0, double(n) - 1.0));
}

struct Entry {
  uint32_t key;  // row within the band * nu + iu
  RayHit hit;
};

struct BandScratch {
  std::vector<Entry> entries;
  std::vector<uint32_t> start;
  std::vector<RayHit> sorted;
};

// The crossings of triangle t with the rays of rows iv0..iv1 (inclusive), appended with band-relative keys.
void scan_triangle(const Projected& t, const Lattice& L, int u, int v, int d, int band_iv0, int iv0, int iv1,
                   std::vector<Entry>& out) {
  const double h = L.h, ou = L.origin[u], ov = L.origin[v];
  const int nu = L.n[u];
  const double umin = std::min({t.p[0][0], t.p[1][0], t.p[2][0]}), umax = std::max({t.p[0][0], t.p[1][0], t.p[2][0]});
  for (int iv = iv0; iv <= iv1; ++iv) {
    const double xv = ov + h * iv;
    // The row's stretch inside the triangle, from the edges it crosses; widened by a node, the side tests decide.
    double lo = umax, hi = umin;
    for (int k = 0; k < 3; ++k) {
      const double* a = t.p[k];
      const double* b = t.p[(k + 1) % 3];
      if (xv < std::min(a[1], b[1]) || xv > std::max(a[1], b[1])) continue;
      if (a[1] == b[1]) {  // an edge along the row
        lo = std::min({lo, a[0], b[0]});
        hi = std::max({hi, a[0], b[0]});
        continue;
      }
      const double x = a[0] + (b[0] - a[0]) * (xv - a[1]) / (b[1] - a[1]);
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    if (hi < lo) continue;
    int i0, i1;
    node_range(std::max(umin, lo) - h, std::min(umax, hi) + h, ou, h, nu, i0, i1);
    for (int iu = i0; iu <= i1; ++iu) {
      const double xu = ou + h * iu;
      if (side(t.p[0], t.p[1], xu, xv) != t.orient || side(t.p[1], t.p[2], xu, xv) != t.orient ||
          side(t.p[2], t.p[0], xu, xv) != t.orient)
        continue;
      const double z = t.p[0][2] + (t.n[0] * (t.p[0][0] - xu) + t.n[1] * (t.p[0][1] - xv)) * t.inv_nd;
      out.push_back({static_cast<uint32_t>((iv - band_iv0) * nu + iu), {z - L.origin[d], t.cos}});
    }
  }
}

// The band's crossings grouped by ray (counting sort on the key), each ray's sorted along it, visited.
void visit_band(BandScratch& s, int band_iv0, int rows, int nu, const RayVisit& visit) {
  const size_t keys = size_t(rows) * nu;
  s.start.assign(keys + 1, 0);
  for (const Entry& e : s.entries) ++s.start[e.key + 1];
  for (size_t k = 0; k < keys; ++k) s.start[k + 1] += s.start[k];
  s.sorted.resize(s.entries.size());
  {
    std::vector<uint32_t>& fill = s.start;  // advanced while filling, restored below
    for (const Entry& e : s.entries) s.sorted[fill[e.key]++] = e.hit;
    for (size_t k = keys; k > 0; --k) fill[k] = fill[k - 1];
    fill[0] = 0;
  }
  for (size_t k = 0; k < keys; ++k) {
    const uint32_t b = s.start[k], e = s.start[k + 1];
    if (b == e) continue;
    RayHit* r = s.sorted.data() + b;
    std::sort(r, r + (e - b), [](const RayHit& x, const RayHit& y) { return x.t < y.t; });
    visit(static_cast<int>(k % nu), band_iv0 + static_cast<int>(k / nu), r, static_cast<int>(e - b));
  }
}

}  // namespace

void scan_mesh_rays(const Mesh& mesh, const Lattice& L, int d, const RayVisit& visit) {
  const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
  const int nu = L.n[u], nv = L.n[v];
  if (nu <= 0 || nv <= 0) return;
  const TriangleArrays a = to_arrays(mesh);
  const int nf = static_cast<int>(a.F.rows());
  std::vector<Projected> tris;
  std::vector<std::array<int, 2>> rows;  // per kept triangle: its first and last row
  tris.reserve(nf);
  rows.reserve(nf);
  for (int f = 0; f < nf; ++f) {
    Projected t;
    if (!project(a, f, u, v, d, t)) continue;
    int iv0, iv1;
    // A node on the boundary may round to either side of the range: one more row each side, the side
    // tests decide.
    node_range(std::min({t.p[0][1], t.p[1][1], t.p[2][1]}) - L.h, std::max({t.p[0][1], t.p[1][1], t.p[2][1]}) + L.h,
               L.origin[v], L.h, nv, iv0, iv1);
    if (iv1 < iv0) continue;
    tris.push_back(t);
    rows.push_back({iv0, iv1});
  }
  // Triangles per band of rows (compressed: counts, then indices).
  const int bands = (nv + kBandRows - 1) / kBandRows;
  std::vector<uint32_t> band_start(size_t(bands) + 1, 0);
  for (const auto& r : rows)
    for (int b = r[0] / kBandRows; b <= r[1] / kBandRows; ++b) ++band_start[b + 1];
  for (int b = 0; b < bands; ++b) band_start[b + 1] += band_start[b];
  std::vector<uint32_t> band_tris(band_start.back());
  {
    std::vector<uint32_t> fill(band_start.begin(), band_start.end() - 1);
    for (size_t i = 0; i < rows.size(); ++i)
      for (int b = rows[i][0] / kBandRows; b <= rows[i][1] / kBandRows; ++b) band_tris[fill[b]++] = static_cast<uint32_t>(i);
  }
  tbb::enumerable_thread_specific<BandScratch> scratch;
  tbb::parallel_for(0, bands, [&](int b) {
    if (band_start[b] == band_start[b + 1]) return;
    BandScratch& s = scratch.local();
    s.entries.clear();
    const int r0 = b * kBandRows, r1 = std::min(nv, r0 + kBandRows) - 1;
    for (uint32_t k = band_start[b]; k < band_start[b + 1]; ++k) {
      const uint32_t i = band_tris[k];
      scan_triangle(tris[i], L, u, v, d, r0, std::max(r0, rows[i][0]), std::min(r1, rows[i][1]), s.entries);
    }
    visit_band(s, r0, r1 - r0 + 1, nu, visit);
  });
}

}  // namespace tf
