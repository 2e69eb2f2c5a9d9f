// Stock mesh from the tri-dexel: dual contouring on the lattice (surface nets). Node occupancy comes from
// the z rays; every lattice edge whose two nodes differ is crossed by the surface at the dexel end lying on
// that edge (its exact position, from the ray along the edge); each cell with such edges gets one vertex
// from its crossings, and each crossed edge one quad joining the four cells around it. The result is
// closed by construction (the lattice has empty padding nodes on every side). Processed one z layer of
// cells at a time, so memory stays proportional to a layer plus the output.
// GCC 12 reports -Wmaybe-uninitialized inside OpenMesh's colour property code (a value-initialised
// colour vector) when request_vertex_colors() is inlined here; it is a false positive in a system header.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <functional>
#include <memory>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "raycast.hpp"
#include "stock_surface.hpp"
#include "tiltfield/core/internal/quiet_openmesh.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

using stock_mesh::LocalFit;
using stock_mesh::Surface;

// The coordinate (relative to the lattice origin) where ray r has an interval end within [a, b].
float crossing(const Dexel& r, float a, float b) {
  for (const Interval& iv : r) {
    if (iv.lo >= a && iv.lo <= b) return iv.lo;
    if (iv.hi >= a && iv.hi <= b) return iv.hi;
  }
  return 0.5f * (a + b);  // occupancy and ray disagree (a sub-cell feature): the edge midpoint
}

// A cell without a vertex.
constexpr int kNone = std::numeric_limits<int>::min();

// Whether a[0..8) and b[0..8) hold the same bytes.
inline bool same8(const uint8_t* a, const uint8_t* b) {
  uint64_t x, y;
  std::memcpy(&x, a, 8);
  std::memcpy(&y, b, 8);
  return x == y;
}

struct Builder {
  const TriDexel& td;
  const Lattice& L;
  int nx, ny, nz;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;
  std::vector<Eigen::Vector3d> points;   // the exact crossings of every vertex's cell
  std::vector<uint32_t> point_start{0};  // vertex v owns points[point_start[v], point_start[v + 1])
  std::vector<uint8_t> occ0, occ1;   // node layers k and k+1
  std::vector<int> cells_prev, cells_cur;  // vertex ids of cell layers k-1 and k (kNone: none)
  std::vector<uint8_t> column;             // per node column of the cell layer: occ0 | occ1 << 1

  explicit Builder(const TriDexel& t) : td(t), L(t.lattice()), nx(L.n[0]), ny(L.n[1]), nz(L.n[2]) {}

  // The layer of the nodes at t_k = k h: an interval end e changes a ray's occupancy at the first layer
  // with t_k >= e (inside is lo <= t < hi), in the same float arithmetic as fill_layer's.
  float layer_t(int k) const { return float(k * L.h); }
  int first_layer_at(float e) const {
    int k = static_cast<int>(std::clamp(std::ceil(double(e) / L.h), 0.0, double(nz)));
    while (k > 0 && layer_t(k - 1) >= e) --k;
    while (k < nz && layer_t(k) < e) ++k;
    return k;
  }

  // Per node layer k in (k_first, k_last]: the z rays (row-major index) whose occupancy differs from
  // layer k - 1's, one entry an interval end between them (an even count changes nothing), in
  // flips[flip_start[k - k_first - 1], flip_start[k - k_first]).
  std::vector<uint32_t> flips, flip_start;
  void find_flips(int k_first, int k_last) {
    const int n = k_last - k_first;
    flip_start.assign(size_t(n) + 1, 0);
    auto each_end = [&](auto&& f) {
      const float t0 = layer_t(k_first), t1 = layer_t(k_last);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const Dexel& r = td.ray(2, i, j);
          for (const Interval& iv : r) {
            if (iv.hi <= t0) continue;
            if (iv.lo > t1) break;
            for (const float e : {iv.lo, iv.hi})
              if (e > t0 && e <= t1) f(first_layer_at(e) - k_first - 1, uint32_t(size_t(j) * nx + i));
          }
        }
    };
    each_end([&](int b, uint32_t) { ++flip_start[size_t(b) + 1]; });
    for (int b = 0; b < n; ++b) flip_start[size_t(b) + 1] += flip_start[size_t(b)];
    flips.resize(flip_start[size_t(n)]);
    std::vector<uint32_t> next(flip_start.begin(), flip_start.end() - 1);
    each_end([&](int b, uint32_t ray) { flips[next[size_t(b)]++] = ray; });
  }
  // Layer k's occupancy into occ: layer k - 1's (below) with its flips (find_flips from k_first).
  void next_layer(std::vector<uint8_t>& occ, const std::vector<uint8_t>& below, int k, int k_first) {
    occ = below;
    const size_t b = size_t(k - k_first - 1);
    for (uint32_t f = flip_start[b]; f < flip_start[b + 1]; ++f) occ[flips[f]] ^= 1;
  }

  // Node occupancy of layer k from the z rays (a chunk's first layer; next_layer makes the others).
  void fill_layer(std::vector<uint8_t>& occ, int k) {
    occ.assign(size_t(nx) * ny, 0);
    const float t = layer_t(k);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        for (const Interval& iv : td.ray(2, i, j)) {
          if (iv.lo > t) break;
          if (t < iv.hi) {  // inside: lo <= t < hi
            occ[size_t(j) * nx + i] = 1;
            break;
          }
        }
      }
  }

  // Exact crossing points on the edges of cell (i, j, k); corners from the two occupancy layers.
  bool cell_vertex(int i, int j, int k, Eigen::Vector3d& out) {
    auto o = [&](int di, int dj, int dk) {
      return (dk ? occ1 : occ0)[size_t(j + dj) * nx + (i + di)] != 0;
    };
    // Most cells lie wholly inside or outside: all eight corners alike, no crossing.
    const bool c0 = o(0, 0, 0);
    if (o(1, 0, 0) == c0 && o(0, 1, 0) == c0 && o(1, 1, 0) == c0 && o(0, 0, 1) == c0 && o(1, 0, 1) == c0 &&
        o(0, 1, 1) == c0 && o(1, 1, 1) == c0)
      return false;
    const float h = float(L.h);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        // x edges at (j + a, k + b)
        if (o(0, a, b) != o(1, a, b)) {
          const float x = crossing(td.ray(0, j + a, k + b), i * h, (i + 1) * h);
          sum += Eigen::Vector3d(x, (j + a) * L.h, (k + b) * L.h);
          points.push_back(L.origin + Eigen::Vector3d(x, (j + a) * L.h, (k + b) * L.h));
          ++n;
        }
        // y edges at (x = i + a, z = k + b): grid 1 has u = z, v = x
        if (o(a, 0, b) != o(a, 1, b)) {
          const float y = crossing(td.ray(1, k + b, i + a), j * h, (j + 1) * h);
          sum += Eigen::Vector3d((i + a) * L.h, y, (k + b) * L.h);
          points.push_back(L.origin + Eigen::Vector3d((i + a) * L.h, y, (k + b) * L.h));
          ++n;
        }
        // z edges at (i + a, j + b)
        if (o(a, b, 0) != o(a, b, 1)) {
          const float z = crossing(td.ray(2, i + a, j + b), k * h, (k + 1) * h);
          sum += Eigen::Vector3d((i + a) * L.h, (j + b) * L.h, z);
          points.push_back(L.origin + Eigen::Vector3d((i + a) * L.h, (j + b) * L.h, z));
          ++n;
        }
      }
    if (n == 0) return false;
    out = L.origin + sum / n;
    return true;
  }

  void quad(int a, int b, int c, int d, bool flip) {
    // kNone cannot happen inside the padded lattice.
    if (a == kNone || b == kNone || c == kNone || d == kNone) return;
    if (flip) std::swap(b, d);
    faces.emplace_back(a, b, c);
    faces.emplace_back(a, c, d);
  }

  // The vertices of cell layer k into cells_cur (their ids), from node layers occ0 (k) and occ1 (k + 1).
  void cell_layer(int k) {
    const size_t layer = size_t(nx) * ny;
    cells_cur.assign(layer, kNone);
    // Per node column of this cell layer: 0 (both nodes out), 3 (both in), else mixed.
    column.resize(layer);
    for (size_t c = 0; c < layer; ++c) column[c] = static_cast<uint8_t>(occ0[c] | (occ1[c] << 1));
    for (int j = 0; j + 1 < ny; ++j) {
      const uint8_t *r0 = &column[size_t(j) * nx], *r1 = r0 + nx;
      for (int i = 0; i + 1 < nx;) {
        // Eight cells at once where their nine columns on both rows are alike and not mixed (most of the
        // lattice is wholly in or out): a, b, c, d equal means r0[i..i+8] and r1[i..i+8] all one value.
        if (i + 9 <= nx) {
          uint64_t a, b, c, d;
          std::memcpy(&a, r0 + i, 8);
          std::memcpy(&b, r0 + i + 1, 8);
          std::memcpy(&c, r1 + i, 8);
          std::memcpy(&d, r1 + i + 1, 8);
          if (a == b && c == d && a == c && (a == 0 || a == 0x0303030303030303ull)) {
            i += 8;
            continue;
          }
        }
        Eigen::Vector3d p;
        if (cell_vertex(i, j, k, p)) {
          cells_cur[size_t(j) * nx + i] = static_cast<int>(vertices.size());
          vertices.push_back(p);
          point_start.push_back(static_cast<uint32_t>(points.size()));
        }
        ++i;
      }
    }
  }

  // Cell layers k0..k1-1 (node layers k0..k1): their vertices, the quads of the z edges through them and of
  // the x and y edges on node layers k0..k1-1. A chunk that starts above the first layer makes cell layer
  // k0 - 1 again for those quads, and numbers its vertices -m..-1: they are the previous chunk's last m
  // (the same cells in the same order), so that vertex id + the chunk's first id is the global id for all.
  void run(int k0, int k1, const std::function<void()>& layer_done) {
    const size_t layer = size_t(nx) * ny;
    cells_prev.assign(layer, kNone);
    // Only the first layer is read from the rays; each next one is the one below with its flips.
    const int k_first = std::max(k0 - 1, 0);
    find_flips(k_first, k1);
    if (k0 > 0) {
      fill_layer(occ0, k0 - 1);
      next_layer(occ1, occ0, k0, k_first);
      cell_layer(k0 - 1);
      const int m = static_cast<int>(vertices.size());
      for (int& id : cells_cur)
        if (id != kNone) id -= m;
      std::swap(cells_prev, cells_cur);
      vertices.clear();
      points.clear();
      point_start.assign(1, 0);
      std::swap(occ0, occ1);  // layer k0, made above
    } else {
      fill_layer(occ0, k0);
    }
    for (int k = k0; k < k1; ++k) {
      next_layer(occ1, occ0, k + 1, k_first);
      cell_layer(k);
      layer_quads(k);
      std::swap(cells_prev, cells_cur);
      std::swap(occ0, occ1);
      layer_done();
    }
  }

  // The quads of the z edges through cell layer k and of the x and y edges on node layer k (k >= 1).
  void layer_quads(int k) {
    auto cell = [&](const std::vector<int>& layer_ids, int i, int j) {
      if (i < 0 || j < 0 || i + 1 >= nx || j + 1 >= ny) return kNone;
      return layer_ids[size_t(j) * nx + i];
    };
    // Each edge loop skips eight nodes at once where none of their edges is crossed (most of the lattice).
    // z edges (i, j, k)-(i, j, k+1): cells (i-1..i, j-1..j) of layer k. Material below: normal +z.
    for (int j = 1; j + 1 < ny; ++j)
      for (int i = 1; i + 1 < nx; ++i) {
        const size_t at = size_t(j) * nx + i;
        if (i + 9 <= nx && same8(&occ0[at], &occ1[at])) {
          i += 7;
          continue;
        }
        const bool lo = occ0[at], hi = occ1[at];
        if (lo == hi) continue;
        quad(cell(cells_cur, i - 1, j - 1), cell(cells_cur, i, j - 1), cell(cells_cur, i, j), cell(cells_cur, i - 1, j), !lo);
      }
    // x and y edges on node layer k (k >= 1): cells of layers k-1 and k.
    if (k >= 1) {
      for (int j = 1; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
          // x edge (i, j, k)-(i+1, j, k): cells (i, j-1..j, k-1..k). Material at i: normal +x.
          const size_t at = size_t(j) * nx + i;
          if (i + 9 <= nx && same8(&occ0[at], &occ0[at + 1])) {
            i += 7;
            continue;
          }
          const bool lo = occ0[at], hi = occ0[at + 1];
          if (lo == hi) continue;
          quad(cell(cells_prev, i, j - 1), cell(cells_prev, i, j), cell(cells_cur, i, j), cell(cells_cur, i, j - 1), !lo);
        }
      for (int j = 0; j + 1 < ny; ++j)
        for (int i = 1; i + 1 < nx; ++i) {
          // y edge (i, j, k)-(i, j+1, k): cells (i-1..i, j, k-1..k). Material at j: normal +y.
          const size_t at = size_t(j) * nx + i;
          if (i + 9 <= nx && same8(&occ0[at], &occ0[at + nx])) {
            i += 7;
            continue;
          }
          const bool lo = occ0[at], hi = occ0[at + nx];
          if (lo == hi) continue;
          quad(cell(cells_prev, i - 1, j), cell(cells_cur, i - 1, j), cell(cells_cur, i, j), cell(cells_prev, i, j), !lo);
        }
    }
  }

  void release_layers() {
    for (auto* v : {&occ0, &occ1, &column}) std::vector<uint8_t>().swap(*v);
    for (auto* v : {&cells_prev, &cells_cur}) std::vector<int>().swap(*v);
    for (auto* v : {&flips, &flip_start}) std::vector<uint32_t>().swap(*v);
  }
};

// The surface nets of the whole lattice: chunks of cell layers built on the threads, then joined in
// order (the same vertices and faces, in the same order, as one pass over the layers).
Surface build_surface(const TriDexel& td, const Progress& progress) {
  const Lattice& L = td.lattice();
  const int layers = L.n[2] - 1;
  // A few chunks a thread, for balance (the material is not spread evenly over the layers), each at
  // least 16 layers (a chunk makes its first layer's lower neighbour again).
  const int threads = tbb::this_task_arena::max_concurrency();
  const int chunks = std::clamp(layers / 16, 1, 4 * threads);
  std::vector<std::unique_ptr<Builder>> parts(size_t(std::max(chunks, 0)));
  std::mutex report_mutex;
  int done = 0;
  auto layer_done = [&] {
    const std::lock_guard<std::mutex> lock(report_mutex);
    // The layers are most of the time; the fits and colours after them the rest.
    if (++done % 32 == 0) report(progress, "mesh", 0.7 * done / std::max(layers, 1));
  };
  tbb::parallel_for(0, chunks, [&](int c) {
    auto b = std::make_unique<Builder>(td);
    b->run(int(int64_t(layers) * c / chunks), int(int64_t(layers) * (c + 1) / chunks), layer_done);
    b->release_layers();  // a layer's buffers per chunk would add up over the chunks waiting to be joined
    parts[size_t(c)] = std::move(b);
  });
  Surface out;
  out.h = L.h;
  size_t nv = 0, nf = 0, np = 0;
  for (const auto& b : parts) nv += b->vertices.size(), nf += b->faces.size(), np += b->points.size();
  out.vertices.reserve(nv), out.faces.reserve(nf), out.points.reserve(np), out.point_start.reserve(nv + 1);
  for (auto& b : parts) {
    const int base = static_cast<int>(out.vertices.size());
    const auto first_point = static_cast<uint32_t>(out.points.size());
    for (const Eigen::Vector3i& f : b->faces) out.faces.push_back(f + Eigen::Vector3i::Constant(base));
    out.vertices.insert(out.vertices.end(), b->vertices.begin(), b->vertices.end());
    out.points.insert(out.points.end(), b->points.begin(), b->points.end());
    for (size_t v = 0; v < b->vertices.size(); ++v) out.point_start.push_back(first_point + b->point_start[v]);
    b.reset();  // its layers' buffers go as it is copied
  }
  out.point_start.push_back(static_cast<uint32_t>(out.points.size()));
  return out;
}

// The mesh of vertices V and faces F into `mesh` (empty; filled in place, as Mesh has no move:
// mesh.hpp); `copies` receives, for each vertex added beyond V, the vertex of V it copies.
void to_mesh(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F, Mesh& mesh,
             std::vector<int>& copies) {
  // A closed surface has about three edges for every two faces; reserving spares the growing arrays'
  // copies (millions of elements on a fine lattice).
  mesh.reserve(V.size(), F.size() * 3 / 2 + 16, F.size());
  std::vector<Mesh::VertexHandle> vh(V.size());
  for (size_t i = 0; i < V.size(); ++i) vh[i] = mesh.add_vertex(to_om(V[i]));
  const internal::QuietOpenMesh quiet;  // OpenMesh reports each non-manifold face; they are handled below
  for (const auto& f : F) {
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) continue;
    auto fh = mesh.add_face(vh[f[0]], vh[f[1]], vh[f[2]]);
    if (!fh.is_valid()) {
      // A non-manifold spot (two sheets meeting in one cell): keep the face on its own vertex copies so
      // the surface stays closed geometrically.
      std::array<Mesh::VertexHandle, 3> own;
      for (int k = 0; k < 3; ++k) {
        own[size_t(k)] = mesh.add_vertex(to_om(V[f[k]]));
        copies.push_back(f[k]);
      }
      mesh.add_face(own[0], own[1], own[2]);
    }
  }
  mesh.update_face_normals();
}

// The signed distance (mm, positive outside) from each of the points V to the design, on the threads.
std::vector<double> design_deviation(const Mesh& design, const std::vector<Eigen::Vector3d>& V) {
  const RayMesh rm(design);
  std::vector<double> dev(V.size(), 0.0);
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : V) box.extend(p);
  const double far = bounding_box(design).sizes().norm() + box.sizes().norm() + 1.0;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, V.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
    // Neighbouring vertices are mostly next to each other in the mesh's order: the last vertex's distance
    // plus the step between them bounds this one's (the triangle inequality), and a query that starts
    // with that radius skips most of the design's tree. The tree and the query point are in floats: a
    // margin of several of their last bits at the part's coordinates keeps the closest triangle inside.
    Eigen::Vector3d last = Eigen::Vector3d::Zero();
    double last_distance = -1.0;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3d& p = V[i];
      Eigen::Vector3d q, n;
      const double margin = 1e-4 + 1e-6 * p.cwiseAbs().maxCoeff();
      const double bound = last_distance >= 0.0 ? last_distance + (p - last).norm() + margin : far;
      if (!(bound < far && rm.closest(p, bound, q, n)) && !rm.closest(p, far, q, n)) {
        last_distance = -1.0;
        continue;
      }
      const double s = (p - q).dot(n) >= 0 ? 1.0 : -1.0;
      dev[i] = s * (p - q).norm();
      last = p;
      last_distance = (p - q).norm();
    }
  });
  return dev;
}

}  // namespace

Mesh reconstruct_stock(const TriDexel& stock, const Mesh* design, const StockMeshOptions& options) {
  Surface b = build_surface(stock, options.progress);
  if (options.smooth || options.refine > 0) {
    std::vector<LocalFit> fits = stock_mesh::smooth_vertices(b);
    if (!options.smooth)
      for (auto& f : fits) f.valid = false;
    for (int level = 0; level < options.refine; ++level) stock_mesh::refine(b.vertices, b.faces, fits);
  }
  report(options.progress, "mesh", 0.8);
  const bool colour = design && design->n_faces() > 0 && options.colour_by_deviation && !b.vertices.empty();
  Mesh mesh;
  std::vector<int> copies;
  std::vector<double> dev;
  // OpenMesh builds the mesh on one thread; the deviations need only the vertices' places, and are
  // measured on the others meanwhile.
  tbb::parallel_invoke([&] { to_mesh(b.vertices, b.faces, mesh, copies); },
                       [&] {
                         if (colour) dev = design_deviation(*design, b.vertices);
                       });
  if (colour) {
    for (const int k : copies) dev.push_back(dev[size_t(k)]);
    double largest = 0.0;
    for (const double x : dev) largest = std::max(largest, std::abs(x));
    const double range = options.colour_range_mm > 0 ? options.colour_range_mm : std::max(0.05, largest);
    set_vertex_deviation(mesh, dev);
    mesh.request_vertex_colors();
    for (auto v : mesh.vertices()) {
      const double t = std::clamp(dev[v.idx()] / range, -1.0, 1.0);
      // green at 0, red for material left (t > 0), blue for over-cut (t < 0)
      const auto c = [&](double x) { return static_cast<unsigned char>(std::lround(255.0 * std::clamp(x, 0.0, 1.0))); };
      mesh.set_color(v, Mesh::Color(c(t), c(1.0 - std::abs(t)), c(-t)));
    }
  }
  report(options.progress, "mesh", 1.0);
  return mesh;
}

}  // namespace tf
