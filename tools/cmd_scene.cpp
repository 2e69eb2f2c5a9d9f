#include "cli.hpp"

namespace tf::cli {

void add_scene_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("scene", "writes a parametric scene (impeller, pocket, block)");
  cmd->require_subcommand(1);
  auto* imp = cmd->add_subcommand("impeller", "parametric impeller");
  static std::string dir;
  imp->add_option("-o,--output", dir, "output folder")->required();
  imp->callback([] { not_yet_delivered("scene impeller", 2); });
}

}  // namespace tf::cli
