// Grinding scene loader: JSON scene + G-code-like program (format in docs/grinding.md).
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>

#include "tiltfield/core/internal/json_fields.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/grind/grind.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::grind {
namespace {

using namespace tf::json_fields;
namespace fs = std::filesystem;

constexpr double kMinBlankRadius = 0.01;  // mm

const char* const kKinds[] = {"fluting", "gashing", "od_sharpening", "end_face", "notching"};

void within_travel(double v, const std::string& file, const std::string& field) {
  if (v <= kMaxTravelMm) return;
  std::ostringstream msg;
  msg << "is " << v << " mm, beyond the grinder's +-" << kMaxTravelMm << " mm (a lost decimal point?)";
  throw InputError(file, 0, field, msg.str());
}

Wheel parse_wheel(const json& j, const std::string& file) {
  require_object(j, file, "wheel");
  only_keys(j, {"radius", "thickness", "edge_radius", "profile"}, file, "wheel");
  Wheel w;
  w.radius = positive(required_number(j, "radius", file, "wheel"), file, "wheel.radius");
  w.thickness = positive(required_number(j, "thickness", file, "wheel"), file, "wheel.thickness");
  within_travel(w.radius, file, "wheel.radius");
  within_travel(w.thickness, file, "wheel.thickness");
  w.edge_radius = number_or(j, "edge_radius", 0.0, file, "wheel");
  if (w.edge_radius < 0.0) throw InputError(file, 0, "wheel.edge_radius", "must not be negative");
  if (w.edge_radius > 0.5 * w.thickness || w.edge_radius > w.radius)
    throw InputError(file, 0, "wheel.edge_radius", "must not exceed half the thickness nor the radius");
  if (!j.contains("profile")) {
    w.profile = make_wheel_profile(w.radius, w.thickness, w.edge_radius);
    return w;
  }
  if (j.contains("edge_radius"))
    throw InputError(file, 0, "wheel.profile", "give either edge_radius or profile, not both");
  const json& p = j.at("profile");
  if (!p.is_array() || p.size() < 2) throw InputError(file, 0, "wheel.profile", "must be an array of >= 2 [t, rho] pairs");
  for (size_t i = 0; i < p.size(); ++i) {
    const std::string f = "wheel.profile[" + std::to_string(i) + "]";
    if (!p[i].is_array() || p[i].size() != 2) throw InputError(file, 0, f, "must be a pair [t, rho]");
    const Eigen::Vector2d q(number(p[i][0], file, f + "[0]"), number(p[i][1], file, f + "[1]"));
    if (q.y() < 0.0 || q.y() > w.radius + 1e-9) throw InputError(file, 0, f, "rho must be in [0, wheel.radius]");
    if (std::abs(q.x()) > 0.5 * w.thickness + 1e-9) throw InputError(file, 0, f, "t must be within +-thickness/2");
    if (!w.profile.empty() && !(q.x() > w.profile.back().x()))
      throw InputError(file, 0, f, "t must increase along the profile");
    w.profile.push_back(q);
  }
  // The hull of the rings is the wheel's section only for a convex wheel: rho must be concave in t. A point
  // within kConcaveTolerance inside the chord of its neighbours is taken as on it (the wheel as its hull):
  // a profile written to 4 decimals had been refused for 5e-5 mm (black-box testing).
  constexpr double kConcaveTolerance = 1e-3;  // mm
  for (size_t i = 1; i + 1 < w.profile.size(); ++i) {
    const Eigen::Vector2d a = w.profile[i] - w.profile[i - 1], b = w.profile[i + 1] - w.profile[i];
    const Eigen::Vector2d chord = w.profile[i + 1] - w.profile[i - 1];
    const double inside = (a.x() * b.y() - a.y() * b.x()) / std::max(chord.norm(), 1e-12);  // below the chord, mm
    if (inside > kConcaveTolerance) {
      std::ostringstream msg;
      msg << "profile must be convex (rho concave in t): this point lies " << std::setprecision(4) << inside
          << " mm inside the line through its neighbours (at most " << kConcaveTolerance << " mm is taken as on it)";
      throw InputError(file, 0, "wheel.profile[" + std::to_string(i) + "]", msg.str());
    }
  }
  return w;
}

// An axis value within the grinder's plausible range (kMaxTravelMm, kMaxTurnDeg).
void check_axis_range(double v, char axis, const std::string& file, int line, const std::string& field) {
  const bool rotary = axis == 'A' || axis == 'W' || axis == 'a' || axis == 'w';
  const double limit = rotary ? kMaxTurnDeg : kMaxTravelMm;
  if (std::abs(v) <= limit) return;
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(3) << "puts " << char(std::toupper(static_cast<unsigned char>(axis)))
      << " at " << v << (rotary ? " deg" : " mm") << ", beyond +-" << std::setprecision(0) << limit
      << (rotary ? " deg" : " mm") << " (a lost decimal point?)";
  throw InputError(file, line, field, msg.str());
}

Axes parse_start(const json& j, const std::string& file) {
  require_object(j, file, "start");
  only_keys(j, {"x", "y", "z", "u", "a", "w"}, file, "start");
  Axes s;
  s.x = number_or(j, "x", 0.0, file, "start");
  s.y = number_or(j, "y", 0.0, file, "start");
  s.z = number_or(j, "z", 0.0, file, "start");
  s.u = number_or(j, "u", 0.0, file, "start");
  s.a = number_or(j, "a", 0.0, file, "start");
  s.w = number_or(j, "w", 0.0, file, "start");
  const std::pair<double, char> values[] = {{s.x, 'x'}, {s.y, 'y'}, {s.z, 'z'}, {s.u, 'u'}, {s.a, 'a'}, {s.w, 'w'}};
  for (const auto& [v, axis] : values) check_axis_range(v, axis, file, 0, std::string("start.") + axis);
  return s;
}

// Strips "( ... )" and ";" comments; an unclosed "(" is an error.
std::string strip_comments(const std::string& line, const std::string& file, int n) {
  std::string out;
  bool in_paren = false;
  for (char c : line) {
    if (in_paren) {
      in_paren = c != ')';
      continue;
    }
    if (c == ';') break;
    if (c == '(') {
      in_paren = true;
      continue;
    }
    out += c;
  }
  if (in_paren) throw InputError(file, n, "", "unclosed comment '('");
  return out;
}

double& axis_ref(Axes& a, char w) {
  switch (w) {
    case 'X': return a.x;
    case 'Y': return a.y;
    case 'Z': return a.z;
    case 'U': return a.u;
    case 'A': return a.a;
    default: return a.w;
  }
}

}  // namespace

std::vector<Operation> parse_grind_program(const std::string& text, const std::string& file, const Axes& start) {
  std::vector<Operation> ops;
  std::istringstream in{std::string(without_utf8_bom(text))};
  std::string raw;
  int n = 0;
  Axes pos = start;
  bool incremental = false, rapid = false;
  while (std::getline(in, raw)) {
    ++n;
    // Control bytes (a NUL cut the message short) are no G-code.
    for (const unsigned char c : raw)
      if (c < 0x20 && c != '\t' && c != '\r') {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02x", c);
        throw InputError(file, n, hex, "binary data: a control byte in a program line");
      }
    std::string line = strip_comments(raw, file, n);
    std::istringstream words(line);
    std::string first;
    if (!(words >> first)) continue;
    std::string upper = first;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (upper == "OP") {
      Operation op;
      op.line = n;
      if (!(words >> op.kind)) throw InputError(file, n, "OP", "missing operation kind");
      bool known = false;
      for (const char* k : kKinds) known |= op.kind == k;
      if (!known)
        throw InputError(file, n, "OP", "unknown operation kind '" + op.kind +
                                             "' (fluting, gashing, od_sharpening, end_face, notching)");
      std::string rest;
      std::getline(words, rest);
      const auto b = rest.find_first_not_of(" \t\r");
      op.label = b == std::string::npos ? op.kind : rest.substr(b, rest.find_last_not_of(" \t\r") - b + 1);
      ops.push_back(std::move(op));
      continue;
    }
    // Motion line: split into letter + number words ("G1", "X-2.5"); spaces between words optional.
    Axes target = pos;
    bool has_axis = false;
    std::string seen;  // the words' letters (a G: its modal group) on this line, which G-code allows once
    auto once = [&](char key, const std::string& word, const char* what) {
      if (seen.find(key) != std::string::npos) throw InputError(file, n, word, std::string("a second ") + what + " on one line");
      seen += key;
    };
    size_t i = 0;
    while (i < line.size()) {
      const unsigned char ch = static_cast<unsigned char>(line[i]);
      if (std::isspace(ch)) {
        ++i;
        continue;
      }
      const char letter = static_cast<char>(std::toupper(ch));
      size_t j = i + 1;
      while (j < line.size() && !std::isalpha(static_cast<unsigned char>(line[j])) &&
             !std::isspace(static_cast<unsigned char>(line[j])))
        ++j;
      // A number like 1e3 splits into the words "X1" and "e3": name the number, not the exponent.
      if (j < line.size() && (line[j] == 'e' || line[j] == 'E') && j > i + 1 &&
          (std::isdigit(static_cast<unsigned char>(line[j - 1])) || line[j - 1] == '.')) {
        size_t k = j + 1;
        while (k < line.size() && !std::isalpha(static_cast<unsigned char>(line[k])) &&
               !std::isspace(static_cast<unsigned char>(line[k])))
          ++k;
        throw InputError(file, n, line.substr(i, k - i), "exponent notation is not G-code: write the number out");
      }
      const std::string word = line.substr(i, j - i);
      const std::string num = line.substr(i + 1, j - i - 1);
      i = j;
      if (!std::isalpha(ch)) throw InputError(file, n, word, "expected a word like X12.5");
      if (num.empty()) throw InputError(file, n, word, "word without a number");
      if (letter == 'N') continue;  // block number
      const double v = parse_number(num, file, n, std::string(1, letter));
      if (letter == 'G') {
        once(v == 90.0 || v == 91.0 ? 'd' : 'm', word, v == 90.0 || v == 91.0 ? "G90/G91" : "motion G code");
        if (v == 0.0) rapid = true;
        else if (v == 1.0) rapid = false;
        else if (v == 90.0) incremental = false;
        else if (v == 91.0) incremental = true;
        else throw InputError(file, n, word, "unsupported G code (G0, G1, G90, G91)");
        continue;
      }
      if (letter == 'F') {
        once('F', word, "F word");
        if (!(v > 0.0)) throw InputError(file, n, word, "feed must be positive");
        continue;
      }
      if (std::string("XYZUAW").find(letter) == std::string::npos)
        throw InputError(file, n, word, "unknown axis word (X, Y, Z, U, A, W, G, F, N)");
      once(letter, word, (std::string(1, letter) + " word").c_str());
      double& ref = axis_ref(target, letter);
      ref = incremental ? ref + v : v;
      check_axis_range(ref, letter, file, n, word);
      has_axis = true;
    }
    if (!has_axis) continue;
    if (ops.empty()) throw InputError(file, n, "", "motion before the first OP statement");
    ops.back().moves.push_back(Move{target, n, rapid});
    pos = target;
  }
  for (const Operation& op : ops)
    if (op.moves.empty()) throw InputError(file, op.line, "OP", "operation '" + op.label + "' has no motion");
  return ops;
}

GrindScene load_grind_scene(const fs::path& path) {
  const std::string file = path.string();
  const json j = parse_file(file, "grinding scene");
  require_object(j, file, "");
  only_keys(j, {"units", "blank", "wheel", "start", "program"}, file, "");
  if (j.contains("units") && string(j.at("units"), file, "units") != "mm")
    throw InputError(file, 0, "units", "only \"mm\" is supported");
  GrindScene s;
  s.file = file;
  if (!j.contains("blank")) throw InputError(file, 0, "blank", "missing");
  const json& b = j.at("blank");
  require_object(b, file, "blank");
  only_keys(b, {"radius", "length"}, file, "blank");
  s.blank.radius = positive(required_number(b, "radius", file, "blank"), file, "blank.radius");
  // Below this the sections' contours collapse at the geometry's tolerances (a radius of 1e-7 mm failed to
  // close its surface); no ground tool is that thin.
  if (s.blank.radius < kMinBlankRadius)
    throw InputError(file, 0, "blank.radius", "must be at least 0.01 mm");
  s.blank.length = positive(required_number(b, "length", file, "blank"), file, "blank.length");
  // Beyond the grinder's travel a dimension is a typo; it was blamed on --spacing or --step before.
  within_travel(s.blank.radius, file, "blank.radius");
  within_travel(s.blank.length, file, "blank.length");
  if (!j.contains("wheel")) throw InputError(file, 0, "wheel", "missing");
  s.wheel = parse_wheel(j.at("wheel"), file);
  if (j.contains("start")) s.start = parse_start(j.at("start"), file);
  if (!j.contains("program")) throw InputError(file, 0, "program", "missing");
  const json& p = j.at("program");
  if (p.is_string()) {
    if (p.get<std::string>().empty())
      throw InputError(file, 0, "program", "is empty: name the program file, or give its lines as an array");
    const fs::path prog = path.parent_path() / p.get<std::string>();
    s.program = prog.string();
    s.operations = parse_grind_program(read_text_file(prog, "grinding program"), prog.string(), s.start);
  } else if (p.is_array()) {
    std::string text;
    for (size_t i = 0; i < p.size(); ++i) text += string(p[i], file, "program[" + std::to_string(i) + "]") + "\n";
    s.program = file + " (program)";
    s.operations = parse_grind_program(text, s.program, s.start);
  } else {
    throw InputError(file, 0, "program", "must be a file name or an array of lines");
  }
  if (s.operations.empty()) throw InputError(file, 0, "program", "has no operation");
  return s;
}

}  // namespace tf::grind
