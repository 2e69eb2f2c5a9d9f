// tiltfield gcode (internal): RS274/NGC parameters and expressions as LinuxCNC's interpreter reads them.
// A line's words may take their values from numbered (#1 ... #5602) or named (#<name>, #<_global>)
// parameters and from bracketed expressions ([#1 * 2], SIN[30], ATAN[#2]/[#3]); "#1 = ..." and
// "#<name> = ..." set parameters once the whole line has been read (a word of the same line reads the old
// value). Not here: O-word subroutines and control flow (refused with their own message).
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

// The highest numbered parameter (LinuxCNC's RS274NGC_MAX_PARAMETERS - 1).
inline constexpr int kMaxParameter = 5602;

// Reads one code line (strip_line's output: upper case, no blanks or comments) into words with their
// values and the parameter settings it makes. Throws InputError (file, line, the word or operator, what is
// wrong) on a malformed number or expression, an undefined named parameter, a parameter number out of
// range, a division by zero or a function outside its domain, and on O-word subroutines and control flow.
ParsedLine parse_line(const std::string& code, const std::string& file, int line, const ParameterValues& params);

}  // namespace tf::gcode
