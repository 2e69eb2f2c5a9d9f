#include <gtest/gtest.h>

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
