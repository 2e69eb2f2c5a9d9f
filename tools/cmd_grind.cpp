#include "cli.hpp"

namespace tf::cli {

void add_grind_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("grind", "cross-section simulation of tool grinding");
  static std::string scene, out;
  cmd->add_option("GRIND", scene, "grinding scene JSON")->required();
  cmd->add_option("-o,--output", out, "tool mesh (PLY)")->required();
  cmd->callback([] { not_yet_delivered("grind", 8); });
}

}  // namespace tf::cli
