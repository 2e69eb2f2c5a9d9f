#include "inside_solids.hpp"

#include <tbb/parallel_for.h>

#include <stdexcept>

#include "tiltfield/core/triangle_bvh.hpp"

namespace tf {

std::vector<int8_t> points_inside_solids(const std::vector<std::vector<const Mesh*>>& sets,
                                         const std::vector<Eigen::Vector3d>& points) {
  if (sets.size() > 127) throw std::invalid_argument("points_inside_solids: more than 127 obstacle sets");
  std::vector<int8_t> out(points.size(), -1);
  for (size_t s = sets.size(); s-- > 0;) {  // backwards: the first set containing a point is the one kept
    for (const Mesh* m : sets[s]) {
      if (m->n_faces() == 0 || !is_closed(*m) || !(signed_volume(*m) > 0.0)) continue;
      const TriangleBvh bvh({m});
      tbb::parallel_for(size_t{0}, points.size(), [&](size_t i) {
        if (inside_solid(bvh, points[i])) out[i] = static_cast<int8_t>(s);
      });
    }
  }
  return out;
}

}  // namespace tf
