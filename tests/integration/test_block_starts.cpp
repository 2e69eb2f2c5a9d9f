// Where a block starts when the program did not move the tool there itself: after a tool change in a
// program with tool length offsets (the spindle nose stays, the new tool's tip is elsewhere) and after a
// reference return (the reference is not in the scene; the tool comes from where the program next puts
// the axes). Both found by black-box testing: the old tool's tip and the G28 intermediate point had been
// taken as the start, which cut material no tool reached and reported rapid collisions.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_support.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/verify.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace tf {
namespace {

constexpr double kPi = std::numbers::pi;

// A 100 x 60 x 30 block; tool 2 a ball of gauge length 80, tool 3 a flat end 10 mm shorter.
const char* const kStartsScene = R"({
  "stock": {"box": {"min": [0, 0, 0], "max": [100, 60, 30]}},
  "tools": [{"number": 1, "type": "flat", "radius": 5, "flute_length": 20, "length": 60},
            {"number": 2, "type": "ball", "radius": 3, "flute_length": 15, "length": 80},
            {"number": 3, "type": "flat", "radius": 4, "flute_length": 15, "length": 70}]
})";

VerifyReport verify_text(const std::string& program) {
  test::TempDir dir;
  test::write_text(dir / "scene.json", kStartsScene);
  test::write_text(dir / "p.ngc", program);
  const Scene scene = load_scene(dir / "scene.json");
  VerifyOptions opt;
  opt.resolution = 0.1;
  return verify_program(scene, read_gcode(dir / "p.ngc", MachineSpec{}, gcode_options(scene)), scene_forward(scene), opt)
      .report;
}

// Tool 2's tip at Z 29, 1 mm into the stock, slots 20 mm; then T3 M6 and a move up. The nose stays at
// 29 + 80, so tool 3's tip starts at 39, above the stock: the move up cuts nothing and meets nothing
// (from tool 2's tip, 10 mm lower, it had swept 29.5 mm3 and reported a rapid collision).
TEST(BlockStarts, AToolChangeKeepsTheSpindleNose) {
  // The ball 1 mm deep: a plunge's spherical cap, then the slot's circular segment of width 2 sqrt(5).
  const double h = 1.0, r = 3.0;
  const double cap = kPi * h * h * (3.0 * r - h) / 3.0;
  const double half_chord = std::sqrt(r * r - (r - h) * (r - h));
  const double segment = r * r * std::acos((r - h) / r) - (r - h) * half_chord;
  const double expected = cap + 20.0 * segment;
  for (const char* change : {"T3 M6\nG0 Z60\n", "T3 M6\nG43 H3\nG1 Z60 F300\n", "M61 Q3\nG0 Z60\n"}) {
    const VerifyReport rep =
        verify_text(std::string("G21 G90 G17\nT2 M6\nG43 H2\nG0 X50 Y20 Z40\nG1 Z29 F300\nG1 X70\n") + change + "M2\n");
    EXPECT_TRUE(rep.collisions.empty()) << change << rep.collisions.front().line;
    EXPECT_NEAR(rep.removed_volume_mm3, expected, 0.01 * expected) << change;
    EXPECT_NEAR(rep.per_block.back().removed_mm3, 0.0, 1e-9) << change;
  }
}

// G28 X80 Y50 sends X and Y to the reference after the intermediate point; the next block comes from
// the reference, taken where the program then puts them: a straight plunge at X20 Y20 from Z35 to Z27,
// pi 5^2 3 mm3, not a ramp from the intermediate point through the stock (613 mm3).
TEST(BlockStarts, AfterAReferenceReturnTheToolComesFromWhereTheProgramPutsIt) {
  const VerifyReport rep = verify_text("G21 G90 G17\nT1 M6\nG0 X10 Y10 Z35\nG28 X80 Y50\nG1 X20 Y20 Z27 F300\nG0 Z40\nM2\n");
  ASSERT_EQ(rep.per_block.size(), 4u);
  const double plunge = kPi * 25.0 * 3.0;
  EXPECT_NEAR(rep.per_block[2].removed_mm3, plunge, 0.005 * plunge);
  EXPECT_NEAR(rep.removed_volume_mm3, plunge, 0.005 * plunge);
  // Sent home with no axis word: Z rises straight up (a block of its own), X and Y come from the
  // reference, so the rapid down at X20 Y20 starts above it.
  const VerifyReport all = verify_text("G21 G90 G17\nT1 M6\nG0 X10 Y10 Z35\nG28\nG0 X20 Y20\nG1 Z27 F300\nM2\n");
  EXPECT_NEAR(all.removed_volume_mm3, plunge, 0.005 * plunge);
  EXPECT_TRUE(all.collisions.empty());
}

}  // namespace
}  // namespace tf
