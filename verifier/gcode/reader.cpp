#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/core/io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "tiltfield/core/error.hpp"

namespace tf {
namespace {

struct Word {
  char letter;
  double value;
  std::string text;  // as written (letter + number), for messages
};

// Strips "( ... )" and "; ..." comments and whitespace; returns the code part in upper case.
// Throws on an unclosed "(".
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

// Splits "G1X10.5Y-3" into words. Numbers are RS274 decimals: [+-] digits [. digits] (no exponent).
std::vector<Word> split_words(const std::string& code, const std::string& file, int line) {
  std::vector<Word> words;
  size_t i = 0;
  while (i < code.size()) {
    const char letter = code[i];
    if (letter == '#' || letter == '[' || letter == '<')
      throw InputError(file, line, std::string(1, letter), "parameters and expressions are not supported");
    if (!std::isalpha(static_cast<unsigned char>(letter)))
      throw InputError(file, line, std::string(1, letter), "expected a word letter");
    size_t j = i + 1;
    if (j < code.size() && (code[j] == '+' || code[j] == '-')) ++j;
    bool digits = false, point = false;
    while (j < code.size() && (std::isdigit(static_cast<unsigned char>(code[j])) || (code[j] == '.' && !point))) {
      if (code[j] == '.') point = true; else digits = true;
      ++j;
    }
    const std::string text = code.substr(i, j - i);
    if (!digits) throw InputError(file, line, text.empty() ? std::string(1, letter) : text, "missing or malformed number");
    if (j < code.size() && !std::isalpha(static_cast<unsigned char>(code[j])) && code[j] != '#' && code[j] != '[')
      throw InputError(file, line, code.substr(i, j - i + 1), "malformed number");
    double v = 0.0;
    try {
      v = std::stod(code.substr(i + 1, j - i - 1));
    } catch (const std::exception&) {
      throw InputError(file, line, text, "malformed number");
    }
    if (!std::isfinite(v)) throw InputError(file, line, text, "number out of range");
    words.push_back({letter, v, text});
    i = j;
  }
  return words;
}

// A G or M number with up to one decimal, as an integer key: G43.4 -> 434, G1 -> 10.
int code_key(const Word& w, const std::string& file, int line) {
  const double k = std::round(w.value * 10.0);
  if (std::abs(k - w.value * 10.0) > 1e-6 || k < 0 || k > 99990)
    throw InputError(file, line, w.text, "not a valid code number");
  return static_cast<int>(k);
}

// "G43.4" from the key 434.
std::string code_name(char letter, int key) {
  std::string s(1, letter);
  s.append(std::to_string(key / 10));
  if (key % 10) s.append(".").append(std::to_string(key % 10));
  return s;
}

bool is_axis(char c) { return c == 'X' || c == 'Y' || c == 'Z' || c == 'A' || c == 'B' || c == 'C'; }

double& axis_ref(Joints& j, char c) {
  switch (c) {
    case 'X': return j.x;
    case 'Y': return j.y;
    case 'Z': return j.z;
    case 'A': return j.a;
    case 'B': return j.b;
    default: return j.c;
  }
}

// "M128" (or "m128", "M 128") -> key 1280; nullopt when the machine names no such code.
std::optional<int> machine_m_code(const std::string& code) {
  std::string s;
  for (char ch : code)
    if (!std::isspace(static_cast<unsigned char>(ch))) s.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
  if (s.size() < 2 || s[0] != 'M') return std::nullopt;
  try {
    size_t used = 0;
    const double v = std::stod(s.substr(1), &used);
    if (used != s.size() - 1) return std::nullopt;
    return static_cast<int>(std::lround(v * 10.0));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

struct State {
  Joints pos;
  std::array<bool, 6> known{};  // X Y Z A B C given at least once
  int motion = -1;              // 0, 1, 2, 3 or -1 (none yet)
  int plane = 17;
  bool inch = false;
  bool incremental = false;
  bool arc_incremental = true;  // G91.1 default
  bool inverse_time = false;
  bool tcp = false;
  double feed = 0.0;
  double spindle = 0.0;
  int tool = 0, pending_tool = 0;
  bool ended = false;
};

int axis_index(char c) { return std::string_view("XYZABC").find(c); }

// A block's value words (not G, M, N or O) by letter.
using Values = std::array<std::optional<double>, 26>;

std::optional<double> word_value(const Values& val, char c) { return val[c - 'A']; }

class Reader {
 public:
  Reader(const std::string& file, const MachineSpec& machine, const GcodeOptions& options)
      : file_(file), machine_(machine), options_(options) {
    if (auto k = machine_m_code(machine.tcp_on_code)) tcp_on_ = *k;
    if (auto k = machine_m_code(machine.tcp_off_code)) tcp_off_ = *k;
    if (options.start) {
      st_.pos = *options.start;
      st_.known.fill(true);
    }
  }

  void line(std::string_view raw, int number) {
    if (st_.ended) return;
    std::string_view view = raw;
    while (!view.empty() && std::isspace(static_cast<unsigned char>(view.front()))) view.remove_prefix(1);
    if (!view.empty() && view.front() == '/') {
      if (options_.block_delete) return;
      view.remove_prefix(1);
    }
    if (!view.empty() && view.front() == '%') return;
    const std::string code = strip_line(view, file_, number);
    if (code.empty()) return;
    block(split_words(code, file_, number), number);
  }

  Program finish() {
    // Axes the program never set before a block keep the first value it gives them (see GcodeOptions).
    if (!options_.start) {
      for (int a = 0; a < 6; ++a) {
        double first = 0.0;
        bool found = false;
        for (size_t b = 0; b < given_.size() && !found; ++b)
          if (given_[b][a]) { first = axis_ref(program_.blocks[b].target, "XYZABC"[a]); found = true; }
        if (!found) continue;
        axis_ref(program_.start, "XYZABC"[a]) = first;
        for (size_t b = 0; b < given_.size() && !given_[b][a]; ++b) axis_ref(program_.blocks[b].target, "XYZABC"[a]) = first;
      }
    }
    return std::move(program_);
  }

 private:
  // One warning per distinct code and message: "file:line: CODE message".
  void warn(int line, const std::string& code, const char* what) {
    std::string key = code;
    key.append(what);
    if (!warned_.insert(key).second) return;
    std::string w = file_;
    w.append(":").append(std::to_string(line)).append(": ").append(key);
    program_.warnings.push_back(std::move(w));
  }

  void block(const std::vector<Word>& words, int line) {
    Values val{};
    std::vector<int> gs, ms;
    sort_words(words, line, val, gs, ms);
    const bool skip_motion = apply_g_codes(gs, line);
    const double unit = st_.inch ? 25.4 : 1.0;  // after this block's G20/G21
    apply_feed_speed_tool(val, unit, line);
    apply_m_codes(ms, line);
    bool has_axis_word = false;
    for (char c : std::string_view("XYZABC")) has_axis_word |= word_value(val, c).has_value();
    if (!has_axis_word || skip_motion) return;
    if (st_.motion < 0) throw InputError(file_, line, "G", "axis words before any motion mode (G0/G1/G2/G3)");
    add_motion_block(val, unit, line);
  }

  // The block's G and M codes (as code keys, in their order) and its value words by letter; N and O are
  // ignored. Throws on a letter the machine or the reader does not know and on a word given twice.
  void sort_words(const std::vector<Word>& words, int line, Values& val, std::vector<int>& gs,
                  std::vector<int>& ms) const {
    for (const Word& w : words) {
      if (w.letter == 'G') { gs.push_back(code_key(w, file_, line)); continue; }
      if (w.letter == 'M') { ms.push_back(code_key(w, file_, line)); continue; }
      if (w.letter == 'N' || w.letter == 'O') continue;
      if (is_axis(w.letter) && !machine_.has_axis(w.letter))
        throw InputError(file_, line, w.text,
                         "machine '" + machine_.name + "' has no " + std::string(1, w.letter) + " axis (axes: XYZ" +
                             machine_.rotary_axes() + ")");
      if (std::string_view("UVW").find(w.letter) != std::string_view::npos)
        throw InputError(file_, line, w.text,
                         "machine '" + machine_.name + "' has no " + std::string(1, w.letter) + " axis");
      if (std::string_view("XYZABCIJKRFSTPQHDLE").find(w.letter) == std::string_view::npos)
        throw InputError(file_, line, w.text, "unknown word letter");
      auto& slot = val[w.letter - 'A'];
      if (slot) throw InputError(file_, line, w.text, "word given twice in one block");
      slot = w.value;
    }
  }

  // The modal settings of the block's G codes, first and in RS274/NGC execution order. True when the
  // block's motion is not simulated (reference return, canned cycle).
  bool apply_g_codes(const std::vector<int>& gs, int line) {
    bool skip_motion = false;
    for (int g : gs) {
      switch (g) {
        case 930: st_.inverse_time = true; break;
        case 940: st_.inverse_time = false; break;
        case 950: throw InputError(file_, line, "G95", "feed per revolution is not supported");
        case 200: st_.inch = true; break;
        case 210: st_.inch = false; break;
        case 170: st_.plane = 17; break;
        case 180: st_.plane = 18; break;
        case 190: st_.plane = 19; break;
        case 900: st_.incremental = false; break;
        case 910: st_.incremental = true; break;
        case 901: st_.arc_incremental = false; break;
        case 911: st_.arc_incremental = true; break;
        case 434: st_.tcp = true; break;
        case 490: st_.tcp = false; break;
        case 0: case 10: case 20: case 30: st_.motion = g / 10; break;
        case 430: case 400: case 800: case 610: case 640: case 150: case 690: case 500: case 530:
        case 980: case 990: break;  // accepted, nothing to simulate
        case 40: break;  // dwell: no motion
        case 410: case 420: warn(line, code_name('G', g), " cutter compensation is not simulated"); break;
        case 280: case 300:
          warn(line, code_name('G', g), " reference return is not simulated");
          skip_motion = true;
          break;
        default:
          if (g >= 540 && g <= 593) {
            warn(line, code_name('G', g), " work offset is not simulated (coordinates taken as part coordinates)");
          } else if (g >= 810 && g <= 890) {
            warn(line, code_name('G', g), " canned cycle is not simulated");
            skip_motion = true;
          } else {
            warn(line, code_name('G', g), " unknown code ignored");
          }
      }
    }
    return skip_motion;
  }

  // F, S and T words; `unit` converts an inch feed to mm.
  void apply_feed_speed_tool(const Values& val, double unit, int line) {
    if (word_value(val, 'F')) {
      const double f = *word_value(val, 'F');
      if (f < 0) throw InputError(file_, line, "F", "negative feed");
      st_.feed = st_.inverse_time ? f : f * unit;
    }
    if (word_value(val, 'S')) st_.spindle = *word_value(val, 'S');
    if (word_value(val, 'T')) st_.pending_tool = static_cast<int>(std::lround(*word_value(val, 'T')));
  }

  // The block's M codes, after its G codes and F S T words; the machine's own TCP codes come first.
  void apply_m_codes(const std::vector<int>& ms, int line) {
    for (int m : ms) {
      if (tcp_on_ && m == *tcp_on_) { st_.tcp = true; continue; }
      if (tcp_off_ && m == *tcp_off_) { st_.tcp = false; continue; }
      switch (m) {
        case 30: case 40: break;                       // spindle on (speed from S)
        case 50: break;                                // spindle stop
        case 60: st_.tool = st_.pending_tool; break;   // tool change
        case 1280: st_.tcp = true; break;
        case 1290: st_.tcp = false; break;
        case 20: case 300: st_.ended = true; break;
        case 0: case 10: case 70: case 80: case 90: break;  // stops and coolant: nothing to simulate
        default: warn(line, code_name('M', m), " unknown code ignored");
      }
    }
  }

  // The motion of a block with axis words, in the modal state after its codes.
  void add_motion_block(const Values& val, double unit, int line) {
    Block b;
    b.line = line;
    b.motion = st_.motion == 0 ? Motion::Rapid : st_.motion == 1 ? Motion::Linear
             : st_.motion == 2 ? Motion::ArcCW : Motion::ArcCCW;
    const Joints start = st_.pos;
    const std::array<bool, 6> given = move_axes(val, unit);
    b.target = st_.pos;
    b.tcp = st_.tcp;
    b.feed_mode = st_.inverse_time ? FeedMode::InverseTime : FeedMode::PerMinute;
    b.feed = st_.feed;
    b.spindle_rpm = st_.spindle;
    b.tool = st_.tool;
    b.plane = st_.plane;
    if (b.motion != Motion::Rapid) {
      if (st_.inverse_time && !word_value(val, 'F'))
        throw InputError(file_, line, "F", "inverse-time feed (G93) needs F on every feed block");
      if (!st_.inverse_time && st_.feed <= 0.0) throw InputError(file_, line, "F", "feed block with no feed rate set");
      if (st_.inverse_time && st_.feed <= 0.0) throw InputError(file_, line, "F", "inverse-time feed must be positive");
    }
    if (b.motion == Motion::ArcCW || b.motion == Motion::ArcCCW) arc_center(b, start, val, unit, line);
    program_.blocks.push_back(b);
    given_.push_back(given);
  }

  // Moves the position by the block's axis words (absolute or incremental, linear ones in `unit`); returns
  // the axes whose position the program has set, in this block or before.
  std::array<bool, 6> move_axes(const Values& val, double unit) {
    std::array<bool, 6> given{};
    for (char c : std::string_view("XYZABC")) {
      if (!word_value(val, c)) continue;
      const bool linear = c == 'X' || c == 'Y' || c == 'Z';
      const double v = *word_value(val, c) * (linear ? unit : 1.0);
      double& p = axis_ref(st_.pos, c);
      p = st_.incremental ? p + v : v;
      st_.known[axis_index(c)] = true;
      given[axis_index(c)] = true;
    }
    // An axis the program never set keeps "unknown" status; incremental words on it count from 0.
    for (int a = 0; a < 6; ++a) given[a] = given[a] || st_.known[a];
    return given;
  }

  void arc_center(Block& b, const Joints& start, const Values& val, double unit, int line) {
    // In-plane axes (u, v) and their offset letters.
    int iu = 0, iv = 1;
    char lu = 'I', lv = 'J';
    if (b.plane == 18) { iu = 2; iv = 0; lu = 'K'; lv = 'I'; }
    if (b.plane == 19) { iu = 1; iv = 2; lu = 'J'; lv = 'K'; }
    const Eigen::Vector3d s(start.x, start.y, start.z), e(b.target.x, b.target.y, b.target.z);
    Eigen::Vector3d c = s;
    const auto R = val['R' - 'A'];
    const auto ou = val[lu - 'A'], ov = val[lv - 'A'];
    if (R) {
      if (ou || ov) throw InputError(file_, line, "R", "give either R or the centre offsets, not both");
      const double r = *R * unit;
      const Eigen::Vector2d s2(s[iu], s[iv]), e2(e[iu], e[iv]);
      const double chord = (e2 - s2).norm();
      if (chord < 1e-9) throw InputError(file_, line, "R", "an R-form arc needs distinct start and end points");
      if (std::abs(r) < chord / 2.0 - options_.arc_tolerance)
        throw InputError(file_, line, "R", "radius is smaller than half the chord");
      const double h = std::sqrt(std::max(0.0, r * r - chord * chord / 4.0));
      const Eigen::Vector2d mid = 0.5 * (s2 + e2), dir = (e2 - s2) / chord;
      const Eigen::Vector2d left(-dir.y(), dir.x());
      // CCW with positive R: the centre is on the left of the chord; CW on the right; negative R flips.
      double side = b.motion == Motion::ArcCCW ? 1.0 : -1.0;
      if (r < 0) side = -side;
      const Eigen::Vector2d c2 = mid + side * h * left;
      c[iu] = c2.x();
      c[iv] = c2.y();
    } else {
      if (!ou && !ov) throw InputError(file_, line, std::string(1, lu), "arc without centre offsets or R");
      const double du = ou.value_or(0.0) * unit, dv = ov.value_or(0.0) * unit;
      c[iu] = st_.arc_incremental ? s[iu] + du : (ou ? du : s[iu]);
      c[iv] = st_.arc_incremental ? s[iv] + dv : (ov ? dv : s[iv]);
      const double rs = std::hypot(s[iu] - c[iu], s[iv] - c[iv]);
      const double re = std::hypot(e[iu] - c[iu], e[iv] - c[iv]);
      if (std::abs(rs - re) > std::max(options_.arc_tolerance, 1e-3 * rs))
        throw InputError(file_, line, std::string(1, lu), "start and end are not on one circle about the centre");
      if (rs < 1e-9) throw InputError(file_, line, std::string(1, lu), "arc radius is zero");
    }
    b.arc_center = c;
  }

  std::string file_;
  const MachineSpec& machine_;
  GcodeOptions options_;
  std::optional<int> tcp_on_, tcp_off_;
  State st_;
  Program program_;
  std::vector<std::array<bool, 6>> given_;
  std::set<std::string> warned_;
};

}  // namespace

Program parse_gcode(std::string_view text, const std::string& file, const MachineSpec& machine, const GcodeOptions& options) {
  Reader reader(file, machine, options);
  int number = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(pos, end - pos);
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    ++number;
    reader.line(raw, number);
    if (end == text.size()) break;
    pos = end + 1;
  }
  Program p = reader.finish();
  if (options.start) p.start = *options.start;
  return p;
}

Program read_gcode(const std::filesystem::path& file, const MachineSpec& machine, const GcodeOptions& options) {
  return parse_gcode(read_text_file(file, "G-code file"), file.string(), machine, options);
}

}  // namespace tf
