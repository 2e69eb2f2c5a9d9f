// tiltfield scene generators: small geometry helpers shared by the parametric scenes (curve sampling by a
// chordal tolerance, solids of revolution, prisms, boxes). Units: mm, radians inside the code.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "tiltfield/core/mesh.hpp"

namespace tf::scenes {

inline constexpr double kPi = std::numbers::pi;
inline double rad(double deg) { return deg * kPi / 180.0; }
// Options and measured facts go to scene.json rounded to 1e-6, so the file stays readable.
inline double tidy(double v) { return std::round(v * 1e6) / 1e6; }
inline bool positive(double v) { return std::isfinite(v) && v > 0; }
// A size the generators build from, mm: 1e308 had written infinite vertices, 1e-300 degenerate meshes
// that `check` took (black-box testing).
inline constexpr double kMinSizeMm = 0.01, kMaxSizeMm = 10000.0;
inline bool size_mm(double v) { return std::isfinite(v) && v >= kMinSizeMm && v <= kMaxSizeMm; }
inline const char* kSizeRange = "must be from 0.01 to 10000 mm";
// The most rows a generated path may have (a 0.001 mm stepover had written 5.8 million).
inline constexpr double kMaxSceneRows = 2e6;

// Parameters t0 = p[0] < ... < p.back() = t1 such that, for every sample curve returned by `eval(t)`
// (several curves evaluated at the same parameter, e.g. the lines of a surface at fixed spans), the
// chord between consecutive parameters deviates from the curve by at most `tolerance` mm at its
// parameter midpoint and quarter points. Starts from `min_intervals` equal intervals and bisects where
// needed (at most 2^20 intervals). The curves must be continuous on [t0, t1].
std::vector<double> sample_by_chord(const std::function<std::vector<Eigen::Vector3d>(double)>& eval, double t0,
                                    double t1, double tolerance, int min_intervals = 8);

// Number of equal segments for a full circle of radius `radius` mm so that a chord deviates from the
// circle by at most `tolerance` mm (at least 12).
int circle_segments(double radius, double tolerance);

// A closed solid of revolution about +z. `profile` holds meridian points (r, z), r >= 0, going
// counter-clockwise around the solid's half-section (the solid on the left when r points right and z
// up); the first and last points must lie on the axis (r == 0) and become poles. Every other point
// becomes a ring of `segments` vertices. Faces point outward; the mesh is closed.
Mesh revolve_profile(const std::vector<Eigen::Vector2d>& profile, int segments);

// A closed prism: the polygon `section` (y, z) (counter-clockwise seen from +x, i.e. y right, z up,
// convex) extruded along x from x0 to x1 > x0. Faces point outward.
Mesh extrude_along_x(const std::vector<Eigen::Vector2d>& section, double x0, double x1);

// A closed axis-aligned box, faces outward.
Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

// Points along a polyline through `knots` every at most `step` mm (the knots themselves included, no
// point repeated). Used for link moves on flat faces.
std::vector<Eigen::Vector3d> resample_polyline(const std::vector<Eigen::Vector3d>& knots, double step);

}  // namespace tf::scenes
