// Decimation within a distance bound (see mesh_simplify.hpp): OpenMesh's decimater modules driven by a
// lazy selection loop, over slabs of the mesh in parallel.
#include "tiltfield/core/mesh_simplify.hpp"
#include "tiltfield/core/internal/quiet_openmesh.hpp"
#include "tiltfield/core/triangle_bvh.hpp"
#include "decimate_bound.hpp"

#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <queue>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <vector>

namespace tf {
namespace {

namespace dec = OpenMesh::Decimater;
using Quadric = dec::ModQuadricT<Mesh>;
using NormalFlipping = dec::ModNormalFlippingT<Mesh>;
using AspectRatio = dec::ModAspectRatioT<Mesh>;
using internal::InputSurface;
using internal::ModSurfaceDistance;
using internal::ModVertexDistance;

// OpenMesh's decimater framework (modules, legality tests, collapse bookkeeping) with a lazy selection:
// vertices wait in a heap keyed by their cheapest collapse by the quadric alone, and the binary modules
// (the distance bounds above all) are asked only when a vertex comes to the top. A collapse beside a
// queued vertex leaves its entry in place: the key is taken again when the entry comes up (the quadrics
// only grow, so a key mostly gets dearer; one that got cheaper, by the new edge to the vertex kept, waits
// at its old place), which keeps the heap at about one entry a vertex.
class LazyDecimater : public dec::BaseDecimaterT<Mesh> {
 public:
  using dec::BaseDecimaterT<Mesh>::BaseDecimaterT;

  // Collapses while any legal collapse is left; `tick(fraction)` every few thousand heap entries.
  void run(Quadric& quadric, const std::function<void(double)>& tick) {
    Mesh& m = mesh();
    stamp_.assign(m.n_vertices(), 0);
    queued_.assign(m.n_vertices(), 0);
    for (auto v : m.vertices()) push(quadric, v);
    const double initial = double(std::max<size_t>(heap_.size(), 1));
    std::vector<Candidate> candidates;
    std::vector<Mesh::VertexHandle> ring;
    for (size_t pops = 1; !heap_.empty(); ++pops) {
      const Entry e = heap_.top();
      heap_.pop();
      if (pops % 4096 == 0) tick(1.0 - double(heap_.size()) / initial);
      const Mesh::VertexHandle v(e.v);
      if (m.status(v).deleted() || e.stamp != stamp_[size_t(e.v)]) continue;
      queued_[size_t(e.v)] = 0;
      collapses(quadric, v, candidates);
      if (candidates.empty()) continue;
      // The key was taken when v was queued; a collapse beside v since then may have made its cheapest
      // collapse dearer: then v waits for its turn again.
      const Entry now{candidates.front().error, candidates.front().length2, e.v, 0};
      if (!heap_.empty() && now < heap_.top()) {
        enqueue(now);
        continue;
      }
      Mesh::HalfedgeHandle chosen;
      for (const Candidate& c : candidates) {
        const CollapseInfo ci(m, c.h);
        if (is_collapse_legal(ci) && collapse_priority(ci) >= 0.0f) {
          chosen = c.h;
          break;
        }
      }
      if (!chosen.is_valid()) continue;  // queued again when a neighbour changes
      CollapseInfo ci(m, chosen);
      preprocess_collapse(ci);
      m.collapse(chosen);
      for (auto f : m.vf_range(ci.v1)) m.set_normal(f, m.calc_face_normal(f));
      postprocess_collapse(ci);
      ring.assign(m.vv_begin(ci.v1), m.vv_end(ci.v1));
      ring.push_back(ci.v1);
      // A vertex already queued is looked at again when its entry comes up; one that had no collapse
      // left may have one now.
      for (auto w : ring)
        if (!queued_[size_t(w.idx())]) push(quadric, w);
    }
    tick(1.0);
  }

 private:
  struct Entry {
    float error, length2;
    int v;
    uint32_t stamp;
    // std::priority_queue keeps the greatest on top: the greatest is the cheapest collapse.
    bool operator<(const Entry& o) const {
      return std::tie(o.error, o.length2, o.v) < std::tie(error, length2, v);
    }
  };
  struct Candidate {
    float error, length2;
    Mesh::HalfedgeHandle h;
    bool operator<(const Candidate& o) const {
      return std::tuple(error, length2, h.idx()) < std::tuple(o.error, o.length2, o.h.idx());
    }
  };

  // The quadric's error of a collapse and its squared edge length (the tie-break that keeps a flat
  // region's collapses spread out instead of growing one fan); false when the quadric refuses it. Where the
  // true error is zero (a flat region) the quadric's sum rounds to either side of it: a tiny negative
  // value is zero, not a refusal (ILLEGAL_COLLAPSE is -1).
  static bool cheap(Quadric& quadric, const CollapseInfo& ci, float& error, float& length2) {
    error = quadric.collapse_priority(ci);
    length2 = float((ci.p0 - ci.p1).sqrnorm());
    if (error <= float(Quadric::ILLEGAL_COLLAPSE)) return false;
    error = std::max(error, 0.0f);
    return true;
  }

  // v's collapses that the quadric allows, cheapest first; the topology test is left to the collapses
  // tried (it is the costliest test but the distance ones).
  void collapses(Quadric& quadric, Mesh::VertexHandle v, std::vector<Candidate>& out) {
    Mesh& m = mesh();
    out.clear();
    for (auto h : m.voh_range(v)) {
      float error, length2;
      if (cheap(quadric, CollapseInfo(m, h), error, length2)) out.push_back({error, length2, h});
    }
    std::sort(out.begin(), out.end());
  }

  // Queues v with its cheapest collapse by the quadric, legal or not.
  void push(Quadric& quadric, Mesh::VertexHandle v) {
    if (mesh().status(v).deleted()) return;
    collapses(quadric, v, scratch_);
    if (!scratch_.empty()) enqueue({scratch_.front().error, scratch_.front().length2, v.idx(), 0});
  }

  // Queues e for its vertex; an older entry of the vertex is then stale.
  void enqueue(Entry e) {
    e.stamp = ++stamp_[size_t(e.v)];
    queued_[size_t(e.v)] = 1;
    heap_.push(e);
  }

  std::vector<uint32_t> stamp_;
  std::vector<uint8_t> queued_;  // per vertex: it has a live entry in the heap
  std::vector<Candidate> scratch_;
  std::priority_queue<Entry> heap_;
};

// A part of the input: its own mesh, and per vertex the input vertex it copies.
struct Slab {
  Mesh mesh;
  OpenMesh::VPropHandleT<int> source;
};

// Faces of the input into `count` slabs of about equal face count along the longest axis (by centroid).
std::vector<int> slab_of_faces(const Mesh& in, int count) {
  std::vector<int> slab(in.n_faces(), 0);
  if (count <= 1) return slab;
  const Eigen::AlignedBox3d box = bounding_box(in);
  int axis = 0;
  box.sizes().maxCoeff(&axis);
  std::vector<double> key(in.n_faces());
  for (auto f : in.faces()) {
    double c = 0.0;
    for (auto v : in.fv_range(f)) c += in.point(v)[axis];
    key[size_t(f.idx())] = c;
  }
  std::vector<double> sorted = key, cut;
  for (int k = 1; k < count; ++k) {
    auto nth = sorted.begin() + long(sorted.size() * size_t(k) / size_t(count));
    std::nth_element(sorted.begin(), nth, sorted.end());
    cut.push_back(*nth);
  }
  std::sort(cut.begin(), cut.end());
  for (size_t f = 0; f < key.size(); ++f) slab[f] = int(std::upper_bound(cut.begin(), cut.end(), key[f]) - cut.begin());
  return slab;
}

// The faces of slab `s` as a mesh of their own. Vertices that faces of other slabs use are locked, so
// the slabs still meet on them after decimation; a face OpenMesh refuses (the slab would make a vertex
// non-manifold) goes in on locked copies of its vertices.
void build_slab(const Mesh& in, const std::vector<int>& slab_of, const std::vector<uint8_t>& shared, int s, Slab& out) {
  Mesh& m = out.mesh;
  m.add_property(out.source);
  std::vector<int> local(in.n_vertices(), -1);
  auto add = [&](Mesh::VertexHandle v, bool copy) {
    if (!copy && local[size_t(v.idx())] >= 0) return Mesh::VertexHandle(local[size_t(v.idx())]);
    const Mesh::VertexHandle w = m.add_vertex(in.point(v));
    m.property(out.source, w) = v.idx();
    if (shared[size_t(v.idx())] || copy) m.status(w).set_locked(true);
    if (!copy) local[size_t(v.idx())] = w.idx();
    return w;
  };
  for (auto f : in.faces()) {
    if (slab_of[size_t(f.idx())] != s) continue;
    std::array<Mesh::VertexHandle, 3> fv;
    int k = 0;
    for (auto v : in.fv_range(f))
      if (k < 3) fv[size_t(k++)] = v;
    if (k != 3) continue;
    if (m.add_face(add(fv[0], false), add(fv[1], false), add(fv[2], false)).is_valid()) continue;
    m.add_face(add(fv[0], true), add(fv[1], true), add(fv[2], true));
  }
  m.update_face_normals();
}

void decimate_slab(Slab& slab, const Mesh& in, const InputSurface& surface, const BoundedDecimateOptions& o,
                   const std::function<void(double)>& tick) {
  LazyDecimater d(slab.mesh);
  Quadric::Handle quadric;
  NormalFlipping::Handle flipping;
  AspectRatio::Handle aspect;
  ModVertexDistance::Handle hausdorff;
  ModSurfaceDistance::Handle distance;
  // Binary modules are asked in the order added: the cheap guards first, the distance tests last.
  d.add(quadric);
  d.add(flipping);
  d.add(aspect);
  d.add(hausdorff);
  d.add(distance);
  d.module(quadric).unset_max_err();
  d.module(flipping).set_max_normal_deviation(o.max_normal_deviation_deg);
  d.module(aspect).set_aspect_ratio(float(o.max_aspect_ratio));
  d.module(hausdorff).set_bound(o.max_error_mm);
  d.module(distance).set_surface(&surface, &in, slab.source, o.max_error_mm);
  if (!d.initialize()) throw std::logic_error("decimate_within: OpenMesh's decimater did not initialise");
  d.run(d.module(quadric), tick);
  slab.mesh.garbage_collection();
}

// Progress over all slabs: the mean of their fractions, reported when it has grown by half a percent.
class SlabProgress {
 public:
  SlabProgress(const Progress& progress, size_t slabs) : progress_(progress), fraction_(slabs, 0.0) {}
  std::function<void(double)> slab(size_t i) {
    return [this, i](double f) {
      if (!progress_) return;
      const std::lock_guard<std::mutex> lock(mutex_);
      fraction_[i] = std::max(fraction_[i], std::clamp(f, 0.0, 1.0));
      double mean = 0.0;
      for (double x : fraction_) mean += x / double(fraction_.size());
      if (mean >= reported_ + 0.005 || mean >= 1.0) {
        reported_ = mean;
        progress_("decimate", mean);
      }
    };
  }

 private:
  const Progress& progress_;
  std::vector<double> fraction_;
  double reported_ = -1.0;
  std::mutex mutex_;
};

// Runs job(i) for i in [0, count) on up to the machine's threads; the first exception is rethrown.
void parallel_each(size_t count, const std::function<void(size_t)>& job) {
  const size_t threads = std::min<size_t>(count, std::max(1u, std::thread::hardware_concurrency()));
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (size_t i = next++; i < count; i = next++) {
      try {
        job(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// The slabs joined again: a vertex the slabs share (locked, so still there) becomes one vertex.
BoundedDecimation join(const Mesh& in, std::vector<Slab>& slabs) {
  BoundedDecimation out;
  std::vector<int> global(in.n_vertices(), -1);
  auto vertex = [&](int source, bool copy) {
    if (!copy && global[size_t(source)] >= 0) return Mesh::VertexHandle(global[size_t(source)]);
    const Mesh::VertexHandle w = out.mesh.add_vertex(in.point(Mesh::VertexHandle(source)));
    out.source_vertex.push_back(source);
    if (!copy) global[size_t(source)] = w.idx();
    return w;
  };
  const internal::QuietOpenMesh quiet;  // OpenMesh reports each refused face; they are handled below
  for (Slab& s : slabs) {
    for (auto f : s.mesh.faces()) {
      std::array<int, 3> src{};
      int k = 0;
      for (auto v : s.mesh.fv_range(f))
        if (k < 3) src[size_t(k++)] = s.mesh.property(s.source, v);
      if (out.mesh.add_face(vertex(src[0], false), vertex(src[1], false), vertex(src[2], false)).is_valid()) continue;
      out.mesh.add_face(vertex(src[0], true), vertex(src[1], true), vertex(src[2], true));
    }
    s.mesh.clear();  // free each slab once copied
  }
  return out;
}

}  // namespace

BoundedDecimation decimate_within(const Mesh& in, const BoundedDecimateOptions& options) {
  if (!std::isfinite(options.max_error_mm))
    throw std::invalid_argument("decimate_within: the bound must be a finite number of mm");
  BoundedDecimation out;
  out.input_vertices = in.n_vertices();
  out.input_faces = in.n_faces();
  if (!(options.max_error_mm > 0.0) || in.n_faces() == 0) {
    out.mesh = in;
    out.source_vertex.resize(in.n_vertices());
    for (size_t i = 0; i < in.n_vertices(); ++i) out.source_vertex[i] = int(i);
    report(options.progress, "decimate", 1.0);
    return out;
  }
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const int count = options.slabs > 0 ? options.slabs : in.n_faces() > 200000 ? 2 * threads : 1;
  const std::vector<int> slab_of = slab_of_faces(in, count);
  std::vector<uint8_t> shared(in.n_vertices(), 0);
  for (auto v : in.vertices()) {
    int first = -1;
    for (auto f : in.vf_range(v)) {
      const int s = slab_of[size_t(f.idx())];
      if (first >= 0 && s != first) shared[size_t(v.idx())] = 1;
      first = s;
    }
  }
  const InputSurface surface(in);
  std::vector<Slab> slabs(static_cast<size_t>(count));
  SlabProgress progress(options.progress, slabs.size());
  {
    const internal::QuietOpenMesh quiet;  // refused faces are handled in build_slab
    parallel_each(slabs.size(), [&](size_t s) {
      build_slab(in, slab_of, shared, int(s), slabs[s]);
      decimate_slab(slabs[s], in, surface, options, progress.slab(s));
    });
  }
  BoundedDecimation joined = join(in, slabs);
  joined.input_vertices = out.input_vertices;
  joined.input_faces = out.input_faces;
  joined.mesh.update_face_normals();
  if (in.has_vertex_colors()) {
    joined.mesh.request_vertex_colors();
    for (auto v : joined.mesh.vertices())
      joined.mesh.set_color(v, in.color(Mesh::VertexHandle(joined.source_vertex[size_t(v.idx())])));
  }
  // The kept vertices are the input's: so are their deviations from the design, when it has them.
  if (const std::vector<double> dev = vertex_deviation(in); !dev.empty()) {
    std::vector<double> kept(joined.mesh.n_vertices());
    for (size_t v = 0; v < kept.size(); ++v) kept[v] = dev[size_t(joined.source_vertex[v])];
    set_vertex_deviation(joined.mesh, kept);
  }
  return joined;
}

}  // namespace tf
