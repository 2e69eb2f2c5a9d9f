// tiltfield engagement: cutter-workpiece engagement at the end of a block (after Sullivan, Erdim, Perry and
// Frisken, engagement on a sampled workpiece), plugged into the simulation as VerifyOptions::engagement.
//
// In: the in-process stock *before* the block removes its material, the tool, and the tool's motion at
// the block's end (two poses: a little before the end, and the end). Out: the engagement surface, as
// entry/exit angle pairs per axial height, its area (mm^2), the axial depth and radial width of cut (mm).
//
// Method (their sampling test, made exact where the tri-dexel allows): points are spread over the cutting
// surface (end form and flutes) on rings: spherical sampling on a ball, toroidal on a bull corner, polar on
// a flat end face and cylindrical on the flutes, every ring sampled at the same angles. A point x with
// outward normal nu is engaged when it faces its own motion (nu . v > 0: the rear of the tool only rubs the
// wall it has cut) and the stock before the block still holds material just inside the tool there, at x -
// 0.001 mm nu: the block removes it as it arrives. A stock point is classified by the three ray grids: each
// gives the exact along-ray state of the ray nearest the point, and the grid whose nearest material
// boundary is the closest decides (a ray crossing a boundary steeply locates it exactly; one running along
// it is off by up to half a spacing). Every change of state between neighbouring samples, around a ring and
// along the profile, is then refined by bisection, so angles, depths and areas are not quantised to the
// sampling.
//
// Angles (after Altintas): in the plane normal to the tool axis a at the block's end, measured clockwise
// seen from the spindle (the teeth's direction of travel under M3), starting from n = a x f, the normal to
// the feed direction f (the tip's velocity without its axial part). So 90 deg is the feed direction:
// slotting engages 0..180, a half-immersion cut engages 0..90 in conventional (up) milling, with the
// material on the left of the feed, and 90..180 in climb (down) milling, with the material on the right. A
// pair that runs through 0 has entry > exit. When the tip moves along the axis only (a plunge), f is the
// part's x axis projected normal to a (its y axis when a is along x).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <limits>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/dexel/tridexel.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {

struct EngagementOptions {
  // Sample spacing around the axis, deg. Boundaries between samples are refined to a fraction of the
  // lattice spacing, so the step only bounds what can be missed: an engaged arc narrower than it.
  double angle_step_deg = 6.0;
  // Ring spacing along the profile (the heights of the engagement pairs), mm; 0: the arc between two
  // angle samples at the tool's radius, but not below the lattice spacing. Boundaries between rings are
  // refined and the area integrated to second order or better between them, so the spacing only bounds
  // what can be missed: an engaged band narrower than it.
  double axial_step_mm = 0.0;
  int max_rings = 160;          // cap on the ring count (a long profile is sampled more coarsely)
  // Evaluations per boundary between samples of opposite states, around a ring or along a meridian, at
  // most: each at the zero of the measure that tells them apart (the facing value, or the depth in
  // material), until the bracket is half the lattice spacing (what the nearest rays resolve).
  int refine_steps = 8;
  // How far outside the box of the material a block removed a sample can still be engaged, beyond the
  // classification's reach of 1.5 lattice spacings: the sweep's bound (the swept parts hold the true tool
  // within it), mm.
  double removed_margin_mm = 0.05;
  bool keep_pairs = false;      // keep every pair at every height (Engagement::pairs)
};

// True when p lies in the stock's material (see the classification above).
bool stock_contains(const TriDexel& stock, const Eigen::Vector3d& p);

// The engagement of `tool` at pose `end`, reached from `before` (the pose a short time earlier: it gives
// the velocity of every surface point). `stock` is the in-process stock before the block. `removed`, when
// given, is the box (part frame, mm) holding the material the block removed: only samples near it can
// be engaged, and only they are looked up (an empty box: nothing is engaged).
Engagement measure_engagement(const TriDexel& stock, const Tool& tool, const ToolPose& before, const ToolPose& end,
                              const EngagementOptions& options = {}, const Eigen::AlignedBox3d* removed = nullptr);

// The verifier's per-block hook (VerifyOptions::engagement) measuring the block's tool with `options`.
EngagementProbe engagement_probe(const EngagementOptions& options = {});

}  // namespace tf
