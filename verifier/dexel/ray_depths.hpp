// tiltfield verifier: depths measured along the rays of the lattice, from an obstacle's or the design's
// crossings on a ray (obstacles.hpp) and the intervals a block's parts cover or removed there, or the
// material left.
#pragma once
#include <vector>

#include "obstacles.hpp"
#include "tiltfield/dexel/tridexel.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {

// Overlap of the interval [a, b] with an obstacle's crossings [c, e) on one ray, mm: solid obstacles by
// their inside spans (winding), open surfaces by the distance from a crossing to the nearer end of [a, b].
float obstacle_depth(const Crossing* c, const Crossing* e, bool solid, float a, float b);

// Deepest over-cut (normal to the design) of the removed pieces on one ray, mm, from the design's
// crossings [c, e); `where` receives the position along the ray. 0 when none.
double gouge_depth(const Crossing* c, const Crossing* e, const std::vector<Interval>& removed, double* where);

// Material left outside the design: at every crossing of the design with |cos| >= 0.5, the thickness of
// the stock's material on the outer side along the ray times |cos| (mm); count, mean, 95th percentile
// and maximum over all of them.
ExcessStats excess_left(const RayTable& design, const TriDexel& stock);

}  // namespace tf
