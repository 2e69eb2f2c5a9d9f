// LinuxCNC's own simultaneous 5-axis demos, read and simulated on the scenes made for them, every motion
// block: impeller-7bl-xyzac.ngc (4492 blocks in TCP mode with G93), boat-xyzac.ngc and boat-xyzbc.ngc
// (1832 and 1821 blocks: G54, T1 M6, Z-level roughing with arcs and 5-axis flowline finishing under TCP,
// boat-xyzbc with G43 H1 and G53 G49 at the end), all written for a Hermle by a CAM system. Release only
// (*Slow): numerical checks the sanitizer run does not need.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace {

const std::string kDemos =
    "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/vismach/5axis/table-rotary-tilting/demos/";
const std::string kDemo = kDemos + "impeller-7bl-xyzac.ngc";

std::filesystem::path demo_scene(const std::string& name) {
  return std::filesystem::path(TILTFIELD_SOURCE_DIR) / "tests" / "data" / "linuxcnc" / name;
}

// Reads a boat demo with its scene's tool and work offsets and simulates every block at 0.25 mm.
tf::VerifyResult simulate_boat(const std::string& name, size_t blocks, tf::Program& program) {
  const tf::Scene scene = tf::load_scene(demo_scene(name + ".json"));
  program = tf::read_gcode(kDemos + name + ".ngc", *scene.machine, tf::gcode_options(scene));
  EXPECT_EQ(program.blocks.size(), blocks);
  for (const std::string& w : program.warnings) EXPECT_EQ(w.find("work_offsets"), std::string::npos) << w;
  for (const tf::Block& b : program.blocks) EXPECT_EQ(b.tool, 1) << "line " << b.line;
  tf::VerifyOptions opt;
  opt.resolution = 0.25;
  tf::VerifyResult r = tf::verify_program(scene, program, tf::scene_forward(scene), opt);
  EXPECT_EQ(r.report.blocks, static_cast<int>(blocks));
  EXPECT_LE(r.report.sweep_error_mm, opt.sweep.tolerance);
  EXPECT_LE(r.report.holder_sweep_error_mm, opt.sweep.holder_tolerance);
  EXPECT_GT(r.report.sweep_error_mm, 0.0);  // 5-axis blocks
  const double gone = r.report.stock_volume_start_mm3 - r.report.stock_volume_end_mm3;
  EXPECT_NEAR(r.report.removed_volume_mm3, gone, 1e-6 * gone);
  EXPECT_GT(gone, 0.5 * r.report.stock_volume_start_mm3);  // roughed out around the hull
  return r;
}

TEST(LinuxcncDemoSlow, ImpellerEveryBlockSimulatedWithinTheStatedBound) {
  if (!std::filesystem::exists(kDemo)) GTEST_SKIP() << "linuxcnc-uspace is not installed";
  const tf::Scene scene = tf::load_scene(demo_scene("impeller-7bl.json"));
  const tf::Program program = tf::read_gcode(kDemo, *scene.machine);
  ASSERT_EQ(program.blocks.size(), 4492u);
  tf::VerifyOptions opt;
  opt.resolution = 0.2;
  const tf::VerifyResult r = tf::verify_program(scene, program, tf::scene_forward(scene), opt);
  EXPECT_EQ(r.report.blocks, 4492);
  EXPECT_LE(r.report.sweep_error_mm, opt.sweep.tolerance);
  EXPECT_LE(r.report.holder_sweep_error_mm, opt.sweep.holder_tolerance);
  EXPECT_GT(r.report.sweep_error_mm, 0.0);  // it is a 5-axis program
  // The removed volume balances the stock before and after, and agrees with a five times finer sweep.
  const double gone = r.report.stock_volume_start_mm3 - r.report.stock_volume_end_mm3;
  EXPECT_NEAR(r.report.removed_volume_mm3, gone, 1e-6 * gone);
  opt.sweep.tolerance = 0.002;
  const tf::VerifyResult fine = tf::verify_program(scene, program, tf::scene_forward(scene), opt);
  EXPECT_LE(fine.report.sweep_error_mm, 0.002);
  EXPECT_NEAR(r.report.removed_volume_mm3, fine.report.removed_volume_mm3, 1e-3 * fine.report.removed_volume_mm3);
}

TEST(LinuxcncDemoSlow, BoatXyzacEveryBlockWithG54AndT1) {
  if (!std::filesystem::exists(kDemos + "boat-xyzac.ngc")) GTEST_SKIP() << "linuxcnc-uspace is not installed";
  tf::Program program;
  simulate_boat("boat-xyzac", 1832, program);
  // No tool length offset: under TCP X Y Z are the tip, e.g. the Z-level pass at line 16.
  const auto it = std::find_if(program.blocks.begin(), program.blocks.end(), [](const tf::Block& b) { return b.line == 16; });
  ASSERT_NE(it, program.blocks.end());
  EXPECT_TRUE(it->tcp);
  EXPECT_NEAR(it->target.z, -6.625, 1e-9);
}

TEST(LinuxcncDemoSlow, BoatXyzbcEveryBlockWithG43AndG53) {
  if (!std::filesystem::exists(kDemos + "boat-xyzbc.ngc")) GTEST_SKIP() << "linuxcnc-uspace is not installed";
  tf::Program program;
  const tf::VerifyResult r = simulate_boat("boat-xyzbc", 1821, program);
  // With G43 H1 (T1's own length) the tip is the programmed point (line 12: G43 H1 Z5.0 at Y-2.436).
  EXPECT_NEAR(program.blocks[1].target.x, -34.78, 1e-9);
  EXPECT_NEAR(program.blocks[1].target.z, 5.0, 1e-9);
  // The last two blocks cancel it (G49) and move the spindle nose to machine Z30 (G53): the 50 mm tool's tip
  // goes to Z-20 (B at 0), into the stock, and the simulation reports that rapid.
  const tf::Block& last = program.blocks.back();
  EXPECT_NEAR(last.target.z, 30.0 - 50.0, 1e-9);
  bool end_crash = false;
  for (const tf::Collision& c : r.report.collisions) end_crash |= c.line >= 1863 && c.rapid;
  EXPECT_TRUE(end_crash);
}

}  // namespace
