// The lexical part of the G-code reader: comments and code keys.
#include "words.hpp"

#include <cctype>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <exception>

#include "tiltfield/core/error.hpp"

namespace tf::gcode {

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  for (size_t pos = 0; pos <= text.size();) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    lines.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return lines;
}

namespace {

// What may follow a comment: the start of the next item of the line (a word's letter, LinuxCNC's polar
// words, a parameter setting), another comment, or nothing.
bool starts_item(char upper) { return std::isalpha(static_cast<unsigned char>(upper)) || upper == '@' || upper == '^' || upper == '#'; }

// Where the keyword of an O-word line ends ("O100SUB", "N5O<X>CALL[1]": after SUB, CALL), or npos when
// the line does not open with an O number or name followed by letters.
size_t o_keyword_end(std::string_view code) {
  size_t i = line_number_end(code);
  if (i >= code.size() || code[i] != 'O') return std::string_view::npos;
  const size_t label = ++i;
  if (i < code.size() && code[i] == '<') {
    i = code.find('>', i);
    if (i == std::string_view::npos) return i;
    ++i;
  } else {
    while (i < code.size() && std::isdigit(static_cast<unsigned char>(code[i]))) ++i;
  }
  const size_t keyword = i;
  while (i < code.size() && std::isalpha(static_cast<unsigned char>(code[i]))) ++i;
  return i == keyword || keyword == label ? std::string_view::npos : i;
}

}  // namespace

size_t line_number_end(std::string_view code) {
  if (code.empty() || code[0] != 'N') return 0;
  size_t i = 1;
  while (i < code.size() && std::isdigit(static_cast<unsigned char>(code[i]))) ++i;
  if (i == 1) return 0;
  if (i + 1 < code.size() && code[i] == '.' && std::isdigit(static_cast<unsigned char>(code[i + 1]))) {
    ++i;
    while (i < code.size() && std::isdigit(static_cast<unsigned char>(code[i]))) ++i;
  }
  return i;
}

std::string strip_line(std::string_view raw, const std::string& file, int line) {
  std::string out;
  out.reserve(raw.size());
  bool in_comment = false, after_comment = false;
  size_t first_comment = std::string::npos;  // where in `out` the line's first comment came
  int depth = 0;  // of expression brackets
  // rs274 reads a comment as an item of its own, between words: one inside a number, an expression or a
  // parameter's name ("X1(c).5", "G(c)1", "X[1 (c) + 2]") is refused there, where stripping it first had
  // joined the pieces into a word (black-box testing).
  auto inside_a_word = [&](char ch) {
    return InputError(file, line, std::string(1, ch), "a comment inside a word or expression (LinuxCNC refuses it)");
  };
  for (char ch : raw) {
    const auto u = static_cast<unsigned char>(ch);
    // A control byte (a NUL cut the message that named it short) or a byte of binary data: refused, as
    // rs274 does ("Bad character"), and named by its code.
    if ((u < 0x20 && ch != '\t' && ch != '\r' && ch != '\f' && ch != '\v') || u == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02X", unsigned(u));
      throw InputError(file, line, code, "control character in the program (binary data?)");
    }
    if (in_comment) {
      if (ch == ')') in_comment = false;
      if (ch == '(') throw InputError(file, line, "(", "nested comment (LinuxCNC refuses them)");
      continue;
    }
    if (ch == '(' || ch == ';') {
      if (depth > 0) throw inside_a_word(ch);
      first_comment = std::min(first_comment, out.size());
      if (ch == ';') break;
      in_comment = after_comment = true;
      continue;
    }
    if (ch == ')') throw InputError(file, line, ")", "')' without an opening '('");
    if (std::isspace(u)) continue;
    const char upper = static_cast<char>(std::toupper(u));
    // A call's arguments are bracketed expressions, whole items of their own ("o100 call (c) [1] (c) [2]",
    // as rs274 reads them; "o100 if (c) [1]" it refuses).
    const size_t items = line_number_end(out);
    const bool argument = upper == '[' && out.size() > items && out[items] == 'O' && out.find("CALL") != std::string::npos;
    if (after_comment && !starts_item(upper) && !argument) throw inside_a_word(ch);
    after_comment = false;
    depth += upper == '[' ? 1 : upper == ']' ? -1 : 0;
    out.push_back(upper);
  }
  if (in_comment) throw InputError(file, line, "(", "comment is not closed on this line");
  // rs274 reads an O-word's number and keyword as one item that must open the line (after its number).
  const size_t keyword_end = o_keyword_end(out);
  if (keyword_end != std::string::npos && first_comment < keyword_end) {
    const size_t o = line_number_end(out);
    throw InputError(file, line, out.substr(o, keyword_end - o), "a comment before an O-word's keyword (LinuxCNC refuses it)");
  }
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
