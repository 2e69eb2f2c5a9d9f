// The lexical part of the G-code reader: comments and code keys.
#include "words.hpp"

#include <cctype>
#include <cmath>
#include <exception>

#include "tiltfield/core/error.hpp"

namespace tf::gcode {

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  for (size_t pos = 0; pos <= text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    pos = end + 1;
  }
  return lines;
}

std::string strip_line(std::string_view raw, const std::string& file, int line) {
  std::string out;
  out.reserve(raw.size());
  bool in_comment = false;
  for (char ch : raw) {
    if (in_comment) {
      if (ch == ')') in_comment = false;
      continue;
    }
    if (ch == '(') { in_comment = true; continue; }
    if (ch == ';') break;
    if (std::isspace(static_cast<unsigned char>(ch))) continue;
    out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
  }
  if (in_comment) throw InputError(file, line, "(", "comment is not closed on this line");
  return out;
}

int code_key(const Word& w, const std::string& file, int line) {
  const double k = std::round(w.value * 10.0);
  if (std::abs(k - w.value * 10.0) > 1e-6 || k < 0 || k > 99990)
    throw InputError(file, line, w.text, "not a valid code number");
  return static_cast<int>(k);
}

std::string code_name(char letter, int key) {
  std::string s(1, letter);
  s.append(std::to_string(key / 10));
  if (key % 10) s.append(".").append(std::to_string(key % 10));
  return s;
}

std::optional<int> machine_m_code(const std::string& code) {
  std::string s;
  for (char ch : code)
    if (!std::isspace(static_cast<unsigned char>(ch))) s.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
  if (s.size() < 2 || s[0] != 'M') return std::nullopt;
  try {
    size_t used = 0;
    const double v = std::stod(s.substr(1), &used);
    if (used != s.size() - 1 || !std::isfinite(v) || std::abs(v) > 1e5) return std::nullopt;
    return static_cast<int>(std::lround(v * 10.0));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace tf::gcode
