// Synthetic planner scenes built in the tests: boxes tessellated at a chosen edge length, straight and
// curved ball-centre paths, and an independent FCL clearance check of an oriented path.
#pragma once
#include <fcl/fcl.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "bull_end_fcl.hpp"
#include "tiltfield/core/local_frame.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace tf::test {

// A closed box [lo, hi], outward faces, each face a grid of squares about `edge` mm (two triangles each),
// optionally turned by `rot` about `pivot`.
inline Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double edge,
                     const Eigen::Matrix3d& rot = Eigen::Matrix3d::Identity(),
                     const Eigen::Vector3d& pivot = Eigen::Vector3d::Zero()) {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  const Eigen::Vector3d size = hi - lo;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int nu = std::max(1, static_cast<int>(std::ceil(size[u] / edge)));
      const int nv = std::max(1, static_cast<int>(std::ceil(size[v] / edge)));
      const int base = static_cast<int>(V.size());
      for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
          Eigen::Vector3d p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = lo[u] + size[u] * i / nu;
          p[v] = lo[v] + size[v] * j / nv;
          V.push_back(pivot + rot * (p - pivot));
        }
      for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
          const int a = base + j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
          // (u, v, axis) is right-handed: counter-clockwise seen from +axis is a, b, d, c.
          if (side) {
            F.push_back({a, b, d});
            F.push_back({a, d, c});
          } else {
            F.push_back({a, d, b});
            F.push_back({a, c, d});
          }
        }
    }
  Eigen::MatrixX3d Vm(static_cast<Eigen::Index>(V.size()), 3);
  Eigen::MatrixX3i Fm(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t i = 0; i < V.size(); ++i) Vm.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
  for (size_t i = 0; i < F.size(); ++i) Fm.row(static_cast<Eigen::Index>(i)) = F[i].transpose();
  return mesh_from_arrays(Vm, Fm);
}

// Ball centres along a polyline at `step` mm, normal `n` everywhere, feed NaN (scene feed).
inline ToolPath polyline_path(const std::vector<Eigen::Vector3d>& pts, double step, const Eigen::Vector3d& n) {
  ToolPath p;
  for (size_t k = 0; k + 1 < pts.size(); ++k) {
    const double len = (pts[k + 1] - pts[k]).norm();
    const int m = std::max(1, static_cast<int>(std::round(len / step)));
    for (int i = 0; i < m; ++i) p.rows.push_back({pts[k] + (pts[k + 1] - pts[k]) * (double(i) / m), n.normalized()});
  }
  p.rows.push_back({pts.back(), n.normalized()});
  return p;
}

inline Tool test_tool() {
  Tool t;
  t.cutter = BallCutter{3.0};
  t.flute_length = 12;
  t.shank_radius = 3;
  t.length = 60;
  t.holder = {{12.0, 40.0}};
  return t;
}

// Independent check with FCL: per row the smallest distance of each tool part (sphere and cylinders) to
// the mesh, and the smallest margin over the parts (distance - the part's required clearance).
struct FclCheck {
  double min_distance = 1e9;
  double min_margin = 1e9;
  size_t rows_below = 0;  // rows with margin < -tolerance
};

inline FclCheck fcl_check(const OrientedPath& path, const Tool& tool, const std::vector<const Mesh*>& meshes,
                          const PlannerBasics& basics, double tolerance = 0.01) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> verts;
  std::vector<fcl::Triangle> tris;
  for (const Mesh* m : meshes) {
    const TriangleArrays a = to_arrays(*m);
    const size_t base = verts.size();
    for (Eigen::Index i = 0; i < a.V.rows(); ++i) verts.emplace_back(a.V(i, 0), a.V(i, 1), a.V(i, 2));
    for (Eigen::Index i = 0; i < a.F.rows(); ++i)
      tris.emplace_back(base + static_cast<size_t>(a.F(i, 0)), base + static_cast<size_t>(a.F(i, 1)),
                        base + static_cast<size_t>(a.F(i, 2)));
  }
  model->beginModel();
  model->addSubModel(verts, tris);
  model->endModel();
  fcl::CollisionObjectd mesh(model, fcl::Transform3d::Identity());
  struct Part {
    std::shared_ptr<fcl::CollisionGeometryd> geom;
    double mid;  // centre height above the cutter location
    double req;
  };
  std::vector<Part> parts;
  const double cl = tool.cl_height();
  auto req = [&](ToolComponent c) {
    if (c == ToolComponent::Shank) return basics.shank_clearance.value_or(basics.safety_distance);
    if (c == ToolComponent::Holder) return basics.holder_clearance.value_or(basics.safety_distance);
    return basics.safety_distance;
  };
  auto cyl = [&](double h0, double h1, double r, ToolComponent c) {
    if (h1 - h0 > 1e-9) parts.push_back({std::make_shared<fcl::Cylinderd>(r, h1 - h0), 0.5 * (h0 + h1) - cl, req(c)});
  };
  const auto* bull = std::get_if<BullCutter>(&tool.cutter);
  if (std::holds_alternative<BallCutter>(tool.cutter))
    parts.push_back({std::make_shared<fcl::Sphered>(tool.radius()), 0.0, basics.safety_distance});
  else if (bull && tool.flute_length >= 2 * bull->corner_radius)  // the torus itself, centred on the CL
    parts.push_back({bull_end_convex(tool.radius(), bull->corner_radius, 360, 90), 0.0, basics.safety_distance});
  else
    cyl(0.0, tool.end_height(), tool.radius(), ToolComponent::Ball);
  cyl(tool.end_height(), tool.flute_length, tool.radius(), ToolComponent::Flute);
  cyl(tool.flute_length, tool.length, tool.shank_radius, ToolComponent::Shank);
  double h = tool.length;
  for (const auto& s : tool.holder) {
    cyl(h, h + s.length, s.radius, ToolComponent::Holder);
    h += s.length;
  }
  FclCheck out;
  for (const auto& row : path.rows) {
    const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), row.axis).toRotationMatrix();
    double row_margin = 1e9;
    for (const auto& part : parts) {
      fcl::Transform3d tfm = fcl::Transform3d::Identity();
      tfm.linear() = R;
      tfm.translation() = row_tip(row, tool) + (cl + part.mid) * row.axis;  // a flat or bull end's moved CL
      fcl::CollisionObjectd obj(part.geom, tfm);
      fcl::DistanceRequestd rq;
      fcl::DistanceResultd rs;
      fcl::distance(&mesh, &obj, rq, rs);
      const double d = rs.min_distance;
      out.min_distance = std::min(out.min_distance, d);
      row_margin = std::min(row_margin, d - part.req);
    }
    out.min_margin = std::min(out.min_margin, row_margin);
    if (row_margin < -tolerance) ++out.rows_below;
  }
  return out;
}

// Every motion between consecutive rows as `k` poses (cutter location along the chord, axis along the
// great circle), the rows included.
inline OrientedPath densify(const OrientedPath& path, int k) {
  OrientedPath out;
  for (size_t i = 0; i + 1 < path.rows.size(); ++i)
    for (int j = 0; j < k; ++j) {
      const double u = static_cast<double>(j) / k;
      OrientedRow r = path.rows[i];
      r.p = path.rows[i].p + u * (path.rows[i + 1].p - path.rows[i].p);
      r.axis = slerp_axis(path.rows[i].axis, path.rows[i + 1].axis, u).normalized();
      out.rows.push_back(r);
    }
  out.rows.push_back(path.rows.back());
  return out;
}

}  // namespace tf::test
