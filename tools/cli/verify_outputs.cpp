// tiltfield verify: the compact stock mesh and the HTML report (see verify_outputs.hpp).
#include "verify_outputs.hpp"

#include <algorithm>
#include <chrono>

#include "report/report.hpp"
#include "tiltfield/core/mesh_simplify.hpp"
#include "tiltfield/dexel/stock_blocks.hpp"
#include "tiltfield/dexel/tridexel.hpp"

namespace tf::cli {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

StockOutput stock_output(const Scene& scene, const VerifyResult& verified, const StockMeshRequest& request,
                         const Progress& progress) {
  auto t = std::chrono::steady_clock::now();
  StockMeshOptions mo;
  mo.refine = request.refine;
  mo.progress = progress;
  // The full mesh is made in out.mesh itself (Mesh has no move: mesh.hpp; millions of vertices).
  StockOutput out{reconstruct_stock(verified.stock, scene.design.n_faces() ? &scene.design : nullptr, mo), {}, {}};
  const Mesh& full = out.mesh;
  out.stats.mesh_seconds = seconds_since(t);
  std::vector<uint32_t> full_block;
  if (request.blocks) {
    // The raw stock on the same lattice tells an uncut crossing from a cut one.
    const TriDexel raw = make_stock(scene.stock, verified.stock.lattice());
    full_block = stock_vertex_blocks(full, verified.stock, verified.last_block, &raw);
  }
  out.stats.full_vertices = full.n_vertices();
  out.stats.full_faces = full.n_faces();
  out.stats.max_error_mm = std::max(request.max_error_mm, 0.0);
  if (request.max_error_mm > 0.0) {
    t = std::chrono::steady_clock::now();
    BoundedDecimateOptions bo;
    bo.max_error_mm = request.max_error_mm;
    bo.progress = progress;
    BoundedDecimation compact = decimate_within(full, bo);
    out.stats.decimate_seconds = seconds_since(t);
    out.mesh = compact.mesh;  // a copy of the small mesh, and the full one freed
    if (!full_block.empty())
      for (const int v : compact.source_vertex) out.block.push_back(full_block[size_t(v)]);
  } else {  // the full mesh as it is
    out.block = std::move(full_block);
  }
  out.stats.vertices = out.mesh.n_vertices();
  out.stats.faces = out.mesh.n_faces();
  out.stats.bytes = ply_size(out.mesh);
  return out;
}

void write_verify_report(const Scene& scene, const Program& program, const std::filesystem::path& program_file,
                         const VerifyReport& report, const StockOutput* stock, const std::filesystem::path& html,
                         const std::filesystem::path& report_json) {
  using namespace reporting;
  ReportInputs in;
  in.scene = &scene;
  set_verification(in, program, report, stock ? &stock->mesh : nullptr, scene.design);
  if (stock) {
    in.stock_block = stock->block;
    in.stock_mesh = stock->stats;
  }
  in.summary.title = program_file.filename().string();
  // The footnotes had named verify.json whatever -o was (black-box testing); no JSON written: none named.
  in.report_json = report_json.filename().string();
  std::string note = "tiltfield verify of " + program_file.string() + " on its own (no plan: no oriented path)";
  if (scene.path.rows.empty()) note += "; the scene has no tool path";
  if (scene.design.n_faces() == 0) note += "; no design surface: no deviation colours, no gouge check";
  if (!report.warnings.empty())
    note += "; " + std::to_string(report.warnings.size()) + " warning" + (report.warnings.size() == 1 ? "" : "s") +
            " (listed in " + (in.report_json.empty() ? std::string("the verification report") : in.report_json) + ")";
  in.summary.note = note;
  in.summary.removed_volume_mm3 = report.removed_volume_mm3;
  in.summary.max_gouge_mm = scene.design.n_faces() > 0 ? report.max_gouge_mm : -1.0;
  in.summary.resolution_mm = report.resolution_mm;
  in.summary.stages = {{"verify", report.seconds}};
  if (stock) {
    in.summary.stages.push_back({"stock mesh", stock->stats.mesh_seconds});
    in.summary.stages.push_back({"decimate", stock->stats.decimate_seconds});
  }
  write_html_report(in, html);
}

}  // namespace tf::cli
