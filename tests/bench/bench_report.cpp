// Report speed and size on the bundled impeller (hub + blades ~200k triangles, the machined stock from
// the verifier): the whole job runs once (tiltfield run's run_job, dexel spacing 0.25 mm unless
// TILTFIELD_BENCH_RESOLUTION says otherwise) into build/report_impeller/, then the benchmark times
// render_html_report on those files, and writes build/report_impeller/report.html (the docs' screenshot
// is taken from it with tests/report/check_report.mjs).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/job.hpp"
#include "report/report.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/scene.hpp"

namespace {

namespace fs = std::filesystem;

struct Impeller {
  tf::Scene scene;
  std::unique_ptr<tf::reporting::RunFolder> run;
  std::string error;
};

const Impeller& impeller() {
  static const Impeller data = [] {
    Impeller d;
    const fs::path scene_file = fs::path(TILTFIELD_BINARY_DIR) / "scenes" / "impeller" / "scene.json";
    const fs::path dir = fs::path(TILTFIELD_BINARY_DIR) / "report_impeller";
    try {
      d.scene = tf::load_scene(scene_file);
      // TILTFIELD_BENCH_REUSE=1 keeps a previous run's folder (the job takes minutes) and its numbers.
      const bool reuse = std::getenv("TILTFIELD_BENCH_REUSE") && fs::exists(dir / "job_summary.json");
      nlohmann::json js;
      if (reuse) {
        js = nlohmann::json::parse(std::ifstream(dir / "job_summary.json"));
      } else {
        tf::JobOptions options;
        options.out_dir = dir;
        const char* res = std::getenv("TILTFIELD_BENCH_RESOLUTION");
        options.resolution_mm = res ? std::atof(res) : 0.25;
        const tf::JobSummary s = tf::run_job(d.scene, options);
        js = {{"resolution_mm", options.resolution_mm}, {"collisions_first", s.collisions_first},
              {"collisions_final", s.collisions_final}, {"min_clearance_mm", s.min_clearance_mm},
              {"rounds", s.rounds}, {"rows_replanned", s.rows_replanned},
              {"seconds", {s.seconds.plan, s.seconds.post, s.seconds.verify, s.seconds.replan}}};
        tf::write_file_atomic(dir / "job_summary.json", [&](std::ostream& out) { out << js.dump(2); });
      }
      d.run = tf::reporting::load_run_folder(d.scene, dir);
      auto& sum = d.run->inputs.summary;
      sum.title = "Impeller (bundled scene)";
      sum.collisions_found = js["collisions_first"].get<int>();
      sum.collisions_fixed = js["collisions_first"].get<int>() - js["collisions_final"].get<int>();
      sum.min_clearance_mm = js["min_clearance_mm"].get<double>();
      const auto sec = js["seconds"].get<std::vector<double>>();
      sum.stages = {{"plan", sec[0]}, {"post", sec[1]}, {"verify", sec[2]}, {"replan", sec[3]}};
      sum.note = "tiltfield run, dexel spacing " + tf::fixed(js["resolution_mm"].get<double>(), 3) + " mm; " +
                 std::to_string(js["rounds"].get<int>()) + " re-plan round(s), " +
                 std::to_string(js["rows_replanned"].get<int>()) + " rows re-planned.";
    } catch (const std::exception& e) {
      d.error = e.what();
    }
    return d;
  }();
  return data;
}

void BM_ReportImpeller(benchmark::State& state) {
  const Impeller& d = impeller();
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  size_t bytes = 0;
  for (auto _ : state) {
    const std::string html = tf::reporting::render_html_report(d.run->inputs);
    bytes = html.size();
    benchmark::DoNotOptimize(html.data());
  }
  tf::reporting::write_html_report(d.run->inputs, fs::path(TILTFIELD_BINARY_DIR) / "report_impeller" / "report.html");
  state.counters["html_MB"] = double(bytes) / 1048576.0;
  state.counters["stock_triangles"] = double(d.run->stock.n_faces());
}
BENCHMARK(BM_ReportImpeller)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
