// tiltfield: a machining program as motion blocks in machine axes. Made by the post-processor (and then
// written as G-code) and by the G-code reader (then simulated by the verifier).
#pragma once
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "tiltfield/core/kinematics.hpp"

namespace tf {

enum class Motion { Rapid, Linear, ArcCW, ArcCCW };
enum class FeedMode { PerMinute, InverseTime };  // G94 mm/min, G93 1/min (block time = 1/F min)

struct Block {
  int line = 0;             // 1-based line in the G-code source, 0 for a generated block
  Motion motion = Motion::Linear;
  Joints target;            // axis values at the end of the block
  // When true, target.x/y/z are the tool tip in the part frame (tool-centre-point control active:
  // G43.4, M128 or the machine's configured code) and the tip moves linearly; otherwise they are
  // machine coordinates and every axis is interpolated linearly.
  bool tcp = false;
  FeedMode feed_mode = FeedMode::PerMinute;
  double feed = 0.0;        // mm/min (PerMinute) or 1/min (InverseTime); unused for rapids
  // G20 was in force: the line's words, its F under G94 included, are in inches (feed above is mm/min).
  bool inch = false;
  // Arcs (Motion::ArcCW/ArcCCW): centre in the same coordinates as target, and the plane (17, 18, 19).
  Eigen::Vector3d arc_center = Eigen::Vector3d::Zero();
  int plane = 17;
  double spindle_rpm = 0.0;
  // The tool in the spindle (the T of the last M6; before any, the scene's `tool`: 0 unless the scene's
  // library gives its number).
  int tool = 0;
  // Seconds the controller waits before this block moves (G4, a canned cycle's P at the hole bottom).
  double dwell_s = 0.0;
  // No F word on its line sets its feed: a G33/G33.1 move (K per spindle turn) or a block of a subroutine
  // file (its `line` is the program's call). A feed schedule leaves it as it is.
  bool fixed_feed = false;
  // Under G93, the share of the minutes of its line's F that this block takes (an arc of P turns: each
  // turn's; otherwise 1): its F is the line's F / time_share.
  double time_share = 1.0;
  // The axes (bit 0..5: X Y Z A B C) a reference return (G28/G30) sent to the reference position before
  // this block, which the scene does not know: the block starts at its own target in them, as a program's
  // first block does (the move from the reference is not simulated).
  unsigned char from_reference = 0;
};

struct Program {
  Joints start;                       // axis values before the first block
  std::vector<Block> blocks;          // motion blocks only
  std::vector<std::string> warnings;  // "file:line: ..." for codes read but not simulated
  // A 3-axis program that uses tool length offsets moves the spindle nose: its blocks' targets are the
  // tips, each a gauge length (of the block's tool) below the machine position the controller checks.
  bool xyz_nose_programmed = false;
  // The program uses tool length offsets (G43, G43.4): where its targets are tips (the blocks above, and
  // TCP blocks) a tool change leaves the spindle nose where it was, so the new tool's tip starts the
  // difference of the two gauge lengths along the tool axis from the old one's.
  bool length_offsets = false;
};

}  // namespace tf
