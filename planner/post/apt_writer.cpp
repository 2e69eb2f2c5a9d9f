// APT CLDATA output: machine-neutral tool tips and axes for another post-processor.
#include <cmath>
#include <ostream>
#include <string>
#include <variant>

#include "post_internal.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/post/post.hpp"

namespace tf {
namespace {

std::string goto_line(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis) {
  return "GOTO/" + fixed(tip.x(), 4) + "," + fixed(tip.y(), 4) + "," + fixed(tip.z(), 4) + "," + fixed(axis.x(), 7) + "," +
         fixed(axis.y(), 7) + "," + fixed(axis.z(), 7);
}

// APT CUTTER/d,r: diameter and corner radius.
std::string cutter(const Tool& tool) {
  const double r = tool.radius();
  double corner = 0.0;
  if (std::holds_alternative<BallCutter>(tool.cutter)) corner = r;
  if (const auto* bull = std::get_if<BullCutter>(&tool.cutter)) corner = bull->corner_radius;
  return "CUTTER/" + fixed(2.0 * r, 4) + "," + fixed(corner, 4);
}

}  // namespace

void write_apt(std::ostream& out, const OrientedPath& path, const PostJob& job, const PostOptions& options) {
  Eigen::AlignedBox3d bounds = job.part_bounds;
  for (const OrientedRow& r : path.rows) {
    bounds.extend(r.p);
    bounds.extend(row_tip(r, job.tool));
  }
  // The retract point clears the part along the tool axis, as in the G-code dialects.
  auto clear = [&](const OrientedRow& r) {
    const Eigen::Vector3d axis = r.axis.normalized(), tip = row_tip(r, job.tool);
    const double lift = std::max(0.0, post_detail::max_projection(bounds, axis) - tip.dot(axis)) + job.machine.safe_z;
    return goto_line(tip + lift * axis, axis);
  };
  std::string title;
  for (unsigned char ch : job.title) title += (ch >= 32 && ch < 127 && ch != ',') ? static_cast<char>(ch) : ' ';
  out << "PARTNO/" << title << "\n";
  out << "$$ tool tip and unit tool axis (tip toward spindle) in the part frame, mm\n";
  out << "UNITS/MM\n";
  out << "MULTAX/ON\n";
  out << cutter(job.tool) << "\n";
  out << "LOADTL/" << options.tool_number << "\n";
  out << "SPINDL/RPM," << fixed(options.spindle_rpm, 1) << ",CLW\n";
  if (!path.rows.empty()) {
    out << "RAPID\n" << clear(path.rows.front()) << "\n";
    // Rows linked to (farther apart than the link gap, or after an input APT's RAPID) are linked as the
    // G-code dialects link them (not cut through):
    // retract from the last row along its axis, rapid to above the next one, and feed down onto it. The
    // retract points clear the part's extent (APT carries no machine, so no checked transit is made).
    const double link_gap = effective_link_gap(options, job.tool);
    std::string last_feed;
    for (size_t k = 0; k < path.rows.size(); ++k) {
      const OrientedRow& r = path.rows[k];
      if (k > 0 && linked_to(r.approach, (row_tip(r, job.tool) - row_tip(path.rows[k - 1], job.tool)).norm(), link_gap)) {
        out << "RAPID\n" << clear(path.rows[k - 1]) << "\n";
        out << "RAPID\n" << clear(r) << "\n";
      }
      const std::string f = fixed(std::min(std::isnan(r.feed) ? job.feed : r.feed, job.machine.max_feed), 2);
      if (f != last_feed) out << "FEDRAT/" << f << ",MMPM\n";
      last_feed = f;
      out << goto_line(row_tip(r, job.tool), r.axis.normalized()) << "\n";
    }
    out << "RAPID\n" << clear(path.rows.back()) << "\n";
  }
  out << "SPINDL/OFF\nEND\nFINI\n";
}

}  // namespace tf
