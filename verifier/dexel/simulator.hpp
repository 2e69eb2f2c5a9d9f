// tiltfield verifier: the block loop, shared by simulate.cpp (per block: the sweep, the tiles it can touch,
// the bookkeeping) and simulate_tile.cpp (per tile and ray: the exact union of the swept intervals
// subtracted from the material, with collision, gouge and removal records).
#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "obstacles.hpp"
#include "ray_extents.hpp"
#include "raycast.hpp"
#include "sweep_rows.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tool_set.hpp"

namespace tf::sim {

struct Hit {
  Interval iv;
  uint8_t component;
  bool cutting;
};

// Sorts and merges intervals in place into a disjoint union.
inline void merge_union(std::vector<Interval>& v) {
  // A ray meets a few parts: insertion sort beats std::sort's set-up at these sizes.
  if (v.size() <= 16) {
    for (size_t i = 1; i < v.size(); ++i) {
      const Interval x = v[i];
      size_t k = i;
      for (; k > 0 && x.lo < v[k - 1].lo; --k) v[k] = v[k - 1];
      v[k] = x;
    }
  } else {
    std::sort(v.begin(), v.end(), [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
  }
  size_t m = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    if (m > 0 && v[i].lo <= v[m - 1].hi) v[m - 1].hi = std::max(v[m - 1].hi, v[i].hi);
    else v[m++] = v[i];
  }
  v.resize(m);
}

// A part meeting rays first..last of a tile row; its intervals are at t0/t1[offset + iu].
struct RowPart {
  int part, first, last;
  std::ptrdiff_t offset;
};

// Longest overlap along each grid direction, per component, obstacle kind and rapid flag.
using Depths = std::array<std::array<std::array<std::array<float, 2>, 3>, 4>, 3>;

// A ray of grid d at lattice node (iu, iv) of its (u, v) axes, which lie u_mm, v_mm from the lattice origin.
struct RayAt {
  int d, iu, iv;
  float u_mm, v_mm;
};

// Per thread, per block.
struct Accum {
  std::array<double, 3> removed{};
  Depths depth{};
  double gouge = 0.0;
  std::vector<Hit> hits;                       // of the ray being processed
  std::array<std::vector<Hit>, kTile> ray_hits;  // per ray of the row being cut
  std::vector<Interval> cut, mat, removed_pieces;
  std::vector<int> parts;
  std::vector<double> t0, t1;  // per part of the tile and ray of the row: its interval (see process_tile)
  std::vector<double> shadow_lo, shadow_hi;  // per part and row of the tile: its shadow's stretch
  std::vector<std::pair<int, int>> rows;      // per part: the tile's rows where it can matter
  std::vector<RowPart> row;
  // For the engagement, which is measured after the cut on the stock as it was before the block: the rays
  // this thread changes where the engagement reads keep their material until it has measured. Their new
  // contents wait in a DeferredList (in order: a ray cut twice in a block, by a crash after the cut, takes
  // the last), with the rows whose extents they change; the next block's task for their tile makes them
  // (Simulator::apply), so the writing stays on the threads. Lists alternate with the blocks' parity: a
  // block writes one while its tasks make the other's changes. Per grid, the box of the material the
  // cutting parts removed there (mm from the lattice origin, in the grid's u, v and ray axes; scalar
  // fields, so that the per-ray update stays in registers).
  struct GridBox {
    static constexpr float kInf = std::numeric_limits<float>::infinity();
    float u0 = kInf, u1 = -kInf, v0 = kInf, v1 = -kInf, t0 = kInf, t1 = -kInf;  // empty
  };
  struct Deferred {
    Dexel* ray;
    uint32_t k0, k1;     // its intervals [k0, k1) replaced (Dexel::replace) by
    uint32_t offset, n;  // pool[offset, offset + n)
  };
  struct DeferredList {
    std::vector<Deferred> rays;  // rays[0, n_rays): the rays changed, in order
    std::vector<Interval> pool;  // pool[0, n_pool): their new intervals
    size_t n_rays = 0, n_pool = 0;
    std::vector<std::array<int, 3>> rows;  // grid, tile column, row
    // The storage only grows, kept from block to block, so an addition is a few copies (the sizes are
    // kept apart: a vector's size is a division by the element's).
    void add(Dexel& ray, uint32_t k0, uint32_t k1, const Interval* p, size_t n) {
      if (n_rays == rays_held) [[unlikely]] {
        rays.resize(std::max<size_t>(256, 2 * rays.size()));
        rays_held = rays.size();
      }
      if (n_pool + n > pool_held) [[unlikely]] {
        pool.resize(std::max(2 * pool.size(), n_pool + n + 1024));
        pool_held = pool.size();
      }
      rays[n_rays++] = {&ray, k0, k1, static_cast<uint32_t>(n_pool), static_cast<uint32_t>(n)};
      Interval* to = pool.data() + n_pool;  // a few intervals: a loop, not a call to memcpy
      for (size_t k = 0; k < n; ++k) to[k] = p[k];
      n_pool += n;
    }
    size_t rays_held = 0, pool_held = 0;
    void clear() { n_rays = n_pool = 0, rows.clear(); }
  };
  // One tile's deferred changes: rays[ray0, ray1) and rows[row0, row1) of `list`; `tile`: its extents change.
  struct Span {
    const DeferredList* list;
    int d, tu, tv;
    uint32_t ray0, ray1, row0, row1;
    bool tile;
  };
  bool defer = false;         // set by process_tile (a thread's first task may come after the block's reset)
  // Which rays of the tile being cut defer their changes: none, all, or those the footprint holds.
  enum class DeferRays : uint8_t { None, All, Some } defer_rays = DeferRays::None;
  DeferredList* writing = nullptr;  // this block's list (process_tile)
  std::array<DeferredList, 2> lists;
  std::vector<Span> spans;  // this block's, per tile
  std::array<GridBox, 3> removed_box;
  // Rays of a feed block where a shank or holder met material that the block's cutting parts removed:
  // whether it met it first is decided after the cut, in time order (Simulator::add_ordered_depths). The
  // ray, and its material before the block in masked_pool[offset, offset + n).
  struct Masked {
    int d, iu, iv;
    uint32_t offset, n;
  };
  std::vector<Masked> masked;
  std::vector<Interval> masked_pool;
  std::vector<Interval> scratch, whole;
  // The material of `ray` as this block has left it so far: with its deferred change when it has one
  // (put together in `scratch`).
  std::pair<const Interval*, size_t> current(const Dexel& ray) {
    if (!writing || writing->n_rays == 0 || writing->rays[writing->n_rays - 1].ray != &ray) return {ray.begin(), ray.size()};
    const Deferred& c = writing->rays[writing->n_rays - 1];
    scratch.assign(ray.begin(), ray.begin() + c.k0);
    scratch.insert(scratch.end(), writing->pool.begin() + c.offset, writing->pool.begin() + c.offset + c.n);
    scratch.insert(scratch.end(), ray.begin() + c.k1, ray.end());
    return {scratch.data(), scratch.size()};
  }
  void reset() {
    removed_box = {};
    removed = {};
    for (auto& a : depth)
      for (auto& b : a)
        for (auto& c : b) c = {0.f, 0.f};
    gouge = 0.0;
    spans.clear();
    masked.clear();
    masked_pool.clear();
  }
};

// A tile of the block: `cut` when the block's parts can meet it, `pending` (an index into the previous
// block's deferred spans, -1 for none) when the previous block left changes there.
struct Task {
  int d, tu, tv;
  bool cut = true;
  int pending = -1;
};


// The rays of one task: grid d (ray axis d, across it u and v), rays iu0..iu_end-1 of rows iv0..iv_end-1.
struct TileRays {
  int d, u, v, tu, iu0, iu_end, iv0, iv_end;
};

class Simulator {
 public:
  Simulator(const Scene& scene, const Program& program, const ForwardFn& forward, const VerifyOptions& options);
  VerifyResult run();
  // The lattice of the stock's box (with the fixtures and check surfaces) at spacing h; throws InputError
  // for a spacing the stock cannot take (simulate.cpp).
  static Lattice make_lattice(const Scene& scene, double h);

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

  // What the threads recorded for one block, merged.
  struct BlockTotals {
    std::array<double, 3> removed{};
    double gouge = 0.0;
    Depths depth{};
  };

  // The stretch of ray (iu, iv) of grid d where an obstacle can be met: between its first and last
  // crossing, open-ended where the ray starts or ends inside a solid. Empty (lo > hi) without crossings.
  static Interval obstacle_range(const RayTable& t, int d, int iu, int iv) {
    const Crossing *b = t.begin(d, iu, iv), *e = t.end(d, iu, iv);
    if (b == e) return kNoExtent;
    const float inf = std::numeric_limits<float>::infinity();
    return {t.solid() && b->cos > 0 ? -inf : b->t, t.solid() && (e - 1)->cos < 0 ? inf : (e - 1)->t};
  }

  static Interval material_range(const Dexel& ray) {
    return ray.empty() ? kNoExtent : Interval{ray.begin()->lo, (ray.end() - 1)->hi};
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

  // Per block (simulate.cpp).
  PartSpan part_span(const SweptPart& p, int d) const;
  BlockResult simulate_block(const Block& b, const Joints& from, int index, bool continuing, VerifyReport& rep);
  // Where block bi starts, given where the block before it ended (`from`), across a tool change
  // (Program::length_offsets).
  Joints block_start(size_t bi, Joints from) const;
  PoseAt block_pose(const Block& b, const Joints& from) const;
  void select_tiles();
  void measure_block_engagement(const Tool& tool, const PoseAt& pose_at, bool arc, BlockResult& br, VerifyReport& rep);
  void engagement_reads(const Tool& tool, const ToolPose& end);
  void attach_pending();
  void collect_pending();
  void apply(const Accum::Span& span);
  BlockTotals merged_totals();
  // Collisions in time order (ordered_collisions.cpp).
  void add_ordered_depths(const Block& b, const PoseAt& pose_at, double turn, Depths& depth) const;
  void report_collisions(const Depths& depth, const Block& b, int index, const PoseAt& pose_at, BlockResult& br,
                         VerifyReport& rep) const;
  double feed_path_mm(const Block& b, const Joints& from) const;
  double block_minutes(const Block& b, double len) const;

  // Per tile and ray (simulate_tile.cpp). The stages are inline, and process_tile their only caller, so
  // that they compile into one loop nest as when they were one function: no call per row or ray.
  void process_tile(const Task& task, bool rapid, Accum& acc);
  inline void row_extents(const TileRays& t, std::array<Interval, kTile>& row_ext) const;
  inline void part_shadows(const TileRays& t, const std::array<Interval, kTile>& row_ext, Accum& acc) const;
  inline std::pair<int, int> row_parts(const TileRays& t, int iv, const Interval& row, Accum& acc) const;
  inline bool start_sphere_keeps(const SweptPart& p, const TileRays& t, int iv, int& a, int& b) const;
  inline void ray_ranges(const TileRays& t, int iv, int first, int last, std::array<Interval, kTile>& range) const;
  inline void part_intervals(const TileRays& t, int iv, const std::array<Interval, kTile>& range, Accum& acc) const;
  inline bool cut_row(const TileRays& t, int iv, int first, int last, const std::array<Interval, kTile>& range,
                      bool rapid, Accum& acc);
  inline bool cut_row_direct(const TileRays& t, int iv, int first, int last, const std::array<Interval, kTile>& range,
                             bool rapid, Accum& acc);
  inline bool part_hit(const RowPart& rp, int iu, const Interval& r, const Accum& acc, Hit& h) const;
  inline bool cut_ray(const TileRays& t, int iu, int iv, bool rapid, Accum& acc);
  inline bool process_ray(int d, int iu, int iv, bool rapid, Accum& acc);
  inline bool cut_stock(Dexel& ray, const RayAt& at, bool rapid, Accum& acc);
  // `material`: the ray's material, when not the ray itself (a second subtraction from a deferred ray).
  inline bool subtract(Dexel& ray, const RayAt& at, const Interval* cut, size_t n, std::vector<Interval>* pieces,
                       bool cutting, Accum& acc, std::pair<const Interval*, size_t> material = {});
  RayAt ray_at(int d, int iu, int iv) const {
    return {d, iu, iv, static_cast<float>(lattice_.h * iu), static_cast<float>(lattice_.h * iv)};
  }
  inline void note_masked(const Dexel& ray, const RayAt& at, Accum& acc) const;
  inline void record_obstacles(int d, int iu, int iv, bool rapid, Accum& acc) const;
  inline void record_gouge(int d, int iu, int iv, Accum& acc) const;

  const Scene& scene_;
  const Program& program_;
  VerifyOptions opt_;
  Lattice lattice_;
  TriDexel stock_;
  std::vector<Obstacle> obstacles_;
  std::unique_ptr<RayTable> design_;
  std::unique_ptr<RayMesh> design_mesh_;  // closest-point queries for gouge depths
  ToolSet tools_;  // per block's tool: parts, forward map
  RayExtents ext_;                 // where the material is, per tile and row segment
  std::vector<PartSpan> spans_;    // per swept part of the block and grid
  std::vector<Shadow> shadows_;    // the same
  double inv_h_ = 1.0;             // 1 / lattice spacing
  std::array<std::vector<uint32_t>, 3> stamp_;
  uint32_t stamp_value_ = 0;
  std::vector<Task> tasks_;
  BlockSweep sweep_;
  LastBlocks last_block_;  // VerifyOptions::record_last_block: written in cut_row
  uint32_t block_ = 0;     // 1-based index of the block being simulated
  int unresolved_gouges_ = 0;       // blocks over-cutting the design by more than the gouge tolerance,
  double deepest_unresolved_ = 0.0;  // but within their sweep bound (mm)
  // Rays iu0..iu1 of rows iv0..iv1 of a grid (inclusive; empty when iu1 < iu0 or iv1 < iv0).
  struct Footprint {
    int iu0 = 0, iu1 = -1, iv0 = 0, iv1 = -1;
    bool holds(int iu, int iv) const { return iu >= iu0 && iu <= iu1 && iv >= iv0 && iv <= iv1; }
  };
  bool defer_ = false;  // this block defers its changes where the engagement reads (Accum::defer)
  std::array<Footprint, 3> reads_;  // the rays the engagement can read, per grid
  std::vector<Accum::Span> pending_;  // the changes the previous block deferred, per tile (Task::pending)
  std::array<std::vector<int>, 3> task_of_;  // per tile stamped this block: its task
  tbb::enumerable_thread_specific<Accum> accum_;
};

}  // namespace tf::sim
