// Removed pieces of one change per ray, and the stock read as it was before it (stock_before.hpp).
#include "tiltfield/dexel/stock_before.hpp"

#include <algorithm>
#include <stdexcept>

namespace tf {

void RemovedPieces::start(const std::array<Footprint, 3>& footprint, int writers) {
  if (++stamp_ == 0) {  // the counter wrapped: entries of 2^32 changes ago would read as current
    for (auto& t : table_) std::fill(t.begin(), t.end(), Entry{});
    stamp_ = 1;
  }
  fp_ = footprint;
  for (int d = 0; d < 3; ++d) {
    const Footprint& f = fp_[size_t(d)];
    const size_t n = f.iu1 < f.iu0 || f.iv1 < f.iv0 ? 0 : size_t(f.iu1 - f.iu0 + 1) * size_t(f.iv1 - f.iv0 + 1);
    if (table_[size_t(d)].size() < n) table_[size_t(d)].resize(n);
  }
  if (writers_.size() < size_t(std::max(1, writers))) writers_.resize(size_t(std::max(1, writers)));
  for (Writer& w : writers_) w.used = 0, w.rays = 0;
}

void RemovedPieces::outside_the_change() {
  throw std::logic_error("RemovedPieces::add: writer or ray outside the change");
}

void RemovedPieces::add_again(int w, Entry& e, const Interval* pieces, size_t n) {
  if (e.whole) return;  // the material before the first removal holds the second's pieces too
  const Interval* old = writers_[e.writer].pool.data() + e.offset;
  std::vector<Interval> both;
  std::merge(old, old + e.n, pieces, pieces + n, std::back_inserter(both),
             [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  Writer& wr = writers_[size_t(w)];
  e = {stamp_, uint32_t(w), uint32_t(wr.used), uint32_t(both.size()), 0u};
  wr.append(both.data(), both.size());
}

void RemovedPieces::add_before_again(int w, Entry& e, const Interval* before, size_t n) {
  if (e.whole) return;  // the first record is the material before the change
  // `before` is the ray after the first removal: with that removal's pieces, the ray before the change.
  std::vector<Interval> all;
  join_disjoint(before, n, writers_[e.writer].pool.data() + e.offset, e.n, all);
  Writer& wr = writers_[size_t(w)];
  e = {stamp_, uint32_t(w), uint32_t(wr.used), uint32_t(all.size()), 1u};
  wr.append(all.data(), all.size());
}

size_t RemovedPieces::rays() const {
  size_t n = 0;
  for (const Writer& w : writers_) n += w.rays;
  return n;
}

void join_disjoint(const Interval* a, size_t na, const Interval* b, size_t nb, std::vector<Interval>& out) {
  out.clear();
  size_t i = 0, j = 0;
  while (i < na || j < nb) {
    const Interval& x = j >= nb || (i < na && a[i].lo <= b[j].lo) ? a[i++] : b[j++];
    if (!out.empty() && x.lo <= out.back().hi) out.back().hi = std::max(out.back().hi, x.hi);
    else out.push_back(x);
  }
}

void StockBefore::ray(int d, int iu, int iv, std::vector<Interval>& out) const {
  const RemovedPieces::Kept k = kept(d, iu, iv);
  if (k.whole) return join_disjoint(k.p, k.n, nullptr, 0, out);
  const Dexel& r = now_->ray(d, iu, iv);
  join_disjoint(r.begin(), r.size(), k.p, k.n, out);
}

}  // namespace tf
