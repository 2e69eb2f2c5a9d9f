// tiltfield plan SCENE -o ORIENTED.csv [--json PLAN.json] [--method dynamic|pointwise] [--smooth]
#include <ostream>
#include <cmath>
#include <sstream>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/tilt/plan.hpp"

namespace tf::cli {

namespace {

// JSON text with every number in fixed notation (no output of ours uses scientific notation).
void write_json(std::ostream& os, const nlohmann::json& j, int indent) {
  const std::string pad(static_cast<size_t>(indent + 2), ' '), end_pad(static_cast<size_t>(indent), ' ');
  if (j.is_object()) {
    os << "{";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      os << (first ? "\n" : ",\n") << pad << nlohmann::json(it.key()).dump() << ": ";
      write_json(os, it.value(), indent + 2);
      first = false;
    }
    os << (first ? "}" : "\n" + end_pad + "}");
  } else if (j.is_array()) {
    os << "[";
    bool first = true;
    for (const auto& v : j) {
      os << (first ? "\n" : ",\n") << pad;
      write_json(os, v, indent + 2);
      first = false;
    }
    os << (first ? "]" : "\n" + end_pad + "]");
  } else if (j.is_number_float()) {
    // JSON has no infinity: a value that is none (an unreachable row's margin with no obstacle to measure
    // it by) is null. It had stopped the command with "fixed(): non-finite number" (black-box testing).
    const double v = j.get<double>();
    if (std::isfinite(v)) os << fixed(v, 6);
    else os << "null";
  } else {
    os << j.dump();
  }
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plan", "tool-axis planning by the potential-field rigid-body model");
  struct Args {
    std::string scene, out, json, method;
    bool smooth = false;
  };
  static Args a;
  cmd->add_option("SCENE", a.scene, "scene JSON")->required();
  cmd->add_option("-o,--output", a.out, "oriented path CSV")->required()->check(output_file());
  cmd->add_option("--json", a.json, "plan metrics JSON")->check(output_file());
  cmd->add_option("--method", a.method, "dynamic (default) or pointwise (the point-by-point baseline)")
      ->check(CLI::IsMember({"dynamic", "pointwise"}));
  cmd->add_flag("--smooth", a.smooth, "global smoothing pass (Ceres) after the dynamics");
  cmd->callback([] {
    check_outputs_apart({{"-o", a.out}, {"--json", a.json}}, {a.scene});
    const Scene scene = load_scene(a.scene);
    check_outputs_apart({{"-o", a.out}, {"--json", a.json}}, scene_inputs(scene));
    require_for_planning(scene);
    PlanOptions options = parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
    if (a.method == "pointwise") options.method = PlanMethod::Pointwise;
    if (a.method == "dynamic") options.method = PlanMethod::Dynamic;
    if (a.smooth) options.smooth = true;
    const PlanResult result = plan(scene, options, terminal_progress());
    write_oriented_csv(result.path, a.out);
    if (!a.json.empty()) {
      const nlohmann::json j = plan_report_json(result);
      write_file_atomic(a.json, [&](std::ostream& os) {
        write_json(os, j, 0);
        os << "\n";
      });
    }
    if (!result.uncleared.empty()) {
      std::ostringstream msg;
      msg << uncleared_row_count(result.uncleared) << " row(s) could not be cleared (row: clearance mm):";
      for (size_t k = 0; k < result.uncleared.size() && k < 10; ++k) {
        const UnclearedRow& u = result.uncleared[k];
        msg << (k ? "," : "") << " " << u.row << ": ";
        // A clear row whose motion is not: the row's clearance would read as a contradiction (black-box
        // testing), the motion's shortfall says what fails.
        if (u.between_rows) msg << "the motion to the next row comes " << fixed(-u.margin_mm, 4) << " short";
        else msg << fixed(u.clearance_mm, 4);
        msg << (u.unreachable ? " (unreachable)" : "") << (u.obstacle == "fixtures" ? " (fixture)" : "");
      }
      if (result.uncleared.size() > 10) msg << ", ... (all in --json)";
      throw JobError(msg.str());
    }
  });
}

}  // namespace tf::cli
