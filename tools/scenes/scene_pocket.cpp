#include "scene_pocket.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "scene_distance.hpp"
#include "scene_geometry.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::scenes {

namespace {
void check_pocket(bool ok, const char* option, const std::string& what) { require_option(ok, "pocket", option, what); }
}  // namespace

void validate_pocket_options(const PocketOptions& o) {
  check_pocket(size_mm(o.length), "--length", kSizeRange);
  check_pocket(size_mm(o.width), "--width", kSizeRange);
  check_pocket(size_mm(o.floor_thickness), "--floor-thickness", kSizeRange);
  check_pocket(size_mm(o.wall_height), "--wall-height", kSizeRange);
  check_pocket(size_mm(o.wall_thickness), "--wall-thickness", kSizeRange);
  check_pocket(std::isfinite(o.overhang_deg) && o.overhang_deg >= 0 && o.overhang_deg <= 60, "--overhang",
        "must be within [0, 60] degrees");
  check_pocket(std::isfinite(o.overhang_deg) && o.wall_height * std::tan(rad(o.overhang_deg)) < o.width, "--overhang",
        "the overhang would reach past the vertical wall (lower --overhang or --wall-height)");
  check_pocket(positive(o.wall_sink) && o.wall_sink < o.floor_thickness, "--wall-sink",
        "must be positive and less than the floor thickness");
  check_pocket(size_mm(o.allowance), "--allowance", kSizeRange);
  check_pocket(size_mm(o.tool_radius) && o.tool_radius <= 25, "--tool-radius", "must be from 0.01 to 25 mm");
  require_step(o.step, o.tool_radius, "pocket");
  check_pocket(o.passes >= 1 && o.passes <= 500, "--passes", "must be an integer from 1 to 500");
  check_pocket(std::isfinite(o.ball_clearance) && o.ball_clearance >= 0 && o.ball_clearance <= 10, "--ball-clearance",
        "must be within [0, 10] mm");
  check_pocket(positive(o.feed), "--feed", "must be positive (mm/min)");
  const double rows = o.passes * (o.length / o.step + 1);
  check_pocket(rows <= kMaxSceneRows, "--step", "with --passes and --length makes " + fixed(rows, 0) +
                                                     " rows, more than 2 000 000 (a coarser --step or fewer --passes)");
}

SceneBundle make_pocket_scene(const PocketOptions& o, const nlohmann::json& machine) {
  validate_pocket_options(o);
  const double L = o.length, W = o.width, T = o.wall_thickness, H = o.wall_height, k = o.wall_sink;
  const double ta = std::tan(rad(o.overhang_deg)), ca = std::cos(rad(o.overhang_deg));
  SceneBundle s;
  s.name = "pocket";
  s.design = {"floor.stl", box_mesh({0.0, -T, -o.floor_thickness}, {L, W + T, 0.0})};
  s.check_surfaces.push_back({"wall_vertical.stl", extrude_along_x({{-T, -k}, {0.0, -k}, {0.0, H}, {-T, H}}, 0.0, L)});
  // Inner face: y = W - z tan(overhang), continued below the floor top into the slab.
  s.check_surfaces.push_back(
      {"wall_overhang.stl", extrude_along_x({{W + k * ta, -k}, {W + T, -k}, {W + T, H}, {W - H * ta, H}}, 0.0, L)});
  s.stock_box = {Eigen::Vector3d(0.0, 0.0, -o.floor_thickness), Eigen::Vector3d(L, W, o.allowance)};
  s.tool = ball_tool(o.tool_radius);

  // Passes along x; the outer ones keep the ball (centre at z = R) ball_clearance + a little off the
  // vertical face y = 0 and off the inclined face (distance (W - R tan a - y) cos a).
  Mesh walls = s.check_surfaces[0].mesh;
  append_mesh(walls, s.check_surfaces[1].mesh);
  const TriangleBvh dist({&walls});
  const double R = o.tool_radius, margin = o.ball_clearance + 0.01;
  const double y0 = R + margin, y1 = W - R * ta - (R + margin) / ca;
  require_option(y1 >= y0, "pocket", "--tool-radius", "the floor is too narrow for a ball of radius " + fixed(R, 3) + " mm");
  std::vector<Eigen::Vector3d> knots;
  for (int j = 0; j < o.passes; ++j) {
    const double y = o.passes == 1 ? 0.5 * (y0 + y1) : y0 + (y1 - y0) * j / (o.passes - 1);
    const double xa = j % 2 == 0 ? 0.0 : L, xb = L - xa;
    knots.emplace_back(xa, y, R);
    knots.emplace_back(xb, y, R);
  }
  double min_clear = std::numeric_limits<double>::infinity();
  int hits = 0;
  for (const Eigen::Vector3d& p : resample_polyline(knots, o.step)) {
    s.path.rows.push_back({p, Eigen::Vector3d::UnitZ()});
    min_clear = std::min(min_clear, dist.closest(p).distance - R);
    hits += tool_axis_hits(s.tool, dist, p, Eigen::Vector3d::UnitZ());
  }
  if (min_clear < o.ball_clearance) throw JobError("scene pocket: the ball is not clear of the walls (internal error)");
  s.feed = o.feed;
  // The planner's default 1 mm, but never more than the ball is kept from the check surfaces: a row the
  // ball itself holds closer than the safety distance cannot be cleared by any tilt.
  s.planner.safety_distance = std::min(1.0, o.ball_clearance);
  s.machine = machine;
  s.generator = {{"command", "tiltfield scene pocket"},
                 {"options",
                  {{"length", tidy(L)},
                   {"width", tidy(W)},
                   {"floor_thickness", tidy(o.floor_thickness)},
                   {"wall_height", tidy(H)},
                   {"wall_thickness", tidy(T)},
                   {"overhang_deg", tidy(o.overhang_deg)},
                   {"wall_sink", tidy(k)},
                   {"allowance", tidy(o.allowance)},
                   {"tool_radius", tidy(R)},
                   {"step", tidy(o.step)},
                   {"passes", o.passes},
                   {"ball_clearance", tidy(o.ball_clearance)},
                   {"feed", tidy(o.feed)}}},
                 {"facts",
                  {{"rows", s.path.rows.size()},
                   {"min_ball_clearance_mm", tidy(min_clear)},
                   {"nominal_axis_collision_rows", hits}}}};
  s.view_azimuth_deg = -25.0;
  s.view_elevation_deg = 40.0;
  return s;
}

}  // namespace tf::scenes
