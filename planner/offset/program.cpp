// NC programs for copy milling and ECM from an offset result, and the lead moves they share.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>

#include "tiltfield/core/io.hpp"
#include "offset_internal.hpp"
#include "tiltfield/offset/offset_program.hpp"

namespace tf::offset {
namespace {
using Eigen::Vector2d;
// 8 decimals (10 nm): the printed path stays within 1e-8 mm of the exact one, far inside the 1e-6 mm
// exactness the geometry keeps, and the interpreter's arc radius check sees consistent numbers.
constexpr int kDecimals = 8;
constexpr double kZeroRadiusArc = 0.0013;  // mm: the smallest arc radius written as G2/G3

std::string num(double v) { return fixed(v, kDecimals); }
Vector2d rounded(const Vector2d& p) {
  auto r = [](double v) { return std::round(v * 1e8) / 1e8; };
  return {r(p.x()), r(p.y())};
}

// The contour rotated to start in the middle of its longest segment (a quiet place for the leads).
std::vector<Segment> rotate_to_longest(const std::vector<Segment>& c) {
  size_t best = 0;
  for (size_t k = 1; k < c.size(); ++k)
    if (length(c[k]) > length(c[best])) best = k;
  std::vector<Segment> out;
  out.push_back(sub_segment(c[best], 0.5, 1.0));
  for (size_t k = 1; k < c.size(); ++k) out.push_back(c[(best + k) % c.size()]);
  out.push_back(sub_segment(c[best], 0.0, 0.5));
  out.back().b = out.front().a;
  return out;
}

// Under a gap law one voltage set-point a move keeps U/g constant only where the gap is: a line whose gap
// runs from 0.5 to 1.2 mm had U/g 41 % off at its ends. Each move is cut where its gap (linear along it)
// has changed by kGapStep of the smaller end gap, so U/g stays within half of that of the nominal field.
// Pieces are kept at least kMinPieceMm long, a thousand times the printed resolution (a gap changing
// faster than that along a move is beyond any generator's response anyway).
constexpr double kGapStep = 0.01;
constexpr double kMinPieceMm = 1e-5;
std::vector<Segment> gap_pieces(const Segment& s) {
  const double change = std::abs(s.g1 - s.g0), smaller = std::min(s.g0, s.g1);
  const double by_gap = smaller > 0 ? std::ceil(change / (kGapStep * smaller)) : 1.0;
  const double by_length = std::floor(length(s) / kMinPieceMm);
  const int n = static_cast<int>(std::clamp(std::min(by_gap, by_length), 1.0, 1e5));
  if (n == 1) return {s};
  std::vector<Segment> out;
  for (int k = 0; k < n; ++k) out.push_back(sub_segment(s, double(k) / n, double(k + 1) / n));
  return out;
}

// Whether the lead keeps a clearance >= -eps all along. The distance to the profile changes by at most the
// distance moved, so from a point at distance d the lead may advance d - (the largest gap) without coming
// within any gap; a fixed number of samples had stepped a 128 mm lead's quarter arc over the profile's
// wall (black-box testing). Near the gap the steps are a 256th of the smallest gap: a dip between two of
// them stays within half of that.
bool lead_clear(const Segment& s, const ClearanceField& field, double eps) {
  double g_min = INFINITY, g_max = 0.0;
  for (const Piece& p : field_pieces(field)) {
    g_min = std::min({g_min, p.g0, p.g1});
    g_max = std::max({g_max, p.g0, p.g1});
  }
  const double L = length(s), min_step = std::max(1e-6, g_min / 256);
  constexpr int kMaxSamples = 1000000;  // a lead that runs along the gap that long is refused
  double u = 0.0;
  for (int k = 0; k < kMaxSamples; ++k) {
    const Vector2d p = point_at(s, L > 0 ? u / L : 0.0);
    if (clearance(field, p) < -eps) return false;
    if (u >= L) return true;
    u = std::min(L, u + std::max(profile_distance(field, p) - g_max, min_step));
  }
  return false;
}

// Motion writer shared by both programs: tracks the printed position so that I, J are relative to it.
struct Writer {
  std::ostream& out;
  Vector2d cur{0, 0};
  int motion = -1;  // last modal motion code written

  void rapid_xy(const Vector2d& p) {
    cur = rounded(p);
    out << "G0 X" << num(p.x()) << " Y" << num(p.y()) << "\n";
    motion = 0;
  }
  // Writes the move; false when it vanishes at the printed resolution (then the feed word is kept).
  bool segment(const Segment& s, const std::string& feed_word) {
    const Vector2d end = rounded(s.b);
    if (end == cur) return false;  // would read as a full circle (G2/G3) or nothing (G1)
    // Arcs whose sagitta is below the printed resolution go out as lines (tiny or nearly straight arcs,
    // which the interpreter's radius check handles badly).
    // So do arcs of a radius LinuxCNC refuses as a "zero-radius arc" (below 0.00127 mm: 0.0012 is refused,
    // 0.0013 read, measured with rs274): the chord leaves such an arc by less than its radius.
    const double sagitta = s.is_arc() ? s.r * (1 - std::cos(0.5 * std::min(std::abs(s.sweep), 3.0))) : 0.0;
    if (!s.is_arc() || (s.b - s.a).norm() < 1e-6 || sagitta < 5e-9 || s.r < kZeroRadiusArc) {
      out << "G1 X" << num(s.b.x()) << " Y" << num(s.b.y()) << feed_word << "\n";
    } else {
      out << (s.sweep > 0 ? "G3" : "G2") << " X" << num(s.b.x()) << " Y" << num(s.b.y()) << " I"
          << num(s.c.x() - cur.x()) << " J" << num(s.c.y() - cur.y()) << feed_word << "\n";
    }
    cur = end;
    return true;
  }
};

void header(std::ostream& out, const ProgramInfo& info, const std::vector<RunContour>& contours, const char* what) {
  out << "(tiltfield offset: " << what << ")\n";
  out << "(profile " << info.profile_file << ", gap " << info.gap_text << ", side " << info.side << ", corner "
      << info.corner << ")\n";
  out << "(" << contours.size() << " contour" << (contours.size() == 1 ? "" : "s")
      << ", tool-centre path in the XY plane, mm)\n";
  out << "G21 G17 G90 G94 G40 G49 G80\n";
  out << "G91.1\n";
}
}  // namespace

std::vector<RunContour> plan_leads(const OffsetResult& result, const ClearanceField& field, double lead_radius) {
  std::vector<RunContour> out;
  for (const auto& c : result.contours) {
    if (c.empty()) continue;
    RunContour rc;
    rc.path = rotate_to_longest(c);
    const Vector2d S = rc.path.front().a;
    const Vector2d t = tangent_at(rc.path.front(), 0.0);
    const Vector2d nl(-t.y(), t.x());
    // The free side: where the clearance grows away from the path.
    double probe = 1e-3;
    for (const auto& s : c) probe = std::max(probe, 1e-3 * std::max(s.g0, s.g1));
    const bool left_free = clearance(field, S + probe * nl) >= clearance(field, S - probe * nl);
    const Vector2d away = left_free ? nl : Vector2d(-nl);
    const double eps = 1e-7;
    for (double rho = lead_radius; rho >= lead_radius / 64 && rho > 0; rho *= 0.5) {
      const Vector2d C = S + rho * away;
      Segment in = make_arc_to(C - rho * t, S, C, left_free);
      Segment lo = make_arc_to(S, C + rho * t, C, left_free);
      if (lead_clear(in, field, eps) && lead_clear(lo, field, eps)) {
        rc.lead_in = in;
        rc.lead_out = lo;
        rc.has_leads = true;
        break;
      }
    }
    out.push_back(std::move(rc));
  }
  return out;
}

void write_milling_program(std::ostream& out, const std::vector<RunContour>& contours, const ProgramInfo& info,
                           const MillingOptions& o) {
  header(out, info, contours, "copy-milling trajectory");
  out << "S" << num(o.spindle_rpm) << " M3\n";
  out << "G0 Z" << num(o.z_safe) << "\n";
  Writer w{out};
  const std::string feed = " F" + num(o.feed);
  for (size_t k = 0; k < contours.size(); ++k) {
    const RunContour& rc = contours[k];
    out << "(contour " << k + 1 << " of " << contours.size() << (rc.has_leads ? "" : ", no room for leads") << ")\n";
    w.rapid_xy(rc.has_leads ? rc.lead_in.a : rc.path.front().a);
    out << "G1 Z" << num(o.z_cut) << " F" << num(o.plunge_feed) << "\n";
    std::string f = feed;
    auto emit = [&](const Segment& s) {
      if (w.segment(s, f)) f.clear();
    };
    if (rc.has_leads) {
      out << "(lead-in)\n";
      emit(rc.lead_in);
    }
    out << "(path)\n";
    for (const auto& s : rc.path) emit(s);
    if (rc.has_leads) {
      out << "(lead-out)\n";
      emit(rc.lead_out);
    }
    out << "G0 Z" << num(o.z_safe) << "\n";
  }
  out << "M5\nM30\n";
}

void write_ecm_program(std::ostream& out, const std::vector<RunContour>& contours, const ProgramInfo& info,
                       const EcmOptions& o) {
  header(out, info, contours, "ECM trajectory, unprofiled electrode");
  out << "(electrode-workpiece gap " << num(o.gap) << " mm, voltage " << num(o.voltage) << " V on E"
      << o.voltage_channel << ", generator on P" << o.generator_output << ", feed " << num(o.feed) << " mm/min)\n";
  out << "G0 Z" << num(o.z_safe) << "\n";
  Writer w{out};
  const std::string gen = " P" + std::to_string(o.generator_output);
  const std::string feed = " F" + num(o.feed);
  auto voltage_for = [&](const Segment& s) {
    if (!o.voltage_follows_gap || o.gap <= 0) return o.voltage;
    return o.voltage * 0.5 * (s.g0 + s.g1) / o.gap;
  };
  for (size_t k = 0; k < contours.size(); ++k) {
    const RunContour& rc = contours[k];
    out << "(contour " << k + 1 << " of " << contours.size() << (rc.has_leads ? "" : ", no room for leads") << ")\n";
    w.rapid_xy(rc.has_leads ? rc.lead_in.a : rc.path.front().a);
    out << "G1 Z" << num(o.z_work) << " F" << num(o.approach_feed) << "\n";
    double u = voltage_for(o.voltage_follows_gap ? gap_pieces(rc.path.front()).front() : rc.path.front());
    auto power_on = [&] {
      out << o.electrolyte_on << " (electrolyte on)\n";
      out << "G4 P" << num(o.flush_dwell_s) << " (flush the gap)\n";
      out << "M68 E" << o.voltage_channel << " Q" << num(u) << " (voltage set-point)\n";
      out << "M64" << gen << " (generator on)\n";
      out << "G4 P" << num(o.start_dwell_s) << "\n";
    };
    power_on();
    std::string f = feed;
    double since_retract = 0;
    // path: a move of the contour (its gap law sets the voltage); lead_out: the last move, after which the
    // generator goes off anyway, so no flush follows it.
    // at_flush: the move ends where emit_split cut it for a flush, which is made whatever the sum of the
    // lengths says (rounded, it could stay a hair short, and the next piece, shorter than an ulp of its
    // parameter, never moved on: the program hung, black-box testing).
    auto emit = [&](const Segment& s, bool path, bool lead_out = false, bool at_flush = false) {
      // The set-point in force is kept while U/g at both ends of the move stays within 0.5 % of nominal.
      auto off_field = [&](double g) { return std::abs(u * o.gap / (o.voltage * g) - 1) > 0.005; };
      if (path && o.voltage_follows_gap && o.gap > 0 && o.voltage > 0 && (off_field(s.g0) || off_field(s.g1))) {
        const double v = voltage_for(s);
        if (v != u) {
          u = v;
          out << "M67 E" << o.voltage_channel << " Q" << num(u) << " (voltage follows the gap)\n";
        }
      }
      if (w.segment(s, f)) f.clear();
      since_retract += length(s);
      if (!lead_out && o.retract_every_mm > 0 && (at_flush || since_retract >= o.retract_every_mm)) {
        since_retract = 0;
        out << "M65" << gen << " (generator off: retract and flush)\n";
        out << "G0 Z" << num(o.z_work + o.retract_height) << "\n";
        out << "G4 P" << num(o.flush_dwell_s) << "\n";
        out << "G1 Z" << num(o.z_work) << " F" << num(o.approach_feed) << "\n";
        out << "M64" << gen << " (generator on)\n";
        out << "G4 P" << num(o.start_dwell_s) << "\n";
        f = feed;
      }
    };
    // A flush every retract_every_mm with the generator on: a move longer than what is left to the next
    // one is cut there (the retracts had come only at the ends of moves: 98 mm between flushes on a 100 mm
    // square, black-box testing). A rest shorter than kMinPieceMm stays with its piece.
    // The leads too: the generator is on along them (a lead-in longer than the interval had left the
    // path's first cut a negative length, running backwards along the contour; review).
    auto emit_split = [&](const Segment& s, bool path, bool lead_out = false) {
      const double L = length(s);
      double t = 0;
      while (o.retract_every_mm > 0 && L > 0) {
        // At least kMinPieceMm a piece, so that t always moves on.
        const double left = std::max(o.retract_every_mm - since_retract, kMinPieceMm);
        if ((1 - t) * L <= left + kMinPieceMm) break;
        const double t1 = t + left / L;
        emit(sub_segment(s, t, t1), path, false, true);
        t = t1;
      }
      Segment rest = t == 0 ? s : sub_segment(s, t, 1.0);
      rest.b = s.b;
      emit(rest, path, lead_out);
    };
    auto emit_path = [&](const Segment& s) { emit_split(s, true); };
    if (rc.has_leads) {
      out << "(lead-in)\n";
      emit_split(rc.lead_in, false);
    }
    out << "(path)\n";
    for (const auto& s : rc.path) {
      if (!o.voltage_follows_gap) {
        emit_path(s);
        continue;
      }
      for (const auto& piece : gap_pieces(s)) emit_path(piece);
    }
    if (rc.has_leads) {
      out << "(lead-out)\n";
      emit_split(rc.lead_out, false, true);
    }
    out << "M65" << gen << " (generator off)\n";
    out << "G4 P" << num(o.end_dwell_s) << "\n";
    out << o.electrolyte_off << " (electrolyte off)\n";
    out << "G0 Z" << num(o.z_safe) << "\n";
  }
  out << "M30\n";
}

void write_svg(std::ostream& out, const Profile& profile, const std::vector<RunContour>& contours) {
  Eigen::AlignedBox2d box;
  box.setEmpty();
  for (const auto& e : profile.elements) box.extend(bounding_box(e));
  for (const auto& rc : contours) {
    for (const auto& s : rc.path) box.extend(bounding_box(s));
    if (rc.has_leads) box.extend(bounding_box(rc.lead_in)).extend(bounding_box(rc.lead_out));
  }
  const double margin = 0.05 * box.diagonal().norm() + 1;
  box.min().array() -= margin;
  box.max().array() += margin;
  const double w = box.sizes().x(), h = box.sizes().y(), stroke = box.diagonal().norm() / 600;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(800) << "\" height=\"" << num(800 * h / w)
      << "\" viewBox=\"" << num(box.min().x()) << " " << num(-box.max().y()) << " " << num(w) << " " << num(h)
      << "\">\n";
  out << "<g transform=\"scale(1,-1)\" fill=\"none\" stroke-linejoin=\"round\" stroke-width=\"" << num(stroke) << "\">\n";
  auto path_of = [&](const std::vector<Segment>& segs, const char* color, const char* extra) {
    if (segs.empty()) return;
    out << "<path stroke=\"" << color << "\"" << extra << " d=\"M " << num(segs[0].a.x()) << " " << num(segs[0].a.y());
    for (const auto& s : segs) {
      if (s.is_arc())
        out << " A " << num(s.r) << " " << num(s.r) << " 0 " << (std::abs(s.sweep) > std::numbers::pi ? 1 : 0) << " "
            << (s.sweep > 0 ? 1 : 0) << " " << num(s.b.x()) << " " << num(s.b.y());
      else
        out << " L " << num(s.b.x()) << " " << num(s.b.y());
    }
    out << "\"/>\n";
  };
  path_of(profile.elements, "black", "");
  for (const auto& rc : contours) {
    path_of(rc.path, "#1f5fbf", "");
    std::vector<Segment> sharp;
    for (const auto& s : rc.path)
      if (s.kind == SegmentKind::SharpJoin) sharp.push_back(s);
    for (const auto& s : sharp) path_of({s}, "#d02020", "");
    if (rc.has_leads) {
      path_of({rc.lead_in}, "#888888", " stroke-dasharray=\"2,1\"");
      path_of({rc.lead_out}, "#888888", " stroke-dasharray=\"2,1\"");
    }
  }
  out << "</g>\n</svg>\n";
}

}  // namespace tf::offset
