// tiltfield core, internal: the two decimater modules that hold decimate_within's distance bound (see
// include/tiltfield/core/mesh_simplify.hpp), one for each direction, and the input surface they measure
// against. Binary OpenMesh modules: a collapse is LEGAL_COLLAPSE or ILLEGAL_COLLAPSE. Lengths in mm.
#pragma once
#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <array>
#include <string>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/triangle.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf::internal {

// The input surface as ModSurfaceDistance reads it: its triangles in a tree, and per triangle the
// triangles across its edges, so that a walk over the surface reads two flat arrays (OpenMesh's
// circulators over a mesh of millions of faces made the walk a fifth of the whole decimation).
struct InputSurface {
  TriangleBvh bvh;
  std::vector<int> of_face;                    // input face -> its triangle in bvh; empty: no walks
  std::vector<std::array<int, 3>> neighbours;  // per triangle of bvh: across the edge opposite a, b, c; or -1
  explicit InputSurface(const Mesh& in);
};

// Every input vertex within the bound of the output's faces, as OpenMesh's ModHausdorffT keeps it: each
// face carries the removed input vertices nearest to it, and a collapse is legal only when every vertex the
// moved faces carry (and the removed one) lies within the bound of one of the faces after the collapse.
// The same test with two differences: each vertex is tried first against the face that carried it (it
// nearly always stays near that one), and a face that degenerates to a segment is measured as one
// (ModHausdorffT counts a point as on any degenerate face).
class ModVertexDistance : public OpenMesh::Decimater::ModBaseT<Mesh> {
 public:
  using Handle = OpenMesh::Decimater::ModHandleT<ModVertexDistance>;
  explicit ModVertexDistance(Mesh& mesh);
  ~ModVertexDistance() override;
  const std::string& name() const override;
  void set_bound(double bound) { bound2_ = bound * bound; }
  void initialize() override;
  float collapse_priority(const CollapseInfo& ci) override;
  void postprocess_collapse(const CollapseInfo& ci) override;

 private:
  Triangle moved_triangle(Mesh::FaceHandle f, const CollapseInfo& ci);
  bool within(const Eigen::Vector3d& q, int first) const;

  OpenMesh::FPropHandleT<std::vector<Eigen::Vector3d>> carried_;
  double bound2_ = 0.0;
  std::vector<Mesh::FaceHandle> faces_;  // scratch: the faces a collapse moves, and their triangles
  std::vector<Triangle> triangles_;
  std::vector<Eigen::Vector3d> points_;
};

// The other direction, which ModHausdorffT leaves open (the output's faces near the input surface: without
// it a face bridging a crease can stand 7 times the bound off it while every input vertex is near some
// other face): a collapse is legal only when sample points of every face it moves (a grid of quarters over
// the face and its two moved edges) lie within kSampleMargin times the bound of the input's triangles.
// Between samples the distance can grow (it is 1-Lipschitz, and the samples are up to a quarter face
// apart), hence the margin. On LinuxCNC's impeller demo at 0.1 mm and a bound of 0.01 mm, 66 points a
// face against the input measured 0.0097 mm at most with 0.5 (0.0108 with 0.6, 0.07 without the module);
// tests/integration/test_verify_html.cpp checks 28 points a face.
class ModSurfaceDistance : public OpenMesh::Decimater::ModBaseT<Mesh> {
 public:
  static constexpr double kSampleMargin = 0.5;
  using Handle = OpenMesh::Decimater::ModHandleT<ModSurfaceDistance>;
  explicit ModSurfaceDistance(Mesh& mesh) : OpenMesh::Decimater::ModBaseT<Mesh>(mesh, true) {}
  const std::string& name() const override;
  // The input surface, its mesh, and per vertex of the mesh decimated the input vertex it is; `bound`
  // the decimation's bound (the samples are held to kSampleMargin times it).
  void set_surface(const InputSurface* surface, const Mesh* input, OpenMesh::VPropHandleT<int> source,
                   double bound);
  float collapse_priority(const CollapseInfo& ci) override;

 private:
  bool near(const Eigen::Vector3d& q);
  double distance2(const Eigen::Vector3d& q, int i) const;
  bool walk(const Eigen::Vector3d& q, double limit);

  static constexpr int kWalkSteps = 32;  // triangles crossed at most
  const InputSurface* surface_ = nullptr;
  const Mesh* input_ = nullptr;
  OpenMesh::VPropHandleT<int> source_;
  int at_ = -1;  // the triangle of the input the next walk starts from
  double bound2_ = 0.0;
  std::vector<Mesh::VertexHandle> edges_done_;  // the moved edges tested in this collapse, by their far end
};

}  // namespace tf::internal
