// RS274/NGC text for a posted program (LinuxCNC reads the joint dialect as is).
#include <algorithm>
#include <cmath>
#include <array>
#include <ostream>
#include <string>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/post/post.hpp"
#include "post_internal.hpp"

namespace tf {
namespace {

// Parentheses would end a comment early; keep comments to printable ASCII.
std::string comment(const std::string& text) {
  std::string s;
  for (unsigned char ch : text) {
    if (ch == '(') s += '[';
    else if (ch == ')') s += ']';
    else if (ch >= 32 && ch < 127) s += static_cast<char>(ch);
    else s += '?';
  }
  return "(" + s + ")";
}

struct TcpCodes {
  std::string on, off;
};

TcpCodes tcp_codes(const PostJob& job, const PostOptions& options) {
  if (!job.machine.tcp_on_code.empty()) return {job.machine.tcp_on_code, job.machine.tcp_off_code};
  const TcpStyle style = options.tcp_style.value_or(job.machine.tcp_style);
  if (style == TcpStyle::M128) return {"M128", "M129"};
  return {"G43.4 H" + std::to_string(options.tool_number), "G49"};
}

// F with `decimals` places, or as many more (up to 8) as a small feed needs for four significant digits
// (trailing zeros beyond `decimals` dropped). Rounded to two places a plunge at half of F0.01 had read
// F0.01, and G93's 9.97e-5 F0.0001 (black-box testing); a feed that read 0 a controller refuses ("Cannot
// do G1 with zero feed rate").
std::string feed_word(double feed, int decimals) {
  const int significant = feed > 0.0 && std::isfinite(feed) ? 3 - static_cast<int>(std::floor(std::log10(feed))) : decimals;
  std::string f = fixed(feed, std::clamp(significant, decimals, 8));
  const size_t point = f.find('.');
  while (point != std::string::npos && f.size() > point + 1 + size_t(decimals) && f.back() == '0') f.pop_back();
  if (!f.empty() && f.back() == '.') f.pop_back();
  if (!(std::stod(f) > 0.0))
    throw InputError("", 0, "feed", "a feed of " + std::to_string(feed) + " is too small to write (it reads as F0)");
  return f;
}

std::string describe_tool(const Tool& tool) {
  std::string s = "tool: " + std::string(tool.type_name()) + " radius " + fixed(tool.radius(), 4) + " gauge length " +
                  fixed(tool.length, 4) + " mm";
  return s;
}

}  // namespace

void write_gcode(std::ostream& out, const Program& program, const PostJob& job, const PostOptions& options) {
  const Dialect dialect = effective_dialect(options, job.machine);
  const bool tcp = dialect == Dialect::Tcp;
  const std::string rot = job.machine.rotary_axes();
  const TcpCodes codes = tcp_codes(job, options);

  out << "%\n" << comment(job.title) << "\n";
  out << comment("machine " + job.machine.name + ", kinematics " + std::string(to_string(job.machine.kinematics)) +
                 ", " + (tcp ? "tcp: X Y Z are the tool tip in the part frame" : "joint: machine coordinates"))
      << "\n";
  out << comment(describe_tool(job.tool) + (tcp || job.machine.kinematics == KinematicsType::XYZ
                                                 ? std::string()
                                                 : ", X Y Z are the spindle nose, no tool length offset"))
      << "\n";
  const bool offset = std::any_of(job.work_offset.begin(), job.work_offset.end(), [](double w) { return w != 0.0; });
  out << "G21 G90 G17 G40 G49 G80 G94" << (offset ? " G54" : "") << "\n";
  if (offset) {
    std::string w = "axis words relative to G54 (the scene's work offset";
    for (int k = 0; k < 6; ++k)
      if (job.work_offset[size_t(k)] != 0.0) w += std::string(" ") + "XYZABC"[k] + fixed(job.work_offset[size_t(k)], post_detail::kAxisDecimals);
    out << comment(w + ")") << "\n";
  }
  out << "T" << options.tool_number << " M6\n";
  out << "S" << fixed(options.spindle_rpm, 1) << " M3\n";
  if (tcp) {
    out << codes.on << "\n";
    // A TCP switched on by an M code tracks the point the tool length offset gives it (LinuxCNC's
    // switchkins take it from G43, as its own boat demo writes): without one the controlled point is the
    // spindle nose, and the tip would run a gauge length too deep. G43.4 carries its H.
    if (codes.on.rfind("G43.4", 0) != 0) out << "G43 H" << options.tool_number << "\n";
  }

  // Axis words as last written; empty = not written yet, so the first block that moves an axis names it.
  std::array<std::string, 6> last;
  const char letters[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};
  FeedMode mode = FeedMode::PerMinute;
  std::string last_feed;
  bool first = true;
  for (size_t i = 0; i < program.blocks.size(); ++i) {
    const Block& b = program.blocks[i];
    // The start's second block moves over the first point with the rotaries where the program found them
    // (assumed at the start's, 0; not written, which may lie outside a C axis' limits): the turn follows.
    const bool over_start = i == 1 && b.target.x == program.start.x && b.target.y == program.start.y &&
                            b.target.z == program.start.z && b.target.a == program.start.a &&
                            b.target.b == program.start.b && b.target.c == program.start.c;
    const double v[6] = {b.target.x - job.work_offset[0], b.target.y - job.work_offset[1],
                         b.target.z - job.work_offset[2], b.target.a - job.work_offset[3],
                         b.target.b - job.work_offset[4], b.target.c - job.work_offset[5]};
    std::string words;
    for (int k = 0; k < 6; ++k) {
      if (k >= 3 && rot.find(letters[k]) == std::string::npos) continue;
      if (first && k != 2) continue;  // the first move only lifts Z: the other axes' positions are unknown
      if (over_start && k >= 3) continue;
      const std::string w = fixed(v[k], post_detail::kAxisDecimals);
      if (w == last[k]) continue;
      last[k] = w;
      words += ' ';
      words += letters[k];
      words += w;
    }
    first = false;
    if (words.empty()) continue;
    if (b.motion == Motion::Rapid) {
      out << "G0" << words << "\n";
      continue;
    }
    std::string line;
    if (b.feed_mode != mode) {
      mode = b.feed_mode;
      line += mode == FeedMode::InverseTime ? "G93 " : "G94 ";
      last_feed.clear();
    }
    line += "G1" + words;
    const std::string f = feed_word(b.feed, mode == FeedMode::InverseTime ? 4 : 2);
    if (mode == FeedMode::InverseTime || f != last_feed) line += " F" + f;  // G93 wants F on every move
    last_feed = f;
    out << line << "\n";
  }
  if (mode != FeedMode::PerMinute) out << "G94\n";
  if (tcp && !codes.off.empty()) out << codes.off << "\n";
  if (tcp && codes.on.rfind("G43.4", 0) != 0) out << "G49\n";  // the G43 written beside an M-code TCP
  out << "M5\nM30\n%\n";
}

}  // namespace tf
