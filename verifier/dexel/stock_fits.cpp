// The stock mesh's local fits (stock_surface.hpp): an algebraic sphere or plane per vertex through the
// exact crossings around it, the vertices moved onto them, and the subdivision that follows them.
#include <algorithm>
#include <cmath>
#include <map>
#include <span>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "stock_surface.hpp"

namespace tf::stock_mesh {

Eigen::Matrix<double, 5, 1> smallest_eigenvector(const Eigen::Matrix<double, 5, 5>& M) {
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  // A shift of the trace's 1e-13 keeps the factorisation regular when the points fit exactly (a zero
  // eigenvalue) and moves no eigenvector.
  const double shift = 1e-13 * M.trace();
  if (!(shift > 0.0)) return Vec5::Unit(0);
  const Eigen::LDLT<Eigen::Matrix<double, 5, 5>> ldlt(M + shift * Eigen::Matrix<double, 5, 5>::Identity());
  if (ldlt.info() == Eigen::Success) {
    // A start whose components (the square roots of five primes) no small integer combination cancels:
    // points placed symmetrically give eigenvectors such as (1, -1, 0, 0, 0), to which an even start
    // would be orthogonal, and inverse iteration never finds a direction its start lacks.
    Vec5 u(1.4142135623730951, 1.7320508075688772, 2.2360679774997898, 2.6457513110645907, 3.3166247903554);
    u.normalize();
    for (int k = 0; k < 12; ++k) {
      Vec5 next = ldlt.solve(u);
      const double n = next.norm();
      if (!(n > 0.0) || !std::isfinite(n)) break;
      next /= n;
      if (next.dot(u) < 0.0) next = -next;
      const double step = (next - u).norm();
      u = next;
      if (step < 1e-13) return u;
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> es(M);
  return es.eigenvectors().col(0);
}

LocalFit fit_points(const std::vector<Eigen::Vector3d>& P, double tolerance) {
  LocalFit f;
  if (P.size() < 6) return f;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : P) mean += p;
  mean /= double(P.size());
  double scale = 0.0;
  for (const auto& p : P) scale += (p - mean).squaredNorm();
  scale = std::sqrt(scale / double(P.size()));
  if (scale <= 0) return f;
  // M = sum of a a^T over the points, a = (1, q, |q|^2). The solver reads only its lower triangle, so only
  // that is summed, in scalars: summed into the matrix in memory, each entry waited on its own last store.
  double sx = 0, sy = 0, sz = 0, sw = 0, xx = 0, xy = 0, xz = 0, xw = 0, yy = 0, yz = 0, yw = 0, zz = 0, zw = 0, ww = 0;
  for (const auto& p : P) {
    const Eigen::Vector3d q = (p - mean) / scale;
    const double x = q.x(), y = q.y(), z = q.z(), w = q.squaredNorm();
    sx += x, sy += y, sz += z, sw += w;
    xx += x * x, xy += y * x, xz += z * x, xw += w * x;
    yy += y * y, yz += z * y, yw += w * y;
    zz += z * z, zw += w * z;
    ww += w * w;
  }
  Eigen::Matrix<double, 5, 5> M = Eigen::Matrix<double, 5, 5>::Zero();
  M(0, 0) = double(P.size());
  M(1, 0) = sx, M(2, 0) = sy, M(3, 0) = sz, M(4, 0) = sw;
  M(1, 1) = xx, M(2, 1) = xy, M(3, 1) = xz, M(4, 1) = xw;
  M(2, 2) = yy, M(3, 2) = yz, M(4, 2) = yw;
  M(3, 3) = zz, M(4, 3) = zw;
  M(4, 4) = ww;
  const Eigen::Matrix<double, 5, 1> u = smallest_eigenvector(M);
  const Eigen::Vector3d g = u.segment<3>(1);
  if (std::abs(u[4]) < 1e-9 * g.norm() || std::abs(u[4]) < 1e-12) {
    if (g.norm() < 1e-12) return f;
    f.plane = true;
    f.c = g.normalized();
    // u0 + g.q = 0 with q = (x - mean) / scale  ->  n.x = n.mean - u0 scale / |g|
    f.r = f.c.dot(mean) - u[0] * scale / g.norm();
  } else {
    const Eigen::Vector3d cq = -g / (2.0 * u[4]);
    const double r2 = cq.squaredNorm() - u[0] / u[4];
    if (!(r2 > 0)) return f;
    f.c = mean + scale * cq;
    f.r = scale * std::sqrt(r2);
  }
  for (const auto& p : P)
    if (f.distance(p) > tolerance) return f;
  f.valid = true;
  return f;
}

std::vector<LocalFit> smooth_vertices(Surface& b) {
  const size_t nv = b.vertices.size();
  // The vertices' neighbours in one array (ring[ring_start[v], ring_start[v + 1])): a vector per vertex
  // was millions of small allocations, made on one thread.
  std::vector<uint32_t> ring_start(nv + 1, 0);
  for (const auto& f : b.faces)
    for (int k = 0; k < 3; ++k) ring_start[size_t(f[k]) + 1] += 2;
  for (size_t v = 0; v < nv; ++v) ring_start[v + 1] += ring_start[v];
  std::vector<int> ring(ring_start[nv]);
  {
    std::vector<uint32_t> fill(ring_start.begin(), ring_start.end() - 1);
    for (const auto& f : b.faces)
      for (int k = 0; k < 3; ++k) {
        ring[fill[size_t(f[k])]++] = f[(k + 1) % 3];
        ring[fill[size_t(f[k])]++] = f[(k + 2) % 3];
      }
  }
  std::vector<LocalFit> fits(nv);
  const double tol = 0.05 * b.h;
  // Each vertex's fit depends on its own neighbourhood only: in parallel.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nv, 1024), [&](const tbb::blocked_range<size_t>& range) {
    std::vector<Eigen::Vector3d> P;
    for (size_t v = range.begin(); v != range.end(); ++v) {
      int* const r0 = ring.data() + ring_start[v];
      int* r1 = ring.data() + ring_start[v + 1];
      std::sort(r0, r1);
      r1 = std::unique(r0, r1);
      P.clear();
      for (const int w : std::span<const int>(r0, r1)) P.insert(P.end(), b.points.begin() + b.point_start[w], b.points.begin() + b.point_start[w + 1]);
      P.insert(P.end(), b.points.begin() + b.point_start[v], b.points.begin() + b.point_start[v + 1]);
      std::sort(P.begin(), P.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& c) {
        return std::lexicographical_compare(a.data(), a.data() + 3, c.data(), c.data() + 3);
      });
      P.erase(std::unique(P.begin(), P.end()), P.end());
      fits[v] = fit_points(P, tol);
    }
  });
  for (size_t v = 0; v < nv; ++v) {
    if (!fits[v].valid) continue;
    const Eigen::Vector3d q = fits[v].project(b.vertices[v]);
    if ((q - b.vertices[v]).norm() <= b.h) b.vertices[v] = q;
    else fits[v].valid = false;
  }
  return fits;
}

void refine(std::vector<Eigen::Vector3d>& V, std::vector<Eigen::Vector3i>& F, std::vector<LocalFit>& fits) {
  std::map<std::pair<int, int>, int> mid;
  std::vector<Eigen::Vector3i> G;
  G.reserve(F.size() * 4);
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    const Eigen::Vector3d m = 0.5 * (V[a] + V[b]);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int e : {a, b})
      if (fits[e].valid) {
        sum += fits[e].project(m);
        ++n;
      }
    V.push_back(n ? Eigen::Vector3d(sum / n) : m);
    fits.push_back(fits[a].valid ? fits[a] : fits[b]);
    const int id = static_cast<int>(V.size()) - 1;
    mid.emplace(key, id);
    return id;
  };
  for (const auto& f : F) {
    const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
    G.emplace_back(f[0], a, c);
    G.emplace_back(f[1], b, a);
    G.emplace_back(f[2], c, b);
    G.emplace_back(a, b, c);
  }
  F.swap(G);
}

}  // namespace tf::stock_mesh
