// The verifier's work per tile of rays (one task of the parallel block loop in simulate.cpp): where the
// block's swept parts meet each ray, the exact union of their intervals subtracted from the material, and
// the collision, gouge and removal records of every ray they meet.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "ray_depths.hpp"
#include "simulator.hpp"

namespace tf::sim {

namespace {

// Rows met by at most this many parts gather each ray's hits directly instead of scattering them.
constexpr size_t kFewRowParts = 3;

// Over-cuts estimated along a ray at most this deep (mm) are not measured (record_gouge).
constexpr double kGougeQueryDepth = 0.0025;

// ceil and floor to a lattice index, without a libm call on baseline x86-64; far-off values (a block
// from a mistyped coordinate) are clamped first, well inside int.
int ceil_index(double x) {
  x = std::clamp(x, -1e9, 1e9);
  const int k = static_cast<int>(x);
  return k < x ? k + 1 : k;
}
int floor_index(double x) {
  x = std::clamp(x, -1e9, 1e9);
  const int k = static_cast<int>(x);
  return k > x ? k - 1 : k;
}

float overlap_longest(const Interval& iv, std::pair<const Interval*, size_t> ray) {
  double longest = 0.0;
  overlap_length(&iv, 1, ray.first, ray.second, &longest);
  return static_cast<float>(longest);
}

void record(Accum& acc, int d, uint8_t comp, HitWith with, bool rapid, float depth) {
  float& slot = acc.depth[d][comp][static_cast<int>(with)][rapid ? 1 : 0];
  slot = std::max(slot, depth);
}

}  // namespace

// Takes the disjoint intervals cut[0..n) out of ray `ray` at `at` (the removed pieces into `pieces` when
// not null); false when no material went. `cutting`: the cutting parts' union, whose removal bounds the
// engagement (acc.removed_box), not a crash's. Where the engagement reads, the ray keeps its material
// until the engagement has measured, and its new contents wait in acc.writing.
bool Simulator::subtract(Dexel& ray, const RayAt& at, const Interval* cut, size_t n, std::vector<Interval>* pieces,
                         bool cutting, Accum& acc, std::pair<const Interval*, size_t> material) {
  // The crash after a deferred cut is given the material that cut left (not yet the ray's): its result
  // replaces all of it.
  const bool given = material.first && material.first != ray.begin();
  const auto [all, total] = given ? material : std::pair<const Interval*, size_t>{ray.begin(), ray.size()};
  // Only the intervals the cut spans can change: a ray across a raster of grooves holds hundreds, which
  // are neither subtracted from nor copied.
  const Interval* before = first_ending_after(all, all + total, cut[0].lo);
  const Interval* after = before;
  while (after != all + total && after->lo < cut[n - 1].hi) ++after;
  const size_t count = size_t(after - before);
  const double gone = subtract_intervals(before, count, cut, n, acc.mat, pieces);
  if (!(gone > 0)) return false;
  acc.removed[at.d] += gone;
  auto k0 = static_cast<uint32_t>(before - all), k1 = static_cast<uint32_t>(after - all);
  if (given) {
    acc.whole.assign(all, before);
    acc.whole.insert(acc.whole.end(), acc.mat.begin(), acc.mat.end());
    acc.whole.insert(acc.whole.end(), after, all + total);
    acc.mat.swap(acc.whole);
    k0 = 0, k1 = static_cast<uint32_t>(total);
  }
  if (acc.defer_rays == Accum::DeferRays::None ||
      (acc.defer_rays == Accum::DeferRays::Some && !reads_[size_t(at.d)].holds(at.iu, at.iv))) {
    ray.replace(k0, k1, acc.mat.data(), static_cast<uint32_t>(acc.mat.size()));
    return true;
  }
  if (cutting) {
    // The removed material lies where the cut and the material before overlap.
    Accum::GridBox& b = acc.removed_box[at.d];
    b.t0 = std::min(b.t0, std::max(cut[0].lo, before->lo));
    b.t1 = std::max(b.t1, std::min(cut[n - 1].hi, (after - 1)->hi));
    b.u0 = std::min(b.u0, at.u_mm);
    b.u1 = std::max(b.u1, at.u_mm);
    b.v0 = std::min(b.v0, at.v_mm);
    b.v1 = std::max(b.v1, at.v_mm);
  }
  acc.writing->add(ray, k0, k1, acc.mat.data(), acc.mat.size());
  return true;
}

void Simulator::process_tile(const Task& task, bool rapid, Accum& acc) {
  const int d = task.d, u = Lattice::u_axis(d), v = Lattice::v_axis(d), tu = task.tu;
  acc.defer = defer_;
  acc.writing = &acc.lists[block_ & 1];
  if (task.pending >= 0) apply(pending_[size_t(task.pending)]);
  if (!task.cut) return;
  acc.parts.clear();
  for (size_t i = 0; i < sweep_.parts.size(); ++i)
    if (relevant(static_cast<int>(i), d, tu, task.tv)) acc.parts.push_back(static_cast<int>(i));
  if (acc.parts.empty()) return;
  const int iu0 = tu * kTile;
  const TileRays t{d, u, v, tu, iu0, std::min(lattice_.n[u], iu0 + kTile), task.tv * kTile,
                   std::min(lattice_.n[v], (task.tv + 1) * kTile)};
  acc.t0.resize(acc.parts.size() * kTile);
  acc.t1.resize(acc.parts.size() * kTile);
  // Most tiles of a deferring block lie wholly inside the footprint or outside it: no test per ray.
  const Footprint& reads = reads_[size_t(d)];
  if (!acc.defer || reads.iu1 < t.iu0 || reads.iu0 >= t.iu_end || reads.iv1 < t.iv0 || reads.iv0 >= t.iv_end)
    acc.defer_rays = Accum::DeferRays::None;
  else if (reads.iu0 <= t.iu0 && reads.iu1 >= t.iu_end - 1 && reads.iv0 <= t.iv0 && reads.iv1 >= t.iv_end - 1)
    acc.defer_rays = Accum::DeferRays::All;
  else
    acc.defer_rays = Accum::DeferRays::Some;
  std::array<Interval, kTile> row_ext;
  row_extents(t, row_ext);
  part_shadows(t, row_ext, acc);
  bool changed = false;
  const auto ray0 = static_cast<uint32_t>(acc.writing->n_rays), row0 = static_cast<uint32_t>(acc.writing->rows.size());
  std::array<Interval, kTile> range;
  for (int iv = t.iv0; iv < t.iv_end; ++iv) {
    const Interval row = row_ext[iv - t.iv0];
    if (row.lo > row.hi) continue;
    const auto [first, last] = row_parts(t, iv, row, acc);
    ray_ranges(t, iv, first, last, range);
    part_intervals(t, iv, range, acc);
    if (cut_row(t, iv, first, last, range, rapid, acc)) {
      changed = true;
      // The extents follow the rays' contents: a deferring block's with them (Simulator::apply).
      if (acc.defer) acc.writing->rows.push_back({d, tu, iv});
      else ext_.refresh_row(d, tu, iv, [&](int i) { return material_range(stock_.ray(d, i, iv)); });
    }
  }
  if (acc.defer && (acc.writing->n_rays > ray0 || acc.writing->rows.size() > row0))
    acc.spans.push_back({acc.writing, d, tu, task.tv, ray0, static_cast<uint32_t>(acc.writing->n_rays), row0,
                         static_cast<uint32_t>(acc.writing->rows.size()), changed});
  else if (changed) ext_.refresh_tile(d, tu, task.tv);
}

// Narrows rays a..b of row iv to those on which sphere p, whose start is empty (SweptPart::start_empty),
// can remove material; false when none is left. With c its start centre, d its translation, q a ray's
// point and a = (q - c).d across the ray, a <= -R |d along the ray| skips the ray: the sphere at time s
// lies |q - c(s)|^2 = |q - c|^2 - 2 s a + s^2 |d|^2 (across) from the ray, so its half chord is shorter
// than the start's by at least s (-a) / R >= s |d along the ray|, as far as its centre has moved along
// the ray: its chord lies in the start's, where nothing is left. A linear bound in the ray's index.
bool Simulator::start_sphere_keeps(const SweptPart& p, const TileRays& t, int iv, int& a, int& b) const {
  constexpr double kMargin = 1e-6;  // mm: rays this close to the bound are kept
  const double du = p.d[t.u], limit = -p.radius * std::abs(p.d[t.d]) - kMargin;
  const double rest = (lattice_.origin[t.v] + lattice_.h * iv - p.p0[t.v]) * p.d[t.v];
  if (du == 0.0) return rest > limit;
  // The ray's a is `limit` at node k (fractional); rays on the far side of it from d are skipped.
  const double k = (p.p0[t.u] + (limit - rest) / du - lattice_.origin[t.u]) * inv_h_;
  if (du > 0.0) a = std::max(a, floor_index(k) + 1);
  else b = std::min(b, ceil_index(k) - 1);
  return a <= b;
}

// Where along each row's rays a part must be to matter: the material, or an obstacle.
void Simulator::row_extents(const TileRays& t, std::array<Interval, kTile>& row_ext) const {
  for (int iv = t.iv0; iv < t.iv_end; ++iv) {
    Interval& row = row_ext[iv - t.iv0];
    row = ext_.row(t.d, t.tu, iv);
    for (const Obstacle& ob : obstacles_) row = hull(row, ob.ext.row(t.d, t.tu, iv));
  }
}

// Each part's shadow on the rows where it can matter (first..last), in one batch per part.
void Simulator::part_shadows(const TileRays& t, const std::array<Interval, kTile>& row_ext, Accum& acc) const {
  const double h = lattice_.h;
  acc.shadow_lo.resize(acc.parts.size() * kTile);
  acc.shadow_hi.resize(acc.parts.size() * kTile);
  acc.rows.resize(acc.parts.size());
  for (size_t j = 0; j < acc.parts.size(); ++j) {
    const PartSpan& sp = span(acc.parts[j], t.d);
    int r0 = std::max(t.iv0, sp.v0), r1 = std::min(t.iv_end - 1, sp.v1);
    while (r0 <= r1 && !meets(row_ext[r0 - t.iv0], sp.lo, sp.hi)) ++r0;
    while (r1 >= r0 && !meets(row_ext[r1 - t.iv0], sp.lo, sp.hi)) --r1;
    acc.rows[j] = {r0, r1};
    if (r1 >= r0)
      shadow_rows(shadows_[size_t(acc.parts[j]) * 3 + t.d], lattice_.origin[t.v] + h * r0, h, r1 - r0 + 1,
                  &acc.shadow_lo[j * kTile + (r0 - t.iv0)], &acc.shadow_hi[j * kTile + (r0 - t.iv0)]);
  }
}

// The rays of row iv under each part's shadow (acc.row); returns the first and last of them all (last <
// first when none).
std::pair<int, int> Simulator::row_parts(const TileRays& t, int iv, const Interval& row, Accum& acc) const {
  acc.row.clear();
  int first = t.iu_end, last = t.iu0 - 1;
  for (size_t j = 0; j < acc.parts.size(); ++j) {
    const int pi = acc.parts[j];
    const PartSpan& sp = span(pi, t.d);
    if (iv < acc.rows[j].first || iv > acc.rows[j].second || !meets(row, sp.lo, sp.hi)) continue;
    int a = std::max(t.iu0, sp.u0), b = std::min(t.iu_end - 1, sp.u1);
    const double lo = acc.shadow_lo[j * kTile + (iv - t.iv0)], hi = acc.shadow_hi[j * kTile + (iv - t.iv0)];
    if (!(hi >= lo)) continue;
    a = std::max(a, ceil_index((lo - lattice_.origin[t.u]) * inv_h_));
    b = std::min(b, floor_index((hi - lattice_.origin[t.u]) * inv_h_));
    if (sweep_.parts[size_t(pi)].start_empty && !start_sphere_keeps(sweep_.parts[size_t(pi)], t, iv, a, b)) continue;
    if (b < a) continue;
    acc.row.push_back({pi, a, b, static_cast<std::ptrdiff_t>(j * kTile) - t.iu0});
    first = std::min(first, a);
    last = std::max(last, b);
  }
  return {first, last};
}

// Where each ray first..last of row iv holds material or meets an obstacle.
void Simulator::ray_ranges(const TileRays& t, int iv, int first, int last, std::array<Interval, kTile>& range) const {
  for (int iu = first; iu <= last; ++iu) {
    Interval& r = range[iu - t.iu0];
    r = material_range(stock_.ray(t.d, iu, iv));
    for (const Obstacle& ob : obstacles_) r = hull(r, obstacle_range(*ob.table, t.d, iu, iv));
  }
}

// The parts' intervals on the rays of row iv under their shadows (acc.t0/t1), in one batch per part and row.
void Simulator::part_intervals(const TileRays& t, int iv, const std::array<Interval, kTile>& range, Accum& acc) const {
  const double h = lattice_.h;
  const double cv = lattice_.origin[t.v] + h * iv;
  for (const RowPart& rp : acc.row) {
    const SweptPart& p = sweep_.parts[rp.part];
    Eigen::Vector3d o = lattice_.origin;
    o[t.u] += h * rp.first;
    o[t.v] = cv;
    if (p.kind == ToolPart::Kind::Sphere || p.arc) {
      ray_intervals(p, o, t.d, t.u, h, rp.last - rp.first + 1, &acc.t0[rp.offset + rp.first],
                    &acc.t1[rp.offset + rp.first]);
      continue;
    }
    if (cylinder_intervals(p, o, t.d, t.u, h, rp.last - rp.first + 1, &acc.t0[rp.offset + rp.first],
                           &acc.t1[rp.offset + rp.first]))
      continue;
    // The rows the batch leaves to the scalar method: only the rays whose range the part can meet.
    const PartSpan& sp = span(rp.part, t.d);
    for (int iu = rp.first; iu <= rp.last; ++iu) {
      o[t.u] = lattice_.origin[t.u] + h * iu;
      double& t0 = acc.t0[rp.offset + iu];
      double& t1 = acc.t1[rp.offset + iu];
      if (!meets(range[iu - t.iu0], sp.lo, sp.hi) || !ray_interval(p, o, t.d, t0, t1)) {
        t0 = std::numeric_limits<double>::infinity();
        t1 = -t0;
      }
    }
  }
}

// Per ray first..last of row iv, the parts' intervals that reach its range, cut from it; true when the
// material of any ray changed.
bool Simulator::cut_row(const TileRays& t, int iv, int first, int last, const std::array<Interval, kTile>& range,
                        bool rapid, Accum& acc) {
  if (acc.row.size() <= kFewRowParts) return cut_row_direct(t, iv, first, last, range, rapid, acc);
  // Each part's hits go to the rays it covers (a row of a 5-axis block meets dozens of swept parts, each
  // over a few of its rays: scattering them costs what they hold, not rays times parts).
  for (int iu = first; iu <= last; ++iu) acc.ray_hits[iu - t.iu0].clear();
  Hit h;
  for (const RowPart& rp : acc.row)
    for (int iu = rp.first; iu <= rp.last; ++iu)
      if (part_hit(rp, iu, range[iu - t.iu0], acc, h)) acc.ray_hits[iu - t.iu0].push_back(h);
  bool row_changed = false;
  for (int iu = first; iu <= last; ++iu) {
    std::vector<Hit>& hits = acc.ray_hits[iu - t.iu0];
    if (hits.empty()) continue;
    acc.hits.swap(hits);
    row_changed |= cut_ray(t, iu, iv, rapid, acc);
    acc.hits.swap(hits);
  }
  return row_changed;
}

// cut_row for a row that few parts meet (a 3-axis block's ball and flutes): each ray gathers its hits
// from the parts directly, which costs less than scattering them.
bool Simulator::cut_row_direct(const TileRays& t, int iv, int first, int last, const std::array<Interval, kTile>& range,
                               bool rapid, Accum& acc) {
  bool row_changed = false;
  for (int iu = first; iu <= last; ++iu) {
    const Interval r = range[iu - t.iu0];
    if (r.lo > r.hi) continue;
    acc.hits.clear();
    Hit h;
    for (const RowPart& rp : acc.row)
      if (iu >= rp.first && iu <= rp.last && part_hit(rp, iu, r, acc, h)) acc.hits.push_back(h);
    if (!acc.hits.empty()) row_changed |= cut_ray(t, iu, iv, rapid, acc);
  }
  return row_changed;
}

// The hit of row part rp on ray iu (range r: where the ray holds material or meets an obstacle) into h;
// false when the part misses the ray or meets none of that range.
bool Simulator::part_hit(const RowPart& rp, int iu, const Interval& r, const Accum& acc, Hit& h) const {
  const double t0 = acc.t0[rp.offset + iu], t1 = acc.t1[rp.offset + iu];
  // Compared as stored: a chord shorter than a float's step would become an empty interval.
  const float f0 = static_cast<float>(t0), f1 = static_cast<float>(t1);
  if (!(f1 > f0) || t1 < r.lo || t0 > r.hi) return false;
  const SweptPart& p = sweep_.parts[rp.part];
  h = {{f0, f1}, static_cast<uint8_t>(p.component), p.cutting};
  return true;
}

// process_ray on ray iu of row iv with its hits in acc.hits, and the block that last cut it kept.
bool Simulator::cut_ray(const TileRays& t, int iu, int iv, bool rapid, Accum& acc) {
  if (!process_ray(t.d, iu, iv, rapid, acc)) return false;
  // One task owns each ray in a block, so no other thread writes this entry.
  if (!last_block_[t.d].empty()) last_block_[t.d][size_t(iu) + size_t(lattice_.n[t.u]) * size_t(iv)] = block_;
  return true;
}

// The hits acc.hits on ray (iu, iv) of grid d: removal, collisions and gouges. True when its material changed.
bool Simulator::process_ray(int d, int iu, int iv, bool rapid, Accum& acc) {
  Dexel& ray = stock_.ray(d, iu, iv);
  // The common case: one cutting part, nothing to check but the removal.
  if (acc.hits.size() == 1 && acc.hits[0].cutting && !rapid && obstacles_.empty() && !design_)
    return subtract(ray, ray_at(d, iu, iv), &acc.hits[0].iv, 1, nullptr, true, acc);
  // Union of the cutting parts' intervals.
  acc.cut.clear();
  for (const Hit& h : acc.hits)
    if (h.cutting) acc.cut.push_back(h.iv);
  merge_union(acc.cut);
  bool changed = false;
  acc.removed_pieces.clear();
  if (!ray.empty()) changed = cut_stock(ray, ray_at(d, iu, iv), rapid, acc);
  record_obstacles(d, iu, iv, rapid, acc);
  if (design_ && !acc.removed_pieces.empty()) record_gouge(d, iu, iv, acc);
  return changed;
}

// On a ray holding material: the cutting parts' union (acc.cut) removed, and the overlaps of a rapid's
// cutting parts and of the non-cutting parts with the material recorded. True when the material changed.
bool Simulator::cut_stock(Dexel& ray, const RayAt& at, bool rapid, Accum& acc) {
  const int d = at.d;
  bool changed = false;
  if (rapid)
    for (const Hit& h : acc.hits)
      if (h.cutting) record(acc, d, h.component, HitWith::Stock, true, overlap_longest(h.iv, {ray.begin(), ray.size()}));
  const bool reaches =
      !acc.cut.empty() && acc.cut.front().lo < (ray.end() - 1)->hi && acc.cut.back().hi > ray.begin()->lo;
  if (reaches && !rapid) note_masked(ray, at, acc);
  if (reaches && subtract(ray, at, acc.cut.data(), acc.cut.size(), design_ ? &acc.removed_pieces : nullptr, true, acc))
    changed = true;
  bool crash = false;
  // The material the cut left, put together only for a shank or holder on the ray: a ray whose change
  // waits for the engagement is copied whole for it (hundreds of intervals across a raster's grooves).
  std::pair<const Interval*, size_t> left{nullptr, 0};
  bool have_left = false;
  for (const Hit& h : acc.hits) {
    if (h.cutting) continue;
    if (!have_left) left = acc.current(ray), have_left = true;
    if (left.second == 0) continue;
    const float depth = overlap_longest(h.iv, left);
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
    if (subtract(ray, at, acc.cut.data(), acc.cut.size(), nullptr, false, acc, left)) changed = true;
  }
  return changed;
}

// A shank or holder whose interval overlaps material the cutting parts take away in this block: the
// removal hides it from the check after the cut (cut_stock), though it may have got there first. The ray
// and its material before the block are kept for add_ordered_depths.
void Simulator::note_masked(const Dexel& ray, const RayAt& at, Accum& acc) const {
  for (const Hit& h : acc.hits) {
    if (h.cutting) continue;
    for (const Interval& c : acc.cut) {
      const Interval x{std::max(h.iv.lo, c.lo), std::min(h.iv.hi, c.hi)};
      if (!(x.hi > x.lo) || overlap_longest(x, {ray.begin(), ray.size()}) <= opt_.collision_tolerance) continue;
      acc.masked.push_back({at.d, at.iu, at.iv, static_cast<uint32_t>(acc.masked_pool.size()), ray.size()});
      acc.masked_pool.insert(acc.masked_pool.end(), ray.begin(), ray.end());
      return;
    }
  }
}

// Every part's overlap with the fixtures and check surfaces on ray (iu, iv) of grid d.
void Simulator::record_obstacles(int d, int iu, int iv, bool rapid, Accum& acc) const {
  for (const Obstacle& o : obstacles_) {
    const Crossing* b = o.table->begin(d, iu, iv);
    if (!b) continue;
    const Crossing* e = o.table->end(d, iu, iv);
    for (const Hit& h : acc.hits)
      record(acc, d, h.component, o.with, rapid, obstacle_depth(b, e, o.table->solid(), h.iv.lo, h.iv.hi));
  }
}

// The deepest over-cut of the design by the pieces just removed from ray (iu, iv) of grid d (acc.gouge).
void Simulator::record_gouge(int d, int iu, int iv, Accum& acc) const {
  double at = 0.0;
  const double est = gouge_depth(design_->begin(d, iu, iv), design_->end(d, iu, iv), acc.removed_pieces, &at);
  // The along-ray estimate selects the point; a point deep inside the part along a ray parallel to its
  // surface is much closer to the surface than the ray says, so the depth is its true distance. Shallower
  // estimates skip the closest-point query: a quarter of the default tolerance, or of a finer one (not of
  // a coarser one, which would hide over-cuts from max_gouge_mm).
  if (est > std::min(kGougeQueryDepth, 0.25 * opt_.gouge_tolerance)) {
    Eigen::Vector3d p = lattice_.origin;
    p[Lattice::u_axis(d)] += lattice_.h * iu;
    p[Lattice::v_axis(d)] += lattice_.h * iv;
    p[d] += at;
    Eigen::Vector3d q, n;
    const double dist = design_mesh_->closest(p, est + 1e-6, q, n) ? (p - q).norm() : est;
    acc.gouge = std::max(acc.gouge, std::min(est, dist));
  }
}

}  // namespace tf::sim
