// The G-code reader's moves: straight moves (G0, G1, and G53's machine coordinates), arcs (G2, G3 with I J
// K or R, and P full turns) and the motion blocks they become, at the machine position.
#include <cmath>
#include <numbers>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::gcode {

namespace {
// The in-plane axes (u, v) of a plane and their centre-offset letters.
struct PlaneAxes {
  int u, v;
  char lu, lv;
};
PlaneAxes plane_axes(int plane) {
  if (plane == 18) return {2, 0, 'K', 'I'};
  if (plane == 19) return {1, 2, 'J', 'K'};
  return {0, 1, 'I', 'J'};
}
}  // namespace

void Reader::motion_block(int motion, bool g53, const Values& val, int line) {
  if (motion == 20 || motion == 30) {  // an arc starts where the tool is in its plane
    const PlaneAxes pa = plane_axes(st_.plane);
    assume_position(pa.u);
    assume_position(pa.v);
  }
  if (motion == 331)  // the tap comes back to where it started, which must be known
    for (char c : std::string_view("XYZABC"))
      if ((val.has(c) || ((c == 'X' || c == 'Y') && val.polar())) && st_.axes[size_t(axis_index(c))] != AxisState::Set)
        throw InputError(file_, line, "G33.1", std::string("rigid tapping from a ") + c + " position not set yet (it returns there)");
  // Across a switch of TCP the controller holds the tool where it is, in the other mode's coordinates
  // (tip or joints); the reader does not convert the position, so an axis the first block after the switch
  // does not write keeps its number from before, which means another place now.
  if (st_.tcp_switched) {
    st_.tcp_switched = false;
    std::string missing;
    for (char c : std::string_view("XYZ"))
      if (!val.has(c) || st_.incremental) missing += missing.empty() ? std::string(1, c) : std::string(" ") + c;
    if (!missing.empty() && !g53)
      warn(line, "", "the first motion after tool-centre-point control was switched does not write " + missing +
                         (st_.incremental ? " as absolute values (G91)" : "") +
                         ": taken as the numbers before the switch, not where the controller holds the tool");
    if (g53) st_.tcp_switched = true;  // G53's machine coordinates say nothing of the program's position
  }
  const Axes start = st_.pos;
  if (g53) {
    // G53: the axis words are machine coordinates for this block (the tool length offset included, as
    // LinuxCNC's interpreter takes them).
    if (motion != 0 && motion != 10) throw InputError(file_, line, "G53", "G53 needs G0 or G1");
    if (st_.incremental) throw InputError(file_, line, "G53", "G53 needs absolute distance mode (G90)");
    const Axes off = offset();
    for (char c : std::string_view("XYZABC")) {
      if (!val.has(c)) continue;
      const int a = axis_index(c);
      st_.pos[a] = length(c, *val[c]) - off[a];
      st_.axes[a] = AxisState::Set;
    }
  } else {
    move_axes(val);
  }
  if (motion == 0) {
    emit(Motion::Rapid, st_.pos, line);
    return;
  }
  if (motion == 330 || motion == 331) {
    spindle_synchronized(motion, start, val, line);
    return;
  }
  if (st_.inverse_time && !val.has('F'))
    throw InputError(file_, line, "F", "inverse-time feed (G93) needs F on every feed block");
  if (!st_.inverse_time && st_.feed <= 0.0) throw InputError(file_, line, "F", "feed block with no feed rate set");
  if (st_.inverse_time && st_.feed <= 0.0) throw InputError(file_, line, "F", "inverse-time feed must be positive");
  if (motion == 10) {
    emit(Motion::Linear, st_.pos, line);
    return;
  }
  arc(motion, start, st_.pos, val, line);
}

// Moves the position by the block's axis words (absolute or incremental, linear ones in program units).
Axes Reader::move_axes(const Values& val) {
  for (char c : std::string_view("XYZABC")) {
    if (!val.has(c)) continue;
    const int a = axis_index(c);
    const double v = length(c, *val[c]);
    if (st_.incremental) assume_position(a);
    st_.pos[a] = st_.incremental ? st_.pos[a] + v : v;
    st_.axes[a] = AxisState::Set;
  }
  if (val.polar()) polar_target(val, line_);
  return st_.pos;
}

// (x, y) moved by the block's @ and then its ^, each about the XY origin (LinuxCNC's order, in find_ends
// and in a cycle's repeats); `skip_zero`: a zero step is no step (the cycle loop's test), else any word
// given is one. A step from the origin has no direction.
void Reader::polar_step(double& x, double& y, const Values& val, bool skip_zero, int line) const {
  for (const char w : {'@', '^'}) {
    if (!val.has(w) || (skip_zero && *val[w] == 0.0)) continue;
    if (x == 0.0 && y == 0.0) throw InputError(file_, line, val.word(w), "incremental polar motion from the XY origin has no direction");
    const double r = std::hypot(x, y) + (w == '@' ? *val['@'] * unit() : 0.0);
    const double theta = std::atan2(y, x) + (w == '^' ? *val['^'] * std::numbers::pi / 180.0 : 0.0);
    x = r * std::cos(theta);
    y = r * std::sin(theta);
  }
}

// LinuxCNC's rules for @ and ^ (its interpreter's enhance_block): G17 only, never with X or Y, G53 or a
// code of the non-modal group that takes axis words (`axis_code`: G10, G28, G30, G52 or G92).
void Reader::check_polar(const Values& val, const std::optional<int>& axis_code, bool g53, int line) const {
  const std::string word = val.has('@') ? val.word('@') : val.word('^');
  if (st_.plane != 17) throw InputError(file_, line, word, "polar coordinates only in the G17 plane");
  for (char c : std::string_view("XY"))
    if (val.has(c)) throw InputError(file_, line, val.word(c), "polar coordinates (@, ^) and an " + std::string(1, c) + " word in one block");
  if (g53) throw InputError(file_, line, word, "polar coordinates cannot be used with G53");
  if (axis_code)
    throw InputError(file_, line, word, "polar coordinates can only be used for motion, not with " + code_name('G', *axis_code));
}

// X and Y from the block's polar words, about the XY origin of the current coordinate system (LinuxCNC's
// find_ends): absolute, @ the distance and ^ the angle (degrees, counterclockwise from +X), a word not
// given taken from the present position; incremental, @ and ^ added to the present position's.
void Reader::polar_target(const Values& val, int line) {
  const bool both = val.has('@') && val.has('^');
  if (st_.incremental || !both) {
    assume_position(0);
    assume_position(1);
  }
  const double deg = std::numbers::pi / 180.0;
  double& x = st_.pos[0];
  double& y = st_.pos[1];
  if (st_.incremental) {
    polar_step(x, y, val, false, line);
  } else {
    if (val.has('@') && !val.has('^') && x == 0.0 && y == 0.0)
      throw InputError(file_, line, val.word('@'), "polar distance without an angle at the XY origin");
    const double r = val.has('@') ? *val['@'] * unit() : std::hypot(x, y);
    const double theta = val.has('^') ? *val['^'] * deg : std::atan2(y, x);
    x = r * std::cos(theta);
    y = r * std::sin(theta);
  }
  st_.axes[0] = st_.axes[1] = AxisState::Set;
}

// G33 (a straight move at K per spindle turn) and G33.1 (rigid tapping: in to the target at K per turn,
// then back out to the start, I times as fast; LinuxCNC's RIGID_TAP). The feed is K times the spindle
// speed; the swept volume is the straight move's.
void Reader::spindle_synchronized(int motion, const Axes& start, const Values& val, int line) {
  const std::string name = code_name('G', motion);
  if (!val.has('K')) throw InputError(file_, line, name, "K (the distance per spindle turn) missing");
  if (!(*val['K'] > 0)) throw InputError(file_, line, val.word('K'), "the distance per spindle turn must be positive");
  if (st_.spindle_dir == 0) throw InputError(file_, line, name, "spindle not turning (M3 or M4 first)");
  if (!(st_.spindle > 0)) throw InputError(file_, line, name, "spindle speed S is zero");
  const double feed = st_.feed;
  const bool inverse_time = st_.inverse_time;
  st_.inverse_time = false;
  st_.feed = *val['K'] * unit() * st_.spindle;
  synchronized_ = true;
  emit(Motion::Linear, st_.pos, line);
  if (motion == 331) {
    st_.feed *= std::max(1.0, val['I'].value_or(1.0));
    st_.pos = start;  // LinuxCNC: the tap ends where it started
    emit(Motion::Linear, st_.pos, line);
  }
  synchronized_ = false;
  st_.feed = feed;
  st_.inverse_time = inverse_time;
}

// An axis the program has not positioned yet, where a block needs its position (an incremental word, an
// arc's start in its plane): where the tool is taken to be (program 0, as RS274/NGC starts), from the
// program's first block on, not the value the program gives it later (Reader::fill_unknown_axes).
void Reader::assume_position(int axis) {
  if (st_.axes[size_t(axis)] != AxisState::NotYet) return;
  const double machine = st_.pos[size_t(axis)] + offset()[size_t(axis)];
  for (size_t k = 0; k < program_.blocks.size(); ++k) {
    if (axes_[k][size_t(axis)] != AxisState::NotYet) continue;
    program_.blocks[k].target.axis(axis) = machine;
    axes_[k][size_t(axis)] = AxisState::Set;
  }
  st_.axes[size_t(axis)] = AxisState::Set;
}

// With a tool library every move needs a tool of the library in the spindle.
void Reader::check_tool(int line) const {
  if (options_.tool_lengths.empty()) return;
  if (st_.empty_spindle)
    throw InputError(file_, line, "T0", "motion with no tool in the spindle (T0 loaded at " +
                                             line_name(st_.tool_line) + ")");
  if (st_.tool != 0 && !options_.tool_lengths.count(st_.tool)) {
    std::string numbers;
    for (const auto& [n, length] : options_.tool_lengths) numbers += (numbers.empty() ? "" : ", ") + std::to_string(n);
    throw InputError(file_, line, "T" + std::to_string(st_.tool),
                     "tool " + std::to_string(st_.tool) + " (loaded at " + line_name(st_.tool_line) +
                         ") is not in the scene's tools (" + numbers + ")");
  }
}

// A motion block to `target` (program coordinates), at the machine position: + work offset, G92 offset
// and tool length offset. `centre`: an arc's centre in program coordinates.
void Reader::emit(Motion m, const Axes& target, int line, const Eigen::Vector3d* centre) {
  check_tool(line);
  const Axes off = offset();
  Block b;
  b.line = block_line(line);
  b.fixed_feed = synchronized_ || line > static_cast<int>(main_lines_);
  b.time_share = st_.inverse_time ? time_share_ : 1.0;
  b.motion = m;
  b.target = Joints{target[0] + off[0], target[1] + off[1], target[2] + off[2],
                    target[3] + off[3], target[4] + off[4], target[5] + off[5]};
  b.tcp = st_.tcp;
  b.feed_mode = st_.inverse_time ? FeedMode::InverseTime : FeedMode::PerMinute;
  b.feed = st_.feed;
  b.inch = st_.inch;
  b.spindle_rpm = st_.spindle;
  b.tool = st_.tool;
  b.plane = st_.plane;
  if (centre) b.arc_center = *centre + Eigen::Vector3d(off[0], off[1], off[2]);
  b.dwell_s = st_.dwell;
  st_.dwell = 0.0;
  // An arc's centre was found from where the reader held the tool, and a TCP block's X Y Z are a tip,
  // not the machine axes sent home: both start where the reader has them (from their own end, an arc
  // would be swept as a full circle).
  b.from_reference = (m == Motion::Rapid || m == Motion::Linear) && !st_.tcp ? from_reference_ : 0;
  from_reference_ = 0;
  program_.blocks.push_back(b);
  axes_.push_back(st_.axes);
  block_tlo_.push_back(st_.tlo);
}


// An R-form arc with R > 0 takes the short way round, never a full circle, but the simulation reads an arc whose end lies at its start's angle
// as one (a huge R over a tiny chord: R 1e8 over 0.1 um swept a whole band of the stock, found in
// review). Below 1e-9 rad the arc runs as its chord, r theta^2 / 8 from it: under 1e-9 mm for any R under
// 1e9 mm.
bool Reader::r_form_is_straight(const Axes& start, const Axes& end, const Eigen::Vector3d& c) const {
  const PlaneAxes pa = plane_axes(st_.plane);
  const Eigen::Vector2d a(start[pa.u] - c[pa.u], start[pa.v] - c[pa.v]), b(end[pa.u] - c[pa.u], end[pa.v] - c[pa.v]);
  return std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b))) < 1e-9;
}

// G2/G3 from `start` to `end`; with P n, n - 1 full turns come first (a helix shares its travel along the
// plane's normal and the rotaries by angle), each a block of its own.
void Reader::arc(int motion, const Axes& start, const Axes& end, const Values& val, int line) {
  const bool ccw = motion == 30;
  const Eigen::Vector3d c = arc_center(ccw, start, end, val, line);
  int turns = 1;
  if (val.has('P')) {
    const double p = *val['P'];
    if (!(p >= 1 && p <= 10000) || p != std::floor(p))
      throw InputError(file_, line, val.word('P'), "the turns of an arc must be a whole number from 1 to 10000");
    turns = static_cast<int>(p);
  }
  const Motion m = ccw ? Motion::ArcCCW : Motion::ArcCW;
  if (val['R'] && *val['R'] > 0 && turns == 1 && r_form_is_straight(start, end, c)) {
    emit(Motion::Linear, end, line);
    return;
  }
  if (turns > 1) {
    const PlaneAxes pa = plane_axes(st_.plane);
    const double two_pi = 2.0 * std::numbers::pi;
    const double as = std::atan2(start[pa.v] - c[pa.v], start[pa.u] - c[pa.u]);
    const double ae = std::atan2(end[pa.v] - c[pa.v], end[pa.u] - c[pa.u]);
    double sweep = std::fmod((ccw ? ae - as : as - ae) + 2.0 * two_pi, two_pi);
    if (sweep < 1e-9) sweep = two_pi;  // same start and end: a full circle
    const double total = sweep + two_pi * (turns - 1);
    // Under G93 F is one over the whole arc's minutes: each turn takes its share of them.
    const double feed = st_.feed;
    if (st_.inverse_time) st_.feed = feed * total / two_pi;
    time_share_ = two_pi / total;
    for (int k = 1; k < turns; ++k) {
      Axes p = start;
      const double f = two_pi * k / total;
      for (int a = 0; a < 6; ++a)
        if (a != pa.u && a != pa.v) p[a] = start[a] + f * (end[a] - start[a]);
      emit(m, p, line, &c);
    }
    if (st_.inverse_time) st_.feed = feed * total / sweep;
    time_share_ = sweep / total;
    emit(m, end, line, &c);
    time_share_ = 1.0;
    st_.feed = feed;
    return;
  }
  emit(m, end, line, &c);
}

namespace {
// rs274's radius tolerance, 0.00005 inch in either unit: half an R-form chord may exceed R by it, and an
// arc's radius must reach it (measured: a chord of 10.002 at R 5 is an arc, 10.003 is refused; a radius
// of 0.0013 is an arc, 0.0012 a "zero-radius arc").
constexpr double kRadiusTolerance = 0.00127;  // mm
}  // namespace

Eigen::Vector3d Reader::arc_center(bool ccw, const Axes& start, const Axes& end, const Values& val, int line) const {
  const PlaneAxes pa = plane_axes(st_.plane);
  Eigen::Vector3d c(start[0], start[1], start[2]);
  const auto R = val['R'];
  const auto ou = val[pa.lu], ov = val[pa.lv];
  if (R) {
    if (ou || ov) throw InputError(file_, line, "R", "give either R or the centre offsets, not both");
    const double r = *R * unit();
    const Eigen::Vector2d s2(start[pa.u], start[pa.v]), e2(end[pa.u], end[pa.v]);
    const double chord = (e2 - s2).norm();
    if (chord < 1e-9) throw InputError(file_, line, "R", "an R-form arc needs distinct start and end points");
    // rs274's zero-radius test is the centre form's only: an R arc is refused only at R0, whose centre it
    // makes NaN (a tiny R had been refused, black-box testing).
    if (r == 0.0) throw InputError(file_, line, "R", "arc radius is zero");
    if (std::abs(r) < chord / 2.0 - kRadiusTolerance)
      throw InputError(file_, line, "R", "radius is smaller than half the chord");
    const double h = std::sqrt(std::max(0.0, r * r - chord * chord / 4.0));
    const Eigen::Vector2d mid = 0.5 * (s2 + e2), dir = (e2 - s2) / chord;
    const Eigen::Vector2d left(-dir.y(), dir.x());
    // CCW with positive R: the centre is on the left of the chord; CW on the right; negative R flips.
    double side = ccw ? 1.0 : -1.0;
    if (r < 0) side = -side;
    const Eigen::Vector2d c2 = mid + side * h * left;
    c[pa.u] = c2.x();
    c[pa.v] = c2.y();
  } else {
    if (!ou && !ov) throw InputError(file_, line, std::string(1, pa.lu), "arc without centre offsets or R");
    // In absolute centre mode (G90.1) a missing word is no offset of 0 but a coordinate not given.
    if (!st_.arc_incremental && (!ou || !ov))
      throw InputError(file_, line, std::string(1, ou ? pa.lv : pa.lu), "G90.1 arcs need both centre coordinates");
    const double du = ou.value_or(0.0) * unit(), dv = ov.value_or(0.0) * unit();
    c[pa.u] = st_.arc_incremental ? start[pa.u] + du : (ou ? du : start[pa.u]);
    c[pa.v] = st_.arc_incremental ? start[pa.v] + dv : (ov ? dv : start[pa.v]);
    const double rs = std::hypot(start[pa.u] - c[pa.u], start[pa.v] - c[pa.v]);
    const double re = std::hypot(end[pa.u] - c[pa.u], end[pa.v] - c[pa.v]);
    // LinuxCNC's test: refused when the radii differ by more than the absolute tolerance and by more than
    // 0.1 % of the end radius too.
    if (std::abs(rs - re) > std::max(options_.arc_tolerance * (st_.inch ? 2.54 : 1.0), 1e-3 * re))
      throw InputError(file_, line, std::string(1, pa.lu), "start and end are not on one circle about the centre");
    if (rs < kRadiusTolerance || re < kRadiusTolerance)
      throw InputError(file_, line, std::string(1, pa.lu), "arc radius is zero (below 0.00127 mm, as rs274)");
  }
  return c;
}

}  // namespace tf::gcode
