// tiltfield scene generators: exact point-to-triangle-mesh distance with a bounding-box tree, used to
// keep generated tool paths clear of check solids and to report where the nominal tool axis collides.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf::scenes {

// Closest point on the triangle (a, b, c) to p (the planner's tf::closest_point_on_triangle).
inline Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                 const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return tf::closest_point_on_triangle(p, Triangle{a, b, c});
}

class MeshDistance {
 public:
  // Copies the triangles of `mesh` (any number of shells).
  explicit MeshDistance(const Mesh& mesh);

  // Unsigned distance (mm) from p to the nearest triangle. Where the true distance exceeds `stop_above`
  // the search may end early and return any value > stop_above.
  double distance(const Eigen::Vector3d& p, double stop_above = std::numeric_limits<double>::infinity()) const;

  // The nearest point on the mesh to p.
  Eigen::Vector3d closest_point(const Eigen::Vector3d& p) const;

  size_t triangle_count() const { return tri_.size(); }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children, -1 for a leaf
    int begin = 0, end = 0;     // leaf: range in order_
  };
  struct Tri {
    Eigen::Vector3d a, b, c;
  };
  int build(int begin, int end);
  double nearest(const Eigen::Vector3d& p, double stop_above, Eigen::Vector3d* where) const;

  std::vector<Tri> tri_;
  std::vector<Eigen::Vector3d> centroid_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

// True when the tool body, standing on the cutter location `cl` (mm) along the unit `axis` (tip toward
// spindle), reaches into the obstacles: some sphere that lies inside the body and is centred on the axis
// (every 0.25 mm above the cutter location, up to the top of the holder) comes nearer to the mesh than its
// radius. The end form below the cutter location (the ball) is not tested: generated paths keep it
// clear on their own. A penetration shallower than the sampling's reach may be missed.
bool tool_axis_hits(const Tool& tool, const MeshDistance& obstacles, const Eigen::Vector3d& cl,
                    const Eigen::Vector3d& axis);

}  // namespace tf::scenes
