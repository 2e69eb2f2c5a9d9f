// tiltfield scene generators: the paper's open pocket. A floor slab (the design), two side walls as check
// solids, open at both ends along x: a vertical wall on the y = 0 side and a wall on the y = width side
// whose inner face overhangs the floor by `overhang_deg` from the vertical. A zig-zag floor-finishing
// path with a ball end mill runs along x between the walls (normals +z); the nominal axis (+z) meets the
// overhang on the passes near it.
//
// Frame, mm: floor top at z = 0 over x in [0, length], y in [0, width] between the wall feet; the slab
// reaches under the walls (y from -wall_thickness to width + wall_thickness) down to -floor_thickness.
#pragma once
#include <nlohmann/json.hpp>

#include "scene_writer.hpp"

namespace tf::scenes {

struct PocketOptions {
  double length = 80.0;          // along x, open ends, mm
  double width = 40.0;           // floor width between the wall feet, mm
  double floor_thickness = 10.0; // mm
  double wall_height = 25.0;     // above the floor, mm
  double wall_thickness = 8.0;   // at the foot, mm
  double overhang_deg = 25.0;    // inner face of the second wall leaning over the floor, deg, [0, 60]
  double wall_sink = 1.0;        // walls reach this far into the floor slab (no gap), mm
  double allowance = 0.5;        // stock above the floor, mm
  double tool_radius = 3.0;      // ball radius, mm
  double step = 0.5;             // cutter-location spacing, mm
  int passes = 9;                // passes across the floor, >= 1
  double ball_clearance = 1.2;   // least distance of the ball to the walls, mm (above the 1.0 mm safety distance)
  double feed = 1500.0;          // mm/min
};

// Throws InputError("scene pocket", 0, "--option", what) for the first option out of range.
void validate_pocket_options(const PocketOptions& o);

// The whole scene (floor.stl, wall_vertical.stl, wall_overhang.stl, stock box, path, machine).
SceneBundle make_pocket_scene(const PocketOptions& options, const nlohmann::json& machine);

}  // namespace tf::scenes
