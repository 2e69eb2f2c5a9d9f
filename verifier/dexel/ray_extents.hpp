// tiltfield verifier: where along the rays something is, for groups of rays, so that a swept part can be
// dismissed without reading the rays themselves. Per grid the rays are grouped in tiles of kTile x kTile
// and each tile in kTile row segments (kTile rays of one row); a segment keeps the hull of its rays'
// ranges along the ray axis, a tile the hull of its segments. Both are conservative after any change
// that only shrinks the rays' contents until refreshed, and exact after a refresh.
#pragma once
#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "tiltfield/dexel/tridexel.hpp"

namespace tf {

inline constexpr int kTile = 16;
inline constexpr Interval kNoExtent{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};

inline Interval hull(const Interval& a, const Interval& b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }
inline bool meets(const Interval& a, float lo, float hi) { return hi >= a.lo && lo <= a.hi; }

class RayExtents {
 public:
  RayExtents() = default;
  // All segments and tiles of `lattice`'s grids, empty.
  explicit RayExtents(const Lattice& lattice) {
    for (int d = 0; d < 3; ++d) {
      const int nu = lattice.n[Lattice::u_axis(d)], nv = lattice.n[Lattice::v_axis(d)];
      tiles_u_[d] = (nu + kTile - 1) / kTile;
      tiles_v_[d] = (nv + kTile - 1) / kTile;
      rows_v_[d] = nv;
      nu_[d] = nu;
      row_[d].assign(size_t(tiles_u_[d]) * nv, kNoExtent);
      tile_[d].assign(size_t(tiles_u_[d]) * tiles_v_[d], kNoExtent);
    }
  }
  int tiles_u(int d) const { return tiles_u_[d]; }
  int tiles_v(int d) const { return tiles_v_[d]; }
  const Interval& row(int d, int tu, int iv) const { return row_[d][size_t(iv) * tiles_u_[d] + tu]; }
  const Interval& tile(int d, int tu, int tv) const { return tile_[d][size_t(tv) * tiles_u_[d] + tu]; }

  // Sets segment (tu, iv) of grid d to the hull of range(iu) over its rays (range returns kNoExtent for
  // an empty ray).
  template <class Range>
  void refresh_row(int d, int tu, int iv, Range range) {
    Interval e = kNoExtent;
    for (int iu = tu * kTile, end = std::min(nu_[d], (tu + 1) * kTile); iu < end; ++iu) e = hull(e, range(iu));
    row_[d][size_t(iv) * tiles_u_[d] + tu] = e;
  }
  // Sets tile (tu, tv) of grid d to the hull of its segments.
  void refresh_tile(int d, int tu, int tv) {
    Interval e = kNoExtent;
    for (int iv = tv * kTile, end = std::min(rows_v_[d], (tv + 1) * kTile); iv < end; ++iv) e = hull(e, row(d, tu, iv));
    tile_[d][size_t(tv) * tiles_u_[d] + tu] = e;
  }
  // Every segment and tile from range(d, iu, iv).
  template <class Range>
  void refresh_all(Range range) {
    for (int d = 0; d < 3; ++d)
      for (int tv = 0; tv < tiles_v_[d]; ++tv) {
        for (int iv = tv * kTile, end = std::min(rows_v_[d], (tv + 1) * kTile); iv < end; ++iv)
          for (int tu = 0; tu < tiles_u_[d]; ++tu) refresh_row(d, tu, iv, [&](int iu) { return range(d, iu, iv); });
        for (int tu = 0; tu < tiles_u_[d]; ++tu) refresh_tile(d, tu, tv);
      }
  }

 private:
  std::array<int, 3> tiles_u_{}, tiles_v_{}, rows_v_{}, nu_{};
  std::array<std::vector<Interval>, 3> row_, tile_;
};

}  // namespace tf
