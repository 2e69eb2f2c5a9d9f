// tiltfield core: the planner's output: cutter locations with a tool axis each, and its CSV.
//
// Units: mm, deg. The axis is a unit vector from the tool tip toward the spindle, in the part frame.
#pragma once
#include <cmath>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <limits>
#include <vector>

#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace tf {

// The clearance the planner writes where the tool has nothing to collide with (no check surface or
// fixture): CSV and JSON want a number, but it is no distance to show or plot.
inline constexpr double kNoObstacleClearance = 1e6;
inline bool clearance_measured(double c) { return std::isfinite(c) && c < kNoObstacleClearance; }

struct OrientedRow {
  Eigen::Vector3d p;     // cutter location, part frame, mm (same as the input path's row)
  Eigen::Vector3d axis;  // unit tool axis from the tip toward the spindle
  double lead_deg = 0.0;
  double tilt_deg = 0.0;
  double clearance_mm = 0.0;  // smallest distance of the tool body to the check surfaces
  double feed = std::numeric_limits<double>::quiet_NaN();  // mm/min, NaN: the scene's feed
  // The design normal of the path row (not in the CSV; attach_path_normals or the planner set it): a flat
  // or bull end's cutter location moves with the axis to keep its contact (Tool::contact_offset). Zero:
  // unknown, `p` is the cutter location itself.
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  // How the row before reaches it (not in the CSV either: the path's, attach_path_normals or the planner
  // set it).
  Approach approach = Approach::ByGap;
  // The line of the CSV the row was read from (read_oriented_csv), for messages; 0: not read from a file.
  int source_line = 0;
};

struct OrientedPath {
  std::vector<OrientedRow> rows;
};

// The tool tip of a row: its cutter location (the row point moved by Tool::contact_offset) moved back
// along the axis by the cutter-location height.
Eigen::Vector3d row_tip(const OrientedRow& row, const Tool& tool);

// Gives each row the normal (and Approach) of the path row it was planned from, when `oriented` has the path's rows
// (as many, each within 0.001 mm of its path row) and returns true; otherwise leaves the rows as they are
// (their points then are the cutter locations themselves) and returns false.
bool attach_path_normals(OrientedPath& oriented, const ToolPath& path);
// Throws InputError (naming `file`, and the line of the first row that differs) unless `oriented` has the
// rows of `path`: as many, each cutter location within 0.001 mm of its row's. What `replan` and `check`
// ask of an oriented path given with its scene.
void require_rows_of_path(const OrientedPath& oriented, const ToolPath& path, const std::string& file);

// Header x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm[,feed]. Throws InputError with line and column
// for a bad number, a missing column, a zero or non-unit axis (off by more than 1e-3), or no rows.
OrientedPath read_oriented_csv(const std::filesystem::path& file);
// 9 decimals for positions and axes, no scientific notation; written atomically.
void write_oriented_csv(const OrientedPath& path, const std::filesystem::path& file);

}  // namespace tf
