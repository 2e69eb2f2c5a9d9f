// tiltfield replan SCENE ORIENTED.csv VERIFY.json -o ORIENTED2.csv [--stock-mesh STOCK.ply]
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/replan/replan.hpp"

namespace tf::cli {

namespace {
struct ReplanArgs {
  std::string scene, oriented, verify, out, stock_mesh;
  ReplanOptions options;
};

// "N re-planned row(s) WHAT (rows: the first ten of `rows`, 0-based)".
std::string rows_failing(const std::vector<size_t>& rows, const std::string& what) {
  std::ostringstream msg;
  msg << rows.size() << " re-planned row(s) " << what << " (rows:";
  for (size_t k = 0; k < rows.size() && k < 10; ++k) msg << " " << rows[k];
  msg << (rows.size() > 10 ? " ...)" : ")");
  return msg.str();
}

// The collisions no tool axis fixes, which the re-plan leaves alone: printed by kind, reason and rows (as
// `run`'s "left" lines); "N collision(s) no tool axis fixes", or empty. They had been passed over in
// silence, "0 window(s)" and exit 0 (black-box testing).
// `spans`: collision_spans of the collisions on the oriented path.
std::string left_unfixable(const Scene& scene, const std::vector<Collision>& collisions, const std::vector<RowSpan>& spans) {
  const std::vector<std::string> reasons = unfixable_reasons(collisions, spans, scene.tool);
  struct Group {
    std::string kind, reason;
    size_t count, first, last;
  };
  std::vector<Group> groups;
  size_t total = 0;
  for (size_t k = 0; k < collisions.size(); ++k) {
    if (reasons[k].empty()) continue;
    ++total;
    const std::string kind = collision_kind(collisions[k]);
    auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& x) { return x.kind == kind && x.reason == reasons[k]; });
    if (g == groups.end()) g = groups.insert(groups.end(), {kind, reasons[k], 0, spans[k].first, spans[k].second});
    ++g->count;
    g->first = std::min(g->first, spans[k].first);
    g->last = std::max(g->last, spans[k].second);
  }
  for (const Group& g : groups)  // the failure's detail: printed under --quiet too
    std::cerr << "replan: left " << g.count << " " << g.kind << ", rows " << g.first << "-" << g.last << ": " << g.reason << "\n";
  return total == 0 ? std::string() : std::to_string(total) + " collision(s) no tool axis fixes (see `left` above)";
}

// A report of the program posted from this oriented path: each feed block ends with the tool axis of its
// rows, or between two neighbours' (the post's linearisation), within the post's axis and pole tolerances.
// Simplification (stated): a path re-planned by less than 10.5 deg plus half a row's step passes.
// A report of the path before an earlier re-plan had been taken (black-box testing: axes 40.8 deg off,
// "96 rows changed" where 19 did).
void require_axes_of_path(const OrientedPath& path, const std::vector<Collision>& collisions,
                          const std::vector<RowSpan>& spans, const std::string& report) {
  const auto angle_deg = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.normalized().cross(b.normalized()).norm(), a.normalized().dot(b.normalized())) * 180.0 / M_PI;
  };
  const size_t n = path.rows.size();
  for (size_t k = 0; k < collisions.size(); ++k) {
    const Collision& c = collisions[k];
    if (c.rapid || n == 0 || !c.has_poses || !(c.end.axis.norm() > 1e-9)) continue;
    const size_t first = spans[k].first > 0 ? spans[k].first - 1 : 0, last = std::min(n - 1, spans[k].second + 1);
    double nearest = 180.0, step = 0.0;
    for (size_t i = first; i <= last; ++i) {
      nearest = std::min(nearest, angle_deg(c.end.axis, path.rows[i].axis));
      if (i > first) step = std::max(step, angle_deg(path.rows[i - 1].axis, path.rows[i].axis));
    }
    // The post may leave the axis up to its pole tolerance off at the pole (`post --pole-tol`, at most 10
    // deg), its axis tolerance and 4 decimals elsewhere: a path re-planned since differs by more.
    constexpr double kPostSlackDeg = 10.5;
    if (nearest > 0.5 * step + kPostSlackDeg)
      throw InputError(report, 0, "collisions[" + std::to_string(k) + "].end_axis",
                       "block " + std::to_string(c.block) + " (line " + std::to_string(c.line) + ") ends with the tool axis " +
                           fixed(nearest, 1) + " deg from the oriented path's at rows " + std::to_string(spans[k].first) +
                           "-" + std::to_string(spans[k].second) +
                           ": a report of a program posted from another oriented path (re-plan the path that was posted)");
  }
}

void run_replan(const ReplanArgs& a) {
  check_outputs_apart({{"-o", a.out}}, {a.scene, a.oriented, a.verify, a.stock_mesh});
  const Scene scene = load_scene(a.scene);
  check_outputs_apart({{"-o", a.out}}, scene_inputs(scene, {a.oriented, a.verify, a.stock_mesh}));
  require_for_planning(scene);
  // Read when given, used or not: a missing or broken file is bad input whether or not a stock collision
  // asks for it (it had been read only then, black-box testing).
  std::optional<Mesh> given_stock;
  if (!a.stock_mesh.empty()) given_stock = load_mesh(a.stock_mesh);
  OrientedPath original = read_oriented_csv(a.oriented);
  // The oriented rows must be the scene's path (planned from it): the same cutter locations, row by row.
  require_rows_of_path(original, scene.path, a.oriented);
  attach_path_normals(original, scene.path);  // the rows are the path's (checked above)
  const std::vector<Collision> collisions = read_replan_collisions(a.verify);
  // A report of another program or scene had been re-planned at whatever rows lay nearest (black-box
  // testing). A feed block of this path's program has a cutter location on it; rapids are left alone.
  for (size_t k = 0; k < collisions.size(); ++k) {
    const Collision& c = collisions[k];
    const double d = c.rapid ? 0.0 : collision_distance_to_path(scene.path, scene.tool, c);
    if (d > 2 * scene.tool.radius())  // a flat end's cutter location lies up to a radius off its row
      throw InputError(a.verify, 0, "collisions[" + std::to_string(k) + "]",
                       "block " + std::to_string(c.block) + " (line " + std::to_string(c.line) + ") lies " + fixed(d, 3) +
                           " mm from the scene's path: a report of another program or scene");
  }
  // Each a scan of the path: made once for both checks below.
  const std::vector<RowSpan> spans = collision_spans(scene.path, original, scene.tool, collisions);
  require_axes_of_path(original, collisions, spans, a.verify);
  const PlanOptions plan_options =
      parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
  // The stock as an obstacle for shank and holder: the in-process stock the verifier exported, or the raw
  // stock (a superset of any in-process stock, so never optimistic).
  const bool stock_hit =
      std::any_of(collisions.begin(), collisions.end(), [](const Collision& c) { return c.with == HitWith::Stock; });
  Mesh obstacle;
  std::vector<const Mesh*> extra;
  if (stock_hit) {
    const Mesh stock = given_stock ? *given_stock : stock_to_mesh(scene.stock);
    obstacle = stock_obstacle(stock, scene.path, scene.tool, scene.planner, scene.tool.radius() / 2.0,
                              a.options.crop_margin_mm);
    extra.push_back(&obstacle);
  }
  const ReplanResult r = replan(scene, original, collisions, extra, plan_options, a.options);
  write_oriented_csv(r.path, a.out);
  const std::string left = left_unfixable(scene, collisions, spans);
  if (!global_options().quiet) {
    // No window (every collision one no axis fixes): no clearance to give (it had thrown on infinity).
    const std::string clearance =
        r.windows.empty() || !std::isfinite(r.min_clearance_mm) ? "no window re-planned"
        : clearance_measured(r.min_clearance_mm) ? "min clearance at the windows' rows " + fixed(r.min_clearance_mm, 3) + " mm"
                                                 : "no check surface or fixture near the windows";
    static const char* const widened[] = {"", " (twice as wide as asked)", " (four times as wide as asked)", " (the whole path)"};
    std::cerr << "replan: " << collisions.size() << " collision(s), " << r.windows.size() << " window(s)"
              << widened[std::clamp(r.widened, 0, 3)] << ", " << r.rows_changed << " rows changed, " << clearance << "\n";
  }
  // The job fails after the output was written. The rows below their clearance and the motions between
  // rows that come below it in one line.
  if (!r.unreachable.empty()) throw JobError(rows_failing(r.unreachable, "have no joint solution on the machine"));
  std::string failed;
  if (!r.uncleared.empty()) failed = rows_failing(r.uncleared, "still below their clearance");
  if (!r.uncleared_motions.empty()) {
    failed += (failed.empty() ? "" : "; ") + std::to_string(r.uncleared_motions.size()) +
              " re-planned motion(s) between rows come below their clearance (from row: margin mm):";
    for (size_t k = 0; k < r.uncleared_motions.size() && k < 10; ++k)
      failed += " " + std::to_string(r.uncleared_motions[k].first) + ": " + fixed(r.uncleared_motions[k].second, 3);
    if (r.uncleared_motions.size() > 10) failed += " ...";
  }
  if (!left.empty()) failed += (failed.empty() ? "" : "; ") + left;
  if (!failed.empty()) throw JobError(failed);
}
}  // namespace

void add_replan_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("replan", "re-plans the windows around detected collisions");
  static ReplanArgs a;  // CLI11 binds options to storage living as long as the app
  cmd->add_option("SCENE", a.scene, "scene JSON")->required();
  cmd->add_option("ORIENTED", a.oriented, "oriented path CSV that was posted and verified")->required();
  cmd->add_option("VERIFY", a.verify, "the verifier's report JSON")->required();
  cmd->add_option("-o,--output", a.out, "re-planned oriented path CSV")->required()->check(output_file());
  cmd->add_option("--stock-mesh", a.stock_mesh, "in-process stock mesh from `verify --stock-mesh` (default: the raw stock)");
  cmd->add_option("--window", a.options.window_mm, "rows within this arc length of a collision are re-planned, mm (0: derived)")
      ->check(number_at_least(0, false));
  cmd->add_option("--blend", a.options.blend_mm, "blend length at each window end, mm (0: derived)")
      ->check(number_at_least(0, false));
  cmd->add_flag("!--no-widen", a.options.widen,
                "keep the windows as asked even where they leave rows or motions short (default: plan again twice and "
                "four times as wide, then on the whole path)");
  cmd->callback([] { run_replan(a); });
}

}  // namespace tf::cli
