// tiltfield: the tool as a body of revolution: cutter end form, flutes, shank and stacked holder cylinders.
//
// Tool frame: the tip at the origin, the axis +z pointing from the tip toward the spindle, mm.
// Heights along the axis: [0, end_height) is the end form ("ball" component for every cutter type, as
// the report names it), [end_height, flute_length) the fluted cylinder, [flute_length, length) the
// shank, and from `length` (the gauge length, tip to holder face) upward the holder segments in order.
#pragma once
#include <Eigen/Core>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "tiltfield/core/ball_cutter.hpp"
#include "tiltfield/core/bull_cutter.hpp"
#include "tiltfield/core/flat_cutter.hpp"

namespace tf {

using Cutter = std::variant<BallCutter, FlatCutter, BullCutter>;

enum class ToolComponent { Ball, Flute, Shank, Holder };
std::string_view to_string(ToolComponent c);

struct HolderSegment {
  double radius = 12.0;  // mm
  double length = 40.0;  // mm
};

// A point on the tool body's surface, in the tool frame.
struct ToolSample {
  Eigen::Vector3d p;       // mm
  Eigen::Vector3d normal;  // outward unit normal of the body there
  ToolComponent component;
  int holder_segment = -1;  // index for Holder samples, -1 otherwise
};

struct Tool {
  Cutter cutter = BallCutter{};
  double flute_length = 12.0;  // mm from the tip
  double shank_radius = 3.0;   // mm
  double length = 60.0;        // gauge length, tip to holder face, mm
  std::vector<HolderSegment> holder;

  double radius() const;            // cutter radius, mm
  double cl_height() const;         // cutter location above the tip, mm
  double end_height() const;        // top of the end form, mm
  double total_length() const;      // tip to the top of the last holder segment, mm
  std::string_view type_name() const;  // "ball", "flat" or "bull"

  // Radius of the body at height h (mm above the tip); 0 outside [0, total_length()].
  double radius_at(double h) const;
  ToolComponent component_at(double h) const;
  // Largest radius over [h0, h1].
  double max_radius_between(double h0, double h1) const;

  // In: the design surface's unit normal n at a path row and a unit tool axis. Out: how far the cutter
  // location moves off the row's point for that axis, mm (part frame). A ball turns about its centre: 0.
  // A flat or bull end's row point is the contact point plus the corner radius r times n (the contact
  // point itself for a flat end, the ball centre for r = R): turned about it, a tilted end dug R sin(tilt)
  // into the surface (black-box testing). The end keeps touching there when the cutter location moves by
  // (R - r) along n's part normal to the axis; the move is the least that keeps the end within 0.001 mm
  // below the contact, 0 for an axis within about 0.02 deg of n (the end face flat on the surface), so
  // tiny axis changes there do not move the end. n zero (unknown): 0, the row point is the cutter
  // location itself.
  Eigen::Vector3d contact_offset(const Eigen::Vector3d& n, const Eigen::Vector3d& axis) const;
  // How far below its contact contact_offset() leaves a tilted flat or bull end, mm.
  static constexpr double kContactDipMm = 1e-3;
  // In: a path row's point p (mm), its surface normal n (zero: unknown) and a unit tool axis. Out: the
  // tool's tip there, mm: the cutter location p + contact_offset(n, axis), cl_height() down the axis.
  Eigen::Vector3d tip_at(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& axis) const {
    return p + contact_offset(n, axis) - cl_height() * axis;
  }

  // Points spread over the whole body surface (end form, flutes, shank, every holder segment and the
  // annular faces between them) about `spacing` mm apart, with outward normals. Deterministic.
  std::vector<ToolSample> sample_surface(double spacing) const;
};

// Consecutive rows whose tool tips lie farther apart than this (mm) are linked by the post (retract,
// rapid, approach), not cut through, and the planner does not check a cutting motion across them: 4
// cutter radii, at least 1 mm. Shared so that both sides draw the line at the same place.
inline constexpr double kLinkGapToolRadii = 4.0;
double default_link_gap(const Tool& tool);

// Throws InputError(file, 0, field, ...) when a dimension is not positive/finite or the stack is
// inconsistent (flute_length < end form height, length < flute_length, ...). `field_prefix` is the JSON
// path of the tool object, e.g. "tool".
void validate_tool(const Tool& tool, const std::string& file, const std::string& field_prefix);

}  // namespace tf
