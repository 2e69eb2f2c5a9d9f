// tiltfield post SCENE ORIENTED.csv -o PROGRAM.ngc: inverse kinematics, linearisation and G-code/APT output.
#include <cmath>
#include <iostream>
#include <sstream>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/engagement/feed_schedule.hpp"
#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/post/post.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::cli {
namespace {

struct PostArgs {
  std::string scene, oriented, out;
  std::string dialect, tcp_style, pole_mode = "interpolate";
  PostOptions options;
  FeedScheduleOptions schedule;  // max_mrr > 0: feeds scheduled on a verification of the posted program
  double resolution = 0.1;       // mm, of that verification
  double link_gap = 0.0;         // mm, taken only when --link-gap is given
  CLI::Option* link_gap_option = nullptr;
  CLI::Option* max_mrr_option = nullptr;  // given (0 included, which is refused): feeds are scheduled
  CLI::Option* air_feed_option = nullptr;  // given: its value (0 included, which is refused)
  bool scheduling() const { return max_mrr_option && max_mrr_option->count() > 0; }
};

void positive_option(double v, const char* name) {
  if (!(v > 0.0) || !std::isfinite(v)) throw InputError("", 0, name, "must be a positive number");
}

// --max-mrr: simulates the posted program, read back from its own text so that exactly what is written
// is measured, on the scene's stock, and rewrites its F words so that no block exceeds the MRR limit (air
// moves at the air feed, by default the machine's max_feed).
std::string schedule_posted_feeds(const PostArgs& a, const Scene& scene, const std::string& text) {
  FeedScheduleOptions so = a.schedule;
  so.air_feed = scheduled_air_feed(*a.air_feed_option, so.air_feed, scene.machine->max_feed, so.min_feed);
  check_feed_schedule_options(so);  // before the simulation
  positive_option(a.resolution, "--resolution");
  const Program program = parse_gcode(text, a.out, *scene.machine, gcode_options(scene));
  VerifyOptions vo;
  vo.resolution = a.resolution;
  // No engagement probe: only removed volumes are needed.
  vo.check_gouges = false;
  vo.progress = terminal_progress();
  const VerifyResult vr = verify_program(scene, program, scene_forward(scene), vo);
  const FeedSchedule fs = schedule_feeds(program, vr.report, so);
  print_feed_schedule("tiltfield post", so, fs);
  return rewrite_feeds(text, program, fs);
}

void run_post(PostArgs& a) {
  check_outputs_apart({{"-o", a.out}}, {a.scene, a.oriented});
  PostOptions& o = a.options;
  positive_option(o.tip_tolerance_mm, "--tip-tol");
  positive_option(o.axis_tolerance_deg, "--axis-tol");
  // The pole cone's half-angle is the axis error accepted there: a few degrees at most make sense.
  if (!(o.pole_tolerance_deg >= 0.0 && o.pole_tolerance_deg <= 10.0))
    throw InputError("", 0, "--pole-tol", "must be between 0 and 10 degrees (the axis error allowed at the pole)");
  positive_option(o.spindle_rpm, "--spindle");
  if (o.spindle_rpm < 1.0) throw InputError("", 0, "--spindle", "must be at least 1 rpm");
  // T0 M6 empties the spindle on LinuxCNC.
  if (o.tool_number < 1) throw InputError("", 0, "--tool-number", "must be a tool number of 1 or more");
  if (a.link_gap_option && a.link_gap_option->count() > 0) {
    if (!(a.link_gap > 0.0) || !std::isfinite(a.link_gap))
      throw InputError("", 0, "--link-gap", "must be a positive number of mm");
    o.link_gap_mm = a.link_gap;
  }
  if (!a.dialect.empty())
    o.dialect = a.dialect == "joint" ? Dialect::Joint : a.dialect == "tcp" ? Dialect::Tcp : Dialect::Apt;
  if (!a.tcp_style.empty()) o.tcp_style = a.tcp_style == "M128" ? TcpStyle::M128 : TcpStyle::G43_4;
  o.pole_mode = a.pole_mode == "hold" ? PoleMode::Hold : PoleMode::Interpolate;

  const Scene scene = load_scene(a.scene);
  if (!o.link_gap_mm) o.link_gap_mm = scene_link_gap(scene);
  check_outputs_apart({{"-o", a.out}}, scene_inputs(scene, {a.oriented}));
  if (!scene.machine) throw InputError(a.scene, 0, "machine", "the scene names no machine; posting needs one");
  OrientedPath path = read_oriented_csv(a.oriented);
  PostJob job;
  set_post_job(job, scene, o.tool_number);
  // A flat or bull end's cutter location follows its axis to keep the contact the path row says: it needs
  // the row's design normal, which the scene's path holds (Tool::contact_offset).
  if (!attach_path_normals(path, scene.path) && !std::holds_alternative<BallCutter>(job.tool.cutter) &&
      !global_options().quiet)
    std::cerr << "warning: the oriented rows are not the scene's path: their points are taken as the " << job.tool.type_name()
              << " end's cutter locations, whatever the axis\n";
  job.title = "tiltfield post: " + scene.file.filename().string() + ", " + std::filesystem::path(a.oriented).filename().string();

  const Dialect dialect = effective_dialect(o, job.machine);
  if (dialect == Dialect::Apt && a.scheduling())
    throw InputError("", 0, "--max-mrr", "feeds are scheduled on G-code; APT output has no machine program to simulate");
  if (dialect == Dialect::Apt) {
    write_file_atomic(a.out, [&](std::ostream& out) { write_apt(out, path, job, o); });
    return;
  }
  Program program;
  try {
    program = post_program(path, job, o, terminal_progress());
  } catch (const PostRowError& e) {
    // Name the row by its line in the CSV (comments and blank lines are skipped by the reader).
    const int line = e.row() < path.rows.size() ? path.rows[e.row()].source_line : 0;
    throw InputError(a.oriented, line, "", "row " + std::to_string(e.row() + 1) + ": " + e.what());
  }
  if (!global_options().quiet)
    for (const std::string& w : program.warnings) std::cerr << "tiltfield post: " << a.oriented << ": " << w << "\n";
  if (a.scheduling()) {
    std::ostringstream text;
    write_gcode(text, program, job, o);
    const std::string scheduled = schedule_posted_feeds(a, scene, text.str());
    write_file_atomic(a.out, [&](std::ostream& out) { out << scheduled; });
    return;
  }
  write_file_atomic(a.out, [&](std::ostream& out) { write_gcode(out, program, job, o); });
}

}  // namespace

void add_post_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("post", "inverse kinematics for the scene's machine and G-code output");
  static PostArgs a;  // CLI11 binds to storage that outlives parsing; one post per process
  cmd->add_option("SCENE", a.scene, "scene JSON")->required();
  cmd->add_option("ORIENTED", a.oriented, "oriented path CSV (ball centres and tool axes)")->required();
  cmd->add_option("-o,--output", a.out, "output program (.ngc, or APT CLDATA with --dialect apt)")->required()->check(output_file());
  cmd->add_option("--dialect", a.dialect, "joint (machine axes, G93), tcp (tool tip + rotaries) or apt; default: the machine's output")
      ->check(CLI::IsMember({"joint", "tcp", "apt"}));
  cmd->add_option("--tcp-style", a.tcp_style, "tool-centre-point code for --dialect tcp; default: the machine's tcp_style")
      ->check(CLI::IsMember({"G43.4", "M128"}));
  cmd->add_option("--tip-tol", a.options.tip_tolerance_mm, "largest tip deviation from the straight segment, mm")
      ->capture_default_str();
  cmd->add_option("--axis-tol", a.options.axis_tolerance_deg, "largest tool-axis deviation, deg")->capture_default_str();
  cmd->add_option("--pole-tol", a.options.pole_tolerance_deg,
                  "singular-pole cone: within it C is held or interpolated, deg")
      ->capture_default_str();
  cmd->add_option("--pole-mode", a.pole_mode, "C at the pole: interpolate or hold")
      ->check(CLI::IsMember({"interpolate", "hold"}))
      ->capture_default_str();
  cmd->add_option("--spindle", a.options.spindle_rpm, "spindle speed, rev/min")->capture_default_str();
  cmd->add_option("--tool-number", a.options.tool_number, "tool number (T and H words)")->capture_default_str();
  a.link_gap_option = cmd->add_option("--link-gap", a.link_gap,
                                      "rows farther apart are linked (retract, rapid, approach), not cut through, mm; "
                                      "default: 4 x the tool radius");
  a.max_mrr_option = cmd->add_option("--max-mrr", a.schedule.max_mrr,
                  "simulate the program and lower feeds so that no block removes more than this many mm3/min");
  // The schedule's own options without it had been taken and ignored (black-box testing).
  cmd->add_option("--min-feed", a.schedule.min_feed, "with --max-mrr: slowest feed written, mm/min")
      ->capture_default_str()
      ->needs(a.max_mrr_option);
  a.air_feed_option = cmd->add_option("--air-feed", a.schedule.air_feed,
                                      "with --max-mrr: feed of blocks that cut nothing (default: the machine's max_feed)")
                          ->needs(a.max_mrr_option);
  cmd->add_option("--resolution", a.resolution, "with --max-mrr: dexel spacing of the simulation, mm")
      ->capture_default_str()
      ->needs(a.max_mrr_option);
  cmd->callback([] { run_post(a); });
}

}  // namespace tf::cli
