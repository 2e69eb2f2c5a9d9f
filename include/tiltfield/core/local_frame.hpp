// tiltfield core: the local frame (C_L, f, n, t) of a cutter location (Lacharnay et al., CAD 64, 2015),
// lead/tilt <-> tool axis, and the great-circle interpolation of axes.
//
// f: unit feed direction (path tangent, made orthogonal to n); n: unit design-surface normal;
// t = f x n. Lead (deg) inclines the axis toward +f, tilt (deg) turns it about f toward +t:
//   axis = cos(lead) (cos(tilt) n + sin(tilt) t) + sin(lead) f.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "tiltfield/core/toolpath.hpp"

namespace tf {

struct LocalFrame {
  Eigen::Vector3d f, n, t;
};

// One frame per row. The tangent is the central difference of the neighbours (one-sided at the ends),
// projected onto the plane normal to n; where it degenerates (repeated points, a tangent along n) the
// previous frame's f is carried over (or any vector orthogonal to n on the first row).
std::vector<LocalFrame> local_frames(const ToolPath& path);

Eigen::Vector3d axis_from_lead_tilt(const LocalFrame& frame, double lead_deg, double tilt_deg);
// Inverse of axis_from_lead_tilt for a unit axis: lead = asin(a.f), tilt = atan2(a.t, a.n), degrees.
Eigen::Vector2d lead_tilt_from_axis(const LocalFrame& frame, const Eigen::Vector3d& axis);

// The great-circle interpolation of unit vectors (a at s = 0, b at s = 1).
Eigen::Vector3d slerp_axis(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double s);

}  // namespace tf
