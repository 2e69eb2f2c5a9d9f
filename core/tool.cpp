#include "tiltfield/core/tool.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf {

std::string_view to_string(ToolComponent c) {
  switch (c) {
    case ToolComponent::Ball: return "ball";
    case ToolComponent::Flute: return "flute";
    case ToolComponent::Shank: return "shank";
    case ToolComponent::Holder: return "holder";
  }
  return "?";
}

double default_link_gap(const Tool& tool) { return std::max(1.0, kLinkGapToolRadii * tool.radius()); }

double Tool::radius() const {
  return std::visit([](const auto& c) { return c.radius; }, cutter);
}
double Tool::cl_height() const {
  return std::visit([](const auto& c) { return c.cl_height(); }, cutter);
}
double Tool::end_height() const {
  return std::visit([](const auto& c) { return c.end_height(); }, cutter);
}
Eigen::Vector3d Tool::contact_offset(const Eigen::Vector3d& n, const Eigen::Vector3d& axis) const {
  if (std::holds_alternative<BallCutter>(cutter) || n.squaredNorm() == 0.0) return Eigen::Vector3d::Zero();
  const double R = radius(), r = cl_height();  // r: the corner radius (0 for a flat end)
  const Eigen::Vector3d a = axis.normalized(), normal_part = n.normalized() - n.normalized().dot(a) * a;
  // Moved by m along the unit normal part, the end dips (R - r) sin(t) - m below the contact (t the tilt,
  // sin(t) = |normal_part|): the least move that keeps the dip within 0.001 mm. So an axis within about
  // 0.02 deg of n (the end face on the surface, the default lead and tilt of 0) does not move the end,
  // and the move grows continuously to R - r beyond.
  constexpr double kDip = kContactDipMm;
  const double s = normal_part.norm();
  if ((R - r) * s <= kDip) return Eigen::Vector3d::Zero();
  return ((R - r) - kDip / s) / s * normal_part;
}

std::string_view Tool::type_name() const {
  if (std::holds_alternative<BallCutter>(cutter)) return "ball";
  if (std::holds_alternative<FlatCutter>(cutter)) return "flat";
  return "bull";
}

double Tool::total_length() const {
  double l = length;
  for (const auto& s : holder) l += s.length;
  return l;
}

double Tool::radius_at(double h) const {
  if (h < 0.0 || h > total_length()) return 0.0;
  if (h < end_height()) return std::visit([h](const auto& c) { return c.end_radius_at(h); }, cutter);
  if (h < flute_length) return radius();
  if (h < length) return shank_radius;
  double top = length;
  for (const auto& s : holder) {
    top += s.length;
    if (h <= top) return s.radius;
  }
  return holder.empty() ? shank_radius : holder.back().radius;
}

ToolComponent Tool::component_at(double h) const {
  if (h < end_height()) return ToolComponent::Ball;
  if (h < flute_length) return ToolComponent::Flute;
  if (h < length) return ToolComponent::Shank;
  return ToolComponent::Holder;
}

double Tool::max_radius_between(double h0, double h1) const {
  if (h1 < h0) std::swap(h0, h1);
  h0 = std::max(h0, 0.0);
  h1 = std::min(h1, total_length());
  if (h1 < h0) return 0.0;
  // The body is piecewise monotone: the end form grows with h, every other piece is constant, so the
  // maximum is at a piece boundary or an end of the interval.
  double r = std::max(radius_at(h0), radius_at(h1));
  std::vector<double> breaks = {end_height(), flute_length, length};
  double top = length;
  for (const auto& s : holder) breaks.push_back(top += s.length);
  for (double b : breaks) {
    if (b > h0 && b < h1) r = std::max({r, radius_at(b - 1e-12), radius_at(b + 1e-12)});
  }
  return r;
}

namespace {
// One piece of the meridian (the body's outline in the r-h half plane), sampled by arc length.
struct MeridianPiece {
  // point(u) for u in [0, 1] -> (r, h); normal(u) -> (nr, nh)
  std::function<Eigen::Vector2d(double)> point;
  std::function<Eigen::Vector2d(double)> normal;
  double length;
  ToolComponent component;
  int holder_segment;
};

void revolve(const MeridianPiece& piece, double spacing, std::vector<ToolSample>& out) {
  const int nu = std::max(1, static_cast<int>(std::ceil(piece.length / spacing)));
  for (int i = 0; i <= nu; ++i) {
    const double u = static_cast<double>(i) / nu;
    const Eigen::Vector2d rh = piece.point(u);
    const Eigen::Vector2d nrh = piece.normal(u);
    if (rh.x() < 1e-9) {  // on the axis: a single point
      out.push_back({Eigen::Vector3d(0, 0, rh.y()), Eigen::Vector3d(0, 0, nrh.y() >= 0 ? 1 : -1), piece.component,
                     piece.holder_segment});
      continue;
    }
    const int nv = std::max(6, static_cast<int>(std::ceil(2.0 * std::numbers::pi * rh.x() / spacing)));
    // Stagger alternate rings so the samples do not line up in meridians.
    const double phase = (i % 2) * std::numbers::pi / nv;
    for (int j = 0; j < nv; ++j) {
      const double a = phase + 2.0 * std::numbers::pi * j / nv;
      const double c = std::cos(a), s = std::sin(a);
      out.push_back({Eigen::Vector3d(rh.x() * c, rh.x() * s, rh.y()),
                     Eigen::Vector3d(nrh.x() * c, nrh.x() * s, nrh.y()).normalized(), piece.component,
                     piece.holder_segment});
    }
  }
}

MeridianPiece line_piece(Eigen::Vector2d a, Eigen::Vector2d b, ToolComponent comp, int seg, bool outward_up) {
  Eigen::Vector2d d = (b - a);
  const double len = d.norm();
  Eigen::Vector2d n(d.y(), -d.x());  // right of the direction of travel (a->b going up: +r)
  if (len > 0) n /= len;
  if (outward_up && n.y() < 0) n = -n;
  return {[a, b](double u) { return Eigen::Vector2d(a + u * (b - a)); }, [n](double) { return n; }, len, comp, seg};
}
}  // namespace

std::vector<ToolSample> Tool::sample_surface(double spacing) const {
  if (!(spacing > 0.0)) throw std::invalid_argument("Tool::sample_surface: spacing must be positive");
  std::vector<MeridianPiece> pieces;
  const double R = radius();
  // End form.
  if (const auto* b = std::get_if<BallCutter>(&cutter)) {
    const double r = b->radius;
    pieces.push_back({[r](double u) {
                        const double a = u * std::numbers::pi / 2;  // from the tip up to the equator
                        return Eigen::Vector2d(r * std::sin(a), r - r * std::cos(a));
                      },
                      [](double u) {
                        const double a = u * std::numbers::pi / 2;
                        return Eigen::Vector2d(std::sin(a), -std::cos(a));
                      },
                      r * std::numbers::pi / 2, ToolComponent::Ball, -1});
  } else if (const auto* f = std::get_if<FlatCutter>(&cutter)) {
    const double r = f->radius;
    pieces.push_back({[r](double u) { return Eigen::Vector2d(u * r, 0.0); },
                      [](double) { return Eigen::Vector2d(0, -1); }, r, ToolComponent::Ball, -1});
  } else {
    const auto& c = std::get<BullCutter>(cutter);
    const double r0 = c.radius - c.corner_radius, rc = c.corner_radius;
    if (r0 > 0)
      pieces.push_back({[r0](double u) { return Eigen::Vector2d(u * r0, 0.0); },
                        [](double) { return Eigen::Vector2d(0, -1); }, r0, ToolComponent::Ball, -1});
    pieces.push_back({[r0, rc](double u) {
                        const double a = u * std::numbers::pi / 2;
                        return Eigen::Vector2d(r0 + rc * std::sin(a), rc - rc * std::cos(a));
                      },
                      [](double u) {
                        const double a = u * std::numbers::pi / 2;
                        return Eigen::Vector2d(std::sin(a), -std::cos(a));
                      },
                      rc * std::numbers::pi / 2, ToolComponent::Ball, -1});
  }
  const double eh = end_height();
  pieces.push_back(line_piece({R, eh}, {R, flute_length}, ToolComponent::Flute, -1, false));
  // Shoulder between flutes and shank (either way), then the shank.
  if (std::abs(shank_radius - R) > 1e-9)
    pieces.push_back(line_piece({R, flute_length}, {shank_radius, flute_length}, ToolComponent::Shank, -1, true));
  pieces.push_back(line_piece({shank_radius, flute_length}, {shank_radius, length}, ToolComponent::Shank, -1, false));
  double prev_r = shank_radius, h = length;
  for (size_t i = 0; i < holder.size(); ++i) {
    const auto& s = holder[i];
    // The annular face between the previous radius and this segment faces down when it steps out.
    if (std::abs(s.radius - prev_r) > 1e-9) {
      auto p = line_piece({prev_r, h}, {s.radius, h}, ToolComponent::Holder, static_cast<int>(i), false);
      const double nh = s.radius > prev_r ? -1.0 : 1.0;
      p.normal = [nh](double) { return Eigen::Vector2d(0, nh); };
      pieces.push_back(p);
    }
    pieces.push_back(line_piece({s.radius, h}, {s.radius, h + s.length}, ToolComponent::Holder, static_cast<int>(i), false));
    prev_r = s.radius;
    h += s.length;
  }
  // Top cap.
  {
    const double rt = prev_r, ht = h;
    const auto comp = holder.empty() ? ToolComponent::Shank : ToolComponent::Holder;
    pieces.push_back({[rt, ht](double u) { return Eigen::Vector2d((1 - u) * rt, ht); },
                      [](double) { return Eigen::Vector2d(0, 1); }, rt, comp,
                      holder.empty() ? -1 : static_cast<int>(holder.size()) - 1});
  }
  std::vector<ToolSample> out;
  for (const auto& p : pieces) revolve(p, spacing, out);
  return out;
}

void validate_tool(const Tool& tool, const std::string& file, const std::string& prefix) {
  // At most 1 km, as a path's coordinates: a radius of 1e9 had been taken and verified a facing pass as a
  // third of its volume (black-box testing).
  auto positive = [&](double v, const std::string& field) {
    if (!std::isfinite(v) || v <= 0.0 || v > kMaxCoordinate)
      throw InputError(file, 0, prefix + "." + field, "must be a positive number of mm, at most 1 km (1000000)");
  };
  positive(tool.radius(), "radius");
  if (const auto* b = std::get_if<BullCutter>(&tool.cutter)) {
    positive(b->corner_radius, "corner_radius");
    if (b->corner_radius > b->radius)
      throw InputError(file, 0, prefix + ".corner_radius", "must not exceed the tool radius");
  }
  positive(tool.flute_length, "flute_length");
  positive(tool.shank_radius, "shank_radius");
  positive(tool.length, "length");
  if (tool.flute_length < tool.end_height())
    throw InputError(file, 0, prefix + ".flute_length", "shorter than the cutter's end form");
  if (tool.length < tool.flute_length)
    throw InputError(file, 0, prefix + ".length", "gauge length is shorter than the flute length");
  for (size_t i = 0; i < tool.holder.size(); ++i) {
    positive(tool.holder[i].radius, "holder[" + std::to_string(i) + "].radius");
    positive(tool.holder[i].length, "holder[" + std::to_string(i) + "].length");
  }
}

}  // namespace tf
