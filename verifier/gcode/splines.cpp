// The G-code reader's splines, as LinuxCNC's interpreter reads them (convert_spline): G5, a cubic Bezier
// from the present point through the control points start + (I, J) and end + (P, Q) to the end (without I
// and J, the first control point mirrors the previous G5's second: smooth continuation); G5.1, a quadratic
// Bezier with the control point start + (I, J). XY plane only, no Z or rotary motion, no cutter
// compensation; like LinuxCNC they leave the motion mode as it was. The curve becomes straight feed moves
// (chords) that stay within kChordError of it, all with the block's line. Refused under G93: LinuxCNC
// applies no inverse-time F to a spline (it runs at the feed rate last set), which is not what the
// program says.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::gcode {
namespace {

// How far a chord may stand off the spline, mm: well below any sweep tolerance, so the chords are the curve.
constexpr double kChordError = 5e-4;
constexpr int kMaxChords = 100000;

}  // namespace

void Reader::spline(int motion, const Values& val, int line) {
  const std::string name = code_name('G', motion);
  if (st_.plane != 17) throw InputError(file_, line, name, "splines must be in the XY plane (G17)");
  if (st_.cutter_comp) throw InputError(file_, line, name, "a spline cannot run with cutter compensation on");
  for (char c : std::string_view("ZABC"))
    if (val.has(c)) throw InputError(file_, line, val.word(c), "splines may not move Z, A, B or C");
  if (st_.inverse_time)
    throw InputError(file_, line, name, "a spline under inverse-time feed (G93): LinuxCNC does not apply its F (G94 first)");
  if (st_.feed <= 0.0) throw InputError(file_, line, "F", "feed block with no feed rate set");
  assume_position(0);
  assume_position(1);
  const Eigen::Vector2d p0(st_.pos[0], st_.pos[1]);
  if (val.has('I') != val.has('J'))
    throw InputError(file_, line, val.word(val.has('I') ? 'I' : 'J'), "give both I and J" + std::string(motion == 50 ? ", or neither" : ""));
  if (motion == 51 && !val.has('I')) throw InputError(file_, line, name, "I and J missing");
  // start + (I, J); for G5 without them, the previous G5's -P, -Q as written (LinuxCNC's cycle_i and
  // cycle_j, 0 before any G5), in the present units.
  const Eigen::Vector2d first =
      p0 + unit() * (val.has('I') ? Eigen::Vector2d(*val['I'], *val['J']) : spline_mirror_);
  if (motion == 50 && !(val.has('P') && val.has('Q')))
    throw InputError(file_, line, name, "G5 needs both P and Q (the second control point from the end)");
  move_axes(val);
  const Eigen::Vector2d end(st_.pos[0], st_.pos[1]);
  // Bezier control points (a quadratic raised to a cubic, so one evaluation serves both).
  Eigen::Vector2d c[4];
  c[0] = p0;
  c[3] = end;
  if (motion == 50) {
    const Eigen::Vector2d pq = unit() * Eigen::Vector2d(*val['P'], *val['Q']);
    c[1] = first;
    c[2] = end + pq;
    spline_mirror_ = -Eigen::Vector2d(*val['P'], *val['Q']);
  } else {
    c[1] = p0 + 2.0 / 3.0 * (first - p0);
    c[2] = end + 2.0 / 3.0 * (first - end);
  }
  // n equal parameter steps keep chords within |B''|max / (8 n^2) of the curve; |B''| <= 6 max of the
  // control polygon's second differences.
  const double bend = 6.0 * std::max((c[0] - 2.0 * c[1] + c[2]).norm(), (c[1] - 2.0 * c[2] + c[3]).norm());
  const int n = static_cast<int>(std::clamp(std::ceil(std::sqrt(bend / (8.0 * kChordError))), 1.0, double(kMaxChords)));
  std::vector<Eigen::Vector2d> pts;
  for (int k = 1; k <= n; ++k) {
    const double t = double(k) / n, s = 1.0 - t;
    pts.push_back(s * s * s * c[0] + 3.0 * s * s * t * c[1] + 3.0 * s * t * t * c[2] + t * t * t * c[3]);
  }
  pts.back() = end;
  for (const Eigen::Vector2d& p : pts) {
    st_.pos[0] = p.x();
    st_.pos[1] = p.y();
    emit(Motion::Linear, st_.pos, line);
  }
}

}  // namespace tf::gcode
