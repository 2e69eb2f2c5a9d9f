#include "tiltfield/dexel/tridexel.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <stdexcept>

#include "mesh_rays.hpp"
#include "tiltfield/core/error.hpp"

namespace tf {

Dexel::Dexel(Dexel&& o) noexcept : n_(o.n_), cap_(o.cap_) {
  if (cap_) heap_ = o.heap_; else inl_ = o.inl_;
  o.n_ = 0;
  o.cap_ = 0;
  o.inl_ = {0.f, 0.f};
}

Dexel& Dexel::operator=(Dexel&& o) noexcept {
  if (this == &o) return *this;
  release();
  n_ = o.n_;
  cap_ = o.cap_;
  if (cap_) heap_ = o.heap_; else inl_ = o.inl_;
  o.n_ = 0;
  o.cap_ = 0;
  o.inl_ = {0.f, 0.f};
  return *this;
}

void Dexel::release() {
  if (cap_) delete[] heap_;
  cap_ = 0;
  n_ = 0;
  inl_ = {0.f, 0.f};
}

void Dexel::assign(const Interval* iv, uint32_t n) {
  if (cap_ == 0 && n <= 1) {
    if (n == 1) inl_ = iv[0];
    n_ = n;
    return;
  }
  if (n > cap_) {
    const uint32_t cap = std::max<uint32_t>(n, 2 * cap_);
    auto* mem = new Interval[cap];
    std::memcpy(mem, iv, n * sizeof(Interval));
    release();
    heap_ = mem;
    cap_ = cap;
  } else if (n > 0) {
    std::memmove(heap_, iv, n * sizeof(Interval));
  }
  n_ = n;
}

namespace {
// memcpy with a null source is undefined even for zero bytes; an empty
// replacement may come as (nullptr, 0).
void copy_intervals(Interval* to, const Interval* from, uint32_t n) {
  if (n > 0) std::memcpy(to, from, n * sizeof(Interval));
}
}  // namespace

void Dexel::replace(uint32_t k0, uint32_t k1, const Interval* iv, uint32_t n) {
  const uint32_t size = n_ - (k1 - k0) + n;
  if (cap_ > 0 && cap_ >= size) {  // on the heap, room enough
    // The tail moves only when the count changes (a cut that trims an interval leaves it in place).
    if (n_ > k1 && k1 - k0 != n) std::memmove(heap_ + k0 + n, heap_ + k1, (n_ - k1) * sizeof(Interval));
    copy_intervals(heap_ + k0, iv, n);
    n_ = size;
    return;
  }
  const Interval* old = data();
  if (size <= 1 && cap_ == 0) {  // stays inline
    if (size == 1) inl_ = k0 > 0 ? old[0] : n > 0 ? iv[0] : old[k1];
    n_ = size;
    return;
  }
  const uint32_t cap = std::max<uint32_t>(size, 2 * cap_);
  auto* mem = new Interval[cap];
  copy_intervals(mem, old, k0);
  copy_intervals(mem + k0, iv, n);
  copy_intervals(mem + k0 + n, old + k1, n_ - k1);
  release();
  heap_ = mem;
  cap_ = cap;
  n_ = size;
}

Lattice lattice_for(const Eigen::AlignedBox3d& box, double h, int pad) {
  Lattice L;
  L.h = h;
  for (int a = 0; a < 3; ++a) {
    const double extent = std::max(0.0, box.max()[a] - box.min()[a]);
    const int inside = std::max(1, static_cast<int>(std::ceil(extent / h - 1e-9)));
    L.n[a] = inside + 2 * pad;
    // Centre the inside nodes on the box.
    const double used = (inside - 1) * h;
    L.origin[a] = box.center()[a] - used / 2.0 - pad * h;
  }
  return L;
}

TriDexel::TriDexel(const Lattice& lattice) : lat_(lattice) {
  for (int d = 0; d < 3; ++d) rays_[d].resize(lat_.rays(d));
}

size_t TriDexel::material_rays() const {
  size_t n = 0;
  for (int d = 0; d < 3; ++d)
    for (const Dexel& r : rays_[d]) n += r.empty() ? 0 : 1;
  return n;
}

double TriDexel::volume(int d) const {
  double len = 0.0;
  for (const Dexel& r : rays_[d])
    for (const Interval& iv : r) len += double(iv.hi) - double(iv.lo);
  return len * lat_.h * lat_.h;
}

double TriDexel::volume() const { return (volume(0) + volume(1) + volume(2)) / 3.0; }

TriDexel coarsened(const TriDexel& fine, int k) {
  if (k < 1) throw std::invalid_argument("coarsened: the factor must be at least 1");
  const Lattice& f = fine.lattice();
  Lattice c = f;
  c.h = f.h * k;
  for (int a = 0; a < 3; ++a) c.n[a] = (f.n[a] - 1) / k + 2;
  TriDexel out(c);
  tbb::parallel_for(0, 3, [&](int d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    for (int iv = 0; iv < c.n[v] && iv * k < f.n[v]; ++iv)
      for (int iu = 0; iu < c.n[u] && iu * k < f.n[u]; ++iu) {
        const Dexel& r = fine.ray(d, iu * k, iv * k);
        out.ray(d, iu, iv).assign(r.data(), r.size());
      }
  });
  return out;
}

size_t TriDexel::memory_bytes() const {
  size_t b = 0;
  for (int d = 0; d < 3; ++d) {
    b += rays_[d].capacity() * sizeof(Dexel);
    for (const Dexel& r : rays_[d]) b += r.heap_bytes();
  }
  return b;
}

double subtract_intervals(const Interval* a, size_t na, const Interval* b, size_t nb, std::vector<Interval>& out,
                          std::vector<Interval>* removed) {
  out.clear();
  double gone = 0.0;
  // A removed stretch, joined to the last one of this call where they touch (a sliver dropped next to a cut).
  const size_t first = removed ? removed->size() : 0;
  auto lose = [&](float lo, float hi) {
    gone += double(hi) - double(lo);
    if (!removed) return;
    if (removed->size() > first && removed->back().hi == lo) removed->back().hi = hi;
    else removed->push_back({lo, hi});
  };
  size_t j = 0;
  for (size_t i = 0; i < na; ++i) {
    float lo = a[i].lo;
    const float hi = a[i].hi;
    while (j < nb && b[j].hi <= lo) ++j;
    size_t k = j;
    while (lo < hi) {
      if (k >= nb || b[k].lo >= hi) {
        if (hi - lo > kMinInterval) out.push_back({lo, hi}); else lose(lo, hi);
        break;
      }
      if (b[k].lo > lo) {
        if (b[k].lo - lo > kMinInterval) out.push_back({lo, b[k].lo}); else lose(lo, b[k].lo);
      }
      const float cut_lo = std::max(lo, b[k].lo), cut_hi = std::min(hi, b[k].hi);
      if (cut_hi > cut_lo) lose(cut_lo, cut_hi);
      lo = b[k].hi;
      if (b[k].hi <= hi) ++k;
      else break;
    }
  }
  return gone;
}

double overlap_length(const Interval* a, size_t na, const Interval* b, size_t nb, double* longest) {
  double total = 0.0, best = 0.0;
  size_t i = 0, j = 0;
  while (i < na && j < nb) {
    const double lo = std::max(a[i].lo, b[j].lo), hi = std::min(a[i].hi, b[j].hi);
    if (hi > lo) {
      total += hi - lo;
      best = std::max(best, hi - lo);
    }
    if (a[i].hi < b[j].hi) ++i; else ++j;
  }
  if (longest) *longest = best;
  return total;
}

namespace {

// Material intervals from the sorted crossings of a closed, outward-oriented surface: a winding count;
// parity when the winding does not return to zero (a defective mesh or a ray through a crack).
void intervals_from_hits(const RayHit* hits, int n, std::vector<Interval>& out) {
  out.clear();
  int w = 0;
  double start = 0.0;
  bool ok = true;
  for (const RayHit& h : std::span(hits, size_t(n))) {
    const int before = w;
    w += h.cos < 0 ? 1 : -1;
    if (w < 0) { ok = false; break; }
    if (before == 0 && w == 1) start = h.t;
    if (before == 1 && w == 0 && h.t - start > kMinInterval) out.push_back({float(start), float(h.t)});
  }
  if (ok && w == 0) return;
  out.clear();
  for (int i = 0; i + 1 < n; i += 2)
    if (hits[i + 1].t - hits[i].t > kMinInterval) out.push_back({float(hits[i].t), float(hits[i + 1].t)});
}

}  // namespace

TriDexel dexels_from_mesh(const Mesh& mesh, const Lattice& lattice) {
  if (mesh.n_faces() == 0) throw InputError("", 0, "stock", "the stock mesh has no triangles");
  if (!is_closed(mesh)) throw InputError("", 0, "stock", "the stock mesh is not closed (it must bound a solid)");
  Mesh oriented = mesh;
  if (signed_volume(oriented) < 0) {
    // Inward-facing faces: flip them so the winding counts material as inside.
    TriangleArrays a = to_arrays(oriented);
    a.F.col(1).swap(a.F.col(2));
    oriented = mesh_from_arrays(a.V, a.F);
  }
  TriDexel td(lattice);
  for (int d = 0; d < 3; ++d)
    scan_mesh_rays(oriented, lattice, d, [&](int iu, int iv, const RayHit* hits, int n) {
      thread_local std::vector<Interval> pieces;
      intervals_from_hits(hits, n, pieces);
      td.ray(d, iu, iv).assign(pieces.data(), static_cast<uint32_t>(pieces.size()));
    });
  return td;
}

TriDexel make_stock(const Stock& stock, const Lattice& lattice) {
  if (stock.kind == Stock::Kind::Mesh) return dexels_from_mesh(stock.mesh, lattice);
  if (stock.kind == Stock::Kind::Cylinder && stock.cylinder.axis.normalized().cwiseAbs().maxCoeff() < 1.0 - 1e-12)
    return dexels_from_mesh(stock_to_mesh(stock, 512), lattice);  // oblique cylinder: via a fine mesh
  TriDexel td(lattice);
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    for (int iv = 0; iv < lattice.n[v]; ++iv)
      for (int iu = 0; iu < lattice.n[u]; ++iu) {
        const double cu = lattice.coord(u, iu), cv = lattice.coord(v, iv);
        double lo = 0, hi = 0;
        if (stock.kind == Stock::Kind::Box) {
          const auto& b = stock.box;
          if (cu < b.min[u] || cu > b.max[u] || cv < b.min[v] || cv > b.max[v]) continue;
          lo = b.min[d];
          hi = b.max[d];
        } else {
          // Axis-aligned cylinder: exact circle/segment intersections.
          const auto& c = stock.cylinder;
          const Eigen::Vector3d a = c.axis.normalized();
          int ax = 0;
          a.cwiseAbs().maxCoeff(&ax);
          const double base = c.base[ax], top = c.base[ax] + c.height * a[ax];
          const double amin = std::min(base, top), amax = std::max(base, top);
          if (d == ax) {
            Eigen::Vector3d q = c.base;
            q[u] = cu;
            q[v] = cv;
            if ((q - c.base).squaredNorm() > c.radius * c.radius) continue;
            lo = amin;
            hi = amax;
          } else {
            // Ray along d at (cu, cv): one of u, v is the axis coordinate.
            const double axis_coord = u == ax ? cu : cv;
            const int other = u == ax ? v : u;
            const double oc = u == ax ? cv : cu;
            if (axis_coord < amin || axis_coord > amax) continue;
            const double dd = oc - c.base[other];
            const double s = c.radius * c.radius - dd * dd;
            if (s <= 0) continue;
            lo = c.base[d] - std::sqrt(s);
            hi = c.base[d] + std::sqrt(s);
          }
        }
        const Interval piece{float(lo - lattice.origin[d]), float(hi - lattice.origin[d])};
        if (piece.hi - piece.lo > kMinInterval) td.ray(d, iu, iv).assign(&piece, 1);
      }
  }
  return td;
}

}  // namespace tf
