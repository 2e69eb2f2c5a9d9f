#include "obstacles.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "raycast.hpp"

namespace tf {

RayTable::RayTable(const Mesh& mesh, const Lattice& L) {
  solid_ = mesh.n_faces() > 0 && is_closed(mesh) && signed_volume(mesh) > 0;
  const RayMesh rm(mesh);
  const Eigen::AlignedBox3d box = rm.box();
  for (int d = 0; d < 3; ++d) {
    Grid& g = grids_[d];
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    if (box.isEmpty()) continue;
    // Node index ranges of the box, clamped in double before the conversion.
    auto first = [&](double x, int a) {
      return static_cast<int>(std::clamp(std::ceil((x - L.origin[a]) / L.h), 0.0, double(L.n[a])));
    };
    auto past = [&](double x, int a) {
      return static_cast<int>(std::clamp(std::floor((x - L.origin[a]) / L.h) + 1.0, 0.0, double(L.n[a])));
    };
    g.u0 = first(box.min()[u], u);
    const int u1 = past(box.max()[u], u);
    g.v0 = first(box.min()[v], v);
    const int v1 = past(box.max()[v], v);
    g.nu = std::max(0, u1 - g.u0);
    g.nv = std::max(0, v1 - g.v0);
    g.lo = static_cast<float>(box.min()[d] - L.origin[d]);
    g.hi = static_cast<float>(box.max()[d] - L.origin[d]);
    std::vector<std::vector<Crossing>> rows(g.nv);
    std::vector<std::vector<uint32_t>> counts(g.nv);
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[d] = 1.0;
    tbb::parallel_for(0, g.nv, [&](int jv) {
      std::vector<RayHit> hits;
      counts[jv].resize(g.nu);
      for (int ju = 0; ju < g.nu; ++ju) {
        Eigen::Vector3d o = L.origin;
        o[u] = L.coord(u, g.u0 + ju);
        o[v] = L.coord(v, g.v0 + jv);
        rm.hits(o, e, box.min()[d] - L.origin[d] - 1.0, box.max()[d] - L.origin[d] + 1.0, hits);
        counts[jv][ju] = static_cast<uint32_t>(hits.size());
        for (const RayHit& h : hits) rows[jv].push_back({static_cast<float>(h.t), static_cast<float>(h.cos)});
      }
    });
    g.offsets.assign(size_t(g.nu) * g.nv + 1, 0);
    size_t k = 0;
    for (int jv = 0; jv < g.nv; ++jv)
      for (int ju = 0; ju < g.nu; ++ju, ++k) g.offsets[k + 1] = g.offsets[k] + counts[jv][ju];
    g.items.reserve(g.offsets.back());
    for (auto& r : rows) g.items.insert(g.items.end(), r.begin(), r.end());
  }
}

const Crossing* RayTable::begin(int d, int iu, int iv) const {
  const auto& g = grids_[d];
  if (!covers(d, iu, iv)) return nullptr;
  return g.items.data() + g.offsets[size_t(iv - g.v0) * g.nu + (iu - g.u0)];
}

const Crossing* RayTable::end(int d, int iu, int iv) const {
  const auto& g = grids_[d];
  if (!covers(d, iu, iv)) return nullptr;
  return g.items.data() + g.offsets[size_t(iv - g.v0) * g.nu + (iu - g.u0) + 1];
}

}  // namespace tf
