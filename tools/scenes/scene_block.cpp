#include "scene_block.hpp"

#include <cmath>

#include "scene_geometry.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::scenes {

namespace {
void check_block(bool ok, const char* option, const std::string& what) { require_option(ok, "block", option, what); }
}  // namespace

void validate_block_options(const BlockOptions& o) {
  check_block(size_mm(o.size_x), "--size-x", kSizeRange);
  check_block(size_mm(o.size_y), "--size-y", kSizeRange);
  check_block(size_mm(o.height), "--height", kSizeRange);
  check_block(positive(o.depth) && o.depth < o.height, "--depth", "must be positive and less than --height");
  check_block(size_mm(o.tool_radius) && o.tool_radius <= 25, "--tool-radius", "must be from 0.01 to 25 mm");
  check_block(size_mm(o.stepover) && o.stepover <= 2.0 * o.tool_radius, "--stepover",
        "must be at least 0.01 mm and at most the tool diameter");
  require_step(o.step, o.tool_radius, "block");
  check_block(positive(o.feed), "--feed", "must be positive (mm/min)");
  const double rows = (o.size_y / o.stepover + 1) * ((o.size_x + 2 * o.tool_radius + 4) / o.step + 1);
  check_block(rows <= kMaxSceneRows, "--stepover",
              "with --step and the block's size makes " + fixed(rows, 0) + " rows, more than 2 000 000 (coarser "
              "--stepover or --step)");
}

SceneBundle make_block_scene(const BlockOptions& o, const nlohmann::json& machine) {
  validate_block_options(o);
  SceneBundle s;
  s.name = "block";
  const double top = o.height - o.depth;
  s.design = {"block.stl", box_mesh(Eigen::Vector3d::Zero(), {o.size_x, o.size_y, top})};
  s.stock_box = {Eigen::Vector3d::Zero(), Eigen::Vector3d(o.size_x, o.size_y, o.height)};
  s.tool = flat_tool(o.tool_radius);
  const double run = o.tool_radius + 2.0;
  const int n = std::max(1, static_cast<int>(std::ceil(o.size_y / o.stepover - 1e-9)));
  std::vector<Eigen::Vector3d> knots;
  for (int j = 0; j <= n; ++j) {
    const double y = o.size_y * j / n;
    const double xa = j % 2 == 0 ? -run : o.size_x + run, xb = o.size_x - xa;
    knots.emplace_back(xa, y, top);
    knots.emplace_back(xb, y, top);
  }
  for (const Eigen::Vector3d& p : resample_polyline(knots, o.step)) s.path.rows.push_back({p, Eigen::Vector3d::UnitZ()});
  s.feed = o.feed;
  s.planner.safety_distance = 1.0;
  s.machine = machine;
  s.generator = {{"command", "tiltfield scene block"},
                 {"options",
                  {{"size_x", tidy(o.size_x)},
                   {"size_y", tidy(o.size_y)},
                   {"height", tidy(o.height)},
                   {"depth", tidy(o.depth)},
                   {"tool_radius", tidy(o.tool_radius)},
                   {"stepover", tidy(o.stepover)},
                   {"step", tidy(o.step)},
                   {"feed", tidy(o.feed)}}},
                 {"facts", {{"rows", s.path.rows.size()}, {"passes", n + 1}}}};
  s.view_azimuth_deg = -60.0;
  s.view_elevation_deg = 35.0;
  return s;
}

}  // namespace tf::scenes
