// The reader's motion judged by LinuxCNC's interpreter (rs274 -g): for programs with work offsets from
// the scene (rs274: its .var file), G10 L2/L20, G92, G53, a tool library with G43 H / G43 / G49 (rs274:
// its tool table), canned cycles (G73 G74 G81-G86 G89, G98/G99, L repeats, G91, G18/G19 planes) and dwells,
// every motion block must end where rs274's canonical move ends (plus the offsets it reports), be a feed
// or a rapid as there, and carry the dwell rs274 makes before it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rs274_judge.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace tf {
namespace {

// A table-table AC machine run as joint axes: its targets are the machine positions LinuxCNC commands
// (tool length offset included), so they compare one to one.
MachineSpec trt_joint() {
  MachineSpec m;
  m.name = "trt";
  m.kinematics = KinematicsType::TableTableAC;
  return m;
}

struct Judged {
  Program program;
  test::Rs274Run rs;
};

Judged judge(const std::string& text, const GcodeOptions& options, const MachineSpec& machine) {
  test::TempDir dir;
  std::map<int, std::array<double, 6>> systems;
  const auto& codes = work_offset_codes();
  for (size_t i = 0; i < codes.size(); ++i) {
    const auto it = options.work_offsets.find(codes[i]);
    systems[int(i) + 1] = it == options.work_offsets.end() ? std::array<double, 6>{} : it->second;
  }
  Judged j;
  j.rs = test::run_rs274(dir, text, test::rs274_tool_table(options.tool_lengths), test::rs274_var_file(systems));
  j.program = parse_gcode(text, "judge.ngc", machine, options);
  return j;
}

void expect_same_motion(const Judged& j, const std::string& what, double shift_z = 0.0) {
  ASSERT_EQ(j.rs.exit_code, 0) << what << ": rs274 refused the program:\n" << j.rs.output.substr(0, 3000);
  ASSERT_EQ(j.program.blocks.size(), j.rs.moves.size()) << what << "\n" << j.rs.output.substr(0, 6000);
  for (size_t i = 0; i < j.rs.moves.size(); ++i) {
    const Block& b = j.program.blocks[i];
    const test::CanonMove& m = j.rs.moves[i];
    const double ours[6] = {b.target.x, b.target.y, b.target.z + shift_z, b.target.a, b.target.b, b.target.c};
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(ours[k], m.m[k], 5e-4) << what << ": block " << i + 1 << " (line " << b.line << "), axis "
                                         << "XYZABC"[k];
    EXPECT_EQ(b.motion != Motion::Rapid, m.feed) << what << ": block " << i + 1 << " (line " << b.line << ")";
    EXPECT_NEAR(b.dwell_s, m.dwell_before, 1e-9) << what << ": block " << i + 1 << " (line " << b.line << ")";
  }
}

GcodeOptions library() {
  GcodeOptions o;
  o.tool_lengths = {{1, 42.5}, {2, 61.25}, {7, 30.0}};
  o.tool_length = 42.5;
  o.work_offsets = {{"G54", {12.7, -25.4, -50.8, 0, 0, 0}}, {"G55", {101.6, 50.8, -76.2, 0, 0, 15}}};
  return o;
}

// A Fanuc-style drilling program: G54/G55 from the scene, tools 1, 2 and 7 with G43 H, and every cycle
// with sticky words, both retract modes, repeats and incremental mode; G80 beside G0 in a block.
const char* const kCycles = R"(%
O0100 (judge: cycles)
N10 G21 G17 G40 G49 G80 G90 G94
N20 T1 M6
N30 G54 G0 X0 Y0 Z60. A0 C0
N40 G43 H1 Z50.
N50 S1200 M3
N60 M8
N70 G99 G81 X10. Y10. Z-5. R2. F120.
N80 X20.
N90 Y20. Z-7.
N100 G98 G82 X30. Y10. Z-4. R3. P0.5
N110 G0 G80 Z45. (G80 beside a motion code, as Fanuc posts write it)
N120 G0 Z40.
N130 G55 X5. Y5.
N140 G83 X10. Y12. Z-9.5 R1.5 Q2.2 F100.
N150 G99 G73 X15. Q1.7 Z-6. R2.
N160 G80 G0 Z38.
N170 G91 G81 X4. Y3. Z-3. R2. L3 F80.
N180 X-2. L2
N190 G90 G80
N200 G0 Z30.
N210 T2 M6
N220 G43 H2 Z30.
N230 G85 X0 Y0 Z-2. R1. F50.
N240 G98 G89 X5. Z-3. R1. P1.5
N250 M4
N260 G99 G74 X8. Z-2. R1. P0.2 F40.
N270 M3
N280 G84 X9. Z-2. R1. P0.2
N290 G86 X10. Y1. Z-2. R2. P0.1
N300 G80
N310 T7 M6 G43
N320 G0 Z20.
N330 G18 G81 Z4. X6. Y-2. R3. F90.
N340 G19 G82 Y3. Z4. X-1. R2. P0.25
N350 G17 G80
N360 G0 X0 Y0 Z10.
M9 M5
M30
%
)";

TEST(Rs274Judge, CannedCyclesOffsetsAndToolLengths) {
  TF_REQUIRE_RS274();
  expect_same_motion(judge(kCycles, library(), trt_joint()), "cycles");
}

// A cycle's sticky R, bottom and Q, and the initial level G98 returns to, across G20/G21: LinuxCNC keeps the
// numbers and reads them in the new units (R0.1 in G20, then G21: 0.1 mm; an initial level of 50 mm, 1.9685
// in G20, then 1.9685 mm), where the reader had kept them converted (2.54 mm, 50 mm). The verifier follows
// what the controller does.
TEST(Rs274Judge, StickyCycleWordsAreReadInTheNewUnits) {
  TF_REQUIRE_RS274();
  const char* const program = R"(G21 G17 G90 G94
T1 M6
G43 H1
G0 X0 Y0 Z50 A0 C0
G20
G98 G81 X1 Y1 Z-0.1 R0.1 F10
G21
X30
G20
G99 G83 X2 Y2 Z-0.2 R0.05 Q0.03
G21
X40
G20
X3
G80
M2
)";
  expect_same_motion(judge(program, library(), trt_joint()), "cycles across units");
}

// Offsets changed by the program: G10 L2/L20, G92 and its cancels, G53, G49, dwells, arcs.
const char* const kOffsets = R"(G21 G90 G17
T1 M6
G43 H1
G0 X1 Y2 Z3 A0 C0
G10 L2 P1 X10 Y20 Z30 C5
G0 X1 Y2 Z3
G53 G0 Z5
G0 X4
G92 X7 C1
G0 Y1
G92.1
G0 Y2
G92 X0 Y0
G92.2
G0 X1
G92.3
G0 X2
G10 L20 P2 X0 Y0 Z0
G55 G0 X1
G10 L2 P0 X100
G0 Y1
G91 G0 Z0
G49
G0 X0
G90 G0 Z5
G4 P2.5
G1 X10 F200
G2 X20 Y1 I5 J0
G3 X10 Y1 R5
G52 X3 Y4
G1 X0 Y0
G52 X0 Y0
G1 X10 Y0 Z0
G18 G2 X14 Z0 I2 K0
G19 G3 Y2 Z2 J0 K2
G17 G43 H2
G1 X0 Z0
M2
)";

TEST(Rs274Judge, ProgramOffsetsG10G92G53AndArcs) {
  TF_REQUIRE_RS274();
  expect_same_motion(judge(kOffsets, library(), trt_joint()), "offsets");
}

// Parameters and expressions: numbered, named and global parameters, settings read a line later, the
// functions and operators, the position read back (#5420, #<_z>). (The judge reads rs274's moves in mm.)
const char* const kExpressions = R"(G21 G90 G17 G94
T1 M6
G43 H1
#<r> = 10
#1 = 3 #2 = [#1 * 2]
G10 L2 P1 X[#1 * 2] Y-5 C[ATAN[1]/[1]]
G54 G0 X0 Y0 Z[#<r> / 2] A0 C0
G1 X[#<r> * COS[30]] Y[#<r> * SIN[30]] F[100 * #1]
G2 X[-#<r>] Y0 R#<r>
#2 = [#5420 + 1] G1 Z#2
G1 X#2 Y[#5421 - 2] Z[#<_z> - 1]
G91 G1 X[2**3] Y[7 MOD 3] C[ROUND[12.5]]
G90 G0 Z[FUP[#<r> / 3]]
#<_safe> = [#<r> + [2 - 1] * 5]
G0 Z#<_safe> X[FIX[-1.5]]
G1 X[ABS[-4]] Y[SQRT[9] + [1 EQ 1] + [2 LT 1]] F[#<_feed> / 2]
M2
)";

TEST(Rs274Judge, ParametersAndExpressions) {
  TF_REQUIRE_RS274();
  expect_same_motion(judge(kExpressions, library(), trt_joint()), "expressions");
}

// Subroutines and control flow: arguments and the caller's #1-#30 restored, local and global named
// parameters, returned values, IF/ELSEIF/ELSE, WHILE with CONTINUE, REPEAT, DO/WHILE with BREAK, nested
// calls.
const char* const kControlFlow = R"(G21 G90 G17 G94
T1 M6
G43 H1
G0 X0 Y0 Z5 A0 C0
#5 = 7
#<x> = 3
#<_g> = 4
#<_n> = 0
o100 sub
  G1 X#1 Y#2 Z#5 F100
  #<x> = 9
  #1 = 11
o100 endsub [#1 * 2]
o<lp> sub
  #<i> = 0
  o1 while [#<i> LT 3]
    #<i> = [#<i> + 1]
    o2 if [#<i> EQ 2]
      o1 continue
    o2 endif
    G1 X[#<i> * 10] Y#<_g>
  o1 endwhile
  o3 repeat [2]
    G1 Z[#<_value>]
  o3 endrepeat
  o4 do
    G1 Y99
    o4 break
  o4 while [1]
o<lp> endsub
o<square> sub
  o10 repeat [4]
    G91 G1 X[#1 * COS[#<_n> * 90]] Y[#1 * SIN[#<_n> * 90]] Z-#2 F100
    #<_n> = [#<_n> + 1]
    o100 call [#<_n>] [#<_n> * 2]
  o10 endrepeat
  G90
  o<square> return [#1 + #2]
o<square> endsub
o<square> call [2] [0.5]
#1 = 5
o100 call [1] [2]
G1 X#1 Y#<x> Z#<_value>
o<lp> call
G1 X#<_value_returned>
o5 if [0]
 G1 X1
o5 elseif [1]
 G1 X2
o5 else
 G1 X3
o5 endif
o6 if [#<_n> GT 3]
 o<square> call [1] [0]
o6 endif
G1 Z#<_value>
M2
)";

// CONTINUE in a DO loop: rs274 goes on at the next line of the loop's label and runs it, so a BREAK on the
// way (in an IF not taken) leaves the loop; the reader had followed the text (black-box testing). In the
// main program: inside a subroutine rs274's later IFs and loops then misbehave, which is not modelled.
const char* const kDoContinue = R"(G21 G90 G94
T1 M6
G43 H1
G0 X0 Y0 Z5 A0 C0
#<i> = 3
o7 do
  #<i> = [#<i> + 1]
  o8 if [#<i> EQ 5]
    o7 continue
  o8 endif
  G1 X[#<i>] F100
  o9 if [#<i> GT 100]
    o7 break
  o9 endif
o7 while [#<i> LT 8]
o11 do
  #<i> = [#<i> + 1]
  o12 if [#<i> EQ 7]
    o11 continue
  o12 endif
  G1 Y[#<i>]
o11 while [#<i> LT 9]
M2
)";

TEST(Rs274Judge, SubroutinesAndControlFlow) {
  TF_REQUIRE_RS274();
  expect_same_motion(judge(kControlFlow, library(), trt_joint()), "control flow");
  const Judged j = judge(kDoContinue, library(), trt_joint());
  expect_same_motion(j, "DO with CONTINUE");
  EXPECT_EQ(j.program.blocks.size(), 5u);  // the rapid, X4 (then out at i = 5), Y6, Y8, Y9
}

// rs274 refuses `text`, and the reader too, naming `line`.
void expect_both_refuse(const std::string& text, int line) {
  test::TempDir dir;
  EXPECT_NE(test::run_rs274(dir, text, test::rs274_tool_table(library().tool_lengths), "").exit_code, 0) << text;
  try {
    parse_gcode(text, "judge.ngc", trt_joint(), library());
    ADD_FAILURE() << "no error for " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
  }
}

// Comments only between the items of a line, and lines of at most 252 characters (a CRLF's "\r"
// counted): what rs274 refuses the reader refuses, naming the line, and what rs274 reads it reads. A
// comment inside a number or an expression had been stripped and the pieces joined (black-box testing).
TEST(Rs274Judge, CommentsBetweenWordsAndLongLines) {
  TF_REQUIRE_RS274();
  const std::string head = "G21 G90 G94\nT1 M6\nG43 H1\nG0 X0 Y0 Z5 A0 C0\n";
  for (const std::string& bad : std::vector<std::string>{"G1 X1(c).5 F10", "G(c)1 X1 F10", "G1 X#(c)1 F10", "G1 X[1 (c) + 2] F10",
                                "G1 X[SIN(c)[90]] F10", "#1(c)=3", "G1 X(MSG,hi)3 F10", "G1 X[1 ; c\n] F10",
                                "G1 X1 F10" + std::string(244, ' '), "G1 X1 F10" + std::string(243, ' ') + "\r",
                                                          "o1 if (c) [1 GT 0]\no1 endif"}) {
    expect_both_refuse(head + bad + "\nM2\n", 5);
  }
  const std::string good = head + "G1 X1 (c) F10 (d)\n(e)G1 Y2 (f);g\nG1 X[1+2](h)Y3\n#1=4(i)#2=5\nG1 X#1 Y#2" +
                           std::string(241, ' ') + "\r\no100 sub\nG1 X#1 Y#2\no100 endsub\no100 call (j) [6] (k) [7]\nM2\n";
  expect_same_motion(judge(good, library(), trt_joint()), "comments between words, a line of 252 characters");
}

// An O-word is the first item of its line, after a line number if any, with no comment before its keyword;
// rs274 reads the lines a false condition or a definition skips, and refuses one too long there too.
TEST(Rs274Judge, LineNumbersAndCommentsAroundOWords) {
  TF_REQUIRE_RS274();
  const std::string head = "G21 G90 G94\nT1 M6\nG43 H1\nG0 X0 Y0 Z5 A0 C0\n";
  const std::string sub = "\nG1 X1 F10\no100 endsub\no100 call\n";
  const std::string too_long = "G1 X1 F10 (" + std::string(250, 'c') + ")";
  const std::vector<std::pair<std::string, int>> bad{{"o100 (c) sub" + sub, 5},
                                                     {"(c) o100 sub" + sub, 5},
                                                     {"N5 (c) o100 sub" + sub, 5},
                                                     {"o1 if [0]\n" + too_long + "\no1 endif\n", 6},
                                                     {"o100 sub\n" + too_long + "\no100 endsub\n", 6}};
  for (const auto& [body, line] : bad) expect_both_refuse(head + body + "M2\n", line);
  const std::string good = head + "N5 o100 sub\nN6 G1 X#1 F10\nN7 o100 endsub (c)\nN8 #1=2\nN9 o100 call [3]\n"
                                  "N10.1 o1 if [#1 GT 1]\nN11 G1 Y2\nN12 o1 endif\nM2\n";
  expect_same_motion(judge(good, library(), trt_joint()), "line numbers before O-words");
}

// Fanuc-style subprograms as a Fanuc post writes them: the program number first, M98 P with and without
// L, calls nested two deep from a called program, N numbers, G91 inside, a subprogram that reads
// and sets the caller's #1 and its own named parameter, subprograms after the M30, one reached by the main
// program's own flow after a return (a bare "O" line runs on) and ended by M99 in the main program.
const char* const kFanucSubprograms = R"(%
O2000 (judge: M98 / M99)
N10 G21 G90 G17 G94
N20 T1 M6
N30 G43 H1
N40 G0 X0 Y0 Z10 A0 C0
N50 #1 = 2
N60 #<depth> = 1
N70 M98 P3000 L3
N80 (L0 runs nothing: test_gcode_control.cpp; this rs274 then keeps the call level raised)
N90 G1 X#1 Y#<depth> F100
N100 M98 P4000
N110 M98 P0005
N120 G0 Z20
N130 M30
O3000 (a row of holes)
#<depth> = [#1 / 2]
G91 G1 X5 F200
G1 Z-#<depth>
G0 Z#<depth>
G90
#1 = [#1 + 1]
M99
O4000
G1 Y7 F150
M98 P3000 L2
G1 Y0
M99
O5
G0 X1 Y1
M99
)";

// The same flow reached without a call: after the main program's M98, "O6" runs on into its lines and
// its M99 ends the program (rs274 too: the G1 after it never runs).
const char* const kFlowIntoProgram = R"(G21 G90 G94
T1 M6
G43 H1
G0 X0 Y0 Z5 A0 C0
M98 P6
O6
G1 X3 F100
M99
G1 X9
)";

TEST(Rs274Judge, FanucSubprograms) {
  TF_REQUIRE_RS274();
  expect_same_motion(judge(kFanucSubprograms, library(), trt_joint()), "M98/M99");
  expect_same_motion(judge(kFlowIntoProgram, library(), trt_joint()), "flow into a program");
}

// LinuxCNC's polar coordinates (@ the distance, ^ the angle about the XY origin of the coordinate system
// in force; absolute and incremental, straight moves, an R arc and cycles with repeats) and the spindle-
// synchronised moves G33 and G33.1 (rigid tapping: in and back out).
const char* const kPolarAndSynchronised = R"(G21 G17 G90 G94
T1 M6
G54 G43 H1
G0 X10 Y0 Z5 A0 C0
S500 M3
G33 Z-5 K1.5
G0 Z5
G33.1 Z-8 K1.25 I2
G0 X2.5 Y0
G1 F100 ^120
@4
G91 @1 ^10
G90 @5 ^33
G91 G81 @1 R.1 Z-0.5 L3
G90 G0 X2 Y0
G91 G81 ^[360/17] R.1 Z-0.5 L3
G90 G99 G81 @7 ^-45 R2 Z-1
^45
G80
G0 Z5
G2 @10 ^0 R10
G0 X5 Y5
G33.1 X5 Y5 Z-3 K1
M2
)";

TEST(Rs274Judge, PolarCoordinatesAndSpindleSynchronisedMoves) {
  TF_REQUIRE_RS274();
  expect_same_motion(judge(kPolarAndSynchronised, library(), trt_joint()), "polar, G33, G33.1");
}

// Subroutine files, found by rs274 beside the program (its working directory) and by the reader in the
// program's directory: nested calls between files, arguments, a loop and a numbered O-word inside one, a
// name called in capitals.
TEST(Rs274Judge, SubroutineFiles) {
  TF_REQUIRE_RS274();
  test::TempDir dir;
  test::write_text(dir / "outer.ngc", "o<outer> sub\no<inner> call [#1 * 2]\nG1 X#1 F100\no<outer> endsub\nM2\n");
  test::write_text(dir / "inner.ngc",
                   "o<inner> sub\no100 repeat [2]\nG91 G1 Y#1 F200\no100 endrepeat\nG90 G1 X0 Y0\nG3 X0 Y0 I2 J0\no<inner> endsub\n");
  const std::string program = "G21 G90 G17\nG0 X2 Y0 Z0 A0 C0\nO<OUTER> call [3]\nG0 Z10\no<inner> call [1]\nM2\n";
  Judged j;
  j.rs = test::run_rs274(dir, program, test::rs274_tool_table({}), test::rs274_var_file({}));
  j.program = read_gcode(dir / "judge.ngc", trt_joint(), GcodeOptions{});
  expect_same_motion(j, "subroutine files");
  EXPECT_GT(j.program.blocks.size(), 8u);
}

// A path as a list of (position, feed or rapid, dwell before) with the moves that go nowhere left out (their
// dwells carried to the next): rs274 makes a traverse of a lone "G0", the reader no block. A spline (rs274
// prints none of its points) stays as a mark.
struct PathPoint {
  std::array<double, 6> m;
  bool feed;
  double dwell;
  bool spline = false;
};
std::vector<PathPoint> moving(const std::vector<PathPoint>& in, double tol) {
  std::vector<PathPoint> out;
  std::array<double, 6> at{};
  double dwell = 0.0;
  for (const PathPoint& p : in) {
    dwell += p.dwell;
    if (p.spline) {
      if (out.empty() || !out.back().spline) out.push_back(p);
      continue;
    }
    bool moves = false;
    for (int k = 0; k < 6; ++k) moves |= std::abs(p.m[k] - at[k]) > tol;
    if (!moves) continue;
    out.push_back({p.m, p.feed, dwell});
    at = p.m;
    dwell = 0.0;
  }
  return out;
}

// LinuxCNC's own sample programs (examples/nc_files of the package that brings rs274), each that needs no
// subroutine files, probing, cutter compensation (which the reader does not simulate), lathe cycles or a B
// axis: every move where rs274 puts it. Inch and mm programs, arcs in every plane, polar coordinates, G33
// threading, G5.1 splines, cycles, O-word loops, subroutines and parameters. A first line "G0 X0 Y0 Z0"
// puts the reader where rs274 starts (the reader takes an axis not yet programmed to be where the program
// first sends it); tools 1-99 have length 0. rs274 prints 4 decimals: 0.00005 inch is 0.00127 mm. Of a
// spline rs274 prints nothing: the reader's chords up to the move that follows it are passed over, and
// that move must be rs274's next one.
TEST(Rs274Judge, LinuxcncSamplePrograms) {
  TF_REQUIRE_RS274();
  const std::filesystem::path dir = "/usr/share/doc/linuxcnc/examples/nc_files";
  GcodeOptions options;
  for (int t = 1; t < 100; ++t) options.tool_lengths[t] = 0.0;
  const double tol = 1.3e-3;
  int judged = 0;
  for (const char* name : {"3D_Chips", "3dtest", "arcspiral", "cds", "daisy", "factorial", "flowsnake", "g20sub", "g881",
                           "g881min", "g882", "hole-circle", "lathe_pawn", "m250", "m61demo", "m6demo", "m6remap",
                           "m70m72-demo", "m73-demo", "m75", "m76", "offsets", "plasmatest", "polar", "retval",
                           "roparams", "skeleton", "spiral", "systems", "testm6fail", "threading", "toplevel", "tort",
                           "touchoff"}) {
    const std::filesystem::path file = dir / (std::string(name) + ".ngc");
    if (!std::filesystem::exists(file)) continue;  // a LinuxCNC whose examples differ
    std::ifstream in(file);
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();
    const size_t first = text.find_first_not_of(" \t\r\n");
    const size_t at = first != std::string::npos && text[first] == '%' ? text.find('\n', first) + 1 : 0;
    text.insert(at, "G0 X0 Y0 Z0\n");
    test::TempDir tmp;
    const test::Rs274Run rs = test::run_rs274(tmp, text, test::rs274_tool_table(options.tool_lengths), "");
    ASSERT_EQ(rs.exit_code, 0) << name << ": rs274 refused it:\n" << rs.output.substr(0, 2000);
    const Program program = parse_gcode(text, file.string(), trt_joint(), options);
    std::vector<PathPoint> ours, theirs;
    for (const Block& b : program.blocks)
      ours.push_back({{b.target.x, b.target.y, b.target.z, b.target.a, b.target.b, b.target.c}, b.motion != Motion::Rapid, b.dwell_s});
    for (const test::CanonMove& m : rs.moves) theirs.push_back({m.m, m.feed, m.dwell_before, m.spline});
    ours = moving(ours, tol);
    theirs = moving(theirs, tol);
    auto same = [&](const PathPoint& a, const PathPoint& b) {
      for (int k = 0; k < 6; ++k)
        if (std::abs(a.m[k] - b.m[k]) > tol) return false;
      return a.feed == b.feed;
    };
    size_t j = 0;
    for (size_t i = 0; i < theirs.size(); ++i) {
      if (theirs[i].spline) {
        ASSERT_LT(i + 1, theirs.size()) << name << ": a spline last";
        for (; j < ours.size() && !same(ours[j], theirs[i + 1]); ++j)  // the chords: feed moves only
          ASSERT_TRUE(ours[j].feed) << name << ": a rapid among the chords of the spline before move " << i + 2;
        continue;
      }
      ASSERT_LT(j, ours.size()) << name << ": rs274's move " << i + 1 << " is missing";
      for (int k = 0; k < 6; ++k)
        ASSERT_NEAR(ours[j].m[k], theirs[i].m[k], tol) << name << ": move " << i + 1 << ", axis " << "XYZABC"[k];
      ASSERT_EQ(ours[j].feed, theirs[i].feed) << name << ": move " << i + 1;
      if (i == 0 || !theirs[i - 1].spline) {
        ASSERT_NEAR(ours[j].dwell, theirs[i].dwell, 1e-9) << name << ": move " << i + 1;
      }
      ++j;
    }
    ASSERT_EQ(j, ours.size()) << name << ": moves beyond rs274's";
    ++judged;
  }
  EXPECT_GT(judged, 0) << "no sample program found in " << dir;
}

// On a 3-axis machine with tool length offsets in use the targets are the tool tip: LinuxCNC's position
// (the spindle nose) less the loaded tool's gauge length.
TEST(Rs274Judge, ThreeAxisTargetsAreTheTipBelowTheNose) {
  TF_REQUIRE_RS274();
  const std::string text = "G21 G90\nT2 M6\nG43 H2\nG54 G0 X5 Y5 Z20\nG81 X10 Y10 Z-3 R1 F100\nG80\nM30\n";
  expect_same_motion(judge(text, library(), MachineSpec{}), "3-axis", 61.25);
}

}  // namespace
}  // namespace tf
