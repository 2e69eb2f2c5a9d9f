#include "report_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

namespace tf::reporting {

IndexedMesh to_indexed(const Mesh& mesh, const std::vector<double>* values) {
  IndexedMesh out;
  out.V.reserve(mesh.n_vertices());
  for (auto vh : mesh.vertices()) {
    const auto& p = mesh.point(vh);
    out.V.emplace_back(float(p[0]), float(p[1]), float(p[2]));
  }
  out.F.reserve(mesh.n_faces());
  for (auto fh : mesh.faces()) {
    std::array<uint32_t, 3> f{};
    int k = 0;
    for (auto vh : mesh.fv_range(fh)) {
      if (k < 3) f[k] = uint32_t(vh.idx());
      ++k;
    }
    if (k == 3) out.F.push_back(f);
  }
  if (values) {
    if (values->size() != out.V.size())
      throw std::invalid_argument("report: " + std::to_string(values->size()) + " deviation values for " +
                                  std::to_string(out.V.size()) + " stock vertices");
    out.values.assign(values->begin(), values->end());
  }
  return out;
}

namespace {

Eigen::Vector3f face_normal(const IndexedMesh& m, const std::array<uint32_t, 3>& f) {
  return (m.V[f[1]] - m.V[f[0]]).cross(m.V[f[2]] - m.V[f[0]]);  // length = twice the area
}

double surface_area(const IndexedMesh& m) {
  double a = 0.0;
  for (const auto& f : m.F) a += 0.5 * double(face_normal(m, f).norm());
  return a;
}

}  // namespace

IndexedMesh cluster_decimate(const IndexedMesh& mesh, double cell) {
  if (!(cell > 0.0) || mesh.V.empty()) return mesh;
  Eigen::Vector3f lo = mesh.V[0], hi = mesh.V[0];
  for (const auto& v : mesh.V) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // 20 bits per axis in the key: a finer grid than that would not decimate anything anyway.
  constexpr double kMaxCells = double(1 << 20) - 1.0;
  if ((hi - lo).maxCoeff() / cell > kMaxCells) return mesh;

  std::vector<Eigen::Vector3f> normal(mesh.V.size(), Eigen::Vector3f::Zero());
  for (const auto& f : mesh.F) {
    const Eigen::Vector3f n = face_normal(mesh, f);
    for (uint32_t i : f) normal[i] += n;
  }

  std::unordered_map<uint64_t, uint32_t> cluster_of_key;
  std::vector<uint32_t> cluster(mesh.V.size());
  std::vector<Eigen::Vector3d> sum;
  std::vector<double> value_sum;
  std::vector<uint32_t> count;
  const bool has_values = !mesh.values.empty();
  for (size_t i = 0; i < mesh.V.size(); ++i) {
    const Eigen::Vector3f& p = mesh.V[i];
    uint64_t key = 0;
    for (int a = 0; a < 3; ++a) key = (key << 20) | uint64_t(std::floor((p[a] - lo[a]) / cell));
    const Eigen::Vector3f& n = normal[i];
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    const uint64_t side = n.squaredNorm() == 0.0f ? 6u : uint64_t(2 * axis + (n[axis] < 0.0f ? 1 : 0));
    key = (key << 3) | side;
    auto [it, inserted] = cluster_of_key.try_emplace(key, uint32_t(sum.size()));
    if (inserted) {
      sum.emplace_back(Eigen::Vector3d::Zero());
      value_sum.push_back(0.0);
      count.push_back(0);
    }
    const uint32_t c = it->second;
    cluster[i] = c;
    sum[c] += p.cast<double>();
    if (has_values) value_sum[c] += mesh.values[i];
    ++count[c];
  }

  IndexedMesh out;
  out.V.resize(sum.size());
  for (size_t c = 0; c < sum.size(); ++c) out.V[c] = (sum[c] / double(count[c])).cast<float>();
  if (has_values) {
    out.values.resize(sum.size());
    for (size_t c = 0; c < sum.size(); ++c) out.values[c] = float(value_sum[c] / double(count[c]));
  }
  for (const auto& f : mesh.F) {
    const std::array<uint32_t, 3> g{cluster[f[0]], cluster[f[1]], cluster[f[2]]};
    if (g[0] != g[1] && g[1] != g[2] && g[0] != g[2]) out.F.push_back(g);
  }
  // Drop clusters no triangle uses any more, so the packed arrays stay small.
  std::vector<int64_t> remap(out.V.size(), -1);
  IndexedMesh packed;
  for (auto& f : out.F)
    for (auto& i : f) {
      if (remap[i] < 0) {
        remap[i] = int64_t(packed.V.size());
        packed.V.push_back(out.V[i]);
        if (has_values) packed.values.push_back(out.values[i]);
      }
      i = uint32_t(remap[i]);
    }
  packed.F = std::move(out.F);
  return packed;
}

IndexedMesh decimate_to_budget(const IndexedMesh& mesh, size_t max_triangles) {
  if (mesh.F.size() <= max_triangles) return mesh;
  if (max_triangles == 0) return IndexedMesh{};
  // Clustering a smooth surface of area A on cells of side c leaves about 2 A / c^2 triangles.
  double cell = std::sqrt(2.0 * surface_area(mesh) / double(max_triangles));
  if (!(cell > 0.0)) return IndexedMesh{};
  for (int pass = 0; pass < 16; ++pass) {
    IndexedMesh out = cluster_decimate(mesh, cell);
    if (out.F.size() <= max_triangles) return out;
    cell *= std::max(1.15, std::sqrt(double(out.F.size()) / double(max_triangles)));
  }
  return IndexedMesh{};  // unreachable in practice: a cell the size of the mesh leaves no triangles
}

std::string base64(const void* data, size_t bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes; i += 3) {
    const uint32_t v = (uint32_t(b[i]) << 16) | (uint32_t(b[i + 1]) << 8) | b[i + 2];
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes) {
    uint32_t v = uint32_t(b[i]) << 16;
    if (i + 1 < bytes) v |= uint32_t(b[i + 1]) << 8;
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string base64_floats(const std::vector<float>& v) { return base64(v.data(), v.size() * sizeof(float)); }

nlohmann::json encode_mesh(const IndexedMesh& mesh) {
  nlohmann::json j;
  Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
  if (!mesh.V.empty()) {
    lo = hi = mesh.V[0];
    for (const auto& v : mesh.V) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  }
  Eigen::Vector3f scale = (hi - lo) / 65535.0f;
  for (int a = 0; a < 3; ++a)
    if (!(scale[a] > 0.0f)) scale[a] = 1.0f;
  std::vector<uint16_t> q(mesh.V.size() * 3);
  for (size_t i = 0; i < mesh.V.size(); ++i)
    for (int a = 0; a < 3; ++a)
      q[3 * i + a] = uint16_t(std::clamp(std::lround((mesh.V[i][a] - lo[a]) / scale[a]), 0L, 65535L));
  j["positions"] = base64(q.data(), q.size() * sizeof(uint16_t));
  j["origin"] = {lo.x(), lo.y(), lo.z()};
  j["scale"] = {scale.x(), scale.y(), scale.z()};
  j["vertices"] = mesh.V.size();
  j["triangles"] = mesh.F.size();
  if (mesh.V.size() <= 65536) {
    std::vector<uint16_t> idx;
    idx.reserve(mesh.F.size() * 3);
    for (const auto& f : mesh.F)
      for (uint32_t i : f) idx.push_back(uint16_t(i));
    j["indices"] = base64(idx.data(), idx.size() * sizeof(uint16_t));
    j["index_bits"] = 16;
  } else {
    std::vector<uint32_t> idx;
    idx.reserve(mesh.F.size() * 3);
    for (const auto& f : mesh.F) idx.insert(idx.end(), f.begin(), f.end());
    j["indices"] = base64(idx.data(), idx.size() * sizeof(uint32_t));
    j["index_bits"] = 32;
  }
  if (!mesh.values.empty()) j["values"] = base64_floats(mesh.values);
  return j;
}

}  // namespace tf::reporting
