// tiltfield: swept volumes of the tool over a motion, as exact per-ray intervals.
//
// The tool body (tool.hpp) is split into convex parts: spheres (ball end; the torus of a bull end as a
// ring of spheres on its centre circle) and cylinders (flat end, flutes, shank, holder segments). Under a
// pure translation d the swept volume of a convex part K is K + [0, 1] d, and its intersection with an
// axis-parallel ray is one interval computed exactly: a capsule for a sphere, and for a cylinder the
// t-extent of the convex set {(t, s) : o + t e - s d in K, 0 <= s <= 1} (one quadratic and four linear
// constraints, solved by enumerating the active constraints). So a 3-axis linear move of a ball or flat
// tool is exact. A bull end's torus is the union of spheres spaced so that the lens between neighbours is
// at most `torus_tolerance` deep (stated error, default 0.001 mm).
//
// Rotary motion (simultaneous 5-axis, and arcs or joint-interpolated moves whose tip path is curved) is
// split into sub-steps, each part on its own count. In a sub-step a part is held at the tool axis of the
// sub-step's mid-time and translated along the chord of its own centre (the pivot: a sphere's centre, a
// cylinder piece's mid-point). A point of the part at distance r from the pivot is then within
//   phi * r + dev
// of its true position at every time of the sub-step, and so each set within that distance of the other
// (a Hausdorff bound), with phi the largest angle between the true axis and the held one and dev the
// pivot path's largest distance from its chord at the same time. A sphere is unchanged by a rotation
// about its centre (r = 0), so a ball needs sub-steps only for the curvature of its centre's path,
// which falls with the square of the step. A long cylinder (flutes, shank, holder) is cut into pieces
// along its axis, as many as make the block cheapest (a shorter piece has a smaller r and needs fewer
// sub-steps, but every piece costs its own end overlap); the pieces tile the cylinder exactly.
// Sub-step counts grow until each part's measured bound is at most its tolerance: `tolerance` for the
// cutting parts (ball, flutes), `holder_tolerance` for shank and holder, which only collide. phi and dev
// are measured at the sub-step's ends and at its quarter, half and three-quarter times.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <utility>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/tool.hpp"

namespace tf {

// A convex tool part in the tool frame (tip at the origin, axis +z).
struct ToolPart {
  enum class Kind { Sphere, Cylinder } kind = Kind::Sphere;
  double h0 = 0.0;      // sphere: centre height; cylinder: bottom height, mm
  double h1 = 0.0;      // cylinder: top height, mm
  double radius = 0.0;  // mm
  double offset = 0.0;  // sphere: distance of the centre from the axis (torus ring), mm
  double angle = 0.0;   // sphere: angle of the centre about the axis, rad
  ToolComponent component = ToolComponent::Ball;
  bool cutting = true;  // ball end and flutes cut; shank and holder only collide
};

struct SweepOptions {
  double tolerance = 0.01;         // mm, bound on the cutting parts' sub-step error (see above)
  double holder_tolerance = 0.05;  // mm, the same for shank and holder (collision only)
  double torus_tolerance = 0.001;  // mm, depth of the gaps between a bull end's ring spheres
  int max_substeps = 4096;         // per part and block
  int max_pieces = 16;             // most pieces a cylinder is cut into along its axis
};

// The convex parts of `tool`, in the tool frame.
std::vector<ToolPart> tool_parts(const Tool& tool, const SweepOptions& options = {});

// One part swept by a translation, in the part frame.
struct SweptPart {
  ToolPart::Kind kind = ToolPart::Kind::Sphere;
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero();    // sphere centre / cylinder bottom centre at the start
  Eigen::Vector3d d = Eigen::Vector3d::Zero();     // translation, mm
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(); // cylinder axis (unit)
  double radius = 0.0, height = 0.0;               // mm
  Eigen::AlignedBox3d box;                         // bounds of the swept part
  ToolComponent component = ToolComponent::Ball;
  bool cutting = true;
  // A sphere that starts where the previous block left the tool (the simulation sets it): the material
  // inside it is gone already, so a ray on which the sweep stays inside the start sphere has nothing to
  // lose to it.
  bool start_empty = false;
  // A sphere centred on the tool axis (not one of a bull end's ring spheres, whose places about the axis
  // follow each sub-step's reference direction and so move from one block to the next as the axis turns).
  bool on_axis = true;
  // Arc sweeps (sweep_arc): the part carried, without turning, along a circular arc in the plane across
  // lattice axis arc_axis, its own axis along that one. The arc is a piece of at most a quarter turn
  // between two quadrant angles: centre (arc_cu, arc_cv) in the plane's coordinates u = arc_axis + 1,
  // v = arc_axis + 2 (mod 3), radius, start and end angles counter-clockwise (a0 < a1, rad). Along arc_axis
  // the part spans arc_z0..arc_z1 (a cylinder), or is centred at arc_z0 (a sphere).
  bool arc = false;
  int arc_axis = 2;
  double arc_cu = 0.0, arc_cv = 0.0, arc_radius = 0.0, arc_a0 = 0.0, arc_a1 = 0.0, arc_z0 = 0.0, arc_z1 = 0.0;
  Eigen::Vector4d arc_ends = Eigen::Vector4d::Zero();  // cos a0, sin a0, cos a1, sin a1
  // Sphere sweeps: constants of the per-ray test for each grid direction k, set by sweep_part (they are
  // the same for every ray of a grid): |d|, 1/|d|, d_k/|d|, 1/(1 - (d_k/|d|)^2) and |d|/d_k (0 where
  // the division has no meaning).
  double len = 0.0, inv_len = 0.0;
  Eigen::Vector3d dir_cos = Eigen::Vector3d::Zero(), inv_sin2 = Eigen::Vector3d::Zero(), inv_cos = Eigen::Vector3d::Zero();
};

// Places `part` at the pose (tip, axis) and sweeps it by d. `ref` is a unit vector perpendicular to axis
// fixing the angle origin of ring spheres.
SweptPart sweep_part(const ToolPart& part, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis,
                     const Eigen::Vector3d& ref, const Eigen::Vector3d& d);

// Interval [t0, t1] of the ray o + t e_dir (dir 0, 1, 2: x, y, z) inside the swept part; false if none.
// For a cylinder this is the scalar enumeration, the reference for the simulation's batched rows.
bool ray_interval(const SweptPart& part, const Eigen::Vector3d& o, int dir, double& t0, double& t1);


// The motion of one block: tool pose as a function of time tau in [0, 1].
using PoseAt = std::function<ToolPose(double tau)>;

struct BlockSweep {
  std::vector<SweptPart> parts;   // all sub-steps of all parts
  Eigen::AlignedBox3d box;        // bounds of all parts
  int substeps = 1;               // the most sub-steps of a cutting part
  int swept_parts_cutting = 0;    // swept parts of the cutting parts (all sub-steps and pieces)
  double cutting_error = 0.0;     // bound for ball and flutes, mm
  double holder_error = 0.0;      // bound for shank and holder, mm
  double tip_length = 0.0;        // length of the tip path, mm
  // Scratch reused between blocks: poses at the sub-step ends and quarter times, one set per count.
  std::vector<std::pair<int, std::vector<ToolPose>>> pose_sets;
  size_t pose_sets_used = 0;
};

// Sub-steps and swept parts of one block. `parts` from tool_parts(). `out` is reused between blocks. In a
// rapid (`rapid`) nothing cuts: every part is swept to `holder_tolerance` and its bound counts as the
// holder's (BlockSweep::holder_error). `rotary_turn_deg`: the most any rotary joint turns over the block
// (deg); every sub-step turns at most a quarter turn of it, so that the poses a sub-step's bound samples
// cannot line up across whole turns (a block turning a table four times would otherwise look straight).
// `exact_end`: the cutting parts also at the exact end pose, not moving, when the axis turns (a sub-step
// holds its part at its middle axis, which leaves a sliver of material, within the bound, inside the tool
// at the end; the simulation asks for it before a rapid, which would report the sliver as a collision).
void sweep_block(const PoseAt& pose_at, const std::vector<ToolPart>& parts, const SweepOptions& options,
                 BlockSweep& out, bool rapid = false, double rotary_turn_deg = 0.0, bool exact_end = false);

// A block whose tool axis stays on one lattice axis while the tip runs on a circle in the plane across it
// (a G17 arc with a vertical tool, and the like; no helix): the tip's circle in that plane. Found from the
// motion itself (poses at 0, 1/4, 1/2, 3/4 and 1, all on the circle within 1e-7 mm).
struct PlanarArc {
  int axis = 2;                                        // the lattice axis the tool axis lies on
  Eigen::Vector3d center = Eigen::Vector3d::Zero();   // of the tip's circle (in the tip's plane)
  double radius = 0.0;                                 // mm
  double a0 = 0.0, sweep = 0.0;                        // start angle and signed turn, rad (u toward v)
};
bool planar_arc(const PoseAt& pose_at, PlanarArc& arc);

// The parts of a block that moves them along `arc` without turning (pose0 the start pose), swept exactly
// (no sub-steps: each part's pieces between quadrant angles are exact per ray), into out.parts.
void sweep_arc(const PlanarArc& arc, const ToolPose& pose0, const std::vector<ToolPart>& parts, BlockSweep& out);

// Joint values at time tau of a block starting at `from` (linear in every axis; XYZ on the arc for G2/G3).
Joints interpolate_block(const Joints& from, const Block& block, double tau);

}  // namespace tf
