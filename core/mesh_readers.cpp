#include "mesh_readers.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>

#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/internal/quiet_openmesh.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::detail {
namespace fs = std::filesystem;

Mesh mesh_from_triangles(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& T) {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> vh;
  vh.reserve(V.size());
  for (const auto& p : V) vh.push_back(mesh.add_vertex(to_om(p)));
  const internal::QuietOpenMesh quiet;  // a refused face gets its own vertices below
  for (const auto& t : T) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    if (!mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) {
      mesh.add_face(mesh.add_vertex(to_om(V[t[0]])), mesh.add_vertex(to_om(V[t[1]])), mesh.add_vertex(to_om(V[t[2]])));
    }
  }
  return mesh;
}

namespace {

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "", "cannot open mesh file");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A text mesh's contents without the UTF-8 byte order mark an editor may put first (an OBJ's first vertex
// had been skipped as an unknown keyword, every face then naming the wrong vertices: black-box testing).
std::string text_without_bom(std::string data) {
  if (without_utf8_bom(data).size() != data.size()) data.erase(0, 3);
  return data;
}

// Welds exactly equal coordinates (STL repeats every vertex per facet).
struct Welder {
  std::map<std::array<double, 3>, int> index;
  std::vector<Eigen::Vector3d> vertices;
  int add(const Eigen::Vector3d& p) {
    auto [it, inserted] = index.try_emplace({p.x(), p.y(), p.z()}, static_cast<int>(vertices.size()));
    if (inserted) vertices.push_back(p);
    return it->second;
  }
};

Mesh read_binary_stl(const std::string& data, const std::string& name) {
  uint32_t n = 0;
  std::memcpy(&n, data.data() + 80, 4);
  Welder w;
  std::vector<Eigen::Vector3i> tris;
  tris.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    const char* f = data.data() + 84 + 50 * static_cast<size_t>(i);
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      float c[3];
      std::memcpy(c, f + 12 + 12 * k, 12);
      const Eigen::Vector3d p(c[0], c[1], c[2]);
      if (!p.allFinite()) throw InputError(name, 0, "facet " + std::to_string(i + 1), "non-finite vertex coordinate");
      t[k] = w.add(p);
    }
    tris.push_back(t);
  }
  return mesh_from_triangles(w.vertices, tris);
}

Mesh read_ascii_stl(const std::string& data, const std::string& name) {
  std::istringstream in(data);
  std::string line;
  int ln = 0, in_loop = -1;
  Welder w;
  std::vector<Eigen::Vector3i> tris;
  std::vector<int> loop;
  while (std::getline(in, line)) {
    ++ln;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    if (word == "vertex") {
      if (in_loop < 0) throw InputError(name, ln, "vertex", "vertex outside an 'outer loop'");
      std::string c[3];
      ls >> c[0] >> c[1] >> c[2];
      const Eigen::Vector3d p(parse_number(c[0], name, ln, "vertex"), parse_number(c[1], name, ln, "vertex"),
                              parse_number(c[2], name, ln, "vertex"));
      loop.push_back(w.add(p));
    } else if (word == "outer") {
      if (in_loop >= 0) throw InputError(name, ln, "outer loop", "nested 'outer loop'");
      in_loop = ln;
      loop.clear();
    } else if (word == "endloop") {
      if (in_loop < 0) throw InputError(name, ln, "endloop", "'endloop' without 'outer loop'");
      if (loop.size() < 3) throw InputError(name, in_loop, "outer loop", "a facet needs 3 vertices");
      for (size_t k = 1; k + 1 < loop.size(); ++k) tris.emplace_back(loop[0], loop[k], loop[k + 1]);
      in_loop = -1;
    } else if (word != "solid" && word != "facet" && word != "endfacet" && word != "endsolid") {
      throw InputError(name, ln, word, "unknown STL keyword");
    }
  }
  if (in_loop >= 0) throw InputError(name, in_loop, "outer loop", "not closed by 'endloop'");
  return mesh_from_triangles(w.vertices, tris);
}

// Splits "a/b/c" and returns the vertex index (1-based, negative counts from the end), 0-based out.
int obj_index(const std::string& token, int vertex_count, const std::string& name, int ln) {
  const std::string head = token.substr(0, token.find('/'));
  const double v = parse_number(head, name, ln, "f");
  if (v != static_cast<int>(v) || v == 0) throw InputError(name, ln, "f", "bad vertex index '" + token + "'");
  const int i = v > 0 ? static_cast<int>(v) - 1 : vertex_count + static_cast<int>(v);
  if (i < 0 || i >= vertex_count) throw InputError(name, ln, "f", "vertex index " + head + " out of range");
  return i;
}

}  // namespace

Mesh read_stl(const fs::path& file) {
  const std::string data = slurp(file);
  const std::string name = file.string();
  if (data.size() >= 84) {
    uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50 * static_cast<size_t>(n)) return read_binary_stl(data, name);
  }
  const std::string text = text_without_bom(data);
  if (text.compare(0, 5, "solid") != 0 && text.find("facet") == std::string::npos)
    throw InputError(name, 0, "", "neither a binary STL (size does not match the facet count) nor an ASCII STL");
  return read_ascii_stl(text, name);
}

Mesh read_obj(const fs::path& file) {
  const std::string data = text_without_bom(slurp(file));
  const std::string name = file.string();
  std::istringstream in(data);
  std::string line;
  int ln = 0;
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> T;
  while (std::getline(in, line)) {
    ++ln;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word) || word[0] == '#') continue;
    if (word == "v") {
      std::string c[3];
      ls >> c[0] >> c[1] >> c[2];
      V.emplace_back(parse_number(c[0], name, ln, "v"), parse_number(c[1], name, ln, "v"),
                     parse_number(c[2], name, ln, "v"));
    } else if (word == "f") {
      std::vector<int> idx;
      std::string tok;
      while (ls >> tok) idx.push_back(obj_index(tok, static_cast<int>(V.size()), name, ln));
      if (idx.size() < 3) throw InputError(name, ln, "f", "a face needs at least 3 vertices");
      for (size_t k = 1; k + 1 < idx.size(); ++k) T.emplace_back(idx[0], idx[k], idx[k + 1]);
    }
    // vt, vn, g, o, s, usemtl, mtllib, l, ...: not geometry we use.
  }
  return mesh_from_triangles(V, T);
}

Mesh read_off(const fs::path& file) {
  const std::string data = text_without_bom(slurp(file));
  const std::string name = file.string();
  // Tokenise with line numbers, dropping comments.
  std::vector<std::pair<std::string, int>> tok;
  {
    std::istringstream in(data);
    std::string line;
    int ln = 0;
    while (std::getline(in, line)) {
      ++ln;
      line = line.substr(0, line.find('#'));
      std::istringstream ls(line);
      std::string t;
      while (ls >> t) tok.emplace_back(t, ln);
    }
  }
  size_t k = 0;
  auto next = [&](const char* field) -> std::pair<std::string, int> {
    if (k >= tok.size()) throw InputError(name, tok.empty() ? 0 : tok.back().second, field, "unexpected end of file");
    return tok[k++];
  };
  auto integer = [&](const char* field, long lo, long hi) {
    auto [t, ln] = next(field);
    const double v = parse_number(t, name, ln, field);
    if (v != static_cast<long>(v) || v < lo || v > hi)
      throw InputError(name, ln, field, "'" + t + "' is not a whole number in [" + std::to_string(lo) + ", " +
                                            std::to_string(hi) + "]");
    return static_cast<long>(v);
  };
  auto [head, hl] = next("OFF");
  // COFF: a colour after each vertex, on its line (what the stock mesh is written as).
  const bool coloured = head == "COFF";
  if (head != "OFF" && !coloured)
    throw InputError(name, hl, "OFF", "missing 'OFF' header (plain OFF and COFF are read)");
  const long nv = integer("vertex count", 0, 50'000'000);
  const long nf = integer("face count", 0, 100'000'000);
  integer("edge count", 0, 1'000'000'000);
  // Counts larger than what the file holds are refused before anything is allocated for them.
  if (static_cast<size_t>(nv) * 3 + static_cast<size_t>(nf) * 4 > tok.size() - k)
    throw InputError(name, hl, "OFF", "the vertex and face counts exceed what the file contains");
  std::vector<Eigen::Vector3d> V(nv);
  for (long i = 0; i < nv; ++i) {
    for (int c = 0; c < 3; ++c) {
      auto [t, ln] = next("vertex");
      V[i][c] = parse_number(t, name, ln, "vertex");
      if (coloured && c == 2)
        while (k < tok.size() && tok[k].second == ln) ++k;
    }
  }
  std::vector<Eigen::Vector3i> T;
  for (long i = 0; i < nf; ++i) {
    const int line = k < tok.size() ? tok[k].second : 0;
    const long n = integer("face size", 3, 1000);
    std::vector<int> idx(n);
    for (long j = 0; j < n; ++j) idx[j] = static_cast<int>(integer("face index", 0, nv - 1));
    // Colour values may follow on the same line.
    while (k < tok.size() && tok[k].second == line) ++k;
    for (long j = 1; j + 1 < n; ++j) T.emplace_back(idx[0], idx[j], idx[j + 1]);
  }
  return mesh_from_triangles(V, T);
}

}  // namespace tf::detail
