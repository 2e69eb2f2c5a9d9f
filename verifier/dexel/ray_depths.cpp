// Depths along one ray: obstacle overlap and gouge (see ray_depths.hpp).
#include "ray_depths.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tf {

// Overlap of the interval [a, b] with an obstacle's crossings on one ray: solid obstacles by their inside
// spans (winding), open surfaces by the distance from a crossing to the nearer end of [a, b].
float obstacle_depth(const Crossing* c, const Crossing* e, bool solid, float a, float b) {
  float best = 0.f;
  if (!c) return 0.f;
  if (solid) {
    int w = 0;
    float start = -std::numeric_limits<float>::infinity();
    for (; c != e; ++c) {
      const int before = w;
      w += c->cos < 0 ? 1 : -1;
      if (before == 0 && w > 0) start = c->t;
      if (before > 0 && w == 0) best = std::max(best, std::min(b, c->t) - std::max(a, start));
    }
    return std::max(best, 0.f);
  }
  for (; c != e; ++c)
    if (c->t > a && c->t < b) best = std::max(best, std::min(c->t - a, b - c->t));
  return best;
}

// Deepest over-cut (normal to the design) of the removed pieces on one ray. The part side lies between an
// entering crossing (cos < 0) and the next exiting one; depth at x is the distance to the nearer crossing
// times |cos| there (a planar estimate; crossings more grazing than |cos| < 0.3 are left to other grids).
double gouge_depth(const Crossing* c, const Crossing* e, const std::vector<Interval>& removed, double* where) {
  if (!c || c == e || removed.empty()) return 0.0;
  constexpr double kMinCos = 0.3;
  const double inf = std::numeric_limits<double>::infinity();
  double best = 0.0;
  auto span = [&](double t_in, double c_in, double t_out, double c_out) {
    const bool vin = std::isfinite(t_in) && c_in >= kMinCos, vout = std::isfinite(t_out) && c_out >= kMinCos;
    if (!vin && !vout) return;
    auto depth = [&](double x) {
      double d = inf;
      if (vin) d = std::min(d, (x - t_in) * c_in);
      if (vout) d = std::min(d, (t_out - x) * c_out);
      return d;
    };
    auto take = [&](double x) {
      const double v = depth(x);
      if (v > best) {
        best = v;
        *where = x;
      }
    };
    for (const Interval& r : removed) {
      const double p0 = std::max<double>(r.lo, t_in), p1 = std::min<double>(r.hi, t_out);
      if (!(p1 > p0)) continue;
      take(p0);
      take(p1);
      if (vin && vout) {
        const double x = (t_in * c_in + t_out * c_out) / (c_in + c_out);
        if (x > p0 && x < p1) take(x);
      }
    }
  };
  double t_in = -inf, c_in = 0.0;
  bool inside = c->cos > 0;  // the first crossing exits: the ray starts on the part side
  for (; c != e; ++c) {
    if (c->cos < 0) {
      t_in = c->t;
      c_in = -c->cos;
      inside = true;
    } else {
      if (inside) span(t_in, c_in, c->t, c->cos);
      inside = false;
    }
  }
  if (inside) span(t_in, c_in, inf, 0.0);
  return best;
}

ExcessStats excess_left(const RayTable& design, const TriDexel& stock) {
  ExcessStats out;
  std::vector<double> values;
  const Lattice& lattice = stock.lattice();
  for (int d = 0; d < 3; ++d) {
    const int u = Lattice::u_axis(d), v = Lattice::v_axis(d);
    for (int iv = 0; iv < lattice.n[v]; ++iv)
      for (int iu = 0; iu < lattice.n[u]; ++iu) {
        const Crossing* c = design.begin(d, iu, iv);
        if (!c) continue;
        const Crossing* e = design.end(d, iu, iv);
        const Dexel& ray = stock.ray(d, iu, iv);
        for (const Crossing* x = c; x != e; ++x) {
          if (std::abs(x->cos) < 0.5) continue;
          double along = 0.0;
          const float tol = 1e-3f;
          for (const Interval& m : ray) {
            if (x->cos < 0 && m.lo < x->t && m.hi >= x->t - tol) {
              const float prev = x == c ? -std::numeric_limits<float>::infinity() : (x - 1)->t;
              along = x->t - std::max(m.lo, prev);
            }
            if (x->cos > 0 && m.hi > x->t && m.lo <= x->t + tol) {
              const float next = x + 1 == e ? std::numeric_limits<float>::infinity() : (x + 1)->t;
              along = std::min(m.hi, next) - x->t;
            }
          }
          values.push_back(std::max(0.0, along) * std::abs(x->cos));
        }
      }
  }
  if (values.empty()) return out;
  std::sort(values.begin(), values.end());
  double sum = 0.0;
  for (double x : values) sum += x;
  out.samples = values.size();
  out.mean_mm = sum / values.size();
  out.max_mm = values.back();
  out.p95_mm = values[std::min(values.size() - 1, static_cast<size_t>(0.95 * values.size()))];
  return out;
}

}  // namespace tf
