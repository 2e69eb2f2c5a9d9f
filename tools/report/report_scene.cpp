// tiltfield report: the 3-D view's data. Meshes are decimated to the options' triangle budget (core's
// mesh_decimate) and packed by report_mesh; lines and points go as base64 Float32 arrays.
#include <algorithm>
#include <cmath>
#include <map>
#include <limits>
#include <optional>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "report_internal.hpp"
#include "report_mesh.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/triangle_bvh.hpp"

namespace tf::reporting {

namespace {

IndexedTriangles merged(const std::vector<Mesh>& meshes) {
  IndexedTriangles out;
  for (const auto& m : meshes) {
    IndexedTriangles part = indexed_triangles(m);
    const auto base = uint32_t(out.V.size());
    out.V.insert(out.V.end(), part.V.begin(), part.V.end());
    for (auto f : part.F) out.F.push_back({f[0] + base, f[1] + base, f[2] + base});
  }
  return out;
}

// Value at fraction q of the sorted values (nearest rank).
double quantile(std::vector<float> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

struct MeshLayer {
  std::string id, label, color;
  double opacity = 1.0;
  bool visible = true;
  double weight = 1.0;  // share of the triangle budget per triangle
  IndexedTriangles mesh;
};

// The tool's outline as (radius, height) pairs from the tip up, steps at the component changes, for a
// lathe (surface of revolution) in the viewer.
nlohmann::json tool_profile(const Tool& tool) {
  nlohmann::json pts = nlohmann::json::array();
  const double eps = 1e-6;
  const double end = tool.end_height();
  for (int i = 0; i <= 16; ++i) {
    const double h = end * i / 16.0;
    pts.push_back({tool.radius_at(std::max(h, eps)), h});
  }
  std::vector<double> steps{tool.flute_length, tool.length};
  double h = tool.length;
  for (const auto& seg : tool.holder) steps.push_back(h += seg.length);
  for (double s : steps) {
    if (s <= end) continue;
    pts.push_back({tool.radius_at(s - eps), s});
    pts.push_back({s >= tool.total_length() - eps ? 0.0 : tool.radius_at(s + eps), s});
  }
  return pts;
}

// Tool tips of the posted blocks in the part frame, by block index (needs the machine for joint programs).
std::map<int, ToolPose> block_poses(const ReportInputs& in) {
  std::map<int, ToolPose> poses;
  std::optional<Kinematics> kin;
  if (in.scene->machine) kin.emplace(*in.scene->machine, in.scene->tool.length);
  for (const auto& b : in.axes) {
    ToolPose pose;
    if (kin) {
      pose = kin->forward(b.joints);
      if (b.tcp) pose.tip = {b.joints.x, b.joints.y, b.joints.z};
    } else {
      pose.tip = {b.joints.x, b.joints.y, b.joints.z};
    }
    poses[b.block] = pose;
  }
  return poses;
}

void push(std::vector<float>& v, const Eigen::Vector3d& p) {
  v.push_back(float(p.x()));
  v.push_back(float(p.y()));
  v.push_back(float(p.z()));
}

nlohmann::json pose_json(const ToolPose& pose, const std::string& label) {
  return {{"tip", {pose.tip.x(), pose.tip.y(), pose.tip.z()}},
          {"axis", {pose.axis.x(), pose.axis.y(), pose.axis.z()}},
          {"label", label}};
}

// The stock (machined, with its deviation and the blocks that cut it when known, else the raw stock faint
// and hidden), the check surfaces, the fixtures and the design, each with its share of the triangle budget.
std::vector<MeshLayer> mesh_layers(const ReportInputs& in, const ReportOptions& options) {
  const Scene& scene = *in.scene;
  std::vector<MeshLayer> meshes;
  if (in.stock && in.stock->n_faces() > 0) {
    const bool deviation = !in.stock_deviation_mm.empty(), blocks = !in.stock_block.empty();
    meshes.push_back({"stock", "Machined stock", "#c9b37e", 1.0, true, 1.0,
                      indexed_triangles(*in.stock, deviation ? &in.stock_deviation_mm : nullptr,
                                        blocks ? &in.stock_block : nullptr)});
  } else {
    meshes.push_back({"raw-stock", "Raw stock", "#c9b37e", 0.18, false, 0.3,
                      indexed_triangles(stock_to_mesh(scene.stock, 64))});
  }
  if (!scene.check_surfaces.empty())
    meshes.push_back({"check", "Check surfaces", "#6f9fd8", 0.85, true, 1.0, merged(scene.check_surfaces)});
  // Clamps and vices: what a collision "with fixture" names has to be seen.
  if (!scene.fixtures.empty())
    meshes.push_back({"fixtures", "Fixtures", "#8a8f98", 0.9, true, 0.5, merged(scene.fixtures)});
  if (options.include_design && scene.design.n_faces() > 0)
    // Under a machined stock the design is mostly hidden: a smaller share of the budget, off by default.
    meshes.push_back({"design", "Design surface", "#b9bec6", 1.0, !in.stock, in.stock ? 0.5 : 1.0,
                      indexed_triangles(scene.design)});
  return meshes;
}

// Water-filling: a mesh below its weighted share of the budget keeps every triangle and leaves the rest
// to the others, so a small check surface stays exact next to a million-triangle stock.
std::vector<size_t> layer_budgets(const std::vector<MeshLayer>& meshes, size_t max_triangles) {
  std::vector<size_t> budget(meshes.size(), 0);
  std::vector<bool> open(meshes.size(), true);
  double remaining = double(max_triangles);
  for (bool changed = true; changed;) {
    changed = false;
    double weights = 0.0;
    for (size_t i = 0; i < meshes.size(); ++i)
      if (open[i]) weights += meshes[i].weight;
    for (size_t i = 0; i < meshes.size() && weights > 0.0; ++i)
      if (open[i] && double(meshes[i].mesh.F.size()) <= remaining * meshes[i].weight / weights) {
        budget[i] = meshes[i].mesh.F.size();
        remaining -= double(budget[i]);
        open[i] = false;
        changed = true;
      }
    if (!changed)
      for (size_t i = 0; i < meshes.size(); ++i)
        if (open[i]) budget[i] = size_t(std::max(0.0, remaining * meshes[i].weight / weights));
  }
  return budget;
}

// The ways to colour a mesh with per-vertex values (the deviation: a range that leaves out the extreme
// percent at either end) and labels (the block that last cut: the blocks with their G-code line and tool;
// by tool too when those blocks use more than one), the default first: the deviation when there is a
// design, else the tool when there are several, else the block.
nlohmann::json colorings(const IndexedMesh& mesh, const ReportInputs& in) {
  nlohmann::json out = nlohmann::json::array();
  if (!mesh.values.empty()) {
    const double lo = std::min(quantile(mesh.values, 0.01), -0.01);
    const double hi = std::max(quantile(mesh.values, 0.99), 0.01);
    out.push_back({{"id", "deviation"}, {"kind", "deviation"}, {"label", "deviation from the design"},
                   {"legend", "deviation from the design (mm): \u2212 over-cut, + material left"}, {"range", {lo, hi}}});
  }
  if (mesh.labels.empty()) return out;
  std::vector<uint32_t> ids;
  for (uint32_t b : mesh.labels)
    if (b > 0) ids.push_back(b);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::map<int, const BlockAxes*> by_block;
  for (const BlockAxes& a : in.axes) by_block[a.block] = &a;
  nlohmann::json lines = nlohmann::json::array(), tools = nlohmann::json::array();
  std::vector<int> distinct;
  for (uint32_t b : ids) {
    const auto it = by_block.find(int(b));
    lines.push_back(it == by_block.end() ? 0 : it->second->line);
    tools.push_back(it == by_block.end() ? 0 : it->second->tool);
    distinct.push_back(tools.back().get<int>());
  }
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  const nlohmann::json blocks{{"ids", ids}, {"lines", lines}, {"tools", tools}};
  nlohmann::json by_tool{{"id", "tool"}, {"kind", "tool"}, {"label", "tool that last cut"},
                         {"legend", "tool of the last block to cut each place"},
                         {"note", !distinct.empty() && distinct.front() == 0 ? "Grey: raw stock. T0: blocks before the first tool change (M6)."
                                                        : "Grey: raw stock."},
                         {"blocks", blocks}, {"tools", distinct}};
  nlohmann::json by_block_json{
      {"id", "block"}, {"kind", "block"}, {"label", "block that last cut"},
      {"legend", "last block to cut each place"},
      {"note", "Coloured by order among the blocks that cut; grey: raw stock. Read per dexel ray, so approximate: "
               "where every ray through a place was cut again later elsewhere a later block shows, and where two "
               "passes meet either may (docs/verifier.md)."},
      {"blocks", blocks}};
  const bool several_tools = distinct.size() > 1;
  if (several_tools && mesh.values.empty()) out.push_back(std::move(by_tool));
  out.push_back(std::move(by_block_json));
  if (several_tools && !mesh.values.empty()) out.push_back(std::move(by_tool));
  return out;
}

// One mesh layer decimated to its budget and packed, with its colourings.
nlohmann::json mesh_layer_json(const MeshLayer& m, size_t budget, const ReportInputs& in) {
  const size_t original = m.mesh.F.size();
  const IndexedMesh mesh = original > budget ? to_indexed(decimate_to_budget(m.mesh, budget)) : to_indexed(m.mesh);
  nlohmann::json layer{{"id", m.id},           {"label", m.label},     {"kind", "mesh"},
                       {"color", m.color},     {"opacity", m.opacity}, {"visible", m.visible},
                       {"original_triangles", original}, {"mesh", encode_mesh(mesh)}};
  nlohmann::json c = colorings(mesh, in);
  if (!c.empty()) {
    layer["label"] = m.label + ", coloured by " + c[0]["label"].get<std::string>();
    layer["colorings"] = std::move(c);
  }
  return layer;
}

// The cutter locations as one line, at most about 40000 points (the last one always included).
std::optional<nlohmann::json> path_layer(const ReportInputs& in) {
  std::vector<Eigen::Vector3d> path_points;
  if (in.oriented)
    for (const auto& r : in.oriented->rows) path_points.push_back(r.p);
  else
    for (const auto& r : in.scene->path.rows) path_points.push_back(r.p);
  if (path_points.empty()) return std::nullopt;
  std::vector<float> line;
  const size_t stride = std::max<size_t>(1, path_points.size() / 40000);
  for (size_t i = 0; i < path_points.size(); i += stride) push(line, path_points[i]);
  if ((path_points.size() - 1) % stride != 0) push(line, path_points.back());
  return nlohmann::json{{"id", "path"}, {"label", "Tool path (cutter locations)"}, {"kind", "line"},
                        {"color", "#e0301e"}, {"visible", true}, {"positions", base64_floats(line)}};
}

// Tool axes at evenly spaced rows (tip to holder face), coloured by clearance.
nlohmann::json axes_layer(const std::vector<OrientedRow>& rows, const Scene& scene, int axis_samples) {
  const double safety = scene.planner.safety_distance;
  const size_t n = rows.size();
  const size_t samples = std::min<size_t>(n, size_t(std::max(axis_samples, 1)));
  std::vector<float> seg, clearance;
  for (size_t k = 0; k < samples; ++k) {
    const size_t i = samples == 1 ? 0 : (k * (n - 1) + (samples - 1) / 2) / (samples - 1);
    const Eigen::Vector3d tip = row_tip(rows[i], scene.tool);
    push(seg, tip);
    push(seg, tip + rows[i].axis.normalized() * scene.tool.length);
    // +inf: nothing near (drawn as clear); NaN: not known (drawn grey).
    const double c = rows[i].clearance_mm;
    clearance.push_back(std::isnan(c) ? std::numeric_limits<float>::quiet_NaN() : std::isinf(c) ? 1e9f : float(c));
  }
  return {{"id", "axes"},
          {"label", "Tool axes at " + std::to_string(samples) + (samples == 1 ? " row" : " rows") + ", coloured by clearance"},
          {"kind", "segments"},
          {"visible", true},
          {"positions", base64_floats(seg)},
          {"values", base64_floats(clearance)},
          {"value_label", "clearance to the check surfaces (mm)"},
          {"value_range", {0.0, std::max(3.0 * safety, 0.1)}},
          {"safety_distance", safety}};
}

// The tool pose at the row of least finite clearance (the first such row), if any row has one.
std::optional<nlohmann::json> tightest_row_pose(const std::vector<OrientedRow>& rows, const Tool& tool) {
  size_t tight = 0;
  for (size_t i = 0; i < rows.size(); ++i)
    if (clearance_measured(rows[i].clearance_mm) && !(rows[tight].clearance_mm <= rows[i].clearance_mm)) tight = i;
  if (!clearance_measured(rows[tight].clearance_mm)) return std::nullopt;
  return pose_json({row_tip(rows[tight], tool), rows[tight].axis.normalized()},
                   "tightest row " + std::to_string(tight + 1) + ": clearance " + fixed(rows[tight].clearance_mm, 3) +
                       " mm");
}

// Collision and gouge sites at the tool tip of their block's end point, one point per block.
template <class Item, class Describe>
void add_site_layer(nlohmann::json& layers, const std::map<int, ToolPose>& poses, const std::vector<Item>& items,
                    const std::string& id, const std::string& label, const std::string& color, Describe describe) {
  std::vector<float> pts;
  nlohmann::json titles = nlohmann::json::array();
  std::map<int, bool> seen;
  for (const auto& item : items) {
    auto it = poses.find(item.block);
    if (it == poses.end() || seen[item.block]) continue;
    seen[item.block] = true;
    push(pts, it->second.tip);
    titles.push_back(describe(item));
  }
  if (pts.empty()) return;
  layers.push_back({{"id", id}, {"label", label}, {"kind", "points"}, {"color", color}, {"visible", true},
                    {"positions", base64_floats(pts)}, {"titles", titles}});
}

void add_site_layers(nlohmann::json& layers, const ReportInputs& in, const std::map<int, ToolPose>& poses) {
  add_site_layer(layers, poses, in.collisions, "collisions", "Collision sites (tool tip at the block end)", "#ff1744",
                 [](const Collision& c) {
                   return "block " + std::to_string(c.block) + ", line " + std::to_string(c.line) + ": " +
                          collision_kind(c) + " " + fixed(c.depth_mm, 3) + " mm";
                 });
  add_site_layer(layers, poses, in.gouges, "gouges", "Gouge sites", "#ff9100", [](const Gouge& g) {
    return "block " + std::to_string(g.block) + ", line " + std::to_string(g.line) + ": gouge " + fixed(g.depth_mm, 3) +
           " mm";
  });
}

}  // namespace

std::vector<double> stock_deviation(const Mesh& stock, const Mesh& design) {
  std::vector<double> dev(stock.n_vertices(), 0.0);
  if (design.n_faces() == 0) return dev;
  const TriangleBvh bvh({&design});
  // On the threads, in fixed runs of vertices (simple_partitioner), each run's queries starting from the
  // previous vertex's triangle: where two triangles are equally close (an edge), the one taken, and so
  // the sign, does not depend on the scheduling.
  constexpr size_t kRun = 4096;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, stock.n_vertices(), kRun),
      [&](const tbb::blocked_range<size_t>& range) {
        int hint = -1;
        for (size_t v = range.begin(); v != range.end(); ++v) {
          const Eigen::Vector3d p = to_eigen(stock.point(Mesh::VertexHandle(static_cast<int>(v))));
          const ClosestHit hit = bvh.closest(p, std::numeric_limits<double>::infinity(), hint);
          if (hit.triangle < 0) continue;
          hint = hit.triangle;
          const Triangle& t = bvh.triangle(hit.triangle);
          const Eigen::Vector3d n = (t.b - t.a).cross(t.c - t.a);
          dev[v] = (p - hit.point).dot(n) >= 0.0 ? hit.distance : -hit.distance;
        }
      },
      tbb::simple_partitioner());
  return dev;
}

nlohmann::json build_scene_json(const ReportInputs& in, const ReportOptions& options) {
  const Scene& scene = *in.scene;
  nlohmann::json layers = nlohmann::json::array();
  const std::vector<MeshLayer> meshes = mesh_layers(in, options);
  const std::vector<size_t> budget = layer_budgets(meshes, options.max_triangles);
  for (size_t i = 0; i < meshes.size(); ++i) layers.push_back(mesh_layer_json(meshes[i], budget[i], in));

  if (auto path = path_layer(in)) layers.push_back(std::move(*path));
  nlohmann::json tool_poses = nlohmann::json::array();
  if (in.oriented && !in.oriented->rows.empty()) {
    layers.push_back(axes_layer(in.oriented->rows, scene, options.axis_samples));
    if (auto pose = tightest_row_pose(in.oriented->rows, scene.tool)) tool_poses.push_back(std::move(*pose));
  }

  const auto poses = block_poses(in);
  add_site_layers(layers, in, poses);
  if (!in.collisions.empty()) {
    auto it = poses.find(in.collisions.front().block);
    if (it != poses.end())
      tool_poses.push_back(
          pose_json(it->second, "first collision, block " + std::to_string(in.collisions.front().block)));
  }
  if (!tool_poses.empty())
    layers.push_back({{"id", "tool"}, {"label", "Tool body at the tightest row / first collision"}, {"kind", "tool"},
                      {"color", "#f2c14e"}, {"visible", true}, {"profile", tool_profile(scene.tool)},
                      {"poses", tool_poses}});
  return {{"up", {0, 0, 1}}, {"layers", layers}};
}

}  // namespace tf::reporting
