// tiltfield planner (internal): what every stage of one planning job shares.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/local_frame.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tool_body.hpp"
#include "clearance_bvh.hpp"

namespace tf {

struct PlanContext {
  const ToolPath* path = nullptr;
  const Tool* tool = nullptr;
  PlannerBasics basics;
  PlanOptions options;
  std::vector<LocalFrame> frames;
  std::vector<Eigen::Vector3d> nominal;  // nominal axis per row
  std::vector<double> feed;              // mm/min per row
  std::vector<double> arc;               // cumulative arc length, mm
  ClearanceBvh bvh;
  std::vector<BodyPiece> pieces;
  std::vector<double> required;  // per piece, mm
  double cos_max_tilt = 0.5;
  // Set when the scene's machine has rotary axes with limits: axes must then have a joint solution.
  std::optional<Kinematics> kinematics;

  bool reachable(size_t row, const Eigen::Vector3d& axis) const {
    if (!kinematics) return true;
    const ToolPose pose{path->rows[row].p - tool->cl_height() * axis, axis};
    return !kinematics->inverse(pose, Joints{}).empty();
  }

  Pose pose(size_t row, const Eigen::Vector3d& axis) const { return {path->rows[row].p, axis}; }
  // `hints` (one triangle per piece, see piece_distance) speed up runs of queries at nearby poses.
  BodyClearance clearance(size_t row, const Eigen::Vector3d& axis, std::vector<int>* hints = nullptr) const {
    return body_clearance(bvh, pieces, required, pose(row, axis), hints);
  }
  // True when every piece keeps its required clearance plus `extra` (early exit, cheap when far).
  bool clears(size_t row, const Eigen::Vector3d& axis, double extra, std::vector<int>* hints = nullptr) const;
};

// Exact clearances of all rows, in parallel.
std::vector<BodyClearance> all_clearances(const PlanContext& ctx, const std::vector<Eigen::Vector3d>& axes);
// The same for rows [begin, end) into out (sized to the rows), in parallel.
void clearances(const PlanContext& ctx, const std::vector<Eigen::Vector3d>& axes, size_t begin, size_t end,
                std::vector<BodyClearance>& out);

// The guarantee pass: turns rows below their clearance by the smallest rotation that clears them,
// spread smoothly over the correction window. Updates axes and clear; returns the rows it changed.
size_t enforce_clearance(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes, std::vector<BodyClearance>& clear,
                         const Progress& progress);

// Smallest turn (rotation vector in span{f, t}, rad) from `axis` that makes the row clear with
// `extra` margin, searched up to the max-tilt cone; nullopt-like: returns false when none is found.
bool smallest_clearing_turn(const PlanContext& ctx, size_t row, const Eigen::Vector3d& axis, double extra,
                            double step_rad, Eigen::Vector3d& turn);

// Baseline: per row, independently, the smallest tilt away from the nominal axis that clears.
std::vector<Eigen::Vector3d> pointwise_axes(const PlanContext& ctx, const Progress& progress);

// Ceres pass: smooths the axes keeping every clear row clear. Returns false when Ceres failed (axes kept).
bool smooth_axes(const PlanContext& ctx, std::vector<Eigen::Vector3d>& axes, std::vector<BodyClearance>& clear);

}  // namespace tf
