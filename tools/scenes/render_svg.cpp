#include "render_svg.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/Dense>
#include <cstdio>
#include <limits>
#include <numbers>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/mesh_decimate.hpp"

namespace tf::scenes {

namespace {

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

// The orthographic camera: `cam` points toward the viewer, (right, up) span the picture plane.
struct View {
  Eigen::Vector3d cam, right, up, light;
  Eigen::Vector2d project(const Eigen::Vector3d& p) const { return {p.dot(right), p.dot(up)}; }
};

View camera_view(const SvgOptions& o) {
  const double az = o.azimuth_deg * std::numbers::pi / 180.0, el = o.elevation_deg * std::numbers::pi / 180.0;
  View v;
  v.cam = Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  v.right = Eigen::Vector3d(-std::sin(az), std::cos(az), 0.0);
  v.up = v.cam.cross(v.right);
  v.light = (v.cam + 0.6 * v.up - 0.4 * v.right).normalized();
  return v;
}

// The mesh's share of the triangle budget (by its part of all faces, at least 200), decimated to it
// when larger.
IndexedTriangles preview_triangles(const Mesh& mesh, size_t max_triangles, size_t total_faces) {
  const size_t budget = std::max<size_t>(200, max_triangles * mesh.n_faces() / std::max<size_t>(total_faces, 1));
  IndexedTriangles all = indexed_triangles(mesh);
  if (all.F.size() <= budget) return all;
  return decimate_to_budget(all, budget);
}

// Flat-shaded facing triangles of one mesh, appended to `tris`; `bounds` grows by their projection.
// Back faces are culled when the mesh is closed, drawn from the front when it is open.
void paint_mesh(const IndexedTriangles& mesh, bool closed, const Eigen::Vector3d& rgb, const View& view,
                std::vector<Painted>& tris, Eigen::AlignedBox2d& bounds) {
  for (const auto& f : mesh.F) {
    const Eigen::Vector3d p[3] = {mesh.V[f[0]], mesh.V[f[1]], mesh.V[f[2]]};
    Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    if (n.norm() < 1e-300) continue;
    n.normalize();
    if (n.dot(view.cam) <= 0) {
      if (closed) continue;
      n = -n;
    }
    const double shade = 0.35 + 0.65 * std::max(0.0, n.dot(view.light));
    Painted t{(p[0] + p[1] + p[2]).dot(view.cam) / 3.0,
              {view.project(p[0]), view.project(p[1]), view.project(p[2])},
              {p[0].dot(view.cam), p[1].dot(view.cam), p[2].dot(view.cam)},
              hex_colour(rgb * shade)};
    for (const auto& q : t.p) bounds.extend(q);
    tris.push_back(std::move(t));
  }
}

std::vector<Painted> painted_triangles(const std::vector<SvgMesh>& meshes, const View& view, size_t max_triangles,
                                       Eigen::AlignedBox2d& bounds) {
  size_t total = 0;
  for (const auto& m : meshes) total += m.mesh ? m.mesh->n_faces() : 0;
  std::vector<Painted> tris;
  for (const auto& sm : meshes) {
    if (!sm.mesh || sm.mesh->n_faces() == 0) continue;
    // Decided on the original: a decimated mesh is never closed.
    paint_mesh(preview_triangles(*sm.mesh, max_triangles, total), is_closed(*sm.mesh), sm.rgb, view, tris, bounds);
  }
  return tris;
}

// Picture coordinates: the projected bounds scaled to the width less a margin, y pointing down.
struct Screen {
  Eigen::AlignedBox2d bounds;
  double margin, w, span, scale, h;
  double sx(const Eigen::Vector2d& q) const { return margin + (q.x() - bounds.min().x()) * scale; }
  double sy(const Eigen::Vector2d& q) const { return margin + (bounds.max().y() - q.y()) * scale; }
};

Screen fit_screen(Eigen::AlignedBox2d bounds, const std::vector<SvgPolyline>& lines, const View& view, int width_px) {
  for (const auto& l : lines)
    for (const auto& p : l.points) bounds.extend(view.project(p));
  if (bounds.isEmpty()) bounds.extend(Eigen::Vector2d(0, 0)).extend(Eigen::Vector2d(1, 1));
  Screen s{bounds, 20.0, double(std::max(100, width_px)), 0.0, 0.0, 0.0};
  s.span = std::max(bounds.sizes().x(), 1e-9);
  s.scale = (s.w - 2 * s.margin) / s.span;
  s.h = std::ceil(bounds.sizes().y() * s.scale + 2 * s.margin);
  return s;
}

// Splits large faces (edges over 40 px, growing) but never adds more than half the budget again.
void split_for_painting(std::vector<Painted>& tris, size_t max_triangles, double scale) {
  const size_t limit = tris.size() + max_triangles / 2;
  std::vector<Painted> split;
  for (double edge_px = 40.0;; edge_px *= 1.5) {
    split = tris;
    subdivide(split, edge_px / scale);
    if (split.size() <= limit) break;
  }
  tris = std::move(split);
}

void append_triangles(std::string& out, const std::vector<Painted>& tris, const Screen& s) {
  char buf[160];
  // A stroke in the fill colour hides the hairline seams anti-aliasing leaves between triangles.
  out += "<g stroke-width=\"0.5\" stroke-linejoin=\"round\">\n";
  for (const auto& t : tris) {
    std::snprintf(buf, sizeof buf, "<polygon points=\"%.1f,%.1f %.1f,%.1f %.1f,%.1f\" fill=\"%s\" stroke=\"%s\"/>\n",
                  s.sx(t.p[0]), s.sy(t.p[0]), s.sx(t.p[1]), s.sy(t.p[1]), s.sx(t.p[2]), s.sy(t.p[2]), t.colour.c_str(),
                  t.colour.c_str());
    out += buf;
  }
  out += "</g>\n";
}

// Each polyline as its visible runs: a point is drawn where nothing painted lies in front of it
// (within a small depth bias).
void append_visible_polylines(std::string& out, const std::vector<SvgPolyline>& lines, const View& view,
                              const Screen& s, const DepthBuffer& depth) {
  const double bias = 0.004 * std::max(s.span, s.bounds.sizes().y());
  char buf[160];
  for (const auto& l : lines) {
    std::vector<std::vector<Eigen::Vector2d>> runs(1);
    for (const auto& p : l.points) {
      const Eigen::Vector2d q = view.project(p);
      if (p.dot(view.cam) + bias >= depth.at(s.sx(q), s.sy(q))) {
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
        std::snprintf(buf, sizeof buf, "%.1f,%.1f ", s.sx(q), s.sy(q));
        out += buf;
      }
      out += "\"/>\n";
    }
  }
}

std::string render_once(const std::vector<SvgMesh>& meshes, const std::vector<SvgPolyline>& lines,
                        const SvgOptions& o) {
  const View view = camera_view(o);
  Eigen::AlignedBox2d bounds;
  std::vector<Painted> tris = painted_triangles(meshes, view, o.max_triangles, bounds);
  const Screen s = fit_screen(bounds, lines, view, o.width_px);
  split_for_painting(tris, o.max_triangles, s.scale);
  std::stable_sort(tris.begin(), tris.end(), [](const Painted& a, const Painted& b) { return a.depth < b.depth; });
  const auto to_px = [&](const Eigen::Vector2d& q) { return Eigen::Vector2d(s.sx(q), s.sy(q)); };
  const DepthBuffer depth = rasterize_depth(tris, static_cast<int>(s.w), static_cast<int>(s.h), to_px);

  std::string out;
  out.reserve(tris.size() * 80 + 4096);
  char buf[160];
  const int w = static_cast<int>(s.w), h = static_cast<int>(s.h);
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n", w, h,
                w, h);
  out += buf;
  out += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  append_triangles(out, tris, s);
  append_visible_polylines(out, lines, view, s, depth);
  if (!o.title.empty())
    out += "<text x=\"12\" y=\"22\" font-family=\"sans-serif\" font-size=\"15\" fill=\"#333333\">" +
           xml_escape(o.title) + "</text>\n";
  out += "</svg>\n";
  return out;
}

}  // namespace

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
