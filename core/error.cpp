#include "tiltfield/core/error.hpp"

namespace tf {
namespace {
std::string compose(const std::string& file, int line, const std::string& field, const std::string& what) {
  std::string s;
  s.reserve(file.size() + field.size() + what.size() + 32);
  s.append(file);
  if (line > 0) s.append(":").append(std::to_string(line));
  if (!field.empty()) s.append(s.empty() ? "" : ": ").append("field '").append(field).append("'");
  if (!s.empty()) s.append(": ");
  s.append(what);
  return s;
}
}  // namespace

InputError::InputError(std::string file, int line, std::string field, const std::string& what)
    : std::runtime_error(compose(file, line, field, what)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      reason_(what) {}

}  // namespace tf
