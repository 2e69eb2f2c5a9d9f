// Test helpers for the post's links: a stock with a raised boss, two passes on either side of it whose
// direct move would cross it, and an independent clearance check of the tool body against boxes (closed
// form: body surface points against axis-aligned boxes, no capsules, no hierarchy).
#pragma once
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/tool.hpp"

namespace links_test {

struct Box {
  Eigen::Vector3d lo, hi;
};

// The stock: a base plate [-40, 40] x [-20, 20] x [0, 20] with a boss [-10, 10] x [-20, 20] x [20, 40].
inline std::vector<Box> boss_stock_boxes() {
  return {{{-40, -20, 0}, {40, 20, 20}}, {{-10, -20, 20}, {10, 20, 40}}};
}

// The same stock as one closed mesh with outward faces: the T-shaped profile in x-z extruded along y.
inline tf::Mesh boss_stock_mesh() {
  const std::array<Eigen::Vector2d, 8> profile = {{{-40, 0}, {40, 0}, {40, 20}, {10, 20}, {10, 40}, {-10, 40}, {-10, 20}, {-40, 20}}};
  Eigen::MatrixX3d V(16, 3);
  for (int k = 0; k < 8; ++k) {
    V.row(k) << profile[k].x(), -20.0, profile[k].y();
    V.row(k + 8) << profile[k].x(), 20.0, profile[k].y();
  }
  std::vector<Eigen::Vector3i> F;
  // The profile runs counter-clockwise seen from -y: the y = -20 cap keeps its order, y = +20 reverses it.
  const int cap[6][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 6}, {0, 6, 7}, {3, 4, 5}, {3, 5, 6}};
  for (const auto& t : cap) {
    F.push_back({t[0], t[1], t[2]});
    F.push_back({t[0] + 8, t[2] + 8, t[1] + 8});
  }
  for (int k = 0; k < 8; ++k) {
    const int n = (k + 1) % 8;
    F.push_back({k, k + 8, n + 8});
    F.push_back({k, n + 8, n});
  }
  Eigen::MatrixX3i Fm(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t i = 0; i < F.size(); ++i) Fm.row(static_cast<Eigen::Index>(i)) = F[i].transpose();
  return tf::mesh_from_arrays(V, Fm);
}

// Ball radius 3, flutes 12, shank radius 3, gauge length 60, holder 12 x 40 (the bundled scenes' tool).
inline tf::Tool links_tool() {
  tf::Tool t;
  t.cutter = tf::BallCutter{3.0};
  t.flute_length = 12.0;
  t.shank_radius = 3.0;
  t.length = 60.0;
  t.holder = {{12.0, 40.0}};
  return t;
}

// Two passes along y, 1 mm deep into the plate (ball centre z 22), at x = -25 (y -15 -> 15) and x = +25
// (y 15 -> -15), rows 0.5 mm apart, axis +Z: the move from the first pass's end to the second's start
// crosses the boss.
inline tf::OrientedPath two_passes() {
  tf::OrientedPath path;
  for (double x : {-25.0, 25.0})
    for (int i = 0; i <= 60; ++i) {
      tf::OrientedRow r;
      const double y = -15.0 + 0.5 * i;
      r.p = {x, x < 0 ? y : -y, 22.0};
      r.axis = Eigen::Vector3d::UnitZ();
      path.rows.push_back(r);
    }
  return path;
}

// Signed distance from p to a box: negative inside (minus the depth).
inline double box_signed_distance(const Eigen::Vector3d& p, const Box& b) {
  const Eigen::Vector3d out = (b.lo - p).cwiseMax(p - b.hi);
  if (out.maxCoeff() <= 0.0) return out.maxCoeff();
  return out.cwiseMax(0.0).norm();
}

// The least signed distance of the tool body's surface points (about `spacing` apart) at `pose` to the
// boxes. With spacing s, a box edge can come at most about s/2 closer between the points.
inline double body_clearance(const std::vector<tf::ToolSample>& samples, const tf::ToolPose& pose,
                             const std::vector<Box>& boxes) {
  const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), pose.axis).toRotationMatrix();
  double c = std::numeric_limits<double>::infinity();
  for (const tf::ToolSample& s : samples)
    for (const Box& b : boxes) c = std::min(c, box_signed_distance(pose.tip + R * s.p, b));
  return c;
}

// The rapid blocks of a joint program against the boxes. A rapid that follows a feed block backs out of
// the cut, where the body touches the stock by design: it must run along the tool axis (so it sweeps only
// the body where it already is, plus above it), and only its end pose is checked. Every other rapid is
// sampled every `step` mm of its largest joint motion.
struct RapidCheck {
  double min_clearance = std::numeric_limits<double>::infinity();        // over the sampled rapids
  double min_retract_end = std::numeric_limits<double>::infinity();      // over the ends of retracts
  double max_retract_end = -std::numeric_limits<double>::infinity();
  double max_retract_off_axis_deg = 0.0;
  int rapids = 0;
};
inline tf::Joints lerp_joints(const tf::Joints& a, const tf::Joints& b, double s) {
  return {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z),
          a.a + s * (b.a - a.a), a.b + s * (b.b - a.b), a.c + s * (b.c - a.c)};
}
inline RapidCheck check_rapids(const tf::Program& prog, const tf::Kinematics& kin, const tf::Tool& tool,
                               const std::vector<Box>& boxes, double step = 0.5) {
  const std::vector<tf::ToolSample> samples = tool.sample_surface(0.5);
  RapidCheck rc;
  tf::Joints prev = prog.start;
  bool after_feed = false;
  for (const tf::Block& b : prog.blocks) {
    const tf::Joints& j = b.target;
    if (b.motion == tf::Motion::Rapid && after_feed) {
      ++rc.rapids;
      const tf::ToolPose p0 = kin.forward(prev), p1 = kin.forward(j);
      const Eigen::Vector3d d = (p1.tip - p0.tip).normalized();
      rc.max_retract_off_axis_deg =
          std::max(rc.max_retract_off_axis_deg, std::acos(std::clamp(d.dot(p0.axis), -1.0, 1.0)) * 180.0 / M_PI);
      const double c = body_clearance(samples, p1, boxes);
      rc.min_retract_end = std::min(rc.min_retract_end, c);
      rc.max_retract_end = std::max(rc.max_retract_end, c);
    } else if (b.motion == tf::Motion::Rapid) {
      ++rc.rapids;
      const double span = std::max({std::abs(j.x - prev.x), std::abs(j.y - prev.y), std::abs(j.z - prev.z),
                                    std::abs(j.a - prev.a), std::abs(j.b - prev.b), std::abs(j.c - prev.c)});
      const int n = std::max(1, static_cast<int>(std::ceil(span / step)));
      for (int k = 0; k <= n; ++k)
        rc.min_clearance =
            std::min(rc.min_clearance, body_clearance(samples, kin.forward(lerp_joints(prev, j, double(k) / n)), boxes));
    }
    after_feed = b.motion != tf::Motion::Rapid;
    prev = j;
  }
  return rc;
}

// A closed box mesh [lo, hi] (12 triangles, outward faces).
inline tf::Mesh box_mesh(const Box& b) {
  Eigen::MatrixX3d V(8, 3);
  for (int k = 0; k < 8; ++k)
    V.row(k) << ((k & 1) ? b.hi.x() : b.lo.x()), ((k & 2) ? b.hi.y() : b.lo.y()), ((k & 4) ? b.hi.z() : b.lo.z());
  Eigen::MatrixX3i F(12, 3);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int q = 0; q < 6; ++q) {
    F.row(2 * q) << quads[q][0], quads[q][1], quads[q][2];
    F.row(2 * q + 1) << quads[q][0], quads[q][2], quads[q][3];
  }
  return tf::mesh_from_arrays(V, F);
}

// Whether some feed block moves the ball centre (3 mm above the tip) through the box (sampled every 0.5 mm).
inline bool feed_crosses(const tf::Program& prog, const tf::Kinematics& kin, const Box& box) {
  tf::Joints prev = prog.start;
  for (const tf::Block& b : prog.blocks) {
    if (b.motion == tf::Motion::Linear) {
      const tf::ToolPose p0 = kin.forward(prev), p1 = kin.forward(b.target);
      const Eigen::Vector3d t0 = p0.tip + 3.0 * p0.axis, t1 = p1.tip + 3.0 * p1.axis;
      const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0).norm() / 0.5)));
      for (int k = 0; k <= n; ++k)
        if (box_signed_distance(t0 + (t1 - t0) * (double(k) / n), box) < 0.0) return true;
    }
    prev = b.target;
  }
  return false;
}

}  // namespace links_test
