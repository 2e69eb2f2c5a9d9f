// tiltfield dexel: a tri-dexel stock read as it was before a change (one block's cut) without a copy of
// every ray the change touched. The change keeps, per ray it touched inside a footprint, either the ray's
// material before it (a ray of few intervals: as cheap to copy as its pieces, and read without a merge)
// or the pieces it removed (a long ray); the ray before the change is then its intervals now together
// with those pieces.
//
// In: the stock after the change and what the change kept (coordinates along the ray from the lattice
// origin, mm, as in Interval). Out: per ray, its material before the change.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "tiltfield/dexel/tridexel.hpp"

namespace tf {

// What one change removed from the rays of a TriDexel inside a footprint per grid. Each ray has
// one writer; writers (threads) are told apart by an index below the count given to start() and append to
// their own storage, so a change is recorded from several threads without locks. Entries of earlier
// changes are told apart by a counter, not cleared, so that starting a change costs nothing per ray.
class RemovedPieces {
 public:
  // Rays iu0..iu1 of rows iv0..iv1 of one grid (inclusive; empty when iu1 < iu0 or iv1 < iv0).
  struct Footprint {
    int iu0 = 0, iu1 = -1, iv0 = 0, iv1 = -1;
    bool holds(int iu, int iv) const { return iu >= iu0 && iu <= iu1 && iv >= iv0 && iv <= iv1; }
  };

  // Starts a change: rays inside `footprint` may be recorded, by writers 0..writers-1.
  void start(const std::array<Footprint, 3>& footprint, int writers);
  const Footprint& footprint(int d) const { return fp_[size_t(d)]; }
  // Adds pieces[0..n) (sorted, disjoint, taken from the ray's material now) to what ray (d, iu, iv) has
  // lost in this change. The ray lies inside the footprint, and only writer w writes it in this change.
  void add(int w, int d, int iu, int iv, const Interval* pieces, size_t n) { record(w, checked(w, d, iu, iv), pieces, n, false); }
  // Records instead ray (d, iu, iv)'s whole material before this change, before[0..n) (sorted,
  // disjoint), under the same conditions as add(). A ray without material lost none: nothing to record.
  void add_before(int w, int d, int iu, int iv, const Interval* before, size_t n) {
    record(w, checked(w, d, iu, iv), before, n, true);
  }
  // The same for a caller that asks once whether a ray lies inside the footprint and records it later
  // (the cut asks of every ray it changes, thousands a block): slot() is the ray's record in this change,
  // null outside the footprint; add() and add_before() on a slot check only the writer.
  struct Entry;
  Entry* slot(int d, int iu, int iv) {
    const Footprint& f = fp_[size_t(d)];
    return f.holds(iu, iv) ? &table_[size_t(d)][index(f, iu, iv)] : nullptr;
  }
  void add(int w, Entry* e, const Interval* pieces, size_t n) { record(w, checked(w, e), pieces, n, false); }
  void add_before(int w, Entry* e, const Interval* before, size_t n) { record(w, checked(w, e), before, n, true); }
  // What this change kept of ray (d, iu, iv): sorted, disjoint intervals, the ray's material before the
  // change (`whole`) or the pieces it lost; n = 0 when the change did not touch it (or it is outside).
  struct Kept {
    const Interval* p = nullptr;
    size_t n = 0;
    bool whole = false;
  };
  Kept kept(int d, int iu, int iv) const {
    const Footprint& f = fp_[size_t(d)];
    if (!f.holds(iu, iv)) return {};
    const Entry& e = table_[size_t(d)][index(f, iu, iv)];
    if (e.stamp != stamp_) return {};
    return {writers_[e.writer].pool.data() + e.offset, e.n, e.whole != 0};
  }
  // Rays recorded in this change.
  size_t rays() const;
  // A ray's record (opaque to callers): in this change when its stamp is the change's.
  struct Entry {
    uint32_t stamp = 0, writer = 0, offset = 0;
    uint32_t n : 31 = 0, whole : 1 = 0;
  };

 private:
  Entry& checked(int w, int d, int iu, int iv) {
    Entry* e = slot(d, iu, iv);
    if (!e) [[unlikely]]
      outside_the_change();
    return checked(w, e);
  }
  Entry& checked(int w, Entry* e) {
    if (size_t(w) >= writers_.size() || !e) [[unlikely]]
      outside_the_change();
    return *e;
  }
  void record(int w, Entry& e, const Interval* p, size_t n, bool whole) {
    if (n == 0) return;
    if (e.stamp == stamp_ && e.n > 0) [[unlikely]]
      return whole ? add_before_again(w, e, p, n) : add_again(w, e, p, n);
    Writer& wr = writers_[size_t(w)];
    e = {stamp_, uint32_t(w), uint32_t(wr.used), uint32_t(n), whole ? 1u : 0u};
    wr.append(p, n);
    ++wr.rays;
  }
  [[noreturn]] static void outside_the_change();
  // A ray removed from a second time in one change (a crash after the cut): the pieces of both, in order,
  // or the material before the first.
  void add_again(int w, Entry& e, const Interval* pieces, size_t n);
  void add_before_again(int w, Entry& e, const Interval* before, size_t n);
  static size_t index(const Footprint& f, int iu, int iv) {
    return size_t(iv - f.iv0) * size_t(f.iu1 - f.iu0 + 1) + size_t(iu - f.iu0);
  }
  std::array<Footprint, 3> fp_{};
  std::array<std::vector<Entry>, 3> table_;
  // Per writer, a cache line of its own (two threads appending to neighbouring vectors slowed the cut
  // more than twofold): the pieces it recorded and the count of its rays.
  struct alignas(64) Writer {
    std::vector<Interval> pool;  // pool[0..used): this change's records
    size_t used = 0, rays = 0;
    // The pool only grows (its storage is kept from change to change), so a record is a few copies.
    void append(const Interval* p, size_t n) {
      if (used + n > pool.size()) [[unlikely]]
        pool.resize(std::max(2 * pool.size(), used + n + 1024));
      Interval* dst = pool.data() + used;
      for (size_t k = 0; k < n; ++k) dst[k] = p[k];
      used += n;
    }
  };
  std::vector<Writer> writers_;
  uint32_t stamp_ = 0;
};

// A TriDexel as it was before a change: `now` with the pieces `removed` put back. Without pieces, the
// stock itself.
class StockBefore {
 public:
  explicit StockBefore(const TriDexel& now, const RemovedPieces* removed = nullptr) : now_(&now), removed_(removed) {}
  const TriDexel& now() const { return *now_; }
  const Lattice& lattice() const { return now_->lattice(); }
  RemovedPieces::Kept kept(int d, int iu, int iv) const {
    return removed_ ? removed_->kept(d, iu, iv) : RemovedPieces::Kept{};
  }
  // Ray (d, iu, iv) as it was: sorted, disjoint intervals (a removed piece and the material it touched
  // are one interval again; touching intervals are joined).
  void ray(int d, int iu, int iv, std::vector<Interval>& out) const;

 private:
  const TriDexel* now_;
  const RemovedPieces* removed_;
};

// The union of two sorted lists of disjoint intervals whose intervals do not overlap each other's (they
// may touch), with touching intervals joined: into `out` (cleared first).
void join_disjoint(const Interval* a, size_t na, const Interval* b, size_t nb, std::vector<Interval>& out);

}  // namespace tf
