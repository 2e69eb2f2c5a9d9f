#include "render_svg.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/Dense>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::scenes {

namespace {
struct Key {
  long long x, y, z;
  int dir;  // the vertex normal's dominant axis and sign, 0..5
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z && dir == o.dir; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL ^ k.dir * 2654435761LL);
  }
};

// Area-weighted vertex normals.
std::vector<Eigen::Vector3d> vertex_normals(const Mesh& mesh) {
  std::vector<Eigen::Vector3d> n(mesh.n_vertices(), Eigen::Vector3d::Zero());
  for (auto f : mesh.faces()) {
    Eigen::Vector3d p[3];
    int idx[3], k = 0;
    for (auto v : mesh.fv_range(f)) {
      idx[k] = v.idx();
      p[k++] = to_eigen(mesh.point(v));
    }
    const Eigen::Vector3d fn = (p[1] - p[0]).cross(p[2] - p[0]);
    for (int i : idx) n[i] += fn;
  }
  return n;
}

std::string hex_colour(const Eigen::Vector3d& rgb) {
  char buf[8];
  auto c = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c(rgb.x()), c(rgb.y()), c(rgb.z()));
  return buf;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '&') out += "&amp;";
    else if (ch == '<') out += "&lt;";
    else if (ch == '>') out += "&gt;";
    else out += ch;
  }
  return out;
}

struct Painted {
  double depth;        // toward the camera, mm (larger is nearer)
  Eigen::Vector2d p[3];  // projected, mm
  double z[3];         // vertex depths, mm
  std::string colour;
};

// Splits triangles longer than `max_edge` (projected mm) so painting back to front by centroid depth
// does not let a large face cover a nearer small one.
void subdivide(std::vector<Painted>& tris, double max_edge) {
  std::vector<Painted> out;
  out.reserve(tris.size());
  std::vector<std::pair<Painted, int>> stack;
  for (auto& t : tris) {
    stack.emplace_back(std::move(t), 0);
    while (!stack.empty()) {
      auto [q, level] = std::move(stack.back());
      stack.pop_back();
      const double longest = std::max({(q.p[1] - q.p[0]).norm(), (q.p[2] - q.p[1]).norm(), (q.p[0] - q.p[2]).norm()});
      if (longest <= max_edge || level >= 6) {
        out.push_back(std::move(q));
        continue;
      }
      Eigen::Vector2d m[3];
      double mz[3];
      for (int i = 0; i < 3; ++i) {
        m[i] = 0.5 * (q.p[i] + q.p[(i + 1) % 3]);
        mz[i] = 0.5 * (q.z[i] + q.z[(i + 1) % 3]);
      }
      auto make = [&](Eigen::Vector2d a, double za, Eigen::Vector2d b, double zb, Eigen::Vector2d c, double zc) {
        Painted r{(za + zb + zc) / 3.0, {a, b, c}, {za, zb, zc}, q.colour};
        stack.emplace_back(std::move(r), level + 1);
      };
      make(q.p[0], q.z[0], m[0], mz[0], m[2], mz[2]);
      make(m[0], mz[0], q.p[1], q.z[1], m[1], mz[1]);
      make(m[2], mz[2], m[1], mz[1], q.p[2], q.z[2]);
      make(m[0], mz[0], m[1], mz[1], m[2], mz[2]);
    }
  }
  tris = std::move(out);
}

// Nearest depth per pixel of the painted triangles (screen coordinates from `to_px`).
struct DepthBuffer {
  int w = 0, h = 0;
  std::vector<float> z;
  float at(double x, double y) const {
    const int i = static_cast<int>(x), j = static_cast<int>(y);
    if (i < 0 || j < 0 || i >= w || j >= h) return -std::numeric_limits<float>::infinity();
    return z[static_cast<size_t>(j) * w + i];
  }
};

template <class ToPx>
DepthBuffer rasterize_depth(const std::vector<Painted>& tris, int w, int h, const ToPx& to_px) {
  DepthBuffer db{w, h, std::vector<float>(static_cast<size_t>(w) * h, -std::numeric_limits<float>::infinity())};
  for (const auto& t : tris) {
    const Eigen::Vector2d a = to_px(t.p[0]), b = to_px(t.p[1]), c = to_px(t.p[2]);
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()})))),
              x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()})))),
              y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()})))),
              y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x + 0.5, y + 0.5);
        const double l1 = ((q - a).x() * (c - a).y() - (q - a).y() * (c - a).x()) / area;
        const double l2 = ((b - a).x() * (q - a).y() - (b - a).y() * (q - a).x()) / area;
        const double l0 = 1.0 - l1 - l2;
        if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
        float& d = db.z[static_cast<size_t>(y) * w + x];
        d = std::max(d, static_cast<float>(l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2]));
      }
  }
  return db;
}

std::string render_once(const std::vector<SvgMesh>& meshes, const std::vector<SvgPolyline>& lines,
                        const SvgOptions& o) {
  const double az = o.azimuth_deg * std::numbers::pi / 180.0, el = o.elevation_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d cam(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const Eigen::Vector3d right(-std::sin(az), std::cos(az), 0.0);
  const Eigen::Vector3d up = cam.cross(right);
  const Eigen::Vector3d light = (cam + 0.6 * up - 0.4 * right).normalized();
  auto project = [&](const Eigen::Vector3d& p) { return Eigen::Vector2d(p.dot(right), p.dot(up)); };

  size_t total = 0;
  for (const auto& m : meshes) total += m.mesh ? m.mesh->n_faces() : 0;
  std::vector<Painted> tris;
  Eigen::AlignedBox2d bounds;
  for (const auto& sm : meshes) {
    if (!sm.mesh || sm.mesh->n_faces() == 0) continue;
    const Mesh* mesh = sm.mesh;
    Mesh reduced;
    const size_t budget = std::max<size_t>(200, o.max_triangles * sm.mesh->n_faces() / std::max<size_t>(total, 1));
    if (mesh->n_faces() > budget) {
      // Grow the clustering cell until the mesh fits its share of the budget.
      const double diag = bounding_box(*mesh).diagonal().norm();
      double cell = diag / std::sqrt(static_cast<double>(budget)) * 0.5;
      for (int it = 0; it < 40; ++it, cell *= 1.25) {
        reduced = cluster_decimate(*mesh, cell);
        if (reduced.n_faces() <= budget) break;
      }
      mesh = &reduced;
    }
    const bool closed = is_closed(*sm.mesh);  // decide on the original: the decimated soup is never closed
    for (auto f : mesh->faces()) {
      Eigen::Vector3d p[3];
      int k = 0;
      for (auto v : mesh->fv_range(f)) p[k++] = to_eigen(mesh->point(v));
      Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
      if (n.norm() < 1e-300) continue;
      n.normalize();
      if (n.dot(cam) <= 0) {
        if (closed) continue;
        n = -n;
      }
      const double shade = 0.35 + 0.65 * std::max(0.0, n.dot(light));
      Painted t{(p[0] + p[1] + p[2]).dot(cam) / 3.0,
                {project(p[0]), project(p[1]), project(p[2])},
                {p[0].dot(cam), p[1].dot(cam), p[2].dot(cam)},
                hex_colour(sm.rgb * shade)};
      for (const auto& q : t.p) bounds.extend(q);
      tris.push_back(std::move(t));
    }
  }
  for (const auto& l : lines)
    for (const auto& p : l.points) bounds.extend(project(p));
  if (bounds.isEmpty()) bounds.extend(Eigen::Vector2d(0, 0)).extend(Eigen::Vector2d(1, 1));

  const double margin = 20.0, w = std::max(100, o.width_px);
  const double span = std::max(bounds.sizes().x(), 1e-9);
  const double scale = (w - 2 * margin) / span;
  const double h = std::ceil(bounds.sizes().y() * scale + 2 * margin);
  auto sx = [&](const Eigen::Vector2d& q) { return margin + (q.x() - bounds.min().x()) * scale; };
  auto sy = [&](const Eigen::Vector2d& q) { return margin + (bounds.max().y() - q.y()) * scale; };
  {
    // Split large faces, but never more than half the budget again.
    const size_t limit = tris.size() + o.max_triangles / 2;
    std::vector<Painted> split;
    for (double edge_px = 40.0;; edge_px *= 1.5) {
      split = tris;
      subdivide(split, edge_px / scale);
      if (split.size() <= limit) break;
    }
    tris = std::move(split);
  }
  std::stable_sort(tris.begin(), tris.end(), [](const Painted& a, const Painted& b) { return a.depth < b.depth; });
  const DepthBuffer depth = rasterize_depth(tris, static_cast<int>(w), static_cast<int>(h),
                                            [&](const Eigen::Vector2d& q) { return Eigen::Vector2d(sx(q), sy(q)); });
  // A polyline point is drawn where nothing painted lies in front of it (within a small depth bias).
  const double bias = 0.004 * std::max(span, bounds.sizes().y());

  std::string out;
  out.reserve(tris.size() * 80 + 4096);
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n",
                static_cast<int>(w), static_cast<int>(h), static_cast<int>(w), static_cast<int>(h));
  out += buf;
  out += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  // A stroke in the fill colour hides the hairline seams anti-aliasing leaves between triangles.
  out += "<g stroke-width=\"0.5\" stroke-linejoin=\"round\">\n";
  for (const auto& t : tris) {
    std::snprintf(buf, sizeof buf, "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"%s\" stroke=\"%s\"/>\n",
                  sx(t.p[0]), sy(t.p[0]), sx(t.p[1]), sy(t.p[1]), sx(t.p[2]), sy(t.p[2]), t.colour.c_str(),
                  t.colour.c_str());
    out += buf;
  }
  out += "</g>\n";
  for (const auto& l : lines) {
    // Visible runs of the polyline, each its own element.
    std::vector<std::vector<Eigen::Vector2d>> runs(1);
    for (const auto& p : l.points) {
      const Eigen::Vector2d q = project(p);
      if (p.dot(cam) + bias >= depth.at(sx(q), sy(q))) {
        runs.back().push_back(q);
      } else if (!runs.back().empty()) {
        runs.emplace_back();
      }
    }
    for (const auto& run : runs) {
      if (run.size() < 2) continue;
      std::snprintf(buf, sizeof buf, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"%.2f\" points=\"",
                    xml_escape(l.color).c_str(), l.width_px);
      out += buf;
      for (const auto& q : run) {
        std::snprintf(buf, sizeof buf, "%.1f,%.1f ", sx(q), sy(q));
        out += buf;
      }
      out += "\"/>\n";
    }
  }
  if (!o.title.empty())
    out += "<text x=\"12\" y=\"22\" font-family=\"sans-serif\" font-size=\"15\" fill=\"#333333\">" +
           xml_escape(o.title) + "</text>\n";
  out += "</svg>\n";
  return out;
}
}  // namespace

Mesh cluster_decimate(const Mesh& mesh, double cell) {
  std::unordered_map<Key, int, KeyHash> cells;
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> count, map(mesh.n_vertices());
  // Vertices facing different ways stay apart, so the two sides of a thin wall (a blade) do not merge.
  const std::vector<Eigen::Vector3d> normals = vertex_normals(mesh);
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = to_eigen(mesh.point(v));
    const Eigen::Vector3d& n = normals[v.idx()];
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    const Key k{static_cast<long long>(std::floor(p.x() / cell)), static_cast<long long>(std::floor(p.y() / cell)),
                static_cast<long long>(std::floor(p.z() / cell)), 2 * axis + (n[axis] < 0 ? 1 : 0)};
    auto [it, fresh] = cells.emplace(k, static_cast<int>(sum.size()));
    if (fresh) {
      sum.push_back(Eigen::Vector3d::Zero());
      count.push_back(0);
    }
    sum[it->second] += p;
    ++count[it->second];
    map[v.idx()] = it->second;
  }
  // Each cluster's point minimises the squared distances to the planes of the faces around its vertices
  // (Lindstrom's quadric clustering), which keeps sharp edges such as blade tips straight; a small pull
  // toward the vertices' mean keeps flat clusters (singular quadrics) in place.
  std::vector<Eigen::Matrix3d> qa(sum.size(), Eigen::Matrix3d::Zero());
  std::vector<Eigen::Vector3d> qb(sum.size(), Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3i> faces;
  for (auto f : mesh.faces()) {
    int c[3], k = 0;
    Eigen::Vector3d p[3];
    for (auto v : mesh.fv_range(f)) {
      p[k] = to_eigen(mesh.point(v));
      c[k++] = map[v.idx()];
    }
    const Eigen::Vector3d n2 = (p[1] - p[0]).cross(p[2] - p[0]);  // |n2| = twice the area
    const double len = n2.norm();
    if (len > 0) {
      const Eigen::Vector3d n = n2 / len;
      for (int i = 0; i < 3; ++i) {
        qa[c[i]] += len * n * n.transpose();
        qb[c[i]] += len * n * n.dot(p[0]);
      }
    }
    if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) faces.emplace_back(c[0], c[1], c[2]);
  }
  std::vector<Eigen::Vector3d> rep(sum.size());
  for (size_t i = 0; i < sum.size(); ++i) {
    const Eigen::Vector3d mean = sum[i] / count[i];
    const double eps = 1e-3 * qa[i].trace() + 1e-12;
    Eigen::Vector3d x = (qa[i] + eps * Eigen::Matrix3d::Identity()).ldlt().solve(qb[i] + eps * mean);
    // A representative far outside its cell would be an ill-conditioned solve: fall back to the mean.
    if (!x.allFinite() || (x - mean).norm() > 2.0 * cell) x = mean;
    rep[i] = x;
  }
  // Built as a triangle soup: clustering can make the surface non-manifold, which a half-edge mesh
  // refuses; the renderer only needs the triangles.
  Mesh out;
  for (const auto& f : faces) {
    Mesh::VertexHandle vh[3];
    for (int i = 0; i < 3; ++i) vh[i] = out.add_vertex(to_om(rep[f[i]]));
    out.add_face(vh[0], vh[1], vh[2]);
  }
  return out;
}

std::string render_svg(const std::vector<SvgMesh>& meshes, const std::vector<SvgPolyline>& lines,
                       const SvgOptions& options) {
  SvgOptions o = options;
  std::string svg = render_once(meshes, lines, o);
  // Keep the picture under 3 MB whatever the scene.
  while (svg.size() > 2'900'000 && o.max_triangles > 500) {
    o.max_triangles = o.max_triangles * 6 / 10;
    svg = render_once(meshes, lines, o);
  }
  return svg;
}

void write_scene_preview(const SceneBundle& scene, const std::filesystem::path& file) {
  std::vector<SvgMesh> meshes;
  meshes.push_back({&scene.design.mesh, {0.66, 0.66, 0.68}});
  for (const auto& c : scene.check_surfaces) meshes.push_back({&c.mesh, {0.22, 0.42, 0.85}});
  SvgPolyline path;
  for (const auto& r : scene.path.rows) path.points.push_back(r.p);
  SvgOptions o;
  o.azimuth_deg = scene.view_azimuth_deg;
  o.elevation_deg = scene.view_elevation_deg;
  o.title = "tiltfield scene " + scene.name + ": " + std::to_string(scene.path.rows.size()) + " cutter locations";
  const std::string svg = render_svg(meshes, {path}, o);
  try {
    write_file_atomic(file, [&](std::ostream& out) { out << svg; });
  } catch (const std::runtime_error& e) {
    throw InputError(file.string(), 0, "--preview", e.what());
  }
}

}  // namespace tf::scenes
