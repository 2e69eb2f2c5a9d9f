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

// A mesh from vertex rows and triangles.
Mesh mesh_of(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
  Eigen::MatrixX3d V(v.size(), 3);
  for (size_t k = 0; k < v.size(); ++k) V.row(k) = v[k];
  Eigen::MatrixX3i F(f.size(), 3);
  for (size_t k = 0; k < f.size(); ++k) F.row(k) = f[k];
  return mesh_from_arrays(V, F);
}

// A ring of vertices exactly on the plane: every edge ending there crosses at the vertex itself. One
// vertex a hair off the axis (x = -0.01, or -4e-15 as a sphere's cosines leave it) had its crossing
// interpolated to t = 1, a bit off, and the loop did not close (black-box testing).
TEST(OffsetSection, AVertexRingOnThePlaneCloses) {
  for (const double x : {-0.01, -3.6e-15, 0.0, 0.01}) {
    SCOPED_TRACE(x);
    const Mesh m = mesh_of({{0, 0, -20}, {14, 0, -14}, {0, 14, -14}, {-14, 0, -14}, {0, -14, -14}, {20, 0, 0}, {0, 20, 0},
                            {-20, 0, 0}, {x, -20, 0}, {0, 0, 20}},
                           {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6},
                            {3, 4, 8}, {3, 8, 7}, {4, 1, 5}, {4, 5, 8}, {5, 6, 9}, {6, 7, 9}, {7, 8, 9}, {8, 5, 9}});
    const auto loops = section_loops(m, 0.0);
    ASSERT_EQ(loops.size(), 1u);
    double area = 0;
    for (size_t i = 0; i < loops[0].size(); ++i) area += cross(loops[0][i], loops[0][(i + 1) % loops[0].size()]) / 2;
    EXPECT_NEAR(area, 800.0, 1e-9);  // the square (20,0) (0,20) (-20,0) (x,-20)
  }
}

// A tube's section is two loops: the profile is one (--loop picks it, by area), the other is listed with
// its place; a loop number beyond the section's is refused.
TEST(OffsetSection, ASectionsOtherLoopsAreListed) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  const int n = 120;
  for (const double r : {20.0, 17.0})
    for (const double z : {0.0, 20.0})
      for (int k = 0; k < n; ++k) v.emplace_back(r * std::cos(2 * M_PI * k / n), r * std::sin(2 * M_PI * k / n), z);
  auto at = [&](int ring, int k) { return ring * n + (k % n); };  // rings: outer bottom, outer top, inner bottom, inner top
  for (int k = 0; k < n; ++k) {
    f.emplace_back(at(0, k), at(0, k + 1), at(1, k + 1));  // outer wall, facing out
    f.emplace_back(at(0, k), at(1, k + 1), at(1, k));
    f.emplace_back(at(2, k), at(3, k + 1), at(2, k + 1));  // bore wall, facing in
    f.emplace_back(at(2, k), at(3, k), at(3, k + 1));
    f.emplace_back(at(1, k), at(1, k + 1), at(3, k + 1));  // top
    f.emplace_back(at(1, k), at(3, k + 1), at(3, k));
    f.emplace_back(at(0, k), at(2, k + 1), at(0, k + 1));  // bottom
    f.emplace_back(at(0, k), at(2, k), at(2, k + 1));
  }
  const auto stl = std::filesystem::path(write_temp("x", "")).parent_path() / "tube.stl";
  write_mesh(mesh_of(v, f), stl);
  std::vector<SectionLoop> left_out;
  const Profile outer = profile_from_mesh(stl, 10.0, {}, &left_out);
  EXPECT_GT(signed_area(outer.elements), 1200.0);
  ASSERT_EQ(left_out.size(), 1u);
  EXPECT_TRUE(left_out[0].inside);
  EXPECT_NEAR(left_out[0].area, 17 * 17 * n / 2.0 * std::sin(2 * M_PI / n), 1e-3);  // the mesh's floats
  SectionOptions bore;
  bore.loop = 2;
  left_out.clear();
  const Profile inner = profile_from_mesh(stl, 10.0, bore, &left_out);
  EXPECT_LT(signed_area(inner.elements), -800.0);  // clockwise: material outside it
  ASSERT_EQ(left_out.size(), 1u);
  EXPECT_FALSE(left_out[0].inside);
  bore.loop = 3;
  EXPECT_THROW(profile_from_mesh(stl, 10.0, bore), InputError);
  // The inside path of the outer loop at a gap of 2 runs 1 mm from the bore: refused, exit 1, no program.
  const auto ngc = stl.parent_path() / "tube.ngc";
  const std::string base = std::string(TILTFIELD_EXE) + " --quiet offset --mesh " + stl.string() + " --plane z=10 -o " + ngc.string();
  EXPECT_EQ(WEXITSTATUS(std::system((base + " -d 2 2>/dev/null").c_str())), 1);
  EXPECT_FALSE(std::filesystem::exists(ngc));
  EXPECT_EQ(WEXITSTATUS(std::system((base + " -d 2 --side outside").c_str())), 0);  // far from the bore
  EXPECT_EQ(WEXITSTATUS(std::system((base + " -d 1 --loop 2").c_str())), 0);        // in the bore
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
