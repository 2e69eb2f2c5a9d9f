// `tiltfield verify SCENE PROGRAM.ngc -o VERIFY.json [--blocks BLOCKS.csv] [--stock-mesh STOCK.ply]
//  [--html REPORT.html] [--mesh-tolerance MM] [--resolution MM] [--gouge-tolerance MM] [--collision-tolerance MM]
//  [--engagement PAIRS.csv] [--subroutine-path DIR:DIR]`: tri-dexel
// material-removal simulation of a G-code program (docs/verifier.md), its compact stock mesh and its HTML
// report (docs/report.md). With `--schedule-feed V`, -o names the rewritten program instead
// (docs/engagement.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <utility>

#include "cli.hpp"
#include "verify_outputs.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/engagement/feed_schedule.hpp"
#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/engagement/engagement.hpp"

namespace tf::cli {
namespace {

struct VerifyArgs {
  std::string scene, program, out, blocks, stock_mesh, pairs, report, html, subroutine_path;
  double mesh_tolerance = 0.01;
  double schedule_mrr = 0.0;
  CLI::Option* schedule_option = nullptr;  // given (0 included, which is refused): feeds are scheduled
  CLI::Option* air_feed_option = nullptr;  // given: its value (0 included, which is refused)
  FeedScheduleOptions schedule;
  bool no_engagement = false;
  bool block_delete = false;
  EngagementOptions engagement;
  double resolution = 0.1;
  double tolerance = 0.01;
  double holder_tolerance = 0.05;
  double gouge_tolerance = 0.01;
  double collision_tolerance = 0.001;
  int mesh_refine = 0;
  bool stop_at_first = false;
  bool fail_on_collision = false;
};

void run_verify(const VerifyArgs& a) {
  check_outputs_apart({{"-o", a.out}, {"--blocks", a.blocks}, {"--stock-mesh", a.stock_mesh}, {"--engagement", a.pairs},
                       {"--report", a.report}, {"--html", a.html}},
                      {a.scene, a.program});
  if (!(a.resolution > 0.0)) throw InputError("", 0, "--resolution", "must be a positive number of mm");
  if (!(a.tolerance > 0.0)) throw InputError("", 0, "--tolerance", "must be a positive number of mm");
  if (!(a.holder_tolerance > 0.0)) throw InputError("", 0, "--holder-tolerance", "must be a positive number of mm");
  if (!(a.gouge_tolerance >= 0.0) || !std::isfinite(a.gouge_tolerance))
    throw InputError("", 0, "--gouge-tolerance", "must be a number of mm >= 0");
  if (!(a.collision_tolerance >= 0.0) || !std::isfinite(a.collision_tolerance))
    throw InputError("", 0, "--collision-tolerance", "must be a number of mm >= 0");
  if (!(a.engagement.angle_step_deg > 0.0 && a.engagement.angle_step_deg <= 45.0))
    throw InputError("", 0, "--engagement-angle-step", "must be a number of degrees in (0, 45]");
  if (!(a.engagement.axial_step_mm >= 0.0) || !std::isfinite(a.engagement.axial_step_mm))
    throw InputError("", 0, "--engagement-axial-step", "must be a number of mm >= 0 (0: automatic)");
  if (!(a.mesh_tolerance >= 0.0) || !std::isfinite(a.mesh_tolerance))
    throw InputError("", 0, "--mesh-tolerance", "must be a number of mm >= 0 (0: the full mesh)");
  // Every output name was checked while parsing (output_file()), so that a mistyped one costs no minutes
  // and leaves no other output behind.
  if (!a.stock_mesh.empty()) check_mesh_format(a.stock_mesh);
  const Scene scene = load_scene(a.scene);
  check_outputs_apart({{"-o", a.out}, {"--blocks", a.blocks}, {"--stock-mesh", a.stock_mesh}, {"--engagement", a.pairs},
                       {"--report", a.report}, {"--html", a.html}},
                      scene_inputs(scene, {a.program}));
  const MachineSpec machine = scene.machine.value_or(MachineSpec{});
  GcodeOptions gcode = gcode_options(scene);
  gcode.block_delete = a.block_delete;
  // LinuxCNC's SUBROUTINE_PATH: directories separated by ':', searched after the program's own.
  for (size_t from = 0; from < a.subroutine_path.size();) {
    const size_t to = std::min(a.subroutine_path.find(':', from), a.subroutine_path.size());
    const std::string dir = a.subroutine_path.substr(from, to - from);
    if (!dir.empty() && !std::filesystem::is_directory(dir))
      throw InputError("", 0, "--subroutine-path", "'" + dir + "' is not a directory");
    if (!dir.empty()) gcode.subroutine_dirs.push_back(dir);
    from = to + 1;
  }
  const Program program = read_gcode(a.program, machine, gcode);
  if (program.blocks.empty()) throw InputError(a.program, 0, "", "no motion blocks to verify (an empty program?)");
  VerifyOptions opt;
  opt.resolution = a.resolution;
  opt.sweep.tolerance = a.tolerance;
  opt.sweep.holder_tolerance = a.holder_tolerance;
  opt.gouge_tolerance = a.gouge_tolerance;
  opt.collision_tolerance = a.collision_tolerance;
  opt.stop_at_first_collision = a.stop_at_first;
  if (!a.no_engagement) {
    EngagementOptions eo = a.engagement;
    eo.keep_pairs = !a.pairs.empty();
    opt.engagement = engagement_probe(eo);
  }
  opt.progress = terminal_progress();
  opt.record_last_block = !a.html.empty();  // the report colours the stock by the block that cut it
  const bool scheduling = a.schedule_option && a.schedule_option->count() > 0;
  FeedScheduleOptions so = a.schedule;
  so.max_mrr = a.schedule_mrr;
  if (scheduling) {
    so.air_feed = scheduled_air_feed(*a.air_feed_option, so.air_feed, machine.max_feed, so.min_feed);
    check_feed_schedule_options(so, "--schedule-feed");  // before the long simulation
    if (a.stop_at_first) throw InputError("", 0, "--schedule-feed", "cannot be combined with --stop-at-first-collision");
  }
  VerifyResult result = verify_program(scene, program, scene_forward(scene), opt);
  // Every output is written to a temporary name and renamed; the mesh first (slowest), the report last.
  std::optional<StockOutput> stock;
  if (!a.stock_mesh.empty() || !a.html.empty()) {
    stock = stock_output(scene, result, {a.mesh_tolerance, a.mesh_refine, !a.html.empty()}, opt.progress);
    result.report.stock_mesh = stock->stats;
    if (!a.stock_mesh.empty()) write_mesh(stock->mesh, a.stock_mesh);
  }
  if (!a.blocks.empty()) write_blocks_csv(result.report, a.blocks);
  if (!a.pairs.empty()) write_engagement_csv(result.report, a.pairs);
  if (scheduling) {
    // -o is the rewritten program here (`verify --schedule-feed V -o PROGRAM2.ngc`; --report names the JSON).
    const FeedSchedule fs = schedule_feeds(program, result.report, so);
    const std::string text = read_text_file(a.program, "G-code file");
    if (!a.report.empty()) {
      // The report holds what the schedule could not do too (a block left above the limit), not stderr alone.
      std::vector<std::string>& warnings = result.report.warnings;
      const size_t own = warnings.size();
      for (const std::string& w : fs.warnings) warnings.push_back("feed schedule: " + w);
      write_verify_json(result.report, a.report);
      warnings.resize(own);  // the schedule prints its own below
    }
    write_file_atomic(a.out, [&](std::ostream& out) { out << rewrite_feeds(text, program, fs); });
    print_feed_schedule("verify", so, fs);
  } else {
    write_verify_json(result.report, a.out);
  }
  if (!a.html.empty())
    write_verify_report(scene, program, a.program, result.report, stock ? &*stock : nullptr, a.html, scheduling ? a.report : a.out);
  const VerifyReport& r = result.report;
  if (!global_options().quiet) {
    const std::string gouges = scene.design.n_faces() == 0
                                   ? "gouges not computed (no design)"
                                   : std::to_string(r.gouges.size()) + " gouges (max " + fixed(r.max_gouge_mm, 3) + " mm)";
    std::cerr << "verify: " << r.blocks << " blocks, removed " << fixed(r.removed_volume_mm3, r.removed_volume_mm3 >= 100.0 ? 1 : 4) << " mm3, "
              << r.collisions.size() << " collisions, " << gouges << ", " << fixed(r.seconds, 2) << " s\n";
    if (r.stock_mesh)
      std::cerr << "stock mesh: " << r.stock_mesh->vertices << " vertices, " << r.stock_mesh->faces << " faces, "
                << fixed(double(r.stock_mesh->bytes) / 1e6, 1) << " MB as PLY, "
                << (r.stock_mesh->max_error_mm > 0.0
                        ? "decimated within " + fixed(r.stock_mesh->max_error_mm, 4) + " mm of the full mesh (" +
                              std::to_string(r.stock_mesh->full_vertices) + " vertices)"
                        : std::string("the full mesh"))
                << "; " << fixed(r.stock_mesh->mesh_seconds, 1) << " s mesh, "
                << fixed(r.stock_mesh->decimate_seconds, 1) << " s decimation\n";
    for (const std::string& w : r.warnings) std::cerr << "warning: " << w << "\n";
  }
  if (a.fail_on_collision && !r.collisions.empty())
    throw JobError("verify: " + std::to_string(r.collisions.size()) + " collisions (first at line " +
                   std::to_string(r.collisions.front().line) + ")");
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("verify", "tri-dexel material-removal simulation of a G-code program on the scene's machine");
  static VerifyArgs args;  // CLI11 binds options to storage living as long as the app
  cmd->add_option("SCENE", args.scene, "scene JSON")->required();
  cmd->add_option("PROGRAM", args.program, "G-code program")->required();
  cmd->add_option("-o,--output", args.out, "verification report JSON (with --schedule-feed: the rewritten program)")->required()->check(output_file());
  cmd->add_option("--blocks", args.blocks, "per-block CSV")->check(output_file());
  cmd->add_option("--stock-mesh", args.stock_mesh, "stock mesh (PLY/STL/OBJ/OFF), coloured by deviation from the design")->check(output_file());
  cmd->add_option("--html", args.html, "HTML report: the stock in 3-D (by deviation, or by block/tool), collisions, plots")->check(output_file());
  cmd->add_option("--mesh-tolerance", args.mesh_tolerance,
                  "stock mesh (--stock-mesh, --html) decimated within this distance of the full dual-contoured mesh, mm; 0: the "
                  "full mesh (default 0.01)");
  cmd->add_option("--resolution", args.resolution, "dexel spacing, mm (default 0.1)");
  cmd->add_option("--tolerance", args.tolerance, "5-axis sub-step error bound of the cutting parts, mm (default 0.01)");
  cmd->add_option("--holder-tolerance", args.holder_tolerance,
                  "5-axis sub-step error bound of shank and holder (collision only), mm (default 0.05)");
  cmd->add_option("--gouge-tolerance", args.gouge_tolerance,
                  "over-cuts of the design deeper than this (and than the block's sweep bound) are gouges, mm (default 0.01)");
  cmd->add_option("--collision-tolerance", args.collision_tolerance,
                  "overlaps up to this deep are contact, not collision (shank, holder or a rapid in the stock, any part in "
                  "a check surface or fixture), mm (default 0.001)");
  cmd->add_option("--mesh-refine", args.mesh_refine, "split the stock mesh's triangles in four this many times (default 0)")
      ->check(CLI::Range(0, 4));
  cmd->add_option("--engagement", args.pairs, "every engagement entry/exit pair at every height (CSV)")->check(output_file());
  cmd->add_flag("--no-engagement", args.no_engagement, "skip the engagement measurement (angles, area, depths)");
  cmd->add_option("--engagement-angle-step", args.engagement.angle_step_deg,
                  "engagement samples around the tool axis this far apart, deg; an engaged arc narrower than it can be "
                  "missed (default 6)");
  cmd->add_option("--engagement-axial-step", args.engagement.axial_step_mm,
                  "engagement rings (the heights of --engagement's pairs) this far apart along the tool's profile, mm; "
                  "0: the arc between two angle samples at the tool's radius, at least the resolution (default 0)");
  args.schedule_option = cmd->add_option("--schedule-feed", args.schedule_mrr,
                  "rewrite F words so that no block removes more than this many mm3/min; -o is then the new program");
  // The schedule's own options without it had been taken and ignored (black-box testing).
  cmd->add_option("--min-feed", args.schedule.min_feed, "slowest feed the schedule writes, mm/min")
      ->capture_default_str()
      ->needs(args.schedule_option);
  args.air_feed_option = cmd->add_option("--air-feed", args.schedule.air_feed,
                                         "feed of blocks that cut nothing, mm/min (default: the machine's max_feed)")
                             ->needs(args.schedule_option);
  cmd->add_option("--report", args.report, "with --schedule-feed: also write the verification report JSON")
      ->check(output_file())
      ->needs(args.schedule_option);
  cmd->add_flag("--stop-at-first-collision", args.stop_at_first, "stop after the first block that collides");
  cmd->add_flag("--fail-on-collision", args.fail_on_collision, "exit 1 when any collision is found (outputs are written)");
  cmd->add_flag("--block-delete", args.block_delete,
               "skip the lines that start with '/' (the controller's block-delete switch on; by default they run, "
               "as LinuxCNC starts)");
  cmd->add_option("--subroutine-path", args.subroutine_path,
                  "directories (separated by ':') holding the files <name>.ngc of O<name> subroutines the program calls, "
                  "searched after the program's own directory (LinuxCNC's SUBROUTINE_PATH)");
  cmd->callback([] { run_verify(args); });
}

}  // namespace tf::cli
