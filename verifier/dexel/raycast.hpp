// tiltfield verifier: closest points on a triangle mesh with Embree 3 (gouge depths and deviation
// colours), and RayHit, a crossing of a lattice ray with a mesh (mesh_rays.hpp finds them).
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
