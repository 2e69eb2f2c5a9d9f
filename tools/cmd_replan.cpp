#include "cli.hpp"

namespace tf::cli {

void add_replan_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("replan", "re-plans the windows around detected collisions");
  static std::string scene, oriented, verify, out;
  cmd->add_option("SCENE", scene, "scene JSON")->required();
  cmd->add_option("ORIENTED", oriented, "oriented path CSV")->required();
  cmd->add_option("VERIFY", verify, "verification report JSON")->required();
  cmd->add_option("-o,--output", out, "re-planned oriented path CSV")->required();
  cmd->callback([] { not_yet_delivered("replan", 9); });
}

}  // namespace tf::cli
