// tiltfield tilt: tool-axis planning by the potential-field rigid-body model (Lacharnay et al., CAD 64,
// 2015), with a point-by-point geometric baseline, clearance guarantees and an optional Ceres smoothing.
//
// In: a tool path (cutter locations and design normals), the tool (ball, flutes, shank, holder segments),
// the check surfaces and fixtures as triangle meshes, the planner's basics (safety distance, nominal
// lead/tilt, max tilt, fixture clearance) and PlanOptions. Out: an OrientedPath (a unit tool axis,
// lead/tilt and the body's exact clearance to check surfaces and fixtures per row), metrics, and the rows
// that could not be cleared. Units: mm, deg, mm/min.
//
// At each cutter location C_L the tool turns about C_L. Its orientation is a state carried along the path:
// J dOmega/dt = repulsion + attraction + damping, integrated in time (time = arc length / feed). The
// repulsion is the gradient of a potential of the distance to the check surfaces and to the fixtures
// (each set with its own clearances), felt by points spread over the whole tool body; the attraction
// pulls toward the nominal lead/tilt. Every row, and the motion between consecutive rows, is then
// checked exactly (GJK against each triangle) and corrected where it is below its clearance. Defaults
// derive from the tool and the feed (derive_plan_options). See docs/planner.md.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/progress.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {

enum class PlanMethod { Dynamic, Pointwise };

// Every tuning value of the planner. `derive_plan_options` fills the defaults from the tool and the feed;
// each can be overridden by the scene's "planner" object under the key named in the comment.
struct PlanOptions {
  PlanMethod method = PlanMethod::Dynamic;  // "method": "dynamic" | "pointwise"
  bool smooth = false;                      // "smooth": global Ceres pass after the dynamics

  // Dynamics. The time scale comes from the feed: omega_n = v / response_length, so the axis answers
  // an obstacle over about response_length mm of path whatever the feed.
  double response_length_mm = 0;   // "response_length_mm", default 4 x tool radius
  double damping_ratio = 1.0;      // "damping_ratio": 1 = critically damped attraction
  double inertia = 1.0;            // "inertia": J, in the same (arbitrary) unit as the gains below
  double attraction = 0;           // "attraction": stiffness toward the nominal axis, torque/rad; default J omega_n^2
  double damping = 0;              // "damping": torque/(rad/s); default 2 zeta J omega_n
  double influence_mm = 0;         // "influence_mm": gap (distance beyond the required clearance) where
                                   // repulsion starts; default tool radius + safety distance
  double repulsion_gain = 1.0;     // "repulsion_gain": dimensionless; repulsion relative to attraction
  double min_gap_mm = 0;           // "min_gap_mm": below this gap the repulsive force stops growing; default influence/20
  double max_substep_deg = 0.25;   // "max_substep_deg": largest axis turn per integration sub-step

  // Field and sampling.
  double field_cell_mm = 0;        // "field_cell_mm": distance-field grid step, default tool radius / 2
  double sample_spacing_mm = 0;    // "sample_spacing_mm": spacing of the tool-body points, default tool radius / 2

  // Guarantees: rows left below their clearance are corrected by the smallest axis turn that clears
  // them, spread smoothly over +-correction_window_mm of path.
  double correction_window_mm = 0;     // "correction_window_mm", default 2 x response_length
  double correction_margin_mm = 0.05;  // "correction_margin_mm": aimed above the required clearance
  int correction_iterations = 8;       // "correction_iterations"
  // Between consecutive rows (cutter location along the chord, axis along the great circle) every pose
  // keeps its clearance less at most this much: the motion is refined until the displacement bound of
  // each piece proves it, and rows whose motion does not are corrected like colliding rows.
  double between_rows_tolerance_mm = 0.01;  // "between_rows_tolerance_mm"
  // Rows whose tips lie farther apart than this are linked by the post (retract, rapid, approach): the
  // motion between them is not checked. Default default_link_gap(tool), the post's default.
  double link_gap_mm = 12.0;  // "link_gap_mm"
  // A flat or bull end may dip at most this far below the design surface away from its contact (a
  // concave surface under a level end face): where the nominal axis dips more, its lead is raised.
  double end_dip_tolerance_mm = 0.002;  // "end_dip_tolerance_mm", at least 0.0001

  // Pointwise baseline.
  double pointwise_step_deg = 0.5;  // "pointwise_step_deg": ring step of the search around the nominal axis

  // Smoothing (Ceres): minimise w2 * |second difference of the axis|^2 + wd * |axis - dynamic axis|^2
  // with the clearance as a barrier.
  double smooth_weight = 1.0;             // "smooth_weight" (w2)
  double smooth_deviation_weight = 0.01;  // "smooth_deviation_weight" (wd)
  int smooth_iterations = 50;             // "smooth_iterations"
};

// The defaults for this tool and feed (mm/min), then every key of the scene's "planner" object that the
// planner knows; unknown keys are refused with InputError(file, 0, "planner.KEY", ...).
PlanOptions derive_plan_options(const Tool& tool, const PlannerBasics& basics, double feed_mm_min);
PlanOptions parse_plan_options(const nlohmann::json& planner, const std::string& file, const Tool& tool,
                               const PlannerBasics& basics, double feed_mm_min);

// What the planner keeps the whole tool clear of. From the check surfaces each component keeps its own
// clearance (PlannerBasics: safety_distance, shank_clearance, holder_clearance); from the fixtures every
// component keeps fixture_clearance. Either list may be empty.
struct PlanObstacles {
  std::vector<const Mesh*> check_surfaces;
  std::vector<const Mesh*> fixtures;
  // The surface the path cuts: a flat or bull end must not dip below it (PlanOptions::end_dip_tolerance_mm).
  std::vector<const Mesh*> design;
};
// The scene's check surfaces, fixtures and design.
PlanObstacles scene_obstacles(const Scene& scene);

struct PlanMetrics {
  size_t rows = 0;
  double min_clearance_mm = 0;
  std::string min_clearance_obstacle = "none";  // the set it is measured to: "check_surfaces" | "fixtures"
  size_t check_triangles = 0, fixture_triangles = 0;  // the obstacles the plan was made against
  size_t rows_below_safety = 0;       // rows whose some component is below its required clearance
  size_t rows_nominal_colliding = 0;  // the same figure for the nominal axis
  double max_step_deg = 0;            // largest axis turn between consecutive rows
  double max_deg_per_mm = 0;          // largest axis turn per mm of path
  double rms_second_difference = 0;   // RMS of |a[i-1] - 2 a[i] + a[i+1]| (unit axes), rad
  size_t corrected_rows = 0;          // rows changed by the guarantee pass
  size_t segments_below_safety = 0;   // motions between rows not proven to keep the clearance (see
                                      // PlanOptions::between_rows_tolerance_mm)
  // A flat or bull end against the design surface: rows whose nominal lead was changed so that the end
  // does not dip below it, rows turned after the stages for the same, rows still dipping, the deepest dip.
  size_t rows_lead_raised = 0, rows_end_turned = 0, rows_end_dipping = 0;
  double max_end_dip_mm = 0;
  double seconds = 0;                 // wall time of the whole plan, preprocessing included
  // Wall time per stage: "bvh", "nominal_check", "field", "axes" (dynamics or search), "clearance",
  // "corrections", "smoothing", "end_form", "between_rows".
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::string method;
  bool smoothed = false;
};

struct UnclearedRow {
  size_t row = 0;          // 0-based row of the path
  double clearance_mm = 0; // smallest distance of the body
  double margin_mm = 0;    // clearance minus the required clearance of the offending component
  std::string obstacle;    // the set of that component's margin: "check_surfaces" | "fixtures" (or empty)
  bool unreachable = false;  // the machine has no joint solution for the axis (rotary limits)
  bool between_rows = false; // the motion to the next row is not clear (the row itself has an entry of
                             // its own where it is not clear either)
};

// How many rows `uncleared` names: a row listed with its motion as well counts once.
size_t uncleared_row_count(const std::vector<UnclearedRow>& uncleared);

struct PlanResult {
  OrientedPath path;
  PlanMetrics metrics;
  std::vector<UnclearedRow> uncleared;  // rows that could not be made clear
  std::vector<std::string> notes;       // e.g. limits that were not checked
};

// Plans the scene's path against its check surfaces and fixtures. Never throws for uncleared rows (see
// `uncleared`).
PlanResult plan(const Scene& scene, const PlanOptions& options, const Progress& progress = {});

// The same on explicit inputs (tests, benchmarks). `feed` is the default feed, mm/min.
// `machine`: when given and it has rotary axes with limits, every axis must have a joint solution
// (Kinematics::inverse); rows without one are corrected like colliding rows, or listed.
PlanResult plan_path(const ToolPath& path, const Tool& tool, const PlanObstacles& obstacles,
                     const PlannerBasics& basics, double feed, const PlanOptions& options,
                     const MachineSpec* machine = nullptr, const Progress& progress = {});

// The PLAN.json object: the metrics and the uncleared rows.
nlohmann::json plan_report_json(const PlanResult& result);

// Exact clearance of the whole tool body (ball, flutes, shank, every holder segment) at rows of an
// oriented path against `obstacles`: the smallest distance (mm) and the smallest margin of a component
// over its required clearance (mm, >= 0 when every component keeps its clearance). Rows are indices
// into path.rows, answered in the same order.
struct RowClearance {
  double distance_mm = 0;
  double margin_mm = 0;
};
std::vector<RowClearance> row_clearances(const OrientedPath& path, const std::vector<size_t>& rows, const Tool& tool,
                                        const PlannerBasics& basics, const PlanObstacles& obstacles);

// The motions between consecutive rows of an oriented path (the cutter location along the chord, the axis
// along the great circle), proven as the planner proves its own to PlanOptions::between_rows_tolerance_mm:
// for each i in `rows`, the motion from row i to row i + 1 of `oriented` over the points and normals of
// `path` (the same rows). Beside a row below its clearance the motion must not come lower than the lower
// of its rows; a motion whose tips lie farther apart than the link gap (the post's transit) is not
// checked. Out, in the same order: whether it keeps the clearance and, where not, the lowest margin
// found, mm (< 0).
struct MotionClearance {
  bool clear = true;
  double margin_mm = 0;
};
std::vector<MotionClearance> motion_clearances(const ToolPath& path, const OrientedPath& oriented,
                                               const std::vector<size_t>& rows, const Tool& tool,
                                               const PlannerBasics& basics, const PlanObstacles& obstacles,
                                               const PlanOptions& options);

// Metrics that only depend on the axes (step, deg/mm, RMS second difference); the rest left as is.
void axis_metrics(const OrientedPath& path, PlanMetrics& metrics);

}  // namespace tf
