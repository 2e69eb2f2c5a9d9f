// The block loop of the verifier, per block: the swept parts, the lattice tiles they can touch, the
// engagement, and the collision, gouge and removal bookkeeping. The work per tile and ray, in parallel
// over tiles, is in simulate_tile.cpp.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <sstream>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "axis_limits.hpp"
#include "ray_depths.hpp"
#include "simulator.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {

ToolPose forward_xyz(const Joints& j) { return {Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d::UnitZ()}; }

namespace sim {

namespace {

// The axes a reference return left unknown: where the block goes in them (Block::from_reference).
Joints from_reference(const Block& b, Joints from) {
  for (int a = 0; a < 6; ++a)
    if (b.from_reference & (1u << a)) from.axis(a) = b.target.axis(a);
  return from;
}

}  // namespace


Simulator::Simulator(const Scene& scene, const Program& program, const ForwardFn& forward, const VerifyOptions& options)
    : scene_(scene), program_(program), opt_(options), lattice_(make_lattice(scene, options.resolution)),
      stock_(make_stock(scene.stock, lattice_)), tools_(scene, forward, options.sweep) {
  for (const Mesh& m : scene.fixtures)
    obstacles_.push_back({std::make_unique<RayTable>(m, lattice_), HitWith::Fixture, {}});
  for (const Mesh& m : scene.check_surfaces)
    obstacles_.push_back({std::make_unique<RayTable>(m, lattice_), HitWith::Check, {}});
  for (Obstacle& o : obstacles_) {
    o.ext = RayExtents(lattice_);
    o.ext.refresh_all([&](int d, int iu, int iv) { return obstacle_range(*o.table, d, iu, iv); });
  }
  if (options.check_gouges && scene.design.n_faces() > 0) {
    design_ = std::make_unique<RayTable>(scene.design, lattice_);
    design_mesh_ = std::make_unique<RayMesh>(scene.design);
  }
  inv_h_ = 1.0 / lattice_.h;
  ext_ = RayExtents(lattice_);
  ext_.refresh_all([&](int d, int iu, int iv) { return material_range(stock_.ray(d, iu, iv)); });
  for (int d = 0; d < 3; ++d) {
    stamp_[d].assign(size_t(ext_.tiles_u(d)) * ext_.tiles_v(d), 0);
    task_of_[d].assign(stamp_[d].size(), -1);
  }
  if (options.record_last_block)
    for (int d = 0; d < 3; ++d) last_block_[d].assign(stock_.grid(d).size(), 0);
}

VerifyResult Simulator::run() {
  const auto t_start = std::chrono::steady_clock::now();
  VerifyReport rep;
  rep.resolution_mm = lattice_.h;
  rep.sweep_tolerance_mm = opt_.sweep.tolerance;
  rep.holder_tolerance_mm = opt_.sweep.holder_tolerance;
  rep.gouge_tolerance_mm = opt_.gouge_tolerance;
  rep.collision_tolerance_mm = opt_.collision_tolerance;
  rep.rays = stock_.ray_count();
  rep.material_rays = stock_.material_rays();
  rep.stock_volume_start_mm3 = stock_.volume();
  rep.warnings = program_.warnings;
  // emplace_back: push_back of the literal trips a GCC 12 array-bounds false positive.
  if (scene_.design.n_faces() == 0) {
    rep.design_checked = false;
    rep.warnings.emplace_back("no design surface: gouges and excess material were not computed");
  }
  Joints from = program_.start;
  bool prev_tcp = program_.blocks.empty() ? false : program_.blocks.front().tcp;
  const size_t nb = program_.blocks.size();
  for (size_t bi = 0; bi < nb; ++bi) {
    const Block& b = program_.blocks[bi];
    // The block starts where the previous one left this tool (so its end pose's material is gone).
    bool continuing = bi > 0 && program_.blocks[bi - 1].tool == b.tool && b.from_reference == 0;
    from = block_start(bi, from);
    if (b.tcp != prev_tcp) {
      continuing = false;
      if (b.tcp) {
        const ToolPose p = tools_.forward(b.tool)(from);  // joint position -> tip in the part frame
        from.x = p.tip.x();
        from.y = p.tip.y();
        from.z = p.tip.z();
      } else {
        // The tip held where the last TCP block left it: the joints that put it there.
        const auto forward = tools_.forward(b.tool);
        from = joints_for_tip(forward, from, Eigen::Vector3d(from.x, from.y, from.z));
      }
      prev_tcp = b.tcp;
    }
    from = from_reference(b, from);
    if (scene_.machine) {
      const double nose = program_.xyz_nose_programmed && !b.tcp ? tools_.tool(b.tool).length : 0.0;
      check_axis_limits(*scene_.machine, b, from, static_cast<int>(bi) + 1, tools_.forward(b.tool), rep, nose);
    }
    BlockResult br = simulate_block(b, from, static_cast<int>(bi) + 1, continuing, rep);
    rep.per_block.push_back(br);
    rep.removed_volume_mm3 += br.removed_mm3;
    from = b.target;
    if ((bi & 255) == 0) report(opt_.progress, "verify", double(bi) / double(std::max<size_t>(nb, 1)));
    if (br.collision && opt_.stop_at_first_collision) {
      rep.stopped_early = bi + 1 < nb;
      break;
    }
  }
  for (const Accum::Span& span : pending_) apply(span);  // the last block's deferred changes
  pending_.clear();
  if (!rep.axis_limits.empty()) {
    const AxisLimitExcess& e = rep.axis_limits.front();
    rep.warnings.push_back(std::to_string(rep.axis_limits.size()) + " axis positions beyond the machine's limits (first: block " +
                           std::to_string(e.block) + ", line " + std::to_string(e.line) + ", " + std::string(1, e.axis) +
                           " " + fixed(e.value, 4) + "; axis_limits lists them)");
  }
  // A block that needed more than max_substeps sub-steps for a part reports its bound, above the tolerance.
  if (rep.sweep_error_mm > opt_.sweep.tolerance)
    rep.warnings.push_back("the swept volume's bound " + std::to_string(rep.sweep_error_mm) + " mm exceeds --tolerance " +
                           std::to_string(opt_.sweep.tolerance) + " mm: a block needed more than " +
                           std::to_string(opt_.sweep.max_substeps) + " sub-steps for a tool part (split it)");
  if (unresolved_gouges_ > 0)
    rep.warnings.push_back(std::to_string(unresolved_gouges_) + (unresolved_gouges_ == 1 ? " block" : " blocks") +
                           " over-cut the design by up to " + std::to_string(deepest_unresolved_) +
                           " mm, within the bound of the swept volume: not listed as gouges (a smaller --tolerance, "
                           "or --holder-tolerance for rapids, tells them apart)");
  rep.blocks = static_cast<int>(rep.per_block.size());
  rep.stock_volume_end_mm3 = stock_.volume();
  rep.memory_bytes = stock_.memory_bytes();
  if (design_) rep.excess = excess_left(*design_, stock_);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  report(opt_.progress, "verify", 1.0);
  return {std::move(rep), std::move(stock_), std::move(last_block_)};
}

Joints Simulator::block_start(size_t bi, Joints from) const {
  if (bi == 0) return from;
  const Block& prev = program_.blocks[bi - 1];
  const Block& b = program_.blocks[bi];
  if (prev.tool != b.tool && program_.length_offsets && (prev.tcp || program_.xyz_nose_programmed)) {
    // The tips of tool-length-offset targets: M6 moves nothing, so the nose stays and the tip moves.
    const Eigen::Vector3d axis = tools_.forward(prev.tool)(from).axis;
    const Eigen::Vector3d tip =
        Eigen::Vector3d(from.x, from.y, from.z) + (tools_.tool(prev.tool).length - tools_.tool(b.tool).length) * axis;
    from.x = tip.x();
    from.y = tip.y();
    from.z = tip.z();
  }
  return from;
}

Lattice Simulator::make_lattice(const Scene& scene, double h) {
  if (!(h > 0.0) || !std::isfinite(h)) throw InputError("", 0, "resolution", "must be a positive number of mm");
  Eigen::AlignedBox3d box;
  if (scene.stock.kind == Stock::Kind::Mesh) {
    box = bounding_box(scene.stock.mesh);
  } else if (scene.stock.kind == Stock::Kind::Box) {
    box = Eigen::AlignedBox3d(scene.stock.box.min, scene.stock.box.max);
  } else {
    const auto& c = scene.stock.cylinder;
    const Eigen::Vector3d a = c.axis.normalized();
    const Eigen::Vector3d ext = (Eigen::Vector3d::Ones() - a.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * c.radius;
    box = Eigen::AlignedBox3d(c.base - ext, c.base + ext);
    box.extend(c.base + c.height * a - ext);
    box.extend(c.base + c.height * a + ext);
  }
  if (box.isEmpty()) throw InputError(scene.file.string(), 0, "stock", "the stock is empty");
  // A lattice coarser than a quarter of the stock's thinnest side cannot hold it: at 50 mm a 60 x 40 x 20
  // block lost 30 % of its volume, at 1000 mm it gained 800 times its own (black-box testing).
  const double thinnest = box.sizes().minCoeff();
  if (h > 0.25 * thinnest)
    throw InputError("", 0, "resolution",
                     "too coarse for this stock: " + fixed(h, 4) + " mm against its thinnest side of " +
                         fixed(thinnest, 4) + " mm (at most a quarter of it, " + fixed(0.25 * thinnest, 4) + " mm)");
  for (const Mesh& m : scene.fixtures) box.extend(bounding_box(m));
  for (const Mesh& m : scene.check_surfaces) box.extend(bounding_box(m));
  const Eigen::Vector3d ext = box.sizes();
  const double nodes = (ext.x() / h + 3) * (ext.y() / h + 3) * (ext.z() / h + 3);
  const double rays = nodes / std::max({ext.x() / h + 3, ext.y() / h + 3, ext.z() / h + 3}) * 3;
  if (rays > 2e8) {
    // The lattice spans the fixtures and check surfaces too: say what it spans, or a check surface far
    // off reads as a fault of the resolution (black-box testing).
    std::ostringstream msg;
    msg << "too fine for this scene: more than 2e8 rays at " << h << " mm over the box of the stock"
        << (scene.fixtures.empty() && scene.check_surfaces.empty() ? "" : ", fixtures and check surfaces") << ", "
        << ext.x() << " x " << ext.y() << " x " << ext.z() << " mm";
    throw InputError("", 0, "resolution", msg.str());
  }
  return lattice_for(box, h, 2);
}

Simulator::PartSpan Simulator::part_span(const SweptPart& p, int d) const {
  const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
  auto first = [&](double x, int axis) {
    return static_cast<int>(
        std::clamp(std::ceil((x - lattice_.origin[axis]) / lattice_.h), 0.0, lattice_.n[axis] + 1.0));
  };
  auto last = [&](double x, int axis) {
    return static_cast<int>(
        std::clamp(std::floor((x - lattice_.origin[axis]) / lattice_.h), -1.0, lattice_.n[axis] - 1.0));
  };
  return {first(p.box.min()[u], u), last(p.box.max()[u], u), first(p.box.min()[v], v), last(p.box.max()[v], v),
          static_cast<float>(p.box.min()[d] - lattice_.origin[d]),
          static_cast<float>(p.box.max()[d] - lattice_.origin[d])};
}

BlockResult Simulator::simulate_block(const Block& b, const Joints& from, int index, bool continuing, VerifyReport& rep) {
  BlockResult br;
  br.block = index;
  block_ = static_cast<uint32_t>(index);
  br.line = b.line;
  br.tool = b.tool;
  br.dwell_minutes = b.dwell_s / 60.0;
  const PoseAt pose_at = block_pose(b, from);
  const double turn = std::max({std::abs(b.target.a - from.a), std::abs(b.target.b - from.b), std::abs(b.target.c - from.c)});
  // Before a rapid the feed's end pose is swept exactly (sweep_block, exact_end).
  const bool before_rapid = size_t(index) < program_.blocks.size() && program_.blocks[size_t(index)].motion == Motion::Rapid;
  sweep_block(pose_at, tools_.parts(b.tool), opt_.sweep, sweep_, b.motion == Motion::Rapid, turn, before_rapid);
  // A block that moves its cutting spheres along straight lines (one sub-step each) from where the
  // previous block left them finds their start empty. Not with fixtures or check surfaces: the rays inside
  // the start spheres still meet those, and every block reports its own collisions. Not a bull end's ring
  // spheres: turned about the axis from where the previous block left them.
  if (continuing && obstacles_.empty() && sweep_.substeps == 1)
    for (SweptPart& p : sweep_.parts)
      p.start_empty = p.kind == ToolPart::Kind::Sphere && !p.arc && p.cutting && p.on_axis && p.len > 0.0;
  br.substeps = sweep_.substeps;
  rep.sweep_error_mm = std::max(rep.sweep_error_mm, sweep_.cutting_error);
  rep.holder_sweep_error_mm = std::max(rep.holder_sweep_error_mm, sweep_.holder_error);
  br.path_mm = feed_path_mm(b, from);
  br.minutes = block_minutes(b, br.path_mm);
  select_tiles();
  const bool cuts = !tasks_.empty();
  attach_pending();
  const bool rapid = b.motion == Motion::Rapid;
  br.rapid = rapid;
  br.feed = b.feed;
  br.feed_mode = b.feed_mode;
  const bool engagement = opt_.engagement && !rapid && cuts;
  defer_ = engagement;
  if (engagement) engagement_reads(tools_.tool(b.tool), pose_at(1.0));
  for (auto& a : accum_) a.reset();
  tbb::parallel_for(size_t(0), tasks_.size(), [&](size_t k) { process_tile(tasks_[k], rapid, accum_.local()); });
  collect_pending();
  if (engagement) measure_block_engagement(tools_.tool(b.tool), pose_at, b.motion == Motion::ArcCW || b.motion == Motion::ArcCCW, br, rep);

  BlockTotals tot = merged_totals();
  if (!rapid) add_ordered_depths(b, pose_at, turn, tot.depth);
  br.removed_mm3 = (tot.removed[0] + tot.removed[1] + tot.removed[2]) / 3.0 * lattice_.h * lattice_.h;
  report_collisions(tot.depth, b, index, pose_at, br, rep);
  if (tot.gouge > 0) {
    rep.max_gouge_mm = std::max(rep.max_gouge_mm, tot.gouge);
    // The swept parts hold the true tool within the block's bound, and may reach that far beyond it: an
    // over-cut within the bound may be the sweep's and is only counted (a warning after the run). A
    // rapid's cutting parts are swept to the holder's bound.
    const double bound = rapid ? std::max(sweep_.cutting_error, sweep_.holder_error) : sweep_.cutting_error;
    if (tot.gouge > std::max(opt_.gouge_tolerance, bound)) {
      rep.gouges.push_back({index, b.line, tot.gouge});
    } else if (tot.gouge > opt_.gouge_tolerance) {
      ++unresolved_gouges_;
      deepest_unresolved_ = std::max(deepest_unresolved_, tot.gouge);
    }
  }
  return br;
}

// The tool's pose at time tau of the block. Under tool-centre-point control the block moves the tip in
// the part frame, and the joints give only the axis.
PoseAt Simulator::block_pose(const Block& b, const Joints& from) const {
  const bool tcp = b.tcp;
  const ForwardFn& forward = tools_.forward(b.tool);
  return [&forward, &b, &from, tcp](double tau) {
    const Joints j = interpolate_block(from, b, tau);
    if (!tcp) return forward(j);
    Joints rot = j;
    rot.x = rot.y = rot.z = 0.0;
    ToolPose p = forward(rot);
    p.tip = Eigen::Vector3d(j.x, j.y, j.z);
    return p;
  };
}

// The spans and shadows of the block's swept parts, and the tiles any part can touch (tasks_, each once:
// stamp_ marks the tiles taken for this block).
void Simulator::select_tiles() {
  ++stamp_value_;
  tasks_.clear();
  spans_.resize(sweep_.parts.size() * 3);
  shadows_.resize(sweep_.parts.size() * 3);
  for (size_t i = 0; i < sweep_.parts.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      spans_[i * 3 + d] = part_span(sweep_.parts[i], d);
      shadows_[i * 3 + d] = make_shadow(sweep_.parts[i], d, Lattice::u_axis(d));
    }
  for (size_t i = 0; i < sweep_.parts.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      const PartSpan& sp = span(static_cast<int>(i), d);
      if (sp.u1 < sp.u0 || sp.v1 < sp.v0) continue;
      for (int tv = sp.v0 / kTile; tv <= sp.v1 / kTile; ++tv)
        for (int tu = sp.u0 / kTile; tu <= sp.u1 / kTile; ++tu) {
          uint32_t& s = stamp_[d][size_t(tv) * ext_.tiles_u(d) + tu];
          if (s == stamp_value_ || !relevant(static_cast<int>(i), d, tu, tv)) continue;
          s = stamp_value_;
          task_of_[d][size_t(tv) * ext_.tiles_u(d) + tu] = static_cast<int>(tasks_.size());
          tasks_.push_back({d, tu, tv});
        }
    }
}

// Engagement is measured on the stock before this block removed anything (the in-process workpiece the
// tool meets at the block's end), and only where the block removed material next to the tool's end pose:
// there the cut deferred its changes, so the measurement reads the stock itself. A block that removed
// nothing there engaged nothing and costs nothing here.
void Simulator::measure_block_engagement(const Tool& tool, const PoseAt& pose_at, bool arc, BlockResult& br,
                                         VerifyReport& rep) {
  Eigen::AlignedBox3d removed;
  removed.setEmpty();
  for (const Accum& a : accum_)
    for (int d = 0; d < 3; ++d) {
      const Accum::GridBox& b = a.removed_box[d];
      if (!(b.t1 >= b.t0)) continue;
      Eigen::Vector3d lo, hi;
      lo[d] = b.t0, hi[d] = b.t1;
      lo[Lattice::u_axis(d)] = b.u0, hi[Lattice::u_axis(d)] = b.u1;
      lo[Lattice::v_axis(d)] = b.v0, hi[Lattice::v_axis(d)] = b.v1;
      removed.extend(lo);
      removed.extend(hi);
    }
  if (removed.isEmpty()) return;
  const auto t0 = std::chrono::steady_clock::now();
  // The velocity at the block's end, over the last quarter of a sub-step: long enough that a point's motion
  // stays far above the poses' rounding on short blocks. An arc is swept in one step, and a quarter of it had
  // turned its feed direction by an eighth of its sweep, and its engagement with it (black-box testing): an
  // arc's step is 1e-4 of it, where the chord is the tangent within 0.005 % of the sweep.
  const double back = arc ? 1e-4 : 1.0 / (4.0 * std::max(1, sweep_.substeps));
  br.engagement = opt_.engagement(tool, stock_, pose_at(1.0 - back), pose_at(1.0),
                                  Eigen::AlignedBox3d(removed.min() + lattice_.origin, removed.max() + lattice_.origin));
  rep.engagement_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The tasks for the tiles where the previous block deferred changes (pending_): the block's own task for
// the tile, or a task that only makes them.
void Simulator::attach_pending() {
  for (size_t k = 0; k < pending_.size(); ++k) {
    const Accum::Span& p = pending_[k];
    const size_t tile = size_t(p.tv) * ext_.tiles_u(p.d) + p.tu;
    if (stamp_[p.d][tile] != stamp_value_) {
      stamp_[p.d][tile] = stamp_value_;
      task_of_[p.d][tile] = static_cast<int>(tasks_.size());
      tasks_.push_back({p.d, p.tu, p.tv, false});
    }
    tasks_[size_t(task_of_[p.d][tile])].pending = static_cast<int>(k);
  }
}

// After the block's tasks: the previous block's changes are made, so its lists are emptied, and this
// block's deferred spans become the next block's pending_.
void Simulator::collect_pending() {
  pending_.clear();
  for (Accum& a : accum_) {
    a.lists[(block_ + 1) & 1].clear();
    pending_.insert(pending_.end(), a.spans.begin(), a.spans.end());
  }
}

// Makes the changes a block deferred in one tile, and the extents of its rows and the tile follow.
void Simulator::apply(const Accum::Span& span) {
  const Accum::DeferredList& l = *span.list;
  // The rays were last touched a block ago, often by the other thread: their headers, then the intervals
  // the change writes, are fetched ahead, so that the misses overlap instead of coming one by one (across
  // a long raster's grooves, rays of hundreds of intervals, Dexel::replace took 7 % of the run's samples,
  // against 1.5 % where the cut makes the changes at once).
  constexpr uint32_t kHeaderAhead = 16, kDataAhead = 8;
  for (uint32_t k = span.ray0; k < span.ray1; ++k) {
    if (k + kHeaderAhead < span.ray1) __builtin_prefetch(l.rays[k + kHeaderAhead].ray, 1);
    if (k + kDataAhead < span.ray1) {
      const Accum::Deferred& a = l.rays[k + kDataAhead];
      __builtin_prefetch(a.ray->data() + a.k0, 1);
    }
    const Accum::Deferred& c = l.rays[k];
    c.ray->replace(c.k0, c.k1, l.pool.data() + c.offset, c.n);
  }
  for (uint32_t k = span.row0; k < span.row1; ++k) {
    const auto& [d, tu, iv] = l.rows[k];
    ext_.refresh_row(d, tu, iv, [&](int i) { return material_range(stock_.ray(d, i, iv)); });
  }
  if (span.tile) ext_.refresh_tile(span.d, span.tu, span.tv);
}

// The rays the engagement can read: those within 1.5 spacings (the reach of its nearest-ray lookups) of
// the cutting surface at the block's end (ball or end face up to the flutes' top, a cylinder of the
// tool's radius), per grid as a footprint across the rays; the cut defers its changes there.
void Simulator::engagement_reads(const Tool& tool, const ToolPose& end) {
  const Eigen::Vector3d a = end.axis.normalized(), top = end.tip + tool.flute_length * a;
  const Eigen::Vector3d ext =
      (Eigen::Vector3d::Ones() - a.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * tool.radius() + Eigen::Vector3d::Constant(1.5 * lattice_.h);
  const Eigen::Vector3d lo = (end.tip.cwiseMin(top) - ext - lattice_.origin) * inv_h_,
                        hi = (end.tip.cwiseMax(top) + ext - lattice_.origin) * inv_h_;
  // The lattice nodes inside [lo, hi] along axis k (an empty range when none).
  auto first = [&](int k) { return static_cast<int>(std::clamp(std::ceil(lo[k]), 0.0, double(lattice_.n[k]))); };
  auto last = [&](int k) { return static_cast<int>(std::clamp(std::floor(hi[k]), -1.0, double(lattice_.n[k] - 1))); };
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    reads_[size_t(d)] = {first(u), last(u), first(v), last(v)};
  }
}

Simulator::BlockTotals Simulator::merged_totals() {
  BlockTotals tot;
  for (const Accum& a : accum_) {
    for (int d = 0; d < 3; ++d) tot.removed[d] += a.removed[d];
    tot.gouge = std::max(tot.gouge, a.gouge);
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 4; ++c)
        for (int w = 0; w < 3; ++w)
          for (int r = 0; r < 2; ++r) tot.depth[d][c][w][r] = std::max(tot.depth[d][c][w][r], a.depth[d][c][w][r]);
  }
  return tot;
}

// A collision per tool component, obstacle kind and rapid flag whose overlap is deeper than the tolerance.
void Simulator::report_collisions(const Depths& depth, const Block& b, int index, const PoseAt& pose_at,
                                  BlockResult& br, VerifyReport& rep) const {
  for (int c = 0; c < 4; ++c)
    for (int w = 0; w < 3; ++w)
      for (int r = 0; r < 2; ++r) {
        // The smallest of the directions that saw it: the longest overlap along a ray grazing the
        // contact overstates the depth, the ray most normal to it does not.
        double dep = std::numeric_limits<double>::infinity();
        for (int d = 0; d < 3; ++d)
          if (depth[d][c][w][r] > 0) dep = std::min<double>(dep, depth[d][c][w][r]);
        if (!std::isfinite(dep) || dep <= opt_.collision_tolerance) continue;
        rep.collisions.push_back({index, b.line, static_cast<ToolComponent>(c), static_cast<HitWith>(w), r == 1, dep,
                                  pose_at(0.0), pose_at(1.0)});
        rep.collisions.back().tool = b.tool;
        br.collision = true;
      }
}

// The length the block's feed refers to: arcs and TCP moves the tip path; joint moves the XYZ path (the
// controller's feed reference), rotary degrees when only rotaries move.
double Simulator::feed_path_mm(const Block& b, const Joints& from) const {
  const double xyz = std::sqrt((b.target.x - from.x) * (b.target.x - from.x) +
                               (b.target.y - from.y) * (b.target.y - from.y) +
                               (b.target.z - from.z) * (b.target.z - from.z));
  double len = b.tcp || b.motion == Motion::ArcCW || b.motion == Motion::ArcCCW ? sweep_.tip_length : xyz;
  // Only rotaries: D = sqrt(dA^2 + dB^2 + dC^2) degrees, as RS274/NGC and LinuxCNC take it (their sum had
  // made a move of A30 C40 take 70 / F minutes for 50 / F, black-box testing).
  if (len < 1e-9)
    len = std::sqrt((b.target.a - from.a) * (b.target.a - from.a) + (b.target.b - from.b) * (b.target.b - from.b) +
                    (b.target.c - from.c) * (b.target.c - from.c));
  return len;
}

double Simulator::block_minutes(const Block& b, double len) const {
  if (b.motion == Motion::Rapid) return len / std::max(1.0, scene_.machine ? scene_.machine->rapid_feed : 20000.0);
  if (b.feed_mode == FeedMode::InverseTime) return b.feed > 0 ? 1.0 / b.feed : 0.0;
  return b.feed > 0 ? len / b.feed : 0.0;
}

}  // namespace sim

void check_verify_resolution(const Scene& scene, double h) { sim::Simulator::make_lattice(scene, h); }

VerifyResult verify_program(const Scene& scene, const Program& program, const ForwardFn& forward,
                            const VerifyOptions& options) {
  sim::Simulator sim(scene, program, forward, options);
  return sim.run();
}

}  // namespace tf
