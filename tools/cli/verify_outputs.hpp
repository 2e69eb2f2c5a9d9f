// tiltfield verify: the stock mesh (compact, within a bound of the dexel surface) and the HTML report of
// a verified program (cmd_verify.cpp writes them).
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/progress.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::cli {

struct StockMeshRequest {
  double max_error_mm = 0.01;  // --mesh-tolerance: the decimation bound, 0 for the full mesh
  int refine = 0;              // --mesh-refine
  bool blocks = false;         // name the block that last cut each vertex (needs VerifyResult::last_block)
};

struct StockOutput {
  Mesh mesh;                    // the compact mesh, coloured by deviation when the scene has a design
  std::vector<uint32_t> block;  // per vertex: the block that last cut there, 0 raw stock (when asked)
  StockMeshStats stats;
};

// The stock after the program as a mesh: dual contouring of the tri-dexel (stage "mesh"), then
// decimation within the bound (stage "decimate"). In: the scene (stock, design), the verification with
// its stock (and last blocks when `request.blocks`). Units mm, seconds.
StockOutput stock_output(const Scene& scene, const VerifyResult& verified, const StockMeshRequest& request,
                         const Progress& progress);

// The HTML report (tools/report) of a program verified on its own: no plan, so no oriented path; the
// scene's path and design when it has them. `stock` may be null (no stock mesh). Written atomically.
void write_verify_report(const Scene& scene, const Program& program, const std::filesystem::path& program_file,
                         const VerifyReport& report, const StockOutput* stock, const std::filesystem::path& html,
                         const std::filesystem::path& report_json);

}  // namespace tf::cli
