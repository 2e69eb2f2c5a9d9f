// tiltfield gcode (internal): RS274/NGC parameters and expressions as LinuxCNC's interpreter reads them.
// A line's words may take their values from numbered (#1 ... #5602) or named (#<name>, #<_global>)
// parameters and from bracketed expressions ([#1 * 2], SIN[30], ATAN[#2]/[#3]); "#1 = ..." and
// "#<name> = ..." set parameters once the whole line has been read (a word of the same line reads the old
// value). O-word lines (subroutines and control flow) are recognised here and run by the reader (control.cpp).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "words.hpp"

namespace tf::gcode {

// The values a line's parameter references read.
class ParameterValues {
 public:
  virtual ~ParameterValues() = default;
  // Numbered parameter k (1 ... 5602). nullopt: a system parameter the reader does not simulate.
  virtual std::optional<double> numbered(int k) const = 0;
  // Named parameter (upper case, as the line is), nullopt when it is not defined.
  virtual std::optional<double> named(const std::string& name) const = 0;
  // Whether a named parameter is defined (EXISTS), without reading it.
  virtual bool defined(const std::string& name) const = 0;
};

// One "#k = value" or "#<name> = value" of a line: number k, or name when number is 0.
struct ParameterSetting {
  int number = 0;
  std::string name;
  double value = 0.0;
  std::string text;  // "#3" or "#<depth>", for messages
};

struct ParsedLine {
  std::vector<Word> words;
  std::vector<ParameterSetting> settings;
};

// An O-word line of LinuxCNC's subroutines and control flow: "O100 WHILE [#1 LT 3]", "O<probe> CALL [2]".
struct OWord {
  std::string label;    // "100" (leading zeros dropped) or "<PROBE>"
  std::string keyword;  // SUB ENDSUB CALL RETURN IF ELSEIF ELSE ENDIF DO WHILE ENDWHILE REPEAT ENDREPEAT BREAK CONTINUE
  size_t args = 0;      // where its bracketed values start in the line
  std::string name() const { return "O" + label; }
};

// The O-word a code line (strip_line's output) opens with; nullopt for any other line (a plain "O1000"
// program number included).
std::optional<OWord> o_word(const std::string& code);

// The number of a Fanuc-style program line, "O1000" alone (what M98 P1000 calls; the main program's own
// number too), leading zeros dropped as in OWord::label; nullopt for any other line.
std::optional<std::string> program_number(const std::string& code);

// The bracketed values after an O-word ("[1] [#2 * 3]": a call's arguments, a condition, a return value),
// evaluated now. Throws InputError on anything else after the O-word or a bad expression.
std::vector<double> o_word_values(const std::string& code, const OWord& o, const std::string& file, int line,
                                  const ParameterValues& params);

// The highest numbered parameter (LinuxCNC's RS274NGC_MAX_PARAMETERS - 1).
inline constexpr int kMaxParameter = 5602;

// Reads one code line (strip_line's output: upper case, no blanks or comments) into words with their
// values and the parameter settings it makes. Throws InputError (file, line, the word or operator, what is
// wrong) on a malformed number or expression, an undefined named parameter, a parameter number out of
// range, a division by zero or a function outside its domain, and on O-word subroutines and control flow.
ParsedLine parse_line(const std::string& code, const std::string& file, int line, const ParameterValues& params);

}  // namespace tf::gcode
