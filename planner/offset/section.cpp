// A profile from a part mesh: plane section, chaining, line/arc fitting. See tiltfield/offset_section.hpp.
#include <algorithm>
#include <cmath>
#include <map>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/offset/offset_section.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;

// Plane crossing of an edge, computed from the lexicographically smaller end so that both faces that
// share the edge get bit-identical points (meshes from STL may not share vertex indices).
Vector2d crossing(Eigen::Vector3d p, Eigen::Vector3d q, double z0) {
  if (std::lexicographical_compare(q.data(), q.data() + 3, p.data(), p.data() + 3)) std::swap(p, q);
  // A vertex on the plane is the crossing of every edge it ends, exactly: interpolated to t = 1 it came
  // out a bit off (14 + (-0.01 - 14)), and the section's loop did not close there (black-box testing).
  if (p.z() == z0) return p.head<2>();
  if (q.z() == z0) return q.head<2>();
  const double t = (z0 - p.z()) / (q.z() - p.z());
  return {p.x() + t * (q.x() - p.x()), p.y() + t * (q.y() - p.y())};
}

bool circle_through_samples(const Vector2d& p, const Vector2d& q, const Vector2d& r, Vector2d* c) {
  const Vector2d b = q - p, d = r - p;
  const double den = 2 * cross(b, d);
  if (std::abs(den) <= 1e-12 * b.norm() * d.norm() * std::max(b.norm(), d.norm())) return false;
  const double b2 = b.squaredNorm(), d2 = d.squaredNorm();
  *c = p + Vector2d(d.y() * b2 - b.y() * d2, b.x() * d2 - d.x() * b2) / den;
  return true;
}

// How far the part of arc s between two of its points `share` of its sweep apart lies from their chord:
// the mesh is straight between section points (black-box testing: a box's section, four corners on one
// circle, had been fitted as an arc 28 mm off its sides).
double sagitta(const Segment& s, double share) { return s.r * (1.0 - std::cos(0.5 * std::abs(s.sweep) * share)); }

bool line_fits(const std::vector<Vector2d>& P, size_t i, size_t j, double tol) {
  const Segment s = make_line(P[i], P[j]);
  if ((P[j] - P[i]).norm() == 0) return false;
  for (size_t k = i + 1; k < j; ++k)
    if (distance(s, P[k]) > tol) return false;
  return true;
}

// The arc through P[i], P[(i+j)/2], P[j] when every point between lies within tol of it, in order, and
// so does the section's straight piece between each two of them.
bool arc_fits(const std::vector<Vector2d>& P, size_t i, size_t j, double tol, Segment* arc) {
  if (j < i + 2) return false;
  const size_t m = (i + j) / 2;
  Vector2d c;
  if (!circle_through_samples(P[i], P[m], P[j], &c)) return false;
  const Segment s = make_arc_to(P[i], P[j], c, cross(P[m] - P[i], P[j] - P[m]) > 0);
  if (s.r > 1e5 || std::abs(s.sweep) >= 2 * M_PI - 1e-9) return false;
  double last = 0;
  for (size_t k = i + 1; k < j; ++k) {
    double t = 0;
    if (distance(s, P[k], &t) > tol) return false;
    const double tk = parameter_of(s, P[k]);
    if (tk < last - 1e-12 || tk > 1) return false;  // points must run along the arc in order
    if (sagitta(s, tk - last) > tol) return false;
    last = tk;
  }
  if (sagitta(s, 1.0 - last) > tol) return false;
  *arc = s;
  return true;
}
double polygon_area(const std::vector<Vector2d>& loop) {
  double a = 0;
  for (size_t i = 0; i < loop.size(); ++i) a += cross(loop[i], loop[(i + 1) % loop.size()]);
  return 0.5 * a;
}

// Crossing number of the ray from q toward +x.
bool point_in_polygon(const std::vector<Vector2d>& loop, const Vector2d& q) {
  bool in = false;
  for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++)
    if ((loop[i].y() > q.y()) != (loop[j].y() > q.y()) &&
        q.x() < loop[j].x() + (q.y() - loop[j].y()) / (loop[i].y() - loop[j].y()) * (loop[i].x() - loop[j].x()))
      in = !in;
  return in;
}
}  // namespace

double parse_plane(const std::string& text) {
  std::string s;
  for (char ch : text)
    if (ch != ' ') s += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (s.size() < 3 || s.rfind("z=", 0) != 0) throw InputError("", 0, "plane", "expected 'z=H', got '" + text + "'");
  return parse_number(s.substr(2), "", 0, "plane");
}

std::vector<std::vector<Vector2d>> section_loops(const Mesh& mesh, double z0) {
  std::vector<std::pair<Vector2d, Vector2d>> segs;
  for (auto f : mesh.faces()) {
    std::vector<Eigen::Vector3d> v;
    for (auto vh : mesh.fv_range(f)) v.push_back(to_eigen(mesh.point(vh)));
    if (v.size() != 3) continue;
    std::vector<Vector2d> pts;
    for (int k = 0; k < 3; ++k) {
      const auto& p = v[k];
      const auto& q = v[(k + 1) % 3];
      if ((p.z() >= z0) != (q.z() >= z0)) pts.push_back(crossing(p, q, z0));
    }
    if (pts.size() != 2 || pts[0] == pts[1]) continue;
    const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]);
    // Material on the left: the outward normal points to the right of the direction of travel.
    const Vector2d dir(-n.y(), n.x());
    if ((pts[1] - pts[0]).dot(dir) < 0) std::swap(pts[0], pts[1]);
    segs.emplace_back(pts[0], pts[1]);
  }
  auto key = [](const Vector2d& p) { return std::make_pair(p.x(), p.y()); };
  std::multimap<std::pair<double, double>, size_t> from;
  for (size_t k = 0; k < segs.size(); ++k) from.emplace(key(segs[k].first), k);
  std::vector<char> used(segs.size(), 0);
  std::vector<std::vector<Vector2d>> loops;
  for (size_t k = 0; k < segs.size(); ++k) {
    if (used[k]) continue;
    std::vector<Vector2d> loop;
    size_t cur = k;
    bool closed = false;
    while (true) {
      used[cur] = 1;
      loop.push_back(segs[cur].first);
      const Vector2d end = segs[cur].second;
      if (end == segs[k].first) {
        closed = true;
        break;
      }
      size_t next = segs.size();
      for (auto [it, last] = from.equal_range(key(end)); it != last; ++it)
        if (!used[it->second]) {
          next = it->second;
          break;
        }
      if (next == segs.size()) break;
      cur = next;
    }
    if (closed && loop.size() >= 3) loops.push_back(std::move(loop));
  }
  return loops;
}

Profile fit_profile(const std::vector<Vector2d>& loop_in, double tol, const std::string& file) {
  std::vector<Vector2d> P;
  for (const auto& p : loop_in)
    if (P.empty() || (p - P.back()).norm() > 1e-9) P.push_back(p);
  while (P.size() > 1 && (P.front() - P.back()).norm() <= 1e-9) P.pop_back();
  if (P.size() < 3) throw InputError(file, 0, "", "section has fewer than three distinct points");
  // Start at the sharpest corner so that no arc is cut in two at the seam.
  const size_t n = P.size();
  size_t start = 0;
  double sharpest = -1;
  for (size_t k = 0; k < n; ++k) {
    const Vector2d a = (P[k] - P[(k + n - 1) % n]).normalized(), b = (P[(k + 1) % n] - P[k]).normalized();
    const double turn = std::abs(std::atan2(cross(a, b), a.dot(b)));
    if (turn > sharpest) sharpest = turn, start = k;
  }
  std::vector<Vector2d> Q;
  for (size_t k = 0; k <= n; ++k) Q.push_back(P[(start + k) % n]);

  Profile profile;
  profile.file = file;
  size_t i = 0;
  while (i < n) {
    // Exponential then binary search for the longest run that a line or an arc fits.
    auto fits = [&](size_t j, Segment* s) {
      if (line_fits(Q, i, j, tol)) {
        *s = make_line(Q[i], Q[j]);
        return true;
      }
      return arc_fits(Q, i, j, tol, s);
    };
    Segment best = make_line(Q[i], Q[i + 1]);
    size_t good = i + 1, step = 1;
    Segment s;
    while (good + step <= n && fits(good + step, &s)) good += step, best = s, step *= 2;
    size_t lo = good, hi = std::min(n + 1, good + step);
    while (hi - lo > 1) {
      const size_t mid = (lo + hi) / 2;
      if (mid <= n && fits(mid, &s))
        lo = mid, best = s;
      else
        hi = mid;
    }
    best.b = Q[lo];
    profile.elements.push_back(best);
    i = lo;
  }
  profile.elements.back().b = profile.elements.front().a;
  return profile;
}

Profile profile_from_mesh(const std::filesystem::path& mesh_file, double z0, const SectionOptions& options,
                          std::vector<SectionLoop>* left_out) {
  const Mesh mesh = load_mesh(mesh_file);
  const auto loops = section_loops(mesh, z0);
  if (loops.empty())
    throw InputError(mesh_file.string(), 0, "plane", "the plane z=" + fixed(z0, 6) + " does not cut the mesh in a closed section");
  std::vector<std::pair<double, size_t>> by_area;  // largest first
  for (size_t k = 0; k < loops.size(); ++k) by_area.emplace_back(std::abs(polygon_area(loops[k])), k);
  std::stable_sort(by_area.begin(), by_area.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  if (options.loop < 1 || static_cast<size_t>(options.loop) > loops.size())
    throw InputError(mesh_file.string(), 0, "loop",
                     std::to_string(options.loop) + ": the section at z=" + fixed(z0, 6) + " has " + std::to_string(loops.size()) +
                         " loop(s)");
  const auto& taken = loops[by_area[static_cast<size_t>(options.loop - 1)].second];
  Profile p = fit_profile(taken, options.tolerance, mesh_file.string());
  try {
    validate_profile(p);
  } catch (const InputError& e) {
    // The fitted elements of a section thinner than the tolerance can fold back on each other.
    throw InputError(mesh_file.string(), 0, "fit-tolerance",
                     "the section at z=" + fixed(z0, 6) + " fitted within " + fixed(options.tolerance, 6) +
                         " mm is not a valid profile (" + e.reason() + "): is it thinner than the tolerance?");
  }
  if (left_out)
    for (const auto& [area, k] : by_area)
      if (&loops[k] != &taken) left_out->push_back({loops[k], area, point_in_polygon(taken, loops[k].front())});
  return p;
}

}  // namespace tf::offset
