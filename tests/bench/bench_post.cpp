// Posting speed: rows per second on a 100k-row 5-axis path (impeller-like: the axis leans 5 .. 88 deg
// off +Z and turns about Z several times), per machine type, joint dialect with the default
// tolerances; and the G-code writer alone.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "tiltfield/core/machine.hpp"
#include "tiltfield/post/post.hpp"

namespace {

constexpr double kDeg = M_PI / 180.0;

tf::OrientedPath long_path(int rows) {
  tf::OrientedPath path;
  path.rows.reserve(rows);
  // Row spacing about 0.1 mm: 100k rows over ~10 m of flank passes round a 40 mm hub.
  for (int i = 0; i < rows; ++i) {
    const double u = double(i) / double(rows - 1);
    const double phi = 360.0 * 40.0 * u;
    const double r = 40.0 + 8.0 * std::sin(2.0 * M_PI * 300.0 * u);
    tf::OrientedRow row;
    row.p = {r * std::cos(phi * kDeg), r * std::sin(phi * kDeg), 15.0 + 10.0 * std::sin(2.0 * M_PI * 120.0 * u)};
    const double tilt = (46.5 + 41.5 * std::sin(2.0 * M_PI * 60.0 * u)) * kDeg;
    const double az = (phi + 25.0 * std::sin(2.0 * M_PI * 400.0 * u)) * kDeg;
    row.axis = {std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt)};
    path.rows.push_back(row);
  }
  return path;
}

tf::PostJob job(tf::KinematicsType k) {
  tf::PostJob j;
  j.machine.kinematics = k;
  j.machine.pivot = {0, 0, 0};
  j.machine.tilt_offset = {0, 20, 10};
  j.machine.head_pivot_length = 150.0;
  j.tool.cutter = tf::BallCutter{3.0};
  j.tool.length = 60.0;
  j.feed = 1500.0;
  j.part_bounds = Eigen::AlignedBox3d(Eigen::Vector3d(-50, -50, 0), Eigen::Vector3d(50, 50, 25));
  return j;
}

const tf::OrientedPath& path100k() {
  static const tf::OrientedPath p = long_path(100000);
  return p;
}

void BM_Post(benchmark::State& state) {
  const auto k = static_cast<tf::KinematicsType>(state.range(0));
  const tf::PostJob j = job(k);
  const tf::OrientedPath& path = path100k();
  size_t blocks = 0;
  for (auto _ : state) {
    const tf::Program prog = tf::post_program(path, j, tf::PostOptions{});
    blocks = prog.blocks.size();
    benchmark::DoNotOptimize(blocks);
  }
  state.SetLabel(std::string(tf::to_string(k)));
  state.counters["rows_per_s"] = benchmark::Counter(double(path.rows.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["blocks"] = double(blocks);
}
BENCHMARK(BM_Post)
    ->Arg(int(tf::KinematicsType::TableTableAC))
    ->Arg(int(tf::KinematicsType::TableTableBC))
    ->Arg(int(tf::KinematicsType::HeadTableBC))
    ->Arg(int(tf::KinematicsType::HeadHeadAC))
    ->Unit(benchmark::kMillisecond);

void BM_PostAndWrite(benchmark::State& state) {
  const tf::PostJob j = job(tf::KinematicsType::TableTableAC);
  const tf::OrientedPath& path = path100k();
  for (auto _ : state) {
    std::ostringstream out;
    tf::write_gcode(out, tf::post_program(path, j, tf::PostOptions{}), j, tf::PostOptions{});
    benchmark::DoNotOptimize(out.str().size());
  }
  state.counters["rows_per_s"] = benchmark::Counter(double(path.rows.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_PostAndWrite)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
