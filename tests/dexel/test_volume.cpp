// Removed volumes of analytic cuts, and the tri-dexel stock itself.
#include <gtest/gtest.h>

#include <numbers>

#include "helpers.hpp"
#include "moves.hpp"
#include "tiltfield/core/triangle_bvh.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {
namespace {

constexpr double kPi = std::numbers::pi;

// The largest difference in material length (mm) between the same ray of two stocks on one lattice.
double worst_ray_difference(const TriDexel& a, const TriDexel& b) {
  const Lattice& L = a.lattice();
  double worst = 0.0;
  for (int d = 0; d < 3; ++d)
    for (int iv = 0; iv < L.n[Lattice::v_axis(d)]; ++iv)
      for (int iu = 0; iu < L.n[Lattice::u_axis(d)]; ++iu) {
        double la = 0.0, lb = 0.0;
        for (const Interval& x : a.ray(d, iu, iv)) la += double(x.hi) - x.lo;
        for (const Interval& x : b.ray(d, iu, iv)) lb += double(x.hi) - x.lo;
        worst = std::max(worst, std::abs(la - lb));
      }
  return worst;
}

TEST(Volume, BoxAndCylinderStock) {
  Stock box;
  box.kind = Stock::Kind::Box;
  box.box = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 20, 5)};
  const TriDexel td = make_stock(box, lattice_for(Eigen::AlignedBox3d(box.box.min, box.box.max), 0.5, 1));
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(td.volume(d), 1000.0, 1e-3);
  Stock cyl;
  cyl.kind = Stock::Kind::Cylinder;
  cyl.cylinder = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1), 10.0, 20.0};
  const TriDexel tc = make_stock(cyl, lattice_for(Eigen::AlignedBox3d(Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(10, 10, 20)), 0.1, 1));
  EXPECT_NEAR(tc.volume(), kPi * 100 * 20, kPi * 100 * 20 * 0.002);
}

// Every k-th ray, as they are: the stock's mesh on the coarse lattice closes, its box within a coarse
// spacing of the true one, with a k-th of the fine mesh's faces squared (the re-planner's obstacle).
TEST(Volume, CoarsenedStockKeepsItsRaysAndCloses) {
  Stock box;
  box.kind = Stock::Kind::Box;
  box.box = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 20, 5)};
  const TriDexel fine = make_stock(box, lattice_for(Eigen::AlignedBox3d(box.box.min, box.box.max), 0.1, 1));
  const TriDexel coarse = coarsened(fine, 3);
  EXPECT_DOUBLE_EQ(coarse.lattice().h, 0.3);
  EXPECT_EQ(coarse.lattice().origin, fine.lattice().origin);
  for (int iv = 0; iv < coarse.lattice().n[2]; ++iv)  // grid 0: u along y, v along z
    for (int iu = 0; iu < coarse.lattice().n[1]; ++iu) {
      const bool inside = 3 * iu < fine.lattice().n[1] && 3 * iv < fine.lattice().n[2];
      const Dexel& c = coarse.ray(0, iu, iv);
      ASSERT_EQ(c.size(), inside ? fine.ray(0, 3 * iu, 3 * iv).size() : 0u);
      if (c.size() > 0) {
        EXPECT_EQ(c.begin()->lo, fine.ray(0, 3 * iu, 3 * iv).begin()->lo);
      }
    }
  StockMeshOptions mo;
  mo.colour_by_deviation = false;
  const Mesh m = reconstruct_stock(coarse, nullptr, mo), mf = reconstruct_stock(fine, nullptr, mo);
  EXPECT_TRUE(is_closed(m));
  Eigen::AlignedBox3d bounds;
  for (auto v : m.vertices()) bounds.extend(to_eigen(m.point(v)));
  EXPECT_LT((bounds.min() - box.box.min).cwiseAbs().maxCoeff(), 0.3);
  EXPECT_LT((bounds.max() - box.box.max).cwiseAbs().maxCoeff(), 0.3);
  EXPECT_LT(m.n_faces() * 6, mf.n_faces());
  EXPECT_THROW(coarsened(fine, 0), std::invalid_argument);
}

TEST(Volume, SphereMeshRebuiltFrom147Rays) {
  // The tri-dexel model's headline case (Lee): a sphere R = 10 on 3 x 7 x 7 rays. Rays at -8.57 .. 8.57 (spacing 20/7).
  const Mesh sphere = test::icosphere(10.0, 5);
  const Lattice L = lattice_for(Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-10), Eigen::Vector3d::Constant(10)), 20.0 / 7.0, 1);
  const TriDexel td = dexels_from_mesh(sphere, L);
  EXPECT_EQ(L.n[0], 9);  // 7 inside + 2 padding
  size_t inner = 0;
  double end_error = 0.0;
  for (int d = 0; d < 3; ++d)
    for (int iv = 1; iv < 8; ++iv)
      for (int iu = 1; iu < 8; ++iu) {
        ++inner;
        const Dexel& r = td.ray(d, iu, iv);
        for (const Interval& iv_ : r) {
          Eigen::Vector3d p = L.origin;
          p[Lattice::u_axis(d)] += L.h * iu;
          p[Lattice::v_axis(d)] += L.h * iv;
          for (double t : {double(iv_.lo), double(iv_.hi)}) {
            Eigen::Vector3d q = p;
            q[d] += t;
            end_error = std::max(end_error, std::abs(q.norm() - 10.0));
          }
        }
      }
  EXPECT_EQ(inner, 147u);
  EXPECT_LT(end_error, 0.01);  // the icosphere's own chordal error
  StockMeshOptions mo;
  mo.refine = 2;
  const Mesh m = reconstruct_stock(td, nullptr, mo);
  EXPECT_TRUE(is_closed(m));
  double vmax = 0.0, fmax = 0.0;
  for (auto v : m.vertices()) vmax = std::max(vmax, std::abs(to_eigen(m.point(v)).norm() - 10.0));
  for (auto f : m.faces()) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> P;
    for (auto v : m.fv_range(f)) P.push_back(to_eigen(m.point(v)));
    for (int i = 0; i < 3; ++i) {
      fmax = std::max(fmax, std::abs((0.5 * (P[i] + P[(i + 1) % 3])).norm() - 10.0));
      c += P[i] / 3.0;
    }
    fmax = std::max(fmax, std::abs(c.norm() - 10.0));
  }
  RecordProperty("sphere_vertex_error_mm", std::to_string(vmax));
  RecordProperty("sphere_face_error_mm", std::to_string(fmax));
  std::cout << "sphere R=10 at 147 rays: vertex error " << vmax << " mm, face error " << fmax << " mm, "
            << m.n_faces() << " faces\n";
  EXPECT_LE(std::max(vmax, fmax), 0.1);
}

TEST(Volume, BallEndSlot) {
  // Ball R = 5, centre on the top face z = 20, along x for 40 mm: half a capsule.
  const Scene s = test::box_scene({0, 0, 0}, {60, 40, 20}, test::ball_tool(5, 20, 5, 50, {{15, 30}}));
  const Program p = test::Moves().rapid({10, 20, 30}).line({.z = 15}, 500).line({.x = 50}, 1000).program();
  VerifyOptions o;
  o.resolution = 0.1;
  const VerifyResult r = verify_program(s, p, forward_xyz, o);
  const double expected = kPi * 25 * 40 / 2 + 2.0 / 3.0 * kPi * 125;
  EXPECT_NEAR(r.report.removed_volume_mm3, expected, expected * 0.005);
  EXPECT_TRUE(r.report.collisions.empty());
  ASSERT_EQ(r.report.per_block.size(), 3u);
  // The plunge takes the lower hemisphere; the feed move the half cylinder and the far quarter spheres
  // less the near ones already gone: the half cylinder exactly.
  EXPECT_NEAR(r.report.per_block[1].removed_mm3, 2.0 / 3.0 * kPi * 125, 2.0 / 3.0 * kPi * 125 * 0.005);
  EXPECT_NEAR(r.report.per_block[2].removed_mm3, kPi * 25 * 20, kPi * 25 * 20 * 0.005);
  EXPECT_NEAR(r.report.per_block[2].minutes, 40.0 / 1000.0, 1e-12);
  EXPECT_NEAR(r.report.stock_volume_start_mm3 - r.report.stock_volume_end_mm3, r.report.removed_volume_mm3, 1e-6 * expected + 0.01);
}

TEST(Volume, FlatEndSlot) {
  Tool t;
  t.cutter = FlatCutter{5};
  t.flute_length = 15;
  t.shank_radius = 5;
  t.length = 50;
  const Scene s = test::box_scene({0, 0, 0}, {60, 40, 20}, t);
  const Program p = test::Moves().rapid({10, 20, 30}).line({.z = 15}, 500).line({.x = 50}, 1000).program();
  VerifyOptions o;
  o.resolution = 0.1;
  const VerifyResult r = verify_program(s, p, forward_xyz, o);
  const double expected = (2 * 5 * 40 + kPi * 25) * 5;
  EXPECT_NEAR(r.report.removed_volume_mm3, expected, expected * 0.005);
  EXPECT_TRUE(r.report.collisions.empty());
}

TEST(Volume, BullEndPocketFloor) {
  // A bull tool plunged 3 mm into the top and moved 30 mm: the swept cross-section is the tool's
  // outline below the top face (a rectangle minus the two corner fillets) times the length, plus the
  // tool's solid of revolution below the top.
  const Scene s = test::box_scene({0, 0, 0}, {60, 40, 20}, test::bull_tool(5, 1, 15, 5, 50));
  const Program p = test::Moves().rapid({15, 20, 30}).line({.z = 17}, 500).line({.x = 45}, 1000).program();
  VerifyOptions o;
  o.resolution = 0.1;
  const VerifyResult r = verify_program(s, p, forward_xyz, o);
  const double fillet = (1.0 - kPi / 4.0);                 // area outside a quarter circle r = 1 in its square
  const double section = 10 * 3 - 2 * fillet;             // mm^2
  // Revolved body below the top: cylinder r = 5, h = 3 minus the corner ring (Pappus: area * 2 pi * centroid).
  const double xc = 4.0 + (1.0 - 2.0 / (3.0 * (4.0 - kPi)) * 1.0) * 1.0;  // centroid radius of the fillet region
  const double body = kPi * 25 * 3 - fillet * 2 * kPi * xc;
  const double expected = section * 30 + body;
  EXPECT_NEAR(r.report.removed_volume_mm3, expected, expected * 0.005);
}

// A tool axis tilting by 30 degrees about the tip (TCP block, tip fixed), flat end R = 5 with its tip
// 5 mm below the top. The removed volume is integrated independently on a fine point grid with exact
// membership: a point is swept when its angular window about the tip, half-width asin(w / rho) with
// w the chord half-width of the cylinder at its x, meets the axis' angular range.
TEST(Volume, FiveAxisTiltAboutTheTip) {
  Tool t;
  t.cutter = FlatCutter{5};
  t.flute_length = 15;
  t.shank_radius = 5;
  t.length = 60;
  const double alpha = 30.0 * kPi / 180.0;
  const Eigen::Vector3d P(30, 20, 15);
  const double top = 20;
  Scene s = test::box_scene({0, 0, 0}, {60, 40, top}, t);
  // Joint "A" tilts the axis about x: axis = (0, -sin A, cos A).
  const ForwardFn fwd = [](const Joints& j) {
    const double a = j.a * kPi / 180.0;
    return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d(0, -std::sin(a), std::cos(a))};
  };
  const Program p =
      test::Moves().tcp().rapid({30, 20, 40, 0}).line({.z = 15}, 500).inverse_time({.a = 30}, 10).program();
  VerifyOptions o;
  o.resolution = 0.1;
  o.sweep.tolerance = 0.02;
  const VerifyResult r = verify_program(s, p, fwd, o);
  // Independent integral (midpoint rule, 0.04 mm in y and z, 0.05 in x).
  double vol = 0.0;
  const double hx = 0.05, hyz = 0.04;
  for (double x = -5 + hx / 2; x < 5; x += hx) {
    const double w = std::sqrt(25 - x * x);
    for (double z = P.z() - 6 + hyz / 2; z < top; z += hyz)
      for (double y = P.y() - 12; y < P.y() + 6; y += hyz) {
        const double dy = y + hyz / 2 - P.y(), dz = z - P.z();
        const double rho = std::hypot(dy, dz);
        const double phi = std::atan2(-dy, dz);  // angle of the point from +z toward -y (the tilt direction)
        const double half = rho <= w ? kPi / 2 : std::asin(w / rho);
        if (phi + half >= 0.0 && phi - half <= alpha) vol += hx * hyz * hyz;
      }
  }
  EXPECT_EQ(r.report.per_block.back().substeps > 100, true);
  EXPECT_LE(r.report.sweep_error_mm, 0.02 + 1e-9);
  // The plunge block removed the tool's footprint at A = 0, part of the same union.
  EXPECT_NEAR(r.report.removed_volume_mm3, vol, vol * 0.005) << "independent " << vol;
  EXPECT_TRUE(r.report.collisions.empty());
  std::cout << "5-axis tilt: verifier " << r.report.removed_volume_mm3 << " mm3 (" << r.report.seconds << " s, " << r.report.per_block.back().substeps << " sub-steps), independent " << vol << " mm3\n";
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

TEST(Volume, StockMeshAfterCutsIsClosedAndMatchesTheDexels) {
  Scene s = test::box_scene({0, 0, 0}, {30, 20, 10}, test::ball_tool(3, 12, 3, 40, {}));
  s.design = test::box_mesh({-1, -1, -1}, {31, 21, 8});
  const Program p =
      test::Moves().rapid({5, 10, 20}).line({.z = 7}, 500).line({.x = 25}).line({.y = 15}).line({.x = 5}).program();
  VerifyOptions o;
  o.resolution = 0.25;
  const VerifyResult r = verify_program(s, p, forward_xyz, o);
  const Mesh m = reconstruct_stock(r.stock, &s.design);
  EXPECT_TRUE(is_closed(m));
  EXPECT_TRUE(m.has_vertex_colors());
  const double vol = signed_volume(m);
  EXPECT_NEAR(vol, r.report.stock_volume_end_mm3, r.report.stock_volume_end_mm3 * 0.01);
  // The cut floor (1 mm above the design at z = 7) and the top are green to red, not blue; the stock's
  // sides and bottom lie inside the (larger) design box and are blue.
  int blue_top = 0, blue_side = 0;
  for (auto v : m.vertices()) {
    const Eigen::Vector3d q = to_eigen(m.point(v));
    const bool blue = m.color(v)[2] > 128;
    if (q.z() > 6.5 && q.x() > 1 && q.x() < 29 && q.y() > 1 && q.y() < 19) blue_top += blue;
    if (q.z() < 0.1) blue_side += blue;
  }
  EXPECT_EQ(blue_top, 0);
  EXPECT_GT(blue_side, 0);
  // The deviation the colours came from stays on the mesh for the report: each vertex's distance to the
  // design, as core's own closest-point tree measures it (the colours' come from Embree).
  const std::vector<double> dev = vertex_deviation(m);
  ASSERT_EQ(dev.size(), m.n_vertices());
  const TriangleBvh design({&s.design});
  double worst = 0.0;
  for (auto v : m.vertices()) {
    const ClosestHit hit = design.closest(to_eigen(m.point(v)));
    worst = std::max(worst, std::abs(std::abs(dev[size_t(v.idx())]) - hit.distance));
  }
  EXPECT_LT(worst, 1e-9);
}

// The surface nets are built in chunks of lattice layers on the threads (8 or more here: 244 layers) and
// joined: every quad across a chunk's first layer must find the previous chunk's vertices. A slot down the
// whole height crosses every chunk's boundary; the mesh stays closed, of genus 0 (V - E + F = 2), and
// holds the dexels' volume.
TEST(Volume, TallStockMeshIsClosedAcrossTheBuildChunks) {
  const Scene s = test::box_scene({0, 0, 0}, {6, 6, 60}, test::ball_tool(1.5, 70, 1.5, 80, {}));
  const Program p = test::Moves().rapid({0, 3, 65}).line({.z = 5}, 500).program();
  VerifyOptions o;
  o.resolution = 0.25;
  const VerifyResult r = verify_program(s, p, forward_xyz, o);
  ASSERT_GE(r.stock.lattice().n[2], 240);
  StockMeshOptions mo;
  mo.colour_by_deviation = false;
  const Mesh m = reconstruct_stock(r.stock, nullptr, mo);
  EXPECT_TRUE(is_closed(m));
  EXPECT_EQ(int(m.n_vertices()) - int(m.n_edges()) + int(m.n_faces()), 2);
  EXPECT_NEAR(signed_volume(m), r.report.stock_volume_end_mm3, r.report.stock_volume_end_mm3 * 0.01);
  EXPECT_GT(r.report.removed_volume_mm3, 100.0);
}

}  // namespace
}  // namespace tf

namespace tf {
namespace {

// A path cut as two long moves and as 450 short ones (0.1 mm, sloped, round a corner) leaves the same
// stock: a short move starts where the previous left the ball, so the rays its sweep keeps inside the
// ball's start are skipped (nothing is left there), and that must not change what is cut.
TEST(Volume, ShortMovesCutWhatLongOnesCut) {
  const Scene s = test::box_scene({0, 0, 0}, {40, 30, 20}, test::ball_tool(3, 12, 3, 30, {{10, 30}}));
  const Eigen::Vector3d p0(-5, 10, 17.5), p1(20, 12, 16.5), p2(35, 25, 18.2);
  auto to = [](const Eigen::Vector3d& p) { return test::Axes{.x = p.x(), .y = p.y(), .z = p.z()}; };
  test::Moves long_moves, short_moves;
  long_moves.rapid(to(p0)).line(to(p1), 1000).line(to(p2));
  short_moves.rapid(to(p0));
  for (int k = 1; k <= 250; ++k) short_moves.line(to(p0 + (p1 - p0) * (k / 250.0)), 1000);
  for (int k = 1; k <= 200; ++k) short_moves.line(to(p1 + (p2 - p1) * (k / 200.0)));
  VerifyOptions o;
  o.resolution = 0.1;
  const VerifyResult a = verify_program(s, long_moves.program(), forward_xyz, o);
  const VerifyResult b = verify_program(s, short_moves.program(), forward_xyz, o);
  EXPECT_NEAR(b.report.removed_volume_mm3, a.report.removed_volume_mm3, 1e-6 * a.report.removed_volume_mm3);
  EXPECT_LT(worst_ray_difference(a.stock, b.stock), 1e-4) << "mm of material on one ray";
  EXPECT_GT(a.report.removed_volume_mm3, 500.0);
}

// A ball end 1 mm into a round bar while the bar turns four times about x (a 4th axis, A1440) and the
// tool feeds 40 mm along it: a helical groove. One block must cut what the same motion cut in sixteen
// quarter turns cuts; sampled only at its quarter points, the single block would look like a straight
// move along the bar.
TEST(Volume, FourTurnsOfATableInOneBlockCutTheHelix) {
  Scene s;
  s.stock.kind = Stock::Kind::Cylinder;
  s.stock.cylinder = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), 10.0, 50.0};
  s.tool = test::ball_tool(3, 4, 3, 30, {});
  const ForwardFn table_a = [](const Joints& j) {
    const Eigen::AngleAxisd part(-j.a * kPi / 180.0, Eigen::Vector3d::UnitX());
    return ToolPose{part * Eigen::Vector3d(j.x, j.y, j.z), part * Eigen::Vector3d::UnitZ()};
  };
  test::Moves one, quarters;
  one.rapid({.x = 5, .y = 0, .z = 20, .a = 0}).line({.z = 9}, 300).line({.x = 45, .a = 1440}, 1000);
  quarters.rapid({.x = 5, .y = 0, .z = 20, .a = 0}).line({.z = 9}, 300);
  for (int k = 1; k <= 16; ++k) quarters.line({.x = 5 + 40.0 * k / 16, .a = 90.0 * k}, 1000);
  VerifyOptions o;
  o.resolution = 0.1;
  o.sweep.tolerance = 0.05;  // the flutes' four turns within max_substeps
  const VerifyResult a = verify_program(s, one.program(), table_a, o);
  const VerifyResult b = verify_program(s, quarters.program(), table_a, o);
  EXPECT_GT(a.report.per_block.back().substeps, 16);
  EXPECT_LE(a.report.sweep_error_mm, o.sweep.tolerance);
  // The groove's cross-section is about the ball's cap 1 mm deep (4.7 mm^2) along a helix of about 255 mm.
  EXPECT_GT(b.report.removed_volume_mm3, 600.0);
  EXPECT_NEAR(a.report.removed_volume_mm3, b.report.removed_volume_mm3, 0.005 * b.report.removed_volume_mm3);
}

// A C table turning 4.25 turns in one block under a vertical ball: the tip runs round a circle, which
// five poses cannot tell from a quarter turn; the block must cut the whole ring, as the same turn split at
// 1440 degrees does (found in review: it cut a quarter ring, as an exact arc).
TEST(Volume, MoreThanFourTurnsOfACTableCutTheWholeRing) {
  const Scene s = test::box_scene({-20, -20, 0}, {20, 20, 10}, test::ball_tool(3, 12, 3, 50, {}));
  const ForwardFn table_c = [](const Joints& j) {
    const Eigen::AngleAxisd part(-j.c * kPi / 180.0, Eigen::Vector3d::UnitZ());
    return ToolPose{part * Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d::UnitZ()};
  };
  test::Moves one, split;
  one.rapid({.x = 15, .y = 0, .z = 20, .c = 0}).line({.z = 8}, 300).line({.c = 1530}, 5000);
  split.rapid({.x = 15, .y = 0, .z = 20, .c = 0}).line({.z = 8}, 300).line({.c = 1440}, 5000).line({.c = 1530}, 5000);
  VerifyOptions o;
  o.resolution = 0.2;
  const VerifyResult a = verify_program(s, one.program(), table_c, o);
  const VerifyResult b = verify_program(s, split.program(), table_c, o);
  // The ring: the ball's cap 2 mm deep swept round R 15.
  EXPECT_GT(b.report.removed_volume_mm3, 700.0);
  EXPECT_NEAR(a.report.removed_volume_mm3, b.report.removed_volume_mm3, 0.005 * b.report.removed_volume_mm3);
}

// A move of the rotaries alone under G94 takes D / F minutes with D = sqrt(dA^2 + dC^2) degrees, as
// RS274/NGC and LinuxCNC time it; their sum had made A30 C40 at F50 take 1.4 minutes for 1.0 (black-box
// testing), and its MRR read low by as much.
TEST(Volume, ARotaryOnlyMoveIsTimedByItsEuclideanTurn) {
  const Scene s = test::box_scene({-20, -20, 0}, {20, 20, 10}, test::ball_tool(3, 12, 3, 50, {}));
  const ForwardFn table_ac = [](const Joints& j) {
    const Eigen::Matrix3d part = (Eigen::AngleAxisd(-j.c * kPi / 180.0, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(-j.a * kPi / 180.0, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    return ToolPose{part * Eigen::Vector3d(j.x, j.y, j.z), part * Eigen::Vector3d::UnitZ()};
  };
  const Program p = test::Moves().rapid({0, 0, 30, 0, 0, 0}).line({.a = 30, .c = 40}, 50).program();
  VerifyOptions o;
  o.resolution = 0.5;
  const VerifyResult r = verify_program(s, p, table_ac, o);
  ASSERT_EQ(r.report.per_block.size(), 2u);
  EXPECT_NEAR(r.report.per_block[1].minutes, 1.0, 1e-12);
}

// A rotating 5-axis feed, then a rapid straight back up the tool's axis: the rapid's cutting parts start
// inside the pose the feed ended at, where nothing is left; a sub-step held at its middle axis left a
// sliver there (up to the sweep's bound) that the rapid reported as a collision (found in review).
TEST(Volume, ARapidFromWhereARotatingFeedEndedMeetsNothing) {
  Tool flat = test::bull_tool(3, 1, 11.3, 3, 50);
  flat.cutter = FlatCutter{3};
  const Scene s = test::box_scene({0, 0, 0}, {40, 20, 10}, flat);
  const ForwardFn fwd = [](const Joints& j) {
    const double a = j.a * kPi / 180.0;
    return ToolPose{Eigen::Vector3d(j.x, j.y, j.z), Eigen::Vector3d(0, std::sin(a), std::cos(a))};
  };
  const double a = 15 * kPi / 180.0;
  test::Moves m;
  m.tcp().rapid({.x = -10, .y = 5, .z = 30, .a = 0}).line({.z = 8}, 300).line({.x = 30, .a = 15}, 1000);
  m.rapid({.x = 30, .y = 5 + 20 * std::sin(a), .z = 8 + 20 * std::cos(a)});
  VerifyOptions o;
  o.resolution = 0.1;
  const VerifyResult r = verify_program(s, m.program(), fwd, o);
  EXPECT_GT(r.report.removed_volume_mm3, 100.0);
  EXPECT_TRUE(r.report.collisions.empty()) << r.report.collisions.front().depth_mm;
}

// Short 5-axis moves of a bull end whose axis leans 3 degrees and swings around the vertical: each block's
// rotation is below one sub-step, so the blocks after the first skip the rays their cutting spheres keep
// inside where the previous block left them. A check surface far from the path (inside the stock's box, so
// the lattice is the same) turns that skipping off; the stock must be the same either way.
TEST(Volume, SwingingBullEndCutsTheSameWithoutSkippingItsStart) {
  const Scene plain = test::box_scene({0, 0, 0}, {30, 30, 10}, test::bull_tool(3, 1, 6, 3, 30));
  Scene guarded = plain;
  guarded.check_surfaces.push_back(test::box_mesh({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}));
  const ForwardFn fwd = [](const Joints& j) {
    const double a = j.a * kPi / 180.0, c = j.c * kPi / 180.0;
    return ToolPose{Eigen::Vector3d(j.x, j.y, j.z),
                    Eigen::Vector3d(std::sin(a) * std::cos(c), std::sin(a) * std::sin(c), std::cos(a))};
  };
  test::Moves m;
  m.tcp().rapid({.x = 8, .y = 15, .z = 20, .a = 3, .c = 0}).line({.z = 8.5}, 300);
  for (int k = 1; k <= 240; ++k) m.line({.x = 8 + 14.0 * k / 240, .y = 15 + 2.0 * std::sin(k / 40.0), .c = 0.75 * k});
  VerifyOptions o;
  o.resolution = 0.1;
  o.sweep.tolerance = 0.05;
  const VerifyResult a = verify_program(plain, m.program(), fwd, o);
  const VerifyResult b = verify_program(guarded, m.program(), fwd, o);
  int single = 0;
  for (const BlockResult& br : a.report.per_block) single += br.substeps == 1;
  ASSERT_GT(single, 200) << "the blocks must be short enough to skip";
  ASSERT_EQ(a.stock.lattice().n, b.stock.lattice().n);
  EXPECT_LT(worst_ray_difference(a.stock, b.stock), 1e-5) << "mm of material on one ray";
  EXPECT_GT(a.report.removed_volume_mm3, 100.0);
}


}  // namespace
}  // namespace tf
