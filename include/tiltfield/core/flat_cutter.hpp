// tiltfield: flat-end cutter. Tool frame: tip at the origin, axis +z toward the spindle, mm.
#pragma once

namespace tf {

struct FlatCutter {
  double radius = 3.0;  // cutter radius, mm

  // The cutter location of a flat end mill is the centre of its end face.
  double cl_height() const { return 0.0; }
  double end_height() const { return 0.0; }
  double end_radius_at(double) const { return radius; }
};

}  // namespace tf
