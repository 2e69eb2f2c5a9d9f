// O-word subroutines and control flow in the G-code reader (rs274 judges a whole program of them in
// test_rs274_judge.cpp): what it does not cover, and the errors naming the O-word and its line.
#include <gtest/gtest.h>

#include <string>

#include "gcode_test_util.hpp"
#include "test_support.hpp"

namespace tf {
namespace {

using test::expect_gcode_error;
using test::expect_refused;
using test::parse_program;

std::vector<double> xs(const Program& p) {
  std::vector<double> out;
  for (const Block& b : p.blocks) out.push_back(b.target.x);
  return out;
}

TEST(GcodeControl, CallsFindSubroutinesAnywhereInTheFile) {
  // The call comes first; the definition is not run where it stands.
  const Program p = parse_program("G0 X0 Y0 Z0\no<hop> call [5]\nG1 X1 F100\no<hop> sub\n  G0 X#1\no<hop> endsub\nM2\n");
  EXPECT_EQ(xs(p), (std::vector<double>{0, 5, 1}));
}

TEST(GcodeControl, RepeatCountsAndLevels) {
  // REPEAT rounds its count to the nearest whole, halves to even (rs274: 2.5 passes twice, 2.7 three times);
  // none for 0 or less. #<_call_level> is 1 inside a call.
  const Program p = parse_program(
      "G0 X0 Y0 Z0\nG91\no1 repeat [2.5]\nG0 X1\no1 endrepeat\no2 repeat [2.7]\nG0 X10\no2 endrepeat\n"
      "o3 repeat [0]\nG0 X100\no3 endrepeat\no4 sub\nG0 X#<_call_level>\no4 endsub\no4 call\n");
  EXPECT_EQ(xs(p), (std::vector<double>{0, 1, 2, 12, 22, 32, 33}));
}

TEST(GcodeControl, ReturnedValues) {
  // A return without a value clears #<_value> (rs274); a call leaves #<_value_returned> as it was.
  const Program p = parse_program(
      "G0 X0 Y0 Z0\no2 sub\no2 return [7]\no2 endsub\no1 sub\nG0 Z#<_value_returned>\no1 return\no1 endsub\n"
      "o2 call\nG0 X#<_value>\no1 call\nG0 X#<_value> Y#<_value_returned>\n");
  ASSERT_EQ(p.blocks.size(), 4u);
  EXPECT_DOUBLE_EQ(p.blocks[1].target.x, 7);
  EXPECT_DOUBLE_EQ(p.blocks[2].target.z, 1);
  EXPECT_DOUBLE_EQ(p.blocks[3].target.x, 0);
  EXPECT_DOUBLE_EQ(p.blocks[3].target.y, 0);
}

TEST(GcodeControl, EndInsideASubroutineEndsTheProgram) {
  const Program p = parse_program("G0 X0 Y0 Z0\no1 sub\nG0 X1\nM2\no1 endsub\no1 call\nG0 X9\n");
  EXPECT_EQ(xs(p), (std::vector<double>{0, 1}));
}

TEST(GcodeControl, ErrorsNameTheOWord) {
  expect_refused({
      {"G0 X0\nO<probe> call\n", 2, "O<PROBE>"},                      // no such subroutine here
      {"G0 X0\no100 sub\nG0 X1\n", 2, "O100"},                        // no ENDSUB
      {"G0 X0\no100 endsub\n", 2, "O100"},                            // no SUB
      {"o1 sub\no2 sub\no2 endsub\no1 endsub\n", 2, "O2"},            // defined inside another
      {"o1 sub\no1 endsub\no1 sub\no1 endsub\n", 3, "O1"},            // defined twice
      {"G0 X0\no1 return\n", 2, "O1"},                                // outside a call
      {"o1 sub\no1 call\no1 endsub\no1 call\n", 2, "O1"},             // recursion: 9 levels deep at most
      {"G0 X0\no2 repeat [3]\no2 break\no2 endrepeat\n", 3, "O2"},     // BREAK only in WHILE and DO
      {"G0 X0\no200 if [0]\nG0 X1\n", 2, "O200"},                     // IF without ENDIF
      {"G0 X0\no3 endwhile\n", 2, "O3"},                              // ENDWHILE without WHILE
      {"G0 X0\no3 while [1]\no3 endrepeat\n", 3, "O3"},               // the wrong end
      {"G0 X0\no4 break\n", 2, "O4"},                                 // outside a loop
      {"G0 X0\no5 if 1\no5 endif\n", 2, "O5"},                        // arguments are bracketed
      {"G0 X0\no5 if [1] [2]\no5 endif\n", 2, "O5"},                  // one condition
      {"o6 sub\no6 endsub\no6 call [1] [2] [3] [4] [5] [6] [7] [8] [9] [10] [11] [12] [13] [14] [15] [16] [17] "
       "[18] [19] [20] [21] [22] [23] [24] [25] [26] [27] [28] [29] [30] [31]\n", 3, "O6"},  // 31 arguments
      {"G0 X0\no7 if [#<nope>]\no7 endif\n", 2, "#<NOPE>"},           // a condition's error
      {"G0 X0\nO#1 sub\n", 2, "O#1"},                                 // a label is a number or <name>
  });
  GcodeOptions few;
  few.max_lines_run = 1000;  // beyond the file's own lines  // a loop that does not end is refused, naming the line where the count ran out
  expect_gcode_error("G0 X0\no1 while [1]\nG91 G0 X1\no1 endwhile\n", 4, "", few);
}

TEST(GcodeControl, FanucSubprogramsRunAsLinuxcncRunsThem) {
  // L counts runs (L0 none); the first of two programs of one number is the one run (rs274 alike).
  const Program p = parse_program(
      "G0 X0 Y0 Z0\nG91\nM98 P10 L2\nN5 M98 P10 L0\nM98 P010\nM30\nO10\nG0 X1\nM99\nO10\nG0 X100\nM99\n");
  EXPECT_EQ(xs(p), (std::vector<double>{0, 1, 2, 3}));
  // L0 does not look for the program; M99 clears #<_value> and #<_value_returned> (rs274 alike).
  const Program v = parse_program(
      "G0 X0 Y0 Z0\nM98 P77 L0\no1 sub\no1 return [5]\no1 endsub\no1 call\nM98 P10\n"
      "G0 X#<_value> Y#<_value_returned>\nM30\nO10\nM99\n");
  EXPECT_EQ(xs(v), (std::vector<double>{0, 0}));
  EXPECT_DOUBLE_EQ(v.blocks.back().target.y, 0);
  // Words after M98's P and L are ignored, as rs274 ignores them, with a warning.
  const Program q = parse_program("G0 X0 Y0 Z0\nM98 P10 G91 #2=5\nG0 X#2\nM30\nO10\nG0 X1\nM99\n");
  EXPECT_EQ(xs(q), (std::vector<double>{0, 1, 0}));
  ASSERT_EQ(q.warnings.size(), 1u);
  EXPECT_NE(q.warnings[0].find("M98"), std::string::npos) << q.warnings[0];
  // M99 in the main program ends it (warned: the controller would run it again).
  const Program r = parse_program("G0 X0 Y0 Z0\nG0 X1 M99\nG0 X2\n");
  EXPECT_EQ(xs(r), (std::vector<double>{0, 1}));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("M99"), std::string::npos) << r.warnings[0];
}

TEST(GcodeControl, FanucSubprogramErrorsNameTheWord) {
  // Each refused by rs274 too (its messages: no P-word, negative L, non-integer, EOF seeking the O-word,
  // "must be called with M98", "must end with M99", unknown M code, unexpected character, levels).
  expect_refused({
      {"G0 X0\nM98\n", 2, "M98"},                                      // no P
      {"G0 X0\nM98 P10 L-1\nM30\nO10\nM99\n", 2, "L-1"},             // negative repeat count
      {"G0 X0\nM98 P10 L2.6\nM30\nO10\nM99\n", 2, "L2.6"},           // not a whole count
      {"G0 X0\nM98 P10.5\nM30\nO10\nM99\n", 2, "P10.5"},             // not a program number
      {"G0 X0\nM98 P1000\n", 2, "P1000"},                                // no such program here
      {"G0 X0\nM98 P10\nM30\no10 sub\no10 endsub\n", 2, "P10"},      // an O-word subroutine
      {"G0 X0\no10 call\nM30\nO10\nM99\n", 2, "O10"},                 // a Fanuc program called by CALL
      {"G0 X0\nM98 P10\nM30\nO10\no10 return\n", 5, "O10"},           // a program ended by RETURN
      {"G0 X0\nM98 P10 L2 L3\nM30\nO10\nM99\n", 2, "L3"},             // L twice
      {"G0 X0\nM98 P10\nM30\nO10\nG0 X1\n", 2, "M98"},                // the file ends inside the program
      {"o1 sub\nO10\nM99\no1 endsub\n", 2, "O10"},                    // a program inside a subroutine
      {"G0 X0\no10 call\nM30\no10 sub\nM99\no10 endsub\n", 5, "M99"},  // a subroutine ended by M99
      {"G0 X0\nG0 X1 M98 P10\nM30\nO10\nM99\n", 2, "M98"},            // M98 opens its line
      {"G0 X0\nM98 P10\nM30\nO10\nG90 M99\n", 5, "M99"},              // a return stands alone
      {"G0 X0\nM98 P10\nM30\nO10\nM99 X5\n", 5, "M99"},
      {"G0 X0\nM98 P1\nM30\nO1\nM98 P1\nM99\n", 5, "M98"},           // 9 levels at most
  });
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

// Subroutine files: O<name> not in the program is the file <name>.ngc (lower case) of the first
// subroutine directory that has it; only its SUB ... ENDSUB runs (the M2 after it does not end the
// program); errors and warnings name the file and its line, the blocks it makes the line of the call.
TEST(GcodeControl, SubroutineFilesRunFromTheDirectories) {
  test::TempDir first, second;
  test::write_text(second.path() / "drill.ngc",
                   "(a library file)\no<drill> sub\nG0 X#1 Y#2\nG1 Z-1 F50\nG0 Z1\no<drill> endsub\nM2\n");
  test::write_text(first.path() / "row.ngc", "o<row> sub\no<drill> call [#1] [0]\no<drill> call [#1 + 10] [0]\no<row> endsub\n");
  test::write_text(first.path() / "main.ngc", "G21 G90\nG0 X0 Y0 Z1\nO<ROW> call [5]\nG0 X50\nM2\n");
  GcodeOptions options;
  options.subroutine_dirs = {second.path()};
  const Program p = read_gcode(first.path() / "main.ngc", MachineSpec{}, options);  // row.ngc: the program's own directory
  EXPECT_EQ(xs(p), (std::vector<double>{0, 5, 5, 5, 15, 15, 15, 50}));
  ASSERT_EQ(p.blocks.size(), 8u);
  for (size_t k = 1; k < 7; ++k) EXPECT_EQ(p.blocks[k].line, 3) << k;
  EXPECT_EQ(p.blocks[7].line, 4);

  // An error in a file names the file and its line; a warning too.
  test::write_text(second.path() / "bad.ngc", "(library)\n\no<bad> sub\nM123\nG1 X1 Q2 F100\no<bad> endsub\n");
  test::write_text(first.path() / "calls_bad.ngc", "G21\nG0 X0 Y0 Z0\no<bad> call\nM2\n");
  try {
    read_gcode(first.path() / "calls_bad.ngc", MachineSpec{}, options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (second.path() / "bad.ngc").string());
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.field(), "Q2");
  }
  test::write_text(second.path() / "warns.ngc", "o<warns> sub\nM123\no<warns> endsub\n");
  test::write_text(first.path() / "calls_warns.ngc", "G21\no<warns> call\nG0 X0 Y0 Z0\nM2\n");
  const Program w = read_gcode(first.path() / "calls_warns.ngc", MachineSpec{}, options);
  ASSERT_FALSE(w.warnings.empty());
  EXPECT_EQ(w.warnings.front().rfind((second.path() / "warns.ngc").string() + ":2: M123", 0), 0u) << w.warnings.front();

  // Not found anywhere, a file without the subroutine, a file that calls itself without end: errors
  // naming the call (in a subroutine file: there).
  auto expect_error = [&](const std::string& program, const std::string& file, int line, const std::string& field) {
    test::write_text(first.path() / "calls.ngc", program);
    try {
      read_gcode(first.path() / "calls.ngc", MachineSpec{}, options);
      ADD_FAILURE() << "no error for " << program;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file) << program;
      EXPECT_EQ(e.line(), line) << program;
      EXPECT_EQ(e.field(), field) << program;
    }
  };
  const std::string calls = (first.path() / "calls.ngc").string();
  expect_error("G21\no<none> call\nM2\n", calls, 2, "O<NONE>");
  test::write_text(second.path() / "empty.ngc", "G0 X1\nM2\n");
  expect_error("G21\n\no<empty> call\nM2\n", calls, 3, "O<EMPTY>");
  test::write_text(second.path() / "again.ngc", "o<again> sub\nG0 X1\no<again> call\no<again> endsub\n");
  expect_error("G21\no<again> call\nM2\n", (second.path() / "again.ngc").string(), 3, "O<AGAIN>");
  // Numbered O-words are the file's own: the program's O100 loop and the file's O100 loop do not meet.
  test::write_text(second.path() / "loop.ngc", "o<loop> sub\no100 repeat [2]\nG91 G0 X1\no100 endrepeat\nG90\no<loop> endsub\n");
  test::write_text(first.path() / "loops.ngc", "G21 G90\nG0 X0 Y0 Z0\no100 repeat [3]\no<loop> call\no100 endrepeat\nM2\n");
  EXPECT_EQ(xs(read_gcode(first.path() / "loops.ngc", MachineSpec{}, options)), (std::vector<double>{0, 1, 2, 3, 4, 5, 6}));
  // parse_gcode has no directory of its own: the call is an error unless the options give one.
  expect_gcode_error("G21\no<row> call [1]\nM2\n", 2, "O<ROW>");
}

}  // namespace
}  // namespace tf
