// tiltfield: the one error type that parsers throw.
//
// Parsers never print and never exit: they throw InputError carrying the file, the line (0 when the
// problem is not tied to a line) and the field. Only the command line turns it into exit code 2.
#pragma once
#include <stdexcept>
#include <string>

namespace tf {

class InputError : public std::runtime_error {
 public:
  // file: the path as the user gave it; line: 1-based, 0 for none; field: JSON key path, CSV column or
  // G-code word, may be empty; what: what is wrong, in plain words.
  InputError(std::string file, int line, std::string field, const std::string& what);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_;
  int line_;
  std::string field_;
  std::string reason_;
};

// A failure of the job itself (exit 1): e.g. collisions left when asked to fail on them.
class JobError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tf
