// The G-code reader's splines, as LinuxCNC's interpreter reads them (convert_spline): G5, a cubic Bezier
// from the present point through the control points start + (I, J) and end + (P, Q) to the end (without I
// and J, the first control point mirrors the previous G5's second: smooth continuation); G5.1, a quadratic
// Bezier with the control point start + (I, J). XY plane only, no Z or rotary motion, no cutter
// compensation; like LinuxCNC they leave the motion mode as it was. The curve becomes straight feed moves
// (chords) that stay within kChordError of it, all with the block's line; under G93 the block's one F is
// shared by the chords in proportion to their length.
#include <algorithm>
#include <cmath>

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
  if (st_.inverse_time && !val.has('F')) throw InputError(file_, line, "F", "inverse-time feed (G93) needs F on every feed block");
  if (st_.feed <= 0.0) throw InputError(file_, line, "F", "feed block with no feed rate set");
  assume_position(0);
  assume_position(1);
  const Eigen::Vector2d p0(st_.pos[0], st_.pos[1]);
  Eigen::Vector2d first;  // start + (I, J), or the mirror of the previous G5's second control point
  if (val.has('I') != val.has('J'))
    throw InputError(file_, line, val.word(val.has('I') ? 'I' : 'J'), "give both I and J" + std::string(motion == 50 ? ", or neither" : ""));
  if (val.has('I')) {
    first = p0 + unit() * Eigen::Vector2d(*val['I'], *val['J']);
  } else if (motion == 50 && spline_mirror_) {
    first = p0 + *spline_mirror_;
  } else {
    throw InputError(file_, line, name, motion == 50 ? "I and J missing and no G5 before to continue from" : "I and J missing");
  }
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
    spline_mirror_ = -pq;
  } else {
    c[1] = p0 + 2.0 / 3.0 * (first - p0);
    c[2] = end + 2.0 / 3.0 * (first - end);
  }
  // n equal parameter steps keep chords within |B''|max / (8 n^2) of the curve; |B''| <= 6 max of the
  // control polygon's second differences.
  const double bend = 6.0 * std::max((c[0] - 2.0 * c[1] + c[2]).norm(), (c[1] - 2.0 * c[2] + c[3]).norm());
  const int n = std::clamp(static_cast<int>(std::ceil(std::sqrt(bend / (8.0 * kChordError)))), 1, kMaxChords);
  std::vector<Eigen::Vector2d> pts;
  for (int k = 1; k <= n; ++k) {
    const double t = double(k) / n, s = 1.0 - t;
    pts.push_back(s * s * s * c[0] + 3.0 * s * s * t * c[1] + 3.0 * s * t * t * c[2] + t * t * t * c[3]);
  }
  pts.back() = end;
  double total = 0.0;
  Eigen::Vector2d at = p0;
  for (const Eigen::Vector2d& p : pts) total += (p - at).norm(), at = p;
  const double feed = st_.feed;
  at = p0;
  for (const Eigen::Vector2d& p : pts) {
    const double len = (p - at).norm();
    if (st_.inverse_time) st_.feed = len > 0.0 ? feed * total / len : feed;  // the block's time by length
    st_.pos[0] = p.x();
    st_.pos[1] = p.y();
    emit(Motion::Linear, st_.pos, line);
    at = p;
  }
  st_.feed = feed;
}

}  // namespace tf::gcode
