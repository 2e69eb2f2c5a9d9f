// Profile text format: parsing, closure, self-crossing check, formatting. See docs/offset.md.
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "segment_bvh.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/offset/offset.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;

struct RawElement {
  double R;
  Vector2d chord;
  bool long_arc;
  int line;
};

std::vector<std::string> tokens_of(std::string line) {
  if (auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
  for (char& ch : line)
    if (ch == ',' || ch == ';' || ch == '\t' || ch == '\r') ch = ' ';
  std::istringstream ss(line);
  std::vector<std::string> out;
  for (std::string t; ss >> t;) out.push_back(t);
  return out;
}

bool equals_word(const std::string& s, const char* word) {
  std::string u = s;
  for (char& ch : u) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return u == word;
}

// The arc or line from a to b described by R (signed) and the LONG flag.
Segment element_segment(const Vector2d& a, const Vector2d& b, double R, bool long_arc) {
  if (R == 0) return make_line(a, b);
  const Vector2d d = b - a;
  const double L = d.norm();
  const double r = std::abs(R);
  const double h = std::sqrt(std::max(0.0, r * r - 0.25 * L * L));
  const Vector2d left = Vector2d(-d.y(), d.x()) / L;
  const double side = (R > 0 ? 1.0 : -1.0) * (long_arc ? -1.0 : 1.0);
  Segment s;
  s.a = a;
  s.b = b;
  s.c = 0.5 * (a + b) + side * h * left;
  s.r = std::max(r, 0.5 * L);  // a half circle whose decimal chord is a hair longer than 2|R|
  const double half = std::asin(std::min(1.0, 0.5 * L / r));
  const double sw = long_arc ? 2 * std::numbers::pi - 2 * half : 2 * half;
  s.sweep = R > 0 ? sw : -sw;
  return s;
}

double profile_scale(const Profile& p) {
  Eigen::AlignedBox2d box;
  box.setEmpty();
  for (const auto& e : p.elements) box.extend(bounding_box(e));
  return std::max(1.0, box.diagonal().norm());
}
}  // namespace

Profile parse_profile(std::string_view text, const std::string& file) {
  if (text.find('\0') != std::string_view::npos) throw InputError(file, 0, "", "binary data in a profile file");
  auto within = [&](double v, int line, const std::string& field, const char* what = "the value") {
    if (std::abs(v) <= kMaxLengthMm) return v;
    std::ostringstream msg;
    msg << what << " " << v << " is beyond +-1000000 mm";
    throw InputError(file, line, field, msg.str());
  };
  std::istringstream in{std::string(without_utf8_bom(text))};
  std::string line;
  int n = 0;
  bool have_start = false;
  Vector2d start(0, 0), pos(0, 0);  // pos: where the elements so far end
  std::vector<RawElement> raw;
  while (std::getline(in, line)) {
    ++n;
    const auto tok = tokens_of(line);
    if (tok.empty()) continue;
    if (!have_start) {
      if (!equals_word(tok[0], "START"))
        throw InputError(file, n, "START", "the first line must be 'START x y', found '" + tok[0] + "'");
      if (tok.size() != 3) throw InputError(file, n, "START", "expected 'START x y'");
      start = {within(parse_number(tok[1], file, n, "x"), n, "x"), within(parse_number(tok[2], file, n, "y"), n, "y")};
      pos = start;
      have_start = true;
      continue;
    }
    if (equals_word(tok[0], "START")) throw InputError(file, n, "START", "a second START line");
    if (tok.size() != 3 && tok.size() != 4)
      throw InputError(file, n, "", "expected 'R DX DY' or 'R DX DY LONG', found " + std::to_string(tok.size()) +
                                        " fields");
    RawElement e;
    e.R = within(parse_number(tok[0], file, n, "R"), n, "R");
    e.chord = {within(parse_number(tok[1], file, n, "DX"), n, "DX"), within(parse_number(tok[2], file, n, "DY"), n, "DY")};
    pos += e.chord;
    within(pos.x(), n, "DX", "the element's end x");
    within(pos.y(), n, "DY", "the element's end y");
    e.long_arc = false;
    e.line = n;
    if (tok.size() == 4) {
      if (!equals_word(tok[3], "LONG")) throw InputError(file, n, "LONG", "expected LONG, found '" + tok[3] + "'");
      if (e.R == 0) throw InputError(file, n, "LONG", "LONG on a line (R = 0)");
      e.long_arc = true;
    }
    const double L = e.chord.norm();
    if (L == 0) throw InputError(file, n, "DX", "element of zero length (DX = DY = 0)");
    // Below the 1e-6 mm the closure snaps: such an element has no direction the geometry can use, and a
    // 1e-12 mm one was reported as a self-crossing of its neighbours (black-box testing).
    if (L < 1e-6)
      throw InputError(file, n, "DX", "element " + fixed(L, 12) + " mm long, below the profile's 1e-6 mm resolution (join it "
                                      "to a neighbour)");
    // A half circle written in decimals (R 1.41421356 over the chord (2, 2)) has its chord up to about
    // 1e-8 longer than 2|R|; it was refused (black-box testing).
    if (e.R != 0 && L > 2 * std::abs(e.R) * (1 + 1e-9) + 2e-8)
      throw InputError(file, n, "R", "chord " + fixed(L, 9) + " is longer than the arc's diameter 2|R| = " +
                                         fixed(2 * std::abs(e.R), 9));
    raw.push_back(e);
  }
  if (!have_start) throw InputError(file, 0, "", "empty profile: no 'START x y' line");
  if (raw.empty()) throw InputError(file, n, "", "profile has no elements after START");

  // Closure: accumulated decimal input rarely lands bit-exactly on the start; snap within 1e-6 mm.
  Vector2d end = start;
  for (const auto& e : raw) end += e.chord;
  const double miss = (end - start).norm();
  if (miss > 1e-6)
    throw InputError(file, raw.back().line, "",
                     "profile is not closed: it ends at (" + fixed(end.x(), 6) + ", " + fixed(end.y(), 6) + "), " +
                         fixed(miss, 6) + " mm from its START (" + fixed(start.x(), 6) + ", " + fixed(start.y(), 6) +
                         ")");
  Profile p;
  p.file = file;
  Vector2d a = start;
  for (size_t i = 0; i < raw.size(); ++i) {
    const Vector2d b = i + 1 == raw.size() ? start : Vector2d(a + raw[i].chord);
    if (i + 1 == raw.size()) {
      const double L = (b - a).norm();
      if (L == 0 || (raw[i].R != 0 && L > 2 * std::abs(raw[i].R) * (1 + 1e-9) + 2e-8))
        throw InputError(file, raw[i].line, "", "the closing element degenerates when snapped onto START");
    }
    Segment s = element_segment(a, b, raw[i].R, raw[i].long_arc);
    s.line = raw[i].line;
    p.elements.push_back(s);
    a = b;
  }
  return p;
}

void validate_profile(const Profile& p) {
  const size_t n = p.elements.size();
  const double scale = profile_scale(p);
  const double tol = 1e-9 * scale;
  const double vertex_tol = std::max(1e-6, 1e-8 * scale);
  // A closed profile needs to turn; a cusp (the direction reversing at a vertex) has no offset.
  for (size_t i = 0; i < n; ++i) {
    const Segment& s = p.elements[i];
    const Segment& next = p.elements[(i + 1) % n];
    const Vector2d t0 = tangent_at(s, 1.0), t1 = tangent_at(next, 0.0);
    if (t0.dot(t1) < -1 + 1e-12)
      throw InputError(p.file, next.line, "", "the profile reverses onto itself at this element's start");
  }
  std::vector<Eigen::AlignedBox2d> boxes;
  for (const auto& e : p.elements) {
    auto b = bounding_box(e);
    boxes.push_back(Eigen::AlignedBox2d(b.min().array() - tol, b.max().array() + tol));
  }
  detail::BoxTree tree(boxes);
  for (size_t i = 0; i < n; ++i) {
    tree.query(boxes[i], [&](int j) {
      if (static_cast<size_t>(j) <= i) return;
      const bool next = static_cast<size_t>(j) == i + 1, wrap = (j + 1) % n == i;
      for (const auto& c : intersect(p.elements[i], p.elements[j], tol)) {
        if (next && (c.p - p.elements[i].b).norm() <= vertex_tol) continue;
        if (wrap && (c.p - p.elements[i].a).norm() <= vertex_tol) continue;
        const int line = std::max(p.elements[i].line, p.elements[j].line);
        const int other = std::min(p.elements[i].line, p.elements[j].line);
        throw InputError(p.file, line, "",
                         "self-crossing profile: this element meets the element on line " + std::to_string(other) +
                             " at (" + fixed(c.p.x(), 6) + ", " + fixed(c.p.y(), 6) + ")");
      }
    });
  }
}

Profile read_profile(const std::filesystem::path& file) {
  Profile p = parse_profile(read_text_file(file, "profile file"), file.string());
  validate_profile(p);
  return p;
}

std::string format_profile(const Profile& p) {
  std::ostringstream out;
  if (p.elements.empty()) return "";
  // Chords from rounded end points, so that the printed chords add up to a closed profile exactly.
  auto r9 = [](const Vector2d& v) { return Vector2d(std::round(v.x() * 1e9) / 1e9, std::round(v.y() * 1e9) / 1e9); };
  out << "START " << fixed(p.elements[0].a.x(), 9) << " " << fixed(p.elements[0].a.y(), 9) << "\n";
  for (const auto& e : p.elements) {
    const double R = e.is_arc() ? (e.sweep > 0 ? e.r : -e.r) : 0.0;
    const Vector2d d = r9(e.b) - r9(e.a);
    out << fixed(R, 9) << " " << fixed(d.x(), 9) << " " << fixed(d.y(), 9);
    if (std::abs(e.sweep) > std::numbers::pi) out << " LONG";
    out << "\n";
  }
  return out.str();
}

}  // namespace tf::offset
