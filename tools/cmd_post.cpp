#include "cli.hpp"

namespace tf::cli {

void add_post_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("post", "inverse kinematics for the scene's machine and G-code output");
  static std::string scene, oriented, out;
  cmd->add_option("SCENE", scene, "scene JSON")->required();
  cmd->add_option("ORIENTED", oriented, "oriented path CSV")->required();
  cmd->add_option("-o,--output", out, "G-code program")->required();
  cmd->callback([] { not_yet_delivered("post", 4); });
}

}  // namespace tf::cli
