// The analytic impeller model, its option checks and its meshes (hub, blades, stock).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "scene_geometry.hpp"
#include "tiltfield/core/io.hpp"
#include "scene_impeller.hpp"

namespace tf::scenes {

namespace {
constexpr double kHalfPi = std::numbers::pi / 2;
// Share of the chordal tolerance given to each of the two tessellation directions: a triangle's deviation
// is at most about the larger of the two sags on these saddle-like surfaces, the rest is margin.
constexpr double kDirectionShare = 0.8;


void check_impeller(bool ok, const char* option, const std::string& what) { require_option(ok, "impeller", option, what); }
bool finite_in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }
}  // namespace

void validate_impeller_options(const ImpellerOptions& o) {
  check_impeller(o.blades >= 2 && o.blades <= 64, "--blades", "must be an integer from 2 to 64");
  check_impeller(finite_in(o.splitter_start, 0.05, 0.9), "--splitter-start", "must be within [0.05, 0.9]");
  check_impeller(std::isfinite(o.lean_deg) && std::abs(o.lean_deg) < 45, "--lean", "must be within (-45, 45) degrees");
  check_impeller(finite_in(o.wrap_deg, -180, 180), "--wrap", "must be within [-180, 180] degrees");
  check_impeller(size_mm(o.inlet_radius), "--inlet-radius", kSizeRange);
  check_impeller(size_mm(o.outlet_radius) && o.outlet_radius > o.inlet_radius, "--outlet-radius",
        "must be greater than --inlet-radius, at most 10000 mm");
  check_impeller(size_mm(o.outlet_z), "--outlet-z", kSizeRange);
  check_impeller(size_mm(o.inlet_z) && o.inlet_z > o.outlet_z, "--inlet-z",
                 "must be greater than --outlet-z, at most 10000 mm");
  check_impeller(size_mm(o.nose_z) && o.nose_z > o.inlet_z, "--nose-z", "must be greater than --inlet-z, at most 10000 mm");
  check_impeller(std::isfinite(o.inlet_height) && o.inlet_height >= 1 && o.inlet_height < o.outlet_radius - o.inlet_radius,
        "--inlet-height", "must be at least 1 mm and less than --outlet-radius minus --inlet-radius");
  check_impeller(std::isfinite(o.outlet_height) && o.outlet_height >= 1 && o.outlet_height < o.inlet_z - o.outlet_z,
        "--outlet-height", "must be at least 1 mm and less than --inlet-z minus --outlet-z");
  // Blades thicker than half the pitch at the inlet leave no channel (the path search had run for minutes).
  const double half_pitch = kPi * o.inlet_radius / (o.blades * (o.splitters ? 2 : 1));
  const std::string thickness = "must be from 0.05 mm to half the blade pitch at the inlet, " + fixed(half_pitch, 3) + " mm";
  check_impeller(finite_in(o.thickness_hub, 0.05, half_pitch), "--thickness-hub", thickness);
  check_impeller(finite_in(o.thickness_tip, 0.05, half_pitch), "--thickness-tip", thickness);
  check_impeller(size_mm(o.blade_sink) && o.blade_sink < o.outlet_z, "--blade-sink",
        "must be positive and less than --outlet-z");
  check_impeller(finite_in(o.tolerance, 0.0005, 1.0), "--tolerance", "must be within [0.0005, 1] mm");
  check_impeller(finite_in(o.blade_tolerance, 0.0005, 1.0), "--blade-tolerance", "must be within [0.0005, 1] mm");
  check_impeller(finite_in(o.stock_tolerance, 0.0005, 1.0), "--stock-tolerance", "must be within [0.0005, 1] mm");
  check_impeller(size_mm(o.allowance) && o.allowance < o.inlet_radius, "--allowance",
        "must be positive and less than --inlet-radius");
  check_impeller(size_mm(o.tool_radius) && o.tool_radius <= 25, "--tool-radius", "must be from 0.01 to 25 mm");
  require_step(o.step, o.tool_radius, "impeller");
  check_impeller(o.passes >= 1 && o.passes <= 500, "--passes", "must be an integer from 1 to 500");
  check_impeller(finite_in(o.m_start, 0.0, 1.0), "--m-start", "must be within [0, 1]");
  check_impeller(finite_in(o.m_end, 0.0, 1.0) && o.m_end > o.m_start, "--m-end", "must be within [0, 1] and above --m-start");
  check_impeller(finite_in(o.ball_clearance, 0.0, 10.0), "--ball-clearance", "must be within [0, 10] mm");
  check_impeller(std::isfinite(o.feed) && o.feed > 0, "--feed", "must be positive (mm/min)");
}

ImpellerModel::ImpellerModel(const ImpellerOptions& options)
    : o_(options), a_(options.outlet_radius - options.inlet_radius), b_(options.inlet_z - options.outlet_z) {}

Eigen::Vector2d ImpellerModel::hub_rz(double m) const {
  const double phi = m * kHalfPi;
  return {o_.outlet_radius - a_ * std::cos(phi), o_.inlet_z - b_ * std::sin(phi)};
}

Eigen::Vector2d ImpellerModel::hub_tangent_rz(double m) const {
  const double phi = m * kHalfPi;
  return kHalfPi * Eigen::Vector2d(a_ * std::sin(phi), -b_ * std::cos(phi));
}

Eigen::Vector2d ImpellerModel::hub_normal_rz(double m) const {
  const double phi = m * kHalfPi;
  return Eigen::Vector2d(b_ * std::cos(phi), a_ * std::sin(phi)).normalized();
}

Eigen::Vector3d ImpellerModel::hub_point(double m, double theta) const {
  const Eigen::Vector2d rz = hub_rz(m);
  return {rz.x() * std::cos(theta), rz.x() * std::sin(theta), rz.y()};
}

Eigen::Vector3d ImpellerModel::hub_normal(double m, double theta) const {
  const Eigen::Vector2d n = hub_normal_rz(m);
  return {n.x() * std::cos(theta), n.x() * std::sin(theta), n.y()};
}

int ImpellerModel::blade_count() const { return o_.splitters ? 2 * o_.blades : o_.blades; }

Eigen::Vector2d ImpellerModel::camber_rz(double m, double s) const {
  const double phi = m * kHalfPi;
  return {o_.outlet_radius - (a_ - s * o_.inlet_height) * std::cos(phi),
          o_.inlet_z - (b_ - s * o_.outlet_height) * std::sin(phi)};
}

double ImpellerModel::span_length(double m) const {
  const double phi = m * kHalfPi;
  return std::hypot(o_.inlet_height * std::cos(phi), o_.outlet_height * std::sin(phi));
}

double ImpellerModel::sink_span(double m) const {
  const double phi = m * kHalfPi;
  const Eigen::Vector2d span(o_.inlet_height * std::cos(phi), o_.outlet_height * std::sin(phi));
  // The span line is never tangent to the hub (both ellipses share the centre), so the dot is positive.
  return -o_.blade_sink / span.dot(hub_normal_rz(m));
}

double ImpellerModel::camber_theta(int blade, double m, double s) const {
  const int k = blade % o_.blades;
  double theta0 = 2.0 * kPi * k / o_.blades;
  if (is_splitter(blade)) theta0 += kPi / o_.blades;
  const double w = m + 0.6 * m * (1.0 - m);
  const double r = camber_rz(m, s).x();
  return theta0 + rad(o_.wrap_deg) * w + s * span_length(m) * std::tan(rad(o_.lean_deg)) / r;
}

Eigen::Vector3d ImpellerModel::camber_point(int blade, double m, double s) const {
  const Eigen::Vector2d rz = camber_rz(m, s);
  const double t = camber_theta(blade, m, s);
  return {rz.x() * std::cos(t), rz.x() * std::sin(t), rz.y()};
}

Eigen::Vector3d ImpellerModel::camber_normal(int blade, double m, double s) const {
  // Central differences: the surface is smooth and the offset only needs the direction.
  const double h = 1e-6;
  const Eigen::Vector3d dm = camber_point(blade, m + h, s) - camber_point(blade, m - h, s);
  const Eigen::Vector3d ds = camber_point(blade, m, s + h) - camber_point(blade, m, s - h);
  return ds.cross(dm).normalized();
}

double ImpellerModel::thickness(double s) const {
  return o_.thickness_hub + (o_.thickness_tip - o_.thickness_hub) * std::clamp(s, 0.0, 1.0);
}

Eigen::Vector3d ImpellerModel::face_point(int blade, int side, double m, double sigma) const {
  const double s = span_of(m, sigma);
  return camber_point(blade, m, s) + (side * 0.5 * thickness(s)) * camber_normal(blade, m, s);
}

namespace {
Eigen::Vector3d rz3(const Eigen::Vector2d& p) { return {p.x(), 0.0, p.y()}; }

// The hub's meridian, counter-clockwise: axis bottom, rim, curved hub from outlet to inlet, nose, cap.
// `offset` moves every face but the bottom outward (the stock); square corners where the offset opens.
std::vector<Eigen::Vector2d> hub_profile(const ImpellerModel& model, double offset, double tolerance) {
  const ImpellerOptions& o = model.options();
  auto curve = [&](double m) { return Eigen::Vector2d(model.hub_rz(m) + offset * model.hub_normal_rz(m)); };
  const std::vector<double> ms =
      sample_by_chord([&](double m) { return std::vector<Eigen::Vector3d>{rz3(curve(m))}; }, 0.0, 1.0, tolerance, 16);
  std::vector<Eigen::Vector2d> p;
  p.emplace_back(0.0, 0.0);
  p.emplace_back(o.outlet_radius + offset, 0.0);
  if (offset > 0) p.emplace_back(o.outlet_radius + offset, o.outlet_z + offset);
  for (auto it = ms.rbegin(); it != ms.rend(); ++it) p.push_back(curve(*it));
  p.emplace_back(o.inlet_radius + offset, o.nose_z + offset);
  p.emplace_back(0.0, o.nose_z + offset);
  return p;
}

// A blade is a twisted surface: its triangles can leave it inside a grid cell even when every grid line
// is within the tolerance. Refines the tensor grid (ms x sig) until the cell's two triangles (split along
// the (i, j)-(i+1, j+1) diagonal, as meshed) follow both faces within `tol` at interior sample points,
// splitting each bad cell along its longer side.
void refine_for_twist(const ImpellerModel& model, int blade, std::vector<double>& ms, std::vector<double>& sig,
                      double tol) {
  static const double samples[][2] = {{0.5, 0.5},  {1.0 / 3, 2.0 / 3}, {2.0 / 3, 1.0 / 3}, {0.25, 0.5},
                                      {0.5, 0.75}, {0.75, 0.5},        {0.5, 0.25}};
  for (int pass = 0; pass < 12; ++pass) {
    const size_t nm = ms.size(), ns = sig.size();
    std::vector<char> split_m(nm - 1, 0), split_s(ns - 1, 0);
    bool any = false;
    for (int side : {1, -1}) {
      std::vector<Eigen::Vector3d> g(nm * ns);
      for (size_t i = 0; i < nm; ++i)
        for (size_t j = 0; j < ns; ++j) g[i * ns + j] = model.face_point(blade, side, ms[i], sig[j]);
      for (size_t i = 0; i + 1 < nm; ++i)
        for (size_t j = 0; j + 1 < ns; ++j) {
          const Eigen::Vector3d &p00 = g[i * ns + j], &p10 = g[(i + 1) * ns + j], &p01 = g[i * ns + j + 1],
                                &p11 = g[(i + 1) * ns + j + 1];
          double dev = 0;
          for (const auto& uv : samples) {
            const double u = uv[0], v = uv[1];
            const Eigen::Vector3d flat = v >= u ? Eigen::Vector3d((1 - v) * p00 + (v - u) * p01 + u * p11)
                                                : Eigen::Vector3d((1 - u) * p00 + v * p11 + (u - v) * p10);
            const Eigen::Vector3d exact =
                model.face_point(blade, side, ms[i] + u * (ms[i + 1] - ms[i]), sig[j] + v * (sig[j + 1] - sig[j]));
            dev = std::max(dev, (exact - flat).norm());
          }
          if (dev <= tol) continue;
          any = true;
          ((p10 - p00).norm() >= (p01 - p00).norm() ? split_m[i] : split_s[j]) = 1;
        }
    }
    if (!any) return;
    auto refine = [](std::vector<double>& t, const std::vector<char>& split) {
      std::vector<double> out;
      for (size_t k = 0; k + 1 < t.size(); ++k) {
        out.push_back(t[k]);
        if (split[k]) out.push_back(0.5 * (t[k] + t[k + 1]));
      }
      out.push_back(t.back());
      t = std::move(out);
    };
    refine(ms, split_m);
    refine(sig, split_s);
  }
}

Mesh closed_or_throw(Mesh mesh, const char* what) {
  if (!is_closed(mesh) || !(signed_volume(mesh) > 0))
    throw std::logic_error(std::string("impeller generator: the ") + what + " mesh is not a closed outward solid");
  return mesh;
}
}  // namespace

Mesh impeller_hub_mesh(const ImpellerModel& model) {
  const ImpellerOptions& o = model.options();
  const double tol = kDirectionShare * o.tolerance;
  return closed_or_throw(revolve_profile(hub_profile(model, 0.0, tol), circle_segments(o.outlet_radius, tol)), "hub");
}

Mesh impeller_stock_mesh(const ImpellerModel& model) {
  const ImpellerOptions& o = model.options();
  const double tol = kDirectionShare * o.stock_tolerance;
  return closed_or_throw(
      revolve_profile(hub_profile(model, o.allowance, tol), circle_segments(o.outlet_radius + o.allowance, tol)),
      "stock");
}

Mesh impeller_blade_mesh(const ImpellerModel& model, int blade) {
  const double tol = kDirectionShare * model.options().blade_tolerance;
  const double m0 = model.blade_m_start(blade);
  const std::vector<double> sig_probe = {0.0, 0.25, 0.5, 0.75, 1.0};
  std::vector<double> ms = sample_by_chord(
      [&](double m) {
        std::vector<Eigen::Vector3d> pts;
        for (int side : {1, -1})
          for (double sg : sig_probe) pts.push_back(model.face_point(blade, side, m, sg));
        return pts;
      },
      m0, 1.0, tol, 16);
  std::vector<double> sig = sample_by_chord(
      [&](double sg) {
        std::vector<Eigen::Vector3d> pts;
        for (int side : {1, -1})
          for (int k = 0; k <= 8; ++k) pts.push_back(model.face_point(blade, side, m0 + (1.0 - m0) * k / 8.0, sg));
        return pts;
      },
      0.0, 1.0, tol, 4);
  refine_for_twist(model, blade, ms, sig, 0.9 * model.options().blade_tolerance);
  const int nm = static_cast<int>(ms.size()), ns = static_cast<int>(sig.size());
  Eigen::MatrixX3d V(2 * nm * ns, 3);
  auto P = [&](int i, int j) { return i * ns + j; };            // the + face
  auto M = [&](int i, int j) { return nm * ns + i * ns + j; };  // the - face
  for (int i = 0; i < nm; ++i)
    for (int j = 0; j < ns; ++j) {
      V.row(P(i, j)) = model.face_point(blade, 1, ms[i], sig[j]).transpose();
      V.row(M(i, j)) = model.face_point(blade, -1, ms[i], sig[j]).transpose();
    }
  // Orientation (see the camber normal n = d/ds x d/dm): the + face's outward normal is +n, the tip's
  // +d/ds, the bottom's -d/ds, the leading edge's -d/dm, the trailing edge's +d/dm.
  std::vector<Eigen::Vector3i> f;
  for (int i = 0; i + 1 < nm; ++i)
    for (int j = 0; j + 1 < ns; ++j) {
      f.emplace_back(P(i, j), P(i, j + 1), P(i + 1, j + 1));
      f.emplace_back(P(i, j), P(i + 1, j + 1), P(i + 1, j));
      f.emplace_back(M(i, j), M(i + 1, j + 1), M(i, j + 1));
      f.emplace_back(M(i, j), M(i + 1, j), M(i + 1, j + 1));
    }
  for (int i = 0; i + 1 < nm; ++i) {
    const int t = ns - 1;
    f.emplace_back(P(i, t), M(i + 1, t), P(i + 1, t));  // tip
    f.emplace_back(P(i, t), M(i, t), M(i + 1, t));
    f.emplace_back(P(i, 0), P(i + 1, 0), M(i + 1, 0));  // bottom
    f.emplace_back(P(i, 0), M(i + 1, 0), M(i, 0));
  }
  for (int j = 0; j + 1 < ns; ++j) {
    const int e = nm - 1;
    f.emplace_back(P(0, j), M(0, j + 1), P(0, j + 1));  // leading edge
    f.emplace_back(P(0, j), M(0, j), M(0, j + 1));
    f.emplace_back(P(e, j), P(e, j + 1), M(e, j + 1));  // trailing edge
    f.emplace_back(P(e, j), M(e, j + 1), M(e, j));
  }
  Eigen::MatrixX3i F(f.size(), 3);
  for (size_t i = 0; i < f.size(); ++i) F.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  return closed_or_throw(mesh_from_arrays(V, F), "blade");
}

Mesh impeller_blades_mesh(const ImpellerModel& model) {
  Mesh all;
  for (int k = 0; k < model.blade_count(); ++k) append_mesh(all, impeller_blade_mesh(model, k));
  return all;
}

}  // namespace tf::scenes
