// Fixtures on generated impellers: a clamp block where the holder, or the shank, passes halfway along the
// path (placed from a plan made without it) is avoided by the planner (an independent FCL check with the
// clamp as the obstacle) and `run` leaves no collision; a clamp the cutter itself passes through is
// reported as unfixable, with exit 1. Named *Slow: the sanitizer build skips it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "scenes/scene_impeller.hpp"
#include "scenes/scene_writer.hpp"
#include "test_support.hpp"
#include "tilt/synthetic.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/triangle_bvh.hpp"
#include "tiltfield/tilt/plan.hpp"

namespace tf {
namespace {

enum class Clamp { Holder, Shank, Cutter };

struct ClampCase {
  int blades;
  double lean;
  Clamp clamp;
};

scenes::ImpellerOptions clamp_impeller(int blades, double lean) {
  scenes::ImpellerOptions o;
  o.blades = blades;
  o.lean_deg = lean;
  o.passes = 2;
  o.step = 1.0;
  o.tolerance = 0.01;
  o.ball_clearance = 1.2;  // the ball itself cannot be turned away from a blade
  return o;
}

std::vector<const Mesh*> blades_of(const scenes::SceneBundle& b) {
  std::vector<const Mesh*> m;
  for (const auto& c : b.check_surfaces) m.push_back(&c.mesh);
  return m;
}

// A cube of side `size` centred at `centre`.
Mesh clamp_cube(const Eigen::Vector3d& centre, double size) {
  const Eigen::Vector3d h = Eigen::Vector3d::Constant(0.5 * size);
  return test::box_mesh(centre - h, centre + h, size / 4);
}

// The clamp: at the middle row of `free` (a plan made without it), beside the holder's (or shank's)
// middle on the side nearer the blades, overlapping the cylinder by 1.5 mm; or around the cutter itself.
Mesh place_clamp(const scenes::SceneBundle& b, const PlanResult& free, Clamp clamp) {
  const size_t m = free.path.rows.size() / 2;
  const Eigen::Vector3d c = free.path.rows[m].p, a = free.path.rows[m].axis;
  const Tool& t = b.tool;
  if (clamp == Clamp::Cutter) return clamp_cube(c, 2 * t.radius() + 2.0);
  const bool holder = clamp == Clamp::Holder;
  const double h = holder ? t.length - t.cl_height() + 0.5 * t.holder[0].length
                          : 0.5 * (t.flute_length + t.length) - t.cl_height();
  const double r = holder ? t.holder[0].radius : t.shank_radius;
  const double size = holder ? 6.0 : 3.0;
  const Eigen::Vector3d f = (free.path.rows[m + 1].p - free.path.rows[m - 1].p).normalized();
  const Eigen::Vector3d side = a.cross(f).normalized();
  const TriangleBvh blades(blades_of(b));
  Eigen::Vector3d best;
  double nearest = std::numeric_limits<double>::infinity();
  for (double s : {-1.0, 1.0}) {
    const Eigen::Vector3d centre = c + h * a + s * (r + 0.5 * size - 1.5) * side;
    const double d = blades.closest(centre).distance;
    if (d < nearest) nearest = d, best = centre;
  }
  return clamp_cube(best, size);
}

// The scene with its clamp, written to `dir`; `free` receives the plan made without the clamp.
std::filesystem::path write_clamp_scene(const ClampCase& c, const std::filesystem::path& dir, PlanResult& free) {
  scenes::SceneBundle b =
      scenes::make_impeller_scene(clamp_impeller(c.blades, c.lean), scenes::machine_json("table-table-ac", {}));
  free = plan_path(b.path, b.tool, {blades_of(b), {}, {}}, b.planner, b.feed, derive_plan_options(b.tool, b.planner, b.feed));
  b.fixtures.push_back({"clamp.stl", place_clamp(b, free, c.clamp)});
  return scenes::write_scene_folder(b, dir);
}

class ImpellerFixtureSlow : public ::testing::TestWithParam<ClampCase> {};

TEST_P(ImpellerFixtureSlow, PlannedClearOfTheClampAndRunLeavesNothingItCouldFix) {
  const ClampCase c = GetParam();
  test::TempDir dir;
  PlanResult blind;
  const std::filesystem::path scene_file = write_clamp_scene(c, dir.path(), blind);
  const Scene scene = load_scene(scene_file);
  ASSERT_EQ(scene.fixtures.size(), 1u);

  // Without the clamp as an obstacle the plan meets it: the test can fail.
  const std::vector<const Mesh*> clamp{&scene.fixtures[0]}, blades = scene_obstacles(scene).check_surfaces;
  PlannerBasics at_clamp = scene.planner;  // every component keeps the fixture clearance from the clamp
  at_clamp.shank_clearance = at_clamp.holder_clearance = at_clamp.safety_distance =
      scene.planner.fixture_clearance.value_or(scene.planner.safety_distance);
  EXPECT_GT(test::fcl_check(blind.path, scene.tool, clamp, at_clamp).rows_below, 0u);

  const auto run = test::run_tiltfield("run '" + scene_file.string() + "' -o out --resolution 0.2", dir.path());
  if (c.clamp == Clamp::Cutter) {
    EXPECT_EQ(run.exit_code, 1) << run.out;
    EXPECT_EQ(run.out.find(" 0 rows not cleared"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("ball in fixture"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("no tool axis moves it"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("in 0 re-plan round(s)"), std::string::npos) << run.out;  // nothing it could fix
    return;
  }
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find(" 0 rows not cleared"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find(" 0 found, 0 fixed in 0 re-plan round(s) (0 rows), 0 left"), std::string::npos) << run.out;
  // No collision, so no re-plan: the oriented path written is the plan. Independent check with FCL.
  const OrientedPath planned = read_oriented_csv(dir / "out/oriented.csv");
  ASSERT_EQ(planned.rows.size(), scene.path.rows.size());
  const auto by_clamp = test::fcl_check(planned, scene.tool, clamp, at_clamp);
  EXPECT_EQ(by_clamp.rows_below, 0u) << "min margin to the clamp " << by_clamp.min_margin;
  const auto by_blades = test::fcl_check(planned, scene.tool, blades, scene.planner);
  EXPECT_EQ(by_blades.rows_below, 0u) << "min margin to the blades " << by_blades.min_margin;
  double reported = 1e9;
  for (const auto& row : planned.rows) reported = std::min(reported, row.clearance_mm);
  EXPECT_NEAR(reported, std::min(by_clamp.min_distance, by_blades.min_distance), 0.01);
}

INSTANTIATE_TEST_SUITE_P(Impellers, ImpellerFixtureSlow,
                         ::testing::Values(ClampCase{7, 15, Clamp::Holder}, ClampCase{7, 15, Clamp::Shank},
                                           ClampCase{7, 15, Clamp::Cutter}, ClampCase{9, -10, Clamp::Holder},
                                           ClampCase{9, -10, Clamp::Shank}, ClampCase{5, 0, Clamp::Holder}),
                         [](const ::testing::TestParamInfo<ClampCase>& info) {
                           const ClampCase& c = info.param;
                           const char* what = c.clamp == Clamp::Holder  ? "Holder"
                                              : c.clamp == Clamp::Shank ? "Shank"
                                                                        : "Cutter";
                           return std::to_string(c.blades) + "Blades" + (c.lean < 0 ? "Minus" : "") +
                                  std::to_string(static_cast<int>(std::abs(c.lean))) + "Deg" + what;
                         });

}  // namespace
}  // namespace tf
