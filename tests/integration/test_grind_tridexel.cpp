// Cross-check with the tri-dexel verifier: the same grinding program, the wheel given to the verifier as a
// flat "tool" (a cylinder of the wheel's radius and width), removes the same volume as the section
// simulation. Both use a sharp-cornered wheel (edge_radius 0), the one wheel shape both represent exactly:
// the verifier's tools round only the tip end. The program here moves by translations only (three straight
// flutes, a swivelled gash plunge, a notch), which the verifier sweeps exactly and quickly; the bundled
// end mill's helical program is cross-checked the same way in bench_grind (it takes minutes there).
#include <gtest/gtest.h>

#include "grind/grind_test_util.hpp"
#include "tridexel_bridge.hpp"
#include "tiltfield/grind/sections.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::grind {
namespace {

const char* kProgram = R"(
OP fluting flute 1
G0 X1.5 Y60 Z50 A0
G1 Y43.5
G1 Z12
G0 Y150
OP fluting flute 2
G0 A120
G0 Y43.5 Z50
G1 Z12
G0 Y150
OP fluting flute 3
G0 A240
G0 Y43.5 Z50
G1 Z12
G0 Y150
OP gashing gash
G0 X18.955 Y60 Z7.77 A40 W60
G1 Y41.2
G0 Y150
OP notching notch
G0 X0 Y150 Z59.7 A0 W0
G0 Y8
G1 Y-8
G0 Y150
)";

TEST(TriDexelCrossCheck, SameRemovedVolumeWithinOnePercent) {
  const GrindScene g = testing::make_scene(5.0, 20.0, 40.0, 3.0, 0.0, kProgram, Axes{0, 150, 0, 0, 0, 0});

  SectionOptions sopt;
  sopt.spacing = 0.05;
  const double removed_sections = testing::sections_removed(simulate_sections(g, sopt));
  const VerifyReport report = testing::tridexel_report(g, 0.1, 0.01);
  const double rel = std::abs(report.removed_volume_mm3 - removed_sections) / removed_sections;
  std::printf("tri-dexel cross-check: removed %.3f mm3 (tri-dexel, %.2f mm rays, sweep error %.4f mm) vs %.3f mm3 "
              "(sections, 0.05 mm), rel. diff %.4f\n",
              report.removed_volume_mm3, 0.1, report.sweep_error_mm, removed_sections, rel);
  EXPECT_LT(rel, 0.01);
}

}  // namespace
}  // namespace tf::grind
