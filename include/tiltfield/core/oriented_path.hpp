// tiltfield core: the planner's output: cutter locations with a tool axis each, and its CSV.
//
// Units: mm, deg. The axis is a unit vector from the tool tip toward the spindle, in the part frame.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <limits>
#include <vector>

#include "tiltfield/core/tool.hpp"

namespace tf {

struct OrientedRow {
  Eigen::Vector3d p;     // cutter location, part frame, mm (same as the input path's row)
  Eigen::Vector3d axis;  // unit tool axis from the tip toward the spindle
  double lead_deg = 0.0;
  double tilt_deg = 0.0;
  double clearance_mm = 0.0;  // smallest distance of the tool body to the check surfaces
  double feed = std::numeric_limits<double>::quiet_NaN();  // mm/min, NaN: the scene's feed
};

struct OrientedPath {
  std::vector<OrientedRow> rows;
};

// The tool tip of a row: the cutter location moved back along the axis by the cutter-location height.
Eigen::Vector3d row_tip(const OrientedRow& row, const Tool& tool);

// Header x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm[,feed]. Throws InputError with line and column
// for a bad number, a missing column, a zero or non-unit axis (off by more than 1e-3), or no rows.
OrientedPath read_oriented_csv(const std::filesystem::path& file);
// 9 decimals for positions and axes, no scientific notation; written atomically.
void write_oriented_csv(const OrientedPath& path, const std::filesystem::path& file);

}  // namespace tf
