#include "report_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace tf::reporting {

IndexedMesh to_indexed(const IndexedTriangles& mesh) {
  IndexedMesh out;
  out.V.reserve(mesh.V.size());
  for (const auto& p : mesh.V) out.V.push_back(p.cast<float>());
  out.F = mesh.F;
  out.values.assign(mesh.values.begin(), mesh.values.end());
  out.labels = mesh.labels;
  return out;
}

IndexedMesh to_indexed(const Mesh& mesh, const std::vector<double>* values) {
  return to_indexed(indexed_triangles(mesh, values));
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
  if (!mesh.labels.empty()) j["labels"] = base64(mesh.labels.data(), mesh.labels.size() * sizeof(uint32_t));
  return j;
}

}  // namespace tf::reporting
