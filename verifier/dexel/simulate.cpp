// The block loop of the verifier: per block the swept parts, the lattice tiles they can touch, and per
// ray (in parallel over tiles) the exact union of the swept intervals subtracted from the material, with
// collision, gouge and removal bookkeeping.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <utility>

#include "obstacles.hpp"
#include "ray_depths.hpp"
#include "ray_extents.hpp"
#include "raycast.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {

ToolPose forward_xyz(const Joints& j) { return {Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d::UnitZ()}; }

namespace {


struct Hit {
  Interval iv;
  uint8_t component;
  bool cutting;
};

// A part meeting rays first..last of a tile row; its intervals are at t0/t1[offset + iu].
struct RowPart {
  int part, first, last;
  std::ptrdiff_t offset;
};

// Per thread, per block.
struct Accum {
  std::array<double, 3> removed{};
  // Longest overlap along each grid direction, per component, obstacle kind and rapid flag.
  std::array<std::array<std::array<std::array<float, 2>, 3>, 4>, 3> depth{};
  double gouge = 0.0;
  std::vector<Hit> hits;
  std::vector<Interval> cut, mat, removed_pieces;
  std::vector<int> parts;
  std::vector<double> t0, t1;  // per part of the tile and ray of the row: its interval (see process_tile)
  std::vector<double> shadow_lo, shadow_hi;  // per part and row of the tile: its shadow's stretch
  std::vector<std::pair<int, int>> rows;      // per part: the tile's rows where it can matter
  std::vector<RowPart> row;
  void reset() {
    removed = {};
    for (auto& a : depth)
      for (auto& b : a)
        for (auto& c : b) c = {0.f, 0.f};
    gouge = 0.0;
  }
};

struct Task {
  int d, tu, tv;
};

class Simulator {
 public:
  Simulator(const Scene& scene, const Program& program, const ForwardFn& forward, const VerifyOptions& options)
      : scene_(scene), program_(program), forward_(forward), opt_(options),
        lattice_(make_lattice(scene, options.resolution)), stock_(make_stock(scene.stock, lattice_)) {
    for (const Mesh& m : scene.fixtures) obstacles_.push_back({std::make_unique<RayTable>(m, lattice_), HitWith::Fixture, {}});
    for (const Mesh& m : scene.check_surfaces) obstacles_.push_back({std::make_unique<RayTable>(m, lattice_), HitWith::Check, {}});
    for (Obstacle& o : obstacles_) {
      o.ext = RayExtents(lattice_);
      o.ext.refresh_all([&](int d, int iu, int iv) { return obstacle_range(*o.table, d, iu, iv); });
    }
    if (options.check_gouges && scene.design.n_faces() > 0) {
      design_ = std::make_unique<RayTable>(scene.design, lattice_);
      design_mesh_ = std::make_unique<RayMesh>(scene.design);
    }
    parts_ = tool_parts(scene.tool, options.sweep);
    for (const ToolPart& p : parts_) {
      const double reach = p.kind == ToolPart::Kind::Sphere ? std::hypot(p.offset, p.h0) + p.radius : std::hypot(p.radius, p.h1);
      reach_all_ = std::max(reach_all_, reach);
      if (p.cutting) reach_cut_ = std::max(reach_cut_, reach);
    }
    inv_h_ = 1.0 / lattice_.h;
    ext_ = RayExtents(lattice_);
    ext_.refresh_all([&](int d, int iu, int iv) { return material_range(stock_.ray(d, iu, iv)); });
    for (int d = 0; d < 3; ++d) stamp_[d].assign(size_t(ext_.tiles_u(d)) * ext_.tiles_v(d), 0);
  }

  VerifyResult run() {
    const auto t_start = std::chrono::steady_clock::now();
    VerifyReport rep;
    rep.resolution_mm = lattice_.h;
    rep.rays = stock_.ray_count();
    rep.material_rays = stock_.material_rays();
    rep.stock_volume_start_mm3 = stock_.volume();
    rep.warnings = program_.warnings;
    Joints from = program_.start;
    bool prev_tcp = program_.blocks.empty() ? false : program_.blocks.front().tcp;
    const size_t nb = program_.blocks.size();
    for (size_t bi = 0; bi < nb; ++bi) {
      const Block& b = program_.blocks[bi];
      if (b.tcp != prev_tcp) {
        if (b.tcp) {
          const ToolPose p = forward_(from);  // joint position -> tip in the part frame
          from.x = p.tip.x();
          from.y = p.tip.y();
          from.z = p.tip.z();
        } else {
          rep.warnings.push_back("block " + std::to_string(bi + 1) + " (line " + std::to_string(b.line) +
                                 "): tool-centre-point control switched off; the block is simulated from its end position");
          from.x = b.target.x;
          from.y = b.target.y;
          from.z = b.target.z;
        }
        prev_tcp = b.tcp;
      }
      BlockResult br = simulate_block(b, from, static_cast<int>(bi) + 1, rep);
      rep.per_block.push_back(br);
      rep.removed_volume_mm3 += br.removed_mm3;
      from = b.target;
      if ((bi & 255) == 0) report(opt_.progress, "verify", double(bi) / double(std::max<size_t>(nb, 1)));
      if (br.collision && opt_.stop_at_first_collision) {
        rep.stopped_early = bi + 1 < nb;
        break;
      }
    }
    rep.blocks = static_cast<int>(rep.per_block.size());
    rep.stock_volume_end_mm3 = stock_.volume();
    rep.memory_bytes = stock_.memory_bytes();
    if (design_) rep.excess = excess_left(*design_, stock_);
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    report(opt_.progress, "verify", 1.0);
    return {std::move(rep), std::move(stock_)};
  }

 private:
  struct Obstacle {
    std::unique_ptr<RayTable> table;
    HitWith with;
    RayExtents ext;  // where along the rays the obstacle can be met (obstacle_range)
  };

  // Where a swept part is in ray indices for grid d: rays u0..u1 of rows v0..v1 (empty when u1 < u0 or
  // v1 < v0), between lo and hi along the rays (relative to the lattice origin).
  struct PartSpan {
    int u0, u1, v0, v1;
    float lo, hi;
  };

  // The stretch of ray (iu, iv) of grid d where an obstacle can be met: between its first and last
  // crossing, open-ended where the ray starts or ends inside a solid. Empty (lo > hi) without crossings.
  static Interval obstacle_range(const RayTable& t, int d, int iu, int iv) {
    const Crossing *b = t.begin(d, iu, iv), *e = t.end(d, iu, iv);
    if (b == e) return kNoExtent;
    const float inf = std::numeric_limits<float>::infinity();
    return {t.solid() && b->cos > 0 ? -inf : b->t, t.solid() && (e - 1)->cos < 0 ? inf : (e - 1)->t};
  }

  static Lattice make_lattice(const Scene& scene, double h) {
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
    for (const Mesh& m : scene.fixtures) box.extend(bounding_box(m));
    for (const Mesh& m : scene.check_surfaces) box.extend(bounding_box(m));
    if (box.isEmpty()) throw InputError(scene.file.string(), 0, "stock", "the stock is empty");
    const Eigen::Vector3d ext = box.sizes();
    const double nodes = (ext.x() / h + 3) * (ext.y() / h + 3) * (ext.z() / h + 3);
    const double rays = nodes / std::max({ext.x() / h + 3, ext.y() / h + 3, ext.z() / h + 3}) * 3;
    if (rays > 2e8) throw InputError("", 0, "resolution", "too fine for this stock (more than 2e8 rays)");
    return lattice_for(box, h, 2);
  }

  static Interval material_range(const Dexel& ray) {
    return ray.empty() ? kNoExtent : Interval{ray.begin()->lo, (ray.end() - 1)->hi};
  }

  // ceil and floor to a lattice index, without a libm call on baseline x86-64; far-off values (a block
  // from a mistyped coordinate) are clamped first, well inside int.
  static int ceil_index(double x) {
    x = std::clamp(x, -1e9, 1e9);
    const int k = static_cast<int>(x);
    return k < x ? k + 1 : k;
  }
  static int floor_index(double x) {
    x = std::clamp(x, -1e9, 1e9);
    const int k = static_cast<int>(x);
    return k > x ? k - 1 : k;
  }

  PartSpan part_span(const SweptPart& p, int d) const {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    auto first = [&](double x, int axis) {
      return static_cast<int>(std::clamp(std::ceil((x - lattice_.origin[axis]) / lattice_.h), 0.0, lattice_.n[axis] + 1.0));
    };
    auto last = [&](double x, int axis) {
      return static_cast<int>(std::clamp(std::floor((x - lattice_.origin[axis]) / lattice_.h), -1.0, lattice_.n[axis] - 1.0));
    };
    return {first(p.box.min()[u], u), last(p.box.max()[u], u), first(p.box.min()[v], v), last(p.box.max()[v], v),
            static_cast<float>(p.box.min()[d] - lattice_.origin[d]), static_cast<float>(p.box.max()[d] - lattice_.origin[d])};
  }
  const PartSpan& span(int part, int d) const { return spans_[size_t(part) * 3 + d]; }

  // Can part `part` touch material or an obstacle in tile (tu, tv) of grid d?
  bool relevant(int part, int d, int tu, int tv) const {
    const PartSpan& s = span(part, d);
    if (s.u1 < tu * kTile || s.u0 >= (tu + 1) * kTile || s.v1 < tv * kTile || s.v0 >= (tv + 1) * kTile) return false;
    if (meets(ext_.tile(d, tu, tv), s.lo, s.hi)) return true;
    for (const Obstacle& o : obstacles_)
      if (meets(o.ext.tile(d, tu, tv), s.lo, s.hi)) return true;
    return false;
  }

  BlockResult simulate_block(const Block& b, const Joints& from, int index, VerifyReport& rep) {
    BlockResult br;
    br.block = index;
    br.line = b.line;
    const bool tcp = b.tcp;
    PoseAt pose_at = [&](double tau) {
      const Joints j = interpolate_block(from, b, tau);
      if (!tcp) return forward_(j);
      Joints rot = j;
      rot.x = rot.y = rot.z = 0.0;
      ToolPose p = forward_(rot);
      p.tip = Eigen::Vector3d(j.x, j.y, j.z);
      return p;
    };
    sweep_block(pose_at, parts_, reach_cut_, reach_all_, opt_.sweep, sweep_);
    br.substeps = sweep_.substeps;
    rep.sweep_error_mm = std::max(rep.sweep_error_mm, sweep_.cutting_error);
    rep.holder_sweep_error_mm = std::max(rep.holder_sweep_error_mm, sweep_.holder_error);
    br.path_mm = feed_path_mm(b, from);
    br.minutes = block_minutes(b, br.path_mm);

    // Tiles any part can touch.
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
            tasks_.push_back({d, tu, tv});
          }
      }
    const bool rapid = b.motion == Motion::Rapid;
    br.rapid = rapid;
    br.feed = b.feed;
    br.feed_mode = b.feed_mode;
    // Engagement is measured on the stock before this block removes anything (seed 001: the in-process
    // workpiece met by the tool at the block's end).
    if (opt_.engagement && !rapid && !tasks_.empty()) {
      const auto t0 = std::chrono::steady_clock::now();
      const double back = 1.0 / (4.0 * std::max(1, sweep_.substeps));
      br.engagement = opt_.engagement(stock_, pose_at(1.0 - back), pose_at(1.0),
                                      [this](const Eigen::AlignedBox3d& box) { return may_hold_material(box); });
      rep.engagement_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    for (auto& a : accum_) a.reset();
    tbb::parallel_for(size_t(0), tasks_.size(), [&](size_t k) { process_tile(tasks_[k], rapid, accum_.local()); });

    std::array<double, 3> removed{};
    double gouge = 0.0;
    std::array<std::array<std::array<std::array<float, 2>, 3>, 4>, 3> depth{};
    for (const Accum& a : accum_) {
      for (int d = 0; d < 3; ++d) removed[d] += a.removed[d];
      gouge = std::max(gouge, a.gouge);
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 4; ++c)
          for (int w = 0; w < 3; ++w)
            for (int r = 0; r < 2; ++r) depth[d][c][w][r] = std::max(depth[d][c][w][r], a.depth[d][c][w][r]);
    }
    br.removed_mm3 = (removed[0] + removed[1] + removed[2]) / 3.0 * lattice_.h * lattice_.h;
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
          br.collision = true;
        }
    if (gouge > 0) {
      rep.max_gouge_mm = std::max(rep.max_gouge_mm, gouge);
      if (gouge > opt_.gouge_tolerance) rep.gouges.push_back({index, b.line, gouge});
    }
    return br;
  }

  // False only when no ray of any grid holds material inside `box` (the tiles' material extents).
  bool may_hold_material(const Eigen::AlignedBox3d& box) const {
    const Eigen::AlignedBox3d b(box.min().array() - lattice_.h, box.max().array() + lattice_.h);
    for (int d = 0; d < 3; ++d) {
      const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
      int tu0, tu1, tv0, tv1;
      if (!tile_range(b.min()[u], b.max()[u], u, tu0, tu1) || !tile_range(b.min()[v], b.max()[v], v, tv0, tv1)) continue;
      const float lo = static_cast<float>(b.min()[d] - lattice_.origin[d]), hi = static_cast<float>(b.max()[d] - lattice_.origin[d]);
      for (int tv = tv0; tv <= tv1; ++tv)
        for (int tu = tu0; tu <= tu1; ++tu) {
          if (meets(ext_.tile(d, tu, tv), lo, hi)) return true;
        }
    }
    return false;
  }

  // Tiles along lattice axis `axis` whose nodes lie in [lo, hi]; false when none.
  bool tile_range(double lo, double hi, int axis, int& t0, int& t1) const {
    const double big = lattice_.n[axis] + 1.0;
    const int n0 = static_cast<int>(std::clamp(std::ceil((lo - lattice_.origin[axis]) / lattice_.h), 0.0, big));
    const int n1 = static_cast<int>(std::clamp(std::floor((hi - lattice_.origin[axis]) / lattice_.h), -1.0, lattice_.n[axis] - 1.0));
    if (n1 < n0) return false;
    t0 = n0 / kTile;
    t1 = n1 / kTile;
    return true;
  }

  void process_tile(const Task& task, bool rapid, Accum& acc) {
    const int d = task.d, u = Lattice::u_axis(d), v = Lattice::v_axis(d), tu = task.tu;
    acc.parts.clear();
    for (size_t i = 0; i < sweep_.parts.size(); ++i)
      if (relevant(static_cast<int>(i), d, tu, task.tv)) acc.parts.push_back(static_cast<int>(i));
    if (acc.parts.empty()) return;
    bool changed = false;
    const double h = lattice_.h;
    const int iu0 = tu * kTile, iu_end = std::min(lattice_.n[u], iu0 + kTile);
    const int iv_end = std::min(lattice_.n[v], (task.tv + 1) * kTile);
    acc.t0.resize(acc.parts.size() * kTile);
    acc.t1.resize(acc.parts.size() * kTile);
    // Where along each row's rays a part must be to matter: the material, or an obstacle.
    const int iv0 = task.tv * kTile;
    std::array<Interval, kTile> row_ext;
    for (int iv = iv0; iv < iv_end; ++iv) {
      Interval& row = row_ext[iv - iv0];
      row = ext_.row(d, tu, iv);
      for (const Obstacle& ob : obstacles_) row = hull(row, ob.ext.row(d, tu, iv));
    }
    // Each part's shadow on the rows where it can matter (first..last), in one batch per part.
    acc.shadow_lo.resize(acc.parts.size() * kTile);
    acc.shadow_hi.resize(acc.parts.size() * kTile);
    acc.rows.resize(acc.parts.size());
    for (size_t j = 0; j < acc.parts.size(); ++j) {
      const PartSpan& sp = span(acc.parts[j], d);
      int r0 = std::max(iv0, sp.v0), r1 = std::min(iv_end - 1, sp.v1);
      while (r0 <= r1 && !meets(row_ext[r0 - iv0], sp.lo, sp.hi)) ++r0;
      while (r1 >= r0 && !meets(row_ext[r1 - iv0], sp.lo, sp.hi)) --r1;
      acc.rows[j] = {r0, r1};
      if (r1 >= r0)
        shadow_rows(shadows_[size_t(acc.parts[j]) * 3 + d], lattice_.origin[v] + h * r0, h, r1 - r0 + 1,
                    &acc.shadow_lo[j * kTile + (r0 - iv0)], &acc.shadow_hi[j * kTile + (r0 - iv0)]);
    }
    std::array<Interval, kTile> range;
    for (int iv = iv0; iv < iv_end; ++iv) {
      const Interval row = row_ext[iv - iv0];
      if (row.lo > row.hi) continue;
      const double cv = lattice_.origin[v] + h * iv;
      // The rays of this row under each part's shadow.
      acc.row.clear();
      int first = iu_end, last = iu0 - 1;
      for (size_t j = 0; j < acc.parts.size(); ++j) {
        const int pi = acc.parts[j];
        const PartSpan& sp = span(pi, d);
        if (iv < acc.rows[j].first || iv > acc.rows[j].second || !meets(row, sp.lo, sp.hi)) continue;
        int a = std::max(iu0, sp.u0), b = std::min(iu_end - 1, sp.u1);
        const double lo = acc.shadow_lo[j * kTile + (iv - iv0)], hi = acc.shadow_hi[j * kTile + (iv - iv0)];
        if (!(hi >= lo)) continue;
        a = std::max(a, ceil_index((lo - lattice_.origin[u]) * inv_h_));
        b = std::min(b, floor_index((hi - lattice_.origin[u]) * inv_h_));
        if (b < a) continue;
        acc.row.push_back({pi, a, b, static_cast<std::ptrdiff_t>(j * kTile) - iu0});
        first = std::min(first, a);
        last = std::max(last, b);
      }
      // Where each of those rays holds material or meets an obstacle.
      for (int iu = first; iu <= last; ++iu) {
        Interval& r = range[iu - iu0];
        r = material_range(stock_.ray(d, iu, iv));
        for (const Obstacle& ob : obstacles_) r = hull(r, obstacle_range(*ob.table, d, iu, iv));
      }
      // The parts' intervals on them, in one batch per part and row.
      for (const RowPart& rp : acc.row) {
        const SweptPart& p = sweep_.parts[rp.part];
        Eigen::Vector3d o = lattice_.origin;
        o[u] += h * rp.first;
        o[v] = cv;
        if (p.kind == ToolPart::Kind::Sphere) {
          ray_intervals(p, o, d, u, h, rp.last - rp.first + 1, &acc.t0[rp.offset + rp.first], &acc.t1[rp.offset + rp.first]);
          continue;
        }
        if (cylinder_intervals(p, o, d, u, h, rp.last - rp.first + 1, &acc.t0[rp.offset + rp.first],
                               &acc.t1[rp.offset + rp.first]))
          continue;
        // The rows the batch leaves to the scalar method: only the rays whose range the part can meet.
        const PartSpan& sp = span(rp.part, d);
        for (int iu = rp.first; iu <= rp.last; ++iu) {
          o[u] = lattice_.origin[u] + h * iu;
          double& t0 = acc.t0[rp.offset + iu];
          double& t1 = acc.t1[rp.offset + iu];
          if (!meets(range[iu - iu0], sp.lo, sp.hi) || !ray_interval(p, o, d, t0, t1)) {
            t0 = std::numeric_limits<double>::infinity();
            t1 = -t0;
          }
        }
      }
      bool row_changed = false;
      for (int iu = first; iu <= last; ++iu) {
        const Interval r = range[iu - iu0];
        if (r.lo > r.hi) continue;
        acc.hits.clear();
        for (const RowPart& rp : acc.row) {
          if (iu < rp.first || iu > rp.last) continue;
          const double t0 = acc.t0[rp.offset + iu], t1 = acc.t1[rp.offset + iu];
          if (!(t1 > t0) || t1 < r.lo || t0 > r.hi) continue;
          const SweptPart& p = sweep_.parts[rp.part];
          acc.hits.push_back({{static_cast<float>(t0), static_cast<float>(t1)}, static_cast<uint8_t>(p.component), p.cutting});
        }
        if (!acc.hits.empty() && process_ray(d, iu, iv, rapid, acc)) row_changed = true;
      }
      if (row_changed) {
        changed = true;
        ext_.refresh_row(d, tu, iv, [&](int i) { return material_range(stock_.ray(d, i, iv)); });
      }
    }
    if (changed) ext_.refresh_tile(d, tu, task.tv);
  }

  bool process_ray(int d, int iu, int iv, bool rapid, Accum& acc) {
    Dexel& ray = stock_.ray(d, iu, iv);
    // The common case: one cutting part, nothing to check but the removal.
    if (acc.hits.size() == 1 && acc.hits[0].cutting && !rapid && obstacles_.empty() && !design_) {
      const double gone = subtract_intervals(ray.begin(), ray.size(), &acc.hits[0].iv, 1, acc.mat, nullptr);
      if (!(gone > 0)) return false;
      ray.assign(acc.mat.data(), static_cast<uint32_t>(acc.mat.size()));
      acc.removed[d] += gone;
      return true;
    }
    // Union of the cutting parts' intervals.
    acc.cut.clear();
    for (const Hit& h : acc.hits)
      if (h.cutting) acc.cut.push_back(h.iv);
    merge_union(acc.cut);
    bool changed = false;
    acc.removed_pieces.clear();
    if (!ray.empty()) {
      if (rapid)
        for (const Hit& h : acc.hits)
          if (h.cutting) record(acc, d, h.component, HitWith::Stock, true, overlap_longest(h.iv, ray));
      if (!acc.cut.empty() && acc.cut.front().lo < (ray.end() - 1)->hi && acc.cut.back().hi > ray.begin()->lo) {
        const double gone = subtract_intervals(ray.begin(), ray.size(), acc.cut.data(), acc.cut.size(), acc.mat,
                                               design_ ? &acc.removed_pieces : nullptr);
        if (gone > 0) {
          ray.assign(acc.mat.data(), static_cast<uint32_t>(acc.mat.size()));
          acc.removed[d] += gone;
          changed = true;
        }
      }
      bool crash = false;
      for (const Hit& h : acc.hits) {
        if (h.cutting || ray.empty()) continue;
        const float depth = overlap_longest(h.iv, ray);
        record(acc, d, h.component, HitWith::Stock, rapid, depth);
        crash |= depth > 0;
      }
      // A crash destroys the material the shank or holder met: take it away too, so the following
      // blocks report their own collisions, not this one again.
      if (crash) {
        acc.cut.clear();
        for (const Hit& h : acc.hits)
          if (!h.cutting) acc.cut.push_back(h.iv);
        merge_union(acc.cut);
        const double gone = subtract_intervals(ray.begin(), ray.size(), acc.cut.data(), acc.cut.size(), acc.mat, nullptr);
        if (gone > 0) {
          ray.assign(acc.mat.data(), static_cast<uint32_t>(acc.mat.size()));
          acc.removed[d] += gone;
          changed = true;
        }
      }
    }
    for (const Obstacle& o : obstacles_) {
      const Crossing* b = o.table->begin(d, iu, iv);
      if (!b) continue;
      const Crossing* e = o.table->end(d, iu, iv);
      for (const Hit& h : acc.hits)
        record(acc, d, h.component, o.with, rapid, obstacle_depth(b, e, o.table->solid(), h.iv.lo, h.iv.hi));
    }
    if (design_ && !acc.removed_pieces.empty()) {
      double at = 0.0;
      const double est = gouge_depth(design_->begin(d, iu, iv), design_->end(d, iu, iv), acc.removed_pieces, &at);
      // The along-ray estimate selects the point; a point deep inside the part along a ray parallel to its
      // surface is much closer to the surface than the ray says, so the depth is its true distance.
      if (est > 0.25 * opt_.gouge_tolerance) {
        Eigen::Vector3d p = lattice_.origin;
        p[Lattice::u_axis(d)] += lattice_.h * iu;
        p[Lattice::v_axis(d)] += lattice_.h * iv;
        p[d] += at;
        Eigen::Vector3d q, n;
        const double dist = design_mesh_->closest(p, est + 1e-6, q, n) ? (p - q).norm() : est;
        acc.gouge = std::max(acc.gouge, std::min(est, dist));
      }
    }
    return changed;
  }

  // Sorts and merges intervals in place into a disjoint union.
  static void merge_union(std::vector<Interval>& v) {
    std::sort(v.begin(), v.end(), [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
    size_t m = 0;
    for (size_t i = 0; i < v.size(); ++i) {
      if (m > 0 && v[i].lo <= v[m - 1].hi) v[m - 1].hi = std::max(v[m - 1].hi, v[i].hi);
      else v[m++] = v[i];
    }
    v.resize(m);
  }

  static float overlap_longest(const Interval& iv, const Dexel& ray) {
    double longest = 0.0;
    overlap_length(&iv, 1, ray.begin(), ray.size(), &longest);
    return static_cast<float>(longest);
  }

  static void record(Accum& acc, int d, uint8_t comp, HitWith with, bool rapid, float depth) {
    float& slot = acc.depth[d][comp][static_cast<int>(with)][rapid ? 1 : 0];
    slot = std::max(slot, depth);
  }

  // The length the block's feed refers to: arcs and TCP moves the tip path; joint moves the XYZ path (the
  // controller's feed reference), rotary degrees when only rotaries move.
  double feed_path_mm(const Block& b, const Joints& from) const {
    const double xyz = std::sqrt((b.target.x - from.x) * (b.target.x - from.x) + (b.target.y - from.y) * (b.target.y - from.y) +
                                 (b.target.z - from.z) * (b.target.z - from.z));
    double len = b.tcp || b.motion == Motion::ArcCW || b.motion == Motion::ArcCCW ? sweep_.tip_length : xyz;
    if (len < 1e-9)
      len = std::abs(b.target.a - from.a) + std::abs(b.target.b - from.b) + std::abs(b.target.c - from.c);
    return len;
  }

  double block_minutes(const Block& b, double len) const {
    if (b.motion == Motion::Rapid) return len / std::max(1.0, scene_.machine ? scene_.machine->rapid_feed : 20000.0);
    if (b.feed_mode == FeedMode::InverseTime) return b.feed > 0 ? 1.0 / b.feed : 0.0;
    return b.feed > 0 ? len / b.feed : 0.0;
  }

  const Scene& scene_;
  const Program& program_;
  ForwardFn forward_;
  VerifyOptions opt_;
  Lattice lattice_;
  TriDexel stock_;
  std::vector<Obstacle> obstacles_;
  std::unique_ptr<RayTable> design_;
  std::unique_ptr<RayMesh> design_mesh_;  // closest-point queries for gouge depths
  std::vector<ToolPart> parts_;
  double reach_cut_ = 0.0, reach_all_ = 0.0;
  RayExtents ext_;                 // where the material is, per tile and row segment
  std::vector<PartSpan> spans_;    // per swept part of the block and grid
  std::vector<Shadow> shadows_;    // the same
  double inv_h_ = 1.0;             // 1 / lattice spacing
  std::array<std::vector<uint32_t>, 3> stamp_;
  uint32_t stamp_value_ = 0;
  std::vector<Task> tasks_;
  BlockSweep sweep_;
  tbb::enumerable_thread_specific<Accum> accum_;
};

}  // namespace

VerifyResult verify_program(const Scene& scene, const Program& program, const ForwardFn& forward,
                            const VerifyOptions& options) {
  Simulator sim(scene, program, forward, options);
  return sim.run();
}

}  // namespace tf
