// Decimation within a distance bound (see mesh_simplify.hpp): OpenMesh's decimater modules driven by a
// lazy selection loop, over slabs of the mesh in parallel.
#include "tiltfield/core/mesh_simplify.hpp"
#include "tiltfield/core/internal/quiet_openmesh.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
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
using Hausdorff = dec::ModHausdorffT<Mesh>;
using NormalFlipping = dec::ModNormalFlippingT<Mesh>;
using AspectRatio = dec::ModAspectRatioT<Mesh>;

// A binary decimater module for the direction ModHausdorffT leaves open (the output's faces near the
// input surface: without it a face bridging a crease can stand 7 times the bound off it while every input
// vertex is near some other face): a collapse is legal only when sample points of every face it moves (a
// grid of quarters over the face and its two moved edges) lie within `bound` of the input's triangles.
// Between samples the distance can grow (it is 1-Lipschitz, and the samples are up to a quarter face
// apart), so the samples are held to kSampleMargin times the bound. On LinuxCNC's impeller demo at 0.1 mm
// and a bound of 0.01 mm, 66 points a face against the input measured 0.0097 mm at most with 0.5 (0.0108
// with 0.6, 0.07 without the module); tests/integration/test_verify_html.cpp checks 28 points a face.
constexpr double kSampleMargin = 0.5;
class ModSurfaceDistance : public dec::ModBaseT<Mesh> {
 public:
  using Handle = dec::ModHandleT<ModSurfaceDistance>;
  explicit ModSurfaceDistance(Mesh& mesh) : dec::ModBaseT<Mesh>(mesh, true) {}
  const std::string& name() const override {
    static const std::string n = "SurfaceDistance";
    return n;
  }
  // The input as a tree of its triangles and as a mesh (whose faces are walked), and per vertex of the
  // mesh decimated the input vertex it is.
  void set_surface(const TriangleBvh* surface, const Mesh* input, OpenMesh::VPropHandleT<int> source, double bound) {
    surface_ = surface;
    input_ = input;
    source_ = source;
    bound2_ = bound * bound;
  }
  float collapse_priority(const CollapseInfo& ci) override {
    Mesh& m = mesh();
    // The walk starts on the input at the vertex the moved faces meet at.
    walk_face_ = Mesh::FaceHandle();
    for (auto f : input_->vf_range(Mesh::VertexHandle(m.property(source_, ci.v1)))) {
      walk_face_ = f;
      break;
    }
    // A moved edge (v0 to a neighbour w) is shared by two moved faces: its samples are tested once. They
    // come out the same from either face (the third corner's weight is zero), so the verdict is too.
    edges_done_.clear();
    auto edge_done = [&](Mesh::VertexHandle w) {
      if (std::find(edges_done_.begin(), edges_done_.end(), w) != edges_done_.end()) return true;
      edges_done_.push_back(w);
      return false;
    };
    for (auto f : m.vf_range(ci.v0)) {
      if (f == ci.fl || f == ci.fr) continue;
      // The face after the collapse: v0 moved onto v1; corner `moved` is the moved one.
      std::array<Eigen::Vector3d, 3> p;
      std::array<Mesh::VertexHandle, 3> fv;
      int k = 0, moved = 0;
      for (auto v : m.fv_range(f)) {
        if (v == ci.v0) moved = k;
        fv[size_t(k)] = v;
        p[size_t(k++)] = to_eigen(v == ci.v0 ? ci.p1 : m.point(v));
      }
      const Eigen::Vector3d& a = p[size_t(moved)];
      const Eigen::Vector3d& b = p[size_t((moved + 1) % 3)];
      const Eigen::Vector3d& c = p[size_t((moved + 2) % 3)];
      // A barycentric grid of quarters with the moved corner's weight 1..3 quarters: the face's interior
      // and its two moved edges (a-b: c's weight 0; a-c: b's weight 0; the third edge did not move).
      const bool ab = !edge_done(fv[size_t((moved + 1) % 3)]), ac = !edge_done(fv[size_t((moved + 2) % 3)]);
      // Nearest the meeting vertex first, so that the walk goes out step by step.
      for (int i = 3; i >= 1; --i)
        for (int j = 0; i + j <= 4; ++j) {
          if ((j == 0 && !ac) || (i + j == 4 && !ab)) continue;
          if (!near((i * a + j * b + (4 - i - j) * c) / 4.0)) return ILLEGAL_COLLAPSE;
        }
    }
    return LEGAL_COLLAPSE;
  }

 private:
  bool near(const Eigen::Vector3d& q) {
    const auto& tris = surface_->triangles();
    const double limit = bound2_ * (1.0 + 1e-9);
    auto d2 = [&](int i) { return (closest_point_on_triangle(q, tris[size_t(i)]) - q).squaredNorm(); };
    // Consecutive samples lie close together: the triangle that answered the last one often answers this,
    // or one a few steps from the face the walk reached.
    if (hint_ >= 0 && d2(hint_) < limit) return true;
    if (walk(q, limit)) return true;
    // A yes/no query: the search stops at the first triangle within the bound (the minimum stays at
    // `limit` when there is none).
    const double found = surface_->minimum(
        [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { return box_distance_squared(q, lo, hi); },
        [&](int i, double) {
          const double d = d2(i);
          if (d < limit) hint_ = i;
          return d;
        },
        limit, limit);
    return found < limit;
  }
  // A greedy walk over the input's faces from walk_face_ toward q: each step moves to the neighbouring face
  // nearest q while that comes nearer. True only when it reaches a face within `limit` (squared), which is
  // then where the next walk starts; a walk that stalls (a crease, a gap) proves nothing.
  bool walk(const Eigen::Vector3d& q, double limit) {
    if (!walk_face_.is_valid()) return false;
    auto d2 = [&](Mesh::FaceHandle f) {
      Triangle t;
      auto v = input_->cfv_begin(f);
      t.a = to_eigen(input_->point(*v++));
      t.b = to_eigen(input_->point(*v++));
      t.c = to_eigen(input_->point(*v));
      return (closest_point_on_triangle(q, t) - q).squaredNorm();
    };
    Mesh::FaceHandle f = walk_face_;
    double best = d2(f);
    for (int step = 0; best >= limit && step < kWalkSteps; ++step) {
      Mesh::FaceHandle next;
      for (auto g : input_->ff_range(f)) {
        const double d = d2(g);
        if (d < best) best = d, next = g;
      }
      if (!next.is_valid()) return false;
      f = next;
    }
    if (best >= limit) return false;
    walk_face_ = f;
    return true;
  }
  static constexpr int kWalkSteps = 8;
  const TriangleBvh* surface_ = nullptr;
  const Mesh* input_ = nullptr;
  OpenMesh::VPropHandleT<int> source_;
  Mesh::FaceHandle walk_face_;
  double bound2_ = 0.0;
  int hint_ = -1;
  std::vector<Mesh::VertexHandle> edges_done_;  // the moved edges tested in this collapse, by their far end
};

// OpenMesh's decimater framework (modules, legality tests, collapse bookkeeping) with a lazy selection:
// vertices wait in a heap keyed by their cheapest collapse by the quadric alone, and the binary modules
// (the Hausdorff bound above all) are asked only when a vertex comes to the top.
class LazyDecimater : public dec::BaseDecimaterT<Mesh> {
 public:
  using dec::BaseDecimaterT<Mesh>::BaseDecimaterT;

  // Collapses while any legal collapse is left; `tick(fraction)` every few thousand heap entries.
  void run(Quadric& quadric, const std::function<void(double)>& tick) {
    Mesh& m = mesh();
    stamp_.assign(m.n_vertices(), 0);
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
      candidates.clear();
      for (auto h : m.voh_range(v)) {
        const CollapseInfo ci(m, h);
        float error, length2;
        if (is_collapse_legal(ci) && cheap(quadric, ci, error, length2)) candidates.push_back({error, length2, h});
      }
      std::sort(candidates.begin(), candidates.end());
      Mesh::HalfedgeHandle chosen;
      for (const Candidate& c : candidates)
        if (collapse_priority(CollapseInfo(m, c.h)) >= 0.0f) {
          chosen = c.h;
          break;
        }
      if (!chosen.is_valid()) continue;  // back in the heap when a neighbour changes
      CollapseInfo ci(m, chosen);
      preprocess_collapse(ci);
      m.collapse(chosen);
      for (auto f : m.vf_range(ci.v1)) m.set_normal(f, m.calc_face_normal(f));
      postprocess_collapse(ci);
      ring.assign(m.vv_begin(ci.v1), m.vv_end(ci.v1));
      ring.push_back(ci.v1);
      for (auto w : ring) push(quadric, w);
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
    bool operator<(const Candidate& o) const { return std::tie(error, length2) < std::tie(o.error, o.length2); }
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

  // (Re-)queues v with its cheapest collapse by the quadric, legal or not: the topology test is left to
  // the pop (it is the costliest test but the Hausdorff one, and most keys go stale before their turn).
  // An older entry of v is then stale.
  void push(Quadric& quadric, Mesh::VertexHandle v) {
    Mesh& m = mesh();
    if (m.status(v).deleted()) return;
    uint32_t& s = stamp_[size_t(v.idx())];
    ++s;
    Entry best{0.0f, 0.0f, v.idx(), s};
    bool found = false;
    for (auto h : m.voh_range(v)) {
      float error, length2;
      if (!cheap(quadric, CollapseInfo(m, h), error, length2)) continue;
      if (!found || std::tie(error, length2) < std::tie(best.error, best.length2)) {
        best.error = error;
        best.length2 = length2;
        found = true;
      }
    }
    if (found) heap_.push(best);
  }

  std::vector<uint32_t> stamp_;
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

void decimate_slab(Slab& slab, const Mesh& in, const TriangleBvh& surface, const BoundedDecimateOptions& o,
                   const std::function<void(double)>& tick) {
  LazyDecimater d(slab.mesh);
  Quadric::Handle quadric;
  NormalFlipping::Handle flipping;
  AspectRatio::Handle aspect;
  Hausdorff::Handle hausdorff;
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
  d.module(hausdorff).set_tolerance(o.max_error_mm);
  d.module(distance).set_surface(&surface, &in, slab.source, kSampleMargin * o.max_error_mm);
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
  const TriangleBvh surface({&in});
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
  return joined;
}

}  // namespace tf
