// tiltfield planner: the tool body as convex pieces posed at a cutter location, and its exact clearance
// to the check surfaces.
//
// The body of revolution is the union of a sphere (the ball, centred on the cutter location) and stacked
// finite cylinders (flutes, shank, every holder segment). Heights are measured along the tool axis from
// the rotation centre C_L (the cutter location), mm. The ball's clearance does not depend on the axis.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "tiltfield/core/scene.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {

struct BodyPiece {
  ToolComponent component = ToolComponent::Flute;
  int holder_segment = -1;
  bool sphere = false;  // the ball: centre at height h0 (= 0 for a ball cutter), radius `radius`
  double h0 = 0, h1 = 0;  // height range above C_L, mm (h0 < h1 for a cylinder)
  double radius = 0;      // mm
  // A cylinder rounded by `rounding` (mm): the points within it of the cylinder of radius radius - rounding
  // over [h0 + rounding, h1 - rounding]. A bull end is the disc of radius R - r at its torus' centre
  // height rounded by r. 0: a plain cylinder.
  double rounding = 0;
};

// The pieces of a tool. A ball cutter gives a sphere of its radius; a flat end a cylinder of the cutter
// radius over the end-form height; a bull end the rounded disc of its torus (exact: its upper half lies
// inside the flutes), or, when the flutes are shorter than twice the corner radius, the cylinder of the
// cutter radius over the end-form height, which encloses the torus (conservative: the rounded disc would
// reach above the flutes). Pieces of zero length are left out.
std::vector<BodyPiece> body_pieces(const Tool& tool);

// Clearance each component must keep from the check surfaces: ball and flutes the safety distance, the
// shank and holder their own when given (else the safety distance). mm.
double required_clearance(const PlannerBasics& basics, ToolComponent component);
// The least clearance the checks require, mm, whatever the scene asks: their distances are unsigned (0
// inside an obstacle), so a required 0 let a shank 0.27 mm deep in a blade pass (found in review). The
// verifier's default collision tolerance.
inline constexpr double kLeastClearance = 0.001;
// Clearance every component must keep from the fixtures: planner.fixture_clearance, else the safety
// distance. mm.
double fixture_clearance(const PlannerBasics& basics);

struct Pose {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();          // rotation centre (cutter location), mm
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();      // unit tool axis
};

// Exact distance (GJK against each triangle, to 1e-6 mm) from a piece to the surfaces, or a value >=
// `limit` when it is at least `limit`. 0 when they touch or intersect. With `first_below` set, returns as
// soon as some triangle is nearer than `limit` (then only "< limit" is meaningful): a cheap yes/no test.
double piece_distance(const TriangleBvh& bvh, const BodyPiece& piece, const Pose& pose, double limit,
                      bool first_below = false);

// Distance between a triangle and a finite cylinder (axis p0 -> p1, radius r) by GJK, mm. 0 on contact.
double triangle_cylinder_distance(const Triangle& t, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double r);
// The same for the cylinder centred at `mid` about the unit `axis`, half height `half` >= 0 and radius r >= 0:
// a disc when half = 0, a segment when r = 0.
double triangle_cylinder_distance(const Triangle& t, const Eigen::Vector3d& mid, const Eigen::Vector3d& axis,
                                  double half, double r);
// Distance between a triangle and a rounded cylinder (BodyPiece::rounding; 0: a plain cylinder) whose outer
// extent runs from p0 to p1 along its axis with radius R, mm, or a value >= `best` (a lower bound) when it
// cannot beat `best`.
double rounded_cylinder_distance(const Triangle& t, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double R,
                                 double rounding, double best);

struct BodyClearance {
  double distance = 0;  // smallest distance of the whole body to the surfaces, mm
  double margin = 0;    // smallest (piece distance - its required clearance), mm; >= 0 means clear
  int piece = -1;       // the piece that sets `margin`
  // With several obstacle sets (check surfaces, fixtures): the set of the smallest distance and the set
  // that sets `margin`; -1 when nothing is near.
  int nearest_set = -1, margin_set = -1;
};

// `required[i]` is the clearance piece i must keep. Exact for both figures.
BodyClearance body_clearance(const TriangleBvh& bvh, const std::vector<BodyPiece>& pieces,
                             const std::vector<double>& required, const Pose& pose);

}  // namespace tf
