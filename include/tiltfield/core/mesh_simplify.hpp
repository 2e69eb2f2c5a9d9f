// tiltfield core: decimation within a stated distance bound, with OpenMesh's decimater, for a compact
// stock mesh (`tiltfield verify --stock-mesh`, the report of `verify --html`).
//
// In:  a triangle mesh (mm), the bound. Out: a mesh made by half-edge collapses, so every output vertex
//      is an input vertex at its own position (`source_vertex` names it). Within the bound, one way exact,
//      the other sampled:
//      - every input vertex lies within `max_error_mm` of the output's triangles: each face carries the
//        removed input vertices nearest to it (as OpenMesh's ModHausdorffT does), and a collapse is allowed
//        only when each of them stays within the bound (exact, for the vertices);
//      - the output's faces lie near the input: a collapse is allowed only when a grid of points over each
//        face it moves (quarters of the face) lies within half the bound of the input's triangles
//        (a sampled test, with a margin for the points between the samples; the tests measure 28 points a
//        face against the input: within the bound).
// Guards: ModNormalFlippingT (no face turns by more than `max_normal_deviation_deg`) and ModAspectRatioT
//      (no face longer than `max_aspect_ratio` times its height, unless the collapse improves the worst).
// Order: the cheapest collapse by OpenMesh's area-weighted error quadric (ModQuadricT), the shorter edge
//      on a tie. OpenMesh's DecimaterT evaluates every module for every outgoing edge of every vertex
//      around each collapse, which took tens of minutes on a 3 M-vertex stock. The loop here uses the same
//      framework (BaseDecimaterT: modules, legality tests, collapse bookkeeping) but runs the tests only
//      for the collapse about to be made: vertices wait in a heap keyed by their cheapest collapse by the
//      quadric alone, a key is taken again when it comes up (so the order is cheapest first only nearly:
//      a key that got cheaper meanwhile waits at its old place), and core's TriangleBvh answers the
//      surface test.
// Parallel: meshes over 200k faces are cut into slabs of equal face count along their longest axis,
//      decimated in parallel; vertices on the cuts are locked (kept), so the slabs join exactly.
#pragma once
#include <cstddef>
#include <vector>

#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/progress.hpp"

namespace tf {

struct BoundedDecimateOptions {
  double max_error_mm = 0.01;              // every input vertex within this of the output; <= 0: a copy
  double max_normal_deviation_deg = 60.0;  // ModNormalFlippingT
  double max_aspect_ratio = 20.0;          // ModAspectRatioT: edge length over height
  int slabs = 0;                           // 0: two per worker thread above 200k faces, else one
  Progress progress;                       // stage "decimate"
};

struct BoundedDecimation {
  Mesh mesh;                        // vertex colours and deviations (vertex_deviation) copied when the input has them
  std::vector<int> source_vertex;   // per output vertex: the input vertex it is
  size_t input_vertices = 0, input_faces = 0;
};

// Throws std::invalid_argument for a bound that is not finite.
BoundedDecimation decimate_within(const Mesh& mesh, const BoundedDecimateOptions& options = {});

}  // namespace tf
