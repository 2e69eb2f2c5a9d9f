// tiltfield gcode (internal): the lexical part of a line of RS274/NGC text: comments and blanks removed,
// letters in upper case, G and M numbers as integer keys (the words themselves: expressions.hpp).
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tf::gcode {

struct Word {
  char letter;
  double value;
  std::string text;  // as written (letter + number), for messages
};

// The lines of a program's text, without their "\n" (the "\r" of a "\r\n" is kept: rs274 counts it in a
// line's length, and strip_line reads it as a blank); views into `text`.
std::vector<std::string_view> split_lines(std::string_view text);

// Strips "( ... )" and "; ..." comments and whitespace; returns the code part in upper case.
// Throws InputError on an unclosed "(", on a comment that is not between two items of the line, and on one
// before an O-word's keyword ("(c) o100 sub", "o100 (c) sub": rs274 refuses both).
std::string strip_line(std::string_view raw, const std::string& file, int line);

// Where a line's items start after its line number ("N10" or rs274's sub-line "N10.1"): 0 when it has none.
// `code` is strip_line's output.
size_t line_number_end(std::string_view code);

// A G or M number with up to one decimal, as an integer key: G43.4 -> 434, G1 -> 10. Throws on anything else.
int code_key(const Word& w, const std::string& file, int line);

// "G43.4" from the key 434.
std::string code_name(char letter, int key);

// "M128" (or "m128", "M 128") -> key 1280; nullopt when the text names no M code.
std::optional<int> machine_m_code(const std::string& code);

// A block's value words (not G, M, N or O) by letter, with their text for messages: A to Z, and LinuxCNC's
// polar coordinates @ (the distance) and ^ (the angle).
struct Values {
  static size_t slot(char c) { return c == '@' ? 26 : c == '^' ? 27 : size_t(c - 'A'); }
  std::array<std::optional<double>, 28> value{};
  std::array<std::string, 28> text{};
  const std::optional<double>& operator[](char c) const { return value[slot(c)]; }
  bool has(char c) const { return value[slot(c)].has_value(); }
  bool polar() const { return has('@') || has('^'); }
  std::string word(char c) const { return text[slot(c)].empty() ? std::string(1, c) : text[slot(c)]; }
};

}  // namespace tf::gcode
