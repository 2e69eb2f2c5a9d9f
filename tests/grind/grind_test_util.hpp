// Shared helpers of the grinding tests.
#pragma once
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <string>

#include "tiltfield/grind/grind.hpp"
#include "tiltfield/core/mesh.hpp"

namespace tf::grind::testing {

inline GrindScene make_scene(double r, double l, double R, double w, double e, const std::string& program,
                             const Axes& start = {0, 200, 0, 0, 0, 0}) {
  GrindScene s;
  s.blank = {r, l};
  s.wheel.radius = R;
  s.wheel.thickness = w;
  s.wheel.edge_radius = e;
  s.wheel.profile = make_wheel_profile(R, w, e);
  s.start = start;
  s.operations = parse_grind_program(program, "test", start);
  s.file = "test";
  return s;
}

// Exact radius of a rounded-rim wheel at axial offset t (for independent checks), -1 outside.
inline double wheel_rho(double R, double w, double e, double t) {
  const double h = 0.5 * w, at = std::abs(t);
  if (at > h) return -1.0;
  if (at <= h - e) return R;
  const double d = at - (h - e);
  return R - e + std::sqrt(std::max(0.0, e * e - d * d));
}

// Self-intersection by CGAL (shared vertices and edges between adjacent faces allowed).
inline bool self_intersects(const Mesh& mesh) {
  using SM = CGAL::Surface_mesh<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>;
  SM sm;
  std::vector<SM::Vertex_index> vi;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    vi.push_back(sm.add_vertex({p[0], p[1], p[2]}));
  }
  for (auto f : mesh.faces()) {
    std::vector<SM::Vertex_index> fv;
    for (auto v : mesh.fv_range(f)) fv.push_back(vi[v.idx()]);
    if (sm.add_face(fv) == SM::null_face()) return true;
  }
  return CGAL::Polygon_mesh_processing::does_self_intersect(sm);
}

}  // namespace tf::grind::testing
