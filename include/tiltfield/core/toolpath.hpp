// tiltfield core: the input tool path: cutter locations with design-surface normals, in cutting order,
// from the path CSV or APT CLDATA. Units: mm, mm/min.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <limits>
#include <vector>

#include "tiltfield/core/tool.hpp"

namespace tf {

// How a row is reached from the one before it. A path CSV does not say: a jump longer than the link gap
// (PlanOptions::link_gap_mm, PostOptions::link_gap_mm) is a link, the rest cut. APT CLDATA does: a GOTO
// after RAPID is linked to, any other is cut however long (a 60 mm straight GOTO had been linked over as
// a jump, and nothing cut; black-box testing).
enum class Approach : unsigned char { ByGap, Cut, Link };

// Whether a row reached by `approach` over a tip jump of `jump` mm is linked to (retract, transit,
// approach) rather than cut to, with the link gap `link_gap` mm.
inline bool linked_to(Approach approach, double jump, double link_gap) {
  return approach == Approach::Link || (approach == Approach::ByGap && jump > link_gap);
}

struct CLPoint {
  // The ball centre of a ball end mill; for a flat or bull end the contact point plus the corner radius
  // times n (the contact point itself for a flat end), from which its cutter location follows the axis
  // (Tool::contact_offset). Part frame, mm.
  Eigen::Vector3d p;
  Eigen::Vector3d n;  // unit normal of the design surface at the contact point
  double feed = std::numeric_limits<double>::quiet_NaN();  // mm/min; NaN: use the scene's feed
  // False where n only stands in for a missing normal (APT CLDATA: the tool axis): `p` is then the cutter
  // location itself, which no axis moves.
  bool normal_known = true;
  Approach approach = Approach::ByGap;  // how the row before it reaches it
  int line = 0;                         // the line of the file it was read from (0: not read from a file)
  // The normal a flat or bull end keeps its contact by: n, or zero where it is not known.
  Eigen::Vector3d contact_normal() const { return normal_known ? n : Eigen::Vector3d::Zero(); }
};

struct ToolPath {
  std::vector<CLPoint> rows;
  // Cumulative arc length of the cutter locations, mm; arc_length()[0] == 0.
  std::vector<double> arc_length() const;
};

// Reads the path CSV (header x,y,z,nx,ny,nz[,feed], columns in any order, extra columns refused).
// Throws InputError with the line and column for a missing column, a bad number, NaN, a zero or
// non-unit normal (|n| off by more than 1e-3; normals within that are renormalised), or no rows.
ToolPath read_toolpath_csv(const std::filesystem::path& file);

// Reads APT CLDATA: GOTO/x,y,z[,i,j,k] (tool tip and axis), MULTAX[/ON|OFF], FEDRAT/f[,MMPM], RAPID
// (the next GOTO is a positioning move and is skipped; the row after it is linked to, Approach::Link; the
// others are cut, Approach::Cut), comments and other records ignored. The tool
// tip is converted to the cutter location with the tool's cl_height along the axis. CLDATA has no
// surface normal: the tool axis is taken as the normal (3-axis GOTO: +z). Continuation lines ending
// in '$' are joined.
ToolPath read_toolpath_apt(const std::filesystem::path& file, const Tool& tool);

// Dispatches on the extension: .cl/.apt to CLDATA, anything else to CSV.
ToolPath read_toolpath(const std::filesystem::path& file, const Tool& tool);

// Writes the path CSV (x,y,z,nx,ny,nz and feed when any row has one), 9 decimals, atomically.
void write_toolpath_csv(const ToolPath& path, const std::filesystem::path& file);

}  // namespace tf
