#include "cli.hpp"

namespace tf::cli {

void add_offset_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("offset", "offset-profile trajectory for copy milling or ECM");
  static std::string profile, gap_law, side = "inside", target = "milling", out, svg;
  static double gap = 0;
  cmd->add_option("PROFILE", profile, "profile text file")->required();
  cmd->add_option("-d,--gap", gap, "gap (offset distance), mm")->required();
  cmd->add_option("--gap-law", gap_law, "CSV s,gap");
  cmd->add_option("--side", side, "inside or outside");
  cmd->add_option("--target", target, "milling or ecm");
  cmd->add_option("-o,--output", out, "G-code program")->required();
  cmd->add_option("--svg", svg, "SVG plot");
  cmd->callback([] { not_yet_delivered("offset", 7); });
}

}  // namespace tf::cli
