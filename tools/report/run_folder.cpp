// tiltfield report: the report's inputs from a program and from the files of a `tiltfield run` folder.
#include <cmath>

#include "report.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::reporting {

void set_verification(ReportInputs& in, const Program& program, const VerifyReport& report, const Mesh* stock,
                      const Mesh& design) {
  in.axes = block_axes(program);
  in.blocks.clear();
  for (const BlockResult& b : report.per_block) in.blocks.push_back(block_row(b));
  in.collisions = report.collisions;
  in.gouges = report.gouges;
  in.stock = stock;
  in.stock_deviation_mm.clear();
  if (!stock || design.n_faces() == 0) return;
  // The deviation the stock mesh was coloured by, when it carries it (reconstruct_stock's, from the same
  // design); else measured here.
  in.stock_deviation_mm = vertex_deviation(*stock);
  if (in.stock_deviation_mm.empty()) in.stock_deviation_mm = stock_deviation(*stock, design);
}

std::vector<BlockAxes> block_axes(const Program& program) {
  std::vector<BlockAxes> axes;
  axes.reserve(program.blocks.size());
  for (size_t i = 0; i < program.blocks.size(); ++i) {
    const Block& b = program.blocks[i];
    axes.push_back({int(i) + 1, b.line, b.target, b.motion == Motion::Rapid, b.tcp, b.tool});
  }
  return axes;
}

std::unique_ptr<RunFolder> load_run_folder(const Scene& scene, const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  auto run = std::make_unique<RunFolder>();
  ReportInputs& in = run->inputs;
  in.scene = &scene;
  if (fs::exists(dir / "oriented.csv")) {
    run->oriented = read_oriented_csv(dir / "oriented.csv");
    attach_path_normals(run->oriented, scene.path);  // the tips of a flat or bull end (Tool::contact_offset)
    in.oriented = &run->oriented;
  }
  if (fs::exists(dir / "program.ngc"))
    in.axes = block_axes(read_gcode(dir / "program.ngc", scene.machine.value_or(MachineSpec{})));
  if (fs::exists(dir / "verify.json")) {
    VerifyReport v = read_verify_json(dir / "verify.json");
    in.collisions = std::move(v.collisions);
    in.gouges = std::move(v.gouges);
    // Figures the file does not give are NaN: the page shows them as unknown.
    auto known = [](double x) { return std::isnan(x) ? -1.0 : x; };
    in.summary.removed_volume_mm3 = known(v.removed_volume_mm3);
    in.summary.max_gouge_mm = known(v.max_gouge_mm);
    in.summary.resolution_mm = known(v.resolution_mm);
    in.stock_mesh = v.stock_mesh;
  }
  if (fs::exists(dir / "blocks.csv")) in.blocks = read_blocks_csv(dir / "blocks.csv");
  if (fs::exists(dir / "stock.ply")) {
    run->stock = load_mesh(dir / "stock.ply");
    in.stock = &run->stock;
    if (scene.design.n_faces() > 0) in.stock_deviation_mm = stock_deviation(run->stock, scene.design);
  }
  return run;
}

}  // namespace tf::reporting
