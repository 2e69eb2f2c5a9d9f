// LinuxCNC's own simultaneous 5-axis demo (impeller-7bl-xyzac.ngc: 4492 blocks in TCP mode with G93,
// written for a Hermle by a CAM system), read and simulated on the scene made for it. Release only
// (*Slow): a numerical check the sanitizer run does not need.
#include <gtest/gtest.h>

#include <filesystem>

#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace {

const char* const kDemo =
    "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/vismach/5axis/table-rotary-tilting/demos/"
    "impeller-7bl-xyzac.ngc";

TEST(LinuxcncDemoSlow, ImpellerEveryBlockSimulatedWithinTheStatedBound) {
  if (!std::filesystem::exists(kDemo)) GTEST_SKIP() << "linuxcnc-uspace is not installed";
  const tf::Scene scene =
      tf::load_scene(std::filesystem::path(TILTFIELD_SOURCE_DIR) / "tests" / "data" / "linuxcnc" / "impeller-7bl.json");
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

}  // namespace
