// Which path rows a verified collision belongs to: the rows whose tool poses, as the post places them,
// are the collision block's end poses.
#include <gtest/gtest.h>

#include <cmath>

#include "tiltfield/core/report.hpp"
#include "tiltfield/replan/replan.hpp"

namespace {

// Two passes 5.71 mm apart with a flat R4 tilted 40 deg sideways toward the second pass: the tool's tip,
// a radius off its contact point, lies nearer to the second pass's points than to its own row's (black-box
// testing: the windows had been planned on the neighbouring pass, the collisions left as they were).
TEST(CollisionRows, AFlatEndsCollisionIsOnItsOwnRowNotTheNeighbouringPass) {
  tf::Tool tool;
  tool.cutter = tf::FlatCutter{4.0};
  tool.flute_length = 16.0;
  tool.length = 60.0;
  tf::ToolPath path;
  tf::OrientedPath oriented;
  const double tilt = 40.0 * M_PI / 180.0;
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 0; i <= 40; ++i) {
      tf::CLPoint c;
      const double x = pass == 0 ? 0.5 * i : 20.0 - 0.5 * i;  // zig-zag
      c.p = {x, 5.71 * pass, 0.0};
      c.n = Eigen::Vector3d::UnitZ();
      path.rows.push_back(c);
      tf::OrientedRow o;
      o.p = c.p;
      o.n = c.n;
      o.axis = {0.0, std::sin(tilt), std::cos(tilt)};
      oriented.rows.push_back(o);
    }
  size_t nearer_elsewhere = 0;
  for (size_t k = 1; k + 1 < path.rows.size(); ++k) {
    tf::Collision c;
    c.component = tf::ToolComponent::Shank;
    c.with = tf::HitWith::Stock;
    const auto pose = [&](size_t i) {
      return tf::ToolPose{tool.tip_at(path.rows[i].p, path.rows[i].n, oriented.rows[i].axis), oriented.rows[i].axis};
    };
    c.start = pose(k);
    c.end = pose(k + 1);
    if (k + 1 == 41) continue;  // the link between the passes is no cutting block
    const tf::RowSpan span = tf::collision_rows(path, oriented, tool, c);
    EXPECT_EQ(span.first, k);
    EXPECT_EQ(span.second, k + 1);
    // The case this is about: the tip nearer to another row's point than to its own.
    double nearest_other = 1e9;
    for (size_t i = 0; i < path.rows.size(); ++i)
      if (i != k) nearest_other = std::min(nearest_other, (path.rows[i].p - c.start.tip).norm());
    if (nearest_other < (path.rows[k].p - c.start.tip).norm() - 0.3) ++nearer_elsewhere;
  }
  EXPECT_GT(nearer_elsewhere, 30u);
  const std::vector<tf::RowSpan> spans = tf::collision_spans(path, oriented, tool, {});
  EXPECT_TRUE(spans.empty());
}

}  // namespace
