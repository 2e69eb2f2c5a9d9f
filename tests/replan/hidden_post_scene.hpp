// A scene for the closed loop's tests: a straight ball-end pass beside a tall post that only the stock
// holds (the check surfaces omit it), so only the verifier can find the holder meeting it.
#pragma once
#include <filesystem>
#include <string>

#include "test_support.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf::test {
namespace fs = std::filesystem;

inline tf::Mesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  tf::Stock s;
  s.kind = tf::Stock::Kind::Box;
  s.box = {lo, hi};
  return tf::stock_to_mesh(s);
}

// A straight ball-end pass over a floor; the stock holds a thin layer to cut and a tall post beside the
// pass that the holder (radius 12, 60 mm above the tip) meets when the axis stays vertical. The post is
// in the stock only, not in the check surfaces, so the planner cannot know it.
inline fs::path write_hidden_post_scene(const tf::test::TempDir& dir) {
  tf::write_mesh(box({-50, -10, -10}, {90, 10, 0}), dir / "floor.stl");
  tf::Mesh stock = box({-50, -10, -10}, {90, 10, 0.5});
  tf::append_mesh(stock, box({15, 8, 1}, {25, 20, 80}));
  tf::write_mesh(stock, dir / "stock.stl");
  // A low wall on the far side, so the check surfaces are not empty.
  tf::write_mesh(box({-50, -22, 0}, {90, -20, 5}), dir / "wall.stl");
  std::string csv = "x,y,z,nx,ny,nz\n";
  for (int i = 0; i <= 240; ++i) csv += tf::fixed(-40 + i * 0.5, 3) + ",0,3,0,0,1\n";
  tf::test::write_text(dir / "path.csv", csv);
  fs::copy_file(fs::path(TILTFIELD_SOURCE_DIR) / "scenes/machines/table-table-ac.json", dir / "machine.json");
  tf::test::write_text(dir / "scene.json", R"({
    "design": "floor.stl", "check_surfaces": ["wall.stl"], "stock": {"mesh": "stock.stl"},
    "tool": {"type": "ball", "radius": 3, "flute_length": 12, "shank_radius": 3, "length": 60,
             "holder": [{"radius": 12, "length": 40}]},
    "path": {"file": "path.csv", "feed": 1200},
    "planner": {"safety_distance": 1.0},
    "machine": "machine.json"})");
  return dir / "scene.json";
}

}  // namespace tf::test
