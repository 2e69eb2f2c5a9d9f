// tiltfield verifier: meshes that are not stock (fixtures, check surfaces, the design) seen along the rays
// of the tri-dexel lattice: per ray, the crossings of the mesh, kept only for the rays whose line meets
// the mesh's bounding box.
#pragma once
#include <cstdint>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/dexel/tridexel.hpp"

namespace tf {

struct Crossing {
  float t;    // coordinate along the ray relative to the lattice origin, mm
  float cos;  // outward unit normal . ray direction (< 0: the ray enters the solid / the part side)
};

class RayTable {
 public:
  // Casts every lattice ray through `mesh`. A closed mesh becomes solid intervals (`solid()`), an open
  // one stays a list of surface crossings.
  RayTable(const Mesh& mesh, const Lattice& lattice);
  bool solid() const { return solid_; }
  // The crossings of ray (iu, iv) of grid d: [begin, end). Empty outside the mesh's footprint.
  const Crossing* begin(int d, int iu, int iv) const;
  const Crossing* end(int d, int iu, int iv) const;
  // The mesh's extent along grid d's rays (relative to the lattice origin) and its footprint in ray
  // indices, for culling.
  float lo(int d) const { return grids_[d].lo; }
  float hi(int d) const { return grids_[d].hi; }
  bool covers(int d, int iu, int iv) const {
    const auto& g = grids_[d];
    return iu >= g.u0 && iu < g.u0 + g.nu && iv >= g.v0 && iv < g.v0 + g.nv;
  }

 private:
  struct Grid {
    int u0 = 0, v0 = 0, nu = 0, nv = 0;
    float lo = 0, hi = 0;
    std::vector<uint32_t> offsets;  // nu * nv + 1
    std::vector<Crossing> items;
  };
  bool solid_ = false;
  std::array<Grid, 3> grids_;
};

}  // namespace tf
