// A profile from a part mesh: plane section, chaining and line/arc fitting within the tolerance.
#include "offset_test_util.hpp"
#include "tiltfield/offset/offset_section.hpp"

namespace tf::offset::test {
namespace {

// A prism over a D-shape (a half disc of radius 20 on a 40 x 15 rectangle), facets every 3 degrees.
Mesh d_prism(double height) {
  std::vector<Eigen::Vector2d> ring;
  ring.emplace_back(-20, -15);
  ring.emplace_back(20, -15);
  for (int k = 0; k <= 60; ++k) ring.emplace_back(20 * std::cos(M_PI * k / 60), 20 * std::sin(M_PI * k / 60));
  const int n = static_cast<int>(ring.size());
  Eigen::MatrixX3d V(2 * n + 2, 3);
  for (int k = 0; k < n; ++k) {
    V.row(k) << ring[k].x(), ring[k].y(), 0;
    V.row(n + k) << ring[k].x(), ring[k].y(), height;
  }
  V.row(2 * n) << 0, 0, 0;
  V.row(2 * n + 1) << 0, 0, height;
  std::vector<Eigen::Vector3i> F;
  for (int k = 0; k < n; ++k) {
    const int j = (k + 1) % n;
    F.emplace_back(k, j, n + j);
    F.emplace_back(k, n + j, n + k);
    F.emplace_back(2 * n, j, k);                  // bottom, facing -z
    F.emplace_back(2 * n + 1, n + k, n + j);      // top, facing +z
  }
  Eigen::MatrixX3i Fm(F.size(), 3);
  for (size_t k = 0; k < F.size(); ++k) Fm.row(k) = F[k];
  return mesh_from_arrays(V, Fm);
}

TEST(OffsetSection, SlicesChainsAndFitsLinesAndArcs) {
  const auto loops = section_loops(d_prism(10), 4.0);
  ASSERT_EQ(loops.size(), 1u);
  const Profile p = fit_profile(loops[0], 0.01, "prism");
  validate_profile(p);
  EXPECT_GT(signed_area(p.elements), 0);  // counter-clockwise around the material
  // Straight sides stay lines; the facetted half circle's corners lie on one circle: a few arcs at most.
  int arcs = 0;
  for (const auto& e : p.elements)
    if (e.is_arc()) {
      ++arcs;
      EXPECT_NEAR(e.r, 20.0, 1e-6);
    }
  EXPECT_GE(arcs, 1);
  EXPECT_LE(p.elements.size(), 8u);
  for (const auto& q : loops[0]) {
    double d = 1e9;
    for (const auto& e : p.elements) d = std::min(d, distance(e, q));
    EXPECT_LE(d, 0.01 + 1e-9);
  }
}

// A section of four corners (or three) lies on one circle: it is straight between them, so lines, not an
// arc through them (black-box testing: a box's top section had come out as an arc 28 mm off its sides).
TEST(OffsetSection, CornersOnOneCircleStayLines) {
  const std::vector<Eigen::Vector2d> box{{0, 0}, {100, 0}, {100, 60}, {0, 60}};
  const Profile p = fit_profile(box, 0.01, "box");
  validate_profile(p);
  EXPECT_NEAR(signed_area(p.elements), 6000.0, 1e-6);
  for (const auto& e : p.elements) EXPECT_FALSE(e.is_arc());
  const std::vector<Eigen::Vector2d> triangle{{0, 0}, {40, 0}, {0, 30}};
  EXPECT_NEAR(signed_area(fit_profile(triangle, 0.01, "triangle").elements), 600.0, 1e-6);
}

TEST(OffsetSection, CommandLineWithMesh) {
  const auto stl = std::filesystem::path(write_temp("x", "")).parent_path() / "prism.stl";
  write_mesh(d_prism(10), stl);
  const auto ngc = stl.parent_path() / "prism.ngc", prof = stl.parent_path() / "prism.txt";
  const std::string cmd = std::string(TILTFIELD_EXE) + " offset --mesh " + stl.string() + " --plane z=5 -d 2 -o " +
                          ngc.string() + " --profile-out " + prof.string();
  ASSERT_EQ(WEXITSTATUS(std::system(cmd.c_str())), 0);
  const Profile p = read_profile(prof);
  EXPECT_NEAR(std::abs(signed_area(p.elements)), 40 * 15 + M_PI * 400 / 2, 2.0);
  const std::string miss = std::string(TILTFIELD_EXE) + " offset --mesh " + stl.string() + " --plane z=50 -d 2 -o " +
                           ngc.string() + " 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(miss.c_str())), 2);
}

}  // namespace
}  // namespace tf::offset::test
