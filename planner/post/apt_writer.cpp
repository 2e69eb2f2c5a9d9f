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
    std::string last_feed;
    for (const OrientedRow& r : path.rows) {
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
