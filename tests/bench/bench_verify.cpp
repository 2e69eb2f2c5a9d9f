// Verifier throughput: moves per second and peak memory.
//  (a) a 3-axis freeform finishing raster of >= 500k moves on a 100 x 100 x 50 mm block at 0.05 mm
//      (BM_FreeformFinishing/500: 500 lines x 1000 moves; /50 is a quick tenth of it);
//  (b) the bundled impeller's posted program at 0.05 mm, when build/scenes/impeller/program.ngc exists
//      (`tiltfield run` or plan + post write it; skipped otherwise).
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tiltfield/gcode.hpp"
#include "tiltfield/scene.hpp"
#include "tiltfield/verify.hpp"

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

tf::Program raster(int lines, int moves_per_line) {
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
  for (int l = 0; l < lines; ++l) {
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
  const tf::Program program = raster(static_cast<int>(state.range(0)), 1000);
  tf::VerifyOptions opt;
  opt.resolution = 0.05;
  opt.check_gouges = false;
  double seconds = 0.0;
  size_t rays = 0;
  for (auto _ : state) {
    const tf::VerifyResult r = tf::verify_program(scene, program, tf::forward_xyz, opt);
    seconds = r.report.seconds;
    rays = r.report.rays;
    benchmark::DoNotOptimize(r.report.removed_volume_mm3);
  }
  state.counters["moves"] = static_cast<double>(program.blocks.size());
  state.counters["moves_per_s"] = program.blocks.size() / std::max(seconds, 1e-9);
  state.counters["sim_seconds"] = seconds;
  state.counters["rays"] = static_cast<double>(rays);
  state.counters["peak_MB"] = peak_rss_mb();
}
BENCHMARK(BM_FreeformFinishing)->Arg(1)->Arg(5)->Arg(50)->Arg(500)->Iterations(1)->Unit(benchmark::kSecond);

void BM_Impeller(benchmark::State& state) {
  const std::filesystem::path dir = std::filesystem::path(TILTFIELD_BINARY_DIR) / "scenes" / "impeller";
  const std::filesystem::path program_file = dir / "program.ngc";
  if (!std::filesystem::exists(program_file) || !std::filesystem::exists(dir / "scene.json")) {
    state.SkipWithError("no posted impeller program (run `tiltfield run` into build/scenes/impeller first)");
    return;
  }
  const tf::Scene scene = tf::load_scene(dir / "scene.json");
  const tf::Program program = tf::read_gcode(program_file, scene.machine.value_or(tf::MachineSpec{}));
  tf::VerifyOptions opt;
  opt.resolution = 0.05;
  double seconds = 0.0;
  size_t collisions = 0;
  for (auto _ : state) {
    const tf::VerifyResult r = tf::verify_program(scene, program, tf::scene_forward(scene), opt);
    seconds = r.report.seconds;
    collisions = r.report.collisions.size();
  }
  state.counters["moves"] = static_cast<double>(program.blocks.size());
  state.counters["moves_per_s"] = program.blocks.size() / std::max(seconds, 1e-9);
  state.counters["collisions"] = static_cast<double>(collisions);
  state.counters["peak_MB"] = peak_rss_mb();
}
BENCHMARK(BM_Impeller)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
