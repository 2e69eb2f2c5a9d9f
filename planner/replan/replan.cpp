// Re-planning windows around verified collisions.
#include "tiltfield/replan/replan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "tiltfield/core/angles.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/local_frame.hpp"

namespace tf {
namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

namespace {

// The tool's tip and axis at each row as the post places them: a flat or bull end's tip lies up to a
// radius off its row's point, on a tilted axis nearer to the neighbouring pass's points than to its own
// (black-box testing: a flat R4 at 40 deg tilt had its windows on the passes beside the collisions).
struct RowPoses {
  std::vector<Eigen::Vector3d> tip, axis;
};
RowPoses row_poses(const ToolPath& path, const OrientedPath& oriented, const Tool& tool) {
  RowPoses r;
  const size_t n = path.rows.size();
  const bool axes = oriented.rows.size() == n;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d axis = axes ? oriented.rows[i].axis.normalized() : Eigen::Vector3d(Eigen::Vector3d::UnitZ());
    r.tip.push_back(axes ? tool.tip_at(path.rows[i].p, path.rows[i].contact_normal(), axis)
                         : Eigen::Vector3d(path.rows[i].p - tool.cl_height() * axis));
    r.axis.push_back(axis);
  }
  return r;
}

// The row whose pose is nearest the block's end pose: tips apart, plus the axes' difference at the tool's
// radius (the block's ends are the rows' poses exactly, up to the program's decimals).
size_t nearest_row(const RowPoses& rows, const Tool& tool, const ToolPose& pose) {
  const Eigen::Vector3d axis = pose.axis.normalized();
  const double r2 = tool.radius() * tool.radius();
  size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < rows.tip.size(); ++i) {
    const double d = (rows.tip[i] - pose.tip).squaredNorm() + r2 * (rows.axis[i] - axis).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

// C1 weight: 0 with zero slope at x <= 0, 1 with zero slope at x >= 1.
double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

std::vector<ReplanWindow> windows_for(const ToolPath& path, const OrientedPath& oriented, const std::vector<double>& arc,
                                      const Tool& tool, const std::vector<Collision>& collisions, double pad_mm) {
  std::vector<ReplanWindow> w;
  const std::vector<RowSpan> spans = collision_spans(path, oriented, tool, collisions);
  const std::vector<std::string> unfixable = unfixable_reasons(collisions, spans, tool);
  for (size_t k = 0; k < collisions.size(); ++k) {
    if (!unfixable[k].empty()) continue;
    auto [a, b] = spans[k];
    const double sa = arc[a] - pad_mm, sb = arc[b] + pad_mm;
    while (a > 0 && arc[a - 1] >= sa) --a;
    while (b + 1 < arc.size() && arc[b + 1] <= sb) ++b;
    w.push_back({a, b, 1});
  }
  std::sort(w.begin(), w.end(), [](const ReplanWindow& x, const ReplanWindow& y) { return x.first < y.first; });
  std::vector<ReplanWindow> merged;
  for (const auto& x : w) {
    if (!merged.empty() && x.first <= merged.back().last + 1) {
      merged.back().last = std::max(merged.back().last, x.last);
      merged.back().collisions += x.collisions;
    } else {
      merged.push_back(x);
    }
  }
  return merged;
}

// The rotaries of the blends of a window's rows in the machine's joints; nullopt where an old or a new
// axis has no joint solution.
std::optional<std::vector<Eigen::Vector3d>> blend_in_rotaries(const std::vector<Eigen::Vector3d>& cl,
                                                              const std::vector<Eigen::Vector3d>& old_axes,
                                                              const std::vector<Eigen::Vector3d>& new_axes,
                                                              const std::vector<double>& weights, const Tool& tool,
                                                              const std::vector<Eigen::Vector3d>& normals,
                                                              const Kinematics& kin) {
  std::vector<Eigen::Vector3d> out;
  Joints prev;
  for (size_t i = 0; i < cl.size(); ++i) {
    const auto pose = [&](const Eigen::Vector3d& a) {
      return ToolPose{tool.tip_at(cl[i], normals[i], a), a};
    };
    const std::optional<Joints> j0 = kin.inverse_nearest(pose(old_axes[i].normalized()), prev);
    if (!j0) return std::nullopt;
    const std::optional<Joints> j1 = kin.inverse_nearest(pose(new_axes[i].normalized()), *j0);
    if (!j1) return std::nullopt;
    Joints j = *j0;
    const double w = weights[i];
    j.a += w * (j1->a - j0->a), j.b += w * (j1->b - j0->b), j.c += w * (j1->c - j0->c);
    out.push_back(kin.forward(j).axis.normalized());
    prev = *j0;
  }
  return out;
}

}  // namespace

std::vector<Eigen::Vector3d> blend_axes(const std::vector<Eigen::Vector3d>& cl, const std::vector<Eigen::Vector3d>& old_axes,
                                        const std::vector<Eigen::Vector3d>& new_axes, const std::vector<double>& weights,
                                        const Tool& tool, const std::vector<Eigen::Vector3d>& normals,
                                        const Kinematics* kin) {
  std::vector<Eigen::Vector3d> out;
  bool reached = true;
  for (size_t i = 0; i < cl.size(); ++i) {
    const Eigen::Vector3d a = slerp_axis(old_axes[i], new_axes[i], weights[i]).normalized();
    out.push_back(a);
    const Eigen::Vector3d tip = tool.tip_at(cl[i], normals[i], a);
    if (kin && reached) reached = !kin->inverse(ToolPose{tip, a}, Joints{}).empty();
  }
  if (reached) return out;
  return blend_in_rotaries(cl, old_axes, new_axes, weights, tool, normals, *kin).value_or(out);
}

namespace {
// A feed along the tool's own axis: the post's approach or retract (or a plunge), not a move between
// cutter locations. Within what a program written to 4 decimals keeps: 2e-4 mm off the line, 0.01 deg.
bool along_tool_axis(const Collision& c) {
  const Eigen::Vector3d d = c.end.tip - c.start.tip;
  return d.norm() > 0.01 && c.start.axis.normalized().dot(c.end.axis.normalized()) > std::cos(0.01 * kDeg) &&
         d.cross(c.start.axis.normalized()).norm() < 2e-4;
}
}  // namespace

std::string unfixable_reason(const Collision& c, const Tool& tool) {
  if (c.rapid) return "a rapid move: the post's retracts and links must clear it, not the tool axis";
  // A flat or bull end swings about its contact with the axis (Tool::contact_offset): its collisions at a
  // cutter location are the axis's to fix (black-box testing: 322 collisions of a bull end with a fixture
  // had been passed over in silence as "the ball itself").
  const bool end_moves = !std::holds_alternative<BallCutter>(tool.cutter);
  if (c.component == ToolComponent::Ball && !(end_moves && !along_tool_axis(c))) {
    const std::string with = c.with == HitWith::Check ? "check surface" : std::string(to_string(c.with));
    // The message had blamed the cutter location of a row that was clear (black-box testing): the
    // re-planner does not move approaches.
    const std::string part = end_moves ? "the tool's end" : "the ball";
    if (along_tool_axis(c))
      return part + " meets the " + with + " on a move along the tool axis (the post's approach or retract)," +
             " not at a cutter location; re-planning the axes does not move it";
    return "the ball itself meets the " + with + " at the cutter location; no tool axis moves it";
  }
  return {};
}

namespace {
RowSpan rows_of(const RowPoses& rows, const Tool& tool, const Collision& c) {
  const size_t i0 = nearest_row(rows, tool, c.start), i1 = nearest_row(rows, tool, c.end);
  return {std::min(i0, i1), std::max(i0, i1)};
}
}  // namespace

RowSpan collision_rows(const ToolPath& path, const OrientedPath& oriented, const Tool& tool, const Collision& c) {
  return rows_of(row_poses(path, oriented, tool), tool, c);
}

namespace {
double distance_to_polyline(const ToolPath& path, const Eigen::Vector3d& q) {
  const auto& rows = path.rows;
  double best = rows.empty() ? kInfinity : (rows.front().p - q).norm();
  for (size_t i = 0; i + 1 < rows.size(); ++i) {
    const Eigen::Vector3d a = rows[i].p, d = rows[i + 1].p - a;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((q - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * d - q).norm());
  }
  return best;
}
}  // namespace

double collision_distance_to_path(const ToolPath& path, const Tool& tool, const Collision& c) {
  const double cl = tool.cl_height();
  const double d0 = distance_to_polyline(path, c.start.tip + cl * c.start.axis.normalized());
  const double d1 = distance_to_polyline(path, c.end.tip + cl * c.end.axis.normalized());
  // A move along the tool axis (the post's plunge or retract) has one end off the path; any other feed block
  // of the path's program has both on it (one end 1 m off had been re-planned, black-box testing).
  return along_tool_axis(c) ? std::min(d0, d1) : std::max(d0, d1);
}

std::vector<RowSpan> collision_spans(const ToolPath& path, const OrientedPath& oriented, const Tool& tool,
                                     const std::vector<Collision>& collisions) {
  const RowPoses rows = row_poses(path, oriented, tool);
  std::vector<RowSpan> spans;
  spans.reserve(collisions.size());
  for (const Collision& c : collisions) spans.push_back(rows_of(rows, tool, c));
  return spans;
}

std::vector<std::string> unfixable_reasons(const std::vector<Collision>& collisions, const std::vector<RowSpan>& spans,
                                           const Tool& tool) {
  std::vector<std::string> out;
  std::vector<size_t> ball;  // collisions of the ball itself on a feed move
  for (size_t k = 0; k < collisions.size(); ++k) {
    out.push_back(unfixable_reason(collisions[k], tool));
    // An approach's collision is no reason to leave the rows' other collisions alone, nor is a flat or
    // bull end's, which the axis moves.
    if (collisions[k].component == ToolComponent::Ball && !collisions[k].rapid && !along_tool_axis(collisions[k]) &&
        !out[k].empty())
      ball.push_back(k);
  }
  for (size_t k = 0; k < collisions.size(); ++k) {
    if (!out[k].empty()) continue;
    for (size_t b : ball)
      if (collisions[b].with == collisions[k].with && spans[k].first <= spans[b].second &&
          spans[b].first <= spans[k].second) {
        out[k] = "the cutter passes through the " + std::string(to_string(collisions[b].with)) +
                 " here (the ball meets it on the same rows); no tool axis fixes that";
        break;
      }
  }
  return out;
}

std::vector<Collision> read_replan_collisions(const std::filesystem::path& verify_json) {
  VerifyReport report = read_verify_json(verify_json);
  for (size_t i = 0; i < report.collisions.size(); ++i)
    if (!report.collisions[i].has_poses)
      throw InputError(verify_json.string(), 0, "collisions[" + std::to_string(i) + "].start_tip",
                       "missing (re-planning needs the block's tool poses)");
  return std::move(report.collisions);
}

namespace {
// The stock obstacle is kept like a check surface (each component its own clearance).
PlanObstacles replan_obstacles(const Scene& scene, const std::vector<const Mesh*>& extra_obstacles) {
  PlanObstacles obstacles = scene_obstacles(scene);
  obstacles.check_surfaces.insert(obstacles.check_surfaces.end(), extra_obstacles.begin(), extra_obstacles.end());
  return obstacles;
}

// The windows' rows and motions proven against everything the re-planner knew, and the rows' joint
// solutions on the machine (`kin` null: none); what fails is listed in `result`.
void prove_windows(const Scene& scene, const std::vector<const Mesh*>& extra_obstacles, const PlanObstacles& obstacles,
                   const PlanOptions& plan_options, const Kinematics* kin, ReplanResult& result) {
  const ToolPath& path = scene.path;
  const size_t n = path.rows.size();
  std::vector<size_t> rows;
  for (const ReplanWindow& w : result.windows)
    for (size_t i = w.first; i <= w.last; ++i) rows.push_back(i);
  const std::vector<RowClearance> clear = row_clearances(result.path, rows, scene.tool, scene.planner, obstacles);
  // The CSV's clearance is the plan's: to the check surfaces and fixtures, not the stock obstacle the
  // windows were also kept from (black-box testing: 10 mm to the stock in a scene without check surfaces,
  // where `plan` writes none).
  const std::vector<RowClearance> scene_clear =
      extra_obstacles.empty() ? clear : row_clearances(result.path, rows, scene.tool, scene.planner, scene_obstacles(scene));
  result.min_clearance_mm = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < rows.size(); ++k) {
    const double d = scene_clear[k].distance_mm;
    result.path.rows[rows[k]].clearance_mm = std::isfinite(d) ? std::min(d, kNoObstacleClearance) : kNoObstacleClearance;
    result.min_clearance_mm = std::min(result.min_clearance_mm, result.path.rows[rows[k]].clearance_mm);
    // The planner's own test: below the clearance is below it (a tolerance here hid rows 0.005 mm short).
    if (clear[k].margin_mm < 0.0) {
      ++result.rows_below_safety;
      result.uncleared.push_back(rows[k]);
    }
  }
  // The motions between the windows' rows and across their ends, proven as the planner proves its own: a
  // blend can turn the axis through an obstacle between two clear rows (black-box testing: 27 degrees
  // between two rows swept the holder through a post, and the window read 0.833 mm).
  std::vector<size_t> motions;
  for (const ReplanWindow& w : result.windows)
    for (size_t i = w.first > 0 ? w.first - 1 : 0; i <= w.last && i + 1 < n; ++i) motions.push_back(i);
  const std::vector<MotionClearance> between =
      motion_clearances(path, result.path, motions, scene.tool, scene.planner, obstacles, plan_options);
  for (size_t k = 0; k < motions.size(); ++k)
    if (!between[k].clear) result.uncleared_motions.emplace_back(motions[k], between[k].margin_mm);
  // The blended axes on the scene's machine: a window the limits cannot follow is reported, not posted.
  if (kin) {
    for (size_t i : rows) {
      const OrientedRow& r = result.path.rows[i];
      if (kin->inverse(ToolPose{row_tip(r, scene.tool), r.axis.normalized()}, Joints{}).empty())
        result.unreachable.push_back(i);
    }
  }
}

// One attempt: the windows re-planned and blended into `result.path` (the original's rows elsewhere), then
// their rows and motions proven against everything the re-planner knew.
void plan_windows(const Scene& scene, const OrientedPath& original, const std::vector<const Mesh*>& extra_obstacles,
                  const PlanOptions& plan_options, const std::vector<double>& arc, double blend, ReplanResult& result) {
  const ToolPath& path = scene.path;
  const size_t n = path.rows.size();

  const PlanObstacles obstacles = replan_obstacles(scene, extra_obstacles);
  const std::vector<LocalFrame> frames = local_frames(path);
  std::optional<Kinematics> kin;
  if (scene.machine) kin.emplace(*scene.machine, scene.tool.length);

  for (const ReplanWindow& w : result.windows) {
    ToolPath sub;
    sub.rows.assign(path.rows.begin() + static_cast<long>(w.first), path.rows.begin() + static_cast<long>(w.last) + 1);
    const PlanResult planned = plan_path(sub, scene.tool, obstacles, scene.planner, scene.feed, plan_options,
                                         scene.machine ? &*scene.machine : nullptr);
    const double s0 = arc[w.first], length = arc[w.last] - s0;
    const double ramp = std::min(blend, 0.5 * length);
    std::vector<Eigen::Vector3d> cl, old_axes, new_axes, normals;
    std::vector<double> weights;
    for (size_t i = w.first; i <= w.last; ++i) {
      const double s = arc[i] - s0;
      // No blend toward a path end: there is no axis beyond it to keep (row 0 had kept its old axis, below
      // its clearance, where a window reached the path's start; black-box testing).
      const double from_start = w.first == 0 ? kInfinity : s, to_end = w.last + 1 == n ? kInfinity : length - s;
      weights.push_back(ramp > 0 ? smoothstep(std::min({from_start, to_end, ramp}) / ramp) : 1.0);
      cl.push_back(path.rows[i].p);
      normals.push_back(path.rows[i].contact_normal());
      old_axes.push_back(original.rows[i].axis);
      new_axes.push_back(planned.path.rows[i - w.first].axis);
    }
    const std::vector<Eigen::Vector3d> blended = blend_axes(cl, old_axes, new_axes, weights, scene.tool, normals, kin ? &*kin : nullptr);
    for (size_t i = w.first; i <= w.last; ++i) {
      const Eigen::Vector3d& old_axis = original.rows[i].axis;
      OrientedRow& row = result.path.rows[i];
      // Where the weight is 0 the row keeps its axis to the digit (the blend returns it normalised).
      row.axis = weights[i - w.first] == 0.0 ? old_axis : blended[i - w.first];
      const Eigen::Vector2d lt = lead_tilt_from_axis(frames[i], row.axis);
      row.lead_deg = lt.x();
      row.tilt_deg = lt.y();
      if ((row.axis - old_axis).norm() > 1e-12) ++result.rows_changed;
    }
  }

  prove_windows(scene, extra_obstacles, obstacles, plan_options, kin ? &*kin : nullptr, result);
}

// What an attempt leaves short that the original path did not: wider windows take in more rows, and a row
// the original left short already (a planner fall-back, a ball inside a check surface) is no attempt's
// fault (review: the whole path could never have won). Except in the windows as asked: their rows are
// the re-plan's to clear, short before or not (black-box testing: with --window and --blend given, rows a
// crashed holder had left short before the re-plan stayed short, and the first attempt counted as clean).
struct AlreadyShort {
  std::vector<char> row, motion;  // per row; per motion from row i
};
AlreadyShort already_short(const Scene& scene, const OrientedPath& original, const std::vector<const Mesh*>& extra_obstacles,
                           const PlanOptions& plan_options, const std::vector<ReplanWindow>& asked) {
  const size_t n = original.rows.size();
  const PlanObstacles obstacles = replan_obstacles(scene, extra_obstacles);
  std::vector<size_t> rows(n), motions(n > 0 ? n - 1 : 0);
  for (size_t i = 0; i < n; ++i) rows[i] = i;
  for (size_t i = 0; i + 1 < n; ++i) motions[i] = i;
  AlreadyShort a{std::vector<char>(n, 0), std::vector<char>(n, 0)};
  const std::vector<RowClearance> r = row_clearances(original, rows, scene.tool, scene.planner, obstacles);
  for (size_t i = 0; i < n; ++i) a.row[i] = r[i].margin_mm < 0.0;
  const std::vector<MotionClearance> m = motion_clearances(scene.path, original, motions, scene.tool, scene.planner, obstacles, plan_options);
  for (size_t i = 0; i + 1 < n; ++i) a.motion[i] = !m[i].clear;
  for (const ReplanWindow& w : asked)
    for (size_t i = w.first; i <= w.last && i < n; ++i) a.row[i] = a.motion[i] = 0;
  return a;
}

size_t failures(const ReplanResult& r, const AlreadyShort* already) {
  size_t f = r.unreachable.size();
  for (size_t row : r.uncleared) f += !already || !already->row[row];
  for (const auto& [row, margin] : r.uncleared_motions) f += !already || !already->motion[row];
  return f;
}
}  // namespace

ReplanResult replan(const Scene& scene, const OrientedPath& original, const std::vector<Collision>& collisions,
                    const std::vector<const Mesh*>& extra_obstacles, const PlanOptions& plan_options,
                    const ReplanOptions& options) {
  const ToolPath& path = scene.path;
  const size_t n = path.rows.size();
  if (original.rows.size() != n)
    throw InputError("", 0, "", "the oriented path has " + std::to_string(original.rows.size()) +
                                    " rows but the scene's path has " + std::to_string(n));
  ReplanResult result;
  result.path = original;
  // The scene's normals, whatever the caller attached: the windows' plans place flat and bull ends by them.
  for (size_t i = 0; i < n; ++i) {
    result.path.rows[i].n = path.rows[i].contact_normal();
    result.path.rows[i].approach = path.rows[i].approach;
  }
  if (collisions.empty() || n == 0) return result;

  const double radius = scene.tool.radius();
  const double response = plan_options.response_length_mm > 0 ? plan_options.response_length_mm : 4.0 * radius;
  const double blend = options.blend_mm > 0 ? options.blend_mm : response;
  // The dynamics need about one response length to turn the axis; the blend comes on top.
  const double pad = (options.window_mm > 0 ? options.window_mm : response) + blend;
  const std::vector<double> arc = path.arc_length();
  // A window planned afresh can meet the old axes at its ends from the other side of an obstacle, and
  // the blend then swings through it (black-box testing: 33 degrees between two rows, through a plate a
  // whole-path plan clears). Such a result is planned again on windows twice as wide, then four times,
  // then on the whole path; the first that leaves no row or motion short is kept, else the one that
  // leaves fewest.
  // Attempts are compared by what they leave short that the original did not.
  std::optional<ReplanResult> best;
  std::optional<AlreadyShort> already;
  std::vector<ReplanWindow> last_windows, asked;
  for (int attempt = 0; attempt < 4; ++attempt) {
    ReplanResult r = result;
    r.windows = windows_for(path, original, arc, scene.tool, collisions, attempt < 3 ? pad * double(1 << attempt) : kInfinity);
    const auto same = [](const ReplanWindow& a, const ReplanWindow& b) { return a.first == b.first && a.last == b.last; };
    if (best && std::equal(r.windows.begin(), r.windows.end(), last_windows.begin(), last_windows.end(), same)) continue;
    last_windows = r.windows;
    if (attempt == 0) asked = r.windows;
    plan_windows(scene, original, extra_obstacles, plan_options, arc, blend, r);
    r.widened = attempt;
    if (!options.widen || failures(r, nullptr) == 0) return r;
    if (!already) already = already_short(scene, result.path, extra_obstacles, plan_options, asked);
    // No early stop on a result that leaves only rows short before the re-plan: wider windows may clear
    // them (black-box testing: --window 0.5 --blend 0.1 stopped twice as wide, rows below the clearance).
    if (!best || failures(r, &*already) < failures(*best, &*already)) best = std::move(r);
  }
  return *best;
}

}  // namespace tf
