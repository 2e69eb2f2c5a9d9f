// Test helpers for the post-processor: temporary scenes, synthetic oriented paths, running commands.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tiltfield/core/io.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/post/post.hpp"

namespace post_test {

namespace fs = std::filesystem;
constexpr double kDeg = M_PI / 180.0;

inline fs::path machine_file(const std::string& name) {
  return fs::path(TILTFIELD_SOURCE_DIR) / "scenes" / "machines" / (name + ".json");
}

// A fresh folder under the build tree, removed at the end of the test.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    std::random_device rd;
    path = fs::path(TILTFIELD_BINARY_DIR) / "test_tmp" / (tag + "-" + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

inline double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDeg;
}

inline Eigen::Vector3d polar_axis(double tilt_deg, double azimuth_deg) {
  const double t = tilt_deg * kDeg, p = azimuth_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// An impeller-like 5-axis path: the ball runs round a hub of radius ~40 mm, the tool axis leaning
// outward and sideways from 5 to 88 deg off +Z, turning about Z by more than a full turn.
inline tf::OrientedPath impeller_like_path(int rows, double radius = 40.0) {
  tf::OrientedPath path;
  for (int i = 0; i < rows; ++i) {
    const double u = double(i) / double(rows - 1);
    const double phi = 400.0 * u;  // deg, more than a turn: C has to unwind
    const double r = radius + 8.0 * std::sin(6.0 * M_PI * u);
    tf::OrientedRow row;
    row.p = {r * std::cos(phi * kDeg), r * std::sin(phi * kDeg), 15.0 + 10.0 * std::sin(4.0 * M_PI * u)};
    const double tilt = 46.5 + 41.5 * std::sin(2.0 * M_PI * u * 1.5);  // 5 .. 88 deg
    row.axis = polar_axis(tilt, phi + 25.0 * std::sin(8.0 * M_PI * u));
    path.rows.push_back(row);
  }
  return path;
}

// A 3-axis path (axis +Z) over a wavy surface.
inline tf::OrientedPath three_axis_path(int rows) {
  tf::OrientedPath path;
  for (int i = 0; i < rows; ++i) {
    const double u = double(i) / double(rows - 1);
    tf::OrientedRow row;
    row.p = {-40.0 + 80.0 * u, 10.0 * std::sin(6.0 * u), 23.0 + 2.0 * std::cos(9.0 * u)};
    row.axis = Eigen::Vector3d::UnitZ();
    path.rows.push_back(row);
  }
  return path;
}

inline void write_box_stl(const fs::path& file, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::ofstream out(file);
  out << "solid box\n";
  auto corner = [&](int k) {
    return Eigen::Vector3d((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  };
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    for (const auto& tri : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      const Eigen::Vector3d a = corner(tri[0]), b = corner(tri[1]), c = corner(tri[2]);
      const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
      out << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\nouter loop\n";
      for (const auto& v : {a, b, c}) out << "vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
      out << "endloop\nendfacet\n";
    }
  }
  out << "endsolid box\n";
}

// A scene in `dir` with a box part, a ball tool (radius 3, gauge length 60) and the given machine
// file; its input path holds the oriented rows' centres with the axes as normals. Returns the scene.
inline fs::path write_scene(const fs::path& dir, const fs::path& machine, const tf::OrientedPath& path,
                            double feed = 1500.0) {
  write_box_stl(dir / "part.stl", {-50, -50, 0}, {50, 50, 20});
  {
    std::ofstream csv(dir / "path.csv");
    csv << "x,y,z,nx,ny,nz\n";
    for (const auto& r : path.rows)
      csv << tf::fixed(r.p.x(), 9) << "," << tf::fixed(r.p.y(), 9) << "," << tf::fixed(r.p.z(), 9) << ","
          << tf::fixed(r.axis.x(), 12) << "," << tf::fixed(r.axis.y(), 12) << "," << tf::fixed(r.axis.z(), 12) << "\n";
  }
  std::ofstream scene(dir / "scene.json");
  scene << "{\n  \"units\": \"mm\",\n  \"design\": \"part.stl\",\n  \"check_surfaces\": [],\n"
        << "  \"stock\": {\"box\": {\"min\": [-50, -50, 0], \"max\": [50, 50, 25]}},\n  \"fixtures\": [],\n"
        << "  \"tool\": {\"type\": \"ball\", \"radius\": 3.0, \"flute_length\": 12.0, \"shank_radius\": 3.0,"
        << " \"length\": 60.0, \"holder\": [{\"radius\": 12.0, \"length\": 40.0}]},\n"
        << "  \"path\": {\"file\": \"path.csv\", \"feed\": " << feed << "},\n"
        << "  \"planner\": {\"lead_deg\": 0.0, \"tilt_deg\": 0.0, \"safety_distance\": 1.0},\n"
        << "  \"machine\": \"" << machine.string() << "\"\n}\n";
  return dir / "scene.json";
}

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

inline CommandResult run_command(const std::string& command) {
  CommandResult r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Distance from p to the segment a..b, mm.
inline double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double L2 = d.squaredNorm();
  const double t = L2 < 1e-300 ? 0.0 : std::clamp((p - a).dot(d) / L2, 0.0, 1.0);
  return (a + t * d - p).norm();
}

// Angle from v to the great-circle arc a..b, deg.
inline double distance_to_arc(const Eigen::Vector3d& v, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double ends = std::min(angle_deg(v, a), angle_deg(v, b));
  const Eigen::Vector3d n = a.cross(b);
  if (n.norm() < 1e-12) return ends;
  const Eigen::Vector3d u = n.normalized();
  const Eigen::Vector3d w = (v - v.dot(u) * u).normalized();
  if (std::abs(angle_deg(a, w) + angle_deg(w, b) - angle_deg(a, b)) > 1e-9) return ends;
  return std::asin(std::min(1.0, std::abs(v.dot(u)))) / kDeg;
}

// A post job on one of the bundled machines: ball R3, gauge length 60, F1500, a part of 100 x 100 x 25.
inline tf::PostJob job_for(const std::string& machine) {
  tf::PostJob job;
  job.machine = tf::read_machine_json(machine_file(machine));
  job.tool.cutter = tf::BallCutter{3.0};
  job.tool.length = 60.0;
  job.feed = 1500.0;
  job.part_bounds = Eigen::AlignedBox3d(Eigen::Vector3d(-50, -50, 0), Eigen::Vector3d(50, 50, 25));
  return job;
}

// The cutting blocks between the approach plunge and the final retract, with the joints before each.
struct Cut {
  tf::Joints from, to;
};
inline std::vector<Cut> cutting_blocks(const tf::Program& p) {
  std::vector<Cut> out;
  tf::Joints cur = p.start;
  bool plunged = false;
  for (const tf::Block& b : p.blocks) {
    if (b.motion == tf::Motion::Linear) {
      if (plunged) out.push_back({cur, b.target});
      plunged = true;
    } else {
      plunged = false;
    }
    cur = b.target;
  }
  return out;
}

}  // namespace post_test
