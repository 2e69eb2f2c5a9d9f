// tiltfield dexel: the tri-dexel stock model (Lee's "orthogonales Multi-Dexel-Modell"): three orthogonal grids
// of rays along x, y and z through the nodes of one cubic lattice; per ray a sorted list of disjoint
// material intervals. Memory grows with the number of rays (the grid faces) and the number of surface
// crossings, not with the volume.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {

// One material interval on a ray, as coordinates along the ray's axis relative to the lattice origin, mm.
struct Interval {
  float lo, hi;
};

// The intervals of one ray: sorted, disjoint, each longer than kMinInterval. 16 bytes; one interval is
// stored inline, more on the heap. Move-only.
class Dexel {
 public:
  Dexel() : inl_{0.f, 0.f} {}
  ~Dexel() { release(); }
  Dexel(const Dexel&) = delete;
  Dexel& operator=(const Dexel&) = delete;
  Dexel(Dexel&& o) noexcept;
  Dexel& operator=(Dexel&& o) noexcept;

  uint32_t size() const { return n_; }
  bool empty() const { return n_ == 0; }
  const Interval* data() const { return cap_ ? heap_ : &inl_; }
  const Interval* begin() const { return data(); }
  const Interval* end() const { return data() + n_; }
  // Replaces the intervals (sorted, disjoint). Reuses the heap block when large enough.
  void assign(const Interval* iv, uint32_t n);
  // Replaces intervals [k0, k1) by iv[0..n) (which must not point into this ray), keeping the others: the
  // result must be sorted and disjoint. Moves the tail in place when the storage holds the result.
  void replace(uint32_t k0, uint32_t k1, const Interval* iv, uint32_t n);
  // Heap bytes held (for memory statistics).
  size_t heap_bytes() const { return cap_ * sizeof(Interval); }
  // Exchanges the contents, storage included (no allocation).
  friend void swap(Dexel& a, Dexel& b) noexcept {
    std::swap(a.raw_, b.raw_);
    std::swap(a.n_, b.n_);
    std::swap(a.cap_, b.cap_);
  }

 private:
  void release();
  union {
    Interval inl_;
    Interval* heap_;
    uint64_t raw_;  // either of the two, as one word for swap
  };
  uint32_t n_ = 0, cap_ = 0;
};

// The first of the sorted, disjoint intervals [b, e) that ends at or after t (e when none). Most rays hold a
// few intervals, where a scan is cheapest; a ray across a raster of grooves holds hundreds.
inline const Interval* first_ending_after(const Interval* b, const Interval* e, float t) {
  if (e - b <= 8) {
    while (b != e && b->hi < t) ++b;
    return b;
  }
  return std::partition_point(b, e, [t](const Interval& iv) { return iv.hi < t; });
}

// Pieces shorter than this (mm) are dropped after a subtraction (numerical slivers).
inline constexpr float kMinInterval = 1e-4f;

// A cubic lattice: node (i, j, k) at origin + h (i, j, k); n nodes per axis.
struct Lattice {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // mm
  double h = 1.0;                                    // spacing, mm
  std::array<int, 3> n{0, 0, 0};
  // The two lattice axes across a ray grid along axis d: (d+1)%3 and (d+2)%3.
  static int u_axis(int d) { return (d + 1) % 3; }
  static int v_axis(int d) { return (d + 2) % 3; }
  size_t rays(int d) const { return size_t(n[u_axis(d)]) * size_t(n[v_axis(d)]); }
  double coord(int axis, int i) const { return origin[axis] + h * i; }
};

// Nodes at box.min + (i + 0.5 - pad) h per axis, enough to cover the box, plus `pad` empty nodes on each
// side (so the reconstructed surface closes). A box 20 mm wide at h = 20/7 gets 7 nodes inside.
Lattice lattice_for(const Eigen::AlignedBox3d& box, double h, int pad = 1);

class TriDexel {
 public:
  TriDexel() = default;  // empty: no rays
  explicit TriDexel(const Lattice& lattice);
  const Lattice& lattice() const { return lat_; }
  // Ray (iu, iv) of grid d: along axis d at node iu of u_axis(d) and iv of v_axis(d).
  Dexel& ray(int d, int iu, int iv) { return rays_[d][size_t(iu) + size_t(lat_.n[Lattice::u_axis(d)]) * iv]; }
  const Dexel& ray(int d, int iu, int iv) const {
    return rays_[d][size_t(iu) + size_t(lat_.n[Lattice::u_axis(d)]) * iv];
  }
  std::vector<Dexel>& grid(int d) { return rays_[d]; }
  const std::vector<Dexel>& grid(int d) const { return rays_[d]; }
  size_t ray_count() const { return rays_[0].size() + rays_[1].size() + rays_[2].size(); }
  // Rays holding at least one interval.
  size_t material_rays() const;
  // Volume measured by grid d alone: sum of interval lengths times h^2, mm^3.
  double volume(int d) const;
  // The mean of the three grids' volumes, mm^3.
  double volume() const;
  // Bytes held by the rays (inline and heap).
  size_t memory_bytes() const;

 private:
  Lattice lat_;
  std::array<std::vector<Dexel>, 3> rays_;
};

// In: a tri-dexel and a whole factor k >= 1. Out: every k-th ray of each grid (the same origin, spacing
// k h), the rays exact as they are, with one empty node more on the high side of each axis so that the
// surface of material reaching the fine lattice's last nodes still closes. What the coarse lattice does
// not resolve (walls thinner than k h between its rays) may be lost in a mesh made from it.
TriDexel coarsened(const TriDexel& fine, int k);

// Stock from the scene's box, cylinder or closed mesh, on `lattice`. Meshes are ray cast with Embree 3
// (winding of the outward-oriented faces, parity when the winding does not close). Throws InputError
// ("stock", ...) for an empty or open stock mesh.
TriDexel make_stock(const Stock& stock, const Lattice& lattice);
// Stock from a closed mesh alone.
TriDexel dexels_from_mesh(const Mesh& mesh, const Lattice& lattice);

// r = a \ b for sorted disjoint interval lists; returns the length removed (mm). `removed`, when not
// null, receives the removed pieces, the slivers dropped under kMinInterval included (joined to a piece
// they touch), so that r and the pieces make up a exactly. `out` is cleared first.
double subtract_intervals(const Interval* a, size_t na, const Interval* b, size_t nb, std::vector<Interval>& out,
                          std::vector<Interval>* removed);
// Total overlap length of two sorted disjoint lists, and the longest single overlap (mm).
double overlap_length(const Interval* a, size_t na, const Interval* b, size_t nb, double* longest);

}  // namespace tf
