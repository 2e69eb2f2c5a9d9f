#include "cli.hpp"

namespace tf::cli {

void add_plan_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plan", "tool-axis planning by the potential-field rigid-body model");
  static std::string scene, out, json;
  cmd->add_option("SCENE", scene, "scene JSON")->required();
  cmd->add_option("-o,--output", out, "oriented path CSV")->required();
  cmd->add_option("--json", json, "plan metrics JSON");
  cmd->callback([] { not_yet_delivered("plan", 3); });
}

}  // namespace tf::cli
