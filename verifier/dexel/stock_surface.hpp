// tiltfield verifier (internal): the stock mesh's surface nets before they become a Mesh, and the local
// fits that place its vertices on the exact dexel ends (reconstruct.cpp builds the nets, stock_fits.cpp
// fits them).
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace tf::stock_mesh {

// The surface nets of the whole lattice: one vertex per cell with crossings, its crossings (the exact
// dexel ends on the cell's edges, mm), and triangles (two per crossed edge's quad).
struct Surface {
  std::vector<Eigen::Vector3d> vertices, points;
  std::vector<Eigen::Vector3i> faces;
  std::vector<uint32_t> point_start;  // vertex v owns points[point_start[v], point_start[v + 1])
  double h = 0.0;
};

// A local algebraic sphere (a plane when flat) fitted to the exact crossings around a vertex (the
// vertex's cell and its neighbours): u0 + u.x + u4 |x|^2 = 0 on points centred and scaled for conditioning.
struct LocalFit {
  bool valid = false;
  bool plane = false;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  // sphere centre, or plane normal
  double r = 0.0;                               // sphere radius, or plane offset (n.x = r)
  Eigen::Vector3d project(const Eigen::Vector3d& p) const {
    if (plane) return p - (c.dot(p) - r) * c;
    const Eigen::Vector3d d = p - c;
    const double n = d.norm();
    return n > 0 ? Eigen::Vector3d(c + d * (r / n)) : p;
  }
  double distance(const Eigen::Vector3d& p) const { return plane ? std::abs(c.dot(p) - r) : std::abs((p - c).norm() - r); }
};

// The unit eigenvector of the smallest eigenvalue of a symmetric positive semi-definite M (its lower
// triangle read). By inverse iteration: where points fit a sphere or plane, that eigenvalue is far below
// the next, and one factorisation and a few solves settle the vector (successive unit vectors within
// 1e-13), at a fraction of a full eigen-decomposition's cost. Where they fit nothing well (edges,
// corners) and 12 solves do not settle it, Eigen's full decomposition decides.
Eigen::Matrix<double, 5, 1> smallest_eigenvector(const Eigen::Matrix<double, 5, 5>& M);

// The sphere or plane through points P (mm) in the least-squares sense of u0 + u.x + u4 |x|^2 = 0 on the
// points centred and scaled; valid when every point lies within `tolerance` (mm) of it. Invalid for fewer
// than six points.
LocalFit fit_points(const std::vector<Eigen::Vector3d>& P, double tolerance);

// Moves each vertex onto the surface fitted to its neighbourhood's exact crossings where that fit lies
// within 5 % of the spacing of them (smooth regions); keeps the mass point near edges and corners, where
// no sphere fits. Returns each vertex's fit (valid or not), for refine.
std::vector<LocalFit> smooth_vertices(Surface& b);

// Splits every triangle in four; the new edge midpoints go onto the vertices' fitted surfaces (fits grows
// with the vertices).
void refine(std::vector<Eigen::Vector3d>& V, std::vector<Eigen::Vector3i>& F, std::vector<LocalFit>& fits);

}  // namespace tf::stock_mesh
