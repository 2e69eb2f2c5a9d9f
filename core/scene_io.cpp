#include <algorithm>
#include <cmath>

#include "tiltfield/core/io.hpp"

#include "tiltfield/core/internal/json_fields.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {
namespace fs = std::filesystem;
using namespace json_fields;

Tool parse_tool_json(const json& j, const std::string& file, const std::string& prefix) {
  require_object(j, file, prefix);
  only_keys(j, {"type", "radius", "corner_radius", "flute_length", "shank_radius", "length", "holder", "comment"}, file,
            prefix);
  Tool t;
  const std::string type = j.contains("type") ? string(j["type"], file, join(prefix, "type")) : "ball";
  const double r = required_number(j, "radius", file, prefix);
  if (type == "ball") {
    t.cutter = BallCutter{r};
  } else if (type == "flat") {
    t.cutter = FlatCutter{r};
  } else if (type == "bull") {
    t.cutter = BullCutter{r, required_number(j, "corner_radius", file, prefix)};
  } else {
    throw InputError(file, 0, join(prefix, "type"), "unknown tool type '" + type + "' (use ball, flat or bull)");
  }
  if (type != "bull" && j.contains("corner_radius"))
    throw InputError(file, 0, join(prefix, "corner_radius"), "only a bull tool has a corner radius");
  t.flute_length = number_or(j, "flute_length", 4.0 * r, file, prefix);
  t.shank_radius = number_or(j, "shank_radius", r, file, prefix);
  t.length = number_or(j, "length", std::max(t.flute_length, 10.0 * r), file, prefix);
  if (j.contains("holder")) {
    const auto& h = j["holder"];
    const std::string hp = join(prefix, "holder");
    if (!h.is_array()) throw InputError(file, 0, hp, "must be an array of {radius, length}");
    for (size_t i = 0; i < h.size(); ++i) {
      const std::string sp = hp + "[" + std::to_string(i) + "]";
      require_object(h[i], file, sp);
      only_keys(h[i], {"radius", "length"}, file, sp);
      t.holder.push_back({required_number(h[i], "radius", file, sp), required_number(h[i], "length", file, sp)});
    }
  }
  validate_tool(t, file, prefix);
  return t;
}

namespace {
// The file a field names, relative to the scene's folder; recorded among the files the scene reads.
fs::path resolve(Scene& s, const json& j, const std::string& field) {
  const std::string name = string(j, s.file.string(), field);
  if (name.empty()) throw InputError(s.file.string(), 0, field, "empty file name");
  fs::path p(name);
  if (!p.is_absolute()) p = s.dir / p;
  // Named with the field that refers to it: "./x.stl: mesh file not found" had not said which of the
  // scene's files it was (black-box testing).
  std::error_code ec;
  if (!fs::exists(p, ec)) throw InputError(s.file.string(), 0, field, "the file '" + p.string() + "' does not exist");
  if (fs::is_directory(p, ec)) throw InputError(s.file.string(), 0, field, "'" + p.string() + "' is a directory, not a file");
  s.files.push_back(p);
  return p;
}

Stock parse_stock(Scene& s, const json& j) {
  const std::string file = s.file.string();
  require_object(j, file, "stock");
  if (j.size() != 1) throw InputError(file, 0, "stock", "must have exactly one of 'mesh', 'box' or 'cylinder'");
  Stock st;
  if (j.contains("mesh")) {
    st.kind = Stock::Kind::Mesh;
    const fs::path mp = resolve(s, j["mesh"], "stock.mesh");
    st.mesh = load_mesh(mp);
    if (!is_closed(st.mesh)) throw InputError(mp.string(), 0, "", "stock mesh is not closed (it must bound a solid)");
    if (signed_volume(st.mesh) <= 0.0)
      throw InputError(mp.string(), 0, "", "stock mesh is inside out (faces must be oriented outward)");
  } else if (j.contains("box")) {
    st.kind = Stock::Kind::Box;
    const auto& b = j["box"];
    require_object(b, file, "stock.box");
    only_keys(b, {"min", "max"}, file, "stock.box");
    if (!b.contains("min")) throw InputError(file, 0, "stock.box.min", "missing");
    if (!b.contains("max")) throw InputError(file, 0, "stock.box.max", "missing");
    st.box.min = point_within_km(b["min"], file, "stock.box.min");
    st.box.max = point_within_km(b["max"], file, "stock.box.max");
    if ((st.box.max - st.box.min).minCoeff() <= 0.0)
      throw InputError(file, 0, "stock.box", "max must be greater than min on every axis");
  } else if (j.contains("cylinder")) {
    st.kind = Stock::Kind::Cylinder;
    const auto& c = j["cylinder"];
    const std::string cp = "stock.cylinder";
    require_object(c, file, cp);
    only_keys(c, {"base", "axis", "radius", "height"}, file, cp);
    if (!c.contains("base")) throw InputError(file, 0, cp + ".base", "missing");
    st.cylinder.base = point_within_km(c["base"], file, cp + ".base");
    const Eigen::Vector3d a = c.contains("axis") ? vec3(c["axis"], file, cp + ".axis") : Eigen::Vector3d::UnitZ();
    if (a.norm() < 1e-12) throw InputError(file, 0, cp + ".axis", "zero-length axis");
    st.cylinder.axis = a.normalized();
    st.cylinder.radius = within_km(positive(required_number(c, "radius", file, cp), file, cp + ".radius"), file, cp + ".radius");
    st.cylinder.height = within_km(positive(required_number(c, "height", file, cp), file, cp + ".height"), file, cp + ".height");
  } else {
    throw InputError(file, 0, "stock", "must have exactly one of 'mesh', 'box' or 'cylinder'");
  }
  return st;
}

// "tools": [{"number": n, ...the fields of "tool"...}, ...]; numbers whole, >= 1 and distinct.
std::vector<ToolEntry> parse_tool_library(const json& j, const std::string& file) {
  if (!j.is_array() || j.empty()) throw InputError(file, 0, "tools", "must be a non-empty array of tools");
  std::vector<ToolEntry> tools;
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string prefix = "tools[" + std::to_string(i) + "]";
    require_object(j[i], file, prefix);
    if (!j[i].contains("number")) throw InputError(file, 0, prefix + ".number", "missing");
    const json& n = j[i]["number"];
    if (!n.is_number_integer() || n.get<long long>() < 1 || n.get<long long>() > 99999)
      throw InputError(file, 0, prefix + ".number", "must be a whole number from 1 to 99999");
    ToolEntry e;
    e.number = static_cast<int>(n.get<long long>());
    for (const ToolEntry& other : tools)
      if (other.number == e.number)
        throw InputError(file, 0, prefix + ".number", "tool " + std::to_string(e.number) + " is given twice");
    json fields = j[i];
    fields.erase("number");
    e.tool = parse_tool_json(fields, file, prefix);
    tools.push_back(std::move(e));
  }
  return tools;
}

// "work_offsets": {"G54": [x, y, z(, a, b, c)], ...}; mm and degrees.
std::map<std::string, WorkOffset> parse_work_offsets(const json& j, const std::string& file) {
  require_object(j, file, "work_offsets");
  std::map<std::string, WorkOffset> out;
  const auto& codes = work_offset_codes();
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string field = "work_offsets." + it.key();
    if (std::find(codes.begin(), codes.end(), it.key()) == codes.end())
      throw InputError(file, 0, field, "unknown work offset (use G54 ... G59, G59.1, G59.2, G59.3)");
    const json& v = it.value();
    if (!v.is_array() || (v.size() != 3 && v.size() != 6))
      throw InputError(file, 0, field, "must be an array of 3 numbers (x, y, z) or 6 (x, y, z, a, b, c)");
    WorkOffset w{};
    for (size_t k = 0; k < v.size(); ++k) {
      const std::string f = field + "[" + std::to_string(k) + "]";
      w[k] = number(v[k], file, f);
      if (std::abs(w[k]) > 1e9) throw InputError(file, 0, f, "out of range (more than 1e9)");
    }
    out[it.key()] = w;
  }
  return out;
}

// A path that names its tool axes (APT CLDATA) on a 3-axis machine: every axis must be the machine's +Z.
// A tilted GOTO axis, even -Z, had been turned to +Z with only a note in PLAN.json (black-box testing).
void check_path_axes_on_machine(const Scene& s) {
  if (!s.machine || s.machine->kinematics != KinematicsType::XYZ) return;
  for (const CLPoint& r : s.path.rows)
    if (!r.normal_known && (r.n - Eigen::Vector3d::UnitZ()).norm() > 1e-6)
      throw InputError(s.path_file.string(), r.line, "i,j,k",
                       "the tool axis (" + fixed(r.n.x(), 6) + ", " + fixed(r.n.y(), 6) + ", " + fixed(r.n.z(), 6) +
                           ") is not vertical, and the scene's machine is 3-axis (xyz)");
}

// A rotary offset on an axis the machine lacks would silently do nothing: refused.
void check_work_offset_axes(const Scene& s) {
  const MachineSpec machine = s.machine.value_or(MachineSpec{});
  for (const auto& [code, w] : s.work_offsets)
    for (int k = 3; k < 6; ++k)
      if (w[k] != 0.0 && !machine.has_axis("ABC"[k - 3]))
        throw InputError(s.file.string(), 0, "work_offsets." + code + "[" + std::to_string(k) + "]",
                         "the machine has no " + std::string(1, "ABC"[k - 3]) + " axis");
}

PlannerBasics parse_planner_basics(const json& j, const std::string& file) {
  require_object(j, file, "planner");
  PlannerBasics p;
  p.lead_deg = number_or(j, "lead_deg", p.lead_deg, file, "planner");
  p.tilt_deg = number_or(j, "tilt_deg", p.tilt_deg, file, "planner");
  p.safety_distance = number_or(j, "safety_distance", p.safety_distance, file, "planner");
  if (p.safety_distance < 0) throw InputError(file, 0, "planner.safety_distance", "must not be negative");
  p.shank_clearance = optional_number(j, "shank_clearance", file, "planner");
  p.holder_clearance = optional_number(j, "holder_clearance", file, "planner");
  p.fixture_clearance = optional_number(j, "fixture_clearance", file, "planner");
  if (p.shank_clearance && *p.shank_clearance < 0)
    throw InputError(file, 0, "planner.shank_clearance", "must not be negative");
  if (p.holder_clearance && *p.holder_clearance < 0)
    throw InputError(file, 0, "planner.holder_clearance", "must not be negative");
  if (p.fixture_clearance && *p.fixture_clearance < 0)
    throw InputError(file, 0, "planner.fixture_clearance", "must not be negative");
  p.max_tilt_deg = number_or(j, "max_tilt_deg", p.max_tilt_deg, file, "planner");
  if (!(p.max_tilt_deg > 0 && p.max_tilt_deg <= 90))
    throw InputError(file, 0, "planner.max_tilt_deg", "must be in (0, 90] degrees");
  if (std::abs(p.lead_deg) >= 90) throw InputError(file, 0, "planner.lead_deg", "must be within (-90, 90) degrees");
  if (std::abs(p.tilt_deg) >= 90) throw InputError(file, 0, "planner.tilt_deg", "must be within (-90, 90) degrees");
  return p;
}
}  // namespace

void require_for_planning(const Scene& s) {
  if (s.design.n_faces() == 0) throw InputError(s.file.string(), 0, "design", "missing (planning needs the design surface)");
  if (s.path.rows.empty()) throw InputError(s.file.string(), 0, "path", "missing (planning needs the input path)");
}

const std::vector<std::string>& work_offset_codes() {
  static const std::vector<std::string> codes = {"G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"};
  return codes;
}

const Tool& scene_tool(const Scene& scene, int number) {
  for (const ToolEntry& e : scene.tools)
    if (e.number == number) return e.tool;
  return scene.tool;
}

Scene load_scene(const fs::path& file) { return parse_scene(read_text_file(file, "scene file"), file); }

Scene parse_scene(const std::string& text, const fs::path& file) {
  Scene s;
  s.file = file;
  s.dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!file.empty()) s.files.push_back(file);
  const std::string name = file.string();
  const json j = parse_text(text, name);
  require_object(j, name, "(top level)");
  only_keys(j,
            {"units", "design", "check_surfaces", "stock", "fixtures", "tool", "tools", "work_offsets", "path",
             "planner", "machine", "name", "comment", "generator"},
            name, "");
  if (j.contains("units")) {
    s.units = string(j["units"], name, "units");
    if (s.units != "mm") throw InputError(name, 0, "units", "only 'mm' is supported");
  }
  // Optional: a program verified on its own often comes without a design (no gouge figures then) or a
  // path; planning needs both (require_for_planning).
  if (j.contains("design")) {
    const fs::path dp = resolve(s, j["design"], "design");
    s.design = load_mesh(dp);
    // The gouge test reads the part's side from the faces' normals: a closed design turned inside out
    // would invent gouges everywhere and hide the real ones (found in review). An open one cannot be told.
    if (is_closed(s.design) && signed_volume(s.design) <= 0.0)
      throw InputError(dp.string(), 0, "", "design mesh is inside out (faces must be oriented outward)");
  }
  if (j.contains("check_surfaces")) {
    const auto& c = j["check_surfaces"];
    if (!c.is_array()) throw InputError(name, 0, "check_surfaces", "must be an array of mesh files");
    for (size_t i = 0; i < c.size(); ++i) {
      const fs::path p = resolve(s, c[i], "check_surfaces[" + std::to_string(i) + "]");
      s.check_files.push_back(p);
      s.check_surfaces.push_back(load_mesh(p));
    }
  }
  if (!j.contains("stock")) throw InputError(name, 0, "stock", "missing");
  s.stock = parse_stock(s, j["stock"]);
  if (j.contains("fixtures")) {
    const auto& f = j["fixtures"];
    if (!f.is_array()) throw InputError(name, 0, "fixtures", "must be an array of mesh files");
    for (size_t i = 0; i < f.size(); ++i) s.fixtures.push_back(load_mesh(resolve(s, f[i], "fixtures[" + std::to_string(i) + "]")));
  }
  if (j.contains("tools")) s.tools = parse_tool_library(j["tools"], name);
  if (j.contains("tool")) {
    s.tool = parse_tool_json(j["tool"], name, "tool");
  } else if (!s.tools.empty()) {
    s.tool = s.tools.front().tool;
    s.tool_number = s.tools.front().number;
  } else {
    throw InputError(name, 0, "tool", "missing (give \"tool\" or a \"tools\" library)");
  }
  if (j.contains("work_offsets")) s.work_offsets = parse_work_offsets(j["work_offsets"], name);
  if (j.contains("path")) {
    const auto& p = j["path"];
    require_object(p, name, "path");
    only_keys(p, {"file", "feed"}, name, "path");
    if (!p.contains("file")) throw InputError(name, 0, "path.file", "missing");
    s.path_file = resolve(s, p["file"], "path.file");
    s.feed = positive(number_or(p, "feed", s.feed, name, "path"), name, "path.feed");
    s.path = read_toolpath(s.path_file, s.tool);
  }
  if (j.contains("planner")) {
    s.planner_json = j["planner"];
    s.planner = parse_planner_basics(s.planner_json, name);
  }
  if (j.contains("machine")) {
    const auto& m = j["machine"];
    if (m.is_string()) {
      s.machine_file = resolve(s, m, "machine");
      s.machine = read_machine_json(s.machine_file);
    } else {
      s.machine = parse_machine_json(m, name, "machine");
    }
  }
  check_work_offset_axes(s);
  check_path_axes_on_machine(s);
  return s;
}

}  // namespace tf
