// The impeller scene: assembles the model's meshes, the path and the scene description.
#include "scene_impeller.hpp"

#include "scene_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tf::scenes {

SceneBundle make_impeller_scene(const ImpellerOptions& o, const nlohmann::json& machine) {
  validate_impeller_options(o);
  const ImpellerModel model(o);
  SceneBundle s;
  s.name = "impeller";
  s.design = {"hub.stl", impeller_hub_mesh(model)};
  Mesh blades = impeller_blades_mesh(model);
  ImpellerPathReport report;
  s.path = impeller_path(model, blades, &report);
  s.check_surfaces.push_back({"blades.stl", std::move(blades)});
  s.stock_mesh = NamedMesh{"stock.stl", impeller_stock_mesh(model)};
  s.tool = ball_tool(o.tool_radius);
  s.feed = o.feed;
  s.planner.lead_deg = 0.0;
  s.planner.tilt_deg = 0.0;
  // The planner's default 1 mm, but never more than the ball is kept from the check surfaces: a row the
  // ball itself holds closer than the safety distance cannot be cleared by any tilt.
  s.planner.safety_distance = std::min(1.0, o.ball_clearance);
  s.machine = machine;
  s.generator = {
      {"command", "tiltfield scene impeller"},
      {"options",
       {{"blades", o.blades},
        {"splitters", o.splitters},
        {"splitter_start", tidy(o.splitter_start)},
        {"lean_deg", tidy(o.lean_deg)},
        {"wrap_deg", tidy(o.wrap_deg)},
        {"inlet_height", tidy(o.inlet_height)},
        {"outlet_height", tidy(o.outlet_height)},
        {"thickness_hub", tidy(o.thickness_hub)},
        {"thickness_tip", tidy(o.thickness_tip)},
        {"blade_sink", tidy(o.blade_sink)},
        {"inlet_radius", tidy(o.inlet_radius)},
        {"inlet_z", tidy(o.inlet_z)},
        {"outlet_radius", tidy(o.outlet_radius)},
        {"outlet_z", tidy(o.outlet_z)},
        {"nose_z", tidy(o.nose_z)},
        {"tolerance", tidy(o.tolerance)},
        {"blade_tolerance", tidy(o.blade_tolerance)},
        {"allowance", tidy(o.allowance)},
        {"stock_tolerance", tidy(o.stock_tolerance)},
        {"tool_radius", tidy(o.tool_radius)},
        {"step", tidy(o.step)},
        {"passes", o.passes},
        {"m_start", tidy(o.m_start)},
        {"m_end", tidy(o.m_end)},
        {"ball_clearance", tidy(o.ball_clearance)},
        {"feed", tidy(o.feed)}}},
      {"facts",
       {{"rows", s.path.rows.size()},
        {"min_ball_clearance_mm", tidy(report.min_ball_clearance)},
        {"nominal_axis_collision_rows", report.nominal_axis_hits},
        {"hub_triangles", s.design.mesh.n_faces()},
        {"blade_triangles", s.check_surfaces[0].mesh.n_faces()}}}};
  // Look into the machined channel from outside and above.
  const double mid = model.camber_theta(0, 0.5, 0.0) + std::numbers::pi / (o.splitters ? 2 * o.blades : o.blades);
  s.view_azimuth_deg = mid * 180.0 / std::numbers::pi - 25.0;
  s.view_elevation_deg = 40.0;
  return s;
}

}  // namespace tf::scenes
