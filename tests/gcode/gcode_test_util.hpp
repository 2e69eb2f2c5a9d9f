// Shared helpers of the G-code reader's tests: parse a program text as file "p.ngc", and expect the
// InputError that names its line and word.
#pragma once
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "tiltfield/core/error.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace tf::test {

inline Program parse_program(const std::string& text, const GcodeOptions& options = {},
                             const MachineSpec& machine = MachineSpec{}) {
  return parse_gcode(text, "p.ngc", machine, options);
}

inline void expect_gcode_error(const std::string& text, int line, const std::string& field,
                               const GcodeOptions& options = {}, const MachineSpec& machine = MachineSpec{}) {
  try {
    parse_program(text, options, machine);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "p.ngc");
    EXPECT_EQ(e.line(), line) << e.what() << "\n" << text;
    EXPECT_EQ(e.field(), field) << e.what() << "\n" << text;
  }
}

// One refused program: its text, the line and the field the error names.
struct Refused {
  std::string text;
  int line;
  std::string field;
};

inline void expect_refused(std::initializer_list<Refused> cases) {
  for (const Refused& c : cases) expect_gcode_error(c.text, c.line, c.field);
}

}  // namespace tf::test
