#include "obstacles.hpp"

#include <algorithm>
#include <cmath>

#include "mesh_rays.hpp"

namespace tf {

RayTable::RayTable(const Mesh& mesh, const Lattice& L) {
  solid_ = mesh.n_faces() > 0 && is_closed(mesh) && signed_volume(mesh) > 0;
  const Eigen::AlignedBox3d box = bounding_box(mesh);
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
    std::vector<std::vector<uint32_t>> counts(g.nv, std::vector<uint32_t>(g.nu, 0));
    // Rays are visited in increasing iu within a row, and each row by one task.
    scan_mesh_rays(mesh, L, d, [&](int iu, int iv, const RayHit* hits, int n) {
      const int ju = iu - g.u0, jv = iv - g.v0;
      if (ju < 0 || ju >= g.nu || jv < 0 || jv >= g.nv) return;
      counts[jv][ju] = static_cast<uint32_t>(n);
      for (int k = 0; k < n; ++k) rows[jv].push_back({static_cast<float>(hits[k].t), static_cast<float>(hits[k].cos)});
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
