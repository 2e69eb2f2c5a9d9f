// The G-code reader's offsets, as LinuxCNC's interpreter keeps them: coordinate systems (G54 ... G59.3,
// G10 L2/L20), G92/G52 axis offsets, tool length offsets (G43 H, G43.4 H, G49) and reference returns
// (G28/G30). None of them moves the machine: the program's coordinates of the current point change
// instead. At the end of the program: axes the program had not set take the next value it gives them, and
// where tool length offsets are used, 3-axis and TCP targets become the tool tip.
#include <algorithm>
#include <cmath>
#include <limits>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/kinematics.hpp"

namespace tf::gcode {

Axes Reader::offset() const {
  Axes o{};
  for (int a = 0; a < 6; ++a) o[a] = st_.offsets[size_t(st_.cs)][a] + st_.g92[a];
  o[2] += st_.tlo;
  return o;
}

// Applies `change` to the offsets so that the machine stays where it is: the current point's program
// coordinates absorb the difference.
void Reader::set_offset_keeping_position(const std::function<void()>& change) {
  const Axes before = offset();
  change();
  const Axes after = offset();
  for (int a = 0; a < 6; ++a) st_.pos[a] += before[a] - after[a];
}

void Reader::select_coordinate_system(int key, int line) {
  const int index = work_offset_index(key);
  if (index < 0) throw InputError(file_, line, code_name('G', key), "not a coordinate system");
  if (!st_.defined[size_t(index)])
    warn(line, code_name('G', key), " is not in the scene's work_offsets: taken as zero (LinuxCNC's default)");
  set_offset_keeping_position([&] { st_.cs = index; });
}

// G92 (and G52): the current point gets the given coordinates; G92.1 and G92.2 drop the offsets (G92.1
// also the stored ones), G92.3 restores the stored ones. Only the named axes change.
void Reader::set_g92(int key, const Values& val, int line) {
  if (key == 920 || key == 520) {
    bool any = false;
    for (char c : std::string_view("XYZABC")) {
      if (!val.has(c)) continue;
      any = true;
      const int a = axis_index(c);
      const double v = length(c, *val[c]), old = st_.g92[a];
      if (key == 520) {  // G52: the offset itself
        st_.pos[a] += old - v;
        st_.g92[a] = v;
      } else {
        st_.g92[a] = st_.pos[a] + old - v;
        st_.pos[a] = v;
      }
    }
    if (!any) throw InputError(file_, line, code_name('G', key), "needs at least one axis word");
    st_.g92_saved = st_.g92;
    return;
  }
  set_offset_keeping_position([&] {
    if (key == 921 || key == 922) st_.g92 = Axes{};
    if (key == 921) st_.g92_saved = Axes{};
    if (key == 923) st_.g92 = st_.g92_saved;
  });
}

// G10 L2 P n: coordinate system n's offsets (P0: the current one); G10 L20 P n: the offsets that give the
// current point the named coordinates in system n. Tool table edits (L1, L10, L11) and rotation (R) are
// not simulated: an error.
void Reader::g10(const Values& val, int line) {
  const double l = val['L'].value_or(-1.0);
  if (l != 2 && l != 20)
    throw InputError(file_, line, "G10", "only G10 L2 and L20 (coordinate systems) are read; give tools in the scene");
  if (!val.has('P') || *val['P'] < 0 || *val['P'] > 9 || *val['P'] != std::floor(*val['P']))
    throw InputError(file_, line, "G10", "needs P, a coordinate system 0 ... 9");
  if (val.has('R') && *val['R'] != 0.0) throw InputError(file_, line, val.word('R'), "rotated coordinate systems are not supported");
  const int p = static_cast<int>(*val['P']);
  const size_t n = p == 0 ? size_t(st_.cs) : size_t(p - 1);
  set_offset_keeping_position([&] {
    for (char c : std::string_view("XYZABC")) {
      if (!val.has(c)) continue;
      const int a = axis_index(c);
      const double v = length(c, *val[c]);
      st_.offsets[n][a] = l == 2 ? v : st_.pos[a] + st_.offsets[size_t(st_.cs)][a] - v;
    }
    st_.defined[n] = true;
  });
}

// The gauge length G43 H takes for tool `number` (0: the tool in the spindle).
double Reader::tool_length(int number, int line, const std::string& word) const {
  if (number == 0) number = st_.tool;
  if (options_.tool_lengths.empty()) return options_.tool_length;
  if (number == 0) return st_.empty_spindle ? 0.0 : options_.tool_length;
  const auto it = options_.tool_lengths.find(number);
  if (it == options_.tool_lengths.end())
    throw InputError(file_, line, word, "tool " + std::to_string(number) + " is not in the scene's tools");
  return it->second;
}

// G43 [H n] and G43.4 [H n]: the tool length offset of tool n (without H, or H0, the tool in the
// spindle); G43.4 also switches tool-centre-point control on. G49 cancels both.
void Reader::tool_length_offset(int key, const Values& val, int line) {
  if (key == 431 || key == 432)
    throw InputError(file_, line, code_name('G', key), "dynamic and added tool length offsets are not supported");
  double t = 0.0;
  if (key == 430 || key == 434) {
    int h = 0;
    if (val.has('H')) {
      const double v = *val['H'];
      if (v < 0 || v > 99999 || v != std::floor(v)) throw InputError(file_, line, val.word('H'), "not a tool number");
      h = static_cast<int>(v);
    }
    t = tool_length(h, line, val.has('H') ? val.word('H') : code_name('G', key));
    uses_length_offsets_ = true;
  }
  // G43 and G49 end G43.4 (one modal group), not an M code's TCP: the tip is converted with the offset
  // it was programmed under, before that offset changes.
  if (key != 434 && st_.tcp_g434) set_tcp(false, false);
  set_offset_keeping_position([&] { st_.tlo = t; });
  if (key == 434) set_tcp(true, true);
}

// Across a switch of tool-centre-point control the controller holds the tool where it is and reports
// its place in the other mode's coordinates (LinuxCNC's switchkins demos expect exactly that: C at 90,
// joints X 10 Y 0 read as the tip at X 0 Y -10 after M428). The program position is converted so: on,
// the machine position's tip in the part frame (the TCP target's conventions, tool_tip_targets); off,
// the joints that put that tip there at the rotaries held. Returns false where it cannot (a 3-axis
// machine, or an axis not set yet), and the numbers are kept.
bool Reader::convert_position_for_tcp(bool on) {
  if (machine_.kinematics == KinematicsType::XYZ) return false;
  for (char c : "XYZ" + machine_.rotary_axes())
    if (st_.axes[size_t(axis_index(c))] != AxisState::Set) return false;
  const auto it = options_.tool_lengths.find(st_.tool);
  const double gauge = it != options_.tool_lengths.end() ? it->second : options_.tool_length;
  const Kinematics kin(machine_, gauge);
  const Axes off = offset();
  Joints j;
  for (int a = 0; a < 6; ++a) j.axis(a) = st_.pos[size_t(a)] + off[size_t(a)];
  // The tip of a TCP target P: P + work offset + G92 (off less the length offset along Z), moved by
  // offset - gauge along the axis where the program uses length offsets (tool_tip_targets).
  const Eigen::Vector3d axis = kin.forward(j).axis;
  const Eigen::Vector3d shift =
      Eigen::Vector3d(off[0], off[1], off[2] - st_.tlo) + (uses_length_offsets_ ? (st_.tlo - gauge) : 0.0) * axis;
  Eigen::Vector3d p;
  if (on) {
    p = kin.forward(j).tip - shift;
  } else {
    const Eigen::Vector3d tip = Eigen::Vector3d(st_.pos[0], st_.pos[1], st_.pos[2]) + shift;
    const Joints m = joints_for_tip([&](const Joints& q) { return kin.forward(q); }, j, tip);
    p = Eigen::Vector3d(m.x - off[0], m.y - off[1], m.z - off[2]);
  }
  for (int a = 0; a < 3; ++a) st_.pos[size_t(a)] = p[a];
  if (!uses_length_offsets_) tcp_converted_without_offsets_ = true;
  return true;
}

// G28/G30: a rapid to the intermediate point given by the axis words, then the named axes (all without
// words) go to the reference position, which the scene does not define: that move is not simulated and
// those axes count as not set until the program gives them a value again.
void Reader::reference_return(int key, const Values& val, int line) {
  const bool z_known = st_.axes[2] == AxisState::Set;
  bool words = false;
  for (char c : std::string_view("XYZABC")) words |= val.has(c);
  if (words) {
    // An increment from a position not set yet leads to an unknown point: no move is simulated then.
    bool known = true;
    for (char c : std::string_view("XYZABC"))
      if (val.has(c)) known &= st_.axes[axis_index(c)] == AxisState::Set || !st_.incremental;
    const Axes before = st_.pos;
    const auto axes_before = st_.axes;
    move_axes(val);
    if (known && (st_.pos != before || st_.axes != axes_before)) emit(Motion::Rapid, st_.pos, line);
  }
  // Z goes home first, straight up (a mill's reference height is at the top of its travel): a rapid to
  // the reference height, taken as the highest Z the program commands (fill_unknown_axes), so that what
  // follows traverses there and not at the next cutting depth.
  const bool z_rises = (!words || val.has('Z')) && z_known;
  if (z_rises) {
    st_.axes[2] = AxisState::SentHome;
    emit(Motion::Rapid, st_.pos, line);
  }
  for (char c : std::string_view("XYZABC"))
    if ((!words || val.has(c)) && (axis_index(c) < 3 || machine_.has_axis(c))) {
      st_.axes[axis_index(c)] = AxisState::SentHome;
      // The next block comes from the reference in this axis, which the scene lacks (Block::from_reference).
      if (c != 'Z' || !z_rises) from_reference_ = static_cast<unsigned char>(from_reference_ | (1u << axis_index(c)));
    }
  reference_line_ = line;
  warn(line, code_name('G', key),
       " reference return: the reference position is not in the scene; Z is taken there at the highest Z the"
       " program commands, the other axes sent there are next seen where the program positions them");
}

// Axes not set when a block was read take the value the program next gives them (the machine is taken
// to be there already); Z sent home is at the reference height, taken as the highest Z the program
// commands. Blocks whose other axes were sent home and never positioned again are dropped.
void Reader::fill_unknown_axes() {
  auto& blocks = program_.blocks;
  std::vector<bool> drop(blocks.size(), false);
  double z_home = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < blocks.size(); ++k)
    if (axes_[k][2] == AxisState::Set) z_home = std::max(z_home, blocks[k].target.z);
  for (size_t k = 0; k < blocks.size(); ++k)
    if (axes_[k][2] == AxisState::SentHome && std::isfinite(z_home)) {
      blocks[k].target.z = z_home;
      axes_[k][2] = AxisState::Set;
    }
  for (int a = 0; a < 6; ++a) {
    size_t b = 0;
    while (b < blocks.size()) {
      if (axes_[b][size_t(a)] == AxisState::Set) { ++b; continue; }
      size_t e = b;
      while (e < blocks.size() && axes_[e][size_t(a)] != AxisState::Set) ++e;
      for (size_t k = b; k < e; ++k) {
        if (e < blocks.size()) blocks[k].target.axis(a) = blocks[e].target.axis(a);
        else if (axes_[k][size_t(a)] == AxisState::SentHome) drop[k] = true;
      }
      b = e;
    }
  }
  drop_blocks_sent_home(drop);
}

void Reader::drop_blocks_sent_home(const std::vector<bool>& drop) {
  const size_t dropped = size_t(std::count(drop.begin(), drop.end(), true));
  if (dropped == 0) return;
  size_t k = 0;
  for (size_t b = 0; b < program_.blocks.size(); ++b) {
    if (drop[b]) continue;
    program_.blocks[k] = program_.blocks[b];
    block_tlo_[k] = block_tlo_[b];
    ++k;
  }
  program_.blocks.resize(k);
  block_tlo_.resize(k);
  const auto [file, line] = source_of(reference_line_);
  program_.warnings.push_back(file + ":" + std::to_string(line) + ": " + std::to_string(dropped) +
                              " motion blocks after the reference return move axes that stay at the reference"
                              " position: not simulated");
}

// With tool length offsets in use the machine position is the spindle nose's (LinuxCNC: the controlled
// point moves by the offset). A 5-axis joint program's targets already are (the kinematics add the gauge
// length); a 3-axis target becomes the tip, the loaded tool's gauge length below the nose, and a TCP
// target the tip the controller reaches: the point it tracks (nose minus the offset along Z) moved by
// offset - gauge length along the tool axis (zero when the offset is the loaded tool's own).
void Reader::tool_tip_targets() {
  if (!uses_length_offsets_) return;
  program_.xyz_nose_programmed = machine_.kinematics == KinematicsType::XYZ;
  program_.length_offsets = true;
  const Kinematics kin(machine_, 0.0);
  for (size_t b = 0; b < program_.blocks.size(); ++b) {
    Block& blk = program_.blocks[b];
    if (!blk.tcp && machine_.kinematics != KinematicsType::XYZ) continue;
    const auto it = options_.tool_lengths.find(blk.tool);
    const double gauge = it != options_.tool_lengths.end() ? it->second : options_.tool_length;
    Eigen::Vector3d delta(0.0, 0.0, -gauge);
    if (blk.tcp) {
      const Eigen::Vector3d axis = kin.forward(Joints{0, 0, 0, blk.target.a, blk.target.b, blk.target.c}).axis;
      delta = Eigen::Vector3d(0.0, 0.0, -block_tlo_[b]) + (block_tlo_[b] - gauge) * axis;
    }
    blk.target.x += delta.x();
    blk.target.y += delta.y();
    blk.target.z += delta.z();
    blk.arc_center += delta;
  }
}

Program Reader::finish() {
  if (st_.dwell > 0.0)
    program_.warnings.push_back(file_ + ": a dwell after the last motion block: its time is not counted");
  // rs274 refuses a program without an end; a file cut short in its transfer reads as one.
  if (!st_.ended && !program_.blocks.empty())
    program_.warnings.push_back(file_ + ": the file ends without M2, M30 or a closing %: is it cut short?");
  fill_unknown_axes();
  if (tcp_converted_without_offsets_ && uses_length_offsets_)
    program_.warnings.push_back(file_ + ": a switch of tool-centre-point control before the program's first tool length "
                                        "offset converted the position without one; the offsets that follow move TCP "
                                        "targets by offset - gauge length along the tool axis");
  tool_tip_targets();
  if (options_.start) program_.start = *options_.start;
  else if (!program_.blocks.empty()) program_.start = program_.blocks.front().target;
  return std::move(program_);
}

}  // namespace tf::gcode
