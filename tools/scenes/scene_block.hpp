// tiltfield scene generators: a small 3-axis scene. A box stock, the finished block (the stock less the
// facing depth) as the design, a flat end mill facing the top in a zig-zag (cutter location = the centre
// of the tool's end face, normals +z), a 3-axis machine, no check surfaces.
//
// Frame, mm: the stock is [0, size_x] x [0, size_y] x [0, height]; the faced top is at height - depth.
// Passes run along x from x = -(r + 2) to size_x + r + 2 (entering and leaving off the block), stepping
// across y from 0 to size_y by at most `stepover`.
#pragma once
#include <nlohmann/json.hpp>

#include "scene_writer.hpp"

namespace tf::scenes {

struct BlockOptions {
  double size_x = 60.0;      // mm
  double size_y = 40.0;      // mm
  double height = 20.0;      // stock height, mm
  double depth = 1.0;        // facing depth, mm, < height
  double tool_radius = 4.0;  // flat end mill radius, mm
  double stepover = 6.0;     // largest distance between passes, mm, <= 2 r
  double step = 0.5;         // cutter-location spacing, mm
  double feed = 800.0;       // mm/min
};

// Throws InputError("scene block", 0, "--option", what) for the first option out of range.
void validate_block_options(const BlockOptions& o);

// The whole scene (block.stl as the design, stock box, path, machine).
SceneBundle make_block_scene(const BlockOptions& options, const nlohmann::json& machine);

}  // namespace tf::scenes
