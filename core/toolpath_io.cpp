#include <algorithm>
#include <cstring>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace tf {
namespace fs = std::filesystem;

std::vector<double> ToolPath::arc_length() const {
  std::vector<double> s(rows.size(), 0.0);
  for (size_t i = 1; i < rows.size(); ++i) s[i] = s[i - 1] + (rows[i].p - rows[i - 1].p).norm();
  return s;
}

namespace {
constexpr double kUnitTolerance = 1e-3;

Eigen::Vector3d unit_vector(const Eigen::Vector3d& v, const std::string& file, int line, const std::string& field) {
  const double n = v.norm();
  if (n < 1e-12) throw InputError(file, line, field, "zero-length vector");
  if (std::abs(n - 1.0) > kUnitTolerance)
    throw InputError(file, line, field, "not a unit vector (length " + fixed(n, 6) + ")");
  return v / n;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}
}  // namespace

ToolPath read_toolpath_csv(const fs::path& file) {
  const std::string name = file.string();
  const CsvTable t = read_csv(file);
  const char* required[] = {"x", "y", "z", "nx", "ny", "nz"};
  int col[6];
  for (int i = 0; i < 6; ++i) {
    col[i] = t.column(required[i]);
    if (col[i] < 0) throw InputError(name, 1, required[i], "missing column (header must be x,y,z,nx,ny,nz[,feed])");
  }
  const int feed_col = t.column("feed");
  for (const auto& h : t.header) {
    if (std::find(std::begin(required), std::end(required), h) == std::end(required) && h != "feed")
      throw InputError(name, 1, h, "unknown column (header must be x,y,z,nx,ny,nz[,feed])");
  }
  ToolPath path;
  path.rows.reserve(t.rows.size());
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const int line = t.lines[r];
    double v[6];
    for (int i = 0; i < 6; ++i)
      v[i] = i < 3 ? parse_coordinate(t.rows[r][col[i]], name, line, required[i])
                   : parse_number(t.rows[r][col[i]], name, line, required[i]);
    CLPoint pt;
    pt.p = {v[0], v[1], v[2]};
    pt.n = unit_vector({v[3], v[4], v[5]}, name, line, "nx,ny,nz");
    if (feed_col >= 0 && !t.rows[r][feed_col].empty()) {
      pt.feed = parse_number(t.rows[r][feed_col], name, line, "feed");
      if (pt.feed <= 0) throw InputError(name, line, "feed", "must be positive (mm/min)");
    }
    pt.line = line;
    path.rows.push_back(pt);
  }
  if (path.rows.empty()) throw InputError(name, 0, "", "tool path has no rows");
  return path;
}

ToolPath read_toolpath_apt(const fs::path& file, const Tool& tool) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(name, 0, "", "cannot open file");
  ToolPath path;
  std::string raw, record;
  int line = 0, record_line = 0;
  double feed = std::numeric_limits<double>::quiet_NaN();
  double unit = 1.0;                               // mm per file unit (UNITS/INCHES: 25.4)
  Eigen::Vector3d last_axis = Eigen::Vector3d::UnitZ();  // a GOTO of three values keeps the tool axis in force
  std::optional<Eigen::Vector3d> last_tip;               // mm: where GODLTA starts from (UNITS may change between)
  bool skip_next_goto = false, finished = false, link_next = false;
  // A tool tip (file units) and axis reached by a motion record: a row, unless a RAPID came before it.
  auto reach = [&](const Eigen::Vector3d& tip_mm, const Eigen::Vector3d& axis, int at) {
    last_tip = tip_mm;
    last_axis = axis;
    if (skip_next_goto) {
      skip_next_goto = false;
      link_next = true;
      return;
    }
    CLPoint pt;
    pt.approach = link_next ? Approach::Link : Approach::Cut;
    pt.line = at;
    link_next = false;
    pt.p = tip_mm + tool.cl_height() * axis;
    pt.n = axis;
    pt.normal_known = false;  // the axis stands in: a flat or bull end keeps this cutter location
    pt.feed = feed;
    path.rows.push_back(pt);
  };
  auto handle = [&](const std::string& rec, int at) {
    std::string r = upper(rec);
    r.erase(std::remove_if(r.begin(), r.end(), [](unsigned char c) { return std::isspace(c); }), r.end());
    if (r.empty() || r.rfind("$$", 0) == 0 || r.rfind("PPRINT", 0) == 0 || r.rfind("REMARK", 0) == 0) return;
    const auto slash = r.find('/');
    const std::string word = r.substr(0, slash);
    // A record that names a word the reader follows but lacks its '/' ("GOTO 1,2,19") had been skipped as
    // an unknown record, and its point dropped (black-box testing).
    for (const char* w : {"GOTO", "GODLTA", "FROM", "FEDRAT", "UNITS"})
      if (word.size() > std::strlen(w) && word.rfind(w, 0) == 0)
        throw InputError(name, at, w, std::string("expected '") + w + "/' before its values");
    const std::string args = slash == std::string::npos ? "" : r.substr(slash + 1);
    std::vector<std::string> a;
    {
      std::stringstream ss(args);
      std::string item;
      while (std::getline(ss, item, ',')) a.push_back(item);
    }
    if (word == "FINI") {
      finished = true;  // the end of the part program: nothing after it is read
    } else if (word == "UNITS") {
      if (a.size() == 1 && (a[0] == "MM" || a[0] == "MILLIMETERS" || a[0] == "MILLIMETRES")) unit = 1.0;
      else if (a.size() == 1 && (a[0] == "INCHES" || a[0] == "INCH" || a[0] == "IN")) unit = 25.4;
      else throw InputError(name, at, "UNITS", "unknown units '" + args + "' (MM or INCHES)");
    } else if (word == "RAPID") {
      skip_next_goto = true;
    } else if (word == "FEDRAT") {
      if (a.empty()) throw InputError(name, at, "FEDRAT", "missing feed value");
      // FEDRAT/[MMPM|IPM,]f or FEDRAT/f[,MMPM|IPM]: per minute, in the file's units unless named.
      std::string mode;
      std::string value = a[0];
      if (std::isalpha(static_cast<unsigned char>(a[0][0]))) {
        mode = a[0];
        value = a.size() > 1 ? a[1] : "";
      } else if (a.size() > 1) {
        mode = a[1];
      }
      if (mode == "IPR" || mode == "MMPR")
        throw InputError(name, at, "FEDRAT/" + mode, "feed per revolution is not supported: give it per minute (MMPM or IPM)");
      if (!mode.empty() && mode != "MMPM" && mode != "IPM")
        throw InputError(name, at, "FEDRAT/" + mode, "unknown feed unit (MMPM or IPM)");
      feed = parse_number(value, name, at, "FEDRAT");
      if (feed <= 0) throw InputError(name, at, "FEDRAT", "feed must be positive");
      feed *= mode == "MMPM" ? 1.0 : mode == "IPM" ? 25.4 : unit;
    } else if (word == "GOTO" || word == "FROM") {
      if (a.size() != 3 && a.size() != 6)
        throw InputError(name, at, word, "expected x,y,z or x,y,z,i,j,k, found " + std::to_string(a.size()) + " values");
      double v[6] = {0, 0, 0, last_axis.x(), last_axis.y(), last_axis.z()};
      for (size_t i = 0; i < a.size(); ++i) v[i] = i < 3 ? parse_coordinate(a[i], name, at, word) : parse_number(a[i], name, at, word);
      const Eigen::Vector3d axis = unit_vector({v[3], v[4], v[5]}, name, at, word + " i,j,k");
      if (word == "FROM") {  // the start position: where GODLTA counts from, not a cut
        last_tip = unit * Eigen::Vector3d(v[0], v[1], v[2]);
        last_axis = axis;
      } else {
        reach(unit * Eigen::Vector3d(v[0], v[1], v[2]), axis, at);
      }
    } else if (word == "GODLTA") {
      // GODLTA/dx,dy,dz (from the last position), /dx,dy,dz,i,j,k (and a new axis) or /d (along the axis).
      if (a.size() != 1 && a.size() != 3 && a.size() != 6)
        throw InputError(name, at, "GODLTA", "expected d, dx,dy,dz or dx,dy,dz,i,j,k, found " + std::to_string(a.size()) + " values");
      if (!last_tip) throw InputError(name, at, "GODLTA", "an incremental move before any GOTO or FROM: there is no position to move from");
      double v[6] = {0, 0, 0, last_axis.x(), last_axis.y(), last_axis.z()};
      for (size_t i = 0; i < a.size(); ++i) v[i] = i < 3 ? parse_coordinate(a[i], name, at, "GODLTA") : parse_number(a[i], name, at, "GODLTA");
      const Eigen::Vector3d axis = unit_vector({v[3], v[4], v[5]}, name, at, "GODLTA i,j,k");
      const Eigen::Vector3d delta = a.size() == 1 ? Eigen::Vector3d(v[0] * last_axis) : Eigen::Vector3d(v[0], v[1], v[2]);
      reach(*last_tip + unit * delta, axis, at);
    } else if (word == "CIRCLE" || word == "CYCLE" || word == "MOVARC" || word == "GOFWD" || word == "GOLFT" ||
               word == "GORGT" || word == "GOBACK" || word == "GOUP" || word == "GODOWN" || word == "GO") {
      // Motion these records define (an arc to the next GOTO, a drilling cycle at each GOTO, a move along
      // a part surface) is no straight line between the points: read silently, an arc had been cut as its
      // chord (black-box testing). CYCLE/OFF only ends a cycle.
      if (!(word == "CYCLE" && a.size() == 1 && a[0] == "OFF"))
        throw InputError(name, at, word,
                         "motion record not followed here (arcs, cycles and part-surface moves): give the path as "
                         "GOTO points (CLDATA with arcs and cycles linearised)");
    }
    // Other records (MULTAX, CUTTER, LOADTL, SPINDL, COOLNT, FINI, ...) do not change the geometry.
  };
  while (std::getline(in, raw)) {
    ++line;
    if (raw.find('\0') != std::string::npos) throw InputError(name, line, "", "binary data in a CLDATA file");
    if (finished) break;
    std::string t(line == 1 ? without_utf8_bom(raw) : std::string_view(raw));
    // "$$" starts a comment that runs to the end of the line, whether the line holds a record or not.
    if (const size_t c = t.find("$$"); c != std::string::npos) t.erase(c);
    while (!t.empty() && (t.back() == '\r' || t.back() == ' ' || t.back() == '\t')) t.pop_back();
    if (t.empty()) continue;  // blank, or a comment only (also between the lines of a continued record)
    if (record.empty()) record_line = line;
    if (t.back() == '$') {  // continued on the next line
      t.pop_back();
      record += t;
      continue;
    }
    record += t;
    handle(record, record_line);
    record.clear();
  }
  if (!record.empty() && !finished) handle(record, record_line);
  if (path.rows.empty()) throw InputError(name, 0, "", "no GOTO records");
  return path;
}

ToolPath read_toolpath(const fs::path& file, const Tool& tool) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".cl" || ext == ".apt") return read_toolpath_apt(file, tool);
  return read_toolpath_csv(file);
}

void write_toolpath_csv(const ToolPath& path, const fs::path& file) {
  const bool with_feed =
      std::any_of(path.rows.begin(), path.rows.end(), [](const CLPoint& p) { return std::isfinite(p.feed); });
  write_file_atomic(file, [&](std::ostream& out) {
    out << "x,y,z,nx,ny,nz" << (with_feed ? ",feed" : "") << "\n";
    for (const auto& r : path.rows) {
      out << fixed(r.p.x(), 9) << ',' << fixed(r.p.y(), 9) << ',' << fixed(r.p.z(), 9) << ',' << fixed(r.n.x(), 9)
          << ',' << fixed(r.n.y(), 9) << ',' << fixed(r.n.z(), 9);
      if (with_feed) out << ',' << (std::isfinite(r.feed) ? fixed(r.feed, 3) : "");
      out << '\n';
    }
  });
}

}  // namespace tf
