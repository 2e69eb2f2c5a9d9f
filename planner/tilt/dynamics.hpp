// tiltfield planner (internal): the rigid-body tool model and its integrator along the path.
#pragma once
#include <Eigen/Core>
#include <atomic>
#include <vector>

#include "distance_field.hpp"
#include "tiltfield/core/local_frame.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tiltfield/core/progress.hpp"
#include "tool_body.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace tf {

// Points spread over the tool body that feel the potential, grouped in chunks along the axis so whole
// chunks far from every obstacle are skipped. Positions relative to C_L in the tool frame (z = axis).
struct BodySamples {
  struct Chunk {
    double hc = 0;        // centre height above C_L, mm
    double rho = 0;       // radius of a sphere about the centre holding every sample of the chunk, mm
    double required = 0;  // largest required clearance of its samples, mm
    int begin = 0, end = 0;
  };
  std::vector<Eigen::Vector3d> p;
  std::vector<double> weight;    // surface area each point stands for, mm^2
  std::vector<double> required;  // clearance the point's component must keep, mm
  std::vector<Chunk> chunks;
};

// The ball of a ball cutter is left out: a sphere turning about its own centre keeps its distances, so
// any torque it felt would only be sampling noise. Holder segments are sampled at least 24 points round.
BodySamples make_body_samples(const Tool& tool, const PlannerBasics& basics, double spacing);
// The same points keeping one clearance (mm) for every component (the fixtures' clearance).
BodySamples with_clearance(BodySamples samples, double required);

// One obstacle set as the body feels it: its triangles, their distance field, and the samples with the
// clearances they keep from that set. The repulsions of all sets add up.
struct PotentialSource {
  const ClearanceBvh* bvh = nullptr;
  DistanceField* field = nullptr;
  const BodySamples* samples = nullptr;
};

// What the integrator needs at one instant along the path.
struct PathState {
  Eigen::Vector3d c, f, n, t, nominal;  // cutter location, local frame, nominal axis
};

struct DynamicsParams {
  double inertia = 1, attraction = 1, damping = 2;
  double influence = 6, min_gap = 0.3;  // mm
  double force_scale = 1;               // repulsion per unit area and unit potential slope
  double max_substep_rad = 0.004;
  double cos_max_tilt = 0.5;
};
DynamicsParams dynamics_params(const PlanOptions& options, const Tool& tool, const PlannerBasics& basics);

// Whether the integration starts afresh at row i (from the nominal axis, settled): where the path says the
// row is linked to, or where it reverses between rows i - 1 and i (the move into i - 1 and the one out of
// i more than 120 deg apart: a zig-zag's step-over) and the nominal axis turns there by more than a degree
// beyond the surface normal's own turn (a lead, which flips with the feed). There the tool turns on the step-over instead of carrying the last
// pass's axis into the next: with a lead of 5 deg, the flipped lead had taken most of a 66 mm pass to
// settle, and a flat end passing the normal left stock uncut (black-box testing). Where the nominal runs
// on (lead 0 on a smooth surface), the axis the obstacles deflected runs on too.
constexpr double kReversalCos = -0.5;
constexpr double kRestartJumpRad = 1.0 * 3.14159265358979323846 / 180.0;
bool restarts_at(const ToolPath& path, const std::vector<Eigen::Vector3d>& nominal, size_t i);

// Integrates the axis along the path into `axes` (one per row, resized to the path). `feed` per row in
// mm/min. `published`, when given, is raised (release order) as rows get their final axis, so another
// thread can work on them while the integration goes on.
void integrate_axes(const ToolPath& path, const std::vector<LocalFrame>& frames,
                    const std::vector<Eigen::Vector3d>& nominal, const std::vector<double>& feed,
                    const std::vector<PotentialSource>& sources, const DynamicsParams& params,
                    const Progress& progress, std::vector<Eigen::Vector3d>& axes,
                    std::atomic<size_t>* published = nullptr);

// Axis `a` turned by the rotation vector w (rad), Rodrigues.
Eigen::Vector3d rotate_axis(const Eigen::Vector3d& a, const Eigen::Vector3d& w);

// Puts `a` inside the cone of half-angle acos(cos_max) about n (turning it toward n when outside).
Eigen::Vector3d clamp_to_cone(const Eigen::Vector3d& a, const Eigen::Vector3d& n, double cos_max);

}  // namespace tf
