// tiltfield scene generators: whether a tool body standing on a cutter location reaches into obstacles,
// by exact point-to-mesh distances (core's TriangleBvh), to report where a generated path's nominal axis
// collides.
#pragma once
#include <Eigen/Core>

#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf::scenes {

// True when the tool body, standing on the cutter location `cl` (mm) along the unit `axis` (tip toward
// spindle), reaches into the obstacles: some sphere that lies inside the body and is centred on the axis
// (every 0.25 mm above the cutter location, up to the top of the holder) comes nearer to the mesh than its
// radius. The end form below the cutter location (the ball) is not tested: generated paths keep it
// clear on their own. A penetration shallower than the sampling's reach may be missed.
bool tool_axis_hits(const Tool& tool, const TriangleBvh& obstacles, const Eigen::Vector3d& cl,
                    const Eigen::Vector3d& axis);

}  // namespace tf::scenes
