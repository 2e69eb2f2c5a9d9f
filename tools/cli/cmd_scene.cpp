// `tiltfield scene impeller|pocket|block [options] -o DIR [--preview FILE.svg]`: parametric scenes.
#include <iostream>
#include <memory>

#include "cli.hpp"
#include "scenes/render_svg.hpp"
#include "scenes/scene_block.hpp"
#include "scenes/scene_impeller.hpp"
#include "scenes/scene_pocket.hpp"
#include "scenes/scene_writer.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::cli {
namespace {
namespace sc = tf::scenes;
namespace fs = std::filesystem;

struct Common {
  std::string dir, preview, machine;
};

void add_common(CLI::App* cmd, Common& c) {
  cmd->add_option("-o,--output", c.dir, "output folder (created when missing)")->required();
  cmd->add_option("--preview", c.preview, "also write an SVG picture of the scene");
  cmd->add_option("--machine", c.machine, "machine JSON to copy into the scene instead of the built-in one");
}

// Before the scene is written: a preview that cannot be written had left a whole scene behind, and one
// named as a file of the scene replaced it with the picture (black-box testing).
void check_preview(const sc::SceneBundle& scene, const Common& c) {
  if (c.preview.empty()) return;
  std::error_code ec;
  const auto normal = [&ec](const std::string& p) {
    fs::path q = fs::weakly_canonical(fs::absolute(p, ec), ec).lexically_normal();
    return q.filename().empty() ? q.parent_path() : q;  // "dir/" names dir
  };
  const fs::path dir = normal(c.dir), preview = normal(c.preview);
  if (preview == dir) throw InputError(c.preview, 0, "--preview", "is the output folder (-o), not a file name");
  for (const std::string& name : sc::scene_folder_files(scene))
    if (preview == dir / name)
      throw InputError(c.preview, 0, "--preview", "is the scene's own " + name + " in the output folder: give the picture its own name");
  if (preview.parent_path() == dir && !fs::exists(dir, ec)) return;  // inside the folder -o creates
  check_output_file("--preview", c.preview);
}

void finish(const sc::SceneBundle& scene, const Common& c, const std::string& summary) {
  check_preview(scene, c);
  const auto file = sc::write_scene_folder(scene, c.dir);
  if (!c.preview.empty()) sc::write_scene_preview(scene, c.preview);
  if (!global_options().quiet) std::cout << file.string() << ": " << summary << "\n";
}

void add_impeller(CLI::App* parent) {
  auto* cmd = parent->add_subcommand("impeller", "parametric centrifugal impeller with a hub-finishing path");
  auto o = std::make_shared<sc::ImpellerOptions>();
  auto c = std::make_shared<Common>();
  add_common(cmd, *c);
  cmd->add_option("--blades", o->blades, "number of main blades")->capture_default_str();
  cmd->add_flag("--splitters", o->splitters, "add a splitter blade between main blades");
  cmd->add_option("--splitter-start", o->splitter_start, "meridional parameter where splitters begin")->capture_default_str();
  cmd->add_option("--lean", o->lean_deg, "blade lean, deg")->capture_default_str();
  cmd->add_option("--wrap", o->wrap_deg, "blade wrap angle inlet to outlet, deg")->capture_default_str();
  cmd->add_option("--inlet-height", o->inlet_height, "blade height at the inlet, mm")->capture_default_str();
  cmd->add_option("--outlet-height", o->outlet_height, "blade height at the outlet, mm")->capture_default_str();
  cmd->add_option("--thickness-hub", o->thickness_hub, "blade thickness at the hub, mm")->capture_default_str();
  cmd->add_option("--thickness-tip", o->thickness_tip, "blade thickness at the tip, mm")->capture_default_str();
  cmd->add_option("--blade-sink", o->blade_sink, "blade bottom depth below the hub, mm")->capture_default_str();
  cmd->add_option("--inlet-radius", o->inlet_radius, "hub radius at the inlet, mm")->capture_default_str();
  cmd->add_option("--inlet-z", o->inlet_z, "hub height at the inlet, mm")->capture_default_str();
  cmd->add_option("--outlet-radius", o->outlet_radius, "hub radius at the outlet, mm")->capture_default_str();
  cmd->add_option("--outlet-z", o->outlet_z, "hub height at the outlet, mm")->capture_default_str();
  cmd->add_option("--nose-z", o->nose_z, "top of the hub nose, mm")->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance, "chordal tolerance of the hub, mm")->capture_default_str();
  cmd->add_option("--blade-tolerance", o->blade_tolerance, "chordal tolerance of the blades, mm")->capture_default_str();
  cmd->add_option("--allowance", o->allowance, "stock allowance over the hub, mm")->capture_default_str();
  cmd->add_option("--stock-tolerance", o->stock_tolerance, "chordal tolerance of the stock, mm")->capture_default_str();
  cmd->add_option("--tool-radius", o->tool_radius, "ball radius, mm")->capture_default_str();
  cmd->add_option("--step", o->step, "cutter-location spacing along a pass, mm")->capture_default_str();
  cmd->add_option("--passes", o->passes, "passes across the channel")->capture_default_str();
  cmd->add_option("--m-start", o->m_start, "first meridional parameter of a pass")->capture_default_str();
  cmd->add_option("--m-end", o->m_end, "last meridional parameter of a pass")->capture_default_str();
  cmd->add_option("--ball-clearance", o->ball_clearance, "least ball distance to the blades, mm")->capture_default_str();
  cmd->add_option("--feed", o->feed, "feed, mm/min")->capture_default_str();
  cmd->callback([o, c] {
    const auto scene = sc::make_impeller_scene(*o, sc::machine_json("table-table-ac", c->machine));
    const auto& f = scene.generator["facts"];
    finish(scene, *c,
           std::to_string(scene.path.rows.size()) + " rows, ball clearance >= " +
               fixed(f["min_ball_clearance_mm"].get<double>(), 3) + " mm, nominal axis meets the blades on " +
               std::to_string(f["nominal_axis_collision_rows"].get<int>()) + " rows");
  });
}

void add_pocket(CLI::App* parent) {
  auto* cmd = parent->add_subcommand("pocket", "open pocket with a vertical and an overhanging wall");
  auto o = std::make_shared<sc::PocketOptions>();
  auto c = std::make_shared<Common>();
  add_common(cmd, *c);
  cmd->add_option("--length", o->length, "pocket length along x (open ends), mm")->capture_default_str();
  cmd->add_option("--width", o->width, "floor width between the wall feet, mm")->capture_default_str();
  cmd->add_option("--floor-thickness", o->floor_thickness, "floor slab thickness, mm")->capture_default_str();
  cmd->add_option("--wall-height", o->wall_height, "wall height above the floor, mm")->capture_default_str();
  cmd->add_option("--wall-thickness", o->wall_thickness, "wall thickness at the foot, mm")->capture_default_str();
  cmd->add_option("--wall-sink", o->wall_sink, "depth of the walls inside the floor slab, mm")->capture_default_str();
  cmd->add_option("--overhang", o->overhang_deg, "overhang of the second wall from vertical, deg")->capture_default_str();
  cmd->add_option("--allowance", o->allowance, "stock allowance over the floor, mm")->capture_default_str();
  cmd->add_option("--tool-radius", o->tool_radius, "ball radius, mm")->capture_default_str();
  cmd->add_option("--step", o->step, "cutter-location spacing along a pass, mm")->capture_default_str();
  cmd->add_option("--passes", o->passes, "passes across the pocket")->capture_default_str();
  cmd->add_option("--ball-clearance", o->ball_clearance, "least ball distance to the walls, mm")->capture_default_str();
  cmd->add_option("--feed", o->feed, "feed, mm/min")->capture_default_str();
  cmd->callback([o, c] {
    const auto scene = sc::make_pocket_scene(*o, sc::machine_json("table-table-bc", c->machine));
    const auto& f = scene.generator["facts"];
    finish(scene, *c,
           std::to_string(scene.path.rows.size()) + " rows, nominal axis meets the overhang on " +
               std::to_string(f["nominal_axis_collision_rows"].get<int>()) + " rows");
  });
}

void add_block(CLI::App* parent) {
  auto* cmd = parent->add_subcommand("block", "3-axis facing of a block with a flat end mill");
  auto o = std::make_shared<sc::BlockOptions>();
  auto c = std::make_shared<Common>();
  add_common(cmd, *c);
  cmd->add_option("--size-x", o->size_x, "block length, mm")->capture_default_str();
  cmd->add_option("--size-y", o->size_y, "block width, mm")->capture_default_str();
  cmd->add_option("--height", o->height, "stock height, mm")->capture_default_str();
  cmd->add_option("--depth", o->depth, "facing depth, mm")->capture_default_str();
  cmd->add_option("--tool-radius", o->tool_radius, "flat end mill radius, mm")->capture_default_str();
  cmd->add_option("--stepover", o->stepover, "largest distance between passes, mm")->capture_default_str();
  cmd->add_option("--step", o->step, "cutter-location spacing along a pass, mm")->capture_default_str();
  cmd->add_option("--feed", o->feed, "feed, mm/min")->capture_default_str();
  cmd->callback([o, c] {
    const auto scene = sc::make_block_scene(*o, sc::machine_json("xyz", c->machine));
    finish(scene, *c, std::to_string(scene.path.rows.size()) + " rows");
  });
}
}  // namespace

void add_scene_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("scene", "writes a parametric scene folder (impeller, pocket, block)");
  cmd->require_subcommand(1);
  add_impeller(cmd);
  add_pocket(cmd);
  add_block(cmd);
}

}  // namespace tf::cli
