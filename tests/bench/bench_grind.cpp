// Cross-section grinding simulation of the bundled 3-flute end mill (scenes/grinding/endmill.json) at
// 0.05 mm section spacing: sections per second of the machining step, the tiling step, and the total.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "integration/tridexel_bridge.hpp"
#include "tiltfield/grind/sections.hpp"

namespace {

namespace fs = std::filesystem;

const tf::grind::GrindScene& scene() {
  // The bench's own source path locates the scene (benchmarks get no source-dir definition).
  static const tf::grind::GrindScene s = tf::grind::load_grind_scene(
      fs::path(__FILE__).parent_path().parent_path().parent_path() / "scenes" / "grinding" / "endmill.json");
  return s;
}

tf::grind::SectionOptions options(double spacing) {
  tf::grind::SectionOptions o;
  o.spacing = spacing;
  return o;
}

void BM_SimulateSections(benchmark::State& state) {
  const double spacing = state.range(0) / 1000.0;
  size_t sections = 0;
  for (auto _ : state) {
    const auto stack = tf::grind::simulate_sections(scene(), options(spacing));
    sections = stack.sections.size();
    benchmark::DoNotOptimize(stack.sections.data());
  }
  state.counters["sections"] = static_cast<double>(sections);
  state.counters["sections_per_s"] = benchmark::Counter(static_cast<double>(sections * state.iterations()),
                                                        benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulateSections)->Arg(50)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_TileSections(benchmark::State& state) {
  const auto stack = tf::grind::simulate_sections(scene(), options(0.05));
  tf::grind::TilingOptions topt;
  topt.check_slabs = state.range(0) != 0;
  size_t faces = 0;
  for (auto _ : state) {
    const tf::Mesh mesh = tf::grind::tile_sections(stack, topt);
    faces = mesh.n_faces();
  }
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["slabs_per_s"] = benchmark::Counter(static_cast<double>((stack.sections.size() - 1) * state.iterations()),
                                                     benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TileSections)->Arg(1)->Arg(0)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_GrindTotal(benchmark::State& state) {
  size_t sections = 0;
  for (auto _ : state) {
    const auto stack = tf::grind::simulate_sections(scene(), options(0.05));
    const tf::Mesh mesh = tf::grind::tile_sections(stack);
    sections = stack.sections.size();
    benchmark::DoNotOptimize(mesh.n_faces());
  }
  state.counters["sections_per_s"] = benchmark::Counter(static_cast<double>(sections * state.iterations()),
                                                        benchmark::Counter::kIsRate);
}
BENCHMARK(BM_GrindTotal)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// The tri-dexel cross-check of the whole end-mill program (helical flutes included), with the wheel's corners
// made sharp in both simulators (the verifier's tools cannot round both edges of a disc). Reports both
// removed volumes and their relative difference in percent; slow (minutes), hence here and not in the tests.
void BM_TriDexelCrossCheck(benchmark::State& state) {
  tf::grind::GrindScene g = scene();
  g.wheel.edge_radius = 0.0;
  g.wheel.profile = tf::grind::make_wheel_profile(g.wheel.radius, g.wheel.thickness, 0.0);
  double sections = 0, dexels = 0;
  for (auto _ : state) {
    sections = tf::grind::testing::sections_removed(tf::grind::simulate_sections(g, options(0.05)));
    dexels = tf::grind::testing::tridexel_report(g, 0.1, 0.01).removed_volume_mm3;
  }
  state.counters["removed_sections_mm3"] = sections;
  state.counters["removed_tridexel_mm3"] = dexels;
  state.counters["diff_pct"] = 100.0 * (dexels - sections) / sections;
}
BENCHMARK(BM_TriDexelCrossCheck)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
