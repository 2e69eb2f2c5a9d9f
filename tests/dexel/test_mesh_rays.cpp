// Scan conversion of meshes onto the lattice rays (mesh_rays.cpp): watertight where rays pass exactly
// through vertices and edges, and the same crossings as a brute-force ray-triangle test elsewhere.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <mutex>
#include <vector>

#include "helpers.hpp"
#include "mesh_rays.hpp"

namespace tf {
namespace {

// Every ray's crossings: how many, and whether as many enter as leave (a closed oriented surface, even
// where snapping folded it) and whether they alternate (a surface without folds).
struct RayStats {
  size_t rays = 0, odd = 0, unbalanced = 0, not_alternating = 0, crossings = 0;
};

RayStats scan_stats(const Mesh& m, const Lattice& L) {
  RayStats s;
  std::mutex mu;
  for (int d = 0; d < 3; ++d)
    scan_mesh_rays(m, L, d, [&](int, int, const RayHit* h, int n) {
      bool alternating = true;
      int winding = 0;
      for (int k = 0; k < n; ++k) {
        alternating &= (h[k].cos < 0) == (k % 2 == 0);
        winding += h[k].cos < 0 ? 1 : -1;
      }
      std::lock_guard<std::mutex> lock(mu);
      ++s.rays;
      s.crossings += size_t(n);
      s.odd += n % 2;
      s.not_alternating += !alternating;
      s.unbalanced += winding != 0;
    });
  return s;
}

// A mesh whose vertices are snapped to lattice nodes, so that many rays pass exactly through vertices
// and along edges: the icosphere scaled and rounded to the node grid (a closed, outward surface still).
Mesh snapped_sphere(const Lattice& L, double r, int levels, const Eigen::Vector3d& c) {
  TriangleArrays a = to_arrays(test::icosphere(r, levels, c));
  for (Eigen::Index i = 0; i < a.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) a.V(i, k) = L.origin[k] + L.h * std::round((a.V(i, k) - L.origin[k]) / L.h);
  return mesh_from_arrays(a.V, a.F);
}

TEST(MeshRays, WatertightThroughVerticesAndEdges) {
  const Lattice L = lattice_for(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-6), Eigen::Vector3d::Constant(6)), 0.3, 2);
  // A box whose faces, edges and corners lie on node coordinates.
  const Eigen::Vector3d lo = L.origin + L.h * Eigen::Vector3d(4, 4, 4), hi = L.origin + L.h * Eigen::Vector3d(20, 18, 16);
  const Mesh box = test::box_mesh(lo, hi);
  for (const Mesh& m : {box, snapped_sphere(L, 5.0, 2, Eigen::Vector3d::Zero()),
                        snapped_sphere(L, 4.3, 3, Eigen::Vector3d(0.25, -0.5, 0.75))}) {
    const RayStats s = scan_stats(m, L);
    EXPECT_GT(s.rays, 100u);
    EXPECT_EQ(s.odd, 0u) << "a ray through a vertex or an edge was counted once or three times";
    EXPECT_EQ(s.unbalanced, 0u);
  }
  EXPECT_EQ(scan_stats(box, L).not_alternating, 0u);
  // Coarse snapping: vertices collapse onto few nodes, so whole fans of edges meet at the rays' nodes.
  for (int k = 0; k < 40; ++k) {
    const Eigen::Vector3d c(0.1 * (k % 5) - 0.2, 0.13 * (k % 7) - 0.4, 0.07 * (k % 3));
    const RayStats s = scan_stats(snapped_sphere(L, 1.0 + 0.11 * k, 3, c), L);
    EXPECT_EQ(s.odd, 0u) << k;
    EXPECT_EQ(s.unbalanced, 0u) << k;
  }
  // The box's rays: those inside its footprint, ties going to the perturbed side (u + eps, v + eps^2): a
  // ray on the box's low u face counts as inside, one on its high u face as outside; the same for v.
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    size_t count = 0, wrong = 0;
    std::mutex mu;
    scan_mesh_rays(box, L, d, [&](int, int, const RayHit* h, int n) {
      const bool ok = n == 2 && std::abs((h[1].t - h[0].t) - (hi[d] - lo[d])) < 1e-9;
      std::lock_guard<std::mutex> lock(mu);
      ++count;
      wrong += !ok;
    });
    EXPECT_EQ(wrong, 0u) << "grid " << d;
    // Nodes from lo (inclusive) to hi (exclusive) in both u and v.
    const double nu = std::round((hi[u] - lo[u]) / L.h), nv = std::round((hi[v] - lo[v]) / L.h);
    EXPECT_EQ(count, size_t(nu * nv)) << "grid " << d;
  }
}

// Möller-Trumbore against every triangle: the reference crossings of one ray (t relative to the origin).
std::vector<double> brute_force(const TriangleArrays& a, const Eigen::Vector3d& o, int d) {
  std::vector<double> ts;
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  e[d] = 1.0;
  for (Eigen::Index f = 0; f < a.F.rows(); ++f) {
    const Eigen::Vector3d p0 = a.V.row(a.F(f, 0)), p1 = a.V.row(a.F(f, 1)), p2 = a.V.row(a.F(f, 2));
    const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0, pv = e.cross(e2);
    const double det = e1.dot(pv);
    if (std::abs(det) < 1e-14) continue;
    const Eigen::Vector3d tv = o - p0;
    const double bu = tv.dot(pv) / det;
    const Eigen::Vector3d qv = tv.cross(e1);
    const double bv = e.dot(qv) / det;
    if (bu < 0 || bv < 0 || bu + bv > 1) continue;
    ts.push_back(e2.dot(qv) / det);
  }
  std::sort(ts.begin(), ts.end());
  return ts;
}

TEST(MeshRays, SameCrossingsAsBruteForce) {
  // A sphere turned by a random rotation (no ray passes near a vertex by construction of the check below).
  const Eigen::Quaterniond q = Eigen::Quaterniond::UnitRandom();
  TriangleArrays a = to_arrays(test::icosphere(3.0, 2));
  for (Eigen::Index i = 0; i < a.V.rows(); ++i) a.V.row(i) = (q * Eigen::Vector3d(a.V.row(i))).transpose();
  const Mesh m = mesh_from_arrays(a.V, a.F);
  const Lattice L = lattice_for(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-3), Eigen::Vector3d::Constant(3)), 0.37, 1);
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    std::vector<std::vector<double>> got(size_t(L.n[u]) * L.n[v]);
    scan_mesh_rays(m, L, d, [&](int iu, int iv, const RayHit* h, int n) {
      for (int k = 0; k < n; ++k) got[size_t(iv) * L.n[u] + iu].push_back(h[k].t);  // one writer per ray
    });
    size_t compared = 0;
    for (int iv = 0; iv < L.n[v]; ++iv)
      for (int iu = 0; iu < L.n[u]; ++iu) {
        Eigen::Vector3d o = L.origin;
        o[u] += L.h * iu;
        o[v] += L.h * iv;
        std::vector<double> ref = brute_force(a, o, d);
        for (double& t : ref) t += o[d] - L.origin[d];
        const auto& mine = got[size_t(iv) * L.n[u] + iu];
        ASSERT_EQ(mine.size(), ref.size()) << "grid " << d << " ray " << iu << "," << iv;
        for (size_t k = 0; k < ref.size(); ++k) EXPECT_NEAR(mine[k], ref[k], 1e-9);
        compared += ref.size();
      }
    EXPECT_GT(compared, 100u);
  }
}

}  // namespace
}  // namespace tf
