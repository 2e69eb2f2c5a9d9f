// tiltfield planner (internal): what every stage of one planning job shares.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/local_frame.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tool_body.hpp"
#include "clearance_bvh.hpp"
#include "end_form.hpp"

namespace tf {

// One set of obstacles and the clearance each body piece must keep from it: the check surfaces (each
// component its own clearance) or the fixtures (one clearance for the whole tool).
struct ObstacleSet {
  const char* name = "check_surfaces";  // as PLAN.json names it
  ClearanceBvh bvh;
  std::vector<double> required;  // per piece, mm
};

// Search hints for runs of clearance queries at nearby poses: per obstacle set, one triangle per piece.
using ClearanceHints = std::vector<std::vector<int>>;

struct PlanContext {
  const ToolPath* path = nullptr;
  const Tool* tool = nullptr;
  PlannerBasics basics;
  PlanOptions options;
  std::vector<LocalFrame> frames;
  std::vector<Eigen::Vector3d> nominal;  // nominal axis per row
  std::vector<double> feed;              // mm/min per row
  std::vector<double> arc;               // cumulative arc length, mm
  std::vector<BodyPiece> pieces;
  std::vector<double> reach;           // per piece: its farthest point from the cutter location, mm (body_reach)
  std::vector<ObstacleSet> obstacles;  // [0] the check surfaces, [1] the fixtures
  // Per row: the obstacle set one of whose solids holds its cutter location (the whole tool is inside it
  // wherever the distances say it is clear: no axis helps), or -1 (inside_solids.hpp).
  std::vector<int8_t> inside_solid;
  // A flat or bull end against the design surface, and per row design_side() at its contact (0: not
  // checked: a ball end, no design, no normal, or the row off the design).
  EndForm end_form;
  std::vector<int8_t> design_side;
  std::vector<float> contact_dip;  // per row: the contact's own depth below the design mesh, mm
  double cos_max_tilt = 0.5;
  // Set when the scene's machine has rotary axes with limits: axes must then have a joint solution.
  std::optional<Kinematics> kinematics;

  bool reachable(size_t row, const Eigen::Vector3d& axis) const {
    if (!kinematics) return true;
    return !kinematics->inverse(ToolPose{tip(row, axis), axis}, Joints{}).empty();
  }

  // The cutter location of `row` at `axis`: the row's point, moved for a flat or bull end so that the
  // end keeps its contact (Tool::contact_offset; a ball turns about the point itself).
  Eigen::Vector3d cutter_location(size_t row, const Eigen::Vector3d& axis) const {
    return path->rows[row].p + tool->contact_offset(path->rows[row].contact_normal(), axis);
  }
  Eigen::Vector3d tip(size_t row, const Eigen::Vector3d& axis) const {
    return tool->tip_at(path->rows[row].p, path->rows[row].contact_normal(), axis);
  }
  Pose pose(size_t row, const Eigen::Vector3d& axis) const { return {cutter_location(row, axis), axis}; }
  // True when the post links rows `row` and `row` + 1 at axes a0, a1 (retract, rapid, approach): the path
  // says so (APT's RAPID), or it does not say and their tips lie farther apart than the link gap. The
  // motion between them is then no cutting motion.
  bool linked(size_t row, const Eigen::Vector3d& a0, const Eigen::Vector3d& a1) const {
    return linked_to(path->rows[row + 1].approach, (tip(row + 1, a1) - tip(row, a0)).norm(), options.link_gap_mm);
  }
  // The body's exact clearance over every obstacle set. `hints` speed up runs of queries at nearby poses.
  BodyClearance clearance(size_t row, const Eigen::Vector3d& axis, ClearanceHints* hints = nullptr) const;
  // True when every piece keeps its required clearance plus `extra` from every set (early exit, cheap
  // when far); the ball centred on the cutter location, and a ball cutter's flutes (which start on its
  // equator), only their clearance plus min(extra, ball_extra).
  bool clears(size_t row, const Eigen::Vector3d& axis, double extra, ClearanceHints* hints = nullptr,
              double ball_extra = std::numeric_limits<double>::infinity()) const;
  // The largest clearance any piece must keep from any set, mm.
  double max_required() const;
};

// How far a point of the piece can lie from the cutter location, mm: what a turn of the axis by theta
// moves it at most (times theta). 0 for a ball centred on the cutter location.
double body_reach(const BodyPiece& piece);

// The motion from row i to row i + 1, proven (see between_rows.cpp) or not.
struct SegmentCheck {
  bool failed = false;
  double deficit = 0;  // how far below its clearance the motion was found to come, mm (> 0 when failed)
  int set = -1;        // the obstacle set it came lowest to (-1: not measured)
};
// The motion between rows i and i + 1 with axes a0, a1 and the rows' clearances c0, c1. Motions whose
// end rows are themselves below their clearance are not checked (those rows are corrected first).
SegmentCheck check_segment(const PlanContext& ctx, size_t i, const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                           const BodyClearance& c0, const BodyClearance& c1);
// The same beside a row below its clearance (either end): the motion must not come lower than the lower
// of its rows (nor below the clearance, in the poses' unsigned measure). {} when both rows are clear.
SegmentCheck check_segment_beside_failing_rows(const PlanContext& ctx, size_t i, const Eigen::Vector3d& a0,
                                               const Eigen::Vector3d& a1, const BodyClearance& c0, const BodyClearance& c1);
// Every motion between consecutive rows, in parallel (n - 1 results).
std::vector<SegmentCheck> check_segments(const PlanContext& ctx, const std::vector<Eigen::Vector3d>& axes,
                                         const std::vector<BodyClearance>& clear);
// For the result: the motions beside rows left below their clearance, which check_segments leaves to the
// rows' corrections, fail where a pose between comes lower than the lower of their two rows by more than
// the tolerance (deficit: how far below its clearance that pose is), so that a crash on the way is
// reported, not only the rows' own shortfall.
void check_segments_beside_failing_rows(const PlanContext& ctx, const std::vector<Eigen::Vector3d>& axes,
                                        const std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments);

// Exact clearances of all rows, in parallel.
std::vector<BodyClearance> all_clearances(const PlanContext& ctx, const std::vector<Eigen::Vector3d>& axes);
// The same for rows [begin, end) into out (sized to the rows), in parallel.
void clearances(const PlanContext& ctx, const std::vector<Eigen::Vector3d>& axes, size_t begin, size_t end,
                std::vector<BodyClearance>& out);

// The guarantee pass: turns rows below their clearance by the smallest rotation that clears them,
// spread smoothly over the correction window. Updates axes and clear; returns the motions' checks at the
// axes it leaves.
std::vector<SegmentCheck> enforce_clearance(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes,
                                            std::vector<BodyClearance>& clear, const Progress& progress);

// Where the guarantee pass left rows failing (below their clearance, unreachable, or at a failing motion)
// or the axis whipping round (a turn of more than 45 degrees per response length, and 5 degrees): the
// point-by-point baseline's axes blended in over the correction window around them, corrected again, and
// kept only when fewer rows fail, or as many and fewer whip, none deeper below its clearance than before.
// Returns what it replaced (zeros when it kept the axes).
struct FallbackResult {
  size_t failing = 0, whipping = 0;
};
FallbackResult fall_back_to_pointwise(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes,
                                      std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments);

// A sphere turning about its centre keeps its distance: when the ball at the cutter location is nearer to an
// obstacle than its clearance plus `extra`, no axis gives it that much. Returns the extra the ball can be
// asked for at `row` (at most `extra`, what it leaves less a rounding step), negative when the ball itself
// is below its clearance (no axis clears the row; asked for that, the ball-like pieces accept what they
// have and the others must still keep theirs); the other pieces are asked for `extra`.
double ball_extra_at(const PlanContext& ctx, size_t row, const Eigen::Vector3d& axis, double extra);

// The last resort (cone_search.cpp): over windows around the rows `bad` flags (at most 1500 rows in
// all), the smoothest axes that clear, by dynamic programming over fixed axes in each row's max-tilt cone
// (rings 5 degrees apart). Sets `axes` and their `clear` there; returns the rows searched.
size_t search_cone(const PlanContext& ctx, const std::vector<char>& bad, std::vector<Eigen::Vector3d>& axes,
                   std::vector<BodyClearance>& clear);
// The rows still failing or whipping searched by search_cone; kept only when better, as the fall-back's.
FallbackResult fall_back_to_cone_search(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes,
                                        std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments);

// Where a motion between two clear rows fails (the axis passes from one side of an obstacle to the other
// between them), one side's region is followed row by row until a motion back to the planned axes is
// proven: the fewer rows of the two directions are changed. Returns the motions it mended.
// `segments` are the motions' checks at `axes`, kept up to date.
size_t bridge_failing_motions(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes,
                              std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments);

// Smallest turn (rotation vector in span{f, t}, rad) from `axis` that makes the row clear with
// `extra` margin, searched up to the max-tilt cone; nullopt-like: returns false when none is found.
bool smallest_clearing_turn(const PlanContext& ctx, size_t row, const Eigen::Vector3d& axis, double extra,
                            double step_rad, Eigen::Vector3d& turn);

// Baseline: per row, independently, the smallest tilt away from the nominal axis that clears.
std::vector<Eigen::Vector3d> pointwise_axes(const PlanContext& ctx, const Progress& progress);

// The end form against the design (end_lead.cpp): its samples, the design's hierarchy and each row's side.
void set_up_end_form(PlanContext& ctx, const std::vector<const Mesh*>& design);
// Whether a flat or bull end at `axis` dips below the design by more than end_dip_tolerance_mm beyond its
// contact's own dip (stops at the first sample that does); false without an end form.
bool end_dips(const PlanContext& ctx, size_t row, const Eigen::Vector3d& axis);
// Rows whose nominal axis dips a flat or bull end below the design surface by more than
// end_dip_tolerance_mm: the least change of lead that lifts it (forward first; 0.5 deg steps bisected to
// 0.016 deg, within the max-tilt cone), spread along the path over the response length so that the axis
// leans before the dip. Returns the rows changed; notes the change and the rows no lead lifts.
size_t lead_nominal_out_of_design(PlanContext& ctx, std::vector<std::string>& notes);
struct EndDips {
  size_t turned = 0, dipping = 0, first = 0;  // rows turned; rows still dipping, the first of them
  double max_dip_mm = 0;
};
// The axes' dips below the design. With may_turn, a row that dips takes the least change of lead that
// lifts it and keeps it clear and reachable (its clearance updated).
EndDips settle_end_dips(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes, std::vector<BodyClearance>& clear,
                        bool may_turn);

// Ceres pass: smooths the axes keeping every clear row clear. Returns false when Ceres failed (axes kept).
bool smooth_axes(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes, std::vector<BodyClearance>& clear);

}  // namespace tf
