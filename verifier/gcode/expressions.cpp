// The G-code reader's line parser: words whose values are numbers, parameters or expressions, and the
// line's parameter settings, evaluated as LinuxCNC's interpreter does (its operator precedence, left to
// right within a level; angles in degrees; EQ and NE within 0.0001).
#include "expressions.hpp"

#include <cctype>
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <string_view>

#include "tiltfield/core/error.hpp"

namespace tf::gcode {
namespace {

bool alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
// The letters that start a word: A to Z and LinuxCNC's polar coordinate words @ and ^.
bool word_letter(char c) { return alpha(c) || c == '@' || c == '^'; }

// The O-word keywords of LinuxCNC's subroutines and control flow (after the O number).
bool o_word_keyword(std::string_view rest) {
  static const char* const keywords[] = {"SUB", "ENDSUB", "CALL", "RETURN", "IF", "ELSEIF", "ELSE", "ENDIF", "DO",
                                         "WHILE", "ENDWHILE", "REPEAT", "ENDREPEAT", "BREAK", "CONTINUE"};
  for (const char* k : keywords)
    if (rest.substr(0, std::string_view(k).size()) == k) return true;
  return false;
}

constexpr char kOWords[] =
    "not an O-word LinuxCNC runs: O100 or O<name> followed by SUB, ENDSUB, CALL, RETURN, IF, ELSEIF, ELSE, ENDIF, "
    "DO, WHILE, ENDWHILE, REPEAT, ENDREPEAT, BREAK or CONTINUE";
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kEqualTolerance = 1e-4;  // LinuxCNC's TOLERANCE_EQUAL for EQ and NE
constexpr double kIntegerTolerance = 1e-4;  // how far a parameter number may be from an integer
constexpr int kMaxDepth = 64;             // nested brackets and parameter references

enum class Op { Power, Times, Divide, Mod, Plus, Minus, Eq, Ne, Gt, Ge, Lt, Le, And, Or, Xor };

int precedence(Op op) {
  switch (op) {
    case Op::Power: return 6;
    case Op::Times: case Op::Divide: case Op::Mod: return 5;
    case Op::Plus: case Op::Minus: return 4;
    case Op::Eq: case Op::Ne: case Op::Gt: case Op::Ge: case Op::Lt: case Op::Le: return 3;
    default: return 2;  // AND, OR, XOR
  }
}

class LineParser {
 public:
  LineParser(const std::string& code, const std::string& file, int line, const ParameterValues& params)
      : code_(code), file_(file), line_(line), params_(params) {}

  // Bracketed values from position `from` to the end of the line.
  std::vector<double> bracketed_values(size_t from, const std::string& word) {
    std::vector<double> out;
    for (i_ = from; i_ < code_.size();) {
      if (code_[i_] != '[') fail(word, "an O-word's arguments are bracketed expressions: " + word + " [...]");
      ++i_;
      out.push_back(finite(bracketed(1), word));
    }
    return out;
  }

  ParsedLine parse() {
    ParsedLine out;
    while (i_ < code_.size()) {
      if (code_[i_] == '#') {
        out.settings.push_back(setting());
        if (!out.settings.back().name.empty()) named_on_line_.push_back(out.settings.back().name);
      } else {
        out.words.push_back(word());
      }
    }
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(file_, line_, field, what);
  }
  char peek(size_t ahead = 0) const { return i_ + ahead < code_.size() ? code_[i_ + ahead] : '\0'; }
  // A few characters from position `from`, to name the place of an error.
  std::string near(size_t from) const { return code_.substr(from, 8); }
  // Beyond 1e9 (1000 km, or a feed or dwell as absurd) a number is a typo; this keeps every sum finite.
  double finite(double v, const std::string& text) const {
    if (!std::isfinite(v) || std::abs(v) > 1e9) fail(text, "number out of range");
    return v;
  }

  Word word() {
    const size_t start = i_;
    const char letter = code_[i_];
    if (!word_letter(letter)) fail(std::string(1, letter), "expected a word letter");
    if (letter == 'O' && peek(1) == '<') fail("O<", kOWords);
    ++i_;
    double v = 0.0;
    const bool plain = digit(peek()) || peek() == '.' || ((peek() == '+' || peek() == '-') && (digit(peek(1)) || peek(1) == '.'));
    if (plain) {
      v = number(true);
      const bool o_line = letter == 'O' && o_word_keyword(std::string_view(code_).substr(i_));
      // A number runs up to the next word or setting: "X1.2.3" or "Z-.5%" is a typo, not two words.
      if (!o_line && i_ < code_.size() && !word_letter(code_[i_]) && code_[i_] != '#')
        fail(code_.substr(start, i_ - start + 1), "malformed number");
    } else if (expression_follows()) {
      v = value(0);
    } else {
      fail(code_.substr(start, peek() == '+' || peek() == '-' ? 2 : 1), "missing or malformed number");
    }
    const std::string text = code_.substr(start, i_ - start);
    if (letter == 'O' && o_word_keyword(std::string_view(code_).substr(i_))) fail(text, kOWords);
    return {letter, finite(v, text), text};
  }

  ParameterSetting setting() {
    const size_t start = i_++;
    ParameterSetting s;
    if (peek() == '<') s.name = name();
    else s.number = parameter_number(0);
    s.text = code_.substr(start, i_ - start);
    if (peek() != '=') fail(s.text, "'=' expected after the parameter (a setting is #1 = value)");
    ++i_;
    s.value = finite(value(0), code_.substr(start, i_ - start));
    return s;
  }

  // [+-] digits [. digits], at least one digit. `word`: the value of a word (its sign read here).
  double number(bool word) {
    const size_t start = i_;
    if (peek() == '+' || peek() == '-') ++i_;
    bool digits = false, point = false;
    while (digit(peek()) || (peek() == '.' && !point)) {
      if (peek() == '.') point = true; else digits = true;
      ++i_;
    }
    if (!digits) fail(word && start > 0 ? code_.substr(start - 1, i_ - start + 1) : near(start), "missing or malformed number");
    // Hundreds of digits make inf, and SIN[inf] a NaN that every later comparison would let through. (A
    // word's value is held to 1e9 in word().)
    const double v = std::strtod(code_.substr(start, i_ - start).c_str(), nullptr);
    if (!std::isfinite(v)) fail(near(start), "number out of range");
    return v;
  }

  // A value other than a plain number at i_: "[", "#", a function or a signed value ("--1" is 1 in rs274),
  // each after an optional sign.
  bool expression_follows() const {
    const size_t at = i_ + (peek() == '+' || peek() == '-' ? 1 : 0);
    const char c = at < code_.size() ? code_[at] : '\0';
    return c == '[' || c == '#' || (at > i_ && (c == '+' || c == '-')) || function_follows(at);
  }

  // An alphabetic run at j that is followed by "[" (a function's name).
  bool function_follows(size_t j) const {
    const size_t from = j;
    while (j < code_.size() && alpha(code_[j])) ++j;
    return j > from && j < code_.size() && code_[j] == '[';
  }

  double value(int depth) {
    if (depth > kMaxDepth) fail(near(i_), "expression nested too deeply");
    const char c = peek();
    if (c == '[') {
      ++i_;
      return bracketed(depth + 1);
    }
    if (c == '#') {
      ++i_;
      return parameter(depth + 1);
    }
    if ((c == '+' || c == '-') && !digit(peek(1)) && peek(1) != '.') {
      ++i_;
      const double v = value(depth + 1);
      return c == '-' ? -v : v;
    }
    if (alpha(c)) return function(depth + 1);
    if (digit(c) || c == '.' || c == '+' || c == '-') return number(false);
    fail(c ? near(i_) : "end of line", "expected a number, a parameter or an expression");
  }

  // After "[": an expression up to and including its "]".
  double bracketed(int depth) {
    const size_t open = i_ - 1;
    const double v = binary(0, depth);
    if (peek() != ']') {
      if (i_ >= code_.size()) fail(near(open), "expression not closed: ']' missing");
      fail(near(i_), "unknown operator");
    }
    ++i_;
    return v;
  }

  double binary(int min_precedence, int depth) {
    double lhs = value(depth);
    for (;;) {
      const size_t at = i_;
      const std::optional<Op> op = binary_operator();
      if (!op) break;
      if (precedence(*op) < min_precedence) {
        i_ = at;
        break;
      }
      const std::string text = code_.substr(at, i_ - at);
      const double rhs = binary(precedence(*op) + 1, depth + 1);
      lhs = apply(*op, lhs, rhs, text);
    }
    return lhs;
  }

  // The operator at i_, consumed; nullopt (nothing consumed) at "]" or the end of the line.
  std::optional<Op> binary_operator() {
    static const std::pair<std::string_view, Op> ops[] = {
        {"**", Op::Power}, {"*", Op::Times}, {"/", Op::Divide}, {"MOD", Op::Mod}, {"+", Op::Plus}, {"-", Op::Minus},
        {"EQ", Op::Eq},    {"NE", Op::Ne},   {"GT", Op::Gt},    {"GE", Op::Ge},   {"LT", Op::Lt},  {"LE", Op::Le},
        {"AND", Op::And},  {"OR", Op::Or},   {"XOR", Op::Xor}};
    if (i_ >= code_.size() || code_[i_] == ']') return std::nullopt;
    const std::string_view rest = std::string_view(code_).substr(i_);
    for (const auto& [text, op] : ops)
      if (rest.substr(0, text.size()) == text) {
        i_ += text.size();
        return op;
      }
    fail(near(i_), "unknown operator");
  }

  // `at`: the operator as written, to name it in an error.
  double apply(Op op, double a, double b, const std::string& at) const {
    double r = 0.0;
    switch (op) {
      case Op::Power:
        if (a < 0.0 && std::floor(b) != b) fail(at, "negative number raised to a non-integer power");
        if (a == 0.0 && b < 0.0) fail(at, "zero raised to a negative power");
        r = std::pow(a, b);
        break;
      case Op::Times: r = a * b; break;
      case Op::Divide:
        if (b == 0.0) fail(at, "division by zero");
        r = a / b;
        break;
      case Op::Mod:
        if (b == 0.0) fail(at, "MOD by zero");
        r = std::fmod(a, b);
        if (r < 0.0) r += std::abs(b);  // LinuxCNC: the result takes the sign of neither operand
        break;
      case Op::Plus: r = a + b; break;
      case Op::Minus: r = a - b; break;
      case Op::Eq: r = std::abs(a - b) < kEqualTolerance; break;
      case Op::Ne: r = std::abs(a - b) >= kEqualTolerance; break;
      case Op::Gt: r = a > b; break;
      case Op::Ge: r = a >= b; break;
      case Op::Lt: r = a < b; break;
      case Op::Le: r = a <= b; break;
      case Op::And: r = a != 0.0 && b != 0.0; break;
      case Op::Or: r = a != 0.0 || b != 0.0; break;
      case Op::Xor: r = (a != 0.0) != (b != 0.0); break;
    }
    if (!std::isfinite(r)) fail(at, "the result is out of range");
    return r;
  }

  // NAME[expression], ATAN[y]/[x] or EXISTS[#<name>].
  double function(int depth) {
    const size_t start = i_;
    while (alpha(peek())) ++i_;
    const std::string f = code_.substr(start, i_ - start);
    if (peek() != '[') fail(f, "a function's argument goes in brackets: " + f + "[...]");
    ++i_;
    if (f == "EXISTS") {
      if (peek() != '#' || peek(1) != '<') fail(f, "EXISTS takes a named parameter: EXISTS[#<name>]");
      ++i_;
      const std::string n = name();
      const bool defined = params_.defined(n) || set_on_line(n);
      if (peek() != ']') fail(f, "EXISTS takes a named parameter: EXISTS[#<name>]");
      ++i_;
      return defined ? 1.0 : 0.0;
    }
    const double x = bracketed(depth);
    if (f == "ATAN") {
      if (peek() != '/' || peek(1) != '[') fail(f, "ATAN takes two arguments: ATAN[y]/[x]");
      i_ += 2;
      return std::atan2(x, bracketed(depth)) / kDeg;
    }
    if (f == "ABS") return std::abs(x);
    if (f == "ACOS" || f == "ASIN") {
      if (x < -1.0 || x > 1.0) fail(f, "argument outside -1 to 1");
      return (f == "ACOS" ? std::acos(x) : std::asin(x)) / kDeg;
    }
    if (f == "COS") return std::cos(x * kDeg);
    if (f == "SIN") return std::sin(x * kDeg);
    if (f == "TAN") return std::tan(x * kDeg);
    if (f == "EXP") return finite(std::exp(x), f);
    if (f == "FIX") return std::floor(x);
    if (f == "FUP") return std::ceil(x);
    if (f == "ROUND") return std::round(x);  // halves away from zero, as LinuxCNC
    if (f == "LN") {
      if (x <= 0.0) fail(f, "argument zero or negative");
      return std::log(x);
    }
    if (f == "SQRT") {
      if (x < 0.0) fail(f, "negative argument");
      return std::sqrt(x);
    }
    fail(f, "unknown function");
  }

  // After "#": the parameter's value.
  double parameter(int depth) {
    const size_t start = i_ - 1;
    if (peek() == '<') {
      const std::string n = name();
      const std::optional<double> v = params_.named(n);
      // rs274 makes a name as it reads its setting: later on the line it reads 0 until the line is done.
      if (!v && set_on_line(n)) return 0.0;
      if (!v) fail("#<" + n + ">", "named parameter not defined");
      return *v;
    }
    const int k = parameter_number(depth);
    const std::optional<double> v = params_.numbered(k);
    if (!v) fail(code_.substr(start, i_ - start), "system parameter #" + std::to_string(k) + " is not simulated");
    return *v;
  }

  // A parameter's number: any value, an integer within 1e-4, 1 ... kMaxParameter.
  int parameter_number(int depth) {
    const size_t start = i_ - 1;
    const double v = value(depth + 1);
    const std::string text = code_.substr(start, i_ - start);
    const double k = std::round(v);
    if (!std::isfinite(v) || std::abs(v - k) > kIntegerTolerance) fail(text, "parameter number is not an integer");
    if (k < 1 || k > kMaxParameter) fail(text, "parameter number out of range (1 to " + std::to_string(kMaxParameter) + ")");
    return static_cast<int>(k);
  }

  // After "#": "<name>", consumed; the name.
  std::string name() {
    const size_t start = i_++;
    const size_t close = code_.find('>', i_);
    if (close == std::string::npos) fail(near(start - 1), "named parameter not closed by '>'");
    if (close == i_) fail("#<>", "empty parameter name");
    i_ = close + 1;
    return code_.substr(start + 1, close - start - 1);
  }

  bool set_on_line(const std::string& n) const {
    for (const std::string& s : named_on_line_)
      if (s == n) return true;
    return false;
  }

  const std::string& code_;
  const std::string& file_;
  int line_;
  const ParameterValues& params_;
  size_t i_ = 0;
  std::vector<std::string> named_on_line_;  // the names this line has set so far
};

// The digits of an O number from code[from], leading zeros dropped, and where they end (i stays `from`
// when none).
std::string number_label(const std::string& code, size_t from, size_t& i) {
  i = from;
  while (i < code.size() && digit(code[i])) ++i;
  std::string label = code.substr(from, i - from);
  if (!label.empty()) label.erase(0, std::min(label.find_first_not_of('0'), label.size() - 1));
  return label;
}

}  // namespace

std::optional<OWord> o_word(const std::string& code) {
  // rs274 reads a line number first and lets it stand before an O-word as before any other line.
  const size_t at = line_number_end(code);
  if (code.size() < at + 2 || code[at] != 'O') return std::nullopt;
  OWord o;
  size_t i = at + 1;
  if (code[i] == '<') {
    const size_t close = code.find('>', i + 1);
    if (close == std::string::npos || close == i + 1) return std::nullopt;
    o.label = code.substr(i, close - i + 1);
    i = close + 1;
  } else {
    o.label = number_label(code, at + 1, i);
    if (i == at + 1) return std::nullopt;
  }
  const size_t k = i;
  while (i < code.size() && alpha(code[i])) ++i;
  o.keyword = code.substr(k, i - k);
  static const char* const keywords[] = {"SUB", "ENDSUB", "CALL", "RETURN", "IF", "ELSEIF", "ELSE", "ENDIF", "DO",
                                         "WHILE", "ENDWHILE", "REPEAT", "ENDREPEAT", "BREAK", "CONTINUE"};
  for (const char* kw : keywords)
    if (o.keyword == kw) {
      o.args = i;
      return o;
    }
  return std::nullopt;
}

std::optional<std::string> program_number(const std::string& code) {
  if (code.size() < 2 || code[0] != 'O') return std::nullopt;
  size_t i = 1;
  std::string label = number_label(code, 1, i);
  if (i == 1 || i != code.size()) return std::nullopt;
  return label;
}

std::vector<double> o_word_values(const std::string& code, const OWord& o, const std::string& file, int line,
                                  const ParameterValues& params) {
  return LineParser(code, file, line, params).bracketed_values(o.args, o.name());
}

ParsedLine parse_line(const std::string& code, const std::string& file, int line, const ParameterValues& params) {
  return LineParser(code, file, line, params).parse();
}

}  // namespace tf::gcode
