#include "job.hpp"

#include "cli.hpp"
#include "report/report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "tiltfield/core/error.hpp"
#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tiltfield/post/post.hpp"
#include "tiltfield/replan/replan.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/engagement/engagement.hpp"

namespace tf {
namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The first program's collisions that are gone: those left less the ones the re-planned axes brought.
size_t collisions_fixed(const JobSummary& s) {
  const size_t old_left = s.collisions_final - std::min(s.collisions_new, s.collisions_final);
  return s.collisions_first - std::min(s.collisions_first, old_left);
}

// One posted and verified state of the path.
struct Round {
  OrientedPath path;
  std::string program_text;
  Program program;  // as read back from program_text, so block lines are the file's lines
  VerifyResult verified;
};

void write_job_report(const Scene& scene, const OrientedPath& first_plan, const Round& final_round,
                      const std::vector<reporting::RowWindow>& replanned, const Mesh& stock_mesh,
                      const JobSummary& summary, double resolution_mm, const fs::path& file) {
  using namespace reporting;
  const VerifyReport& report = final_round.verified.report;
  ReportInputs in;
  in.scene = &scene;
  in.oriented = &final_round.path;
  in.first_plan = &first_plan;
  in.replanned = replanned;
  set_verification(in, final_round.program, report, &stock_mesh, scene.design);
  in.summary.title = scene.file.parent_path().filename().string();
  in.summary.collisions_found = static_cast<int>(summary.collisions_first);
  in.summary.collisions_fixed = static_cast<int>(collisions_fixed(summary));
  in.summary.collisions_new = static_cast<int>(summary.collisions_new);
  in.summary.min_clearance_mm = std::isfinite(summary.min_clearance_mm) ? summary.min_clearance_mm : -1.0;
  in.summary.removed_volume_mm3 = report.removed_volume_mm3;
  in.summary.max_gouge_mm = report.max_gouge_mm;
  in.summary.resolution_mm = resolution_mm;
  in.summary.stages = {{"plan", summary.seconds.plan},
                       {"post", summary.seconds.post},
                       {"verify", summary.seconds.verify},
                       {"replan", summary.seconds.replan},
                       {"stock mesh", summary.seconds.mesh}};
  write_html_report(in, file);
}

struct Planned {
  PlanOptions options;  // the re-planner plans with them too
  PlanResult result;
};

Planned plan_stage(const Scene& scene, const JobOptions& options, JobSummary& summary) {
  const auto t0 = std::chrono::steady_clock::now();
  PlanOptions plan_options =
      parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed);
  PlanResult planned = plan(scene, plan_options, options.progress);
  summary.nominal_colliding_rows = planned.metrics.rows_nominal_colliding;
  summary.uncleared_rows = uncleared_row_count(planned.uncleared);
  summary.end_lead_rows = planned.metrics.rows_lead_raised;
  summary.end_turned_rows = planned.metrics.rows_end_turned;
  summary.end_dipping_rows = planned.metrics.rows_end_dipping;
  summary.max_end_dip_mm = planned.metrics.max_end_dip_mm;
  summary.seconds.plan = seconds_since(t0);
  return {std::move(plan_options), std::move(planned)};
}

// Posts a path for the scene's machine and verifies the program, adding the stages' seconds to `seconds`.
class PostAndVerify {
 public:
  PostAndVerify(const Scene& scene, const JobOptions& options)
      : scene_(scene), options_(options), post_options_(options_for(scene)), forward_(scene_forward(scene)) {
    set_post_job(post_job_, scene, post_options_.tool_number);
    post_job_.title = "tiltfield run: " + scene.file.filename().string();
    verify_options_.resolution = options.resolution_mm;
    verify_options_.progress = options.progress;
    verify_options_.engagement = engagement_probe();
  }

  Round operator()(OrientedPath path, StageSeconds& seconds) const {
    auto t = std::chrono::steady_clock::now();
    const Program posted = post_program(path, post_job_, post_options_, options_.progress);
    std::ostringstream text;
    write_gcode(text, posted, post_job_, post_options_);
    // Verify the text exactly as it will be written, so collisions name its lines.
    Program read_back = parse_gcode(text.str(), (options_.out_dir / "program.ngc").string(), *scene_.machine,
                                     gcode_options(scene_));
    seconds.post += seconds_since(t);
    t = std::chrono::steady_clock::now();
    VerifyResult verified = verify_program(scene_, read_back, forward_, verify_options_);
    seconds.verify += seconds_since(t);
    return Round{std::move(path), text.str(), std::move(read_back), std::move(verified)};
  }

 private:
  // The program's tool: the library number the scene's tool came from, else T1.
  static PostOptions options_for(const Scene& scene) {
    PostOptions o;
    if (scene.tool_number > 0) o.tool_number = scene.tool_number;
    o.link_gap_mm = cli::scene_link_gap(scene);
    return o;
  }

  const Scene& scene_;
  const JobOptions& options_;
  PostJob post_job_;
  const PostOptions post_options_;
  const ForwardFn forward_;
  VerifyOptions verify_options_;
};

bool any_fixable(const Scene& scene, const Round& round) {
  const std::vector<Collision>& collisions = round.verified.report.collisions;
  const std::vector<std::string> reasons =
      unfixable_reasons(collisions, collision_spans(scene.path, round.path, scene.tool, collisions), scene.tool);
  return std::any_of(reasons.begin(), reasons.end(), [](const std::string& r) { return r.empty(); });
}

// The in-process stock for the re-planner's obstacle, which keeps only the shank and holder a clearance
// away: on a lattice up to a quarter of that clearance apart, and 1 mm (every k-th ray of the verifier's), which
// the mesh follows within about its spacing. At the verifier's own spacing the obstacle of a 140 mm
// block at 0.1 mm had 2.5 M faces and took 15 s a round to make and plan against.
TriDexel obstacle_lattice(const TriDexel& stock, const PlannerBasics& basics) {
  const double clearance = std::min(basics.shank_clearance.value_or(basics.safety_distance),
                                    basics.holder_clearance.value_or(basics.safety_distance));
  // At most 1 mm apart whatever the clearance: a boss narrower than the rays' spacing may drop out.
  const int k = std::max(1, static_cast<int>(std::floor(std::min(0.25 * clearance, 1.0) / stock.lattice().h)));
  return coarsened(stock, k);
}

// What a re-plan left below its clearance, in words (empty: nothing).
std::string shortfall(const ReplanResult& re) {
  std::string s;
  if (!re.uncleared.empty())
    s = std::to_string(re.uncleared.size()) + " row(s) below their clearance (first: row " + std::to_string(re.uncleared.front()) + ")";
  if (!re.uncleared_motions.empty()) {
    const auto& [row, margin] = re.uncleared_motions.front();
    s += (s.empty() ? "" : ", ") + std::to_string(re.uncleared_motions.size()) +
         " motion(s) between rows below their clearance (first: from row " + std::to_string(row) + ", " + fixed(margin, 3) + " mm)";
  }
  return s;
}

// Re-plans around the collisions against the in-process stock while some may be fixed and each round
// reduces them; `current` ends as the last round kept. Returns the row windows re-planned in kept rounds;
// `uncleared` receives the rows the last re-planning could not clear.
std::vector<reporting::RowWindow> replan_rounds(const Scene& scene, const PlanOptions& plan_options,
                                                const PostAndVerify& post_and_verify, const JobOptions& options,
                                                Round& current, JobSummary& summary, std::vector<size_t>& uncleared) {
  std::vector<reporting::RowWindow> replanned;
  while (any_fixable(scene, current) && summary.rounds < options.max_rounds) {
    auto t = std::chrono::steady_clock::now();
    StockMeshOptions mesh_options;
    mesh_options.colour_by_deviation = false;
    const Mesh in_process = reconstruct_stock(obstacle_lattice(current.verified.stock, scene.planner), nullptr, mesh_options);
    const Mesh obstacle =
        stock_obstacle(in_process, scene.path, scene.tool, scene.planner, scene.tool.radius() / 2.0, 0.5);
    const ReplanResult re = replan(scene, current.path, current.verified.report.collisions, {&obstacle}, plan_options);
    summary.seconds.replan += seconds_since(t);
    ++summary.rounds;
    // A motion between rows that no axis sequence found clears counts for both its rows (black-box
    // testing: its collisions had been left as "re-planning did not reduce the collisions").
    uncleared = re.uncleared;
    for (const auto& [row, margin] : re.uncleared_motions) uncleared.insert(uncleared.end(), {row, row + 1});
    std::sort(uncleared.begin(), uncleared.end());
    uncleared.erase(std::unique(uncleared.begin(), uncleared.end()), uncleared.end());
    summary.replan_shortfall = shortfall(re);
    // A re-planned path the post cannot take (a row or a move beyond the machine) ends the rounds: the
    // last one posted is kept, and the reason is reported with the collisions left.
    Round next;
    try {
      next = post_and_verify(re.path, summary.seconds);
    } catch (const PostRowError& e) {
      summary.replan_not_posted = "row " + std::to_string(e.row()) + ": " + e.what();
      break;
    } catch (const JobError& e) {
      summary.replan_not_posted = e.what();
      break;
    }
    if (next.verified.report.collisions.size() >= current.verified.report.collisions.size()) break;
    summary.rows_replanned += re.rows_changed;
    for (const auto& w : re.windows) replanned.push_back({static_cast<int>(w.first), static_cast<int>(w.last)});
    current = std::move(next);
  }
  return replanned;
}

constexpr const char* kNotReduced = "re-planning did not reduce the collisions";

// Why a collision is left: the replan library's reason (`unfixable`), else the rows no axis could clear,
// else the rounds.
std::string left_reason(const RowSpan& rows, const std::string& unfixable, const std::vector<size_t>& uncleared,
                        const JobSummary& summary, const JobOptions& options) {
  if (!unfixable.empty()) return unfixable;
  const auto [first, last] = rows;
  const auto it = std::lower_bound(uncleared.begin(), uncleared.end(), first);
  if (it != uncleared.end() && *it <= last)
    return "the re-plan's search found no tool axis within max_tilt_deg and the machine's limits that keeps "
           "the clearance there (at the rows or on the motion between them)";
  if (summary.rounds >= options.max_rounds)
    return "not fixed within " + std::to_string(options.max_rounds) + " re-plan round(s) (--rounds)";
  // Why it did not: what the last re-plan could not clear (black-box testing: a motion between rows 0.84 mm
  // into the stock had gone unsaid).
  if (!summary.replan_shortfall.empty()) return std::string(kNotReduced) + "; the last re-plan left " + summary.replan_shortfall;
  return kNotReduced;
}

// `first`: the rows of the first program's collisions. A collision left on rows none of them touched came
// with the re-planned axes (black-box testing: 33 collisions gone and 15 new ones were "18 fixed", their
// reason "re-planning did not reduce the collisions").
void explain_left(const Scene& scene, const Round& current, const std::vector<size_t>& uncleared,
                  const std::vector<RowSpan>& first, const JobOptions& options, JobSummary& summary) {
  const std::vector<Collision>& left = current.verified.report.collisions;
  const std::vector<RowSpan> spans = collision_spans(scene.path, current.path, scene.tool, left);
  const std::vector<std::string> unfixable = unfixable_reasons(left, spans, scene.tool);
  for (size_t k = 0; k < left.size(); ++k) {
    const Collision& c = left[k];
    const std::string kind = cli::collision_kind(c);
    std::string reason = left_reason(spans[k], unfixable[k], uncleared, summary, options);
    const bool brought = std::none_of(first.begin(), first.end(), [&](const RowSpan& f) {
      return f.first <= spans[k].second && spans[k].first <= f.second;
    });
    if (brought && summary.rounds > 0) {
      ++summary.collisions_new;
      if (reason.rfind(kNotReduced, 0) == 0) reason = "came with the re-planned axes (the round was kept: fewer collisions in all)";
      else reason = "came with the re-planned axes: " + reason;
    }
    const auto [first, last] = spans[k];
    auto it = std::find_if(summary.left.begin(), summary.left.end(),
                           [&](const LeftCollisions& l) { return l.kind == kind && l.reason == reason; });
    if (it == summary.left.end()) {
      summary.left.push_back({kind, reason, 0, first, last});
      it = summary.left.end() - 1;
    }
    ++it->count;
    it->first_row = std::min(it->first_row, first);
    it->last_row = std::max(it->last_row, last);
  }
}

void summarise_final_round(const Round& current, JobSummary& summary) {
  const VerifyReport& report = current.verified.report;
  summary.collisions_final = report.collisions.size();
  summary.gouges_final = report.gouges.size();
  summary.max_gouge_mm = report.max_gouge_mm;
  summary.blocks = static_cast<size_t>(report.blocks);
  summary.removed_volume_mm3 = report.removed_volume_mm3;
  summary.min_clearance_mm = std::numeric_limits<double>::infinity();
  for (const auto& row : current.path.rows)
    summary.min_clearance_mm = std::min(summary.min_clearance_mm, row.clearance_mm);
}

// Every output, each atomically; report.html last since it draws on the rest.
void write_outputs(const Scene& scene, const OrientedPath& first_plan, const Round& current,
                   const std::vector<reporting::RowWindow>& replanned, const JobOptions& options,
                   JobSummary& summary) {
  const VerifyReport& report = current.verified.report;
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (!fs::is_directory(options.out_dir))
    throw InputError(options.out_dir.string(), 0, "-o", "cannot create the output folder");
  auto wrote = [&](const char* name) {
    summary.files.push_back((options.out_dir / name).string());
    return options.out_dir / name;
  };
  write_oriented_csv(current.path, wrote("oriented.csv"));
  write_file_atomic(wrote("program.ngc"), [&](std::ostream& out) { out << current.program_text; });
  write_verify_json(report, wrote("verify.json"));
  write_blocks_csv(report, wrote("blocks.csv"));
  const auto t_mesh = std::chrono::steady_clock::now();
  const Mesh stock_mesh = reconstruct_stock(current.verified.stock, scene.design.n_faces() ? &scene.design : nullptr);
  write_mesh(stock_mesh, wrote("stock.ply"));
  summary.seconds.mesh = seconds_since(t_mesh);
  if (options.write_report) {
    const auto t = std::chrono::steady_clock::now();
    write_job_report(scene, first_plan, current, replanned, stock_mesh, summary, options.resolution_mm,
                     wrote("report.html"));
    summary.seconds.report = seconds_since(t);
  }
}

}  // namespace

namespace {

// A job that stops after the plan writes oriented.csv alone: the other outputs an earlier run left in the
// folder are not of this plan, and are removed (they had stood beside the new plan unmarked). Returns a
// note naming them, or nothing.
std::string remove_stale_outputs(const fs::path& dir) {
  std::string removed;
  for (const char* name : kRunOutputs) {
    if (std::string(name) == "oriented.csv") continue;
    std::error_code ec;
    if (fs::is_regular_file(dir / name, ec) && fs::remove(dir / name, ec))
      removed += (removed.empty() ? "" : ", ") + std::string(name);
  }
  return removed.empty() ? removed : "; " + removed + " of an earlier run removed from " + dir.string();
}

// Rows the machine cannot reach cannot be posted: the plan is written (oriented.csv, with the rows'
// clearances) and the job stops naming them, rather than failing in the post with no output.
void stop_at_unreachable_rows(const PlanResult& planned, const JobOptions& options) {
  std::vector<size_t> rows;
  for (const auto& u : planned.uncleared)
    if (u.unreachable) rows.push_back(u.row);
  if (rows.empty()) return;
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  const fs::path out = options.out_dir / "oriented.csv";
  write_oriented_csv(planned.path, out);
  std::ostringstream msg;
  msg << rows.size() << " planned row(s) have no joint solution on the machine (rows:";
  for (size_t k = 0; k < rows.size() && k < 10; ++k) msg << " " << rows[k];
  msg << (rows.size() > 10 ? " ..." : "") << "); the plan is in " << out.string() << ", nothing was posted"
      << remove_stale_outputs(options.out_dir);
  throw JobError(msg.str());
}

// The plan could not be posted: it is written (oriented.csv) and the job stops saying why, rather than
// leaving nothing.
[[noreturn]] void stop_unposted(const PlanResult& planned, const JobOptions& options, const std::string& why) {
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  const fs::path out = options.out_dir / "oriented.csv";
  write_oriented_csv(planned.path, out);
  throw JobError("the plan could not be posted (" + why + "); the plan is in " + out.string() + ", nothing was posted" +
                 remove_stale_outputs(options.out_dir));
}

}  // namespace

JobSummary run_job(const Scene& scene, const JobOptions& options) {
  if (!scene.machine)
    throw InputError(scene.file.string(), 0, "machine", "the scene names no machine; `run` posts for one");
  JobSummary summary;
  summary.rows = scene.path.rows.size();
  const Planned planned = plan_stage(scene, options, summary);
  stop_at_unreachable_rows(planned.result, options);
  const PostAndVerify post_and_verify(scene, options);
  Round current;
  try {
    current = post_and_verify(planned.result.path, summary.seconds);
  } catch (const PostRowError& e) {
    stop_unposted(planned.result, options, "row " + std::to_string(e.row()) + ": " + e.what());
  } catch (const JobError& e) {
    stop_unposted(planned.result, options, e.what());
  }
  summary.collisions_first = current.verified.report.collisions.size();
  const std::vector<RowSpan> first_spans =
      collision_spans(scene.path, current.path, scene.tool, current.verified.report.collisions);
  std::vector<size_t> uncleared;
  const std::vector<reporting::RowWindow> replanned =
      replan_rounds(scene, planned.options, post_and_verify, options, current, summary, uncleared);
  summarise_final_round(current, summary);
  explain_left(scene, current, uncleared, first_spans, options, summary);
  write_outputs(scene, planned.result.path, current, replanned, options, summary);
  return summary;
}

std::string format_summary(const JobSummary& s, const Scene& scene) {
  std::ostringstream o;
  o << "tiltfield run: " << scene.file.string() << "\n"
    << "  path         " << s.rows << " rows; nominal axis too close on " << s.nominal_colliding_rows << " rows\n"
    << "  plan         min clearance "
    << (clearance_measured(s.min_clearance_mm) ? fixed(s.min_clearance_mm, 3) + " mm"
                                                                       : std::string("none (no check surface or fixture)"))
    << " (safety " << fixed(scene.planner.safety_distance, 3) << "), " << s.uncleared_rows << " rows not cleared\n";
  if (s.end_lead_rows + s.end_turned_rows + s.end_dipping_rows > 0)
    o << "  end form     kept out of the design: nominal lead changed on " << s.end_lead_rows << " rows, "
      << s.end_turned_rows << " rows turned after the stages; " << s.end_dipping_rows << " rows still dip (max " << fixed(s.max_end_dip_mm, 3) << " mm)\n";
  o
    << "  program      " << s.blocks << " blocks\n"
    << "  collisions   " << s.collisions_first << " found, " << collisions_fixed(s) << " fixed in " << s.rounds
    << " re-plan round(s) (" << s.rows_replanned << " rows), "
    << (s.collisions_new > 0 ? std::to_string(s.collisions_new) + " new, " : std::string()) << s.collisions_final << " left\n";
  for (const auto& l : s.left)
    o << "  left         " << l.count << " " << l.kind << ", rows " << l.first_row << "-" << l.last_row << ": " << l.reason
      << "\n";
  if (!s.replan_not_posted.empty())
    o << "  re-plan      the last re-planned path could not be posted, the round before it kept: " << s.replan_not_posted
      << "\n";
  o
    << "  gouges       " << s.gouges_final << " (max " << fixed(s.max_gouge_mm, 3) << " mm)\n"
    << "  removed      " << fixed(s.removed_volume_mm3, s.removed_volume_mm3 >= 100.0 ? 1 : 4) << " mm3\n"
    << "  time (s)     plan " << fixed(s.seconds.plan, 2) << ", post " << fixed(s.seconds.post, 2) << ", verify "
    << fixed(s.seconds.verify, 2) << ", replan " << fixed(s.seconds.replan, 2) << ", stock mesh " << fixed(s.seconds.mesh, 2) << ", report " << fixed(s.seconds.report, 2)
    << "\n";
  for (const auto& f : s.files) o << "  wrote        " << f << "\n";
  return o.str();
}

}  // namespace tf
