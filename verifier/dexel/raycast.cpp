#include "raycast.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {

struct RayMesh::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  // Embree works in float; coordinates are shifted by `shift` (the mesh's box centre) to keep them small.
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  std::vector<float> vertices;     // shifted, 3 a vertex (+1 padding for Embree's 16-byte reads)
  std::vector<unsigned> indices;   // 3 a triangle
  std::vector<Eigen::Vector3d> V;  // double copies for exact normals and distances
  std::vector<Eigen::Vector3i> F;
  std::vector<Eigen::Vector3d> normals;
};

RayMesh::RayMesh(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  const TriangleArrays a = to_arrays(mesh);
  box_ = bounding_box(mesh);
  if (!box_.isEmpty()) m.shift = box_.center();
  m.V.resize(a.V.rows());
  m.vertices.resize(3 * a.V.rows() + 1, 0.f);
  for (Eigen::Index i = 0; i < a.V.rows(); ++i) {
    m.V[i] = a.V.row(i).transpose();
    for (int k = 0; k < 3; ++k) m.vertices[3 * i + k] = static_cast<float>(a.V(i, k) - m.shift[k]);
  }
  m.F.resize(a.F.rows());
  m.normals.resize(a.F.rows());
  m.indices.resize(3 * a.F.rows());
  for (Eigen::Index f = 0; f < a.F.rows(); ++f) {
    m.F[f] = a.F.row(f).transpose();
    for (int k = 0; k < 3; ++k) m.indices[3 * f + k] = static_cast<unsigned>(a.F(f, k));
    const Eigen::Vector3d n = (m.V[m.F[f][1]] - m.V[m.F[f][0]]).cross(m.V[m.F[f][2]] - m.V[m.F[f][0]]);
    m.normals[f] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
  }
  // No "threads=N" here: Debian's Embree schedules with TBB, and a thread count becomes a process-wide
  // tbb::global_control for the device's lifetime, which serialised every TBB loop of the verifier.
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("Embree: cannot create a device");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.vertices.data(), 0, 3 * sizeof(float),
                             m.V.size());
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(), 0, 3 * sizeof(unsigned),
                             m.F.size());
  rtcCommitGeometry(g);
  rtcAttachGeometry(m.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(m.scene);
}

RayMesh::~RayMesh() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

namespace {

struct ClosestQuery {
  const RayMesh::Impl* mesh;
  Eigen::Vector3d p;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  unsigned prim = 0;
};

bool closest_callback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  const auto& f = q->mesh->F[args->primID];
  const Eigen::Vector3d c = closest_point_on_triangle(q->p, Triangle{q->mesh->V[f[0]], q->mesh->V[f[1]], q->mesh->V[f[2]]});
  const double d = (c - q->p).norm();
  if (d < q->best) {
    q->best = d;
    q->point = c;
    q->prim = args->primID;
    args->query->radius = static_cast<float>(d + 1e-6);
    return true;
  }
  return false;
}
}  // namespace

bool RayMesh::closest(const Eigen::Vector3d& p, double max_dist, Eigen::Vector3d& point, Eigen::Vector3d& normal) const {
  ClosestQuery q{impl_.get(), p};
  RTCPointQuery query;
  const Eigen::Vector3d ps = p - impl_->shift;
  query.x = static_cast<float>(ps.x());
  query.y = static_cast<float>(ps.y());
  query.z = static_cast<float>(ps.z());
  query.time = 0.f;
  query.radius = static_cast<float>(max_dist);
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(impl_->scene, &query, &ctx, closest_callback, &q);
  if (!std::isfinite(q.best)) return false;
  point = q.point;
  normal = impl_->normals[q.prim];
  return true;
}

}  // namespace tf
