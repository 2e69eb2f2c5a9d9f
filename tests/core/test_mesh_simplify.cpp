// Decimation within a bound (decimate_within): both ways within the bound, measured with TriangleBvh's
// exact distances and against the closed form of the surface, not with the decimater's own figures.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "tiltfield/core/mesh_simplify.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace {

constexpr double kMajor = 20.0, kMinor = 5.0;

// A torus about z (major radius kMajor, tube kMinor), nu x nv quads split in two, faces outward.
tf::Mesh torus(int nu, int nv) {
  Eigen::MatrixX3d V(nu * nv, 3);
  Eigen::MatrixX3i F(2 * nu * nv, 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double a = 2.0 * std::numbers::pi * i / nu, b = 2.0 * std::numbers::pi * j / nv;
      V.row(i * nv + j) << (kMajor + kMinor * std::cos(b)) * std::cos(a), (kMajor + kMinor * std::cos(b)) * std::sin(a),
          kMinor * std::sin(b);
    }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int k = 2 * (i * nv + j);
      F.row(k) << id(i, j), id(i + 1, j), id(i + 1, j + 1);
      F.row(k + 1) << id(i, j), id(i + 1, j + 1), id(i, j + 1);
    }
  tf::Mesh m = tf::mesh_from_arrays(V, F);
  if (tf::signed_volume(m) < 0.0) {  // keep the faces outward whatever the parametrisation's handedness
    for (int k = 0; k < F.rows(); ++k) std::swap(F(k, 1), F(k, 2));
    m = tf::mesh_from_arrays(V, F);
  }
  return m;
}

double torus_distance(const Eigen::Vector3d& p) {
  return std::abs(std::hypot(std::hypot(p.x(), p.y()) - kMajor, p.z()) - kMinor);
}

struct Measured {
  double input_to_output = 0.0;   // largest distance of an input vertex to the output's triangles
  double output_to_input = 0.0;   // largest distance of 28 points per output face to the input's triangles
  double output_to_torus = 0.0;   // the same points to the closed-form torus
};

Measured measure(const tf::Mesh& input, const tf::Mesh& output) {
  Measured r;
  const tf::TriangleBvh out_bvh({&output}), in_bvh({&input});
  int hint = -1;
  for (auto v : input.vertices()) {
    const tf::ClosestHit h = out_bvh.closest(tf::to_eigen(input.point(v)), 1.0, hint);
    hint = h.triangle;
    r.input_to_output = std::max(r.input_to_output, h.triangle >= 0 ? h.distance : 1.0);
  }
  hint = -1;
  for (auto f : output.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (auto v : output.fv_range(f)) p[size_t(k++)] = tf::to_eigen(output.point(v));
    for (int i = 0; i <= 6; ++i)
      for (int j = 0; i + j <= 6; ++j) {
        const Eigen::Vector3d q = (i * p[0] + j * p[1] + (6 - i - j) * p[2]) / 6.0;
        const tf::ClosestHit h = in_bvh.closest(q, 1.0, hint);
        hint = h.triangle;
        r.output_to_input = std::max(r.output_to_input, h.triangle >= 0 ? h.distance : 1.0);
        r.output_to_torus = std::max(r.output_to_torus, torus_distance(q));
      }
  }
  return r;
}

TEST(MeshSimplify, TorusWithinTheBoundBothWays) {
  const tf::Mesh input = torus(400, 100);  // edges about 0.3 mm: the chords sag by at most 0.0025 mm
  tf::BoundedDecimateOptions o;
  o.max_error_mm = 0.01;
  const tf::BoundedDecimation d = tf::decimate_within(input, o);
  EXPECT_EQ(d.input_vertices, input.n_vertices());
  EXPECT_EQ(d.input_faces, input.n_faces());
  // The faces' samples must stay within half the bound: chords up to sqrt(8 r 0.005) across the tube, much
  // longer around it.
  EXPECT_LT(d.mesh.n_faces(), input.n_faces() / 2);
  EXPECT_GT(d.mesh.n_faces(), 100u);
  ASSERT_EQ(d.source_vertex.size(), d.mesh.n_vertices());
  for (auto v : d.mesh.vertices())
    EXPECT_EQ(d.mesh.point(v), input.point(tf::Mesh::VertexHandle(d.source_vertex[size_t(v.idx())])));
  const Measured m = measure(input, d.mesh);
  EXPECT_LE(m.input_to_output, 0.01 + 1e-9);
  EXPECT_LE(m.output_to_input, 0.01 + 1e-9);
  EXPECT_LE(m.output_to_torus, 0.01 + 0.0025);
  EXPECT_TRUE(tf::is_closed(d.mesh));
  const double volume = 2.0 * std::numbers::pi * std::numbers::pi * kMajor * kMinor * kMinor;
  EXPECT_NEAR(tf::signed_volume(d.mesh), volume, 0.01 * volume);  // outward faces, no fold
}

// An ellipsoid about z with semi-axes a, b, c: nu meridians, nv - 1 rings between the poles, faces outward.
tf::Mesh ellipsoid(double a, double b, double c, int nu, int nv) {
  Eigen::MatrixX3d V(nu * (nv - 1) + 2, 3);
  std::vector<Eigen::Vector3i> faces;
  const int south = nu * (nv - 1), north = south + 1;
  V.row(south) << 0.0, 0.0, -c;
  V.row(north) << 0.0, 0.0, c;
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double t = std::numbers::pi * j / nv - std::numbers::pi / 2, u = 2.0 * std::numbers::pi * i / nu;
      V.row((j - 1) * nu + i) << a * std::cos(t) * std::cos(u), b * std::cos(t) * std::sin(u), c * std::sin(t);
    }
  auto id = [&](int j, int i) { return (j - 1) * nu + (i + nu) % nu; };
  for (int i = 0; i < nu; ++i) {
    faces.emplace_back(south, id(1, i + 1), id(1, i));
    faces.emplace_back(north, id(nv - 1, i), id(nv - 1, i + 1));
    for (int j = 1; j + 1 < nv; ++j) {
      faces.emplace_back(id(j, i), id(j, i + 1), id(j + 1, i + 1));
      faces.emplace_back(id(j, i), id(j + 1, i + 1), id(j + 1, i));
    }
  }
  Eigen::MatrixX3i F(int(faces.size()), 3);
  for (size_t k = 0; k < faces.size(); ++k) F.row(int(k)) = faces[k].transpose();
  return tf::mesh_from_arrays(V, F);
}

// A plate thinner than the bound (an ellipsoid 4 x 0.8 mm across, 0.004 thick): every face inside it lies
// within the bound of the input, so only the vertices' test keeps the outline where it is.
TEST(MeshSimplify, ThinPlateKeepsItsOutline) {
  const tf::Mesh input = ellipsoid(2.0, 0.4, 0.002, 360, 90);
  ASSERT_GT(tf::signed_volume(input), 0.0);
  tf::BoundedDecimateOptions o;
  o.max_error_mm = 0.01;
  const tf::BoundedDecimation d = tf::decimate_within(input, o);
  EXPECT_LT(d.mesh.n_faces(), input.n_faces() / 2);
  const Measured m = measure(input, d.mesh);
  EXPECT_LE(m.input_to_output, 0.01 + 1e-9);
  EXPECT_LE(m.output_to_input, 0.01 + 1e-9);
}

TEST(MeshSimplify, SlabsJoinOnTheirLockedCutsAndKeepTheBound) {
  const tf::Mesh input = torus(200, 60);
  tf::BoundedDecimateOptions o;
  o.max_error_mm = 0.05;
  o.slabs = 3;
  double last = -1.0;
  int calls = 0;
  o.progress = [&](std::string_view stage, double f) {
    EXPECT_EQ(stage, "decimate");
    EXPECT_GE(f, last);
    last = f;
    ++calls;
  };
  const tf::BoundedDecimation d = tf::decimate_within(input, o);
  EXPECT_GT(calls, 0);
  EXPECT_DOUBLE_EQ(last, 1.0);
  EXPECT_LT(d.mesh.n_faces(), input.n_faces() / 2);
  EXPECT_TRUE(tf::is_closed(d.mesh)) << "the slabs meet on the same vertices";
  const Measured m = measure(input, d.mesh);
  EXPECT_LE(m.input_to_output, 0.05 + 1e-9);
  EXPECT_LE(m.output_to_input, 0.05 + 1e-9);
}

TEST(MeshSimplify, ZeroBoundCopiesAndColoursFollowTheirVertices) {
  tf::Mesh input = torus(120, 40);
  input.request_vertex_colors();
  std::vector<double> dev(input.n_vertices());
  for (auto v : input.vertices()) {
    input.set_color(v, tf::Mesh::Color(static_cast<unsigned char>(v.idx() % 251), 7, static_cast<unsigned char>(v.idx() % 13)));
    dev[size_t(v.idx())] = 0.001 * v.idx();
  }
  tf::set_vertex_deviation(input, dev);
  tf::BoundedDecimateOptions o;
  o.max_error_mm = 0.0;
  const tf::BoundedDecimation same = tf::decimate_within(input, o);
  EXPECT_EQ(same.mesh.n_vertices(), input.n_vertices());
  EXPECT_EQ(same.mesh.n_faces(), input.n_faces());
  o.max_error_mm = 0.05;
  const tf::BoundedDecimation d = tf::decimate_within(input, o);
  ASSERT_TRUE(d.mesh.has_vertex_colors());
  EXPECT_LT(d.mesh.n_vertices(), input.n_vertices());
  const std::vector<double> kept = tf::vertex_deviation(d.mesh);
  ASSERT_EQ(kept.size(), d.mesh.n_vertices());
  EXPECT_EQ(tf::vertex_deviation(same.mesh), dev);
  for (auto v : d.mesh.vertices()) {
    EXPECT_EQ(d.mesh.color(v), input.color(tf::Mesh::VertexHandle(d.source_vertex[size_t(v.idx())])));
    EXPECT_EQ(kept[size_t(v.idx())], dev[size_t(d.source_vertex[size_t(v.idx())])]);
  }
  o.max_error_mm = std::nan("");
  EXPECT_THROW(tf::decimate_within(input, o), std::invalid_argument);
}

}  // namespace
