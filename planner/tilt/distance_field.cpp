#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "distance_field.hpp"

namespace tf {
using Eigen::Vector3d;

DistanceField::DistanceField(const ClearanceBvh& bvh, double cell, double band) : bvh_(bvh), cell_(cell), band_(band) {
  if (bvh.empty()) return;
  const auto box = bvh.bounds();
  const Vector3d pad = Vector3d::Constant(band + 2 * cell);
  origin_ = box.min() - pad;
  const Vector3d ext = box.max() + pad - origin_;
  // Keep the brick index small (it is dense): a huge part with a tiny cell gets a coarser cell.
  for (;;) {
    int64_t total = 1;
    for (int k = 0; k < 3; ++k) {
      dims_[k] = std::max(1, static_cast<int>(std::ceil(ext[k] / (kBrick * cell_))));
      total *= dims_[k];
    }
    if (total <= (int64_t{1} << 25)) break;
    cell_ *= 1.25;
  }
  index_.assign(static_cast<size_t>(dims_[0]) * static_cast<size_t>(dims_[1]) * static_cast<size_t>(dims_[2]), kUnbuilt);
}

bool DistanceField::compute_brick(int bx, int by, int bz, float* out) const {
  const double bs = kBrick * cell_;
  const Vector3d lo = origin_ + Vector3d(bx, by, bz) * bs;
  const Vector3d centre = lo + Vector3d::Constant(0.5 * bs);
  const double half_diag = 0.5 * std::sqrt(3.0) * bs;
  const ClosestHit c = bvh_.closest(centre, band_ + half_diag);
  if (c.triangle < 0) return false;
  int hint = c.triangle;
  int k = 0;
  for (int z = 0; z <= kBrick; ++z)
    for (int y = 0; y <= kBrick; ++y)
      for (int x = 0; x <= kBrick; ++x, ++k) {
        const Vector3d p = lo + Vector3d(x, y, z) * cell_;
        const ClosestHit h = bvh_.closest(p, band_, hint);
        if (h.triangle >= 0) {
          hint = h.triangle;
          out[k] = static_cast<float>(h.distance);
        } else {
          out[k] = static_cast<float>(band_);
        }
      }
  return true;
}

int32_t DistanceField::ensure(int bx, int by, int bz) {
  const size_t id = static_cast<size_t>(brick_id(bx, by, bz));
  if (index_[id] != kUnbuilt) return index_[id];
  float tmp[kNodes];
  ++built_;
  if (!compute_brick(bx, by, bz, tmp)) return index_[id] = kFar;
  const size_t off = values_.size();
  values_.insert(values_.end(), tmp, tmp + kNodes);
  return index_[id] = static_cast<int32_t>(off / kNodes);
}

void DistanceField::prefetch(const std::vector<Vector3d>& points, double radius) {
  if (index_.empty()) return;
  std::set<int64_t> wanted;
  const double bs = kBrick * cell_;
  for (const Vector3d& p : points) {
    const Vector3d lo = (p - Vector3d::Constant(radius) - origin_) / bs, hi = (p + Vector3d::Constant(radius) - origin_) / bs;
    int a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = static_cast<int>(std::clamp(std::floor(lo[k]), 0.0, static_cast<double>(dims_[k])));
      b[k] = static_cast<int>(std::clamp(std::floor(hi[k]), -1.0, static_cast<double>(dims_[k] - 1)));
    }
    for (int z = a[2]; z <= b[2]; ++z)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int x = a[0]; x <= b[0]; ++x) {
          const int64_t id = brick_id(x, y, z);
          if (index_[static_cast<size_t>(id)] == kUnbuilt) wanted.insert(id);
        }
  }
  const std::vector<int64_t> ids(wanted.begin(), wanted.end());
  std::vector<float> vals(ids.size() * kNodes);
  std::vector<char> near(ids.size(), 0);
  tbb::parallel_for(size_t{0}, ids.size(), [&](size_t i) {
    const int64_t id = ids[i];
    const int bx = static_cast<int>(id % dims_[0]), by = static_cast<int>((id / dims_[0]) % dims_[1]),
              bz = static_cast<int>(id / (static_cast<int64_t>(dims_[0]) * dims_[1]));
    near[i] = compute_brick(bx, by, bz, vals.data() + i * kNodes) ? 1 : 0;
  });
  for (size_t i = 0; i < ids.size(); ++i) {
    ++built_;
    if (!near[i]) {
      index_[static_cast<size_t>(ids[i])] = kFar;
      continue;
    }
    const size_t off = values_.size();
    values_.insert(values_.end(), vals.begin() + static_cast<std::ptrdiff_t>(i * kNodes),
                   vals.begin() + static_cast<std::ptrdiff_t>((i + 1) * kNodes));
    index_[static_cast<size_t>(ids[i])] = static_cast<int32_t>(off / kNodes);
  }
}

}  // namespace tf
