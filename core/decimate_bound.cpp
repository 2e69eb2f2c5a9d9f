// The decimater modules that hold decimate_within's bound (see decimate_bound.hpp).
#include "decimate_bound.hpp"

#include <algorithm>
#include <limits>

namespace tf::internal {

InputSurface::InputSurface(const Mesh& in) : bvh({&in}) {
  if (bvh.size() != in.n_faces()) return;  // deleted faces (not garbage-collected): no walks, the tree answers
  of_face.resize(bvh.size());
  for (int i = 0; i < int(bvh.size()); ++i) of_face[size_t(bvh.input_index(i))] = i;
  neighbours.assign(bvh.size(), {-1, -1, -1});
  for (int i = 0; i < int(bvh.size()); ++i) {
    const Triangle& t = bvh.triangle(i);
    for (auto g : in.ff_range(Mesh::FaceHandle(bvh.input_index(i)))) {
      // Across the edge opposite the corner of t that g does not share (the same mesh points, exactly).
      const int j = of_face[size_t(g.idx())];
      const Triangle& u = bvh.triangle(j);
      auto shared = [&](const Eigen::Vector3d& p) { return p == u.a || p == u.b || p == u.c; };
      const int k = !shared(t.a) ? 0 : !shared(t.b) ? 1 : !shared(t.c) ? 2 : -1;
      if (k >= 0 && neighbours[size_t(i)][size_t(k)] < 0) neighbours[size_t(i)][size_t(k)] = j;
    }
  }
}

// ---- ModVertexDistance

ModVertexDistance::ModVertexDistance(Mesh& mesh) : OpenMesh::Decimater::ModBaseT<Mesh>(mesh, true) {
  mesh.add_property(carried_);
}

ModVertexDistance::~ModVertexDistance() { mesh().remove_property(carried_); }

const std::string& ModVertexDistance::name() const {
  static const std::string n = "VertexDistance";
  return n;
}

void ModVertexDistance::initialize() {
  for (auto f : mesh().faces()) mesh().property(carried_, f).clear();
}

float ModVertexDistance::collapse_priority(const CollapseInfo& ci) {
  Mesh& m = mesh();
  faces_.clear();
  triangles_.clear();
  for (auto f : m.vf_range(ci.v0)) {
    if (f == ci.fl || f == ci.fr) continue;
    faces_.push_back(f);
    triangles_.push_back(moved_triangle(f, ci));
  }
  if (!within(to_eigen(ci.p0), -1)) return ILLEGAL_COLLAPSE;
  for (auto f : m.vf_range(ci.v0)) {
    const auto own = std::find(faces_.begin(), faces_.end(), f);
    const int first = own == faces_.end() ? -1 : int(own - faces_.begin());
    for (const Eigen::Vector3d& q : m.property(carried_, f))
      if (!within(q, first)) return ILLEGAL_COLLAPSE;
  }
  return LEGAL_COLLAPSE;
}

// The vertices the faces around v1 carried, those of the two removed faces and the removed vertex go each
// to the nearest face around v1.
void ModVertexDistance::postprocess_collapse(const CollapseInfo& ci) {
  Mesh& m = mesh();
  faces_.clear();
  triangles_.clear();
  points_.clear();
  auto take = [&](Mesh::FaceHandle f) {
    auto& carried = m.property(carried_, f);
    points_.insert(points_.end(), carried.begin(), carried.end());
    carried.clear();
  };
  for (auto f : m.vf_range(ci.v1)) {
    faces_.push_back(f);
    triangles_.push_back(moved_triangle(f, ci));  // v0 is gone: the face as it stands
    take(f);
  }
  if (faces_.empty()) return;
  if (ci.fl.is_valid()) take(ci.fl);
  if (ci.fr.is_valid()) take(ci.fr);
  points_.push_back(to_eigen(ci.p0));
  for (const Eigen::Vector3d& q : points_) {
    size_t best = 0;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < triangles_.size(); ++i) {
      const double d2 = (closest_point_on_triangle(q, triangles_[i]) - q).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = i;
    }
    m.property(carried_, faces_[best]).push_back(q);
  }
}

Triangle ModVertexDistance::moved_triangle(Mesh::FaceHandle f, const CollapseInfo& ci) {
  std::array<Eigen::Vector3d, 3> p;
  int k = 0;
  for (auto v : mesh().fv_range(f)) p[size_t(k++)] = to_eigen(v == ci.v0 ? ci.p1 : mesh().point(v));
  return {p[0], p[1], p[2]};
}

// Whether q lies within the bound of a moved face, trying face `first` (-1: none) first.
bool ModVertexDistance::within(const Eigen::Vector3d& q, int first) const {
  const double limit = bound2_ * (1.0 + 1e-9);
  auto near = [&](size_t i) { return (closest_point_on_triangle(q, triangles_[i]) - q).squaredNorm() <= limit; };
  if (first >= 0 && near(size_t(first))) return true;
  for (size_t i = 0; i < triangles_.size(); ++i)
    if (int(i) != first && near(i)) return true;
  return false;
}

// ---- ModSurfaceDistance

const std::string& ModSurfaceDistance::name() const {
  static const std::string n = "SurfaceDistance";
  return n;
}

void ModSurfaceDistance::set_surface(const InputSurface* surface, const Mesh* input,
                                     OpenMesh::VPropHandleT<int> source, double bound) {
  surface_ = surface;
  input_ = input;
  source_ = source;
  bound2_ = kSampleMargin * kSampleMargin * bound * bound;
}

float ModSurfaceDistance::collapse_priority(const CollapseInfo& ci) {
  Mesh& m = mesh();
  // The walk starts on the input at a face of the vertex the moved faces meet at.
  if (!surface_->of_face.empty())
    for (auto f : input_->vf_range(Mesh::VertexHandle(m.property(source_, ci.v1)))) {
      at_ = surface_->of_face[size_t(f.idx())];
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

// Whether q lies within the bound of the input: a walk from the last triangle that answered (consecutive
// samples lie close together), then the tree. Exact either way: the walk only finds a yes sooner.
bool ModSurfaceDistance::near(const Eigen::Vector3d& q) {
  const double limit = bound2_ * (1.0 + 1e-9);
  if (walk(q, limit)) return true;
  // A yes/no query: the search stops at the first triangle within the bound (the minimum stays at
  // `limit` when there is none).
  const double found = surface_->bvh.minimum(
      [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { return box_distance_squared(q, lo, hi); },
      [&](int i, double) {
        const double d = distance2(q, i);
        if (d < limit) at_ = i;
        return d;
      },
      limit, limit);
  return found < limit;
}

double ModSurfaceDistance::distance2(const Eigen::Vector3d& q, int i) const {
  return (closest_point_on_triangle(q, surface_->bvh.triangle(i)) - q).squaredNorm();
}

// A walk over the input's triangles from at_ toward q's projection. True only when the triangle it ends
// on lies within `limit` (squared) of q, which is then where the next walk starts; a walk that ends
// elsewhere (a crease, a gap, a surface bending toward q) proves nothing, and the tree answers. So the
// walk decides nothing: it only finds a yes sooner, and the decimation is the same whatever path it takes.
bool ModSurfaceDistance::walk(const Eigen::Vector3d& q, double limit) {
  if (at_ < 0) return false;
  int f = at_;
  if (!surface_->neighbours.empty()) {
    // Toward q's projection: across the edge that q lies beyond, seen along the triangle's normal (the
    // corner whose barycentric weight is the most negative), until the projection falls inside. One
    // orientation test a step instead of three distances.
    for (int step = 0; step < kWalkSteps; ++step) {
      const Triangle& t = surface_->bvh.triangle(f);
      const Eigen::Vector3d n = (t.b - t.a).cross(t.c - t.a);
      const double w[3] = {(t.c - t.b).cross(q - t.b).dot(n), (t.a - t.c).cross(q - t.c).dot(n),
                           (t.b - t.a).cross(q - t.a).dot(n)};
      const int k = w[0] <= w[1] && w[0] <= w[2] ? 0 : w[1] <= w[2] ? 1 : 2;
      if (!(w[k] < 0.0)) break;
      const int g = surface_->neighbours[size_t(f)][size_t(k)];
      if (g < 0) break;
      f = g;
    }
  }
  if (!(distance2(q, f) < limit)) return false;
  at_ = f;
  return true;
}

}  // namespace tf::internal
