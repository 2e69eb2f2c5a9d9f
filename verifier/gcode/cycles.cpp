// The G-code reader's canned cycles, expanded into the moves LinuxCNC's interpreter makes (its G-code
// reference, "G80-G89 Canned Cycles"): G73 G74 G81 G82 G83 G84 G85 G86 G89 in the selected plane, with
// sticky R, Z, P and Q, G98/G99 retract, L repeats and G91 increments, and polar hole positions (@, ^).
// Dwells become the next block's Block::dwell_s. Spindle reversal and stops do not change the swept volume and are not modelled.
#include <cmath>
#include <numbers>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::gcode {
namespace {

// LinuxCNC's peck clearance of G73 and G83 (0.010 inch), mm.
constexpr double kPeckClearance = 0.254;
constexpr double kMaxCycleMoves = 10000;

// The axes of a plane in LinuxCNC's cycle order: the two in the plane, then the one along the hole.
std::array<int, 3> cycle_axes(int plane) {
  if (plane == 18) return {2, 0, 1};  // G18: aa = Z, bb = X, along Y
  if (plane == 19) return {1, 2, 0};  // G19: aa = Y, bb = Z, along X
  return {0, 1, 2};
}

}  // namespace

void Reader::cycle_move(bool feed, const std::array<int, 3>& axes, double a, double b, double c, int line) {
  st_.pos[axes[0]] = a;
  st_.pos[axes[1]] = b;
  st_.pos[axes[2]] = c;
  st_.axes[axes[2]] = AxisState::Set;
  emit(feed ? Motion::Linear : Motion::Rapid, st_.pos, line);
}

void Reader::canned_cycle(int motion, const Values& val, int line) {
  const std::string name = code_name('G', motion);
  if (st_.feed <= 0.0) throw InputError(file_, line, name, "canned cycle with no feed rate set");
  if (st_.inverse_time) throw InputError(file_, line, name, "canned cycles cannot run with inverse-time feed (G93)");
  for (char c : std::string_view("ABC"))
    if (val.has(c)) throw InputError(file_, line, val.word(c), "rotary axis words are not allowed in a canned cycle");
  const std::array<int, 3> ax = cycle_axes(st_.plane);
  const char la = "XYZ"[ax[0]], lb = "XYZ"[ax[1]], lc = "XYZ"[ax[2]];
  const bool same = st_.motion == motion;  // the same cycle already in force: R, Z, P, Q are sticky
  if (!val.has('R') && !same) throw InputError(file_, line, name, "R (the retract plane) missing");
  const double r_number = val.has('R') ? *val['R'] : st_.cycle_r, r_word = r_number * unit();
  if (!val.has(lc) && !same) throw InputError(file_, line, name, std::string(1, lc) + " (the hole bottom) missing");
  const double cc_number = val.has(lc) ? *val[lc] : st_.cycle_cc, cc_word = cc_number * unit();
  int repeats = 1;
  if (val.has('L')) {
    const double l = *val['L'];
    if (!(l >= 1) || l != std::floor(l)) throw InputError(file_, line, val.word('L'), "repeats must be a whole number >= 1");
    // rs274 takes any count; the reader's bound on one block's moves is what refuses it (the message had
    // said "a whole number >= 1" of L100000, black-box testing).
    if (l > 10000)
      throw InputError(file_, line, val.word('L'), "more than 10 000 repeats: a block expands into at most 10 000 moves here");
    repeats = static_cast<int>(l);
  }
  double p = st_.cycle_p, q_number = st_.cycle_q;
  if (motion == 820 || motion == 860 || motion == 890 || motion == 840 || motion == 740) {
    if (val.has('P')) p = *val['P'];
    else if (!same && motion != 840 && motion != 740) throw InputError(file_, line, name, "P (the dwell) missing");
    if (p < 0) throw InputError(file_, line, val.word('P'), "negative dwell");
  }
  if (motion == 730 || motion == 830) {
    if (val.has('Q')) q_number = *val['Q'];
    else if (!same) throw InputError(file_, line, name, "Q (the peck depth) missing");
    if (!(q_number > 0)) throw InputError(file_, line, val.word('Q'), "the peck depth must be positive");
  }
  const double q = q_number * unit();
  if (motion == 840 && st_.spindle_dir != 1) throw InputError(file_, line, name, "G84 needs the spindle turning clockwise (M3)");
  if (motion == 740 && st_.spindle_dir != -1) throw InputError(file_, line, name, "G74 needs the spindle turning counterclockwise (M4)");
  if (motion == 860 && st_.spindle_dir == 0) throw InputError(file_, line, name, "G86 needs the spindle turning");

  if (st_.axes[ax[2]] != AxisState::Set) {
    // The height the tool comes from is unknown: in absolute G99 it only joins the R plane; otherwise
    // the cycle's moves depend on it.
    if (st_.incremental || !st_.retract_r_plane)
      throw InputError(file_, line, name, "canned cycle with the " + std::string(1, lc) + " position not set yet (G98 or G91 need it)");
    st_.pos[ax[2]] = r_word;
    st_.axes[ax[2]] = AxisState::Set;
  }
  double current_cc = st_.pos[ax[2]];
  double old_cc;
  if (st_.cycle_il_flag) {
    old_cc = st_.cycle_il * unit();
  } else {
    old_cc = current_cc;
    st_.cycle_il = current_cc / unit();
    st_.cycle_il_flag = true;
  }
  double a_inc = 0.0, b_inc = 0.0, r = r_word, bottom = cc_word;
  double a = val.has(la) ? length(la, *val[la]) : st_.pos[ax[0]];
  double b = val.has(lb) ? length(lb, *val[lb]) : st_.pos[ax[1]];
  // Polar words (G17 only): absolute, the hole's distance and angle about the XY origin, a word not given
  // taken from the present position; incremental, added to the polar position before each repeat.
  if (val.polar()) {
    if (st_.incremental || !val.has('@') || !val.has('^')) {  // the present position is needed
      assume_position(0);
      assume_position(1);
    }
    if (!st_.incremental) {
      const double rho = val.has('@') ? *val['@'] * unit() : std::hypot(st_.pos[1], st_.pos[0]);
      const double theta = val.has('^') ? *val['^'] * std::numbers::pi / 180.0 : std::atan2(st_.pos[1], st_.pos[0]);
      a = rho * std::cos(theta);
      b = rho * std::sin(theta);
    }
  }
  if (st_.incremental) {
    // X, Y (in the plane) and R are increments from the current point, the bottom from R.
    a_inc = val.has(la) ? length(la, *val[la]) : 0.0;
    b_inc = val.has(lb) ? length(lb, *val[lb]) : 0.0;
    r = r_word + old_cc;
    bottom = r + cc_word;
    a = st_.pos[ax[0]];
    b = st_.pos[ax[1]];
  }
  if (r < bottom) throw InputError(file_, line, "R", "the retract plane R is below the hole bottom");
  if (old_cc < r) {  // below the R plane: up to it first
    cycle_move(false, ax, st_.pos[ax[0]], st_.pos[ax[1]], r, line);
    old_cc = r;
    current_cc = old_cc;
  }
  const double clear = st_.retract_r_plane ? r : old_cc;
  // A block expands into at most kMaxCycleMoves moves: a tiny Q or a huge L is a mistake, not a program.
  const double pecks = motion == 730 || motion == 830 ? std::ceil((r - bottom) / q) : 0.0;
  if (!(repeats * (4.0 + 3.0 * pecks) <= kMaxCycleMoves))
    throw InputError(file_, line, name, "the cycle expands into more than " + std::to_string(int(kMaxCycleMoves)) +
                                            " moves (check Q and L)");
  if (val.has(la) || val.polar()) st_.axes[ax[0]] = AxisState::Set;
  if (val.has(lb) || val.polar()) st_.axes[ax[1]] = AxisState::Set;
  for (int rep = repeats; rep > 0; --rep) {
    a += a_inc;
    b += b_inc;
    if (st_.incremental) polar_step(a, b, val, true, line);  // LinuxCNC's CYCLE_MACRO
    if (rep == repeats && current_cc > r) {
      cycle_move(false, ax, a, b, current_cc, line);
      cycle_move(false, ax, a, b, r, line);
    } else {
      cycle_move(false, ax, a, b, clear, line);
      if (clear > r) cycle_move(false, ax, a, b, r, line);
    }
    switch (motion) {
      case 730: case 830: {
        // LinuxCNC's loop, with its accumulated depth; the count guards against a Q too small to progress.
        int count = 0;
        for (double depth = r - q; depth > bottom; depth -= q) {
          if (++count > pecks + 2) throw InputError(file_, line, name, "the peck depth Q is too small to progress");
          cycle_move(true, ax, a, b, depth, line);
          if (motion == 830) cycle_move(false, ax, a, b, r, line);
          cycle_move(false, ax, a, b, depth + kPeckClearance, line);
        }
        cycle_move(true, ax, a, b, bottom, line);
        cycle_move(false, ax, a, b, clear, line);
        break;
      }
      case 850:
        cycle_move(true, ax, a, b, bottom, line);
        cycle_move(true, ax, a, b, r, line);
        cycle_move(false, ax, a, b, clear, line);
        break;
      default: {  // G81, G82, G86 (rapid out); G74, G84, G89 (feed out); a dwell at the bottom but G81's
        cycle_move(true, ax, a, b, bottom, line);
        if (motion != 810) st_.dwell += p;
        const bool feed_out = motion == 740 || motion == 840 || motion == 890;
        cycle_move(feed_out, ax, a, b, clear, line);
      }
    }
  }
  st_.cycle_cc = cc_number;
  st_.cycle_r = r_number;
  st_.cycle_p = p;
  st_.cycle_q = q_number;
}

}  // namespace tf::gcode
