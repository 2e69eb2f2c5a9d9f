// tiltfield dexel (internal): swept-part intervals for a whole row of rays at once, and the parts'
// shadows row by row: the simulation's innermost loops, vectorised (capsule_rows.cpp, cylinder_rows.cpp,
// shadow_rows.cpp; see row_kernels.hpp). Raw pointers into the caller's per-tile buffers, no allocation.
// Each agrees with the scalar ray_interval of sweep.hpp, which the tests use as the reference.
#pragma once
#include <Eigen/Core>
#include <array>

#include "tiltfield/dexel/sweep.hpp"

namespace tf {

// ray_interval for a row of n rays, o + i step e_u + t e_dir (i = 0 .. n-1, u != dir): t0[i] < t1[i] on a
// hit; t0[i] = +inf and t1[i] = -inf on a miss. Spheres are evaluated in a vectorised batch.
void ray_intervals(const SweptPart& part, const Eigen::Vector3d& o, int dir, int u, double step, int n, double* t0,
                   double* t1);
// The shadow of a swept part cast along grid axis dir onto the (u, v) plane (v the third axis): a ray of
// grid dir can meet the part only inside it. It is the convex hull of up to four stadiums (a segment in
// (u, v) grown by a radius). Exact for a sphere (the centre's segment grown by the radius) and for a
// cylinder whose axis is along dir (its bottom centre's segment). A tilted cylinder lies inside the
// capsule of radius r about its axis; the shadow bounds that capsule swept by d: the parallelogram of the
// axis and the motion, grown by r (its four edges' stadiums), so it is conservative there, never short.
// Built once per part and grid by make_shadow, then asked row by row.
struct Shadow {
  struct Stadium {
    double pu = 0, pv = 0, du = 0, dv = 0;  // segment start and direction in (u, v), mm
    double tu = 0, tv = 0, len = 0;         // its unit direction and length
    double inv_tu = 0, inv_tv = 0;          // 1 / tu, 1 / tv (0 where the component is 0)
  };
  int count = 0;
  double r = 0;  // the radius, mm
  std::array<Stadium, 4> stadiums;
};
Shadow make_shadow(const SweptPart& part, int dir, int u);
// The stadium of the segment from (pu, pv) along (du, dv).
Shadow::Stadium make_stadium(double pu, double pv, double du, double dv);
// The stretch [lo, hi] of the line {v = cv} inside the shadow; false when the line misses it.
bool shadow_row(const Shadow& shadow, double cv, double& lo, double& hi);
// The same for the n rows v = cv0 + i step in one batch: lo[i] > hi[i] where row i misses.
void shadow_rows(const Shadow& shadow, double cv0, double step, int n, double* lo, double* hi);
// ray_intervals for a sphere part (capsule_rows.cpp).
void capsule_intervals(const SweptPart& part, const Eigen::Vector3d& o, int dir, int u, double step, int n,
                       double* t0, double* t1);
// ray_intervals for a cylinder part, vectorised (cylinder_rows.cpp). Returns false, writing
// nothing, for the rows it leaves to the scalar method: the ray across the cylinder's axis, or the motion
// along it. A cylinder that does not move is done here, ray by ray in closed form.
bool cylinder_intervals(const SweptPart& part, const Eigen::Vector3d& o, int dir, int u, double step, int n,
                        double* t0, double* t1);
// An arc sweep (SweptPart::arc) against the ray o + t e_dir, exactly; and its shadow along dir
// (sweep_arc.cpp).
bool arc_interval(const SweptPart& part, const Eigen::Vector3d& o, int dir, double& t0, double& t1);
Shadow arc_shadow(const SweptPart& part, int dir, int u);

}  // namespace tf
