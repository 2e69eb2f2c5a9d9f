// The planner keeps a flat or bull end out of the design surface: on a concave trough a level end face
// digs in by the curvature, and the planner leans it. Checked against the trough's closed form, not the
// planner's own measure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "synthetic.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/tilt/plan.hpp"

namespace tf {
namespace {

constexpr double kRho = 30.0;  // the trough: the cylinder of this radius about the line y = 0, z = kRho
// The mesh reaches beyond every end the passes place (the closed form below has no edge).
constexpr double kHalfWidth = 20.0, kLength = 60.0;

double trough_z(double y) { return kRho - std::sqrt(kRho * kRho - y * y); }
Eigen::Vector3d trough_normal(double y) { return Eigen::Vector3d(0, -y, kRho - trough_z(y)) / kRho; }

// The trough's surface alone (open), facing up, 0.25 mm across the curvature and 2 mm along it, from
// y = -kHalfWidth to y_edge; with `wall`, a side face down from its edge at y_edge (facing +y).
Mesh trough_mesh(double y_edge = kHalfWidth, bool wall = false) {
  const int ny = static_cast<int>(std::round((y_edge + kHalfWidth) / 0.25)), nx = static_cast<int>(kLength / 2.0);
  const int rows = wall ? ny + 2 : ny + 1;  // the wall's foot as one more row of vertices
  Eigen::MatrixX3d V((nx + 1) * rows, 3);
  Eigen::MatrixX3i F(2 * nx * (rows - 1), 3);
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      const double y = -kHalfWidth + (y_edge + kHalfWidth) * j / ny;
      V.row(i * rows + j) << kLength * i / nx, y, trough_z(y);
    }
    if (wall) V.row(i * rows + ny + 1) << kLength * i / nx, y_edge, -5.0;
  }
  int f = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j + 1 < rows; ++j) {
      const int a = i * rows + j, b = a + rows;
      F.row(f++) << a, b, b + 1;
      F.row(f++) << a, b + 1, a + 1;
    }
  return mesh_from_arrays(V, F);
}

// A pass across the trough at x (the feed along the curvature) and one along it at y (the curvature
// across the feed); row points are the contact plus the corner radius along the normal.
ToolPath trough_passes(double corner) {
  ToolPath p;
  auto add = [&](double x, double y) {
    const Eigen::Vector3d n = trough_normal(y);
    p.rows.push_back({Eigen::Vector3d(x, y, trough_z(y)) + corner * n, n});
  };
  for (int k = 0; k <= 100; ++k) add(20.0, -10.0 + 20.0 * k / 100);
  for (int k = 0; k <= 100; ++k) add(10.0 + 40.0 * k / 100, -6.0);
  return p;
}

Tool end_mill(double corner) {
  Tool t = test::test_tool();
  if (corner > 0)
    t.cutter = BullCutter{3.0, corner};
  else
    t.cutter = FlatCutter{3.0};
  return t;
}

// The deepest point of the end form below the trough, by its closed form (mm): the end's face and
// corner sampled every 1 deg around and 0.05 mm across.
double deepest_dip(const OrientedPath& path, const Tool& tool, double y_edge = kHalfWidth) {
  const double R = tool.radius(), r = tool.cl_height();
  double worst = 0;
  for (const OrientedRow& row : path.rows) {
    const Eigen::Vector3d a = row.axis.normalized(), tip = row_tip(row, tool);
    const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
    auto dip = [&](double rho, double h, double phi) {
      const Eigen::Vector3d x = tip + rho * (std::cos(phi) * e1 + std::sin(phi) * e2) + h * a;
      if (x.y() > y_edge) return 0.0;  // beside the part
      return std::hypot(x.y(), x.z() - kRho) - kRho;  // beyond the cylinder: in the material
    };
    for (int k = 0; k < 360; ++k) {
      const double phi = k * std::numbers::pi / 180;
      for (double rho = 0; rho <= R - r + 1e-9; rho += 0.05) worst = std::max(worst, dip(rho, 0, phi));
      for (double beta = 0; beta <= 0.5 * std::numbers::pi; beta += 0.05)
        worst = std::max(worst, dip(R - r + r * std::sin(beta), r - r * std::cos(beta), phi));
    }
  }
  return worst;
}

PlanResult plan_trough(const Tool& tool, const Mesh* design) {
  PlannerBasics basics;  // lead and tilt 0: the end face level on the surface
  PlanObstacles obstacles;
  if (design) obstacles.design = {design};
  const ToolPath path = trough_passes(tool.cl_height());
  return plan_path(path, tool, obstacles, basics, 1000, derive_plan_options(tool, basics, 1000));
}

TEST(EndForm, FlatAndBullEndsAreLeanedOutOfAConcaveSurface) {
  const Mesh trough = trough_mesh();
  for (double corner : {0.0, 1.0}) {
    SCOPED_TRACE(corner);
    const Tool tool = end_mill(corner);
    // Without the design the level end digs in (the case the lean is for).
    const PlanResult blind = plan_trough(tool, nullptr);
    EXPECT_GT(deepest_dip(blind.path, tool), 0.05);
    const PlanResult r = plan_trough(tool, &trough);
    EXPECT_LT(deepest_dip(r.path, tool), 0.005);
    EXPECT_GT(r.metrics.rows_lead_raised, 0u);
    EXPECT_EQ(r.metrics.rows_end_dipping, 0u);
    EXPECT_LT(r.metrics.max_end_dip_mm, 0.0021);
  }
}

// A pass along the design's boundary edge (the trough cut off at y = 6 by a side face): the contact lies
// as near the side face as the trough (nearer, rounded down a micrometre), and the nearest triangle had
// been the side face, 90 deg off the
// path's normal: the rows went unmeasured, and a flat end gouged the trough by 0.52 mm (black-box
// testing). The triangle that faces like the normal decides.
TEST(EndForm, APassAlongTheDesignsEdgeIsMeasured) {
  constexpr double kEdge = 6.0;
  const Mesh part = trough_mesh(kEdge, true);
  const Tool tool = end_mill(0.0);
  ToolPath path;
  // The contacts on the edge, a micrometre down (as rounded): on the side face, a hair from the trough.
  for (int k = 0; k <= 80; ++k)
    path.rows.push_back({Eigen::Vector3d(10.0 + 0.5 * k, kEdge, trough_z(kEdge) - 1e-6), trough_normal(kEdge)});
  PlannerBasics basics;
  PlanObstacles obstacles;
  obstacles.design = {&part};
  const PlanResult r = plan_path(path, tool, obstacles, basics, 1000, derive_plan_options(tool, basics, 1000));
  EXPECT_GT(r.metrics.rows_lead_raised, 0u);
  EXPECT_LT(deepest_dip(r.path, tool, kEdge), 0.005);
}

TEST(EndForm, ALevelEndOnAPlaneKeepsTheNominalAxis) {
  const Mesh plane = test::box_mesh({-10, -10, -5}, {70, 20, 0}, 5.0);
  const Tool tool = end_mill(0.0);
  const ToolPath path = test::polyline_path({{0, 0, 0}, {60, 10, 0}}, 0.5, {0, 0, 1});
  PlannerBasics basics;
  const PlanResult r = plan_path(path, tool, {{}, {}, {&plane}}, basics, 1000, derive_plan_options(tool, basics, 1000));
  EXPECT_EQ(r.metrics.rows_lead_raised, 0u);
  EXPECT_EQ(r.metrics.rows_end_turned, 0u);
  for (const OrientedRow& row : r.path.rows) EXPECT_NEAR(row.axis.normalized().z(), 1.0, 1e-12);
}

TEST(EndForm, ToleranceIsChecked) {
  const Tool tool = end_mill(0.0);
  PlannerBasics basics;
  EXPECT_THROW(parse_plan_options({{"end_dip_tolerance_mm", 0.0}}, "s.json", tool, basics, 1000), InputError);
  EXPECT_THROW(parse_plan_options({{"end_dip_tolerance_mm", 0.0005}}, "s.json", tool, basics, 1000), InputError);
  EXPECT_DOUBLE_EQ(parse_plan_options({{"end_dip_tolerance_mm", 0.01}}, "s.json", tool, basics, 1000).end_dip_tolerance_mm,
                   0.01);
}

}  // namespace
}  // namespace tf
