// tiltfield engagement (internal): one block's rings (their samples, engaged arcs and the extent of the
// engaged surface) and the area between neighbouring rings (ring_area.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "cutting_surface.hpp"
#include "sampler.hpp"

namespace tf::engagement {

// Boundaries are refined until their bracket is this fraction of the lattice spacing, and the boundary
// is the zero interpolated inside it: a sample is classified by rays up to half a spacing away, so the
// stock is not resolved more finely, and further steps only follow the classification's noise (a quarter
// and an eighth gave the same figures on every closed-form case of tests/engagement, to 1e-4 mm^2; a
// half looks the raster's stock up 13 % less often).
inline constexpr double kRefineFraction = 0.5;
// Neighbouring rings' fractions are integrated as a polynomial only where every end of their engaged
// pieces moves around the tool by at most this many ring spacings (arc length at the larger ring) from one
// ring to the next (ring_area.cpp, same_pieces): a boundary running at least about 27 degrees off the
// rings. Arc length, not angle: near a ball's tip the ends turn fast but move little.
inline constexpr double kSmoothEndMove = 2.0;
// Rings (or pairs of rings) a task takes at once when they are spread over the threads.
inline constexpr int kRingGrain = 4;

// Per ring: the engaged arcs (radians, entry < exit, exit may pass 2 pi) found around the ring.
struct RingResult {
  std::vector<std::pair<double, double>> arcs;
  // The arcs as the lattice resolves them, to tell whether neighbouring rings hold the same pieces of the
  // engaged region: arcs less than two lattice spacings apart (arc length) joined, arcs shorter than one
  // left out.
  std::vector<std::pair<double, double>> pieces;
  double angle = 0.0;  // engaged radians in total
  void clear() { arcs.clear(), pieces.clear(), angle = 0.0; }  // keeps the storage for the next block
};

// Largest and smallest of cos over the arc [a, b] (radians, b >= a, b - a <= 2 pi).
void cos_range(double a, double b, double& lo, double& hi);

// rr.pieces from rr.arcs on a ring of radius r, for lattice spacing h.
void resolved_pieces(RingResult& rr, double r, double h);

// One block's samples: rings i0..i1 are classified (the only ones whose band can meet the region),
// every other ring reads as disengaged. Angles j from -na to 2 na - 1 wrap around.
struct BlockSamples {
  int i0 = 0, i1 = -1, na = 0;
  bool parallel = false;          // enough samples to classify that the work is spread over the threads
  std::vector<RingFrame> frame;   // rings i0..i1
  std::vector<PointState> state;  // ring-major, rings i0..i1
  std::vector<uint8_t> eng;       // the same, engaged or not
  size_t index(int i, int j) const { return size_t(i - i0) * na + (j < 0 ? j + na : j >= na ? j - na : j); }
  const RingFrame& frame_of(int i) const { return frame[size_t(i - i0)]; }
  const PointState& at(int i, int j) const { return state[index(i, j)]; }
};

// The engaged area (mm^2) and the extent of the engaged surface: its heights z along the axis and its
// offsets w along n.
struct Extent {
  double area = 0.0;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  double wmin = zmin, wmax = -zmin;
  void add(const Extent& o) {
    area += o.area;
    zmin = std::min(zmin, o.zmin), zmax = std::max(zmax, o.zmax);
    wmin = std::min(wmin, o.wmin), wmax = std::max(wmax, o.wmax);
  }
};

// The area between every pair of neighbouring rings around the classified ones (b.i0 - 1 to b.i1 + 1), and
// the boundaries found there, into x: per pair on its own (on the threads when the rings were), then added
// in order, so that the sum does not depend on the threads. `parts`: a buffer.
void add_pair_areas(const SampleGrid& g, const BlockSamples& b, const std::vector<RingResult>& rings,
                    const Sampler& sampler, const Profile& prof, int evaluations, std::vector<Extent>& parts,
                    Extent& x);

}  // namespace tf::engagement
