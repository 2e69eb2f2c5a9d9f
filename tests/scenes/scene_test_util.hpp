// Helpers for the scene generator tests: running the built executable, FCL models of meshes, and an
// independent distance to the impeller's analytic hub meridian.
#pragma once
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fcl/fcl.h>

#include "tiltfield/core/mesh.hpp"

namespace scene_test {
namespace fs = std::filesystem;

// A fresh empty folder under the system temp folder, removed by the destructor.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    path = fs::temp_directory_path() / ("tiltfield_test_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs TILTFIELD_EXE with `args` (a shell-quoted string), capturing stdout and stderr.
inline RunResult run_tiltfield(const std::string& args, const fs::path& scratch) {
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const std::string cmd = std::string("'") + TILTFIELD_EXE + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

using BVH = fcl::BVHModel<fcl::OBBRSSd>;

inline std::shared_ptr<BVH> fcl_model(const tf::Mesh& mesh) {
  std::vector<fcl::Vector3d> v;
  std::vector<fcl::Triangle> t;
  for (auto vh : mesh.vertices()) {
    const auto& p = mesh.point(vh);
    v.emplace_back(p[0], p[1], p[2]);
  }
  for (auto f : mesh.faces()) {
    int idx[3], k = 0;
    for (auto vh : mesh.fv_range(f)) idx[k++] = vh.idx();
    t.emplace_back(idx[0], idx[1], idx[2]);
  }
  auto m = std::make_shared<BVH>();
  m->beginModel();
  m->addSubModel(v, t);
  m->endModel();
  return m;
}

// Distance from a sphere (centre c, radius r) to the mesh surface; <= 0 when they touch.
inline double sphere_distance(const std::shared_ptr<BVH>& model, const Eigen::Vector3d& c, double r) {
  fcl::CollisionObjectd obj(model, fcl::Transform3d::Identity());
  fcl::Transform3d tr = fcl::Transform3d::Identity();
  tr.translation() = c;
  fcl::CollisionObjectd s(std::make_shared<fcl::Sphered>(r), tr);
  fcl::DistanceRequestd req;
  fcl::DistanceResultd res;
  fcl::distance(&obj, &s, req, res);
  return res.min_distance;
}

// True when the sphere (centre c, radius r) meets the mesh surface.
inline bool sphere_collides(const std::shared_ptr<BVH>& model, const Eigen::Vector3d& c, double r) {
  fcl::Transform3d tr = fcl::Transform3d::Identity();
  tr.translation() = c;
  fcl::CollisionObjectd obj(model, fcl::Transform3d::Identity());
  fcl::CollisionObjectd s(std::make_shared<fcl::Sphered>(r), tr);
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  fcl::collide(&obj, &s, req, res);
  return res.isCollision();
}

// True when the capsule (segment a-b swept by radius r) meets the mesh surface.
inline bool capsule_collides(const std::shared_ptr<BVH>& model, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             double r) {
  const Eigen::Vector3d d = b - a;
  fcl::Transform3d tr = fcl::Transform3d::Identity();
  tr.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d.normalized()).toRotationMatrix();
  tr.translation() = 0.5 * (a + b);
  fcl::CollisionObjectd obj(model, fcl::Transform3d::Identity());
  fcl::CollisionObjectd cap(std::make_shared<fcl::Capsuled>(r, d.norm()), tr);
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  fcl::collide(&obj, &cap, req, res);
  return res.isCollision();
}

// The impeller hub meridian written out again from the documented formula (not the generator's code):
// r = ro - (ro - ri) cos(phi), z = zi - (zi - zo) sin(phi), phi in [0, pi/2].
struct HubEllipse {
  double ri = 20, zi = 40, ro = 60, zo = 8;
  Eigen::Vector2d at(double phi) const {
    return {ro - (ro - ri) * std::cos(phi), zi - (zi - zo) * std::sin(phi)};
  }
  Eigen::Vector2d normal(double phi) const {
    return Eigen::Vector2d((zi - zo) * std::cos(phi), (ro - ri) * std::sin(phi)).normalized();
  }
  // Nearest phi to the meridian point q = (r, z), for q near the curve: Newton on the squared distance
  // from the point's own elliptic angle about the centre, clamped to the quarter.
  double nearest_phi(const Eigen::Vector2d& q) const {
    const double a = ro - ri, b = zi - zo, half = std::numbers::pi / 2;
    double phi = std::clamp(std::atan2((zi - q.y()) / b, (ro - q.x()) / a), 0.0, half);
    for (int it = 0; it < 30; ++it) {
      const Eigen::Vector2d d = at(phi) - q;
      const Eigen::Vector2d d1(a * std::sin(phi), -b * std::cos(phi)), d2(a * std::cos(phi), b * std::sin(phi));
      const double g = d.dot(d1), h = d1.dot(d1) + d.dot(d2);
      const double next = std::clamp(phi - g / (h > 1e-12 ? h : 1e-12), 0.0, half);
      if (std::abs(next - phi) < 1e-15) break;
      phi = next;
    }
    return phi;
  }
  // Distance from a 3-D point to the hub's curved surface of revolution.
  double distance(const Eigen::Vector3d& p) const {
    const Eigen::Vector2d q(std::hypot(p.x(), p.y()), p.z());
    return (at(nearest_phi(q)) - q).norm();
  }
};

// A binary STL read here without OpenMesh: triangles as indices into vertices welded by exact coordinates.
struct Soup {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
};
inline Soup read_binary_stl(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char header[80];
  in.read(header, 80);
  std::uint32_t n = 0;
  in.read(reinterpret_cast<char*>(&n), 4);
  Soup s;
  std::map<std::array<float, 3>, int> index;
  for (std::uint32_t i = 0; i < n && in; ++i) {
    float rec[12];
    in.read(reinterpret_cast<char*>(rec), 48);
    char attr[2];
    in.read(attr, 2);
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const std::array<float, 3> p{rec[3 + 3 * k], rec[4 + 3 * k], rec[5 + 3 * k]};
      auto [it, fresh] = index.emplace(p, static_cast<int>(s.v.size()));
      if (fresh) s.v.emplace_back(p[0], p[1], p[2]);
      tri[k] = it->second;
    }
    s.f.push_back(tri);
  }
  return s;
}

// Each directed edge exactly once and its reverse exactly once: a closed, consistently oriented surface.
inline bool consistently_oriented(const Soup& s) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : s.f)
    for (int i = 0; i < 3; ++i) ++count[{t[i], t[(i + 1) % 3]}];
  for (const auto& [e, c] : count) {
    if (c != 1) return false;
    auto it = count.find({e.second, e.first});
    if (it == count.end() || it->second != 1) return false;
  }
  return true;
}

}  // namespace scene_test

namespace scene_test {

inline Soup to_soup(const tf::Mesh& mesh) {
  Soup s;
  for (auto vh : mesh.vertices()) s.v.push_back(tf::to_eigen(mesh.point(vh)));
  for (auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto vh : mesh.fv_range(f)) t[k++] = vh.idx();
    s.f.push_back(t);
  }
  return s;
}

// Connected shells (triangles sharing vertices), each as its own soup.
inline std::vector<Soup> shells(const Soup& s) {
  std::vector<int> parent(s.v.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : s.f) {
    parent[find(t[0])] = find(t[1]);
    parent[find(t[1])] = find(t[2]);
  }
  std::map<int, Soup> by_root;
  for (const auto& t : s.f) by_root[find(t[0])].f.push_back(t);
  std::vector<Soup> out;
  for (auto& [root, soup] : by_root) {
    soup.v = s.v;  // indices stay valid
    out.push_back(std::move(soup));
  }
  return out;
}

inline double signed_volume(const Soup& s) {
  double v6 = 0;
  for (const auto& t : s.f) v6 += s.v[t[0]].dot(s.v[t[1]].cross(s.v[t[2]]));
  return v6 / 6.0;
}

}  // namespace scene_test
