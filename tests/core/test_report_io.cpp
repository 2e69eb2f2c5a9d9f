// The verification report's files: what write_verify_json and write_blocks_csv write, read_verify_json and
// read_blocks_csv read back; and the readers' errors name the file, line and field.
#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/report.hpp"

namespace tf {
namespace {

VerifyReport sample_report() {
  VerifyReport r;
  r.blocks = 3;
  r.removed_volume_mm3 = 12.5;
  r.stock_volume_start_mm3 = 1000.0;
  r.stock_volume_end_mm3 = 987.5;
  r.max_gouge_mm = 0.02;
  r.resolution_mm = 0.1;
  r.rays = 300;
  r.material_rays = 120;
  r.seconds = 1.25;
  r.sweep_error_mm = 0.004;
  r.holder_sweep_error_mm = 0.03;
  r.gouge_tolerance_mm = 0.02;
  r.collision_tolerance_mm = 0.005;
  Collision c;
  c.block = 2;
  c.line = 7;
  c.component = ToolComponent::Shank;
  c.with = HitWith::Fixture;
  c.rapid = true;
  c.depth_mm = 0.35;
  c.start = {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0, 0, 1)};
  c.end = {Eigen::Vector3d(4, 5, 6), Eigen::Vector3d(0, 0.6, 0.8)};
  c.tool = 12;
  r.collisions.push_back(c);
  r.gouges.push_back({3, 8, 0.02});
  r.warnings.push_back("p.ngc:1: G54 is not simulated");
  BlockResult cut;
  cut.block = 1;
  cut.line = 6;
  cut.removed_mm3 = 12.5;
  cut.minutes = 0.5;
  cut.dwell_minutes = 0.25;
  cut.tool = 3;
  cut.engagement.entry_deg = 10.0;
  cut.engagement.exit_deg = 170.0;
  cut.engagement.area_mm2 = 4.25;
  cut.engagement.axial_depth_mm = 1.5;
  cut.engagement.radial_width_mm = 6.0;
  cut.engagement.max_pairs = 1;
  BlockResult air;
  air.block = 2;
  air.line = 7;
  air.rapid = true;
  air.collision = true;
  r.per_block = {cut, air};
  r.stock_mesh = StockMeshStats{.max_error_mm = 0.01, .vertices = 1500, .faces = 2996, .bytes = 57000,
                                .full_vertices = 90000, .full_faces = 179996, .mesh_seconds = 0.75,
                                .decimate_seconds = 2.5};
  return r;
}

TEST(ReportIo, VerifyJsonRoundTrip) {
  test::TempDir dir;
  const VerifyReport w = sample_report();
  write_verify_json(w, dir / "v.json");
  const VerifyReport r = read_verify_json(dir / "v.json");
  EXPECT_EQ(r.blocks, 3);
  EXPECT_DOUBLE_EQ(r.removed_volume_mm3, 12.5);
  EXPECT_DOUBLE_EQ(r.stock_volume_end_mm3, 987.5);
  EXPECT_DOUBLE_EQ(r.max_gouge_mm, 0.02);
  EXPECT_DOUBLE_EQ(r.resolution_mm, 0.1);
  EXPECT_EQ(r.rays, 300u);
  EXPECT_EQ(r.material_rays, 120u);
  EXPECT_DOUBLE_EQ(r.holder_sweep_error_mm, 0.03);
  EXPECT_DOUBLE_EQ(r.gouge_tolerance_mm, 0.02);
  EXPECT_DOUBLE_EQ(r.collision_tolerance_mm, 0.005);
  ASSERT_EQ(r.collisions.size(), 1u);
  const Collision& c = r.collisions[0];
  EXPECT_EQ(c.block, 2);
  EXPECT_EQ(c.line, 7);
  EXPECT_EQ(c.component, ToolComponent::Shank);
  EXPECT_EQ(c.with, HitWith::Fixture);
  EXPECT_TRUE(c.rapid);
  EXPECT_DOUBLE_EQ(c.depth_mm, 0.35);
  EXPECT_EQ(c.tool, 12);
  ASSERT_TRUE(c.has_poses);
  EXPECT_EQ(c.start.tip, Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR((c.end.axis - Eigen::Vector3d(0, 0.6, 0.8)).norm(), 0.0, 1e-12);
  ASSERT_EQ(r.gouges.size(), 1u);
  EXPECT_EQ(r.gouges[0].line, 8);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], w.warnings[0]);
  EXPECT_TRUE(r.per_block.empty()) << "blocks.csv carries the blocks";
  ASSERT_TRUE(r.stock_mesh.has_value());
  EXPECT_DOUBLE_EQ(r.stock_mesh->max_error_mm, 0.01);
  EXPECT_EQ(r.stock_mesh->vertices, 1500u);
  EXPECT_EQ(r.stock_mesh->faces, 2996u);
  EXPECT_EQ(r.stock_mesh->bytes, 57000u);
  EXPECT_EQ(r.stock_mesh->full_vertices, 90000u);
  EXPECT_EQ(r.stock_mesh->full_faces, 179996u);
  EXPECT_DOUBLE_EQ(r.stock_mesh->decimate_seconds, 2.5);
  // The program's time: motion and dwells of every block.
  const std::string text = test::read_text(dir / "v.json");
  EXPECT_NE(text.find("\"program_minutes\": 0.75"), std::string::npos) << text;
}

TEST(ReportIo, VerifyJsonWithTheDocumentedFieldsOnly) {
  test::TempDir dir;
  test::write_text(dir / "verify.json", R"({"blocks": 3, "removed_volume_mm3": 12.5, "max_gouge_mm": 0.01,
    "resolution_mm": 0.1, "rays": 100, "seconds": 1.5,
    "collisions": [{"block": 2, "line": 30, "component": "holder", "with": "check", "rapid": false, "depth_mm": 0.3}],
    "gouges": [{"block": 1, "line": 29, "depth_mm": 0.01}]})");
  const VerifyReport v = read_verify_json(dir / "verify.json");
  ASSERT_EQ(v.collisions.size(), 1u);
  EXPECT_EQ(v.collisions[0].component, ToolComponent::Holder);
  EXPECT_EQ(v.collisions[0].with, HitWith::Check);
  EXPECT_FALSE(v.collisions[0].has_poses);
  EXPECT_EQ(v.collisions[0].tool, 0) << "no tool field: 0";
  EXPECT_EQ(v.gouges[0].line, 29);
  EXPECT_DOUBLE_EQ(v.removed_volume_mm3, 12.5);
  EXPECT_TRUE(std::isnan(v.stock_volume_start_mm3)) << "not in the file: unknown";
  EXPECT_FALSE(v.stock_mesh.has_value());
}

// Each malformed report names the field that is wrong.
TEST(ReportIo, VerifyJsonErrorsNameTheField) {
  test::TempDir dir;
  const std::pair<const char*, const char*> cases[] = {
      {R"({"collisions": [{"block": 2, "line": 30, "component": "holder", "with": "check"}]})", "collisions[0].rapid"},
      {R"({"collisions": [{"block": 2, "line": 30, "component": "nozzle", "with": "check", "rapid": false,
          "depth_mm": 1}]})", "collisions[0].component"},
      {R"({"collisions": [{"block": 2.5, "line": 30}]})", "collisions[0].block"},
      {R"({"collisions": [{"block": 2, "line": 30, "component": "ball", "with": "stock", "rapid": false,
          "depth_mm": 1, "start_tip": [0, 0, 0]}]})", "collisions[0].start_axis"},
      {R"({"collisions": [{"block": 2, "line": 30, "component": "ball", "with": "stock", "rapid": false,
          "depth_mm": 1, "start_tip": [0, 0, 0], "start_axis": [0, 0, 2], "end_tip": [1, 0, 0],
          "end_axis": [0, 0, 1]}]})", "collisions[0].start_axis"},
      {R"({"collisions": [{"block": 2, "line": 30, "component": "ball", "with": "stock", "rapid": false,
          "depth_mm": 1, "tool": -1}]})", "collisions[0].tool"},
      {R"({"collisions": [{"block": 2, "line": 30, "component": "ball", "with": "stock", "rapid": false,
          "depth_mm": 1, "tool": "T1"}]})", "collisions[0].tool"},
      {R"({"collisions": [], "gouges": {"block": 1}})", "gouges"},
      {R"({"collisions": [], "removed_volume_mm3": "12"})", "removed_volume_mm3"},
      {R"({})", "collisions"},  // another JSON file (a scene, an empty object): not a report
      {R"({"units": "mm", "stock": {}})", "collisions"},
  };
  for (const auto& [text, field] : cases) {
    test::write_text(dir / "bad.json", text);
    try {
      read_verify_json(dir / "bad.json");
      ADD_FAILURE() << "expected InputError for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << text;
      EXPECT_EQ(e.file(), (dir / "bad.json").string());
    }
  }
  test::write_text(dir / "broken.json", "{\n  \"blocks\": 3,\n  oops\n}");
  try {
    read_verify_json(dir / "broken.json");
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
  }
}

TEST(ReportIo, BlocksCsvRoundTrip) {
  test::TempDir dir;
  write_blocks_csv(sample_report(), dir / "b.csv");
  const std::vector<BlockRow> rows = read_blocks_csv(dir / "b.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].block, 1);
  EXPECT_EQ(rows[0].line, 6);
  EXPECT_DOUBLE_EQ(rows[0].removed_mm3, 12.5);
  EXPECT_DOUBLE_EQ(rows[0].mrr_mm3_min, 25.0);
  EXPECT_DOUBLE_EQ(rows[0].entry_deg, 10.0);
  EXPECT_DOUBLE_EQ(rows[0].exit_deg, 170.0);
  EXPECT_DOUBLE_EQ(rows[0].engaged_area_mm2, 4.25);
  EXPECT_DOUBLE_EQ(rows[0].axial_depth_mm, 1.5);
  EXPECT_EQ(rows[0].pairs, 1);
  EXPECT_EQ(rows[0].tool, 3);
  EXPECT_EQ(rows[1].tool, 0);
  EXPECT_FALSE(rows[0].collision);
  EXPECT_TRUE(std::isnan(rows[1].mrr_mm3_min)) << "a block that takes no time has no MRR";
  EXPECT_TRUE(std::isnan(rows[1].entry_deg)) << "nothing engaged: no angle";
  // A rapid is not measured: its engagement cells are empty, not 0 (black-box testing).
  EXPECT_TRUE(std::isnan(rows[1].engaged_area_mm2));
  EXPECT_TRUE(std::isnan(rows[1].axial_depth_mm));
  EXPECT_TRUE(std::isnan(rows[1].radial_width_mm));
  EXPECT_EQ(rows[1].pairs, -1);
  EXPECT_TRUE(rows[1].collision);
}

TEST(ReportIo, BlocksCsvWithTheDocumentedColumnsOnly) {
  test::TempDir dir;
  test::write_text(dir / "blocks.csv",
                   "block,line,removed_mm3,mrr_mm3_min,entry_deg,exit_deg,engaged_area_mm2,collision\n"
                   "0,12,1.5,300,0,90,2.5,0\n1,13,0,0,0,0,0,true\n2,14,1.25,,,,,0\n");
  const auto rows = read_blocks_csv(dir / "blocks.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_TRUE(std::isnan(rows[2].mrr_mm3_min)) << "empty cell: not computed";
  EXPECT_DOUBLE_EQ(rows[2].removed_mm3, 1.25);
  EXPECT_EQ(rows[0].line, 12);
  EXPECT_DOUBLE_EQ(rows[0].mrr_mm3_min, 300.0);
  EXPECT_TRUE(rows[1].collision);
  EXPECT_TRUE(std::isnan(rows[0].axial_depth_mm));
  EXPECT_EQ(rows[0].pairs, -1);
  EXPECT_EQ(rows[0].tool, -1);
  test::write_text(dir / "bad.csv", "block,line,removed_mm3,mrr_mm3_min,entry_deg,exit_deg,engaged_area_mm2,collision\n"
                                    "0,12,1.5,abc,0,90,2.5,0\n");
  try {
    read_blocks_csv(dir / "bad.csv");
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "mrr_mm3_min");
  }
  test::write_text(dir / "huge.csv", "block,line,removed_mm3,mrr_mm3_min,entry_deg,exit_deg,engaged_area_mm2,collision\n"
                                     "1e300,12,1.5,1,0,90,2.5,0\n");
  EXPECT_THROW(read_blocks_csv(dir / "huge.csv"), InputError);
  test::write_text(dir / "short.csv", "block,line\n0,1\n");
  EXPECT_THROW(read_blocks_csv(dir / "short.csv"), InputError);
}

}  // namespace
}  // namespace tf
