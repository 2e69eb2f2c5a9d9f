// Clearance of the tool body (a stack of capsules) to the stock solid and to the fixture and check
// surfaces, for the post's approach, retract and link moves.
#include "transit_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tf::post_detail {

namespace {

constexpr double kTransitInf = std::numeric_limits<double>::infinity();

}  // namespace

std::vector<BodyCapsule> body_capsules(const Tool& tool) {
  std::vector<BodyCapsule> caps;
  caps.push_back({tool.cl_height(), tool.flute_length, tool.radius()});
  caps.push_back({tool.flute_length, tool.length, tool.shank_radius});
  double h = tool.length;
  for (const HolderSegment& s : tool.holder) {
    caps.push_back({h, h + s.length, s.radius});
    h += s.length;
  }
  for (size_t i = 1; i < caps.size(); ++i) caps[i].radius = std::max(caps[i].radius, caps[i - 1].radius);
  return caps;
}

TransitChecker::TransitChecker(const PostJob& job) : capsules_(body_capsules(job.tool)) {
  if (job.stock.n_faces() > 0) {
    stock_ = TriangleBvh(std::vector<const Mesh*>{&job.stock});
  }
  std::vector<const Mesh*> surfaces = job.fixtures;
  surfaces.insert(surfaces.end(), job.check_surfaces.begin(), job.check_surfaces.end());
  std::erase(surfaces, nullptr);
  if (!surfaces.empty()) surfaces_ = TriangleBvh(surfaces);
}

double TransitChecker::segment_distance(const TriangleBvh& bvh, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                        double start) const {
  const Eigen::Vector3d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  // The distance between the segment's box and a node's box bounds the segment's distance from below.
  return bvh.minimum(
      [&](const Eigen::Vector3d& nlo, const Eigen::Vector3d& nhi) {
        return (nlo - hi).cwiseMax(lo - nhi).cwiseMax(0.0).norm();
      },
      [&](int i, double) { return segment_triangle_distance(a, b, bvh.triangle(i)); }, start);
}

bool TransitChecker::inside_stock(const Eigen::Vector3d& p) const { return inside_solid(stock_, p); }

double TransitChecker::capsule_clearance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
                                         double enough) const {
  // Each search stops at enough + radius. Beyond it a segment is well clear of a surface; from the stock
  // it is either well clear or deep inside, which the parity test tells (the capped depth then still
  // bounds the way out from below, and the returned value from above).
  double c = enough;
  if (!surfaces_.empty()) c = std::min(c, segment_distance(surfaces_, a, b, enough + radius) - radius);
  if (!stock_.empty()) {
    const double d = segment_distance(stock_, a, b, enough + radius);
    if (d < 1e-12)
      c = std::min(c, -radius);
    else if (inside_stock(a))
      c = std::min(c, -(d + radius));
    else
      c = std::min(c, d - radius);
  }
  return c;
}

double TransitChecker::clearance(const ToolPose& pose, double enough) const {
  double c = enough;
  for (const BodyCapsule& k : capsules_)
    c = std::min(c, capsule_clearance(pose.tip + k.h0 * pose.axis, pose.tip + k.h1 * pose.axis, k.radius, enough));
  return c;
}

std::optional<double> TransitChecker::lowest_lift(const ToolPose& pose, double min_lift, double max_lift,
                                                  double margin) const {
  const double enough = margin + 50.0;  // larger steps are not needed; a cap keeps the searches short
  double lift = min_lift;
  for (int k = 0; k < 4096 && lift <= max_lift; ++k) {
    const double c = clearance(ToolPose{pose.tip + lift * pose.axis, pose.axis}, enough);
    if (c >= margin) {
      // The motion out of the cut: the top capsule lengthened by the lift must touch nothing.
      const BodyCapsule& top = capsules_.back();
      const double swept = capsule_clearance(pose.tip + top.h0 * pose.axis, pose.tip + (top.h1 + lift) * pose.axis,
                                             top.radius, enough);
      if (swept < kMinStepMm) return std::nullopt;  // lifting further only lengthens it
      return lift;
    }
    lift += std::max(margin - c, kMinStepMm);
  }
  return std::nullopt;
}

bool TransitChecker::translation_clear(const ToolPose& pose, const Eigen::Vector3d& move, double margin) const {
  const double length = move.norm(), enough = margin + 50.0;
  double s = 0.0;
  for (int k = 0; k < 100000; ++k) {
    const double c = clearance(ToolPose{pose.tip + s * move, pose.axis}, enough);
    if (c < margin + kMinStepMm) return false;
    if (s >= 1.0 || length < 1e-12) return true;
    s = std::min(1.0, s + (c - margin) / length);
  }
  return false;
}

bool TransitChecker::turn_clear(const std::function<ToolPose(double)>& pose_at, double turn_rad, double margin) const {
  const double top = capsules_.back().h1, widest = capsules_.back().radius;
  // Over the whole turn no point of the body moves farther than the chords of the axis segment's ends
  // plus the angle times the widest radius; steps of a tenth of the margin of that keep D small beside it.
  const ToolPose first = pose_at(0.0), last = pose_at(1.0);
  const double span = (first.tip - last.tip).norm() + (first.tip + top * first.axis - last.tip - top * last.axis).norm() +
                      turn_rad * (top + widest);
  const int steps = static_cast<int>(std::clamp(std::ceil(span / std::max(0.1 * margin, kMinStepMm)), 1.0, 4096.0));
  ToolPose prev = first;
  for (int k = 1; k <= steps; ++k) {
    const ToolPose pose = pose_at(double(k) / steps);
    const double d = std::max((pose.tip - prev.tip).norm(), (pose.tip + top * pose.axis - prev.tip - top * prev.axis).norm()) +
                     turn_rad / steps * widest;
    if (clearance(prev, margin + d + 1.0) < margin + d || clearance(pose, margin + d + 1.0) < margin + d) return false;
    prev = pose;
  }
  return true;
}

}  // namespace tf::post_detail
