// `tiltfield scene impeller|pocket|block`: the built executable writes scenes that load back, and the
// impeller's meshes and path have the promised properties, checked independently of the generator's
// code (own STL reader, FCL distances, the hub formula written out again).
#include <gtest/gtest.h>

#include <iostream>

#include <nlohmann/json.hpp>

#include "scene_test_util.hpp"
#include "scenes/scene_writer.hpp"
#include "tiltfield/core/scene.hpp"

using namespace scene_test;

namespace {

// The bundled impeller: written at build time by `tiltfield --quiet scene impeller <scenes/impeller/
// options.txt> -o build/scenes/impeller` (the options file is empty: the defaults). Loaded once per test
// process; the hub formula's dimensions are taken from the options recorded in scene.json.
class BundledImpeller : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    file_ = fs::path(TILTFIELD_BINARY_DIR) / "scenes" / "impeller" / "scene.json";
    scene_ = new tf::Scene(tf::load_scene(file_));
    std::ifstream in(file_);
    options_ = new nlohmann::json(nlohmann::json::parse(in)["generator"]["options"]);
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete options_;
  }
  static HubEllipse hub_formula() {
    const auto& o = *options_;
    return {o["inlet_radius"], o["inlet_z"], o["outlet_radius"], o["outlet_z"]};
  }
  static inline fs::path file_;
  static inline tf::Scene* scene_ = nullptr;
  static inline nlohmann::json* options_ = nullptr;
};

TEST(SceneCli, ImpellerWritesADefaultSceneThatLoadsBack) {
  TempDir d("impeller_cli");
  const RunResult r = run_tiltfield("scene impeller -o '" + (d.path / "imp").string() + "' --preview '" +
                                        (d.path / "imp.svg").string() + "'",
                                    d.path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rows"), std::string::npos);
  const tf::Scene s = tf::load_scene(d.path / "imp" / "scene.json");
  EXPECT_TRUE(tf::is_closed(s.design));
  ASSERT_EQ(s.check_surfaces.size(), 1u);
  EXPECT_EQ(s.stock.kind, tf::Stock::Kind::Mesh);
  EXPECT_TRUE(tf::is_closed(s.stock.mesh));
  EXPECT_EQ(s.tool.type_name(), "ball");
  EXPECT_DOUBLE_EQ(s.tool.radius(), 3.0);
  EXPECT_DOUBLE_EQ(s.tool.flute_length, 12.0);
  EXPECT_DOUBLE_EQ(s.tool.shank_radius, 3.0);
  EXPECT_DOUBLE_EQ(s.tool.length, 60.0);
  ASSERT_EQ(s.tool.holder.size(), 1u);
  EXPECT_DOUBLE_EQ(s.tool.holder[0].radius, 12.0);
  EXPECT_DOUBLE_EQ(s.tool.holder[0].length, 40.0);
  EXPECT_DOUBLE_EQ(s.feed, 1500.0);
  EXPECT_DOUBLE_EQ(s.planner.lead_deg, 0.0);
  EXPECT_DOUBLE_EQ(s.planner.tilt_deg, 0.0);
  EXPECT_DOUBLE_EQ(s.planner.safety_distance, 1.0);
  ASSERT_TRUE(s.machine.has_value());
  EXPECT_EQ(s.machine->kinematics, tf::KinematicsType::TableTableAC);
  ASSERT_TRUE(s.machine->limits.count('A'));
  // The hub normals tilt up to 90 deg from the impeller axis: A must reach 90 deg one way or the other.
  const tf::AxisLimit a = s.machine->limits.at('A');
  EXPECT_TRUE(a.contains(0.0));
  EXPECT_GE(std::max(-a.min, a.max), 90.0);
  EXPECT_FALSE(s.machine->limits.count('C'));  // continuous
  EXPECT_GT(s.path.rows.size(), 500u);
  // With the default options the build's bundled scene is this very scene (same command), so the
  // property tests below, which read the bundled one, cover what this command writes.
  const fs::path bundled_file = fs::path(TILTFIELD_BINARY_DIR) / "scenes" / "impeller" / "scene.json";
  auto options_of = [](const fs::path& f) {
    std::ifstream in(f);
    return nlohmann::json::parse(in)["generator"]["options"];
  };
  if (options_of(bundled_file) == options_of(d.path / "imp" / "scene.json")) {
    const tf::Scene bundled = tf::load_scene(bundled_file);
    ASSERT_EQ(bundled.path.rows.size(), s.path.rows.size());
    EXPECT_TRUE(bundled.path.rows.back().p.isApprox(s.path.rows.back().p, 1e-12));
    EXPECT_EQ(bundled.design.n_faces(), s.design.n_faces());
  }

  const fs::path svg = d.path / "imp.svg";
  ASSERT_TRUE(fs::exists(svg));
  EXPECT_LT(fs::file_size(svg), 3'000'000u);
  std::ifstream in(svg);
  std::string head(4, '\0');
  in.read(head.data(), 4);
  EXPECT_EQ(head, "<svg");
}

TEST_F(BundledImpeller, HubIsAClosedOutwardSolidWithinTheChordalTolerance) {
  const Soup hub = read_binary_stl(file_.parent_path() / "hub.stl");
  EXPECT_TRUE(consistently_oriented(hub));
  EXPECT_GT(signed_volume(hub), 0.0);
  // Volume of the solid of revolution by Pappus from the documented profile.
  const HubEllipse e = hub_formula();
  const double nose = (*options_)["nose_z"], tol = (*options_)["tolerance"];
  double area_moment = 0;  // integral of r dA over the half-section, by the shoelace/centroid formula
  std::vector<Eigen::Vector2d> prof = {{0, 0}, {e.ro, 0}};
  for (int i = 0; i <= 20000; ++i) prof.push_back(e.at(std::numbers::pi / 2 * (1.0 - i / 20000.0)));
  prof.push_back({e.ri, nose});
  prof.push_back({0, nose});
  for (size_t i = 0; i < prof.size(); ++i) {
    const Eigen::Vector2d a = prof[i], b = prof[(i + 1) % prof.size()];
    const double cross = a.x() * b.y() - b.x() * a.y();
    area_moment += cross * (a.x() + b.x()) / 6.0;
  }
  const double analytic = 2 * std::numbers::pi * area_moment;
  EXPECT_NEAR(signed_volume(hub), analytic, 1e-4 * analytic);

  // Curved-surface triangles: every vertex, edge midpoint and centroid within the tolerance, and the
  // face normal pointing away from the solid (along the analytic outward normal).
  int curved = 0;
  double worst = 0, worst_normal = 1;
  for (const auto& t : hub.f) {
    const Eigen::Vector3d a = hub.v[t[0]], b = hub.v[t[1]], c = hub.v[t[2]];
    const Eigen::Vector3d g = (a + b + c) / 3;
    const Eigen::Vector2d q(std::hypot(g.x(), g.y()), g.z());
    if (q.y() > e.zi - 1e-6 || q.y() < e.zo + 1e-6 || q.x() < e.ri + 1e-6 || q.x() > e.ro - 1e-6) continue;
    if (e.distance(g) > 0.05) continue;  // rim, bottom, nose, cap
    ++curved;
    for (const Eigen::Vector3d& p : {a, b, c, g, Eigen::Vector3d((a + b) / 2), Eigen::Vector3d((b + c) / 2),
                                     Eigen::Vector3d((c + a) / 2)})
      worst = std::max(worst, e.distance(p));
    const double phi = e.nearest_phi(q);
    const Eigen::Vector2d n2 = e.normal(phi);
    const Eigen::Vector3d n(n2.x() * g.x() / q.x(), n2.x() * g.y() / q.x(), n2.y());
    worst_normal = std::min(worst_normal, (b - a).cross(c - a).normalized().dot(n));
  }
  EXPECT_GT(curved, 10000);
  std::cout << "hub: " << curved << " curved triangles, worst deviation " << worst << " mm\n";
  EXPECT_LE(worst, tol + 1e-5) << "float rounding of STL allows 1e-5";
  EXPECT_GT(worst_normal, 0.99);
}

TEST_F(BundledImpeller, BladesAreClosedConsistentlyOrientedSolids) {
  const Soup blades = read_binary_stl(file_.parent_path() / "blades.stl");
  EXPECT_TRUE(consistently_oriented(blades));
  const auto parts = shells(blades);
  const int n = (*options_)["blades"];
  ASSERT_EQ(parts.size(), static_cast<size_t>((*options_)["splitters"] ? 2 * n : n));
  for (const auto& p : parts) {
    EXPECT_TRUE(consistently_oriented(p));
    EXPECT_GT(signed_volume(p), 100.0);  // a blade is several hundred mm^3
  }
  EXPECT_TRUE(tf::is_closed(scene_->check_surfaces[0]));
}

TEST_F(BundledImpeller, PathRowsLieOnTheAnalyticHubOffsetByTheBallRadius) {
  const HubEllipse e = hub_formula();
  const auto hub_mesh = fcl_model(scene_->design);
  const double R = scene_->tool.radius(), tol = (*options_)["tolerance"], step = (*options_)["step"];
  double worst_surface = 0, worst_normal = 0, worst_mesh = 0, worst_step = 0;
  for (size_t i = 0; i < scene_->path.rows.size(); ++i) {
    const auto& row = scene_->path.rows[i];
    const Eigen::Vector3d c = row.p - R * row.n;
    const Eigen::Vector2d q(std::hypot(c.x(), c.y()), c.z());
    const double phi = e.nearest_phi(q);
    worst_surface = std::max(worst_surface, (e.at(phi) - q).norm());
    const Eigen::Vector2d n2 = e.normal(phi);
    const Eigen::Vector3d n(n2.x() * c.x() / q.x(), n2.x() * c.y() / q.x(), n2.y());
    worst_normal = std::max(worst_normal, (n - row.n).norm());
    if (i % 7 == 0) worst_mesh = std::max(worst_mesh, sphere_distance(hub_mesh, c, 1e-4) + 1e-4);
    if (i > 0) worst_step = std::max(worst_step, (row.p - scene_->path.rows[i - 1].p).norm());
  }
  std::cout << "path: worst off-surface " << worst_surface << " mm, normal error " << worst_normal
            << ", contact to hub mesh " << worst_mesh << " mm\n";
  EXPECT_LE(worst_surface, 1e-6);
  EXPECT_LE(worst_normal, 1e-6);
  EXPECT_LE(worst_mesh, tol + 1e-5);
  EXPECT_LE(worst_step, step * 1.001);
  EXPECT_GT(worst_step, step * 0.8);
}

TEST_F(BundledImpeller, BallIsClearButTheNominalAxisMeetsTheBlades) {
  const auto blades = fcl_model(scene_->check_surfaces[0]);
  const tf::Tool& tool = scene_->tool;
  const double R = tool.radius(), rc = R - 0.05;
  int hits = 0, tested = 0, touching = 0;
  for (size_t i = 0; i < scene_->path.rows.size(); ++i) {
    const auto& row = scene_->path.rows[i];
    // The ball grown by the promised clearance (less FCL's tolerance) touches no blade.
    touching += sphere_collides(blades, row.p, R + static_cast<double>((*options_)["ball_clearance"]) - 1e-4);
    if (i % 3) continue;
    // A capsule inside the flutes and shank, from the ball centre up to the shank's top.
    const Eigen::Vector3d top = row.p + (tool.length - tool.cl_height() - rc) * row.n;
    hits += capsule_collides(blades, row.p, top, rc);
    ++tested;
  }
  std::cout << "nominal axis meets the blades on " << hits << " of " << tested << " tested rows\n";
  EXPECT_EQ(touching, 0);
  EXPECT_GT(hits, tested / 20);
  EXPECT_LT(hits, tested);
  // ... and the clearance is tight somewhere: the outer passes run close to the blades.
  double least = 1e9;
  for (size_t i = 0; i < scene_->path.rows.size(); i += 5) least = std::min(least, sphere_distance(blades, scene_->path.rows[i].p, R));
  std::cout << "least ball clearance (every 5th row) " << least << " mm\n";
  EXPECT_LT(least, static_cast<double>((*options_)["ball_clearance"]) + 0.3);
}

TEST(SceneCli, PocketLoadsBackWithAnOverhangTheNominalAxisMeets) {
  TempDir d("pocket_cli");
  const RunResult r = run_tiltfield("--quiet scene pocket -o '" + (d.path / "p").string() + "'", d.path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());  // --quiet
  const tf::Scene s = tf::load_scene(d.path / "p" / "scene.json");
  EXPECT_TRUE(tf::is_closed(s.design));
  EXPECT_GT(tf::signed_volume(s.design), 0);
  ASSERT_EQ(s.check_surfaces.size(), 2u);
  for (const auto& w : s.check_surfaces) {
    EXPECT_TRUE(tf::is_closed(w));
    EXPECT_GT(tf::signed_volume(w), 0);
  }
  EXPECT_EQ(s.stock.kind, tf::Stock::Kind::Box);
  EXPECT_NEAR(s.stock.box.max.z(), 0.5, 1e-12);
  ASSERT_TRUE(s.machine.has_value());
  EXPECT_EQ(s.machine->kinematics, tf::KinematicsType::TableTableBC);
  const double R = s.tool.radius();
  const auto vertical = fcl_model(s.check_surfaces[0]);
  const auto overhang = fcl_model(s.check_surfaces[1]);
  int hits_overhang = 0, hits_vertical = 0;
  double least = 1e9;
  for (const auto& row : s.path.rows) {
    EXPECT_NEAR(row.p.z(), R, 1e-9);
    EXPECT_NEAR(row.n.z(), 1.0, 1e-12);
    least = std::min({least, sphere_distance(vertical, row.p, R), sphere_distance(overhang, row.p, R)});
    const Eigen::Vector3d top = row.p + (s.tool.length - R - (R - 0.05)) * row.n;
    hits_overhang += capsule_collides(overhang, row.p, top, R - 0.05);
    hits_vertical += capsule_collides(vertical, row.p, top, R - 0.05);
  }
  EXPECT_GE(least, 0.2 - 1e-4);
  EXPECT_GT(hits_overhang, 0);
  EXPECT_LT(hits_overhang, static_cast<int>(s.path.rows.size()));
  EXPECT_EQ(hits_vertical, 0);
}

// A ball kept closer to the walls than the planner's default 1 mm: the scene's safety distance follows
// it, so that the planner can clear the rows (with 1 mm it failed all 324 rows by the wall).
TEST(SceneCli, SafetyDistanceIsNoMoreThanTheBallClearance) {
  TempDir d("pocket_safety");
  const std::string dir = (d.path / "p").string();
  ASSERT_EQ(run_tiltfield("--quiet scene pocket --ball-clearance 0.5 -o '" + dir + "'", d.path).exit_code, 0);
  const tf::Scene s = tf::load_scene(d.path / "p" / "scene.json");
  EXPECT_DOUBLE_EQ(s.planner.safety_distance, 0.5);
  const RunResult r = run_tiltfield("--quiet plan '" + dir + "/scene.json' -o '" + dir + "/o.csv'", d.path);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(run_tiltfield("--quiet scene pocket -o '" + dir + "2'", d.path).exit_code, 0);
  EXPECT_DOUBLE_EQ(tf::load_scene(d.path / "p2" / "scene.json").planner.safety_distance, 1.0);
}

TEST(SceneCli, BlockLoadsBackAsAThreeAxisFacingScene) {
  TempDir d("block_cli");
  const RunResult r = run_tiltfield("scene block -o '" + (d.path / "b").string() + "'", d.path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const tf::Scene s = tf::load_scene(d.path / "b" / "scene.json");
  EXPECT_TRUE(tf::is_closed(s.design));
  const auto box = tf::bounding_box(s.design);
  EXPECT_TRUE(box.min().isZero(1e-6));
  EXPECT_TRUE(box.max().isApprox(Eigen::Vector3d(60, 40, 19), 1e-6));
  EXPECT_NEAR(tf::signed_volume(s.design), 60.0 * 40 * 19, 1e-3);
  EXPECT_TRUE(s.check_surfaces.empty());
  EXPECT_EQ(s.stock.kind, tf::Stock::Kind::Box);
  EXPECT_TRUE(s.stock.box.max.isApprox(Eigen::Vector3d(60, 40, 20)));
  EXPECT_EQ(s.tool.type_name(), "flat");
  EXPECT_DOUBLE_EQ(s.tool.radius(), 4.0);
  EXPECT_DOUBLE_EQ(s.tool.cl_height(), 0.0);
  ASSERT_TRUE(s.machine.has_value());
  EXPECT_EQ(s.machine->kinematics, tf::KinematicsType::XYZ);
  double ymin = 1e9, ymax = -1e9, xmin = 1e9, xmax = -1e9;
  for (const auto& row : s.path.rows) {
    EXPECT_NEAR(row.p.z(), 19.0, 1e-9);
    EXPECT_NEAR(row.n.z(), 1.0, 1e-12);
    ymin = std::min(ymin, row.p.y()), ymax = std::max(ymax, row.p.y());
    xmin = std::min(xmin, row.p.x()), xmax = std::max(xmax, row.p.x());
  }
  // The flat end covers the whole top: centres from y = 0 to 40 and beyond both ends in x.
  EXPECT_NEAR(ymin, 0.0, 1e-9);
  EXPECT_NEAR(ymax, 40.0, 1e-9);
  EXPECT_LT(xmin, -4.0);
  EXPECT_GT(xmax, 64.0);
}

// One pass down the middle of a two-blade channel lies farther from the blades than any bound on the
// search: its clearance is measured, not infinite (black-box testing: "fixed(): non-finite number").
TEST(SceneCli, OnePassInAWideChannelReportsItsClearance) {
  TempDir d("wide_channel");
  const RunResult r = run_tiltfield("scene impeller --blades 2 --passes 1 -o '" + (d.path / "imp").string() + "'", d.path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NO_THROW(tf::load_scene(d.path / "imp" / "scene.json"));
  std::ifstream in(d.path / "imp" / "scene.json");
  const double clearance = nlohmann::json::parse(in)["generator"]["facts"]["min_ball_clearance_mm"].get<double>();
  EXPECT_GT(clearance, 10.0);
  EXPECT_LT(clearance, 1000.0);
}

TEST(SceneCli, BadOptionsExitTwoWithOneLineNamingTheOption) {
  TempDir d("bad_options");
  struct Case {
    std::string args, option;
  };
  const std::vector<Case> cases = {
      {"scene impeller --blades 1", "--blades"},
      {"scene impeller --tool-radius -1", "--tool-radius"},
      {"scene impeller --passes 0", "--passes"},
      {"scene impeller --lean 60", "--lean"},
      {"scene impeller --tool-radius 12", "--tool-radius"},  // no room in the channel
      {"scene pocket --overhang 70", "--overhang"},
      {"scene pocket --passes 0", "--passes"},
      {"scene block --depth 25", "--depth"},
      {"scene block --stepover 0", "--stepover"},
      {"scene impeller --blades seven", "--blades"},
      // Sizes out of range: 1e308 had written infinite vertices with exit 0, and a pocket's meshes before
      // failing; 1e-300 degenerate meshes; thick blades or low ones had run for minutes (black-box testing).
      {"scene block --size-x 1e308", "--size-x"},
      {"scene block --size-x 1e-300", "--size-x"},
      {"scene block --stepover 1e-300", "--stepover"},
      {"scene block --stepover 0.01 --step 0.01", "--stepover"},  // 28 million rows
      {"scene pocket --width 1e308", "--width"},
      {"scene pocket --tool-radius 1e-300", "--tool-radius"},
      {"scene impeller --thickness-hub 100", "--thickness-hub"},
      {"scene impeller --thickness-tip 1e308", "--thickness-tip"},
      {"scene impeller --inlet-height 1e-6", "--inlet-height"},
      {"scene impeller --outlet-radius 1e308", "--outlet-radius"},
  };
  for (const auto& c : cases) {
    const fs::path out = d.path / "out";
    const RunResult r = run_tiltfield(c.args + " -o '" + out.string() + "'", d.path);
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.option), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args << ": nothing written";
  }
}

TEST(SceneCli, BundledMachineFilesMatchTheBuiltInOnes) {
  for (const char* name : {"table-table-ac", "table-table-bc", "xyz"}) {
    const fs::path file = fs::path(TILTFIELD_SOURCE_DIR) / "scenes" / "machines" / (std::string(name) + ".json");
    std::ifstream in(file);
    ASSERT_TRUE(in) << file;
    EXPECT_EQ(nlohmann::json::parse(in), tf::scenes::builtin_machine(name)) << file;
    const tf::MachineSpec m = tf::read_machine_json(file);
    EXPECT_EQ(tf::to_string(m.kinematics), name);
    EXPECT_EQ(m.output, tf::OutputMode::Joint);
  }
}

TEST(SceneCli, UserMachineFileIsCopiedIntoTheScene) {
  TempDir d("user_machine");
  const fs::path machine = fs::path(TILTFIELD_SOURCE_DIR) / "scenes" / "machines" / "table-table-bc.json";
  const RunResult r = run_tiltfield("--quiet scene block --machine '" + machine.string() + "' -o '" +
                                        (d.path / "b").string() + "'",
                                    d.path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(tf::load_scene(d.path / "b" / "scene.json").machine->kinematics, tf::KinematicsType::TableTableBC);
  const RunResult bad = run_tiltfield("scene block --machine '" + (d.path / "none.json").string() + "' -o '" +
                                          (d.path / "c").string() + "'",
                                      d.path);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("none.json"), std::string::npos);
}

// A preview named as a file of the scene (scene.json, the block's STL, path.csv, also through ".."), or as
// the output folder itself, is refused before anything is written; one inside the folder -o creates is
// written (black-box testing: the first replaced scene.json with the picture and exited 0, the folder
// was refused only after the whole scene had been written, and a new folder's preview was refused).
TEST(SceneCli, APreviewNeverReplacesAFileOfTheScene) {
  TempDir d("preview_names");
  fs::create_directories(d.path / "a");
  // "-o OUT --preview PREVIEW" with both inside the scratch folder (built by appending: GCC 12 warns
  // falsely on a literal + a string here).
  const auto args_for = [&](const std::string& out, const std::string& preview) {
    std::string a = "-o '";
    a += d.path.string();
    a += '/';
    a += out;
    a += "' --preview '";
    a += d.path.string();
    a += '/';
    a += preview;
    a += '\'';
    return a;
  };
  for (const std::string& args : {args_for("a", "a/scene.json"), args_for("a", "a/block.stl"), args_for("b", "b"),
                                  args_for("c", "./c/../c/path.csv"), args_for("e", "e/")}) {
    SCOPED_TRACE(args);
    const RunResult r = run_tiltfield(std::string("scene block ").append(args), d.path);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--preview"), std::string::npos) << r.err;
  }
  EXPECT_TRUE(fs::is_empty(d.path / "a"));
  for (const char* folder : {"b", "c", "e"}) EXPECT_FALSE(fs::exists(d.path / folder)) << folder;
  const RunResult ok = run_tiltfield(std::string("--quiet scene block ").append(args_for("d/", "d/preview.svg")), d.path);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(fs::exists(d.path / "d" / "preview.svg"));
  EXPECT_NO_THROW(tf::load_scene(d.path / "d" / "scene.json"));
}

}  // namespace
