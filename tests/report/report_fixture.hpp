// A small synthetic job for the report tests: a wavy design surface, a cylindrical boss as the check
// surface, three raster passes with tilted axes, a table-table-ac machine, a few collisions and gouges,
// and a "machined" stock (the design raised by a known deviation field).
#pragma once
#include <cmath>
#include <memory>

#include "report/report.hpp"
#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/oriented_path.hpp"

namespace tf::test {

inline double wave(double x, double y) { return 2.0 * std::sin(x / 9.0) * std::cos(y / 13.0); }

// Grid surface z = wave(x, y) + dz over [0, 60] x [0, 40], `n` cells a side.
inline Mesh wavy_surface(int nx, int ny, double dz = 0.0) {
  Eigen::MatrixX3d V((nx + 1) * (ny + 1), 3);
  Eigen::MatrixX3i F(2 * nx * ny, 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = 60.0 * i / nx, y = 40.0 * j / ny;
      V.row(j * (nx + 1) + i) << x, y, wave(x, y) + dz;
    }
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      F.row(f++) << a, b, d;
      F.row(f++) << a, d, c;
    }
  return mesh_from_arrays(V, F);
}

inline Mesh boss() {  // the check surface: a cylinder r 5 at (30, 30), from z -5 to 25
  Stock s;
  s.kind = Stock::Kind::Cylinder;
  s.cylinder = {{30.0, 30.0, -5.0}, {0.0, 0.0, 1.0}, 5.0, 30.0};
  return stock_to_mesh(s, 48);
}

// A collision as the report lists it (no tool poses: the report does not draw them).
inline Collision collision(int block, int line, ToolComponent component, HitWith with, bool rapid, double depth_mm) {
  Collision c;
  c.block = block;
  c.line = line;
  c.component = component;
  c.with = with;
  c.rapid = rapid;
  c.depth_mm = depth_mm;
  c.has_poses = false;
  return c;
}

// Standard base64 decoded (the packed arrays of the viewer's JSON).
inline std::vector<unsigned char> unbase64(const std::string& s) {
  std::vector<unsigned char> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    int v = c >= 'A' && c <= 'Z' ? c - 'A' : c >= 'a' && c <= 'z' ? c - 'a' + 26 : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+' ? 62 : c == '/' ? 63 : -1;
    if (v < 0) continue;
    acc = (acc << 6) | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back((acc >> bits) & 0xff);
    }
  }
  return out;
}

struct SyntheticJob {
  Scene scene;
  OrientedPath oriented, first_plan;
  Mesh stock;
  reporting::ReportInputs inputs;
};

inline std::unique_ptr<SyntheticJob> synthetic_job() {
  auto job = std::make_unique<SyntheticJob>();
  Scene& sc = job->scene;
  sc.file = "synthetic/scene.json";
  sc.design = wavy_surface(60, 40);
  sc.check_surfaces.push_back(boss());
  sc.stock.kind = Stock::Kind::Box;
  sc.stock.box = {{0, 0, -6}, {60, 40, 6}};
  sc.planner.safety_distance = 1.0;
  MachineSpec m;
  m.name = "synthetic-trt";
  m.kinematics = KinematicsType::TableTableAC;
  m.limits['A'] = {-5.0, 110.0};
  sc.machine = m;
  const double R = sc.tool.radius();
  for (int pass = 0; pass < 3; ++pass)
    for (int i = 0; i < 60; ++i) {
      const double x = pass % 2 ? 59.0 - i : 1.0 + i, y = 12.0 + 8.0 * pass;
      const double h = 1e-4;
      Eigen::Vector3d n(-(wave(x + h, y) - wave(x - h, y)) / (2 * h), -(wave(x, y + h) - wave(x, y - h)) / (2 * h), 1.0);
      n.normalize();
      sc.path.rows.push_back({Eigen::Vector3d(x, y, wave(x, y)) + R * n, n});
    }
  Kinematics kin(*sc.machine, sc.tool.length);
  Joints prev;
  const Eigen::Vector3d boss_axis(30.0, 30.0, 0.0);
  for (size_t r = 0; r < sc.path.rows.size(); ++r) {
    const auto& row = sc.path.rows[r];
    OrientedRow o;
    o.p = row.p;
    o.lead_deg = 8.0 * std::sin(0.07 * double(r));
    o.tilt_deg = 12.0 + 6.0 * std::cos(0.05 * double(r));
    o.axis = (row.n + std::tan(o.tilt_deg * M_PI / 180.0) * Eigen::Vector3d::UnitX() +
              std::tan(o.lead_deg * M_PI / 180.0) * Eigen::Vector3d::UnitY()).normalized();
    // Clearance: the horizontal distance of the cutter location to the boss, less both radii.
    o.clearance_mm = (Eigen::Vector3d(o.p.x(), o.p.y(), 0.0) - boss_axis).norm() - 5.0 - sc.tool.shank_radius;
    job->first_plan.rows.push_back(o);
    if (o.clearance_mm < 2.0) o.clearance_mm = 2.0 + 0.3 * std::sin(double(r));  // "re-planned"
    job->oriented.rows.push_back(o);
    const auto j = kin.inverse_nearest({row_tip(o, sc.tool), o.axis}, prev);
    if (j) prev = *j;
    job->inputs.axes.push_back({int(r), int(r) + 20, prev, false, false, r < 90 ? 1 : 2});  // a tool change at row 90
    job->inputs.blocks.push_back({int(r), int(r) + 20, 4.0 + std::sin(0.1 * double(r)), 600.0 + 400.0 * std::sin(0.1 * double(r)),
                                  10.0, 80.0 + 30.0 * std::cos(0.2 * double(r)), 2.0 + std::cos(0.1 * double(r)), false});
  }
  for (int b : {20, 21, 95}) {
    job->inputs.collisions.push_back(
        collision(b, b + 20, b == 95 ? ToolComponent::Holder : ToolComponent::Shank, HitWith::Check, false, 0.25 + 0.01 * b));
    job->inputs.blocks[size_t(b)].collision = true;
  }
  job->inputs.gouges.push_back({130, 150, 0.042});
  // The machined stock: the design raised by 0.3 sin(x/7) - 0.05 (mm), the deviation known per vertex.
  job->stock = wavy_surface(90, 60);
  for (auto vh : job->stock.vertices()) {
    auto p = job->stock.point(vh);
    const double d = 0.3 * std::sin(p[0] / 7.0) - 0.05;
    p[2] += d;
    job->stock.set_point(vh, p);
    job->inputs.stock_deviation_mm.push_back(d);
  }
  auto& in = job->inputs;
  in.scene = &sc;
  in.oriented = &job->oriented;
  in.first_plan = &job->first_plan;
  in.replanned = {{25, 40}, {140, 160}};
  in.stock = &job->stock;
  in.summary.title = "synthetic wavy surface";
  in.summary.collisions_found = 14;
  in.summary.collisions_fixed = 11;
  in.summary.min_clearance_mm = 1.7;
  in.summary.removed_volume_mm3 = 123456.7;
  in.summary.resolution_mm = 0.1;
  in.summary.stages = {{"plan", 1.2}, {"post", 0.1}, {"verify", 3.4}, {"replan", 0.6}, {"verify again", 3.1}};
  return job;
}

// Blocks 10 (tool 1) cut x < 30 and 100 (tool 2) 30 <= x < 45; the rest is raw stock.
inline void label_stock(SyntheticJob& job) {
  job.inputs.stock_block.clear();
  for (auto v : job.stock.vertices()) {
    const double x = job.stock.point(v)[0];
    job.inputs.stock_block.push_back(x < 30.0 ? 10u : x < 45.0 ? 100u : 0u);
  }
}

}  // namespace tf::test
