// Other impeller parameters (blade counts, leans, splitters) still give valid scenes whose nominal tool
// axis meets the blades while the ball stays clear; option checks name the option.
#include <gtest/gtest.h>

#include <iostream>

#include "scenes/scene_impeller.hpp"
#include "scene_test_util.hpp"
#include "tiltfield/core/error.hpp"

using namespace scene_test;

namespace {

struct Variant {
  const char* name;
  int blades;
  double lean;
  bool splitters;
};

void PrintTo(const Variant& v, std::ostream* os) { *os << v.name; }

class ImpellerVariant : public ::testing::TestWithParam<Variant> {};

TEST_P(ImpellerVariant, IsValidAndTheNominalAxisCollides) {
  const Variant v = GetParam();
  tf::scenes::ImpellerOptions o;
  o.blades = v.blades;
  o.lean_deg = v.lean;
  o.splitters = v.splitters;
  // Coarse meshes keep the test fast (also under the sanitizers); the default tolerances are tested on the
  // bundled scene and on a blade of its own below.
  o.tolerance = 0.02;
  o.blade_tolerance = 0.05;
  o.stock_tolerance = 0.05;
  const auto scene = tf::scenes::make_impeller_scene(o, tf::scenes::builtin_machine("table-table-ac"));

  EXPECT_TRUE(tf::is_closed(scene.design.mesh));
  EXPECT_GT(tf::signed_volume(scene.design.mesh), 0);
  ASSERT_TRUE(scene.stock_mesh.has_value());
  EXPECT_GT(tf::signed_volume(scene.stock_mesh->mesh), tf::signed_volume(scene.design.mesh));
  const tf::Mesh& blades_mesh = scene.check_surfaces.at(0).mesh;
  const auto parts = shells(to_soup(blades_mesh));
  EXPECT_EQ(parts.size(), static_cast<size_t>(v.splitters ? 2 * v.blades : v.blades));
  for (const auto& p : parts) {
    EXPECT_TRUE(consistently_oriented(p));
    EXPECT_GT(signed_volume(p), 0);
  }

  const HubEllipse e;
  const auto blades = fcl_model(blades_mesh);
  const tf::Tool& tool = scene.tool;
  const double R = tool.radius(), rc = R - 0.05;
  int hits = 0, tested = 0, touching = 0;
  double off_surface = 0;
  ASSERT_GT(scene.path.rows.size(), 200u);
  for (size_t i = 0; i < scene.path.rows.size(); ++i) {
    const auto& row = scene.path.rows[i];
    off_surface = std::max(off_surface, e.distance(row.p - R * row.n));
    touching += sphere_collides(blades, row.p, R + 0.2 - 1e-4);
    if (i % 4) continue;
    hits += capsule_collides(blades, row.p, row.p + (tool.length - R - rc) * row.n, rc);
    ++tested;
  }
  EXPECT_LE(off_surface, 1e-9);
  EXPECT_EQ(touching, 0);
  EXPECT_GT(hits, 0);
  EXPECT_LT(hits, tested);
}

INSTANTIATE_TEST_SUITE_P(Impeller, ImpellerVariant,
                         ::testing::Values(Variant{"blades5", 5, 15, false}, Variant{"blades9", 9, 15, false},
                                           Variant{"lean0", 7, 0, false}, Variant{"lean25", 7, 25, false},
                                           Variant{"splitters", 7, 15, true},
                                           Variant{"splitters_lean0", 6, 0, true}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(ImpellerOptions, OutOfRangeOptionsNameTheOption) {
  auto field_of = [](auto change) {
    tf::scenes::ImpellerOptions o;
    change(o);
    try {
      tf::scenes::validate_impeller_options(o);
    } catch (const tf::InputError& e) {
      return e.field();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(field_of([](auto& o) { o.blades = 1; }), "--blades");
  EXPECT_EQ(field_of([](auto& o) { o.tool_radius = -1; }), "--tool-radius");
  EXPECT_EQ(field_of([](auto& o) { o.passes = 0; }), "--passes");
  EXPECT_EQ(field_of([](auto& o) { o.inlet_height = 45; }), "--inlet-height");
  EXPECT_EQ(field_of([](auto& o) { o.nose_z = 30; }), "--nose-z");
  EXPECT_EQ(field_of([](auto& o) { o.m_end = 0.01; }), "--m-end");
  EXPECT_EQ(field_of([](auto& o) { o.step = std::nan(""); }), "--step");
  EXPECT_EQ(field_of([](auto&) {}), "(accepted)");
}

// The finest documented step: about forty rows to a knot of the channel's edges. Their shortfalls had
// added up and thrown the edges about until the generator gave up ("could not keep the ball clear",
// black-box testing at 0.010-0.013 mm); each knot now moves by the largest.
TEST(ImpellerOptions, TheFinestStepKeepsTheBallClear) {
  tf::scenes::ImpellerOptions o;
  o.step = 0.01;
  o.passes = 3;  // the rows along a pass are what add up; three passes keep the test short
  o.tolerance = 0.02;
  o.blade_tolerance = 0.05;
  o.stock_tolerance = 0.05;
  const auto scene = tf::scenes::make_impeller_scene(o, tf::scenes::builtin_machine("table-table-ac"));
  const auto blades = fcl_model(scene.check_surfaces.at(0).mesh);
  const double R = scene.tool.radius();
  ASSERT_GT(scene.path.rows.size(), 15000u);
  int touching = 0;
  double worst_step = 0;
  for (size_t i = 0; i < scene.path.rows.size(); ++i) {
    const auto& row = scene.path.rows[i];
    if (i % 8 == 0) touching += sphere_collides(blades, row.p, R + o.ball_clearance - 1e-4);
    if (i > 0) worst_step = std::max(worst_step, (row.p - scene.path.rows[i - 1].p).norm());
  }
  EXPECT_EQ(touching, 0);
  EXPECT_LE(worst_step, o.step * 1.001);
}

TEST(ImpellerModel, HubNormalIsTheUnitOutwardNormalOfTheMeridian) {
  const tf::scenes::ImpellerModel model{tf::scenes::ImpellerOptions{}};
  for (double m : {0.0, 0.2, 0.5, 0.9, 1.0}) {
    const Eigen::Vector2d t = model.hub_tangent_rz(m), n = model.hub_normal_rz(m);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_NEAR(n.dot(t), 0.0, 1e-9);
    // Outward: away from the hub's axis-side interior, i.e. toward +r and +z.
    EXPECT_GE(n.x(), -1e-12);
    EXPECT_GE(n.y(), -1e-12);
  }
  EXPECT_TRUE(model.hub_rz(0).isApprox(Eigen::Vector2d(20, 40)));
  EXPECT_TRUE(model.hub_rz(1).isApprox(Eigen::Vector2d(60, 8)));
  // The blade's span runs along the hub normal at the inlet and the outlet.
  EXPECT_TRUE((model.camber_rz(0, 1) - model.camber_rz(0, 0)).normalized().isApprox(model.hub_normal_rz(0), 1e-12));
  EXPECT_TRUE((model.camber_rz(1, 1) - model.camber_rz(1, 0)).normalized().isApprox(model.hub_normal_rz(1), 1e-12));
  EXPECT_NEAR(model.span_length(0), 25.0, 1e-12);
  EXPECT_NEAR(model.span_length(1), 12.0, 1e-12);
}

TEST(ImpellerModel, BladeMeshFollowsTheAnalyticFacesWithinTheTolerance) {
  tf::scenes::ImpellerOptions o;
  o.splitters = true;
  o.lean_deg = 25;  // more twist
  const tf::scenes::ImpellerModel model(o);
  for (int blade : {0, o.blades}) {  // a main blade and a splitter
    const auto mesh = fcl_model(tf::scenes::impeller_blade_mesh(model, blade));
    const double m0 = model.blade_m_start(blade);
    double worst = 0;
    // Analytic face points on a grid that does not line up with the mesh's vertices.
    for (int side : {1, -1})
      for (int i = 0; i <= 120; ++i)
        for (int j = 0; j <= 12; ++j) {
          const double m = m0 + (1.0 - m0) * (i + 0.37) / 121.0, sigma = (j + 0.41) / 13.0;
          const Eigen::Vector3d p = model.face_point(blade, side, m, sigma);
          const double d = sphere_distance(mesh, p, 1e-5) + 1e-5;
          worst = std::max(worst, d);
        }
    std::cout << "blade " << blade << ": analytic face points within " << worst << " mm of the mesh\n";
    EXPECT_LE(worst, o.blade_tolerance) << "blade " << blade;
  }
}

}  // namespace
