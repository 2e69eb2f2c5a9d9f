// tiltfield core: vertex-clustering decimation of triangle meshes, for pictures of large meshes (the
// report's 3-D view, the scene preview SVG).
//
// In:  an IndexedTriangles: V vertex positions in mm, F triangles as indices into V (counter-clockwise
//      seen from outside), values empty or one scalar per vertex (any unit, e.g. deviation in mm);
//      a grid cell in mm (cluster_decimate) or a triangle budget (decimate_to_budget).
// Out: a new IndexedTriangles: one vertex per cluster that a kept triangle uses, numbered in the order
//      the kept triangles first use them; the triangles whose corners fell in three different clusters,
//      in input order and orientation; values (when given) the mean over each cluster's vertices;
//      labels (when given: categories such as a block number, which a mean would mix up) the label of
//      each cluster's first vertex in input order.
//      The result may be non-manifold (a fan pinched at a cluster point): draw it, do not build a
//      half-edge mesh from it.
// Clustering: the grid starts at the mesh's bounding-box minimum. Vertices of one cell merge only when
// their area-weighted normals face the same way (dominant axis and sign), so the two sides of a wall
// thinner than a cell stay apart. A cluster's point minimises the area-weighted squared distances to the
// planes of the triangles around its vertices (Lindstrom's quadric placement), which keeps sharp edges
// and corners where they were, where the mean of the vertices would cut them off; it is pulled slightly
// toward that mean so that flat clusters (singular quadrics) stay in place, and falls back to the mean
// when it would land more than two cells away from it (an ill-conditioned solve).
// Defaults and limits: cell <= 0, or a grid of more than 2^20 cells along an axis, returns a copy.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tiltfield/core/mesh.hpp"

namespace tf {

struct IndexedTriangles {
  std::vector<Eigen::Vector3d> V;           // mm
  std::vector<std::array<uint32_t, 3>> F;   // indices into V, counter-clockwise seen from outside
  std::vector<double> values;               // empty, or one per vertex
  std::vector<uint32_t> labels;             // empty, or one per vertex
};

// A copy of `mesh` (vertex indices kept, faces of other than three vertices skipped) with `values` and
// `labels` (either may be null). Throws std::invalid_argument when either does not hold one entry per
// vertex.
IndexedTriangles indexed_triangles(const Mesh& mesh, const std::vector<double>* values = nullptr,
                                   const std::vector<uint32_t>* labels = nullptr);

// Clusters on a grid of `cell` mm (see the header comment). Throws std::invalid_argument when values or
// labels are neither empty nor one per vertex.
IndexedTriangles cluster_decimate(const IndexedTriangles& mesh, double cell);

// Clusters with a growing cell until at most `max_triangles` remain; a mesh that already fits is returned
// unchanged, max_triangles = 0 gives an empty mesh. The first cell follows from the surface area (a
// smooth surface of area A on cells of side c keeps about 2 A / c^2 triangles), so one to three passes
// usually suffice; each further pass grows the cell by at least 15 %, for at most 16 passes (then, or
// when the mesh has no area, the result is empty).
IndexedTriangles decimate_to_budget(const IndexedTriangles& mesh, size_t max_triangles);

}  // namespace tf
