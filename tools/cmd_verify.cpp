#include "cli.hpp"

namespace tf::cli {

void add_verify_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("verify", "tri-dexel material-removal simulation of a G-code program on the scene's machine");
  static std::string scene, program, out, blocks, stock_mesh;
  static double resolution = 0.1;
  cmd->add_option("SCENE", scene, "scene JSON")->required();
  cmd->add_option("PROGRAM", program, "G-code program")->required();
  cmd->add_option("-o,--output", out, "verification report JSON")->required();
  cmd->add_option("--blocks", blocks, "per-block CSV");
  cmd->add_option("--stock-mesh", stock_mesh, "stock mesh (PLY/STL)");
  cmd->add_option("--resolution", resolution, "dexel spacing, mm");
  cmd->callback([] { not_yet_delivered("verify", 5); });
}

}  // namespace tf::cli
