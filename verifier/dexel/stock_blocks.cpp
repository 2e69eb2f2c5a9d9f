// Which block last cut each stock-mesh vertex, from the per-ray last blocks (see stock_blocks.hpp).
#include "tiltfield/dexel/stock_blocks.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tf {
namespace {

// True when `ray` has an interval end within `tol` of t (an end the raw stock has: not cut there).
bool has_end_near(const Dexel& ray, float t, float tol) {
  for (const Interval& iv : ray)
    if (std::abs(iv.lo - t) <= tol || std::abs(iv.hi - t) <= tol) return true;
  return false;
}

}  // namespace

std::vector<uint32_t> stock_vertex_blocks(const Mesh& mesh, const TriDexel& stock, const LastBlocks& last_block,
                                          const TriDexel* initial) {
  for (int d = 0; d < 3; ++d)
    if (last_block[d].size() != stock.grid(d).size())
      throw std::invalid_argument("stock_vertex_blocks: the last blocks do not match the stock's rays");
  const Lattice& L = stock.lattice();
  const double reach = 1.5 * L.h;
  // An end nothing cut keeps the raw stock's float bit for bit; a cut end moved by far more than this.
  const float same = 1e-5f;
  std::vector<uint32_t> out(mesh.n_vertices(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.n_vertices(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d p = to_eigen(mesh.point(Mesh::VertexHandle(static_cast<int>(i)))) - L.origin;
      uint32_t best = std::numeric_limits<uint32_t>::max();
      for (int d = 0; d < 3 && best > 0; ++d) {
        const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
        const int iu0 = static_cast<int>(std::floor(p[u] / L.h)), iv0 = static_cast<int>(std::floor(p[v] / L.h));
        for (int iv = std::max(iv0, 0); iv <= std::min(iv0 + 1, L.n[v] - 1); ++iv)
          for (int iu = std::max(iu0, 0); iu <= std::min(iu0 + 1, L.n[u] - 1); ++iu) {
            const Dexel& ray = stock.ray(d, iu, iv);
            for (const Interval& seg : ray)
              for (const float e : {seg.lo, seg.hi}) {
                if (std::abs(e - p[d]) > reach) continue;
                const bool raw = initial && has_end_near(initial->ray(d, iu, iv), e, same);
                best = std::min(best, raw ? 0u : last_block[d][size_t(iu) + size_t(L.n[u]) * size_t(iv)]);
              }
          }
      }
      out[i] = best == std::numeric_limits<uint32_t>::max() ? 0 : best;
    }
  });
  return out;
}

}  // namespace tf
