// Planner throughput: cutter locations per second on a 100k-point impeller hub path with >= 1M check
// triangles, preprocessing (BVH, distance field) included. The point-by-point baseline runs on the same
// scene: 8 blades at a blade chordal tolerance of 0.002 mm (about 409k blade triangles), each triangle
// then split 1:4 at its edge midpoints (same geometry, 1.64M triangles: the generator's channel-width
// checks do not allow enough blades to get there otherwise with the default tool).
// BM_PlanDynamicWithFixture adds a clamp block (a 6 mm cube, 1.5 mm into the holder's side at the nominal
// axis, on the side nearer the blades) halfway along the path: the same plan, with fixtures as a second
// obstacle set, should cost at most about 10 % more.
// BM_PlanNarrowChannel: 9 blades leaning 30 deg, wrap 90, a radius-1 ball 0.3 mm from them, safety 0.1
// mm, the generator's default path (1 300 rows): the dynamics swing the axis and the corrections leave rows
// failing there, so the fall-back to the baseline's axes runs (0.6.14). BM_PlanWideHolder: the bundled
// impeller's tool on a coarse path (203 rows) with a holder of radius 25 at a gauge length of 30: its face
// lies over the blade tips, where every leaf was a cap contact for GJK before 0.6.14. BM_PlanBullEnd: the
// bundled impeller with a bull end (below).
// Options: TILTFIELD_BENCH_ROWS (default 100000), TILTFIELD_BENCH_TOLERANCE (hub, default 0.0005 mm),
// TILTFIELD_BENCH_BLADE_TOLERANCE (blades, default 0.002 mm), TILTFIELD_BENCH_REPEAT (default 1: plans
// this many times and reports the fastest, for a machine shared with other jobs; the rate counter then
// counts every run).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>

#include "scenes/scene_impeller.hpp"
#include "scenes/scene_writer.hpp"
#include "tiltfield/core/triangle_bvh.hpp"
#include "tiltfield/tilt/plan.hpp"

namespace {

struct BenchScene {
  tf::scenes::SceneBundle bundle;
  size_t triangles = 0;
  tf::Mesh clamp;
};

double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

// Every triangle split into four at its edge midpoints (shared midpoints are not welded: the planner
// reads a triangle soup).
tf::Mesh split_1_to_4(const tf::Mesh& m) {
  const tf::TriangleArrays a = tf::to_arrays(m);
  Eigen::MatrixX3d V(a.F.rows() * 6, 3);
  Eigen::MatrixX3i F(a.F.rows() * 4, 3);
  for (Eigen::Index f = 0; f < a.F.rows(); ++f) {
    const Eigen::RowVector3d p0 = a.V.row(a.F(f, 0)), p1 = a.V.row(a.F(f, 1)), p2 = a.V.row(a.F(f, 2));
    const int b = static_cast<int>(6 * f);
    V.row(b) = p0;
    V.row(b + 1) = p1;
    V.row(b + 2) = p2;
    V.row(b + 3) = 0.5 * (p0 + p1);
    V.row(b + 4) = 0.5 * (p1 + p2);
    V.row(b + 5) = 0.5 * (p2 + p0);
    F.row(4 * f) << b, b + 3, b + 5;
    F.row(4 * f + 1) << b + 3, b + 1, b + 4;
    F.row(4 * f + 2) << b + 5, b + 4, b + 2;
    F.row(4 * f + 3) << b + 3, b + 4, b + 5;
  }
  return tf::mesh_from_arrays(V, F);
}

tf::Mesh clamp_beside_holder(const tf::scenes::SceneBundle& b) {
  const auto& rows = b.path.rows;
  const size_t m = rows.size() / 2;
  const tf::Tool& t = b.tool;
  const Eigen::Vector3d n = rows[m].n, f = (rows[m + 1].p - rows[m - 1].p).normalized();
  const Eigen::Vector3d side = n.cross(f).normalized();
  const double h = t.length - t.cl_height() + 0.5 * t.holder[0].length, size = 6.0;
  std::vector<const tf::Mesh*> blades;
  for (const auto& c : b.check_surfaces) blades.push_back(&c.mesh);
  const tf::TriangleBvh bvh(blades);
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double nearest = std::numeric_limits<double>::infinity();
  for (double s : {-1.0, 1.0}) {
    const Eigen::Vector3d centre = rows[m].p + h * n + s * (t.holder[0].radius + 0.5 * size - 1.5) * side;
    const double d = bvh.closest(centre).distance;
    if (d < nearest) nearest = d, best = centre;
  }
  tf::Stock box;
  box.kind = tf::Stock::Kind::Box;
  box.box = {best - Eigen::Vector3d::Constant(0.5 * size), best + Eigen::Vector3d::Constant(0.5 * size)};
  return tf::stock_to_mesh(box);
}

const BenchScene& scene() {
  static std::unique_ptr<BenchScene> s;  // built once, outside the timed loops
  if (s) return *s;
  s = std::make_unique<BenchScene>();
  tf::scenes::ImpellerOptions o;
  // The blades are the check surfaces: their own chordal tolerance sets the triangle count (the hub, the
  // design surface, only carries the path).
  o.tolerance = env_or("TILTFIELD_BENCH_TOLERANCE", 0.0005);
  o.blade_tolerance = env_or("TILTFIELD_BENCH_BLADE_TOLERANCE", 0.002);
  o.blades = 8;
  o.ball_clearance = 1.2;
  // Enough passes and a fine step for the wanted number of rows: first a probe of the path length.
  const double want = env_or("TILTFIELD_BENCH_ROWS", 100000);
  tf::scenes::ImpellerOptions probe = o;
  probe.tolerance = 0.01;
  probe.passes = 100;
  probe.step = 0.5;
  const auto p = tf::scenes::make_impeller_scene(probe, tf::scenes::machine_json("table-table-ac", {}));
  const double per_row_at_half = static_cast<double>(p.path.rows.size());
  o.passes = 100;  // a 0.2 mm stepover: fewer passes would need a step too fine for the generator
  o.step = std::max(0.01, 0.5 * per_row_at_half / want);
  s->bundle = tf::scenes::make_impeller_scene(o, tf::scenes::machine_json("table-table-ac", {}));
  for (auto& c : s->bundle.check_surfaces) {
    c.mesh = split_1_to_4(c.mesh);
    s->triangles += c.mesh.n_faces();
  }
  s->clamp = clamp_beside_holder(s->bundle);
  return *s;
}

void run(benchmark::State& state, tf::PlanMethod method, size_t max_rows, bool fixture = false) {
  const BenchScene& s = scene();
  tf::ToolPath path = s.bundle.path;
  if (path.rows.size() > max_rows) path.rows.resize(max_rows);
  std::vector<const tf::Mesh*> meshes;
  for (const auto& c : s.bundle.check_surfaces) meshes.push_back(&c.mesh);
  tf::PlanOptions o = tf::derive_plan_options(s.bundle.tool, s.bundle.planner, s.bundle.feed);
  o.method = method;
  tf::PlanResult r;
  const int repeat = std::max(1, static_cast<int>(env_or("TILTFIELD_BENCH_REPEAT", 1)));
  for (auto _ : state) {
    for (int k = 0; k < repeat; ++k) {  // on a shared machine: keep the fastest of `repeat` plans
      tf::PlanObstacles obstacles{meshes, {}, {}};
      if (fixture) obstacles.fixtures.push_back(&s.clamp);
      tf::PlanResult x = tf::plan_path(path, s.bundle.tool, obstacles, s.bundle.planner, s.bundle.feed, o);
      if (k == 0 || x.metrics.seconds < r.metrics.seconds) r = std::move(x);
    }
    benchmark::DoNotOptimize(r);
  }
  state.counters["rows"] = static_cast<double>(path.rows.size());
  state.counters["check_triangles"] = static_cast<double>(s.triangles);
  state.counters["cl_points_per_s"] =
      benchmark::Counter(static_cast<double>(path.rows.size()) * repeat * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.counters["plan_seconds"] = r.metrics.seconds;
  state.counters["cl_points_per_plan_s"] = static_cast<double>(path.rows.size()) / r.metrics.seconds;
  state.counters["rows_nominal_colliding"] = static_cast<double>(r.metrics.rows_nominal_colliding);
  state.counters["rows_below_safety"] = static_cast<double>(r.metrics.rows_below_safety);
  state.counters["segments_below_safety"] = static_cast<double>(r.metrics.segments_below_safety);
  state.counters["corrected_rows"] = static_cast<double>(r.metrics.corrected_rows);
  state.counters["rms_second_difference"] = r.metrics.rms_second_difference;
  for (const auto& [name, sec] : r.metrics.stage_seconds) state.counters["s_" + name] = sec;
}

// A generated impeller planned as it is (for the scenes beside the throughput one).
void run_small(benchmark::State& state, const tf::scenes::SceneBundle& b, bool with_design = false) {
  std::vector<const tf::Mesh*> meshes, design;
  for (const auto& c : b.check_surfaces) meshes.push_back(&c.mesh);
  if (with_design) design.push_back(&b.design.mesh);
  const tf::PlanOptions o = tf::derive_plan_options(b.tool, b.planner, b.feed);
  tf::PlanResult r;
  for (auto _ : state) {
    r = tf::plan_path(b.path, b.tool, {meshes, {}, design}, b.planner, b.feed, o);
    benchmark::DoNotOptimize(r);
  }
  state.counters["rows"] = static_cast<double>(b.path.rows.size());
  state.counters["plan_seconds"] = r.metrics.seconds;
  state.counters["rows_below_safety"] = static_cast<double>(r.metrics.rows_below_safety);
  state.counters["segments_below_safety"] = static_cast<double>(r.metrics.segments_below_safety);
  state.counters["corrected_rows"] = static_cast<double>(r.metrics.corrected_rows);
  state.counters["max_step_deg"] = r.metrics.max_step_deg;
  state.counters["min_clearance_mm"] = r.metrics.min_clearance_mm;
  for (const auto& [name, sec] : r.metrics.stage_seconds) state.counters["s_" + name] = sec;
}

void BM_PlanNarrowChannel(benchmark::State& state) {
  tf::scenes::ImpellerOptions o;
  o.blades = 9;
  o.lean_deg = 30;
  o.wrap_deg = 90;
  o.tool_radius = 1.0;
  o.ball_clearance = 0.3;
  auto b = tf::scenes::make_impeller_scene(o, tf::scenes::machine_json("table-table-ac", {}));
  b.planner.safety_distance = 0.1;
  run_small(state, b);
}

void BM_PlanWideHolder(benchmark::State& state) {
  tf::scenes::ImpellerOptions o;
  o.passes = 3;
  o.step = 1.0;
  o.tolerance = 0.01;
  auto b = tf::scenes::make_impeller_scene(o, tf::scenes::machine_json("table-table-ac", {}));
  b.tool.length = 30.0;
  b.tool.holder = {{25.0, 40.0}};  // radius, length
  run_small(state, b);
}

// The bundled impeller's scene with a bull end R 3 r 1 on the same contacts (the path's points moved by
// R - r against the normal) and the hub as design: the exact rounded disc (0.6.22) and the end form.
void BM_PlanBullEnd(benchmark::State& state) {
  auto b = tf::scenes::make_impeller_scene(tf::scenes::ImpellerOptions{}, tf::scenes::machine_json("table-table-ac", {}));
  const double R = b.tool.radius(), r = 1.0;
  b.tool.cutter = tf::BullCutter{R, r};
  for (tf::CLPoint& p : b.path.rows) p.p -= (R - r) * p.contact_normal();
  run_small(state, b, true);
}

void BM_PlanDynamic(benchmark::State& state) { run(state, tf::PlanMethod::Dynamic, SIZE_MAX); }
void BM_PlanDynamicWithFixture(benchmark::State& state) { run(state, tf::PlanMethod::Dynamic, SIZE_MAX, true); }
// The baseline searches every colliding row independently, on the same path.
void BM_PlanPointwise(benchmark::State& state) { run(state, tf::PlanMethod::Pointwise, SIZE_MAX); }

BENCHMARK(BM_PlanDynamic)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_PlanDynamicWithFixture)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_PlanPointwise)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_PlanNarrowChannel)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_PlanWideHolder)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_PlanBullEnd)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
