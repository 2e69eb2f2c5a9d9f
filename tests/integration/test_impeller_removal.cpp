// The bundled impeller, planned and posted in process as `tiltfield run` does: the removed volume summed
// over blocks equals the stock before minus after (within 0.5 %), feed blocks that cut are
// engaged and rapids are not. Named *Slow: the sanitizer build skips it (the release run covers it).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "tiltfield/gcode/gcode.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tiltfield/post/post.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/engagement/engagement.hpp"

namespace tf {
namespace {

TEST(ImpellerSlow, RemovedVolumeBalancesAndCuttingBlocksAreEngaged) {
  const std::filesystem::path file = std::filesystem::path(TILTFIELD_BINARY_DIR) / "scenes" / "impeller" / "scene.json";
  ASSERT_TRUE(std::filesystem::exists(file)) << file;
  const Scene scene = load_scene(file);
  const PlanResult planned =
      plan(scene, parse_plan_options(scene.planner_json, file.string(), scene.tool, scene.planner, scene.feed));
  PostJob post;
  post.machine = *scene.machine;
  post.tool = scene.tool;
  post.feed = scene.feed;
  post.part_bounds = scene_bounds(scene);
  const PostOptions po;
  std::ostringstream text;
  write_gcode(text, post_program(planned.path, post, po), post, po);
  const Program program = parse_gcode(text.str(), "impeller.ngc", post.machine);
  VerifyOptions vo;
  vo.engagement = engagement_probe();
  vo.resolution = 0.2;  // coarse for test time; the benchmark runs 0.1 and 0.05
  const VerifyReport r = verify_program(scene, program, scene_forward(scene), vo).report;
  const double gone = r.stock_volume_start_mm3 - r.stock_volume_end_mm3;
  std::cout << "impeller: removed " << r.removed_volume_mm3 << " mm3 over blocks, stock " << gone << " mm3\n";
  ASSERT_GT(gone, 100.0);
  EXPECT_NEAR(r.removed_volume_mm3, gone, 0.005 * gone);
  int cutting = 0, engaged_cutting = 0;
  for (const BlockResult& b : r.per_block) {
    if (b.rapid) {
      EXPECT_FALSE(b.engagement.engaged()) << "block " << b.block;
      continue;
    }
    if (b.engagement.engaged()) {
      EXPECT_GE(b.engagement.entry_deg, 0.0);
      EXPECT_LE(b.engagement.exit_deg, 360.0);
      EXPECT_LE(b.engagement.axial_depth_mm, scene.tool.flute_length + 1e-9);
    }
    // A block that removes a visible amount was engaged at its end (its last stretch cut too).
    if (b.removed_mm3 > 0.05) {
      ++cutting;
      engaged_cutting += b.engagement.engaged();
    }
  }
  std::cout << engaged_cutting << " of " << cutting << " cutting blocks engaged at their end\n";
  EXPECT_GE(engaged_cutting, 0.9 * cutting);
}

}  // namespace
}  // namespace tf
