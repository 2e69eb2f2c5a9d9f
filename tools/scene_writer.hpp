// tiltfield scene generators: what a generated scene is made of, and how it is written to a folder that
// tf::load_scene reads back (scene.json, binary STL meshes, path.csv, machine.json).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tiltfield/mesh.hpp"
#include "tiltfield/scene.hpp"
#include "tiltfield/tool.hpp"
#include "tiltfield/toolpath.hpp"

namespace tf::scenes {

struct NamedMesh {
  std::string file;  // file name inside the scene folder, e.g. "hub.stl"
  Mesh mesh;
};

struct SceneBundle {
  std::string name;                      // "impeller", "pocket", "block"
  NamedMesh design;                      // the surface to finish
  std::vector<NamedMesh> check_surfaces; // obstacles for the whole tool
  std::optional<NamedMesh> stock_mesh;   // a closed stock mesh, or else:
  StockBox stock_box;                    // the raw block (used when stock_mesh is empty)
  Tool tool;
  ToolPath path;                         // ball centres (cutter locations) and design normals
  double feed = 1500.0;                  // mm/min
  PlannerBasics planner;                 // lead, tilt, safety distance are written
  nlohmann::json machine;                // the machine JSON object, written as machine.json
  nlohmann::json generator;              // options used and facts measured, kept under "generator"
  // Preview camera (see render_svg.hpp): azimuth about +z from +x and elevation above the xy plane, deg.
  double view_azimuth_deg = -60.0;
  double view_elevation_deg = 35.0;
};

// The generated scenes' tools, for a cutter radius r (mm): flutes 4 r long, shank radius r, gauge length
// max(60, 4 r + 20) mm, one holder cylinder of radius max(12, r + 6) and length 40 mm. For r = 3 the ball
// tool is the spec's example tool.
Tool ball_tool(double r);
Tool flat_tool(double r);

// The spec's "tool" object for `tool`.
nlohmann::json tool_to_json(const Tool& tool);

// The built-in machine descriptions the bundled scenes use (identical to scenes/machines/NAME.json):
// "table-table-ac", "table-table-bc" or "xyz". Throws std::invalid_argument for another name.
nlohmann::json builtin_machine(const std::string& name);

// The machine object for a scene: the built-in `builtin_name`, or the file given with --machine (checked
// with tf::read_machine_json, which throws InputError naming the file and field).
nlohmann::json machine_json(const std::string& builtin_name, const std::filesystem::path& user_file);

// Writes every file of the scene into `dir` (created when missing), each atomically, scene.json last so a
// failed run leaves no scene.json. Throws InputError naming `dir` when the folder cannot be created or
// written. Returns the path of scene.json.
std::filesystem::path write_scene_folder(const SceneBundle& scene, const std::filesystem::path& dir);

// Throws InputError("scene NAME", 0, option, what) when `ok` is false: one line naming the option.
void require_option(bool ok, const std::string& scene, const std::string& option, const std::string& what);

}  // namespace tf::scenes
