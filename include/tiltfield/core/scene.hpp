// tiltfield core: the scene: everything one job needs, loaded and validated from the scene JSON.
//
// In: a scene file (README, "Files": design, check surfaces, stock as mesh, box or cylinder, fixtures,
// tool and tool library, work offsets, path and feed, planner options, machine); paths inside it are
// relative to it. Out: a Scene with every mesh and the path loaded, the machine resolved, and the
// planner's basic options (safety distance, lead/tilt, max tilt) with their defaults. Units: mm, deg,
// mm/min. Unknown keys are refused.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace tf {

struct StockBox {
  Eigen::Vector3d min, max;  // mm
};
struct StockCylinder {
  Eigen::Vector3d base;  // centre of the bottom face, mm
  Eigen::Vector3d axis;  // unit
  double radius = 0.0, height = 0.0;
};

struct Stock {
  enum class Kind { Mesh, Box, Cylinder } kind = Kind::Box;
  Mesh mesh;  // Kind::Mesh: a closed mesh
  StockBox box;
  StockCylinder cylinder;
};

// A closed triangle mesh of the stock, whatever its kind (a cylinder with `segments` facets around).
Mesh stock_to_mesh(const Stock& stock, int segments = 128);

// The options every planner shares; the planner's own tuning keys stay in Scene::planner_json and are
// parsed (and checked) by the planner.
struct PlannerBasics {
  double lead_deg = 0.0;          // nominal lead: rotation about t = f x n toward the feed, deg
  double tilt_deg = 0.0;          // nominal tilt: rotation about the feed direction f, deg
  double safety_distance = 1.0;   // clearance of the whole tool to the check surfaces, mm
  std::optional<double> shank_clearance;   // mm, defaults to safety_distance
  std::optional<double> holder_clearance;  // mm, defaults to safety_distance
  std::optional<double> fixture_clearance; // of every part of the tool to the fixtures, mm; defaults to safety_distance
  double max_tilt_deg = 60.0;     // largest angle between the tool axis and the surface normal, deg
};

// A numbered tool of the scene's library ("tools"): a program's T word and M6 select it, G43 H takes its
// gauge length (Tool::length).
struct ToolEntry {
  int number = 1;  // >= 1
  Tool tool;
};

// A work offset (G54 ... G59.3): X Y Z in mm, A B C in degrees, added to the programmed coordinates.
using WorkOffset = std::array<double, 6>;

struct Scene {
  std::filesystem::path file;  // the scene file as given
  std::filesystem::path dir;   // its folder; relative paths inside resolve against it
  std::string units = "mm";
  Mesh design;
  std::vector<Mesh> check_surfaces;
  std::vector<std::filesystem::path> check_files;
  Stock stock;
  std::vector<Mesh> fixtures;
  // The tool for the planner and for programs without a tool change (the spindle's tool before the first
  // M6). Without a "tool" key: the first entry of `tools`.
  Tool tool;
  int tool_number = 0;                             // 0, or the library number `tool` was taken from
  std::vector<ToolEntry> tools;                    // the tool library, in file order (empty: one tool)
  std::map<std::string, WorkOffset> work_offsets;  // "G54" ... "G59.3" -> offset
  ToolPath path;
  std::filesystem::path path_file;
  double feed = 1000.0;  // mm/min
  PlannerBasics planner;
  nlohmann::json planner_json = nlohmann::json::object();  // the whole "planner" object as written
  std::optional<MachineSpec> machine;                      // absent: the scene names no machine
  std::filesystem::path machine_file;                      // empty when inline or absent
  // Every file the scene was read from: the scene file, its meshes, path and machine (the outputs of a
  // command must not replace them).
  std::vector<std::filesystem::path> files;
};

// Everything the part occupies: design, check surfaces, fixtures and stock, part frame, mm (for safe
// heights and simulation bounds).
Eigen::AlignedBox3d scene_bounds(const Scene& scene);

// Loads and validates a scene. Throws InputError naming the scene file (or the referenced file) and the
// JSON field, or the line of a path file. Every referenced mesh and path file is read. `design` and
// `path` are optional here (verifying a program needs neither); Scene::design is then empty and
// Scene::path has no rows.
Scene load_scene(const std::filesystem::path& file);

// The same from the scene's JSON text; `file` names it in errors and its folder resolves relative paths.
Scene parse_scene(const std::string& text, const std::filesystem::path& file);

// The tool numbered `number` in the scene's library, or the scene's `tool` when the library has none of
// that number (every number of a scene without a library).
const Tool& scene_tool(const Scene& scene, int number);

// The work-offset codes a scene may define, as LinuxCNC names them: G54 ... G59, G59.1, G59.2, G59.3.
const std::vector<std::string>& work_offset_codes();

// Throws InputError naming the field when the scene lacks what planning needs (design, path).
void require_for_planning(const Scene& scene);

// Parses the "tool" object; `file` and `prefix` only name the place in errors.
Tool parse_tool_json(const nlohmann::json& j, const std::string& file, const std::string& prefix);

}  // namespace tf
