#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tiltfield/core/internal/json_fields.hpp"
#include "tiltfield/core/machine.hpp"

namespace tf {
namespace fs = std::filesystem;
using namespace json_fields;

std::string_view to_string(KinematicsType k) {
  switch (k) {
    case KinematicsType::XYZ: return "xyz";
    case KinematicsType::TableTableAC: return "table-table-ac";
    case KinematicsType::TableTableBC: return "table-table-bc";
    case KinematicsType::HeadTableBC: return "head-table-bc";
    case KinematicsType::HeadHeadAC: return "head-head-ac";
  }
  return "?";
}

std::string MachineSpec::rotary_axes() const {
  switch (kinematics) {
    case KinematicsType::XYZ: return "";
    case KinematicsType::TableTableAC:
    case KinematicsType::HeadHeadAC: return "AC";
    case KinematicsType::TableTableBC:
    case KinematicsType::HeadTableBC: return "BC";
  }
  return "";
}

bool MachineSpec::has_axis(char letter) const {
  if (letter == 'X' || letter == 'Y' || letter == 'Z') return true;
  return rotary_axes().find(letter) != std::string::npos;
}

namespace {

// A code that switches tool-centre-point control, written on a line of its own: words of a letter and a
// number (M428, G43.4 H1, G68.2 P1), no comment, line break or motion. The post wrote it as given ("M428 (x"
// left a comment open, "M428\nG0 Z-100" put a rapid into the program, black-box testing).
std::string tcp_code(const nlohmann::json& j, const std::string& file, const std::string& field) {
  const std::string code = string(j, file, field);
  for (char c : code)
    if (c != ' ' && c != '\t' && !std::isalnum(static_cast<unsigned char>(c)) && c != '.')
      throw InputError(file, 0, field, "holds a character that is no part of a word (comments and line breaks are not allowed)");
  std::istringstream words(code);
  std::string w;
  while (words >> w) {
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(w[0])));
    bool number = w.size() > 1;
    for (size_t i = 1; i < w.size(); ++i)
      number &= std::isdigit(static_cast<unsigned char>(w[i])) || w[i] == '.';
    if (std::string("GMHDPQL").find(letter) == std::string::npos || !number)
      throw InputError(file, 0, field, "'" + w + "' is no word of a switch code (give words such as M428 or G43.4 H1)");
    if (letter == 'G') {
      const double g = std::atof(w.c_str() + 1);
      if (g < 4 || (g >= 33 && g < 39) || (g >= 73 && g < 90))
        throw InputError(file, 0, field, "'" + w + "' is a motion code, not a switch");
    }
  }
  return code;  // empty: none
}

}  // namespace

MachineSpec parse_machine_json(const nlohmann::json& j, const std::string& file, const std::string& prefix) {
  require_object(j, file, prefix.empty() ? "(top level)" : prefix);
  only_keys(j,
            {"name", "kinematics", "pivot", "tilt_offset", "head_pivot_length", "table_center", "limits", "output", "tcp_style",
             "tcp_on_code", "tcp_off_code", "max_feed", "rapid_feed", "max_rotary_feed", "safe_z", "comment"},
            file, prefix);
  MachineSpec m;
  if (j.contains("name")) m.name = string(j["name"], file, join(prefix, "name"));
  if (!j.contains("kinematics")) throw InputError(file, 0, join(prefix, "kinematics"), "missing");
  const std::string k = string(j["kinematics"], file, join(prefix, "kinematics"));
  bool known = false;
  for (auto t : {KinematicsType::XYZ, KinematicsType::TableTableAC, KinematicsType::TableTableBC,
                 KinematicsType::HeadTableBC, KinematicsType::HeadHeadAC}) {
    if (k == to_string(t)) {
      m.kinematics = t;
      known = true;
    }
  }
  if (!known)
    throw InputError(file, 0, join(prefix, "kinematics"),
                     "unknown kinematics '" + k +
                         "' (use xyz, table-table-ac, table-table-bc, head-table-bc or head-head-ac)");
  if (j.contains("pivot")) m.pivot = point_within_km(j["pivot"], file, join(prefix, "pivot"));
  if (j.contains("tilt_offset")) m.tilt_offset = point_within_km(j["tilt_offset"], file, join(prefix, "tilt_offset"));
  if (j.contains("table_center")) m.table_center = point_within_km(j["table_center"], file, join(prefix, "table_center"));
  m.head_pivot_length = number_or(j, "head_pivot_length", 0.0, file, prefix);
  // Measured up from the spindle nose to the head's rotation centre: below the nose it would turn the head
  // about a point in the tool (a negative length had been taken as given, black-box testing).
  if (!(m.head_pivot_length >= 0.0 && m.head_pivot_length <= 1e4))
    throw InputError(file, 0, join(prefix, "head_pivot_length"),
                     "must be from 0 to 10000 mm: the distance from the spindle nose up to the head's rotation centre");
  if (j.contains("limits")) {
    const auto& lim = j["limits"];
    const std::string lp = join(prefix, "limits");
    require_object(lim, file, lp);
    for (auto it = lim.begin(); it != lim.end(); ++it) {
      const std::string f = lp + "." + it.key();
      if (it.key().size() != 1 || !m.has_axis(it.key()[0]))
        throw InputError(file, 0, f, "this machine has no axis '" + it.key() + "' (axes: XYZ" + m.rotary_axes() + ")");
      if (!it->is_array() || it->size() != 2) throw InputError(file, 0, f, "must be [min, max]");
      AxisLimit a{number((*it)[0], file, f + "[0]"), number((*it)[1], file, f + "[1]")};
      if (a.min > a.max) throw InputError(file, 0, f, "min is greater than max");
      m.limits[it.key()[0]] = a;
    }
  }
  if (j.contains("output")) {
    const std::string o = string(j["output"], file, join(prefix, "output"));
    if (o == "joint") m.output = OutputMode::Joint;
    else if (o == "tcp") m.output = OutputMode::Tcp;
    else throw InputError(file, 0, join(prefix, "output"), "must be 'joint' or 'tcp'");
  }
  if (j.contains("tcp_style")) {
    const std::string s = string(j["tcp_style"], file, join(prefix, "tcp_style"));
    if (s == "G43.4") m.tcp_style = TcpStyle::G43_4;
    else if (s == "M128") m.tcp_style = TcpStyle::M128;
    else throw InputError(file, 0, join(prefix, "tcp_style"), "must be 'G43.4' or 'M128'");
  }
  if (j.contains("tcp_on_code")) m.tcp_on_code = tcp_code(j["tcp_on_code"], file, join(prefix, "tcp_on_code"));
  if (j.contains("tcp_off_code")) m.tcp_off_code = tcp_code(j["tcp_off_code"], file, join(prefix, "tcp_off_code"));
  if (m.tcp_on_code.empty() != m.tcp_off_code.empty())
    throw InputError(file, 0, join(prefix, m.tcp_on_code.empty() ? "tcp_on_code" : "tcp_off_code"),
                     "tcp_on_code and tcp_off_code come together (a program must switch TCP off again)");
  // Beyond any machine's, and small enough that every coordinate and feed the post writes stays a plain number.
  constexpr double kMaxFeed = 1e6, kMaxSafeZ = 1e4;
  m.max_feed = positive_at_most(number_or(j, "max_feed", m.max_feed, file, prefix), kMaxFeed, "mm/min", file,
                                join(prefix, "max_feed"));
  m.rapid_feed = positive_at_most(number_or(j, "rapid_feed", m.rapid_feed, file, prefix), kMaxFeed, "mm/min", file,
                                  join(prefix, "rapid_feed"));
  m.max_rotary_feed = positive_at_most(number_or(j, "max_rotary_feed", m.max_rotary_feed, file, prefix), kMaxFeed,
                                       "deg/min", file, join(prefix, "max_rotary_feed"));
  m.safe_z = positive_at_most(number_or(j, "safe_z", m.safe_z, file, prefix), kMaxSafeZ, "mm", file, join(prefix, "safe_z"));
  return m;
}

MachineSpec read_machine_json(const fs::path& file) {
  return parse_machine_json(parse_file(file.string(), "machine file"), file.string(), "");
}

}  // namespace tf
