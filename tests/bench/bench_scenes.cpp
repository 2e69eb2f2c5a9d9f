// Generation time of the parametric scenes (library calls, no file output).
#include <benchmark/benchmark.h>

#include "scenes/scene_block.hpp"
#include "scenes/scene_impeller.hpp"
#include "scenes/scene_pocket.hpp"

namespace sc = tf::scenes;

static void BM_ImpellerScene(benchmark::State& state) {
  sc::ImpellerOptions o;
  o.blades = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(sc::make_impeller_scene(o, sc::builtin_machine("table-table-ac")));
}
BENCHMARK(BM_ImpellerScene)->Arg(7)->Unit(benchmark::kMillisecond);

static void BM_ImpellerHubMesh(benchmark::State& state) {
  const sc::ImpellerModel model{sc::ImpellerOptions{}};
  for (auto _ : state) benchmark::DoNotOptimize(sc::impeller_hub_mesh(model));
}
BENCHMARK(BM_ImpellerHubMesh)->Unit(benchmark::kMillisecond);

static void BM_ImpellerBladesMesh(benchmark::State& state) {
  const sc::ImpellerModel model{sc::ImpellerOptions{}};
  for (auto _ : state) benchmark::DoNotOptimize(sc::impeller_blades_mesh(model));
}
BENCHMARK(BM_ImpellerBladesMesh)->Unit(benchmark::kMillisecond);

static void BM_ImpellerPath(benchmark::State& state) {
  const sc::ImpellerModel model{sc::ImpellerOptions{}};
  const tf::Mesh blades = sc::impeller_blades_mesh(model);
  for (auto _ : state) benchmark::DoNotOptimize(sc::impeller_path(model, blades));
}
BENCHMARK(BM_ImpellerPath)->Unit(benchmark::kMillisecond);

static void BM_PocketScene(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(sc::make_pocket_scene({}, sc::builtin_machine("table-table-bc")));
}
BENCHMARK(BM_PocketScene)->Unit(benchmark::kMillisecond);

static void BM_BlockScene(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(sc::make_block_scene({}, sc::builtin_machine("xyz")));
}
BENCHMARK(BM_BlockScene)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
