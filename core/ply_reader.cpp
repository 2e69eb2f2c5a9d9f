// Our own PLY reader (ASCII and binary, either byte order): vertex x y z of any numeric type and the
// face list `vertex_indices` (or `vertex_index`); other elements and properties are skipped.
#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mesh_readers.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::detail {
namespace fs = std::filesystem;

namespace {

enum class Format { Ascii, BinaryLE, BinaryBE };

struct Property {
  std::string name;
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // non-empty for a list
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> props;
};

int type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// Reads binary scalars and ASCII tokens through one interface.
class Cursor {
 public:
  Cursor(const std::string& data, size_t pos, Format f, const std::string& name)
      : data_(data), pos_(pos), format_(f), name_(name) {}

  double scalar(const std::string& type, const char* field) {
    if (format_ == Format::Ascii) return ascii(field);
    const int n = type_size(type);
    if (pos_ + n > data_.size()) throw InputError(name_, 0, field, "file ends inside the binary data");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    const bool swap = (format_ == Format::BinaryBE) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(b, b + n);
    if (type == "float" || type == "float32") { float v; std::memcpy(&v, b, 4); return v; }
    if (type == "double" || type == "float64") { double v; std::memcpy(&v, b, 8); return v; }
    if (type == "char" || type == "int8") return static_cast<int8_t>(b[0]);
    if (type == "uchar" || type == "uint8") return b[0];
    if (type == "short" || type == "int16") { int16_t v; std::memcpy(&v, b, 2); return v; }
    if (type == "ushort" || type == "uint16") { uint16_t v; std::memcpy(&v, b, 2); return v; }
    if (type == "int" || type == "int32") { int32_t v; std::memcpy(&v, b, 4); return v; }
    uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  size_t remaining() const { return data_.size() - pos_; }

 private:
  double ascii(const char* field) {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    const size_t start = pos_;
    while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    if (start == pos_) throw InputError(name_, 0, field, "file ends inside the data");
    return parse_number(std::string_view(data_).substr(start, pos_ - start), name_, 0, field);
  }
  const std::string& data_;
  size_t pos_;
  Format format_;
  const std::string& name_;
};

// The header: the body's format, its elements in order, and where the body starts.
struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  size_t body = 0;  // offset of the first byte after the "end_header" line
};

// The rest of an "element <name> <count>" line.
Element parse_element(std::istringstream& ls, const std::string& name, int ln) {
  Element e;
  std::string count;
  ls >> e.name >> count;
  const double c = parse_number(count, name, ln, "element");
  if (c < 0 || c != static_cast<double>(static_cast<size_t>(c)))
    throw InputError(name, ln, "element", "bad element count");
  e.count = static_cast<size_t>(c);
  return e;
}

// The rest of a "property <type> <name>" or "property list <count type> <item type> <name>" line.
Property parse_property(std::istringstream& ls, const std::string& name, int ln) {
  Property p;
  std::string t;
  ls >> t;
  if (t == "list") {
    ls >> p.count_type >> p.type >> p.name;
    if (!type_size(p.count_type)) throw InputError(name, ln, "property", "unknown type '" + p.count_type + "'");
  } else {
    p.type = t;
    ls >> p.name;
  }
  if (!type_size(p.type)) throw InputError(name, ln, "property", "unknown type '" + p.type + "'");
  return p;
}

Header read_header(const std::string& data, const std::string& name) {
  Header hd;
  size_t pos = 0;
  int ln = 0;
  bool ended = false;
  while (pos < data.size() && !ended) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    std::string line = data.substr(pos, eol - pos);
    pos = eol + 1;
    ++ln;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (ln == 1) {
      if (w != "ply") throw InputError(name, 1, "ply", "missing 'ply' magic");
      continue;
    }
    if (w == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii") hd.format = Format::Ascii;
      else if (f == "binary_little_endian") hd.format = Format::BinaryLE;
      else if (f == "binary_big_endian") hd.format = Format::BinaryBE;
      else throw InputError(name, ln, "format", "unknown PLY format '" + f + "'");
    } else if (w == "element") {
      hd.elements.push_back(parse_element(ls, name, ln));
    } else if (w == "property") {
      if (hd.elements.empty()) throw InputError(name, ln, "property", "property before any element");
      hd.elements.back().props.push_back(parse_property(ls, name, ln));
    } else if (w == "end_header") {
      ended = true;
    } else if (w != "comment" && w != "obj_info" && !w.empty()) {
      throw InputError(name, ln, w, "unknown PLY header keyword");
    }
  }
  if (!ended) throw InputError(name, ln, "end_header", "missing 'end_header'");
  hd.body = pos;
  return hd;
}

// A list property of item `item` of element e, read as indices of the `vertices` vertices read so far.
std::vector<int> read_index_list(Cursor& cur, const Property& pr, const Element& e, size_t item, size_t vertices,
                                 const std::string& name) {
  const double n = cur.scalar(pr.count_type, e.name.c_str());
  if (n < 0 || n > 1000 || n != static_cast<int>(n))
    throw InputError(name, 0, e.name + "[" + std::to_string(item) + "]", "bad list length");
  std::vector<int> idx(static_cast<size_t>(n));
  for (auto& x : idx) {
    const double v = cur.scalar(pr.type, e.name.c_str());
    if (v < 0 || v >= static_cast<double>(vertices) || v != static_cast<int>(v))
      throw InputError(name, 0, e.name + "[" + std::to_string(item) + "]", "vertex index out of range");
    x = static_cast<int>(v);
  }
  return idx;
}

// The items of element e: a vertex's x y z into V, a face's vertex indices fanned into triangles into T;
// every other value is read past.
void read_element(Cursor& cur, const Element& e, const std::string& name, std::vector<Eigen::Vector3d>& V,
                  std::vector<Eigen::Vector3i>& T) {
  // Every element item takes at least one byte (or one ASCII character): refuse impossible counts
  // before allocating for them.
  if (e.count > cur.remaining()) throw InputError(name, 0, e.name, "element count exceeds the file's size");
  const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
  int xi = -1, yi = -1, zi = -1;
  for (size_t i = 0; i < e.props.size(); ++i) {
    if (e.props[i].name == "x") xi = static_cast<int>(i);
    if (e.props[i].name == "y") yi = static_cast<int>(i);
    if (e.props[i].name == "z") zi = static_cast<int>(i);
  }
  if (is_vertex && (xi < 0 || yi < 0 || zi < 0)) throw InputError(name, 0, "vertex", "vertex has no x, y and z");
  if (is_vertex) V.reserve(e.count);
  for (size_t item = 0; item < e.count; ++item) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < e.props.size(); ++i) {
      const auto& pr = e.props[i];
      if (pr.count_type.empty()) {
        const double v = cur.scalar(pr.type, e.name.c_str());
        if (static_cast<int>(i) == xi) p.x() = v;
        if (static_cast<int>(i) == yi) p.y() = v;
        if (static_cast<int>(i) == zi) p.z() = v;
        continue;
      }
      if (!is_face || (pr.name != "vertex_indices" && pr.name != "vertex_index")) {
        // Another list (a vertex's texture list, a face's flags): read past, whatever its values
        // (they had been checked as vertex indices: black-box testing).
        const double n = cur.scalar(pr.count_type, e.name.c_str());
        if (n < 0 || n > 1e6 || n != static_cast<double>(static_cast<long>(n)))
          throw InputError(name, 0, e.name + "[" + std::to_string(item) + "]." + pr.name, "bad list length");
        for (long k = 0; k < static_cast<long>(n); ++k) cur.scalar(pr.type, e.name.c_str());
        continue;
      }
      const std::vector<int> idx = read_index_list(cur, pr, e, item, V.size(), name);
      if (idx.size() < 3) throw InputError(name, 0, "face[" + std::to_string(item) + "]", "fewer than 3 vertices");
      for (size_t j = 1; j + 1 < idx.size(); ++j) T.emplace_back(idx[0], idx[j], idx[j + 1]);
    }
    if (is_vertex) {
      if (!p.allFinite()) throw InputError(name, 0, "vertex[" + std::to_string(item) + "]", "non-finite coordinate");
      V.push_back(p);
    }
  }
}

}  // namespace

Mesh read_ply(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "", "cannot open mesh file");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // A text header may start with a UTF-8 byte order mark, as the other readers accept.
  if (without_utf8_bom(data).size() != data.size()) data.erase(0, 3);
  const std::string name = file.string();
  const Header hd = read_header(data, name);
  Cursor cur(data, hd.body, hd.format, name);
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> T;
  for (const auto& e : hd.elements) read_element(cur, e, name, V, T);
  return mesh_from_triangles(V, T);
}

}  // namespace tf::detail
