// tiltfield offset: offset-profile trajectories for copy milling and ECM (Gawlik, Karbowski, Ruszaj).
//
// A section profile (a closed chain of lines and arcs, see docs/offset.md) is offset by a gap D, constant
// or varying along the profile's arc length, to the inside or the outside of the figure. Lines offset to
// lines, arcs to arcs with R' = R - D or R + D; joins are exact (line/arc intersections or arcs of radius
// D about the vertex); invalid local and global loops are cut away, so a narrow neck splits the result.
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "tiltfield/offset/offset_geometry.hpp"

namespace tf::offset {

// A closed profile: elements in order, each ending where the next starts, the last ending at the first's
// start. `file` names the source for error messages.
struct Profile {
  std::vector<Segment> elements;
  std::string file;
};

// Coordinates, radii, chords and gaps beyond this (mm) are typos, not parts: the geometry's tolerances
// scale with the profile, and a 1e300 came out as a "self-crossing" profile rather than as the number it is.
inline constexpr double kMaxLengthMm = 1e6;

// Parses the profile text format (`START x y`, then `R DX DY [LONG]` a line; '#' starts a comment).
// Throws InputError(file, line, field, ...) for garbage, an empty profile, a zero-length element, an arc
// whose chord is longer than 2|R|, or a profile that does not end where it started (the last element's
// line). Within 1e-6 mm the end is snapped onto the start. Does not check for self-crossing.
Profile parse_profile(std::string_view text, const std::string& file);

// Reads and parses a file, then validate_profile(). Throws InputError.
Profile read_profile(const std::filesystem::path& file);

// Throws InputError naming the later element's line when two elements cross or touch anywhere but at
// their shared vertex (a self-crossing profile).
void validate_profile(const Profile& profile);

// The profile in the text format (numbers with 9 decimals), e.g. for a section fitted from a mesh.
std::string format_profile(const Profile& profile);

// The gap as a function of the profile's arc length s (mm): linear interpolation of (s, gap) knots,
// constant beyond the first and the last knot. blend > 0 (mm) rounds each interior knot with a parabola
// over [s_k - blend, s_k + blend] (C1 gap, hence a tangent-continuous trajectory); it changes the law only
// inside those windows. A single knot is a constant gap.
struct GapLaw {
  std::vector<double> s, gap;  // knots, s strictly increasing, gap > 0 (mm)
  double blend = 0;            // half-width of the parabolic blend at interior knots, mm
  std::string file;            // source CSV for error messages (empty for a constant gap)
};
GapLaw constant_gap(double gap);
// Reads the CSV `s,gap`. Throws InputError for a missing column, a bad number, s not increasing, a gap
// that is not positive, or a value beyond +-kMaxLengthMm.
GapLaw read_gap_law(const std::filesystem::path& file);
double gap_at(const GapLaw& law, double s);
bool is_constant(const GapLaw& law);
// Arc lengths inside [0, L] where the law's slope changes (knots, or blend window ends), sorted.
std::vector<double> gap_breaks(const GapLaw& law, double L);

enum class Side { Inside, Outside };
enum class Corner { Round, Sharp };

struct OffsetOptions {
  Side side = Side::Inside;
  Corner corner = Corner::Round;  // Round: arc of radius D at convex corners (a truly constant gap)
  // Sharp joins whose intersection lies further than miter_limit * D from the vertex fall back to a
  // round join (an almost reversing corner would otherwise shoot far out).
  double miter_limit = 10.0;
  // Variable gap: arcs approximate the (non-circular) offset of an arc within this distance, mm.
  double arc_tolerance = 2e-7;
};

struct OffsetResult {
  // Closed contours, each a chain of segments (end of one == start of the next, last end == first start),
  // oriented like the profile. Holes of an outside offset come out with the opposite orientation.
  std::vector<std::vector<Segment>> contours;
  int raw_segments = 0;   // segments of the raw offset before loop removal
  int crossings = 0;      // self-intersection points of the raw offset
  // Variable gap only: pieces of the raw offset that run from closer than the law to farther without
  // crossing the rest, where the closest profile element changes and the law differs across the change.
  // The valid region's boundary then runs along that change (the medial axis), which the method does not
  // build: such pieces are dropped, and the contours may miss part of the region (or be empty).
  int unresolved = 0;
  Eigen::Vector2d unresolved_at{0, 0};  // a point of the first such piece, mm
};

// The trajectory at the gap law's distance from the profile. Throws InputError (field "gap-law") when a
// closed profile's gap differs at s = 0 and s = L.
OffsetResult offset_profile(const Profile& profile, const GapLaw& law, const OffsetOptions& options);

// A query structure over a profile and its gap law. The clearance of a point q is its distance to the
// profile minus the gap at the closest point's arc length s*: 0 on the trajectory (whose points lie at
// gap(s*) from the profile), < 0 where a point comes closer to the profile than the gap asks there.
struct ClearanceField;
struct ClearanceFieldDeleter {
  void operator()(ClearanceField* f) const;
};
using ClearanceFieldPtr = std::unique_ptr<ClearanceField, ClearanceFieldDeleter>;
ClearanceFieldPtr make_clearance_field(const Profile& profile, const GapLaw& law);
// Clearance of q (mm); writes the arc length s* (mm) of the closest profile point.
double clearance(const ClearanceField& field, const Eigen::Vector2d& q, double* s_at = nullptr);
// Plain distance of q to the profile (mm) and the arc length of the closest point.
double profile_distance(const ClearanceField& field, const Eigen::Vector2d& q, double* s_at = nullptr);

}  // namespace tf::offset
