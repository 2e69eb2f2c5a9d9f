// Canned cycles against the moves LinuxCNC's G-code reference spells out (its G81 examples), their dwells
// and the programs LinuxCNC refuses. rs274 judges many more cycles in test_rs274_judge.cpp.
#include <gtest/gtest.h>

#include "gcode_test_util.hpp"

namespace tf {
namespace {

using test::expect_gcode_error;
using test::parse_program;

void expect_cycle_moves(const Program& p, size_t first, const std::vector<std::array<double, 4>>& moves) {
  ASSERT_GE(p.blocks.size(), first + moves.size());
  for (size_t i = 0; i < moves.size(); ++i) {
    const Block& b = p.blocks[first + i];
    EXPECT_NEAR(b.target.x, moves[i][0], 1e-12) << "move " << i;
    EXPECT_NEAR(b.target.y, moves[i][1], 1e-12) << "move " << i;
    EXPECT_NEAR(b.target.z, moves[i][2], 1e-12) << "move " << i;
    EXPECT_EQ(b.motion == Motion::Linear, moves[i][3] == 1.0) << "move " << i;
  }
}

// "Example 1 - Absolute Position G81": G90 G98 G81 X4 Y5 Z1.5 R2.8 from (1, 2, 3).
TEST(GcodeCycles, AbsoluteG81AsLinuxcncDocumentsIt) {
  const Program p = parse_program("G0 X1 Y2 Z3\nG90 G98 G81 X4 Y5 Z1.5 R2.8 F10\n");
  ASSERT_EQ(p.blocks.size(), 5u);
  expect_cycle_moves(p, 1, {{4, 5, 3, 0}, {4, 5, 2.8, 0}, {4, 5, 1.5, 1}, {4, 5, 3, 0}});
}

// "Example 2 - Relative Position G81": G91 G98 G81 X4 Y5 Z-0.6 R1.8 L3 from (1, 2, 3): clear Z 4.8,
// bottom 4.2, holes at (5, 7), (9, 12), (13, 17).
TEST(GcodeCycles, IncrementalRepeatsAsLinuxcncDocumentsThem) {
  const Program p = parse_program("G0 X1 Y2 Z3\nG91 G98 G81 X4 Y5 Z-0.6 R1.8 L3 F10\n");
  ASSERT_EQ(p.blocks.size(), 1u + 1u + 3u * 3u);
  expect_cycle_moves(p, 1,
               {{1, 2, 4.8, 0}, {5, 7, 4.8, 0}, {5, 7, 4.2, 1}, {5, 7, 4.8, 0}, {9, 12, 4.8, 0}, {9, 12, 4.2, 1},
                {9, 12, 4.8, 0}, {13, 17, 4.8, 0}, {13, 17, 4.2, 1}, {13, 17, 4.8, 0}});
}

// G83 pecks Q deep, out to R and back in to 0.254 mm above the last depth; G82's dwell is the time the
// retract waits for; G99 (LinuxCNC's default) retracts to R, G98 to the level the series began at.
TEST(GcodeCycles, PeckDrillingDwellAndRetractModes) {
  const Program p = parse_program("G0 X0 Y0 Z10\nG83 X1 Y1 Z-5 R1 Q2.5 F100\nG98 G82 X2 Z-1 R2 P1.5\nG80\n");
  // G83: to (1,1) at 10, down to R 1, feed -1.5, out 1, in -1.246, feed -4, out 1, in -3.746, feed -5, out 1.
  expect_cycle_moves(p, 1,
               {{1, 1, 10, 0}, {1, 1, 1, 0}, {1, 1, -1.5, 1}, {1, 1, 1, 0}, {1, 1, -1.246, 0}, {1, 1, -4, 1},
                {1, 1, 1, 0}, {1, 1, -3.746, 0}, {1, 1, -5, 1}, {1, 1, 1, 0}});
  // G98 in the same series: the initial level is still 10 (the series began there), so clear Z is 10.
  const size_t g82 = 11;
  expect_cycle_moves(p, g82, {{2, 1, 10, 0}, {2, 1, 2, 0}, {2, 1, -1, 1}, {2, 1, 10, 0}});
  EXPECT_DOUBLE_EQ(p.blocks[g82 + 3].dwell_s, 1.5);  // waited at the bottom before the retract
  EXPECT_DOUBLE_EQ(p.blocks[g82 + 2].dwell_s, 0.0);
}

TEST(GcodeCycles, StickyWordsAndThePlaneOfTheHole) {
  // R, Z and Q stay for the same cycle; G18 drills along Y with Z X in the plane.
  const Program p = parse_program("G0 X0 Y10 Z0\nG18 G81 Z4 X6 Y-2 R3 F90\nX8\n");
  ASSERT_EQ(p.blocks.size(), 1u + 4u + 3u);
  EXPECT_NEAR(p.blocks[3].target.y, -2, 1e-12);
  EXPECT_NEAR(p.blocks[3].target.x, 6, 1e-12);
  EXPECT_NEAR(p.blocks[3].target.z, 4, 1e-12);
  EXPECT_NEAR(p.blocks[6].target.y, -2, 1e-12);
  EXPECT_NEAR(p.blocks[6].target.x, 8, 1e-12);
}

// rs274 takes L100000; the reader's bound on one block's moves refuses it, and says so (it had said "a
// whole number >= 1", black-box testing).
TEST(GcodeCycles, TooManyRepeatsNameTheBound) {
  try {
    parse_program("G0 X0 Y0 Z5\nG81 X0 Y0 Z-1 R1 L100000 F100\n", {}, MachineSpec{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "L100000");
    EXPECT_NE(std::string(e.what()).find("10 000"), std::string::npos) << e.what();
  }
}

TEST(GcodeCycles, ProgramsLinuxcncRefuses) {
  expect_gcode_error("G0 X0 Y0 Z5\nG81 X1 Y1 Z-1 F100\n", 2, "G81");               // no R
  expect_gcode_error("G0 X0 Y0 Z5\nG81 X1 Y1 R1 F100\n", 2, "G81");                // no Z
  expect_gcode_error("G0 X0 Y0 Z5\nG83 X1 Y1 Z-1 R1 F100\n", 2, "G83");            // no Q
  expect_gcode_error("G0 X0 Y0 Z5\nG83 X1 Y1 Z-1 R1 Q0 F100\n", 2, "Q0");          // Q not positive
  expect_gcode_error("G0 X0 Y0 Z5\nG82 X1 Y1 Z-1 R1 F100\n", 2, "G82");            // no P
  expect_gcode_error("G0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 L0 F100\n", 2, "L0");          // zero repeats
  expect_gcode_error("G0 X0 Y0 Z5\nG81 X1 Y1 Z2 R1 F100\n", 2, "R");               // R below the bottom
  expect_gcode_error("G0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1\n", 2, "G81");                 // no feed
  expect_gcode_error("G0 X0 Y0 Z5\nG93 G81 X1 Y1 Z-1 R1 F100\n", 2, "G81");        // inverse time
  expect_gcode_error("G0 X0 Y0 Z5\nM5 G84 X1 Y1 Z-1 R1 F100\n", 2, "G84");         // tapping without M3
  expect_gcode_error("G0 X0 Y0 Z5\nG81 F100\n", 2, "G81");                         // no axis words
  expect_gcode_error("G0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 F100\nG80\nX3\n", 4, "G80");  // axis words after G80
  expect_gcode_error("G0 X0 Y0 Z5\nG87 X1 Y1 Z-1 R1 F100\n", 2, "G87");            // not supported
  const MachineSpec ac = [] {
    MachineSpec m;
    m.kinematics = KinematicsType::TableTableAC;
    return m;
  }();
  try {
    parse_program("G0 X0 Y0 Z5 A0\nG81 X1 Y1 Z-1 R1 A5 F100\n", {}, ac);
    FAIL() << "a rotary word in a cycle was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "A5");
  }
}

// A block expands into at most 10 000 moves: a tiny Q or a huge L is refused before it fills the memory.
TEST(GcodeCycles, ExpansionsAreBounded) {
  expect_gcode_error("G0 X0 Y0 Z5\nG83 X1 Y1 Z-100 R1 Q0.001 F100\n", 2, "G83");
  expect_gcode_error("G0 X0 Y0 Z5\nG91 G81 X1 Y0 Z-1 R1 L5000 F100\n", 2, "G81");
  EXPECT_EQ(parse_program("G0 X0 Y0 Z5\nG91 G81 X1 Y0 Z-1 R1 L1000 F100\n").blocks.size(), 1u + 1u + 3000u);
}

}  // namespace
}  // namespace tf
