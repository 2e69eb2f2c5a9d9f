// Parameters and expressions in the G-code reader: each value as LinuxCNC's interpreter computes it (the
// expected values are rs274's for the same lines), settings taking effect after their line, the system
// and predefined parameters read from the reader's state, and the errors naming the word or operator.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gcode_test_util.hpp"

namespace tf {
namespace {

using test::expect_gcode_error;
using test::expect_refused;
using test::parse_program;

// X's value in "G1 X<value>" after "#1 = 2" and "#<abc> = 5".
double x_of(const std::string& value) {
  const Program p = parse_program("#1 = 2\n#<abc> = 5\nG1 X" + value + " F100\n");
  EXPECT_EQ(p.blocks.size(), 1u) << value;
  return p.blocks.empty() ? NAN : p.blocks.back().target.x;
}

TEST(GcodeExpressions, ValuesAsLinuxCncComputesThem) {
  const struct {
    const char* value;
    double x;
  } cases[] = {
      {"[2+3*4]", 14},           {"[2**3**2]", 64},         {"[7 MOD 3]", 1},          {"[-7 MOD 3]", 2},
      {"[-7 MOD -3]", 2},        {"[1 EQ 1.00001]", 1},     {"[1 EQ 1.001]", 0},       {"[1 NE 1.00001]", 0},
      {"[ATAN[1]/[1]]", 45},     {"[ATAN[-1]/[-1]]", -135}, {"[ROUND[2.5]]", 3},       {"[ROUND[-2.5]]", -3},
      {"[FIX[-1.5]]", -2},       {"[FUP[-1.5]]", -1},       {"-#1", -2},               {"-[1+2]", -3},
      {"+#1", 2},                {"[-#1]", -2},             {"#<abc>", 5},             {"##1", 0},
      {"#[1+1]", 0},             {"#[1.00001]", 2},         {"[EXISTS[#<abc>]]", 1},   {"[EXISTS[#<nope>]]", 0},
      {"[2 GT 1 AND 3 LT 2]", 0}, {"[1 OR 0]", 1},          {"[1 XOR 1]", 0},          {"[0.000001 AND 1]", 1},
      {"[3 - 2 - 1]", 0},        {"[8 / 2 / 2]", 2},        {"[2 ** 0.5]", std::sqrt(2.0)}, {"[2 ** -1]", 0.5},
      {"[1 + 2 EQ 3]", 1},       {"[SQRT[16]]", 4},         {"[ABS[-3]]", 3},          {"[-2 ** 2]", 4},
      {"[0-2**2]", -4},          {"[EXP[0]]", 1},           {"[LN[1]]", 0},            {"[ACOS[0]]", 90},
      {"[ASIN[1]]", 90},         {"[SIN[30]]", 0.5},        {"[COS[60]]", 0.5},        {"[TAN[45]]", 1},
      {"[ROUND[0.5]]", 1},       {"[7 mod 3]", 1},          {"[ 2 * [ 3 + 1 ] ]", 8},  {"SQRT[9]", 3},
      {"--1", 1},                {"+-1", -1},
  };
  for (const auto& c : cases) EXPECT_NEAR(x_of(c.value), c.x, 1e-12) << c.value;
}

TEST(GcodeExpressions, SettingsTakeEffectAfterTheirLine) {
  // rs274: "#3=6 G1 X#3" moves to the old #3; of two settings of one parameter the last stays.
  const Program p = parse_program("#3 = 15\n#3 = 6 G1 X#3 F100\nG1 X#3\n#1=3 #1=4 G1 Y#1\nG1 Y#1\n"
                                  "#<_depth> = [#3 / 2] (a global)\nG1 Z-#<_DEPTH>\n");
  ASSERT_EQ(p.blocks.size(), 5u);
  EXPECT_DOUBLE_EQ(p.blocks[0].target.x, 15);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 6);
  EXPECT_DOUBLE_EQ(p.blocks[2].target.y, 0);
  EXPECT_DOUBLE_EQ(p.blocks[3].target.y, 4);
  EXPECT_DOUBLE_EQ(p.blocks[4].target.z, -3);
  // A name set earlier on a line exists there and reads 0 until the line is done (rs274 alike).
  const Program q = parse_program("#<a> = 1 #<b> = [#<a> + 2] G0 X[EXISTS[#<a>]] Y[EXISTS[#<_x>]]\nG0 Z#<b>\n");
  ASSERT_EQ(q.blocks.size(), 2u);
  EXPECT_DOUBLE_EQ(q.blocks[0].target.x, 1);
  EXPECT_DOUBLE_EQ(q.blocks[0].target.y, 1);  // predefined: exists before any move sets X
  EXPECT_DOUBLE_EQ(q.blocks[1].target.z, 2);
}

TEST(GcodeExpressions, SystemAndPredefinedParametersReadTheState) {
  // #5221...: the coordinate systems in machine units; #5420...: the position in program units.
  const Program p = parse_program(
      "G21 G10 L2 P2 X3 Y4\nG55 G0 X1 Y2 Z0\nG1 X#5241 Y#5220 Z#5421 F100\n"
      "G20 G1 X#5420 Y#<_metric> Z#<_coord_system>\nG21 G91 G1 X#<_incremental> Y#<_feed> Z[#<_motion_mode> / 10]\n");
  ASSERT_EQ(p.blocks.size(), 4u);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 3 + 3);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.y, 2 + 4);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.z, 2);
  // A line's parameters are read before its codes act: #5420 is 3 (mm) before G20, then X3 in inches.
  EXPECT_NEAR(p.blocks[2].target.x, 3 * 25.4 + 3, 1e-9);
  EXPECT_NEAR(p.blocks[2].target.y, 25.4 + 4, 1e-9);        // _metric still 1
  EXPECT_NEAR(p.blocks[2].target.z, 550 * 25.4, 1e-6);      // G55
  EXPECT_NEAR(p.blocks[3].target.x, 3 * 25.4 + 3, 1e-9);    // G91 acts after _incremental (0) is read
  EXPECT_NEAR(p.blocks[3].target.y, 25.4 + 4 + 100, 1e-9);  // _feed: F as written (rs274 too)
  EXPECT_NEAR(p.blocks[3].target.z, 550 * 25.4 + 1, 1e-6);  // _motion_mode 10: G1
}

TEST(GcodeExpressions, ErrorsNameTheWordOrOperator) {
  expect_refused({
      {"G0 X0\nG1 X#<zz> F1\n", 2, "#<ZZ>"},       // undefined named parameter
      {"G1 X[1/0] F1\n", 1, "/"},                   // division by zero
      {"G1 X[1 MOD 0] F1\n", 1, "MOD"},
      {"G1 X[[-8]**[1/3]] F1\n", 1, "**"},          // negative to a non-integer power
      {"G1 X#5603 F1\n", 1, "#5603"},               // out of range
      {"G1 X#0 F1\n", 1, "#0"},
      {"G1 X#[1.4] F1\n", 1, "#[1.4]"},             // not an integer
      {"#1.5 = 2\n", 1, "#1.5"},
      {"#5420 = 3\n", 1, "#5420"},                  // system parameters are not written
      {"#5221 = 3\n", 1, "#5221"},
      {"#<_x> = 3\n", 1, "#<_X>"},                  // predefined: read-only
      {"G1 X#5061 F1\n", 1, "#5061"},               // the probe's result: not simulated
      {"G1 Y#5420 F1\n", 1, "#5420"},               // no position known yet
      {"G1 Z#<_x> F1\n", 1, "#<_X>"},
      {"#[SIN[10**400]] = 1\n", 1, "**"},  // inf
      {"G0 X0\nO#1 SUB\n", 2, "O#1"},
      {"G1 X[SQRT[-1]] F1\n", 1, "SQRT"},
      {"G1 X[LN[0]] F1\n", 1, "LN"},
      {"G1 X[ACOS[2]] F1\n", 1, "ACOS"},
      {"G1 X[ATAN[1]] F1\n", 1, "ATAN"},            // ATAN[y]/[x]
      {"G1 X[COSH[1]] F1\n", 1, "COSH"},            // no such function
      {"G1 X[1 F1\n", 1, "F1"},                     // an operator expected
      {"G1 X[1+2\n", 1, "[1+2"},                    // not closed
      {"G1 X[1+] F1\n", 1, "]F1"},                  // an operand expected
      {"#1 2\n", 1, "#12"},                         // '=' expected
      {"G1 X#<a F1\n", 1, "#<AF1"},                 // name not closed
      {"G1 X1[2] F1\n", 1, "X1["},
      {"G1 X[EXP[100]] F1\n", 1, "EXP"},            // beyond 1e9
      {"G0 X0\no100 sub\n", 2, "O100"},             // subroutines stay refused
  });
  // Brackets nested beyond reason are refused, not recursed into until the stack ends.
  const std::string deep = "G1 X" + std::string(100, '[') + "1" + std::string(100, ']') + " F1\n";
  try {
    parse_program(deep);
    ADD_FAILURE() << "no error for 100 nested brackets";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nested too deeply"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tf
