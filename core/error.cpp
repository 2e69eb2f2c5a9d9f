#include "tiltfield/core/error.hpp"

namespace tf {
namespace {
// The message on one line of text: control characters and bytes that are no UTF-8 shown as \xNN (a CSV
// cell's stray 0xFF had gone to the terminal raw; a newline in a quoted cell broke the one line).
std::string printable(const std::string& in) {
  std::string out;
  out.reserve(in.size());
  auto hex = [&](unsigned char c) {
    static const char* digits = "0123456789ABCDEF";
    out.append("\\x").push_back(digits[c >> 4]);
    out.push_back(digits[c & 15]);
  };
  for (size_t i = 0; i < in.size();) {
    const auto c = static_cast<unsigned char>(in[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7F) hex(c); else out.push_back(static_cast<char>(c));
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (no overlong two-byte forms) is kept whole.
    const size_t len = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    bool ok = len > 0 && i + len <= in.size();
    for (size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(in[i + k]) & 0xC0) == 0x80;
    if (ok) {
      out.append(in, i, len);
      i += len;
    } else {
      hex(c);
      ++i;
    }
  }
  return out;
}

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
    : std::runtime_error(printable(compose(file, line, field, what))),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      reason_(what) {}

}  // namespace tf
