// End to end: a scene whose direct move between two passes would cross a boss of stock is posted by
// `tiltfield post` with a lifted link; every rapid clears the stock by an independent FCL check, and
// `tiltfield verify` finds no collision. Posted without links (a huge --link-gap), the same scene does
// collide. A bad --link-gap exits 2 naming the option.
#include <fcl/fcl.h>
#include <gtest/gtest.h>

#include <fstream>

#include "post/links_fixture.hpp"
#include "test_support.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace tf {
namespace {

namespace fs = std::filesystem;
using namespace links_test;

fs::path write_boss_scene(const test::TempDir& dir) {
  write_mesh(boss_stock_mesh(), dir / "stock.stl");
  std::ofstream csv(dir / "path.csv");
  csv << "x,y,z,nx,ny,nz\n";
  for (const OrientedRow& r : two_passes().rows) csv << r.p.x() << "," << r.p.y() << "," << r.p.z() << ",0,0,1\n";
  write_oriented_csv(two_passes(), dir / "oriented.csv");
  const fs::path machine = fs::path(TILTFIELD_SOURCE_DIR) / "scenes" / "machines" / "xyz.json";
  test::write_text(dir / "scene.json",
                   "{\"units\": \"mm\", \"design\": \"stock.stl\", \"check_surfaces\": [],"
                   " \"stock\": {\"mesh\": \"stock.stl\"}, \"fixtures\": [],"
                   " \"tool\": {\"type\": \"ball\", \"radius\": 3.0, \"flute_length\": 12.0, \"shank_radius\": 3.0,"
                   " \"length\": 60.0, \"holder\": [{\"radius\": 12.0, \"length\": 40.0}]},"
                   " \"path\": {\"file\": \"path.csv\", \"feed\": 1000},"
                   " \"planner\": {\"safety_distance\": 1.0}, \"machine\": \"" + machine.string() + "\"}\n");
  return dir / "scene.json";
}

// The least distance (FCL: a sphere for the ball, cylinders for flutes, shank and holder, boxes for the
// stock) over every rapid that does not back out of a cut, sampled every 0.25 mm; and the rapid count.
std::pair<double, int> fcl_rapid_clearance(const Program& prog, const Kinematics& kin) {
  struct Part {
    std::shared_ptr<fcl::CollisionGeometryd> geom;
    double mid;  // centre height above the tip
  };
  std::vector<Part> parts = {{std::make_shared<fcl::Sphered>(3.0), 3.0},
                             {std::make_shared<fcl::Cylinderd>(3.0, 9.0), 7.5},
                             {std::make_shared<fcl::Cylinderd>(3.0, 48.0), 36.0},
                             {std::make_shared<fcl::Cylinderd>(12.0, 40.0), 80.0}};
  std::vector<fcl::CollisionObjectd> boxes;
  for (const Box& b : boss_stock_boxes()) {
    fcl::Transform3d t = fcl::Transform3d::Identity();
    t.translation() = 0.5 * (b.lo + b.hi);
    const Eigen::Vector3d size = b.hi - b.lo;
    boxes.emplace_back(std::make_shared<fcl::Boxd>(size.x(), size.y(), size.z()), t);
  }
  double least = 1e9;
  int rapids = 0;
  Joints prev = prog.start;
  bool after_feed = false;
  for (const Block& b : prog.blocks) {
    if (b.motion == Motion::Rapid && !after_feed) {
      ++rapids;
      const double span = (kin.forward(b.target).tip - kin.forward(prev).tip).norm();
      const int n = std::max(1, static_cast<int>(std::ceil(span / 0.25)));
      for (int k = 0; k <= n; ++k) {
        const ToolPose pose = kin.forward(lerp_joints(prev, b.target, double(k) / n));
        const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), pose.axis).toRotationMatrix();
        for (const Part& part : parts) {
          fcl::Transform3d t = fcl::Transform3d::Identity();
          t.linear() = R;
          t.translation() = pose.tip + part.mid * pose.axis;
          const fcl::CollisionObjectd body(part.geom, t);
          for (const auto& box : boxes) {
            fcl::DistanceRequestd rq;
            fcl::DistanceResultd rs;
            fcl::distance(&body, &box, rq, rs);
            least = std::min(least, rs.min_distance);
          }
        }
      }
    }
    after_feed = b.motion != Motion::Rapid;
    prev = b.target;
  }
  return {least, rapids};
}

TEST(LinksCli, BossSceneIsPostedWithALiftedLinkThatVerifiesClean) {
  test::TempDir dir;
  const fs::path scene = write_boss_scene(dir);
  const std::string post = "post '" + scene.string() + "' '" + (dir / "oriented.csv").string() + "' -o ";
  const std::string verify = "verify '" + scene.string() + "' ";

  auto r = test::run_tiltfield(post + "'" + (dir / "linked.ngc").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  r = test::run_tiltfield(verify + "'" + (dir / "linked.ngc").string() + "' -o '" + (dir / "linked.json").string() +
                          "' --resolution 0.25");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const VerifyReport linked = read_verify_json(dir / "linked.json");
  EXPECT_TRUE(linked.collisions.empty()) << linked.collisions.size() << " collisions, first at line "
                                          << linked.collisions.front().line;

  const MachineSpec machine = read_machine_json(fs::path(TILTFIELD_SOURCE_DIR) / "scenes" / "machines" / "xyz.json");
  const Program prog = parse_gcode(test::read_text(dir / "linked.ngc"), "linked.ngc", machine);
  const Tool tool = links_tool();
  const auto [least, rapids] = fcl_rapid_clearance(prog, Kinematics(machine, tool.length));
  EXPECT_GE(rapids, 5);
  EXPECT_GT(least, 0.5 * machine.safe_z - 0.25);

  // Without links the jump is one feed move through the boss: the shank and holder meet the stock.
  r = test::run_tiltfield(post + "'" + (dir / "direct.ngc").string() + "' --link-gap 1000000");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  r = test::run_tiltfield(verify + "'" + (dir / "direct.ngc").string() + "' -o '" + (dir / "direct.json").string() +
                          "' --resolution 0.25");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_FALSE(read_verify_json(dir / "direct.json").collisions.empty());
}

TEST(LinksCli, BadLinkGapExitsTwoNamingTheOption) {
  test::TempDir dir;
  const fs::path scene = write_boss_scene(dir);
  for (const char* bad : {"0", "-3", "inf", "abc"}) {
    const auto r = test::run_tiltfield("post '" + scene.string() + "' '" + (dir / "oriented.csv").string() + "' -o '" +
                                       (dir / "p.ngc").string() + "' --link-gap " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.out;
    EXPECT_NE(r.out.find("--link-gap"), std::string::npos) << bad << ": " << r.out;
    EXPECT_EQ(test::count_lines(r.out), 1) << bad << ": " << r.out;
    EXPECT_FALSE(fs::exists(dir / "p.ngc"));
  }
}

}  // namespace
}  // namespace tf
