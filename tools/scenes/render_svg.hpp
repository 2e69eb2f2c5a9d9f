// tiltfield: a small SVG renderer for scene previews. Orthographic view from an oblique direction,
// flat-shaded triangles painted back to front (large ones split first), polylines drawn on top where a
// depth buffer of the triangles says they are not hidden. Large meshes are decimated by vertex
// clustering (core's mesh_decimate) so the picture stays small (a few MB at most).
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "scene_writer.hpp"
#include "tiltfield/core/mesh.hpp"

namespace tf::scenes {

struct SvgMesh {
  const Mesh* mesh = nullptr;
  Eigen::Vector3d rgb{0.6, 0.6, 0.6};  // base colour, components in [0, 1]
};

struct SvgPolyline {
  std::vector<Eigen::Vector3d> points;  // mm
  std::string color = "#d01010";
  double width_px = 1.2;
};

struct SvgOptions {
  double azimuth_deg = -60.0;    // camera direction about +z, from +x, deg
  double elevation_deg = 35.0;   // camera height above the xy plane, deg
  int width_px = 1000;           // picture width; the height follows the scene's aspect
  // Budget of mesh triangles over all meshes (before back faces are dropped); splitting large faces for
  // painting adds at most half as many again.
  size_t max_triangles = 30000;
  std::string title;             // drawn in the top-left corner when not empty
};

// The SVG document. Closed meshes have their back faces culled; open ones are drawn two-sided.
std::string render_svg(const std::vector<SvgMesh>& meshes, const std::vector<SvgPolyline>& lines,
                       const SvgOptions& options);

// The preview of a generated scene: design grey, check surfaces blue, the path red, seen from the
// scene's preview camera. Written atomically; throws InputError naming the file when it cannot be written.
void write_scene_preview(const SceneBundle& scene, const std::filesystem::path& file);

}  // namespace tf::scenes
