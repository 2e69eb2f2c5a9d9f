// The lexical part of the G-code reader: comments, words, numbers and code keys.
#include "words.hpp"

#include <cctype>
#include <cmath>
#include <exception>

#include "tiltfield/core/error.hpp"

namespace tf::gcode {
namespace {

bool alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// The O-word keywords of LinuxCNC's subroutines and control flow (after the O number).
bool o_word_keyword(std::string_view rest) {
  static const char* const keywords[] = {"SUB", "ENDSUB", "CALL", "RETURN", "IF", "ELSEIF", "ELSE", "ENDIF", "DO",
                                         "WHILE", "ENDWHILE", "REPEAT", "ENDREPEAT", "BREAK", "CONTINUE"};
  for (const char* k : keywords)
    if (rest.substr(0, std::string_view(k).size()) == k) return true;
  return false;
}

}  // namespace

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

std::vector<Word> split_words(const std::string& code, const std::string& file, int line) {
  std::vector<Word> words;
  size_t i = 0;
  while (i < code.size()) {
    const char letter = code[i];
    if (letter == '#' || letter == '[' || letter == '<')
      throw InputError(file, line, std::string(1, letter), "parameters and expressions are not supported");
    if (!alpha(letter)) throw InputError(file, line, std::string(1, letter), "expected a word letter");
    if (letter == 'O' && i + 1 < code.size() && code[i + 1] == '<')
      throw InputError(file, line, "O<", "O-word subroutines and control flow are not supported");
    size_t j = i + 1;
    if (j < code.size() && (code[j] == '+' || code[j] == '-')) ++j;
    if (j < code.size() && (code[j] == '#' || code[j] == '[' || code[j] == '<'))
      throw InputError(file, line, std::string(1, letter), "parameters and expressions are not supported");
    bool digits = false, point = false;
    while (j < code.size() && (digit(code[j]) || (code[j] == '.' && !point))) {
      if (code[j] == '.') point = true; else digits = true;
      ++j;
    }
    const std::string text = code.substr(i, j - i);
    if (letter == 'O' && digits && o_word_keyword(std::string_view(code).substr(j)))
      throw InputError(file, line, text, "O-word subroutines and control flow are not supported");
    if (!digits) throw InputError(file, line, text.empty() ? std::string(1, letter) : text, "missing or malformed number");
    if (j < code.size() && !alpha(code[j]) && code[j] != '#' && code[j] != '[')
      throw InputError(file, line, code.substr(i, j - i + 1), "malformed number");
    double v = 0.0;
    try {
      v = std::stod(code.substr(i + 1, j - i - 1));
    } catch (const std::exception&) {
      throw InputError(file, line, text, "malformed number");
    }
    // Beyond 1e9 (1000 km, or a feed or dwell as absurd) a number is a typo; this keeps every sum finite.
    if (!std::isfinite(v) || std::abs(v) > 1e9) throw InputError(file, line, text, "number out of range");
    words.push_back({letter, v, text});
    i = j;
  }
  return words;
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
