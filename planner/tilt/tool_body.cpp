// Exact clearance of the posed tool body: GJK between each triangle and each convex piece.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "clearance_bvh.hpp"
#include "tiltfield/tilt/plan.hpp"
#include "tool_body.hpp"

namespace tf {
using Eigen::Vector3d;

std::vector<BodyPiece> body_pieces(const Tool& tool) {
  std::vector<BodyPiece> out;
  const double cl = tool.cl_height(), R = tool.radius();
  auto cyl = [&](ToolComponent comp, int seg, double a, double b, double r) {
    if (b - a > 1e-9 && r > 0) out.push_back({comp, seg, false, a - cl, b - cl, r});
  };
  const auto* bull = std::get_if<BullCutter>(&tool.cutter);
  if (std::holds_alternative<BallCutter>(tool.cutter)) {
    out.push_back({ToolComponent::Ball, -1, true, 0.0, 0.0, R});
  } else if (bull && tool.flute_length >= 2.0 * bull->corner_radius) {
    const double r = bull->corner_radius;
    out.push_back({ToolComponent::Ball, -1, false, -cl, 2.0 * r - cl, R, r});
  } else {
    cyl(ToolComponent::Ball, -1, 0.0, std::max(tool.end_height(), 1e-6), R);
  }
  cyl(ToolComponent::Flute, -1, tool.end_height(), tool.flute_length, R);
  cyl(ToolComponent::Shank, -1, tool.flute_length, tool.length, tool.shank_radius);
  double h = tool.length;
  for (size_t i = 0; i < tool.holder.size(); ++i) {
    cyl(ToolComponent::Holder, static_cast<int>(i), h, h + tool.holder[i].length, tool.holder[i].radius);
    h += tool.holder[i].length;
  }
  return out;
}

double required_clearance(const PlannerBasics& b, ToolComponent c) {
  switch (c) {
    case ToolComponent::Shank: return std::max(b.shank_clearance.value_or(b.safety_distance), kLeastClearance);
    case ToolComponent::Holder: return std::max(b.holder_clearance.value_or(b.safety_distance), kLeastClearance);
    default: return std::max(b.safety_distance, kLeastClearance);
  }
}

double fixture_clearance(const PlannerBasics& b) {
  return std::max(b.fixture_clearance.value_or(b.safety_distance), kLeastClearance);
}

namespace {

// Closest point to the origin of the simplex y[0..n), by checking the faces of it (Johnson's sub-simplex
// enumeration, brute force). Keeps in y only the vertices that support the closest point. Returns the
// closest point; `inside` when the origin is inside a full tetrahedron. y[n - 1] is the vertex GJK just
// added: the faces without it are faces of the simplex before, whose closest point the search moved
// away from, so only the faces with it are tried (8 of 15 for a tetrahedron; {y[n - 1]} alone always
// gives a point).
Vector3d closest_on_simplex(std::array<Vector3d, 4>& y, int& n, bool& inside) {
  inside = false;
  double best = std::numeric_limits<double>::infinity();
  Vector3d best_v = y[static_cast<size_t>(n - 1)];
  int best_mask = 1 << (n - 1);
  for (int mask = 1 << (n - 1); mask < (1 << n); ++mask) {
    int idx[4], k = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) idx[k++] = i;
    // Minimise |y0 + E mu| over the affine hull, then require barycentrics > 0.
    const Vector3d& y0 = y[static_cast<size_t>(idx[0])];
    double lambda[4] = {1, 0, 0, 0};
    if (k > 1) {
      // mu minimises |y0 + E mu| (E's columns: the other vertices less y0): the normal equations G mu = rhs,
      // solved in closed form per size (the planner's hottest loop with a holder's cap over many triangles).
      const int m = k - 1;
      Vector3d e[3];
      for (int j = 0; j < m; ++j) e[j] = y[static_cast<size_t>(idx[j + 1])] - y0;
      double mu[3] = {0, 0, 0};
      if (m == 1) {
        const double g = e[0].squaredNorm();
        if (g < 1e-300) continue;  // skip degenerate sub-simplices (their faces are checked on their own)
        mu[0] = -e[0].dot(y0) / g;
      } else if (m == 2) {
        const double a = e[0].squaredNorm(), b = e[0].dot(e[1]), c = e[1].squaredNorm();
        const double det = a * c - b * b, trace = a + c + 1e-300;
        if (std::abs(det) < 1e-24 * trace * trace) continue;
        const double r0 = -e[0].dot(y0), r1 = -e[1].dot(y0);
        mu[0] = (c * r0 - b * r1) / det;
        mu[1] = (a * r1 - b * r0) / det;
      } else {
        Eigen::Matrix3d E;
        E << e[0], e[1], e[2];
        const Eigen::Matrix3d G = E.transpose() * E;
        const double det = G.determinant(), trace = G.trace() + 1e-300;
        if (std::abs(det) < 1e-24 * trace * trace * trace) continue;
        const Vector3d sol = G.inverse() * (-E.transpose() * y0);
        for (int j = 0; j < 3; ++j) mu[j] = sol[j];
      }
      double s = 0;
      bool ok = true;
      for (int j = 1; j < k; ++j) {
        lambda[j] = mu[j - 1];
        s += mu[j - 1];
        ok &= mu[j - 1] > 0;
      }
      lambda[0] = 1 - s;
      if (!ok || lambda[0] <= 0) continue;
    }
    Vector3d v = Vector3d::Zero();
    for (int j = 0; j < k; ++j) v += lambda[j] * y[static_cast<size_t>(idx[j])];
    const double d = v.squaredNorm();
    if (d < best) {
      best = d;
      best_v = v;
      best_mask = mask;
      if (k == 4) inside = true;
    }
  }
  if (inside) return Vector3d::Zero();
  std::array<Vector3d, 4> kept;
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (best_mask & (1 << i)) kept[static_cast<size_t>(m++)] = y[static_cast<size_t>(i)];
  y = kept;
  n = m;
  return best_v;
}

}  // namespace

double triangle_cylinder_distance(const Triangle& t, const Vector3d& p0, const Vector3d& p1, double r) {
  return triangle_cylinder_distance(t, 0.5 * (p0 + p1), (p1 - p0).normalized(), 0.5 * (p1 - p0).norm(), r);
}

double triangle_cylinder_distance(const Triangle& t, const Vector3d& mid, const Vector3d& axis, double half, double r) {
  auto support_tri = [&](const Vector3d& d) {
    const double a = t.a.dot(d), b = t.b.dot(d), c = t.c.dot(d);
    return a >= b ? (a >= c ? t.a : t.c) : (b >= c ? t.b : t.c);
  };
  auto support_cyl = [&](const Vector3d& d) {
    const double da = d.dot(axis);
    Vector3d s = mid + (da >= 0 ? half : -half) * axis;
    const Vector3d perp = d - da * axis;
    const double pn = perp.norm();
    if (pn > 1e-12) s += r * perp / pn;
    return s;
  };
  // Minkowski difference triangle - cylinder; its closest point to the origin gives the distance.
  auto support = [&](const Vector3d& d) -> Vector3d { return support_tri(d) - support_cyl(-d); };
  std::array<Vector3d, 4> y;
  int n = 0;
  Vector3d v = (t.a + t.b + t.c) / 3.0 - mid;
  if (v.squaredNorm() < 1e-24) v = Vector3d::UnitX();
  v = support(-v);
  constexpr double kTol = 1e-6;  // mm
  for (int iter = 0; iter < 64; ++iter) {
    const double vn = v.norm();
    if (vn < 1e-12) return 0.0;
    const Vector3d w = support(-v);
    // Lower bound of the distance is v.w/|v|; stop when it is within kTol of |v|.
    if (vn - v.dot(w) / vn <= kTol) return vn;
    bool dup = false;
    for (int i = 0; i < n; ++i) dup |= (y[static_cast<size_t>(i)] - w).squaredNorm() < 1e-20;
    if (dup || n == 4) return vn;
    y[static_cast<size_t>(n++)] = w;
    bool inside = false;
    v = closest_on_simplex(y, n, inside);
    if (inside) return 0.0;
  }
  return v.norm();
}

double rounded_cylinder_distance(const Triangle& t, const Vector3d& p0, const Vector3d& p1, double R, double rounding,
                                 double best) {
  const Vector3d ax = (p1 - p0).normalized();
  const Vector3d c0 = p0 + rounding * ax, c1 = p1 - rounding * ax;  // the core's axis (p0, p1 for rounding 0)
  const bool disc = (c1 - c0).dot(ax) <= 2e-9;
  const Vector3d mid = 0.5 * (c0 + c1);
  const double core = std::max(0.0, R - rounding);
  // The capsule of radius R about the core's axis encloses the piece: a lower bound, exact where the
  // closest axis point lies strictly inside (the direction to the triangle is then normal to the axis and
  // the nearest point is on the lateral surface). Only contacts on the end side need more.
  double s = 0.5;
  const double capsule =
      (disc ? (closest_point_on_triangle(mid, t) - mid).norm() : segment_triangle_distance(c0, c1, t, &s)) - R;
  if (capsule >= best) return capsule;
  if (!disc && s > 1e-9 && s < 1 - 1e-9) return std::max(0.0, capsule);
  // A triangle wholly beyond a face of the core (a bull end's disc: either side) lies at least its nearest
  // vertex's height above it, less the rounding, and exactly that when the vertex stands over the face.
  // For a wide holder over many triangles this spares GJK nearly every leaf: the capsule's hemisphere
  // reaches R past the face, so its bound lets through every triangle within R of it.
  const Vector3d* v[3] = {&t.a, &t.b, &t.c};
  Vector3d end = mid, out = ax;
  if (!disc) {
    end = s <= 0.5 ? c0 : c1;
    out = (s <= 0.5 ? c0 - c1 : c1 - c0).normalized();
  } else if ((*v[0] - mid).dot(ax) + (*v[1] - mid).dot(ax) + (*v[2] - mid).dot(ax) < 0) {
    out = -ax;
  }
  int low = 0;
  double h[3];
  for (int i = 0; i < 3; ++i) {
    h[i] = (*v[i] - end).dot(out);
    if (h[i] < h[low]) low = i;
  }
  if (h[low] > 0) {
    const double d = h[low] - rounding;
    if (d >= best) return d;
    if ((*v[low] - end - h[low] * out).squaredNorm() <= core * core) return std::max(0.0, d);
  }
  const double cylinder = disc ? triangle_cylinder_distance(t, mid, ax, 0.5 * std::max(0.0, (c1 - c0).dot(ax)), core)
                               : triangle_cylinder_distance(t, c0, c1, core);
  return std::max(0.0, cylinder - rounding);
}

double piece_distance(const TriangleBvh& bvh, const BodyPiece& piece, const Pose& pose, double limit,
                      bool first_below) {
  const double inf = std::numeric_limits<double>::infinity();
  if (piece.sphere) {
    const Vector3d c = pose.c + piece.h0 * pose.axis;
    const double R = piece.radius;
    const double lim = limit + R;
    const double d2 = bvh.minimum(
        [&](const Vector3d& lo, const Vector3d& hi) { return box_distance_squared(c, lo, hi); },
        [&](int i, double) { return (closest_point_on_triangle(c, bvh.triangle(i)) - c).squaredNorm(); },
        lim * lim, first_below ? lim * lim : -inf);
    if (d2 >= lim * lim) return limit;  // nothing nearer than the limit (exactly, not up to rounding)
    return std::max(0.0, std::sqrt(d2) - R);
  }
  const Vector3d p0 = pose.c + piece.h0 * pose.axis, p1 = pose.c + piece.h1 * pose.axis;
  const Vector3d mid = 0.5 * (p0 + p1);
  const double half = 0.5 * (piece.h1 - piece.h0), R = piece.radius;
  const Vector3d ax = pose.axis;
  auto seg_point_distance = [&](const Vector3d& q) {
    const double s = std::clamp((q - mid).dot(ax), -half, half);
    return (mid + s * ax - q).norm();
  };
  const double d = bvh.minimum(
      [&](const Vector3d& lo, const Vector3d& hi) {
        // Sphere around the box against the capsule around the piece: a lower bound of the cylinder's.
        const Vector3d c = 0.5 * (lo + hi);
        return seg_point_distance(c) - 0.5 * (hi - lo).norm() - R;
      },
      [&](int i, double best) {
        return rounded_cylinder_distance(bvh.triangle(i), p0, p1, R, piece.rounding, best);
      },
      limit, first_below ? limit : -inf);
  return std::max(0.0, d);
}


void merge_coaxial_pieces(std::vector<BodyPiece>& pieces, std::vector<double>& required) {
  std::vector<BodyPiece> p;
  std::vector<double> r;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const BodyPiece& q = pieces[i];
    if (!p.empty() && !p.back().sphere && !q.sphere && p.back().rounding == 0 && q.rounding == 0 &&
        p.back().radius == q.radius && r.back() == required[i] &&
        std::abs(p.back().h1 - q.h0) <= 1e-12 * (1 + std::abs(q.h0))) {
      p.back().h1 = q.h1;
      continue;
    }
    p.push_back(q);
    r.push_back(required[i]);
  }
  pieces = std::move(p);
  required = std::move(r);
}

size_t piece_query_order(const std::vector<BodyPiece>& pieces, size_t k) {
  const size_t n = pieces.size();
  return pieces[0].sphere ? (k == 0 ? 0 : n - k) : n - 1 - k;
}

double piece_distance(const ClearanceBvh& bvh, const BodyPiece& piece, const Pose& pose, double limit,
                      bool first_below, int* hint) {
  const double inf = std::numeric_limits<double>::infinity();
  const int seed = hint && *hint >= 0 && *hint < static_cast<int>(bvh.size()) ? *hint : -1;
  int arg = -1;
  if (piece.sphere) {
    const Vector3d c = pose.c + piece.h0 * pose.axis;
    const double R = piece.radius;
    const double lim = limit + R, lim2 = lim * lim;
    auto leaf = [&](int i, double best) {
      const double d2 = (closest_point_on_triangle(c, bvh.triangle(i)) - c).squaredNorm();
      if (d2 < best) arg = i;
      return d2;
    };
    double start = lim2;
    if (seed >= 0) start = std::min(start, leaf(seed, start));
    double d2 = start;
    if (!(first_below && start < lim2))
      d2 = bvh.minimum([&](const ClearanceBvh::Node& nd) { return point_node_bound_squared(nd, c); }, leaf, start,
                       first_below ? lim2 : -inf);
    if (hint && arg >= 0) *hint = arg;
    if (d2 >= lim2) return limit;  // nothing nearer than the limit (exactly, not up to rounding)
    return std::max(0.0, std::sqrt(d2) - R);
  }
  const Vector3d p0 = pose.c + piece.h0 * pose.axis, p1 = pose.c + piece.h1 * pose.axis;
  const Vector3d out = -pose.axis.normalized();  // p0's cap faces this way (h0 < h1)
  const double R = piece.radius;
  auto leaf = [&](int i, double best) {
    const double d = rounded_cylinder_distance(bvh.triangle(i), p0, p1, R, piece.rounding, best);
    if (d < best) arg = i;
    return d;
  };
  double start = limit;
  if (seed >= 0) start = std::min(start, leaf(seed, start));
  double d = start;
  if (!(first_below && start < limit))
    d = bvh.minimum([&](const ClearanceBvh::Node& nd) { return cylinder_node_bound(nd, p0, p1, R, out); }, leaf,
                    start, first_below ? limit : -inf);
  if (hint && arg >= 0) *hint = arg;
  return std::max(0.0, d);
}

BodyClearance body_clearance(const ClearanceBvh& bvh, const std::vector<BodyPiece>& pieces,
                             const std::vector<double>& required, const Pose& pose, std::vector<int>* hints,
                             const BodyClearance* below) {
  if (hints && hints->size() != pieces.size()) hints->assign(pieces.size(), -1);
  BodyClearance out;
  out.distance = std::numeric_limits<double>::infinity();
  out.margin = std::numeric_limits<double>::infinity();
  if (below) out = *below;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const size_t i = piece_query_order(pieces, k);
    const double limit = std::max(out.distance, out.margin + required[i]);
    const double d = piece_distance(bvh, pieces[i], pose, limit, false, hints ? &(*hints)[i] : nullptr);
    out.distance = std::min(out.distance, d);
    if (d - required[i] < out.margin) {
      out.margin = d - required[i];
      out.piece = static_cast<int>(i);
    }
  }
  return out;
}

BodyClearance body_clearance(const TriangleBvh& bvh, const std::vector<BodyPiece>& pieces,
                             const std::vector<double>& required, const Pose& pose) {
  BodyClearance out;
  out.distance = std::numeric_limits<double>::infinity();
  out.margin = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < pieces.size(); ++i) {
    const double limit = std::max(out.distance, out.margin + required[i]);
    const double d = piece_distance(bvh, pieces[i], pose, limit);
    out.distance = std::min(out.distance, d);
    if (d - required[i] < out.margin) {
      out.margin = d - required[i];
      out.piece = static_cast<int>(i);
    }
  }
  return out;
}

std::vector<RowClearance> row_clearances(const OrientedPath& path, const std::vector<size_t>& rows, const Tool& tool,
                                        const PlannerBasics& basics, const PlanObstacles& obstacles) {
  const TriangleBvh checks(obstacles.check_surfaces), fixtures(obstacles.fixtures);
  const std::vector<BodyPiece> pieces = body_pieces(tool);
  std::vector<double> required;
  for (const auto& p : pieces) required.push_back(required_clearance(basics, p.component));
  const std::vector<double> fixture_required(pieces.size(), fixture_clearance(basics));
  std::vector<RowClearance> out;
  out.reserve(rows.size());
  for (size_t i : rows) {
    const OrientedRow& row = path.rows.at(i);
    const Pose pose{row.p + tool.contact_offset(row.n, row.axis), row.axis};
    const BodyClearance c = body_clearance(checks, pieces, required, pose);
    const BodyClearance f = body_clearance(fixtures, pieces, fixture_required, pose);
    out.push_back({std::min(c.distance, f.distance), std::min(c.margin, f.margin)});
  }
  return out;
}

}  // namespace tf
