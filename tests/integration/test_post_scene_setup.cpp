// The post takes the scene's set-up as the G-code reader does: the G54 work offset it runs in and the
// library's tool of the program's T (found in review: the offset was ignored, so the verification of
// a posted program saw hundreds of collisions; T2 was posted with the gauge length of `tool`).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "post/post_fixture.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace {

using namespace post_test;

// The scene of the post's tests with `extra` merged into its JSON.
tf::Scene scene_with(const TempDir& dir, const nlohmann::json& extra) {
  const fs::path file = write_scene(dir.path, machine_file("table-table-ac"), impeller_like_path(30));
  nlohmann::json j = nlohmann::json::parse(std::ifstream(file));
  j.merge_patch(extra);
  std::ofstream(file) << j.dump(2);
  return tf::load_scene(file);
}

std::vector<tf::Block> posted_and_read_back(const tf::Scene& scene, int tool_number) {
  tf::PostJob job;
  tf::set_post_job(job, scene, tool_number);
  tf::PostOptions options;
  options.tool_number = tool_number;
  std::ostringstream text;
  tf::write_gcode(text, tf::post_program(impeller_like_path(30), job, options), job, options);
  return tf::parse_gcode(text.str(), "p.ngc", *scene.machine, tf::gcode_options(scene)).blocks;
}

TEST(PostSceneSetup, WorkOffsetIsSubtractedSoTheControllerAddsItBack) {
  TempDir dir("post-g54");
  const std::vector<tf::Block> plain = posted_and_read_back(scene_with(dir, nlohmann::json::object()), 1);
  const tf::Scene offset = scene_with(dir, {{"work_offsets", {{"G54", {10.0, -5.0, 2.5, 0.0, 0.0, 30.0}}}}});
  const std::vector<tf::Block> moved = posted_and_read_back(offset, 1);
  ASSERT_EQ(moved.size(), plain.size());
  ASSERT_GT(plain.size(), 30u);
  for (size_t i = 0; i < plain.size(); ++i) {
    const tf::Joints &a = plain[i].target, &b = moved[i].target;
    EXPECT_NEAR(a.x, b.x, 2e-4) << i;
    EXPECT_NEAR(a.y, b.y, 2e-4) << i;
    EXPECT_NEAR(a.z, b.z, 2e-4) << i;
    EXPECT_NEAR(a.a, b.a, 2e-4) << i;
    EXPECT_NEAR(a.c, b.c, 2e-4) << i;
  }
}

TEST(PostSceneSetup, ToolNumberTakesTheLibrarysTool) {
  TempDir dir("post-tools");
  const nlohmann::json ball = {{"type", "ball"}, {"radius", 3.0}, {"flute_length", 12.0}, {"shank_radius", 3.0}};
  nlohmann::json t1 = ball, t2 = ball;
  t1["number"] = 1, t1["length"] = 60.0;
  t2["number"] = 2, t2["length"] = 80.0;
  const tf::Scene scene = scene_with(dir, {{"tools", {t1, t2}}});
  tf::PostJob job;
  tf::set_post_job(job, scene, 2);
  EXPECT_DOUBLE_EQ(job.tool.length, 80.0);
  // Joint output: Z is the spindle nose, a gauge length above the tip; T2's program sits 20 mm higher
  // wherever the axis is vertical (the first cutting block of this path is).
  const std::vector<tf::Block> one = posted_and_read_back(scene, 1), two = posted_and_read_back(scene, 2);
  ASSERT_EQ(one.size(), two.size());
  double most = 0.0;
  for (size_t i = 0; i < one.size(); ++i) most = std::max(most, two[i].target.z - one[i].target.z);
  EXPECT_NEAR(most, 20.0, 1e-3);
  EXPECT_THROW(tf::set_post_job(job, scene, 7), tf::InputError);
}

}  // namespace
