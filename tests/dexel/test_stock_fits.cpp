// The stock mesh's local fits (stock_surface.hpp): the smallest eigenvector by inverse iteration against
// Eigen's full decomposition, and spheres and planes through points against the closed forms they were
// sampled from.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>
#include <random>
#include <vector>

#include "stock_surface.hpp"

namespace tf::stock_mesh {
namespace {

using Mat5 = Eigen::Matrix<double, 5, 5>;
using Vec5 = Eigen::Matrix<double, 5, 1>;

// M = sum of a a^T with a = (1, q, |q|^2) over points q, its lower triangle only (as fit_points sums it).
Mat5 moment_matrix(const std::vector<Eigen::Vector3d>& points) {
  Mat5 full = Mat5::Zero();
  for (const Eigen::Vector3d& q : points) {
    Vec5 a;
    a << 1.0, q.x(), q.y(), q.z(), q.squaredNorm();
    full += a * a.transpose();
  }
  return full.triangularView<Eigen::Lower>();
}

double alignment(const Vec5& a, const Vec5& b) { return std::abs(a.normalized().dot(b.normalized())); }

// Points on a patch of a sphere of radius r about c, spread over `spread` radians around the pole p.
std::vector<Eigen::Vector3d> sphere_patch(const Eigen::Vector3d& c, double r, const Eigen::Vector3d& pole,
                                          double spread, int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-spread, spread);
  const Eigen::Vector3d p = pole.normalized();
  const Eigen::Vector3d e1 = p.unitOrthogonal(), e2 = p.cross(e1);
  std::vector<Eigen::Vector3d> out;
  for (int k = 0; k < n; ++k) out.push_back(c + r * (p + u(rng) * e1 + u(rng) * e2).normalized());
  return out;
}

TEST(SmallestEigenvector, MatchesTheFullDecompositionOnFittedPatches) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d c(unit(rng), unit(rng), unit(rng));
    const Eigen::Vector3d pole(unit(rng), unit(rng), unit(rng) + 2.0);
    std::vector<Eigen::Vector3d> points = sphere_patch(c, 1.0 + 2.0 * std::abs(unit(rng)), pole, 0.4, 30, rng);
    for (Eigen::Vector3d& q : points) q += 1e-4 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));  // noise
    const Mat5 M = moment_matrix(points);
    const Eigen::SelfAdjointEigenSolver<Mat5> es(M);
    const Vec5 u = smallest_eigenvector(M);
    EXPECT_NEAR(u.norm(), 1.0, 1e-12);
    EXPECT_GT(alignment(u, es.eigenvectors().col(0)), 1.0 - 1e-10) << "trial " << trial;
  }
}

TEST(SmallestEigenvector, FindsTheNullVectorOfExactPointsPlacedSymmetrically) {
  // Points on the plane x = y, symmetric about the origin: the answer (0, 1, -1, 0, 0) / sqrt(2) is
  // orthogonal to an even start vector.
  std::vector<Eigen::Vector3d> points;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) points.emplace_back(i, i, j);
  const Vec5 u = smallest_eigenvector(moment_matrix(points));
  Vec5 expected;
  expected << 0.0, 1.0, -1.0, 0.0, 0.0;
  EXPECT_GT(alignment(u, expected), 1.0 - 1e-12) << u.transpose();
}

TEST(SmallestEigenvector, FindsAnAnswerOrthogonalToAnEvenStart) {
  // Eigenvalue 1 on (0, 1, -1, 0, 0), 2 on (1, 1, 1, 1, 1), 3 to 5 on the rest: an iteration started at
  // (1, 1, 1, 1, 1) would settle at once on the wrong vector.
  Vec5 v0, v1;
  v0 << 0.0, 1.0, -1.0, 0.0, 0.0;
  v1 << 1.0, 1.0, 1.0, 1.0, 1.0;
  Mat5 basis = Mat5::Identity();
  basis.col(0) = v0.normalized();
  basis.col(1) = v1.normalized();
  const Mat5 Q = Eigen::HouseholderQR<Mat5>(basis).householderQ();
  Vec5 lambda;
  lambda << 1.0, 2.0, 3.0, 4.0, 5.0;
  const Mat5 M = Q * lambda.asDiagonal() * Q.transpose();
  EXPECT_GT(alignment(smallest_eigenvector(M), v0), 1.0 - 1e-12);
}

TEST(SmallestEigenvector, IsAnEigenvectorWhereTheSmallestEigenvaluesAreEqual) {
  // diag(1, 1, 2, 3, 4): any unit vector in the first two axes is an answer.
  Mat5 M = Mat5::Zero();
  M.diagonal() << 1.0, 1.0, 2.0, 3.0, 4.0;
  const Vec5 u = smallest_eigenvector(M);
  EXPECT_NEAR(u.norm(), 1.0, 1e-12);
  EXPECT_NEAR((M * u - u).norm(), 0.0, 1e-9) << u.transpose();
}

TEST(FitPoints, RecoversTheSphereAndThePlaneTheCrossingsLieOn) {
  std::mt19937 rng(11);
  const Eigen::Vector3d c(3.0, -2.0, 40.0);
  const std::vector<Eigen::Vector3d> on_sphere = sphere_patch(c, 5.0, Eigen::Vector3d(0.3, 0.1, 1.0), 0.06, 40, rng);
  const LocalFit sphere = fit_points(on_sphere, 0.005);
  ASSERT_TRUE(sphere.valid);
  ASSERT_FALSE(sphere.plane);
  EXPECT_NEAR((sphere.c - c).norm(), 0.0, 1e-6);
  EXPECT_NEAR(sphere.r, 5.0, 1e-6);

  std::vector<Eigen::Vector3d> on_plane;
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, 2.0).normalized();
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 40; ++k) on_plane.push_back(7.0 * n + u(rng) * e1 + u(rng) * e2);
  const LocalFit plane = fit_points(on_plane, 0.005);
  ASSERT_TRUE(plane.valid);
  if (plane.plane) {
    EXPECT_GT(std::abs(plane.c.dot(n)), 1.0 - 1e-12);
    EXPECT_NEAR(plane.c.dot(n) * plane.r, 7.0, 1e-9);
  } else {
    EXPECT_GT(plane.r, 1e6);  // a sphere so large that it is the plane
  }
  for (const Eigen::Vector3d& q : on_plane) EXPECT_LT(plane.distance(q), 1e-9);
}

TEST(FitPoints, RefusesAnEdgeWhereNoSphereFits) {
  // Two faces of a box meeting at a right angle, 0.2 mm each side of the edge.
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i <= 4; ++i)
    for (int j = -2; j <= 2; ++j) {
      points.emplace_back(0.05 * i, 0.05 * j, 0.0);
      points.emplace_back(0.0, 0.05 * j, -0.05 * i);
    }
  EXPECT_FALSE(fit_points(points, 0.005).valid);
}

}  // namespace
}  // namespace tf::stock_mesh
