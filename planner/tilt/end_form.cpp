// The end form against the design (end_form.hpp).
#include "end_form.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <variant>

namespace tf {
namespace {

// Rings of n points at radius rho and height z about the axis.
void add_ring(std::vector<Eigen::Vector3d>& out, double rho, double z, int n) {
  for (int k = 0; k < n; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / n;
    out.emplace_back(rho * std::cos(phi), rho * std::sin(phi), z);
  }
}

}  // namespace

EndForm make_end_form(const Tool& tool, const std::vector<const Mesh*>& design) {
  EndForm form;
  if (std::holds_alternative<BallCutter>(tool.cutter) || design.empty()) return form;
  const double R = tool.radius(), r = tool.cl_height();  // r: the corner radius, 0 for a flat end
  constexpr int kRim = 72;                                // 5 deg around the rim
  // The face: its rim (a flat end's deepest point on a concave surface) and two rings inside.
  const double face = R - r;
  if (face > 0) {
    add_ring(form.points, face, 0.0, kRim);
    add_ring(form.points, face * 2.0 / 3.0, 0.0, kRim / 2);
    add_ring(form.points, face / 3.0, 0.0, kRim / 4);
    form.points.emplace_back(0.0, 0.0, 0.0);
  }
  // A bull end's corner, from the face to where it meets the flutes.
  if (r > 0)
    for (double beta_deg : {18.0, 36.0, 54.0, 72.0, 90.0}) {
      const double beta = beta_deg * std::numbers::pi / 180.0;
      add_ring(form.points, face + r * std::sin(beta), r - r * std::cos(beta), kRim);
    }
  form.design = TriangleBvh(design);
  form.reach = R;
  return form;
}

int design_side(const EndForm& form, const Eigen::Vector3d& contact, const Eigen::Vector3d& normal) {
  if (!form.active() || !(normal.squaredNorm() > 0.5)) return 0;
  const ClosestHit hit = form.design.closest(contact, 0.1 * form.reach);
  if (hit.triangle < 0) return 0;
  // Of the triangles about as near the contact as the nearest (1 um more), the one that faces most like the
  // row's normal: a contact on the design's boundary edge lies as near the side wall as the face it
  // finishes, and a pass along the edge of a trough had gone unmeasured and gouged 0.52 mm (black-box
  // testing).
  const double near = hit.distance + 1e-3;
  const Eigen::Vector3d n = normal.normalized();
  double facing = 0.0;  // the signed cosine of the best triangle
  const double best = form.design.minimum(
      [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
        return box_distance_squared(contact, lo, hi) <= near * near ? -1.0 : std::numeric_limits<double>::infinity();
      },
      [&](int i, double so_far) {
        const Triangle& t = form.design.triangle(i);
        const Eigen::Vector3d nt = (t.b - t.a).cross(t.c - t.a);
        if (!(nt.squaredNorm() > 0) || (closest_point_on_triangle(contact, t) - contact).squaredNorm() > near * near)
          return std::numeric_limits<double>::infinity();
        const double c = nt.normalized().dot(n);
        if (-std::abs(c) < so_far) facing = c;
        return -std::abs(c);
      },
      std::numeric_limits<double>::infinity());
  // A contact whose every near triangle lies more than 60 deg off the row's normal (a sharp edge of the
  // design) does not tell which side the material is on: the row is not checked rather than checked on a
  // guessed side.
  if (!(best <= -0.5)) return 0;
  return facing > 0 ? 1 : -1;
}

double point_dip(const EndForm& form, const Eigen::Vector3d& x, int side, int* hint) {
  if (side == 0 || !form.active()) return 0.0;
  const ClosestHit hit = form.design.closest(x, form.reach, hint ? *hint : -1);
  if (hit.triangle < 0) return 0.0;
  if (hint) *hint = hit.triangle;
  const Triangle& t = form.design.triangle(hit.triangle);
  Eigen::Vector3d nt = (t.b - t.a).cross(t.c - t.a);
  const double len = nt.norm();
  if (!(len > 0)) return 0.0;
  nt *= side / len;
  // Clearly on the material side: more than 30 deg off the triangle's plane (sin 30 = 0.5).
  return (x - hit.point).dot(nt) < -0.5 * hit.distance ? hit.distance : 0.0;
}

double end_dip(const EndForm& form, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis, int side,
               double stop_above) {
  if (side == 0 || !form.active()) return 0.0;
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  double dip = 0.0;
  int hint = -1;
  for (const Eigen::Vector3d& q : form.points) {
    dip = std::max(dip, point_dip(form, tip + q.x() * e1 + q.y() * e2 + q.z() * a, side, &hint));
    if (dip > stop_above) break;
  }
  return dip;
}

}  // namespace tf
