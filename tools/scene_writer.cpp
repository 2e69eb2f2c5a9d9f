#include "scene_writer.hpp"

#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "tiltfield/error.hpp"
#include "tiltfield/io.hpp"
#include "tiltfield/machine.hpp"

namespace tf::scenes {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
Tool generated_tool(Cutter cutter, double r) {
  Tool t;
  t.cutter = cutter;
  t.flute_length = 4.0 * r;
  t.shank_radius = r;
  t.length = std::max(60.0, t.flute_length + 20.0);
  t.holder = {{std::max(12.0, r + 6.0), 40.0}};
  return t;
}
}  // namespace

Tool ball_tool(double r) { return generated_tool(BallCutter{r}, r); }
Tool flat_tool(double r) { return generated_tool(FlatCutter{r}, r); }

json tool_to_json(const Tool& tool) {
  json t;
  t["type"] = std::string(tool.type_name());
  t["radius"] = tool.radius();
  if (const auto* b = std::get_if<BullCutter>(&tool.cutter)) t["corner_radius"] = b->corner_radius;
  t["flute_length"] = tool.flute_length;
  t["shank_radius"] = tool.shank_radius;
  t["length"] = tool.length;
  json holder = json::array();
  for (const auto& h : tool.holder) holder.push_back({{"radius", h.radius}, {"length", h.length}});
  t["holder"] = holder;
  return t;
}

json builtin_machine(const std::string& name) {
  // Travel limits are generous: the scenes exercise the rotary axes, not the table size.
  if (name == "table-table-ac") {
    return {{"name", "table-table-ac"},
            {"comment",
             "Double rotary table, LinuxCNC xyzac-trt convention: A tilts the table about X, C turns it about Z. "
             "pivot: where the A and C axes meet, in machine coordinates with the part origin at the machine "
             "origin and A = C = 0 (the part sits 20 mm above the A axis). C has no limits (continuous)."},
            {"kinematics", "table-table-ac"},
            {"pivot", {0.0, 0.0, -20.0}},
            {"limits", {{"X", {-500.0, 500.0}}, {"Y", {-500.0, 500.0}}, {"Z", {-400.0, 500.0}}, {"A", {-5.0, 110.0}}}},
            {"output", "joint"},
            {"max_feed", 10000.0},
            {"rapid_feed", 20000.0},
            {"safe_z", 50.0}};
  }
  if (name == "table-table-bc") {
    return {{"name", "table-table-bc"},
            {"comment",
             "Double rotary table, LinuxCNC xyzbc-trt convention: B tilts the table about Y, C turns it about Z. "
             "pivot: where the B and C axes meet, in machine coordinates with the part origin at the machine "
             "origin and B = C = 0. C has no limits (continuous)."},
            {"kinematics", "table-table-bc"},
            {"pivot", {40.0, 0.0, -30.0}},
            {"limits", {{"X", {-500.0, 500.0}}, {"Y", {-500.0, 500.0}}, {"Z", {-400.0, 500.0}}, {"B", {-90.0, 90.0}}}},
            {"output", "joint"},
            {"max_feed", 10000.0},
            {"rapid_feed", 20000.0},
            {"safe_z", 50.0}};
  }
  if (name == "xyz") {
    return {{"name", "xyz"},
            {"comment", "3-axis mill: programmed X Y Z are the tool tip in the part frame."},
            {"kinematics", "xyz"},
            {"limits", {{"X", {-500.0, 500.0}}, {"Y", {-500.0, 500.0}}, {"Z", {-400.0, 500.0}}}},
            {"output", "joint"},
            {"max_feed", 10000.0},
            {"rapid_feed", 20000.0},
            {"safe_z", 50.0}};
  }
  throw std::invalid_argument("builtin_machine: unknown machine '" + name + "'");
}

json machine_json(const std::string& builtin_name, const fs::path& user_file) {
  if (user_file.empty()) return builtin_machine(builtin_name);
  read_machine_json(user_file);  // validates; throws InputError naming the file and field
  std::ifstream in(user_file, std::ios::binary);
  return json::parse(in);
}

void require_option(bool ok, const std::string& scene, const std::string& option, const std::string& what) {
  if (!ok) throw InputError("scene " + scene, 0, option, what);
}

fs::path write_scene_folder(const SceneBundle& s, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError(dir.string(), 0, "-o", "cannot create the output folder");
  // OpenMesh's STL writer announces itself on its log stream; a generator's output is one summary line.
  struct LogOff {
    LogOff() { omlog().disable(); }
    ~LogOff() { omlog().enable(); }
  } log_off;
  try {
    write_mesh(s.design.mesh, dir / s.design.file);
    for (const auto& c : s.check_surfaces) write_mesh(c.mesh, dir / c.file);
    if (s.stock_mesh) write_mesh(s.stock_mesh->mesh, dir / s.stock_mesh->file);
    write_toolpath_csv(s.path, dir / "path.csv");
    write_file_atomic(dir / "machine.json", [&](std::ostream& out) { out << s.machine.dump(2) << '\n'; });
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    throw InputError(dir.string(), 0, "-o", std::string("cannot write the scene: ") + e.what());
  }

  json j;
  j["name"] = s.name;
  j["units"] = "mm";
  j["design"] = s.design.file;
  j["check_surfaces"] = json::array();
  for (const auto& c : s.check_surfaces) j["check_surfaces"].push_back(c.file);
  if (s.stock_mesh) {
    j["stock"] = {{"mesh", s.stock_mesh->file}};
  } else {
    const auto& b = s.stock_box;
    j["stock"] = {{"box", {{"min", {b.min.x(), b.min.y(), b.min.z()}}, {"max", {b.max.x(), b.max.y(), b.max.z()}}}}};
  }
  j["fixtures"] = json::array();
  j["tool"] = tool_to_json(s.tool);
  j["path"] = {{"file", "path.csv"}, {"feed", s.feed}};
  j["planner"] = {{"lead_deg", s.planner.lead_deg},
                  {"tilt_deg", s.planner.tilt_deg},
                  {"safety_distance", s.planner.safety_distance}};
  j["machine"] = "machine.json";
  if (!s.generator.is_null()) j["generator"] = s.generator;
  const fs::path scene_file = dir / "scene.json";
  try {
    write_file_atomic(scene_file, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
  } catch (const std::runtime_error& e) {
    throw InputError(dir.string(), 0, "-o", std::string("cannot write the scene: ") + e.what());
  }
  return scene_file;
}

}  // namespace tf::scenes
