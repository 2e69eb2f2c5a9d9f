// Internal to the offset module: pieces of the profile on which the gap law is smooth.
#pragma once
#include <vector>

#include "tiltfield/offset/offset.hpp"

namespace tf::offset {

// A profile element, or the part of one between two gap-law breaks.
struct Piece {
  Segment seg;
  int element = 0;        // index of the profile element
  double s0 = 0, s1 = 0;  // arc length along the profile at its ends, mm
  double g0 = 0, g1 = 0;  // gap at its ends, mm
  bool linear = true;     // the gap is linear in s on the piece (no blend window)
  bool constant = true;   // the gap is constant on the piece
};

// The profile's elements split at the law's breaks, in order.
std::vector<Piece> profile_pieces(const Profile& profile, const GapLaw& law);
bool gap_linear_between(const GapLaw& law, double s0, double s1);
const std::vector<Piece>& field_pieces(const ClearanceField& field);
// clearance(field, q) < -eps, answered faster (first element found within the gap) for a constant gap.
bool closer_than_gap(const ClearanceField& field, const Eigen::Vector2d& q, double eps);

// The raw offset: a closed chain of offset pieces and joins, before loop removal. sigma = +1 offsets to
// the left of the profile's direction, -1 to the right. tol: length tolerance, mm.
std::vector<Segment> raw_offset(const Profile& profile, const GapLaw& law, const OffsetOptions& options,
                                double sigma, double tol);

// Cuts the raw offset at its self-intersections and keeps the closed chains whose clearance is >= -eps.
// Pieces judged closer than the gap that hold points clearly farther than it (variable gap only) are
// counted in `unresolved` with a point of the first in `unresolved_at` (OffsetResult).
std::vector<std::vector<Segment>> remove_loops(const std::vector<Segment>& raw, const ClearanceField& field,
                                               double tol, double eps, int* crossings, int* unresolved = nullptr,
                                               Eigen::Vector2d* unresolved_at = nullptr);

// Sharp corners: complete round joins become the neighbours' extensions to their intersection where that
// miter keeps a clearance >= -eps (mm) and crosses no path segment; miter_limit as in OffsetOptions.
void apply_sharp_corners(std::vector<std::vector<Segment>>& contours, const ClearanceField& field,
                         double miter_limit, double eps);

// Variable gap: splits the contours' segments where their clearance leaves 0 (within thr, mm) and marks
// the parts off the law as SegmentKind::Transition.
void mark_transitions(std::vector<std::vector<Segment>>& contours, const ClearanceField& field, double thr);

}  // namespace tf::offset
