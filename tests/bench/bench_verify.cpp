// Verifier throughput: moves per second and peak memory.
//  (a) a 3-axis freeform finishing raster of >= 500k moves on a 100 x 100 x 50 mm block at 0.05 mm
//      (BM_FreeformFinishing/500/x: 500 lines x 1000 moves; /5 and /50 are quick fractions of it), with
//      and without the engagement measurement;
//  (b) the bundled impeller, planned and posted in process, at 0.05 mm; at 0.1 mm with and without the
//      engagement measurement (its cost);
//  (c) LinuxCNC's own simultaneous 5-axis demo impeller-7bl-xyzac.ngc (4492 blocks, TCP, G93) on the
//      scene tests/data/linuxcnc/impeller-7bl.json, at 0.05 and 0.1 mm, default options, with and
//      without engagement; its sweep error bounds as counters.
//  (d) arcs: a ring pocket as G3 arcs (swept exactly) and as 0.5 mm chords, time per mm of path;
//  (e) the compact stock mesh: decimating the demo's stock within 0.01 mm.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <memory>
#include <sstream>
#include <string>

#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tiltfield/post/post.hpp"
#include "tiltfield/core/mesh_simplify.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/engagement/engagement.hpp"

namespace {

double peak_rss_mb() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

// z of the freeform surface the ball tip follows: finishing depth, 0.5 to 2.5 mm below the block's top.
double surface(double x, double y) { return 48.5 + 1.0 * std::sin(x / 10.0) * std::cos(y / 15.0); }

// The first `run` of `lines` raster lines (all when run = 0), 1000 moves each.
tf::Program raster(int lines, int moves_per_line, int run = 0) {
  tf::Program p;
  const double stepover = 100.0 / lines, step = 100.0 / moves_per_line;
  auto add = [&](tf::Motion m, double x, double y, double z) {
    tf::Block b;
    b.motion = m;
    b.line = static_cast<int>(p.blocks.size()) + 1;
    b.target = {x, y, z};
    b.feed = 3000;
    p.blocks.push_back(b);
  };
  p.start = {0, 0.5 * 100.0 / lines, surface(0, 0.5 * 100.0 / lines)};
  for (int l = 0; l < (run > 0 ? std::min(run, lines) : lines); ++l) {
    const double y = (l + 0.5) * stepover;
    const bool forward = l % 2 == 0;
    const double x0 = forward ? 0.0 : 100.0;
    add(tf::Motion::Linear, x0, y, surface(x0, y));
    for (int i = 1; i <= moves_per_line; ++i) {
      const double x = forward ? i * step : 100.0 - i * step;
      add(tf::Motion::Linear, x, y, surface(x, y));
    }
  }
  return p;
}

void BM_FreeformFinishing(benchmark::State& state) {
  tf::Scene scene;
  scene.stock.kind = tf::Stock::Kind::Box;
  scene.stock.box = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 100, 50)};
  scene.tool.cutter = tf::BallCutter{3};
  scene.tool.flute_length = 15;
  scene.tool.shank_radius = 3;
  scene.tool.length = 60;
  scene.tool.holder = {{12, 40}};
  const tf::Program program = raster(static_cast<int>(state.range(0)), 1000, static_cast<int>(state.range(2)));
  tf::VerifyOptions opt;
  opt.resolution = 0.05;
  if (state.range(1) != 0) opt.engagement = tf::engagement_probe();
  opt.check_gouges = false;
  double seconds = 0.0;
  size_t rays = 0;
  double engagement = 0.0;
  for (auto _ : state) {
    const tf::VerifyResult r = tf::verify_program(scene, program, tf::forward_xyz, opt);
    seconds = r.report.seconds;
    engagement = r.report.engagement_seconds;
    rays = r.report.rays;
    benchmark::DoNotOptimize(r.report.removed_volume_mm3);
  }
  state.counters["moves"] = static_cast<double>(program.blocks.size());
  state.counters["moves_per_s"] = program.blocks.size() / std::max(seconds, 1e-9);
  state.counters["sim_seconds"] = seconds;
  state.counters["rays"] = static_cast<double>(rays);
  state.counters["engagement_pct"] = 100.0 * engagement / std::max(seconds - engagement, 1e-9);
  state.counters["peak_MB"] = peak_rss_mb();
}
// Arguments: raster lines (1000 moves each), engagement off (0) or on (1), lines run (0: all). /500/0/30
// is a quick sample of the full program's steady state (stepover 0.2 mm).
BENCHMARK(BM_FreeformFinishing)
    ->Args({5, 0, 0})
    ->Args({5, 1, 0})
    ->Args({50, 0, 0})
    ->Args({500, 0, 30})
    ->Args({500, 1, 30})
    ->Args({500, 0, 0})
    ->Args({500, 1, 0})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

// (d) Arcs: a pocket of 19 concentric rings (radius 6 to 42 mm, 2 mm apart) 2 mm deep in a 100 x 100 x 20
// block, ball R 3 at 0.05 mm; each ring as four G3 quarter arcs (argument 0: swept exactly along the arc),
// or as chords of about 0.5 mm (1: lines, the same path within 0.003 mm). Time per mm of path is what to
// compare: an arc should cost what a line does.
void BM_ArcPocket(benchmark::State& state) {
  tf::Scene scene;
  scene.stock.kind = tf::Stock::Kind::Box;
  scene.stock.box = {Eigen::Vector3d(-50, -50, 0), Eigen::Vector3d(50, 50, 20)};
  scene.tool.cutter = tf::BallCutter{3};
  scene.tool.flute_length = 15;
  scene.tool.shank_radius = 3;
  scene.tool.length = 60;
  scene.tool.holder = {{12, 40}};
  const bool chords = state.range(0) != 0;
  tf::Program p;
  const double z = 18.0;  // the tip 2 mm below the top
  p.start = {6, 0, 30};
  auto add = [&](tf::Motion m, double x, double y) {
    tf::Block b;
    b.motion = m;
    b.line = static_cast<int>(p.blocks.size()) + 1;
    b.target = {x, y, z};
    b.feed = 2000;
    b.arc_center = {0, 0, z};
    p.blocks.push_back(b);
  };
  double path = 0.0;
  for (double rho = 6; rho <= 42 + 1e-9; rho += 2) {
    add(tf::Motion::Linear, rho, 0);
    const int n = chords ? std::max(4, static_cast<int>(std::ceil(2 * std::numbers::pi * rho / 0.5 / 4)) * 4) : 4;
    for (int i = 1; i <= n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      add(chords ? tf::Motion::Linear : tf::Motion::ArcCCW, rho * std::cos(a), rho * std::sin(a));
    }
    path += 2 * std::numbers::pi * rho;
  }
  tf::VerifyOptions opt;
  opt.resolution = 0.05;
  opt.check_gouges = false;
  double seconds = 0.0, removed = 0.0, err = 0.0;
  for (auto _ : state) {
    const tf::VerifyResult r = tf::verify_program(scene, p, tf::forward_xyz, opt);
    seconds = r.report.seconds;
    removed = r.report.removed_volume_mm3;
    err = r.report.sweep_error_mm;
  }
  state.counters["moves"] = static_cast<double>(p.blocks.size());
  state.counters["sim_seconds"] = seconds;
  state.counters["ms_per_100mm"] = 1e5 * seconds / path;
  state.counters["removed_mm3"] = removed;
  state.counters["sweep_error_um"] = 1000.0 * err;
}
BENCHMARK(BM_ArcPocket)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond);

// The bundled impeller, planned and posted in process (the same steps as `tiltfield run`), read back
// from its G-code text.
struct ImpellerJob {
  tf::Scene scene;
  tf::Program program;
};

const ImpellerJob* impeller_job() {
  static const std::unique_ptr<ImpellerJob> job = []() -> std::unique_ptr<ImpellerJob> {
    const std::filesystem::path file = std::filesystem::path(TILTFIELD_BINARY_DIR) / "scenes" / "impeller" / "scene.json";
    if (!std::filesystem::exists(file)) return nullptr;
    auto j = std::make_unique<ImpellerJob>();
    j->scene = tf::load_scene(file);
    const tf::PlanResult planned = tf::plan(
        j->scene, tf::parse_plan_options(j->scene.planner_json, file.string(), j->scene.tool, j->scene.planner, j->scene.feed));
    tf::PostJob post;
    post.machine = *j->scene.machine;
    post.tool = j->scene.tool;
    post.feed = j->scene.feed;
    post.part_bounds = tf::scene_bounds(j->scene);
    const tf::PostOptions po;
    std::ostringstream text;
    tf::write_gcode(text, tf::post_program(planned.path, post, po), post, po);
    j->program = tf::parse_gcode(text.str(), "impeller.ngc", post.machine);
    return j;
  }();
  return job.get();
}

// Arguments: resolution in 1/100 mm, engagement on (1) or off (0).
void BM_Impeller(benchmark::State& state) {
  const ImpellerJob* job = impeller_job();
  if (!job) {
    state.SkipWithError("build/scenes/impeller/scene.json is missing (the build generates it)");
    return;
  }
  tf::VerifyOptions opt;
  opt.resolution = state.range(0) / 100.0;
  if (state.range(1) != 0) opt.engagement = tf::engagement_probe();
  double seconds = 0.0, balance = 0.0, engagement = 0.0;
  size_t collisions = 0, engaged = 0;
  for (auto _ : state) {
    const tf::VerifyResult r = tf::verify_program(job->scene, job->program, tf::scene_forward(job->scene), opt);
    seconds = r.report.seconds;
    engagement = r.report.engagement_seconds;
    collisions = r.report.collisions.size();
    engaged = 0;
    for (const tf::BlockResult& b : r.report.per_block) engaged += b.engagement.engaged();
    // Removed volume summed over blocks against the stock before minus after, percent.
    const double gone = r.report.stock_volume_start_mm3 - r.report.stock_volume_end_mm3;
    balance = 100.0 * (r.report.removed_volume_mm3 - gone) / std::max(gone, 1e-9);
  }
  state.counters["moves"] = static_cast<double>(job->program.blocks.size());
  state.counters["moves_per_s"] = job->program.blocks.size() / std::max(seconds, 1e-9);
  state.counters["sim_seconds"] = seconds;
  state.counters["collisions"] = static_cast<double>(collisions);
  state.counters["engaged_blocks"] = static_cast<double>(engaged);
  // The engagement's share of the simulation, measured inside it (goal: at most 30 %).
  state.counters["engagement_pct"] = 100.0 * engagement / std::max(seconds - engagement, 1e-9);
  state.counters["volume_balance_pct"] = balance;
  state.counters["peak_MB"] = peak_rss_mb();
}
// Engagement cost: /10/0 against /10/1. /5/1: the impeller at 0.05 mm.
BENCHMARK(BM_Impeller)->Args({10, 0})->Args({10, 1})->Args({5, 1})->Iterations(1)->Unit(benchmark::kSecond);

constexpr const char* kLinuxcncDemo =
    "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/vismach/5axis/table-rotary-tilting/demos/"
    "impeller-7bl-xyzac.ngc";

// The scene made for LinuxCNC's demo.
std::filesystem::path linuxcnc_demo_scene() {
  return std::filesystem::path(TILTFIELD_SOURCE_DIR) / "tests" / "data" / "linuxcnc" / "impeller-7bl.json";
}

// False, and the benchmark skipped, when the demo is not installed.
bool have_linuxcnc_demo(benchmark::State& state) {
  if (std::filesystem::exists(kLinuxcncDemo)) return true;
  state.SkipWithError("LinuxCNC's demo is missing (Debian package linuxcnc-uspace)");
  return false;
}

// Arguments: resolution in 1/100 mm, engagement on (1) or off (0). Whole verify as the command runs it:
// scene and program read, stock built, simulated (wall_seconds); sim_seconds is the block loop.
void BM_LinuxcncImpeller(benchmark::State& state) {
  const std::filesystem::path scene_file = linuxcnc_demo_scene();
  if (!have_linuxcnc_demo(state)) return;
  tf::VerifyOptions opt;
  opt.resolution = state.range(0) / 100.0;
  double seconds = 0.0, wall = 0.0, engagement = 0.0, removed = 0.0, err = 0.0, holder_err = 0.0;
  size_t collisions = 0, blocks = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const tf::Scene scene = tf::load_scene(scene_file);
    const tf::Program program = tf::read_gcode(kLinuxcncDemo, *scene.machine);
    if (state.range(1) != 0) opt.engagement = tf::engagement_probe();
    const tf::VerifyResult r = tf::verify_program(scene, program, tf::scene_forward(scene), opt);
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    seconds = r.report.seconds;
    engagement = r.report.engagement_seconds;
    removed = r.report.removed_volume_mm3;
    err = r.report.sweep_error_mm;
    holder_err = r.report.holder_sweep_error_mm;
    collisions = r.report.collisions.size();
    blocks = program.blocks.size();
  }
  state.counters["moves"] = static_cast<double>(blocks);
  state.counters["wall_seconds"] = wall;
  state.counters["sim_seconds"] = seconds;
  state.counters["engagement_pct"] = 100.0 * engagement / std::max(seconds - engagement, 1e-9);
  state.counters["removed_mm3"] = removed;
  state.counters["sweep_error_um"] = 1000.0 * err;
  state.counters["holder_error_um"] = 1000.0 * holder_err;
  state.counters["collisions"] = static_cast<double>(collisions);
  state.counters["peak_MB"] = peak_rss_mb();
}
BENCHMARK(BM_LinuxcncImpeller)->Args({5, 1})->Args({5, 0})->Args({10, 1})->Iterations(1)->Unit(benchmark::kSecond);

// (e) The compact stock mesh of verify --stock-mesh / --html: LinuxCNC's demo simulated at the argument's
// spacing (1/100 mm; not timed), its full dual-contoured stock mesh, then decimate_within at the default
// bound of 0.01 mm (timed). Counters: the full and compact vertex counts.
// LinuxCNC's demo simulated at `resolution` mm with default options (the stock meshes' input).
tf::VerifyResult simulate_linuxcnc_demo(double resolution) {
  const tf::Scene scene = tf::load_scene(linuxcnc_demo_scene());
  tf::VerifyOptions opt;
  opt.resolution = resolution;
  return tf::verify_program(scene, tf::read_gcode(kLinuxcncDemo, *scene.machine), tf::scene_forward(scene), opt);
}

void BM_StockMeshDecimate(benchmark::State& state) {
  if (!have_linuxcnc_demo(state)) return;
  const tf::VerifyResult r = simulate_linuxcnc_demo(state.range(0) / 100.0);
  const tf::Mesh full = tf::reconstruct_stock(r.stock, nullptr);
  size_t vertices = 0;
  for (auto _ : state) {
    const tf::BoundedDecimation compact = tf::decimate_within(full);
    vertices = compact.mesh.n_vertices();
  }
  state.counters["full_vertices"] = static_cast<double>(full.n_vertices());
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["peak_MB"] = peak_rss_mb();
}
BENCHMARK(BM_StockMeshDecimate)->Arg(20)->Arg(10)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

// (f) The full stock mesh itself (reconstruct_stock: the surface nets in chunks of layers on the threads,
// the vertices' fits, no colours): LinuxCNC's demo simulated at the argument's spacing (1/100 mm; not
// timed). Counters: vertices and faces.
void BM_StockMeshReconstruct(benchmark::State& state) {
  if (!have_linuxcnc_demo(state)) return;
  const tf::VerifyResult r = simulate_linuxcnc_demo(state.range(0) / 100.0);
  size_t vertices = 0, faces = 0;
  for (auto _ : state) {
    const tf::Mesh full = tf::reconstruct_stock(r.stock, nullptr);
    vertices = full.n_vertices();
    faces = full.n_faces();
  }
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["peak_MB"] = peak_rss_mb();
}
BENCHMARK(BM_StockMeshReconstruct)->Arg(10)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
