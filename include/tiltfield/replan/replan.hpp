// tiltfield replan: re-planning the windows of a planned path where verification found collisions.
//
// In: the scene, the oriented path that was posted and verified, the verifier's collisions (each with the
// tool poses of its block, from VerifyReport or read_replan_collisions), extra obstacles (the stock) and
// the planner's options. Out: the path with its windows re-planned, the windows and their clearances.
// Units: mm. Defaults: windows and blends one planner response length (4 x tool radius) long.
//
// The verifier knows what the planner could not: the shank or holder meeting material of the stock
// (which the check surfaces do not describe), fixtures, or check surfaces hit between rows. Each collision
// is located on the path by the tool poses of its block; a window of rows around it is planned again with
// the same potential-field dynamics, against the check surfaces plus the stock as an extra obstacle felt
// by the non-cutting part of the tool, and blended back into the original axes with a C1 weight, so the
// axis and its angular velocity are continuous at the window ends. Rows outside the windows are copied
// unchanged.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {

// The collisions of a VERIFY.json, each with the tool poses of its block (which the re-planner needs to
// find the path rows). Throws InputError naming the file and the field (collisions[i].start_tip, ...)
// when a collision lacks its poses or the report is malformed.
std::vector<Collision> read_replan_collisions(const std::filesystem::path& verify_json);

struct ReplanOptions {
  // Rows within this arc length (mm) plus the blend length of a collision's rows are re-planned; 0: the
  // planner's response length (4 x tool radius by default).
  double window_mm = 0.0;
  // Arc length (mm) at each window end over which the new axes are blended into the old ones; 0: the
  // planner's response length (4 x tool radius by default).
  double blend_mm = 0.0;
  // Margin (mm) added to the cutting reach when the stock is cropped (see stock_obstacle).
  double crop_margin_mm = 0.5;
  // Where a window's rows or motions stay below their clearance (or beyond the machine's reach), plan
  // again on windows twice and four times as wide, then on the whole path, and keep the first result
  // with none such (else the one with fewest).
  bool widen = true;
};

// Why no tool axis can remove `c`, made by `tool`, or empty when re-planning may: a rapid (the post's links
// and retracts must clear it, not the axis), a ball cutter's ball inside a fixture or check surface (it
// sits at the cutter location whatever the axis; only another path can move it; a flat or bull end swings
// with the axis, and is re-planned), or the end on a move along the tool axis (an approach or retract).
std::string unfixable_reason(const Collision& c, const Tool& tool);

// In: the scene's path, the oriented path the program was posted from (its axes; another row count: the
// axes taken as +Z), the tool and a collision with its block's poses. Out: the rows (inclusive, first <=
// last) whose tool poses, as the post places them (Tool::tip_at), are nearest to the block's start and
// end poses.
using RowSpan = std::pair<size_t, size_t>;
RowSpan collision_rows(const ToolPath& path, const OrientedPath& oriented, const Tool& tool, const Collision& c);
// The same for every collision (each a scan of the path: compute them once).
std::vector<RowSpan> collision_spans(const ToolPath& path, const OrientedPath& oriented, const Tool& tool,
                                     const std::vector<Collision>& collisions);

// In: a path, its tool and a collision with its block's poses. Out: the distance (mm) from the nearer of
// the block's two cutter locations (tip + cl_height x axis) to the polyline through the path's rows.
// A block of a program posted from the path has one end on it or within the post's tolerance of it (a
// cutting move both, an approach or retract the end at its row); a report of another program or scene
// gives millimetres.
double collision_distance_to_path(const ToolPath& path, const Tool& tool, const Collision& c);

// unfixable_reason for each collision, and more: a collision of another part on rows where the ball
// itself meets the same obstacle is the cutter passing through it, which no axis fixes either. `spans`:
// collision_spans of the same collisions.
std::vector<std::string> unfixable_reasons(const std::vector<Collision>& collisions, const std::vector<RowSpan>& spans,
                                           const Tool& tool);

struct ReplanWindow {
  size_t first = 0, last = 0;  // rows, inclusive
  int collisions = 0;          // collision sites that fell into it
};

struct ReplanResult {
  OrientedPath path;
  std::vector<ReplanWindow> windows;
  size_t rows_changed = 0;
  size_t rows_below_safety = 0;  // rows of the windows still below their clearance afterwards
  double min_clearance_mm = 0;   // over the windows' rows, to check surfaces and fixtures (kNoObstacleClearance: none)
  std::vector<size_t> uncleared; // those rows
  // Motions (from row i to row i + 1, i listed) within the windows or across their ends that come below
  // their clearance, or beside a row below it lower than that row (motion_clearances), with the lowest
  // margin found, mm.
  std::vector<std::pair<size_t, double>> uncleared_motions;
  std::vector<size_t> unreachable;  // rows of the windows without a joint solution on the scene's machine
  // 0: the windows as asked; 1, 2: twice, four times as wide; 3: the whole path (ReplanOptions::widen).
  int widened = 0;
};

// The part of `stock` that only the non-cutting part of the tool may meet: triangles split to at most
// `edge_mm` long edges, minus every triangle within the cutting reach (flutes and ball around the cutter
// location, plus the safety distance and `margin_mm`) of any row of `path`. What the flutes would meet is
// material they cut, not a collision; so the shank and holder are the only parts this obstacle can stop.
// Simplification (stated): material within the cutting reach of a row is never an obstacle, so a shank
// touching material right above the flutes may pass unseen by the re-planner (the verifier still sees it).
Mesh stock_obstacle(const Mesh& stock, const ToolPath& path, const Tool& tool, const PlannerBasics& basics,
                    double edge_mm, double margin_mm);

// In: a window's path points (mm), the old and the new tool axes of its rows (unit, part frame), each
// row's blend weight in [0, 1] (0 the old axis, 1 the new), the tool, the rows' design normals (zero:
// unknown; see Tool::contact_offset) and the machine (nullptr: none). Out: the blended axes, along the great circle from old to new. Where that leaves the
// machine's reach on a row while every row's old and new axes are reachable, the whole window is blended
// in the machine's rotaries instead (their limits are a box: every blend of two reachable settings lies
// in it); the re-planner had blended rows to tilts no joint solution reaches.
std::vector<Eigen::Vector3d> blend_axes(const std::vector<Eigen::Vector3d>& cl, const std::vector<Eigen::Vector3d>& old_axes,
                                        const std::vector<Eigen::Vector3d>& new_axes, const std::vector<double>& weights,
                                        const Tool& tool, const std::vector<Eigen::Vector3d>& normals,
                                        const Kinematics* kin);

// Re-plans the windows around `collisions` (those with an unfixable_reason are left alone), against the
// check surfaces, the fixtures and the machine's limits. `original` must have one row per scene path row.
// `extra_obstacles` are added to the check surfaces for the windows (e.g. stock_obstacle of the
// in-process or raw stock).
ReplanResult replan(const Scene& scene, const OrientedPath& original, const std::vector<Collision>& collisions,
                    const std::vector<const Mesh*>& extra_obstacles, const PlanOptions& plan_options,
                    const ReplanOptions& options = {});

}  // namespace tf
