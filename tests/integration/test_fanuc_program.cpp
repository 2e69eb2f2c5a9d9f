// A hand-written Fanuc-style program read and simulated: G54 puts the program's zero on the stock's top
// corner, two tools come from the scene's library with G43 H, a G81 / G83 / G82 drilling series and a ball
// slot. The removed volume must match the closed form: holes pi r^2 depth each (the drill is modelled as a
// flat end mill), the slot with the ball's centre on the top face pi R^2 L / 2 + 2/3 pi R^3.
#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>
#include <sstream>

#include "test_support.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace tf {
namespace {

const char* const kScene = R"({
  "comment": "A 60 x 40 x 20 block whose top corner is G54's zero, in machine coordinates.",
  "stock": {"box": {"min": [100, 50, -50], "max": [160, 90, -30]}},
  "tools": [{"number": 1, "type": "flat", "radius": 2.5, "flute_length": 25, "length": 60},
            {"number": 2, "type": "ball", "radius": 4, "flute_length": 20, "length": 75,
             "holder": [{"radius": 15, "length": 30}]}],
  "work_offsets": {"G54": [100, 50, -30]}
})";

const char* const kProgram = R"(%
O2001 (FANUC-STYLE TEST)
N10 G21 G17 G40 G49 G80 G90 G94
N20 G91 G28 Z0.
N30 G90
N40 T1 M06 (5 MM DRILL)
N50 G54 G00 X10. Y10. S2000 M03
N60 G43 H1 Z25. M08
N70 G99 G81 X10. Y10. Z-8. R2. F150.
N80 X20.
N90 X30.
N100 G98 G83 X40. Y10. Z-12. R2. Q3. F120.
N110 X50.
N115 G82 X55. Y18. Z-6. R2. P0.5
N120 G80
N130 G00 Z25. M09
N140 G91 G28 Z0.
N150 T2 M06 (8 MM BALL)
N160 G90 G54 G00 X10. Y28. S6000 M03
N170 G43 H2 Z25. M08
N180 G01 Z-4. F300.
N190 X50. F600.
N200 G00 Z25.
N210 M09 M05
N220 G91 G28 Z0.
N230 G28 X0. Y0.
N240 M30
%
)";

TEST(FanucProgram, RemovedVolumeMatchesTheClosedForm) {
  test::TempDir dir;
  test::write_text(dir / "scene.json", kScene);
  test::write_text(dir / "fanuc.nc", kProgram);
  const Scene scene = load_scene(dir / "scene.json");
  const Program program = read_gcode(dir / "fanuc.nc", MachineSpec{}, gcode_options(scene));
  VerifyOptions opt;
  opt.resolution = 0.1;
  const VerifyResult r = verify_program(scene, program, scene_forward(scene), opt);

  const double pi = std::numbers::pi;
  const double drill = 2.5, ball = 4.0, slot = 40.0;
  const double holes = pi * drill * drill * (3 * 8.0 + 2 * 12.0 + 6.0);
  const double groove = pi * ball * ball * slot / 2.0 + 2.0 / 3.0 * pi * ball * ball * ball;
  const double expected = holes + groove;
  EXPECT_NEAR(r.report.removed_volume_mm3, expected, 0.01 * expected)
      << "measured " << r.report.removed_volume_mm3 << " mm3, closed form " << expected << " mm3";
  std::printf("Fanuc program: removed %.2f mm3, closed form %.2f mm3 (%+.3f %%)\n", r.report.removed_volume_mm3,
              expected, 100.0 * (r.report.removed_volume_mm3 / expected - 1.0));
  EXPECT_TRUE(r.report.collisions.empty()) << r.report.collisions.size() << " collisions, first at line "
                                           << r.report.collisions.front().line;

  // Each tool cut its own feature: the drill the holes, the ball the slot, and the G82 dwell took time.
  int change = 0;  // the line of "T2 M06"
  {
    std::istringstream lines(kProgram);
    int n = 0;
    for (std::string l; std::getline(lines, l);) {
      ++n;
      if (l.find("T2 M06") != std::string::npos) change = n;
    }
  }
  ASSERT_GT(change, 0);
  double drilled = 0.0, slotted = 0.0, dwell = 0.0;
  for (const BlockResult& b : r.report.per_block) {
    EXPECT_EQ(b.tool, b.line < change ? 1 : 2) << "line " << b.line;
    (b.tool == 1 ? drilled : slotted) += b.removed_mm3;
    dwell += b.dwell_minutes;
  }
  EXPECT_NEAR(drilled, holes, 0.01 * holes);
  EXPECT_NEAR(slotted, groove, 0.01 * groove);
  EXPECT_NEAR(dwell, 0.5 / 60.0, 1e-12);
}

}  // namespace
}  // namespace tf
