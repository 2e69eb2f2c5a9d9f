#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/tool.hpp"

namespace {

tf::Tool ball_tool() {
  tf::Tool t;
  t.cutter = tf::BallCutter{3.0};
  t.flute_length = 12;
  t.shank_radius = 2.5;
  t.length = 60;
  t.holder = {{12, 40}, {20, 10}};
  return t;
}

TEST(Tool, RadiusAndComponentsAlongTheBody) {
  const tf::Tool t = ball_tool();
  EXPECT_DOUBLE_EQ(t.cl_height(), 3.0);
  EXPECT_DOUBLE_EQ(t.total_length(), 110.0);
  EXPECT_NEAR(t.radius_at(0.0), 0.0, 1e-12);
  EXPECT_NEAR(t.radius_at(1.0), std::sqrt(9.0 - 4.0), 1e-12);
  EXPECT_NEAR(t.radius_at(5.0), 3.0, 1e-12);
  EXPECT_NEAR(t.radius_at(30.0), 2.5, 1e-12);
  EXPECT_NEAR(t.radius_at(70.0), 12.0, 1e-12);
  EXPECT_NEAR(t.radius_at(105.0), 20.0, 1e-12);
  EXPECT_EQ(t.radius_at(111.0), 0.0);
  EXPECT_EQ(t.component_at(1.0), tf::ToolComponent::Ball);
  EXPECT_EQ(t.component_at(5.0), tf::ToolComponent::Flute);
  EXPECT_EQ(t.component_at(30.0), tf::ToolComponent::Shank);
  EXPECT_EQ(t.component_at(61.0), tf::ToolComponent::Holder);
  EXPECT_NEAR(t.max_radius_between(10, 65), 12.0, 1e-12);
  EXPECT_NEAR(t.max_radius_between(20, 50), 2.5, 1e-12);
}

TEST(Tool, BullAndFlatEndForms) {
  tf::Tool bull;
  bull.cutter = tf::BullCutter{5.0, 1.0};
  EXPECT_DOUBLE_EQ(bull.cl_height(), 1.0);
  EXPECT_NEAR(bull.radius_at(0.0), 4.0, 1e-12);
  EXPECT_NEAR(bull.radius_at(1.0), 5.0, 1e-12);
  tf::Tool flat;
  flat.cutter = tf::FlatCutter{4.0};
  EXPECT_DOUBLE_EQ(flat.cl_height(), 0.0);
  EXPECT_NEAR(flat.radius_at(0.0), 4.0, 1e-12);
}

// Every sample lies on the body's surface: its distance from the axis is the body radius at its
// height (or inside that radius on the horizontal faces), and normals are unit.
TEST(Tool, SamplesCoverEveryComponentOnTheSurface) {
  for (const tf::Cutter& c : {tf::Cutter{tf::BallCutter{3}}, tf::Cutter{tf::FlatCutter{3}}, tf::Cutter{tf::BullCutter{3, 1}}}) {
    tf::Tool t = ball_tool();
    t.cutter = c;
    const auto samples = t.sample_surface(0.5);
    int count[4] = {0, 0, 0, 0};
    int holder_seg[2] = {0, 0};
    for (const auto& s : samples) {
      ++count[static_cast<int>(s.component)];
      if (s.holder_segment >= 0) ++holder_seg[s.holder_segment];
      EXPECT_NEAR(s.normal.norm(), 1.0, 1e-9);
      const double r = std::hypot(s.p.x(), s.p.y());
      const double h = s.p.z();
      const bool horizontal_face = std::abs(s.normal.z()) > 1 - 1e-9;
      if (!horizontal_face) {
        const double expect = t.radius_at(std::clamp(h, 1e-9, t.total_length() - 1e-9));
        // On a step between two radii the sample sits at the step's height: accept either side.
        const double below = t.radius_at(std::max(0.0, h - 1e-9)), above = t.radius_at(h + 1e-9);
        EXPECT_TRUE(std::abs(r - expect) < 1e-6 || std::abs(r - below) < 1e-6 || std::abs(r - above) < 1e-6)
            << "r=" << r << " h=" << h;
      } else {
        EXPECT_LE(r, t.max_radius_between(h - 1e-6, h + 1e-6) + 1e-9);
      }
    }
    for (int i = 0; i < 4; ++i) EXPECT_GT(count[i], 0) << "component " << i;
    EXPECT_GT(holder_seg[0], 0);
    EXPECT_GT(holder_seg[1], 0);
  }
}

// A flat or bull end's cutter location moves with the axis so that the end touches the plane through the
// contact point (the row point less the corner radius times n) and goes no deeper, whatever the tilt; a
// ball's does not move. Turned about the row point, a flat R3 tilted 20 deg dug 1.03 mm in (black-box
// testing). Checked on the end form's surface samples, 0.02 mm apart.
TEST(Tool, FlatAndBullEndsKeepTheirContactWhenTilted) {
  tf::Tool ball;  // short bodies: only the end form matters here
  ball.cutter = tf::BallCutter{3.0};
  ball.flute_length = 3.5, ball.length = 4, ball.holder.clear();
  tf::Tool flat = ball, bull = ball;
  flat.cutter = tf::FlatCutter{3.0};
  bull.cutter = tf::BullCutter{3.0, 1.0};
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const Eigen::Vector3d side = n.unitOrthogonal(), side2 = n.cross(side);
  const Eigen::Vector3d row(10, -4, 7);
  for (const tf::Tool& tool : {ball, flat, bull}) {
    const double r = tool.cl_height();  // the corner radius; the ball's radius
    const Eigen::Vector3d contact = row - r * n;
    const std::vector<tf::ToolSample> end = tool.sample_surface(0.02);
    for (double tilt_deg : {0.0, 0.5, 5.0, 20.0, 45.0})
      for (double azimuth_deg : {0.0, 100.0, 230.0}) {
        const double t = tilt_deg * M_PI / 180, z = azimuth_deg * M_PI / 180;
        const Eigen::Vector3d a = std::cos(t) * n + std::sin(t) * (std::cos(z) * side + std::sin(z) * side2);
        const Eigen::Vector3d tip = row + tool.contact_offset(n, a) - tool.cl_height() * a;
        const Eigen::Matrix3d frame = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), a).toRotationMatrix();
        double lowest = 1e9;
        for (const tf::ToolSample& sample : end)
          if (sample.component == tf::ToolComponent::Ball || sample.p.z() < 1e-9)
            lowest = std::min(lowest, n.dot(tip + frame * sample.p - contact));
        SCOPED_TRACE(std::string(tool.type_name()) + " tilt " + std::to_string(tilt_deg));
        EXPECT_GT(lowest, -1e-3 - 1e-9);  // never deeper than the 0.001 mm the move allows
        EXPECT_LT(lowest, 2e-3);   // and touching it (the samples' spacing)
      }
    EXPECT_EQ(tool.contact_offset(Eigen::Vector3d::Zero(), n), Eigen::Vector3d::Zero());  // normal unknown
  }
  EXPECT_EQ(ball_tool().contact_offset(n, side), Eigen::Vector3d::Zero());
  // An axis a hair off n (the default lead and tilt of 0, the planner's numerical noise) does not move the
  // end: the least move that keeps it within 0.001 mm is none (review).
  EXPECT_EQ(flat.contact_offset(n, (n + 1e-5 * side).normalized()), Eigen::Vector3d::Zero());
  EXPECT_EQ(bull.contact_offset(n, (n + 1e-4 * side).normalized()), Eigen::Vector3d::Zero());
}

TEST(Tool, ValidationNamesTheField) {
  tf::Tool t = ball_tool();
  t.length = 5;
  try {
    tf::validate_tool(t, "scene.json", "tool");
    FAIL();
  } catch (const tf::InputError& e) {
    EXPECT_EQ(e.field(), "tool.length");
    EXPECT_EQ(e.file(), "scene.json");
  }
  t = ball_tool();
  t.holder[1].radius = -1;
  EXPECT_THROW(tf::validate_tool(t, "s", "tool"), tf::InputError);
}

}  // namespace
