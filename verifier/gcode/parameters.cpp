// The G-code reader's parameters: what a line's #k and #<name> read, and the settings a line makes.
// Numbered parameters #1 ... #5000 and named ones are the program's own (0 and undefined at the start, as
// LinuxCNC without a parameter file). The system parameters a program can read are the reader's state:
// G92 (#5211-#5219) and coordinate system offsets (#5221-#5389) in machine units (mm, deg), the current
// coordinate system (#5220), the tool (#5400) and the position (#5420-#5428, program units); so are the
// predefined named parameters (#<_x>, #<_feed>, #<_metric> ...). Others (the probe's, G28's) are refused
// on reading: their values depend on the machine, not the program.
#include <cmath>
#include <set>

#include "reader.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::gcode {

namespace {

constexpr int kDebugParameter = 5599;  // LinuxCNC's switch for (DEBUG, ...) messages: the program's own

// The predefined named parameters LinuxCNC gives programs (read-only), those the reader keeps.
bool is_predefined(const std::string& name) {
  static const std::set<std::string> names = {
      "_X", "_Y", "_Z", "_A", "_B", "_C", "_U", "_V", "_W", "_FEED", "_RPM", "_METRIC", "_IMPERIAL",
      "_ABSOLUTE", "_INCREMENTAL", "_INVERSE_TIME", "_UNITS_PER_MINUTE", "_COORD_SYSTEM", "_MOTION_MODE", "_PLANE",
      "_CURRENT_TOOL", "_SPINDLE_ON", "_SPINDLE_CW", "_VALUE", "_VALUE_RETURNED", "_CALL_LEVEL"};
  return names.count(name) > 0;
}

}  // namespace

// The position of axis a (XYZABC) in the current coordinate system, program units.
double Reader::position(int a, const std::string& parameter) const {
  if (st_.axes[size_t(a)] != AxisState::Set)
    throw InputError(file_, line_, parameter,
                     std::string("the position of ") + "XYZABC"[a] +
                         " is read before any move has set it (no start pose is known)");
  return a < 3 ? st_.pos[size_t(a)] / unit() : st_.pos[size_t(a)];
}

std::optional<double> Reader::numbered(int k) const {
  if (k <= 5000 || k == kDebugParameter) return numbered_[size_t(k)];
  if (k >= 5211 && k <= 5219) return k <= 5216 ? st_.g92[size_t(k - 5211)] : 0.0;  // UVW: none
  if (k == 5220) return st_.cs + 1.0;
  if (k >= 5221 && k <= 5390) {
    const int system = (k - 5221) / 20, axis = (k - 5221) % 20;
    if (axis < 6) return st_.offsets[size_t(system)][size_t(axis)];
    if (axis < 10) return 0.0;  // U V W and the rotation (R), which the reader refuses
  }
  if (k == 5400) return double(st_.tool);
  if (k >= 5420 && k <= 5428) return k <= 5425 ? position(k - 5420, "#" + std::to_string(k)) : 0.0;
  return std::nullopt;
}

// A predefined parameter's value (is_predefined), nullopt for another name.
std::optional<double> Reader::predefined(const std::string& name) const {
  if (!is_predefined(name)) return std::nullopt;
  if (name.size() == 2 && name[0] == '_') {
    const size_t a = std::string_view("XYZABC").find(name[1]);
    if (a != std::string_view::npos) return position(static_cast<int>(a), "#<" + name + ">");
    if (std::string_view("UVW").find(name[1]) != std::string_view::npos) return 0.0;
  }
  if (name == "_FEED") return st_.feed_word;
  if (name == "_RPM") return st_.spindle;
  if (name == "_METRIC") return st_.inch ? 0.0 : 1.0;
  if (name == "_IMPERIAL") return st_.inch ? 1.0 : 0.0;
  if (name == "_ABSOLUTE") return st_.incremental ? 0.0 : 1.0;
  if (name == "_INCREMENTAL") return st_.incremental ? 1.0 : 0.0;
  if (name == "_INVERSE_TIME") return st_.inverse_time ? 1.0 : 0.0;
  if (name == "_UNITS_PER_MINUTE") return st_.inverse_time ? 0.0 : 1.0;
  if (name == "_COORD_SYSTEM") return st_.cs < 6 ? 540.0 + 10.0 * st_.cs : 585.0 + st_.cs;
  if (name == "_MOTION_MODE") return st_.motion < 0 ? 800.0 : double(st_.motion);
  if (name == "_PLANE") return 10.0 * st_.plane;
  if (name == "_CURRENT_TOOL") return double(st_.tool);
  if (name == "_VALUE") return value_;
  if (name == "_VALUE_RETURNED") return value_returned_;
  if (name == "_CALL_LEVEL") return double(calls_.size());
  if (name == "_SPINDLE_ON") return st_.spindle_dir != 0 ? 1.0 : 0.0;
  return st_.spindle_dir == 1 ? 1.0 : 0.0;  // _SPINDLE_CW
}

// Names that begin with "_" are global; the others belong to the call level that set them.
bool Reader::defined(const std::string& name) const {
  return is_predefined(name) || (name[0] == '_' ? globals_ : locals_.back()).count(name) > 0;
}

std::optional<double> Reader::named(const std::string& name) const {
  if (auto v = predefined(name)) return v;
  const auto& scope = name[0] == '_' ? globals_ : locals_.back();
  const auto it = scope.find(name);
  if (it == scope.end()) return std::nullopt;
  return it->second;
}

void Reader::set_parameters(const std::vector<ParameterSetting>& settings, int line) {
  for (const ParameterSetting& s : settings) {
    if (!s.name.empty()) {
      if (is_predefined(s.name)) throw InputError(file_, line, s.text, "a predefined parameter is read-only");
      (s.name[0] == '_' ? globals_ : locals_.back())[s.name] = s.value;
    } else if (s.number > 5000 && s.number != kDebugParameter) {
      throw InputError(file_, line, s.text,
                       "system parameter: a program writing it is not simulated (G10 and G92 set the offsets)");
    } else {
      numbered_[size_t(s.number)] = s.value;
    }
  }
}

}  // namespace tf::gcode
