// A small valid scene on disk that tests mutate one field at a time.
#pragma once
#include <nlohmann/json.hpp>

#include "test_support.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf::test {

inline nlohmann::json valid_scene_json() {
  return nlohmann::json::parse(R"({
    "units": "mm",
    "design": "design.stl",
    "check_surfaces": ["wall.stl"],
    "stock": {"box": {"min": [0, 0, 0], "max": [50, 40, 20]}},
    "fixtures": [],
    "tool": {"type": "ball", "radius": 3.0, "flute_length": 12.0, "shank_radius": 3.0,
             "length": 60.0, "holder": [{"radius": 12.0, "length": 40.0}]},
    "path": {"file": "path.csv", "feed": 1500},
    "planner": {"lead_deg": 0.0, "tilt_deg": 0.0, "safety_distance": 1.0},
    "machine": "machine.json"
  })");
}

inline const char* valid_path_csv() {
  return "x,y,z,nx,ny,nz\n10,10,21,0,0,1\n11,10,21,0,0,1\n12,10,21,0,0,1\n";
}

inline const char* valid_machine_json() {
  return R"({"name": "test", "kinematics": "table-table-ac", "pivot": [0, 0, 0],
             "limits": {"A": [-5, 110], "X": [-500, 500]}, "output": "joint"})";
}

// Writes the scene folder with `scene` as scene.json; returns the scene file.
inline std::filesystem::path write_scene(const TempDir& dir, const nlohmann::json& scene,
                                         const std::string& path_csv = valid_path_csv(),
                                         const std::string& machine = valid_machine_json()) {
  Stock box;
  box.kind = Stock::Kind::Box;
  box.box = {{0, 0, 0}, {50, 40, 18}};
  write_mesh(stock_to_mesh(box), dir / "design.stl");
  box.box = {{-5, 0, 0}, {0, 40, 40}};
  write_mesh(stock_to_mesh(box), dir / "wall.stl");
  write_text(dir / "path.csv", path_csv);
  write_text(dir / "machine.json", machine);
  write_text(dir / "scene.json", scene.dump(2));
  return dir / "scene.json";
}

}  // namespace tf::test
