#include <gtest/gtest.h>

#include <tuple>

#include "test_support.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/local_frame.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace {

tf::Tool ball3() {
  tf::Tool t;
  t.cutter = tf::BallCutter{3.0};
  return t;
}

TEST(PathIO, CsvColumnsInAnyOrderWithFeed) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "p.csv", "# comment\nnz,ny,nx,z,y,x,feed\n1,0,0,3,2,1,800\n0.6,0.8,0,3,2,2,\n");
  const auto p = tf::read_toolpath_csv(dir / "p.csv");
  ASSERT_EQ(p.rows.size(), 2u);
  EXPECT_EQ(p.rows[0].p, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(p.rows[0].n, Eigen::Vector3d(0, 0, 1));
  EXPECT_DOUBLE_EQ(p.rows[0].feed, 800);
  EXPECT_TRUE(std::isnan(p.rows[1].feed));
  EXPECT_NEAR(p.arc_length()[1], 1.0, 1e-12);
}

// A spreadsheet's UTF-8 byte-order mark before the header is skipped: the first column had been read as
// "\xEF\xBB\xBFx" and reported missing (black-box testing). Likewise before an APT file's first record.
TEST(PathIO, ByteOrderMarkBeforeTheHeaderIsSkipped) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "p.csv", "\xEF\xBB\xBFx,y,z,nx,ny,nz\n1,2,3,0,0,1\n");
  const auto p = tf::read_toolpath_csv(dir / "p.csv");
  ASSERT_EQ(p.rows.size(), 1u);
  EXPECT_EQ(p.rows[0].p.x(), 1.0);
  tf::test::write_text(dir / "p.apt", "\xEF\xBB\xBFGOTO/0,0,50,0,0,1\nFINI\n");
  EXPECT_EQ(tf::read_toolpath(dir / "p.apt", ball3()).rows.size(), 1u);
}

TEST(PathIO, CsvRoundTrip) {
  tf::test::TempDir dir;
  tf::ToolPath p;
  p.rows.push_back({{1.123456789, -2, 1e-7}, Eigen::Vector3d(1, 1, 1).normalized(), 1234});
  p.rows.push_back({{0, 0, 0}, {0, 0, 1}, std::numeric_limits<double>::quiet_NaN()});
  tf::write_toolpath_csv(p, dir / "p.csv");
  const std::string text = tf::test::read_text(dir / "p.csv");
  for (size_t i = 1; i < text.size(); ++i)
    EXPECT_FALSE(std::isdigit(static_cast<unsigned char>(text[i - 1])) && (text[i] == 'e' || text[i] == 'E'))
        << "scientific notation in:\n" << text;
  const auto back = tf::read_toolpath_csv(dir / "p.csv");
  ASSERT_EQ(back.rows.size(), 2u);
  EXPECT_NEAR((back.rows[0].p - p.rows[0].p).norm(), 0, 1e-9);
  EXPECT_NEAR((back.rows[0].n - p.rows[0].n).norm(), 0, 1e-8);
}

TEST(PathIO, AptCldataGivesCutterLocations) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "p.apt",
                       "PARTNO/TEST\nCUTTER/6\nMULTAX/ON\nRAPID\nGOTO/0,0,50,0,0,1\nFEDRAT/MMPM,900\n"
                       "GOTO/10,0,0,0,0,1\nGOTO/10,5,0,$\n0.6,0,0.8\n$$ a comment\nGOTO/20,5,0\nFINI\n");
  const auto p = tf::read_toolpath_apt(dir / "p.apt", ball3());
  ASSERT_EQ(p.rows.size(), 3u);  // the RAPID positioning move is not a cutting row
  EXPECT_NEAR((p.rows[0].p - Eigen::Vector3d(10, 0, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.rows[1].p - Eigen::Vector3d(10 + 1.8, 5, 2.4)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.rows[1].n - Eigen::Vector3d(0.6, 0, 0.8)).norm(), 0, 1e-12);
  EXPECT_DOUBLE_EQ(p.rows[2].feed, 900);
  EXPECT_EQ(tf::read_toolpath(dir / "p.apt", ball3()).rows.size(), 3u);
  // The row after the RAPID's is linked to, the others cut (a CSV's rows: by the link gap).
  EXPECT_EQ(p.rows[0].approach, tf::Approach::Link);
  EXPECT_EQ(p.rows[1].approach, tf::Approach::Cut);
  EXPECT_EQ(p.rows[2].approach, tf::Approach::Cut);
}

// UNITS/INCHES scales the coordinates and a feed without its own unit; FEDRAT/IPM is inches a minute;
// "$$" ends a record's line as a comment; a GOTO of three values keeps the tool axis in force; nothing
// after FINI is read. Units the reader does not know, and feeds per revolution, are refused by name.
TEST(PathIO, AptUnitsInlineCommentsAndFini) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "in.cl",
                       "UNITS/INCHES $$ the part in inches\nFEDRAT/IPM,20\nGOTO/1,0,0.5,0.6,0,0.8 $$ first\n"
                       "FEDRAT/10\nGOTO/2,0,0.5\nFINI\nGOTO/9,9,9\n");
  const auto p = tf::read_toolpath_apt(dir / "in.cl", ball3());
  ASSERT_EQ(p.rows.size(), 2u);
  EXPECT_NEAR((p.rows[0].p - (Eigen::Vector3d(25.4, 0, 12.7) + 3.0 * Eigen::Vector3d(0.6, 0, 0.8))).norm(), 0, 1e-12);
  EXPECT_DOUBLE_EQ(p.rows[0].feed, 508.0);
  EXPECT_NEAR((p.rows[1].n - Eigen::Vector3d(0.6, 0, 0.8)).norm(), 0, 1e-12);
  EXPECT_DOUBLE_EQ(p.rows[1].p.x(), 50.8 + 1.8);
  EXPECT_DOUBLE_EQ(p.rows[1].feed, 254.0);
  for (const auto& [text, field] : {std::pair<std::string, std::string>{"UNITS/FURLONG\nGOTO/1,2,3\n", "UNITS"},
                                    {"FEDRAT/IPR,0.1\nGOTO/1,2,3\n", "FEDRAT/IPR"}}) {
    tf::test::write_text(dir / "bad.cl", text);
    try {
      tf::read_toolpath_apt(dir / "bad.cl", ball3());
      ADD_FAILURE() << text;
    } catch (const tf::InputError& e) {
      EXPECT_EQ(e.line(), 1) << text;
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

// GODLTA moves from the last position (FROM's or a GOTO's): by dx,dy,dz, or by d along the tool axis.
// Records whose motion is no straight line to the next point (an arc, a cycle) are refused by name: read
// silently, a CIRCLE's quarter arc had been cut as its chord, 1.46 mm off (black-box testing).
TEST(PathIO, AptIncrementalMovesAndMotionNotFollowed) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "d.cl", "FROM/0,0,50,0,0,1\nGODLTA/0,0,-50\nGODLTA/10,0,0\nGODLTA/0,10,0\nGODLTA/5\nFINI\n");
  const auto p = tf::read_toolpath_apt(dir / "d.cl", ball3());
  ASSERT_EQ(p.rows.size(), 4u);  // FROM is where the tool starts, not a cut
  EXPECT_NEAR((p.rows[0].p - Eigen::Vector3d(0, 0, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.rows[1].p - Eigen::Vector3d(10, 0, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.rows[2].p - Eigen::Vector3d(10, 10, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.rows[3].p - Eigen::Vector3d(10, 10, 8)).norm(), 0, 1e-12);
  // The last position is kept in mm: a UNITS change between a GOTO and a GODLTA moves by the new units only.
  tf::test::write_text(dir / "u.cl", "GOTO/1,0,0\nUNITS/INCHES\nGODLTA/0,0,1\n");
  const auto u = tf::read_toolpath_apt(dir / "u.cl", ball3());
  ASSERT_EQ(u.rows.size(), 2u);
  EXPECT_NEAR((u.rows[1].p - Eigen::Vector3d(1, 0, 25.4 + 3)).norm(), 0, 1e-12);
  for (const auto& [text, line, field] :
       {std::tuple<std::string, int, std::string>{"GODLTA/1,0,0\nGOTO/1,2,3\n", 1, "GODLTA"},
        {"GOTO/5,0,0,0,0,1\nINDIRV/0,1,0\nCIRCLE/0,0,0,0,0,1,5\nGOTO/0,5,0,0,0,1\n", 3, "CIRCLE"},
        {"GOTO/5,0,0\nCYCLE/DRILL,5,100,MMPM\nGOTO/5,0,0\n", 2, "CYCLE"}}) {
    tf::test::write_text(dir / "bad.cl", text);
    try {
      tf::read_toolpath_apt(dir / "bad.cl", ball3());
      ADD_FAILURE() << text;
    } catch (const tf::InputError& e) {
      EXPECT_EQ(e.line(), line) << text;
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
  tf::test::write_text(dir / "off.cl", "GOTO/5,0,0\nCYCLE/OFF\nGOTO/6,0,0\n");
  EXPECT_EQ(tf::read_toolpath_apt(dir / "off.cl", ball3()).rows.size(), 2u);
}

TEST(PathIO, BadAptNamesTheLine) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "p.cl", "MULTAX/ON\nGOTO/1,2,3\nGOTO/1,2\n");
  try {
    tf::read_toolpath(dir / "p.cl", ball3());
    FAIL();
  } catch (const tf::InputError& e) {
    EXPECT_EQ(e.line(), 3);
  }
  tf::test::write_text(dir / "q.cl", "GOTO/1,2,3,0,0,2\n");
  EXPECT_THROW(tf::read_toolpath(dir / "q.cl", ball3()), tf::InputError);
  tf::test::write_text(dir / "r.cl", "MULTAX/ON\n");
  EXPECT_THROW(tf::read_toolpath(dir / "r.cl", ball3()), tf::InputError);
  // A record the reader follows without its '/' had been skipped as unknown, its point dropped.
  for (const char* bad : {"GOTO 1,2,19", "FEDRAT 100", "GODLTA 1,0,0", "UNITS MM"}) {
    tf::test::write_text(dir / "s.cl", std::string("GOTO/0,0,20\n") + bad + "\nGOTO/1,1,20\n");
    try {
      tf::read_toolpath(dir / "s.cl", ball3());
      ADD_FAILURE() << bad;
    } catch (const tf::InputError& e) {
      EXPECT_EQ(e.line(), 2) << bad;
    }
  }
}

TEST(PathIO, OrientedRoundTripAndBadAxis) {
  tf::test::TempDir dir;
  tf::OrientedPath o;
  o.rows.push_back({{1, 2, 3}, Eigen::Vector3d(0, 1, 1).normalized(), 5, -7, 1.25});
  o.rows.push_back({{1, 2, 4}, {0, 0, 1}, 0, 0, std::numeric_limits<double>::infinity()});
  tf::write_oriented_csv(o, dir / "o.csv");
  const auto back = tf::read_oriented_csv(dir / "o.csv");
  ASSERT_EQ(back.rows.size(), 2u);
  EXPECT_NEAR((back.rows[0].axis - o.rows[0].axis).norm(), 0, 1e-8);
  EXPECT_DOUBLE_EQ(back.rows[0].tilt_deg, -7);
  EXPECT_TRUE(std::isinf(back.rows[1].clearance_mm));
  // A file read and written again is the same to the digit: an axis of 9 decimals, whose normalised
  // value prints -0.975883802, keeps its -0.975883803 (rows re-planning leaves alone are copies).
  const std::string text =
      "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm\n1,2,3,-0.975883803,-0.217796178,-0.01468431,0,0,1\n";
  tf::test::write_text(dir / "digits.csv", text);
  tf::write_oriented_csv(tf::read_oriented_csv(dir / "digits.csv"), dir / "again.csv");
  EXPECT_EQ(tf::test::read_text(dir / "again.csv"), text);
  tf::test::write_text(dir / "bad.csv", "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm\n0,0,0,0,0,1,0,0,1\n0,0,0,0,0.5,0.5,0,0,1\n");
  try {
    tf::read_oriented_csv(dir / "bad.csv");
    FAIL();
  } catch (const tf::InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "i,j,k");
  }
  const auto r = tf::test::run_tiltfield("check --oriented '" + (dir / "bad.csv").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("bad.csv:3"), std::string::npos) << r.out;
}

// Coordinates beyond 1 km and columns the format lacks are refused, naming the line and the field (found
// in review: 1e200 hung the planner, 1e100 became 100-digit G-code words, an extra column passed).
TEST(PathIO, AbsurdCoordinatesAndUnknownColumnsNameTheField) {
  tf::test::TempDir dir;
  auto expect_refused = [&](const std::string& file, const std::string& text, int line, const std::string& field,
                            bool oriented) {
    tf::test::write_text(dir / file, text);
    try {
      if (oriented) tf::read_oriented_csv(dir / file);
      else tf::read_toolpath(dir / file, ball3());
      ADD_FAILURE() << text;
    } catch (const tf::InputError& e) {
      EXPECT_EQ(e.line(), line) << text;
      EXPECT_EQ(e.field(), field) << text;
    }
  };
  expect_refused("p.csv", "x,y,z,nx,ny,nz\n0,0,0,0,0,1\n1e200,0,0,0,0,1\n", 3, "x", false);
  expect_refused("p.cl", "GOTO/0,0,50,0,0,1\nGOTO/0,-2e6,50,0,0,1\n", 2, "GOTO", false);
  const std::string header = "x,y,z,i,j,k,lead_deg,tilt_deg,clearance_mm";
  expect_refused("o.csv", header + "\n0,0,1e100,0,0,1,0,0,1\n", 2, "z", true);
  expect_refused("o.csv", header + ",speed\n0,0,0,0,0,1,0,0,1,5\n", 1, "speed", true);
  // A column named twice is refused by its name (the first had been read, the second ignored: black-box
  // testing); the line is the header's, after a comment.
  expect_refused("o.csv", header + ",feed,feed\n0,0,0,0,0,1,0,0,1,100,0\n", 1, "feed", true);
  expect_refused("p.csv", "# cut 1\nx,y,z,nx,ny,nz,x\n0,0,0,0,0,1,5\n", 2, "x", false);
  tf::test::write_text(dir / "ok.csv", header + ",feed\n999999,0,0,0,0,1,0,0,1,500\n");
  EXPECT_EQ(tf::read_oriented_csv(dir / "ok.csv").rows.size(), 1u);
}

TEST(LocalFrame, LeadTiltRoundTripAndConventions) {
  tf::ToolPath p;
  for (int i = 0; i < 5; ++i) p.rows.push_back({{double(i), 0, 0}, {0, 0, 1}});
  const auto frames = tf::local_frames(p);
  EXPECT_NEAR((frames[2].f - Eigen::Vector3d::UnitX()).norm(), 0, 1e-12);
  EXPECT_NEAR((frames[2].t - Eigen::Vector3d(0, -1, 0)).norm(), 0, 1e-12);  // t = f x n
  const Eigen::Vector3d a = tf::axis_from_lead_tilt(frames[2], 10, 0);
  EXPECT_GT(a.x(), 0);  // a positive lead leans the axis toward the feed
  for (double lead : {-30.0, 0.0, 12.5}) {
    for (double tilt : {-45.0, 0.0, 20.0}) {
      const auto lt = tf::lead_tilt_from_axis(frames[1], tf::axis_from_lead_tilt(frames[1], lead, tilt));
      EXPECT_NEAR(lt.x(), lead, 1e-9);
      EXPECT_NEAR(lt.y(), tilt, 1e-9);
    }
  }
}

// Repeated rows take the feed direction of the next distinct point (black-box testing: the first row of a
// path whose every point was repeated took an arbitrary direction, and its sideways axis read as lead).
TEST(LocalFrame, RepeatedRowsTakeTheFeedOfTheNextDistinctPoint) {
  tf::ToolPath p;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 2; ++k) p.rows.push_back({{double(i), 0, 0}, {0, 0, 1}});
  const auto frames = tf::local_frames(p);
  for (size_t i = 0; i < frames.size(); ++i)
    EXPECT_NEAR((frames[i].f - Eigen::Vector3d::UnitX()).norm(), 0, 1e-12) << "row " << i;
  // A reversal on a repeated point turns there, between the two rows (review): 3 4 5 5 4 3 on X.
  tf::ToolPath back;
  for (double x : {3.0, 4.0, 5.0, 5.0, 4.0, 3.0}) back.rows.push_back({{x, 0, 0}, {0, 0, 1}});
  const auto turned = tf::local_frames(back);
  EXPECT_NEAR(turned[2].f.x(), 1.0, 1e-12);
  EXPECT_NEAR(turned[3].f.x(), -1.0, 1e-12);
  // A corner on a repeated point: both rows take the corner's direction, as an unrepeated corner row does
  // (black-box testing: the first had taken +X before the corner, the second +Y after it).
  tf::ToolPath corner;
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0),
                                   Eigen::Vector3d(1, 1, 0)})
    corner.rows.push_back({q, {0, 0, 1}});
  const auto at_corner = tf::local_frames(corner);
  const Eigen::Vector3d diagonal = Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_NEAR((at_corner[1].f - diagonal).norm(), 0, 1e-12);
  EXPECT_NEAR((at_corner[2].f - diagonal).norm(), 0, 1e-12);
}

}  // namespace
