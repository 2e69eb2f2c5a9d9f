// tiltfield planner (internal): a flat or bull end against the design surface it cuts.
//
// Such an end touches the design at its contact, and turned about it can dip below the surface elsewhere:
// at a lead of 0 on a concave surface its rim digs in by the curvature (a flat R 3 across a trough of
// radius 30: 0.15 mm at the rim, more where the contact sits on the rim), which no clearance to the
// check surfaces sees, as the end touches the design by definition. Leaning the end forward lifts the
// rest of it off the surface (a flat end clears a concave radius rho from a lead of about asin(R / rho),
// along the feed and across it). A ball turns about its centre and no axis moves it: it is not checked.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {

struct EndForm {
  TriangleBvh design;
  // The lower surface of the end (a flat end's face and rim; a bull end's face and corner), tool frame:
  // the tip at the origin, the axis +z, mm.
  std::vector<Eigen::Vector3d> points;
  double reach = 0;  // the end's radius, mm: how far from the design a point is looked at
  bool active() const { return !points.empty() && !design.empty(); }
};

// In: the tool and the design meshes. Out: the end form's samples (about 5 degrees apart around the rim)
// with a hierarchy over the design; empty for a ball end or without a design.
EndForm make_end_form(const Tool& tool, const std::vector<const Mesh*>& design);

// In: the end form, a contact point on the design (mm) and the design's outward unit normal there. Out:
// +1 where the design's triangles face out of the material there, -1 where they face into it, 0 where no
// triangle lies within a tenth of the end's radius of the contact (the path is not on the design: nothing to dip under).
int design_side(const EndForm& form, const Eigen::Vector3d& contact, const Eigen::Vector3d& normal);

// In: the end form, a point (mm) and design_side() there. Out: how deep the point lies below the design
// surface by the rule below, mm (0 when it does not).
double point_dip(const EndForm& form, const Eigen::Vector3d& x, int side, int* hint = nullptr);

// In: the end form, the tool's tip (mm) and unit axis, and design_side() at the row's contact. Out: how
// deep the end's deepest sample lies below the design surface, mm (0 when none does). A sample counts as
// below when its nearest point of the design lies within the end's radius and the sample is clearly on
// the material side of that triangle (more than 30 deg off its plane): a point beside an edge of the
// design is not.
// `stop_above`: return as soon as a sample is found deeper than this (a yes/no question).
double end_dip(const EndForm& form, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis, int side,
               double stop_above = std::numeric_limits<double>::infinity());

}  // namespace tf
