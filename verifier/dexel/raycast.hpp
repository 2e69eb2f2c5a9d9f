// tiltfield verifier: ray casting of triangle meshes with Embree 3 (every crossing along a line).
#pragma once
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "tiltfield/core/mesh.hpp"

namespace tf {

struct RayHit {
  double t;    // parameter along the line, mm
  double cos;  // unit outward face normal . line direction (< 0: entering a solid)
};

// An Embree scene of one mesh. Thread-safe queries after construction.
class RayMesh {
 public:
  explicit RayMesh(const Mesh& mesh);
  ~RayMesh();
  RayMesh(const RayMesh&) = delete;
  RayMesh& operator=(const RayMesh&) = delete;

  // All crossings of the line o + t e (e unit) with t in [t0, t1], sorted by t, into `out` (cleared).
  // Hits closer than 1e-5 mm to the previous one (the same crossing seen through two triangles sharing an
  // edge) are merged.
  void hits(const Eigen::Vector3d& o, const Eigen::Vector3d& e, double t0, double t1, std::vector<RayHit>& out) const;

  // Closest point of the mesh to p (within max_dist mm); returns false when none is that close.
  // `normal` receives the unit normal of the closest triangle.
  bool closest(const Eigen::Vector3d& p, double max_dist, Eigen::Vector3d& point, Eigen::Vector3d& normal) const;

  const Eigen::AlignedBox3d& box() const { return box_; }

  struct Impl;  // Embree objects and the mesh arrays

 private:
  std::unique_ptr<Impl> impl_;
  Eigen::AlignedBox3d box_;
};

}  // namespace tf
