// tiltfield dexel (internal): what the batched row kernels (capsule_rows.cpp, cylinder_rows.cpp) share. They
// compute one interval per lattice ray of a row with no branches per ray, so that the compiler vectorises
// them; each is built for AVX-512, AVX2 and baseline x86-64 and the best is picked at load time
// (TF_VECTOR_CLONES).
#pragma once
#include <limits>

#include "tiltfield/core/internal/vector_clones.hpp"

namespace tf::row_kernels {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Calls lane(i, t0[i], t1[i]) for i = 0 .. n-1 in blocks of kLanes rays: a loop of known trip count
// vectorises without a scalar remainder. The last, partial block goes through a buffer, copied by a plain
// loop (see verifier/CMakeLists.txt for why it stays one).
template <class Lane>
[[gnu::always_inline]] inline void in_blocks(int n, double* __restrict t0, double* __restrict t1, Lane lane) {
  constexpr int kLanes = 8;
  int base = 0;
  for (; base + kLanes <= n; base += kLanes)
    for (int i = 0; i < kLanes; ++i) lane(base + i, t0[base + i], t1[base + i]);
  if (base == n) return;
  double b0[kLanes], b1[kLanes];
  for (int i = 0; i < kLanes; ++i) lane(base + i, b0[i], b1[i]);
  for (int i = 0; i < n - base; ++i) {
    t0[base + i] = b0[i];
    t1[base + i] = b1[i];
  }
}

}  // namespace tf::row_kernels
