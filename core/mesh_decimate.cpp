// Vertex clustering (see mesh_decimate.hpp): a grid key per vertex, sums and quadrics per cluster, then
// the triangles collapsed onto the clusters' points.
#include "tiltfield/core/mesh_decimate.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace tf {

namespace {

// A cluster key packs the three cell coordinates (kAxisBits each) and the facing (3 bits) in 63 bits; a
// finer grid than that would not decimate anything anyway.
constexpr int kAxisBits = 20;
constexpr double kMaxCells = double(1 << kAxisBits) - 1.0;
constexpr uint8_t kNoFacing = 6;
constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();

Eigen::Vector3d twice_area_normal(const IndexedTriangles& m, const std::array<uint32_t, 3>& f) {
  return (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]);
}

double surface_area(const IndexedTriangles& m) {
  double a = 0.0;
  for (const auto& f : m.F) a += 0.5 * twice_area_normal(m, f).norm();
  return a;
}

void check_values(const IndexedTriangles& m) {
  for (const size_t n : {m.values.size(), m.labels.size()})
    if (n != 0 && n != m.V.size())
      throw std::invalid_argument("mesh decimation: " + std::to_string(n) + " per-vertex values for " +
                                  std::to_string(m.V.size()) + " vertices");
}

// What clustering needs that does not depend on the cell, so a budget search computes it once.
struct ClusterGrid {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  std::vector<uint8_t> facing;  // per vertex: 2 * dominant axis + (negative ? 1 : 0) of its normal, or kNoFacing
};

ClusterGrid cluster_grid(const IndexedTriangles& mesh) {
  ClusterGrid g;
  if (mesh.V.empty()) return g;
  g.lo = g.hi = mesh.V[0];
  for (const auto& v : mesh.V) {
    g.lo = g.lo.cwiseMin(v);
    g.hi = g.hi.cwiseMax(v);
  }
  std::vector<Eigen::Vector3d> normal(mesh.V.size(), Eigen::Vector3d::Zero());
  for (const auto& f : mesh.F) {
    const Eigen::Vector3d n = twice_area_normal(mesh, f);
    for (uint32_t i : f) normal[i] += n;
  }
  g.facing.resize(mesh.V.size());
  for (size_t i = 0; i < mesh.V.size(); ++i) {
    const Eigen::Vector3d& n = normal[i];
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    g.facing[i] = n.squaredNorm() == 0.0 ? kNoFacing : uint8_t(2 * axis + (n[axis] < 0.0 ? 1 : 0));
  }
  return g;
}

struct Clustering {
  std::vector<uint32_t> of_vertex;
  uint32_t clusters = 0;  // numbered in the order of their first vertex
};

Clustering assign_clusters(const IndexedTriangles& mesh, const ClusterGrid& grid, double cell, size_t expected) {
  Clustering c;
  c.of_vertex.resize(mesh.V.size());
  std::unordered_map<uint64_t, uint32_t> index;  // cluster key -> cluster, in order of first appearance
  index.reserve(expected);
  for (size_t i = 0; i < mesh.V.size(); ++i) {
    const Eigen::Vector3d& p = mesh.V[i];
    uint64_t key = 0;
    for (int a = 0; a < 3; ++a) key = (key << kAxisBits) | uint64_t(std::floor((p[a] - grid.lo[a]) / cell));
    c.of_vertex[i] = index.try_emplace((key << 3) | grid.facing[i], uint32_t(index.size())).first->second;
  }
  c.clusters = uint32_t(index.size());
  return c;
}

bool collapses(const std::array<uint32_t, 3>& g) { return g[0] == g[1] || g[1] == g[2] || g[0] == g[2]; }

std::array<uint32_t, 3> clusters_of(const Clustering& c, const std::array<uint32_t, 3>& f) {
  return {c.of_vertex[f[0]], c.of_vertex[f[1]], c.of_vertex[f[2]]};
}

// The triangle count does not depend on where the cluster points go, so a budget search counts first.
size_t kept_triangles(const IndexedTriangles& mesh, const Clustering& c) {
  size_t n = 0;
  for (const auto& f : mesh.F) n += !collapses(clusters_of(c, f));
  return n;
}

// The quadric sum of w (n . x - d)^2 over the planes (n, d) of some triangles, w twice a triangle's area:
// minimised where A x = b. A is symmetric: xx, xy, xz, yy, yz, zz.
struct ClusterQuadric {
  std::array<double, 6> A{};
  Eigen::Vector3d b = Eigen::Vector3d::Zero();

  ClusterQuadric& operator+=(const ClusterQuadric& q) {
    for (size_t i = 0; i < 6; ++i) A[i] += q.A[i];
    b += q.b;
    return *this;
  }
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d m;
    m << A[0], A[1], A[2], A[1], A[3], A[4], A[2], A[4], A[5];
    return m;
  }
};

struct Cluster {
  Eigen::Vector3d position_sum = Eigen::Vector3d::Zero();
  double value_sum = 0.0;
  uint32_t label = 0;  // of the first vertex
  uint32_t count = 0;
  ClusterQuadric quadric;  // of the triangles at the cluster's vertices
};

std::vector<Cluster> vertex_sums(const IndexedTriangles& mesh, const Clustering& c) {
  std::vector<Cluster> clusters(c.clusters);
  const bool has_values = !mesh.values.empty();
  for (size_t i = 0; i < mesh.V.size(); ++i) {
    Cluster& k = clusters[c.of_vertex[i]];
    k.position_sum += mesh.V[i];
    if (has_values) k.value_sum += mesh.values[i];
    if (k.count == 0 && !mesh.labels.empty()) k.label = mesh.labels[i];
    ++k.count;
  }
  return clusters;
}

// Every triangle's plane goes to the cluster of each of its corners, collapsed triangles included: they
// carry the shape inside a cluster. Most triangles of a fine mesh lie inside one cluster: one update.
void add_plane(const IndexedTriangles& mesh, const std::array<uint32_t, 3>& f, const std::array<uint32_t, 3>& g,
               std::vector<Cluster>& clusters) {
  const Eigen::Vector3d n2 = twice_area_normal(mesh, f);
  const double w = n2.norm();
  if (!(w > 0.0)) return;
  const int corners = g[0] == g[1] && g[1] == g[2] ? 3 : 1;
  // w n n^T = n2 n2^T / w, w n d = n2 (n2 . p) / w.
  const Eigen::Vector3d m = n2 * (corners / w);
  const ClusterQuadric q{{m.x() * n2.x(), m.x() * n2.y(), m.x() * n2.z(), m.y() * n2.y(), m.y() * n2.z(), m.z() * n2.z()},
                  m * n2.dot(mesh.V[f[0]])};
  for (int k = 0; k < 4 - corners; ++k) clusters[g[size_t(k)]].quadric += q;
}

Eigen::Vector3d cluster_point(const Cluster& k, double cell) {
  const Eigen::Vector3d mean = k.position_sum / double(k.count);
  const Eigen::Matrix3d A = k.quadric.matrix();
  const double eps = 1e-3 * A.trace() + 1e-12;
  Eigen::Vector3d x = (A + eps * Eigen::Matrix3d::Identity()).ldlt().solve(k.quadric.b + eps * mean);
  if (!x.allFinite() || (x - mean).norm() > 2.0 * cell) x = mean;
  return x;
}

// The kept triangles on the clusters they use, numbered as first used; placement is solved only for those
// clusters (most clusters of a fine mesh are used, but not all).
IndexedTriangles collapse(const IndexedTriangles& mesh, const Clustering& c, double cell) {
  std::vector<Cluster> clusters = vertex_sums(mesh, c);
  IndexedTriangles out;
  std::vector<uint32_t> index(c.clusters, kUnused), used;
  for (const auto& f : mesh.F) {
    std::array<uint32_t, 3> g = clusters_of(c, f);
    add_plane(mesh, f, g, clusters);
    if (collapses(g)) continue;
    for (uint32_t& i : g) {
      if (index[i] == kUnused) {
        index[i] = uint32_t(used.size());
        used.push_back(i);
      }
      i = index[i];
    }
    out.F.push_back(g);
  }
  out.V.reserve(used.size());
  for (uint32_t i : used) out.V.push_back(cluster_point(clusters[i], cell));
  if (!mesh.values.empty())
    for (uint32_t i : used) out.values.push_back(clusters[i].value_sum / double(clusters[i].count));
  if (!mesh.labels.empty())
    for (uint32_t i : used) out.labels.push_back(clusters[i].label);
  return out;
}

bool too_fine(const ClusterGrid& grid, double cell) {
  return !(cell > 0.0) || (grid.hi - grid.lo).maxCoeff() / cell > kMaxCells;
}

}  // namespace

IndexedTriangles indexed_triangles(const Mesh& mesh, const std::vector<double>* values,
                                   const std::vector<uint32_t>* labels) {
  IndexedTriangles out;
  out.V.resize(mesh.n_vertices(), Eigen::Vector3d::Zero());
  for (auto vh : mesh.vertices()) out.V[size_t(vh.idx())] = to_eigen(mesh.point(vh));
  out.F.reserve(mesh.n_faces());
  for (auto fh : mesh.faces()) {
    std::array<uint32_t, 3> f{};
    int k = 0;
    for (auto vh : mesh.fv_range(fh)) {
      if (k < 3) f[size_t(k)] = uint32_t(vh.idx());
      ++k;
    }
    if (k == 3) out.F.push_back(f);
  }
  if (values) {
    if (values->size() != out.V.size())
      throw std::invalid_argument("indexed_triangles: " + std::to_string(values->size()) + " per-vertex values for " +
                                  std::to_string(out.V.size()) + " vertices");
    out.values = *values;
  }
  if (labels) {
    if (labels->size() != out.V.size())
      throw std::invalid_argument("indexed_triangles: " + std::to_string(labels->size()) + " per-vertex labels for " +
                                  std::to_string(out.V.size()) + " vertices");
    out.labels = *labels;
  }
  return out;
}

IndexedTriangles cluster_decimate(const IndexedTriangles& mesh, double cell) {
  check_values(mesh);
  if (!(cell > 0.0) || mesh.V.empty()) return mesh;
  const ClusterGrid grid = cluster_grid(mesh);
  if (too_fine(grid, cell)) return mesh;
  return collapse(mesh, assign_clusters(mesh, grid, cell, std::min<size_t>(mesh.V.size(), 1 << 16)), cell);
}

IndexedTriangles decimate_to_budget(const IndexedTriangles& mesh, size_t max_triangles) {
  check_values(mesh);
  if (mesh.F.size() <= max_triangles) return mesh;
  if (max_triangles == 0) return {};
  double cell = std::sqrt(2.0 * surface_area(mesh) / double(max_triangles));
  if (!(cell > 0.0)) return {};
  const ClusterGrid grid = cluster_grid(mesh);
  for (int pass = 0; pass < 16; ++pass) {
    size_t kept = mesh.F.size();
    if (!too_fine(grid, cell)) {
      // About one cluster per two kept triangles.
      Clustering c = assign_clusters(mesh, grid, cell, max_triangles / 2);
      kept = kept_triangles(mesh, c);
      if (kept <= max_triangles) return collapse(mesh, c, cell);
    }
    cell *= std::max(1.15, std::sqrt(double(kept) / double(max_triangles)));
  }
  return {};  // unreachable in practice: a cell the size of the mesh leaves no triangles
}

}  // namespace tf
