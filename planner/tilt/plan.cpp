// The planning job: frames, nominal axes, the chosen method, guarantees, smoothing, metrics.
#include "tiltfield/tilt/plan.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <thread>

#include "dynamics.hpp"
#include "inside_solids.hpp"
#include "plan_context.hpp"
#include "tiltfield/core/angles.hpp"

namespace tf {
using Eigen::Vector3d;

namespace {
// Reported clearance when there is nothing to collide with (no check surfaces): JSON and CSV want a number.
constexpr double kNoObstacle = kNoObstacleClearance;

double finite_or(double v, double fallback) { return std::isfinite(v) ? v : fallback; }
}  // namespace

void axis_metrics(const OrientedPath& path, PlanMetrics& m) {
  const auto& r = path.rows;
  m.max_step_deg = 0;
  m.max_deg_per_mm = 0;
  double sum = 0;
  size_t count = 0;
  for (size_t i = 1; i < r.size(); ++i) {
    const double ang = std::acos(std::clamp(r[i].axis.dot(r[i - 1].axis), -1.0, 1.0)) / kDeg;
    m.max_step_deg = std::max(m.max_step_deg, ang);
    const double ds = (r[i].p - r[i - 1].p).norm();
    if (ds > 1e-9) m.max_deg_per_mm = std::max(m.max_deg_per_mm, ang / ds);
    if (i + 1 < r.size()) {
      sum += (r[i - 1].axis - 2 * r[i].axis + r[i + 1].axis).squaredNorm();
      ++count;
    }
  }
  m.rms_second_difference = count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

namespace {

// Appends each stage's wall time, counted from the end of the previous one, to PlanMetrics::stage_seconds.
class StageClock {
 public:
  explicit StageClock(PlanMetrics& metrics) : metrics_(metrics) {}

  void operator()(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    metrics_.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }
  double total_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  PlanMetrics& metrics_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_ = start_;
};

// Per row: the local frame, the arc length, the nominal axis and the feed (the row's own, else the job's).
void set_up_rows(PlanContext& ctx, const ToolPath& path, const Tool& tool, const PlannerBasics& basics, double feed,
                 const PlanOptions& options) {
  const size_t n = path.rows.size();
  ctx.path = &path;
  ctx.tool = &tool;
  ctx.basics = basics;
  ctx.options = options;
  ctx.cos_max_tilt = std::cos(basics.max_tilt_deg * kDeg);
  ctx.frames = local_frames(path);
  ctx.arc = path.arc_length();
  ctx.nominal.resize(n);
  ctx.feed.resize(n);
  for (size_t i = 0; i < n; ++i) {
    ctx.nominal[i] = axis_from_lead_tilt(ctx.frames[i], basics.lead_deg, basics.tilt_deg);
    ctx.feed[i] = std::isfinite(path.rows[i].feed) ? path.rows[i].feed : feed;
  }
}

// Only a limit can leave an axis without a joint solution: a limited axis (rotary, or linear: the tip's
// X Y Z move with the tilt on most machines), or a 3-axis machine, which cannot tilt at all.
bool has_limits(const MachineSpec& machine) {
  if (machine.kinematics == KinematicsType::XYZ) return true;
  bool limited = false;
  for (const auto& [letter, limit] : machine.limits) limited |= std::isfinite(limit.min) || std::isfinite(limit.max);
  return limited;
}

// The tool's pieces, and the kinematics when reachability matters.
void set_up_body(PlanContext& ctx, const Tool& tool, const PlannerBasics& basics, const MachineSpec* machine) {
  ctx.pieces = body_pieces(tool);
  std::vector<double> required;
  for (const auto& p : ctx.pieces) required.push_back(required_clearance(basics, p.component));
  // Pieces are merged only where their check-surface clearances agree; the fixture clearance is one value.
  merge_coaxial_pieces(ctx.pieces, required);
  for (const BodyPiece& p : ctx.pieces) ctx.reach.push_back(body_reach(p));
  ctx.obstacles.resize(2);
  ctx.obstacles[0].required = std::move(required);
  ctx.obstacles[1].name = "fixtures";
  ctx.obstacles[1].required.assign(ctx.pieces.size(), fixture_clearance(basics));
  if (machine && has_limits(*machine)) ctx.kinematics.emplace(*machine, tool.length);
}

void set_up_obstacles(PlanContext& ctx, const PlanObstacles& obstacles, PlanMetrics& metrics) {
  ctx.obstacles[0].bvh = ClearanceBvh(obstacles.check_surfaces);
  ctx.obstacles[1].bvh = ClearanceBvh(obstacles.fixtures);
  metrics.check_triangles = ctx.obstacles[0].bvh.size();
  metrics.fixture_triangles = ctx.obstacles[1].bvh.size();
  std::vector<Vector3d> cl;
  for (const CLPoint& r : ctx.path->rows) cl.push_back(r.p);
  ctx.inside_solid = points_inside_solids({obstacles.check_surfaces, obstacles.fixtures}, cl);
}

// Closed meshes whose faces point inward are taken as open sheets (distances only): a path buried in one
// had planned clear with no word (black-box testing). Named in the notes, with what to do.
void note_inward_solids(const PlanObstacles& obstacles, std::vector<std::string>& notes) {
  const std::pair<const char*, const std::vector<const Mesh*>*> sets[] = {{"check_surfaces", &obstacles.check_surfaces},
                                                                           {"fixtures", &obstacles.fixtures}};
  for (const auto& [name, meshes] : sets)
    for (size_t k = 0; k < meshes->size(); ++k) {
      const Mesh& m = *(*meshes)[k];
      if (m.n_faces() > 0 && is_closed(m) && signed_volume(m) < 0.0)
        notes.push_back(std::string(name) + "[" + std::to_string(k) +
                        "] is closed but its faces point inward: it is taken as an open sheet (distances only, no "
                        "inside); flip its faces to make it a solid");
    }
}

// Rows whose cutter location lies inside a solid obstacle, named in the notes (the first of each set).
void note_rows_inside_solids(const PlanContext& ctx, std::vector<std::string>& notes) {
  for (size_t s = 0; s < ctx.obstacles.size(); ++s) {
    size_t count = 0, first = 0;
    for (size_t i = ctx.inside_solid.size(); i-- > 0;)
      if (ctx.inside_solid[i] == static_cast<int8_t>(s)) ++count, first = i;
    if (count > 0)
      notes.push_back(std::to_string(count) + " row(s) have the cutter location inside a closed mesh of " +
                      ctx.obstacles[s].name + " (first: row " + std::to_string(first) +
                      "): the whole tool is in that solid, no tool axis clears them");
  }
}

// How many rows the nominal axis leaves too close (for the report).
size_t count_nominal_colliding(const PlanContext& ctx) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, ctx.nominal.size(), 64), size_t{0},
      [&](const tbb::blocked_range<size_t>& r, size_t acc) {
        ClearanceHints hints;
        for (size_t i = r.begin(); i != r.end(); ++i) acc += ctx.clears(i, ctx.nominal[i], 0.0, &hints) ? 0 : 1;
        return acc;
      },
      std::plus<size_t>());
}

// The baseline: every row's axis on its own, then the exact clearances of all rows.
void pointwise_stages(const PlanContext& ctx, const Progress& progress, StageClock& stage, PlanMetrics& metrics,
                      std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear) {
  metrics.rows_nominal_colliding = count_nominal_colliding(ctx);
  stage("nominal_check");
  metrics.method = "pointwise";
  axes = pointwise_axes(ctx, progress);
  report(progress, "plan", 0.7);
  stage("axes");
  clear = all_clearances(ctx, axes);
  stage("clearance");
}

// Builds in parallel the bricks the nominal poses will need: around every chunk of the body that is
// within `reach` of an obstacle of `bvh`, at rows about a brick apart.
void prefetch_nominal_bricks(const PlanContext& ctx, const ClearanceBvh& bvh, const BodySamples& samples, double reach,
                             DistanceField& field) {
  const size_t n = ctx.path->rows.size();
  std::vector<Vector3d> centres;
  const double brick = DistanceField::kBrick * field.cell();
  double next = 0;
  for (size_t i = 0; i < n; ++i) {
    if (ctx.arc[i] < next && i + 1 != n) continue;
    next = ctx.arc[i] + 0.5 * brick;
    for (const auto& ch : samples.chunks) centres.push_back(ctx.cutter_location(i, ctx.nominal[i]) + ch.hc * ctx.nominal[i]);
  }
  std::vector<char> near(centres.size(), 0);
  tbb::parallel_for(size_t{0}, centres.size(), [&](size_t k) {
    const auto& ch = samples.chunks[k % samples.chunks.size()];
    near[k] = bvh.closest(centres[k], reach + ch.rho).triangle >= 0 ? 1 : 0;
  });
  std::vector<Vector3d> wanted;
  for (size_t k = 0; k < centres.size(); ++k)
    if (near[k]) wanted.push_back(centres[k]);
  double rho = 0;
  for (const auto& ch : samples.chunks) rho = std::max(rho, ch.rho);
  field.prefetch(wanted, rho + field.cell());
}

// What the integration shares with the thread that computes clearances behind it.
struct ClearingBehind {
  std::atomic<size_t> published{0}, cleared{0};
  std::atomic<bool> stop{false};
  double nominal_seconds = 0;
};

// The background thread: counts the nominal collisions, then clears the rows the integration has
// published, a block at a time, until stopped.
void clear_behind(const PlanContext& ctx, const std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear,
                  PlanMetrics& metrics, ClearingBehind& shared) {
  const auto t = std::chrono::steady_clock::now();
  metrics.rows_nominal_colliding = count_nominal_colliding(ctx);
  shared.nominal_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  constexpr size_t kBlock = 256;
  ClearanceHints hints;
  size_t next = 0;
  while (!shared.stop.load(std::memory_order_acquire)) {
    if (shared.published.load(std::memory_order_acquire) < next + kBlock) {
      std::this_thread::sleep_for(std::chrono::microseconds(100));
      continue;
    }
    for (size_t i = next; i < next + kBlock; ++i) clear[i] = ctx.clearance(i, axes[i], &hints);
    next += kBlock;
    shared.cleared.store(next, std::memory_order_release);
  }
}

// Whatever way the integration ends (a progress callback may throw), the background stops first.
struct StopAndJoin {
  std::atomic<bool>& stop;
  tbb::task_group& group;
  bool waited = false;
  void wait() {
    stop.store(true, std::memory_order_release);
    waited = true;
    group.wait();
  }
  ~StopAndJoin() {
    if (waited) return;
    stop.store(true, std::memory_order_release);
    try {
      group.wait();
    } catch (...) {
    }
  }
};

// The dynamics are sequential along the path. Meanwhile another thread counts the nominal collisions,
// then computes the exact clearances of the rows the integration has finished; what it has not reached
// when the dynamics end is done in parallel afterwards.
void integrate_and_clear(const PlanContext& ctx, const std::vector<PotentialSource>& sources, const Progress& progress,
                         StageClock& stage, PlanMetrics& metrics, std::vector<Vector3d>& axes,
                         std::vector<BodyClearance>& clear) {
  const size_t n = ctx.path->rows.size();
  axes.resize(n);
  clear.resize(n);
  ClearingBehind shared;
  tbb::task_group background;
  background.run([&] { clear_behind(ctx, axes, clear, metrics, shared); });
  // The body turns about its cutter location; a flat or bull end's moves with the axis to keep its
  // contact, taken here at the nominal axis (the dynamics' torques ignore that motion: the clearances and
  // corrections after them are exact at each axis's own cutter location).
  ToolPath pivots;
  if (!std::holds_alternative<BallCutter>(ctx.tool->cutter)) {
    pivots = *ctx.path;
    for (size_t i = 0; i < n; ++i) pivots.rows[i].p = ctx.cutter_location(i, ctx.nominal[i]);
  }
  {
    StopAndJoin join{shared.stop, background};
    integrate_axes(pivots.rows.empty() ? *ctx.path : pivots, ctx.frames, ctx.nominal, ctx.feed, sources,
                   dynamics_params(ctx.options, *ctx.tool, ctx.basics), progress, axes, &shared.published);
    report(progress, "plan", 0.7);
    stage("axes");
    join.wait();
  }
  clearances(ctx, axes, shared.cleared.load(std::memory_order_acquire), n, clear);
  stage("clearance");
  // Ran alongside "axes" (and is part of it in wall time).
  metrics.stage_seconds.emplace_back("nominal_check", shared.nominal_seconds);
}

// The rigid-body model: per obstacle set the distance field it feels (the samples keeping that set's
// clearances), then the integration along the path.
void dynamic_stages(const PlanContext& ctx, const Progress& progress, StageClock& stage, PlanMetrics& metrics,
                    std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear) {
  const PlanOptions& options = ctx.options;
  metrics.method = "dynamic";
  const BodySamples check_samples = make_body_samples(*ctx.tool, ctx.basics, options.sample_spacing_mm);
  const BodySamples fixture_samples = with_clearance(check_samples, fixture_clearance(ctx.basics));
  std::vector<std::unique_ptr<DistanceField>> fields;
  std::vector<PotentialSource> sources;
  for (size_t s = 0; s < ctx.obstacles.size(); ++s) {
    const ObstacleSet& set = ctx.obstacles[s];
    if (set.bvh.empty() && s > 0) continue;  // the check set always runs, as before: it may be empty
    const BodySamples& samples = s == 0 ? check_samples : fixture_samples;
    double max_req = 0;
    for (double r : set.required) max_req = std::max(max_req, r);
    fields.push_back(std::make_unique<DistanceField>(set.bvh, options.field_cell_mm,
                                                     options.influence_mm + max_req + 2 * options.field_cell_mm));
    prefetch_nominal_bricks(ctx, set.bvh, samples, options.influence_mm + max_req, *fields.back());
    sources.push_back({&set.bvh, fields.back().get(), &samples});
  }
  stage("field");
  report(progress, "plan", 0.1);
  integrate_and_clear(ctx, sources, progress, stage, metrics, axes, clear);
}

// The corrections, the bridges over motions that cross an obstacle and, after the dynamics, the fall-back
// to the baseline's axes. Counts the rows they changed; notes say which last resort acted. Returns the
// motions' checks at the axes they leave.
std::vector<SegmentCheck> guarantee_stages(const PlanContext& ctx, const Progress& progress,
                                           std::vector<Vector3d>& axes, std::vector<BodyClearance>& clear,
                                           PlanResult& result) {
  std::vector<std::string>& notes = result.notes;
  const std::vector<Vector3d> planned = axes;
  std::vector<SegmentCheck> segments = enforce_clearance(ctx, axes, clear, progress);
  if (const size_t bridged = bridge_failing_motions(ctx, axes, clear, segments))
    notes.push_back(std::to_string(bridged) +
                    " motion(s) between rows crossed an obstacle: one side was followed until the motion back was "
                    "clear");
  if (ctx.options.method == PlanMethod::Dynamic) {
    const FallbackResult fb = fall_back_to_pointwise(ctx, axes, clear, segments);
    if (fb.failing + fb.whipping > 0)
      notes.push_back("the dynamics and corrections left " + std::to_string(fb.failing) + " row(s) failing and " +
                      std::to_string(fb.whipping) +
                      " row(s) at a whipping turn: the pointwise axes were blended in around them");
  }
  const FallbackResult cone = fall_back_to_cone_search(ctx, axes, clear, segments);
  if (cone.failing + cone.whipping > 0)
    notes.push_back("the stages before left " + std::to_string(cone.failing) + " row(s) failing and " +
                    std::to_string(cone.whipping) +
                    " row(s) at a whipping turn: the smoothest clear axes in the max-tilt cone were searched around "
                    "them");
  result.metrics.corrected_rows = 0;
  for (size_t i = 0; i < axes.size(); ++i) result.metrics.corrected_rows += axes[i] != planned[i] ? 1 : 0;
  return segments;
}

void note_axis_limits(const PlanContext& ctx, const MachineSpec* machine, std::vector<std::string>& notes) {
  if (!machine)
    notes.emplace_back("no machine: only max_tilt_deg limits the axis");
  else if (!ctx.kinematics)
    notes.emplace_back("the machine has no axis limits: only max_tilt_deg limits the axis");
  else if (machine->kinematics == KinematicsType::XYZ)
    notes.emplace_back("3-axis machine: a row whose axis is not vertical has no joint solution");
}

// The oriented rows, the rows left below their clearance or without a joint solution, and the summary metrics.
void write_result(const PlanContext& ctx, const std::vector<Vector3d>& axes, const std::vector<BodyClearance>& clear,
                  const std::vector<SegmentCheck>& segments, PlanResult& result) {
  const ToolPath& path = *ctx.path;
  const size_t n = path.rows.size();
  std::vector<char> unreachable(n, 0);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) { unreachable[i] = ctx.reachable(i, axes[i]) ? 0 : 1; });

  result.path.rows.resize(n);
  double min_c = std::numeric_limits<double>::infinity();
  auto set_name = [&](int s) { return s < 0 ? std::string() : std::string(ctx.obstacles[static_cast<size_t>(s)].name); };
  for (size_t i = 0; i < n; ++i) {
    OrientedRow& o = result.path.rows[i];
    o.p = path.rows[i].p;
    o.n = path.rows[i].contact_normal();
    o.approach = path.rows[i].approach;
    o.axis = axes[i].normalized();
    const Eigen::Vector2d lt = lead_tilt_from_axis(ctx.frames[i], o.axis);
    o.lead_deg = lt.x();
    o.tilt_deg = lt.y();
    o.clearance_mm = finite_or(clear[i].distance, kNoObstacle);
    o.feed = path.rows[i].feed;
    if (o.clearance_mm < min_c) {
      min_c = o.clearance_mm;
      if (clear[i].nearest_set >= 0) result.metrics.min_clearance_obstacle = set_name(clear[i].nearest_set);
    }
    const bool motion = i < segments.size() && segments[i].failed;
    const bool row_clear = clear[i].margin >= 0;
    const std::string motion_set = motion ? set_name(segments[i].set >= 0 ? segments[i].set : clear[i].margin_set) : "";
    if (!row_clear || unreachable[i] || motion)
      result.uncleared.push_back({i, o.clearance_mm, row_clear && motion ? -segments[i].deficit : clear[i].margin,
                                  row_clear && motion ? motion_set : set_name(clear[i].margin_set), unreachable[i] != 0,
                                  row_clear && motion});
    // A row below its clearance whose motion to the next comes lower still: both are listed.
    if (!row_clear && motion) result.uncleared.push_back({i, o.clearance_mm, -segments[i].deficit, motion_set, false, true});
    result.metrics.segments_below_safety += motion ? 1 : 0;
  }
  result.metrics.rows = n;
  result.metrics.min_clearance_mm = n ? min_c : kNoObstacle;
  result.metrics.rows_below_safety = 0;
  for (const auto& u : result.uncleared) result.metrics.rows_below_safety += u.margin_mm < 0 && !u.between_rows ? 1 : 0;
  axis_metrics(result.path, result.metrics);
}
}  // namespace

namespace {
// The end form's dips on the axes the stages leave: rows turned out of the design where the machine can
// tilt (the motions checked again), the rest counted and noted.
void settle_end_form(const PlanContext& ctx, bool may_turn, std::vector<Vector3d>& axes,
                     std::vector<BodyClearance>& clear, std::vector<SegmentCheck>& segments, PlanResult& result) {
  const EndDips dips = settle_end_dips(ctx, axes, clear, may_turn);
  if (dips.turned > 0) segments = check_segments(ctx, axes, clear);
  PlanMetrics& m = result.metrics;
  m.rows_end_turned = dips.turned;
  m.rows_end_dipping = dips.dipping;
  m.max_end_dip_mm = dips.max_dip_mm;
  if (dips.turned > 0)
    result.notes.push_back(std::to_string(dips.turned) +
                           " row(s) dipped the end below the design surface after the stages: their lead was changed");
  if (dips.dipping > 0)
    result.notes.push_back(std::to_string(dips.dipping) + " row(s) dip the end below the design surface by up to " +
                           std::to_string(dips.max_dip_mm) + " mm (first: row " + std::to_string(dips.first) + ")");
}

// A 3-axis machine has one tool axis: every row takes it, and a row it does not clear is reported. The
// stages search other axes, none of them reachable, and met the vertical only where a ring sample fell on
// it: a slope crossed diagonally left every row "unreachable" (black-box testing).
std::vector<SegmentCheck> fixed_axis_stages(const PlanContext& ctx, std::vector<Vector3d>& axes,
                                            std::vector<BodyClearance>& clear) {
  const size_t n = ctx.path->rows.size();
  const Vector3d axis = ctx.kinematics ? ctx.kinematics->forward(Joints{}).axis.normalized() : Vector3d::UnitZ();
  axes.assign(n, axis);
  clear.resize(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) { clear[i] = ctx.clearance(i, axis); });
  return check_segments(ctx, axes, clear);
}
}  // namespace

PlanResult plan_path(const ToolPath& path, const Tool& tool, const PlanObstacles& obstacles,
                     const PlannerBasics& basics, double feed, const PlanOptions& options, const MachineSpec* machine,
                     const Progress& progress) {
  PlanResult result;
  StageClock stage(result.metrics);
  PlanContext ctx;
  set_up_rows(ctx, path, tool, basics, feed, options);
  set_up_body(ctx, tool, basics, machine);
  report(progress, "plan", 0.0);
  set_up_obstacles(ctx, obstacles, result.metrics);
  note_rows_inside_solids(ctx, result.notes);
  note_inward_solids(obstacles, result.notes);
  set_up_end_form(ctx, obstacles.design);
  const bool fixed_axis = machine && machine->kinematics == KinematicsType::XYZ;
  if (!fixed_axis) result.metrics.rows_lead_raised = lead_nominal_out_of_design(ctx, result.notes);
  stage("bvh");
  report(progress, "plan", 0.05);

  std::vector<Vector3d> axes;
  std::vector<BodyClearance> clear;
  std::vector<SegmentCheck> segments;
  if (fixed_axis) {
    segments = fixed_axis_stages(ctx, axes, clear);
  } else {
    if (options.method == PlanMethod::Pointwise)
      pointwise_stages(ctx, progress, stage, result.metrics, axes, clear);
    else
      dynamic_stages(ctx, progress, stage, result.metrics, axes, clear);
    report(progress, "plan", 0.8);
    segments = guarantee_stages(ctx, progress, axes, clear, result);
  }
  stage("corrections");
  if (options.smooth && !fixed_axis) {
    result.metrics.smoothed = smooth_axes(ctx, axes, clear);
    if (!result.metrics.smoothed)
      result.notes.emplace_back("smoothing: Ceres did not converge, the unsmoothed axes are kept");
    stage("smoothing");
    segments = check_segments(ctx, axes, clear);  // the smoothing moved the axes
  }
  settle_end_form(ctx, !fixed_axis, axes, clear, segments, result);
  stage("end_form");
  note_axis_limits(ctx, machine, result.notes);
  check_segments_beside_failing_rows(ctx, axes, clear, segments);
  stage("between_rows");
  write_result(ctx, axes, clear, segments, result);
  result.metrics.seconds = stage.total_seconds();
  report(progress, "plan", 1.0);
  return result;
}

std::vector<MotionClearance> motion_clearances(const ToolPath& path, const OrientedPath& oriented,
                                               const std::vector<size_t>& rows, const Tool& tool,
                                               const PlannerBasics& basics, const PlanObstacles& obstacles,
                                               const PlanOptions& options) {
  if (oriented.rows.size() != path.rows.size()) throw std::invalid_argument("motion_clearances: row counts differ");
  PlanContext ctx;
  set_up_rows(ctx, path, tool, basics, 0.0, options);
  set_up_body(ctx, tool, basics, nullptr);
  PlanMetrics metrics;
  set_up_obstacles(ctx, obstacles, metrics);
  std::vector<MotionClearance> out(rows.size());
  tbb::parallel_for(size_t{0}, rows.size(), [&](size_t k) {
    const size_t i = rows[k];
    if (i + 1 >= path.rows.size()) return;
    const Vector3d a0 = oriented.rows[i].axis.normalized(), a1 = oriented.rows[i + 1].axis.normalized();
    const BodyClearance c0 = ctx.clearance(i, a0), c1 = ctx.clearance(i + 1, a1);
    SegmentCheck s = check_segment(ctx, i, a0, a1, c0, c1);
    if (!s.failed) s = check_segment_beside_failing_rows(ctx, i, a0, a1, c0, c1);
    if (s.failed) out[k] = {false, -s.deficit};
  });
  return out;
}

size_t uncleared_row_count(const std::vector<UnclearedRow>& uncleared) {
  std::vector<size_t> rows;
  for (const UnclearedRow& u : uncleared) rows.push_back(u.row);
  std::sort(rows.begin(), rows.end());
  return static_cast<size_t>(std::unique(rows.begin(), rows.end()) - rows.begin());
}

PlanObstacles scene_obstacles(const Scene& scene) {
  PlanObstacles o;
  if (scene.design.n_faces() > 0) o.design.push_back(&scene.design);
  for (const auto& m : scene.check_surfaces) o.check_surfaces.push_back(&m);
  for (const auto& m : scene.fixtures) o.fixtures.push_back(&m);
  return o;
}

PlanResult plan(const Scene& scene, const PlanOptions& options, const Progress& progress) {
  return plan_path(scene.path, scene.tool, scene_obstacles(scene), scene.planner, scene.feed, options,
                   scene.machine ? &*scene.machine : nullptr, progress);
}

nlohmann::json plan_report_json(const PlanResult& r) {
  const auto& m = r.metrics;
  nlohmann::json j;
  j["method"] = m.method;
  j["smoothed"] = m.smoothed;
  j["rows"] = m.rows;
  j["min_clearance_mm"] = m.min_clearance_mm;
  j["min_clearance_obstacle"] = m.min_clearance_obstacle;
  j["obstacles"] = {{"check_surface_triangles", m.check_triangles}, {"fixture_triangles", m.fixture_triangles}};
  j["rows_below_safety"] = m.rows_below_safety;
  j["rows_nominal_colliding"] = m.rows_nominal_colliding;
  j["corrected_rows"] = m.corrected_rows;
  j["segments_below_safety"] = m.segments_below_safety;
  j["end_form"] = {{"rows_lead_raised", m.rows_lead_raised},
                   {"rows_turned", m.rows_end_turned},
                   {"rows_dipping", m.rows_end_dipping},
                   {"max_dip_mm", m.max_end_dip_mm}};
  j["max_step_deg"] = m.max_step_deg;
  j["max_deg_per_mm"] = m.max_deg_per_mm;
  j["rms_second_difference"] = m.rms_second_difference;
  j["seconds"] = m.seconds;
  nlohmann::json st = nlohmann::json::object();
  for (const auto& [k, v] : m.stage_seconds) st[k] = v;
  j["stage_seconds"] = st;
  nlohmann::json un = nlohmann::json::array();
  for (const auto& u : r.uncleared)
    un.push_back({{"row", u.row},
                  {"clearance_mm", u.clearance_mm},
                  {"margin_mm", u.margin_mm},
                  {"obstacle", u.obstacle},
                  {"unreachable", u.unreachable},
                  {"between_rows", u.between_rows}});
  j["uncleared"] = un;
  j["notes"] = r.notes;
  return j;
}

}  // namespace tf
