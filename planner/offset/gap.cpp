// The gap law (gap as a function of the profile's arc length) and the clearance field built on it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "segment_bvh.hpp"
#include "offset_internal.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/offset/offset.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;

double slope(const GapLaw& law, size_t k) {  // slope of the interval [k, k+1]
  return (law.gap[k + 1] - law.gap[k]) / (law.s[k + 1] - law.s[k]);
}
// Half-width of the blend at knot k (0 when blending is off).
// Interior knots only: the end knots keep their values, so that a law written for a closed profile
// still has equal gaps at s = 0 and s = L.
double blend_width(const GapLaw& law, size_t k) {
  if (law.blend <= 0 || law.s.size() < 3 || k == 0 || k + 1 == law.s.size()) return 0;
  double w = law.blend;
  if (k > 0) w = std::min(w, 0.5 * (law.s[k] - law.s[k - 1]));
  if (k + 1 < law.s.size()) w = std::min(w, 0.5 * (law.s[k + 1] - law.s[k]));
  return w;
}
double slope_left(const GapLaw& law, size_t k) { return k > 0 ? slope(law, k - 1) : 0.0; }
double slope_right(const GapLaw& law, size_t k) { return k + 1 < law.s.size() ? slope(law, k) : 0.0; }

}  // namespace

GapLaw constant_gap(double gap) {
  GapLaw law;
  law.s = {0.0};
  law.gap = {gap};
  return law;
}

bool is_constant(const GapLaw& law) {
  return std::all_of(law.gap.begin(), law.gap.end(), [&](double g) { return g == law.gap.front(); });
}

std::string beyond_limit(double v) {
  std::ostringstream msg;
  msg << "the value " << v << " is beyond +-" << fixed(kMaxLengthMm, 0) << " mm";
  return msg.str();
}

GapLaw read_gap_law(const std::filesystem::path& file) {
  const CsvTable t = read_csv(file);
  const int cs = t.column("s"), cg = t.column("gap");
  if (cs < 0) throw InputError(file.string(), 1, "s", "missing column 's' (header must be 's,gap')");
  if (cg < 0) throw InputError(file.string(), 1, "gap", "missing column 'gap' (header must be 's,gap')");
  GapLaw law;
  law.file = file.string();
  for (size_t i = 0; i < t.rows.size(); ++i) {
    const double s = parse_number(t.rows[i][cs], law.file, t.lines[i], "s");
    const double g = parse_number(t.rows[i][cg], law.file, t.lines[i], "gap");
    if (g <= 0) throw InputError(law.file, t.lines[i], "gap", "the gap must be positive");
    for (const auto& [v, field] : {std::pair{s, "s"}, std::pair{g, "gap"}})
      if (std::abs(v) > kMaxLengthMm)
        throw InputError(law.file, t.lines[i], field, beyond_limit(v));
    if (!law.s.empty() && s <= law.s.back())
      throw InputError(law.file, t.lines[i], "s", "s must increase from row to row");
    law.s.push_back(s);
    law.gap.push_back(g);
  }
  if (law.s.empty()) throw InputError(law.file, 0, "", "gap law has no rows");
  return law;
}

double gap_at(const GapLaw& law, double s) {
  const size_t n = law.s.size();
  if (n == 1) return law.gap[0];
  // Inside a blend window: the parabola joining the two slopes (C1 at both window ends).
  if (law.blend > 0) {
    const size_t k = static_cast<size_t>(std::lower_bound(law.s.begin(), law.s.end(), s) - law.s.begin());
    for (size_t j : {k > 0 ? k - 1 : k, std::min(k, n - 1)}) {
      const double w = blend_width(law, j);
      const double u = s - law.s[j];
      if (w > 0 && std::abs(u) < w) {
        const double m1 = slope_left(law, j), m2 = slope_right(law, j);
        return law.gap[j] + m1 * u + (m2 - m1) * (u + w) * (u + w) / (4 * w);
      }
    }
  }
  if (s <= law.s.front()) return law.gap.front();
  if (s >= law.s.back()) return law.gap.back();
  const size_t k = static_cast<size_t>(std::upper_bound(law.s.begin(), law.s.end(), s) - law.s.begin()) - 1;
  return law.gap[k] + slope(law, k) * (s - law.s[k]);
}

std::vector<double> gap_breaks(const GapLaw& law, double L) {
  std::vector<double> out;
  if (law.s.size() < 2) return out;
  for (size_t k = 0; k < law.s.size(); ++k) {
    const double w = blend_width(law, k);
    for (double v : {law.s[k] - w, law.s[k], law.s[k] + w})
      if (v > 0 && v < L) out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool gap_linear_between(const GapLaw& law, double s0, double s1) {
  if (law.blend <= 0) return true;
  const double m = 0.5 * (s0 + s1);
  for (size_t k = 0; k < law.s.size(); ++k) {
    const double w = blend_width(law, k);
    if (w > 0 && std::abs(m - law.s[k]) < w) return false;
  }
  return true;
}

std::vector<Piece> profile_pieces(const Profile& profile, const GapLaw& law) {
  double L = chain_length(profile.elements);
  const auto breaks = gap_breaks(law, L);
  std::vector<Piece> out;
  double s = 0;
  for (size_t i = 0; i < profile.elements.size(); ++i) {
    const Segment& e = profile.elements[i];
    const double len = length(e);
    std::vector<double> cuts = {0.0};
    // A break within 0.1 um of the element's end is the end: a law written to 9 decimals put its knot
    // 2e-10 mm inside an octagon's side, and the sliver of a piece left there had no offset to join
    // (the offset was "empty", black-box testing).
    constexpr double kSnapMm = 1e-7;
    for (auto it = std::upper_bound(breaks.begin(), breaks.end(), s); it != breaks.end() && *it < s + len; ++it) {
      const double t = (*it - s) / len;
      if (*it - s > kSnapMm && s + len - *it > kSnapMm && t > 1e-12 && t < 1 - 1e-12) cuts.push_back(t);
    }
    cuts.push_back(1.0);
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      Piece p;
      p.seg = sub_segment(e, cuts[k], cuts[k + 1]);
      p.seg.line = e.line;
      p.element = static_cast<int>(i);
      p.s0 = s + cuts[k] * len;
      p.s1 = s + cuts[k + 1] * len;
      p.g0 = gap_at(law, p.s0);
      p.g1 = gap_at(law, p.s1);
      p.linear = gap_linear_between(law, p.s0, p.s1);
      p.constant = p.linear && p.g0 == p.g1;
      out.push_back(p);
    }
    s += len;
  }
  return out;
}

struct ClearanceField {
  GapLaw law;
  std::vector<Piece> pieces;
  detail::BoxTree tree;
  bool constant = true;
};

void ClearanceFieldDeleter::operator()(ClearanceField* f) const { delete f; }

ClearanceFieldPtr make_clearance_field(const Profile& profile, const GapLaw& law) {
  ClearanceFieldPtr f(new ClearanceField);
  f->law = law;
  f->constant = is_constant(law);
  f->pieces = profile_pieces(profile, law);
  std::vector<Eigen::AlignedBox2d> boxes;
  for (const auto& p : f->pieces) boxes.push_back(bounding_box(p.seg));
  f->tree = detail::BoxTree(std::move(boxes));
  return f;
}

double clearance(const ClearanceField& f, const Vector2d& q, double* s_at) {
  double s = 0;
  const double d = profile_distance(f, q, &s);
  if (s_at) *s_at = s;
  return d - gap_at(f.law, s);
}

double profile_distance(const ClearanceField& f, const Vector2d& q, double* s_at) {
  int best = -1;
  const double v = f.tree.nearest(q, 0.0, [&](int id) { return distance(f.pieces[id].seg, q); }, &best);
  if (s_at && best >= 0) {
    double t = 0;
    distance(f.pieces[best].seg, q, &t);
    *s_at = f.pieces[best].s0 + t * (f.pieces[best].s1 - f.pieces[best].s0);
  }
  return v;
}

bool closer_than_gap(const ClearanceField& f, const Vector2d& q, double eps) {
  if (!f.constant) return clearance(f, q) < -eps;
  // Constant gap: any element within gap - eps decides, no need for the nearest one.
  const double r = f.law.gap.front() - eps;
  if (r <= 0) return false;
  const Eigen::AlignedBox2d box(q.array() - r, q.array() + r);
  return f.tree.any(box, [&](int id) { return distance(f.pieces[id].seg, q) < r; });
}

const std::vector<Piece>& field_pieces(const ClearanceField& f) { return f.pieces; }

}  // namespace tf::offset
