// Shared helpers of the offset tests: sample profiles, dense exactness checks, the Clipper reference.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <polyclipping/clipper.hpp>
#include <sstream>
#include <string>

#include "offset/clipper_reference.hpp"
#include "tiltfield/offset/offset.hpp"

namespace tf::offset::test {

inline std::string scene_file(const std::string& name) {
  // Appended in place: GCC 12's -Warray-bounds misreads operator+ on a temporary here (a false positive).
  std::string path = TILTFIELD_SOURCE_DIR;
  path += "/scenes/offset/";
  path += name;
  return path;
}

inline Profile scene_profile(const std::string& name) { return read_profile(scene_file(name)); }

inline Profile profile_text(const std::string& text) {
  Profile p = parse_profile(text, "test");
  validate_profile(p);
  return p;
}

// Two lobes of radius R joined by a neck of half-width h, lobe centres at +-cx.
inline std::string lobes_text(double R, double h, double cx) {
  const double x1 = cx - std::sqrt(R * R - h * h);
  std::ostringstream s;
  s.precision(17);
  s << "START " << -x1 << " " << -h << "\n0 " << 2 * x1 << " 0\n" << R << " 0 " << 2 * h << " LONG\n0 " << -2 * x1
    << " 0\n" << R << " 0 " << -2 * h << " LONG\n";
  return s.str();
}

struct Exactness {
  double max_error = 0;     // max |distance - gap(s)| over exact samples
  double min_sharp = 1e9;   // min (distance - gap) over sharp-join samples
  double min_transition = 1e9;   // min (distance - gap) over transition samples
  double transition_length = 0;  // mm of path marked Transition
  double max_fitted = 0;    // max |distance - gap(s)| over fitted-arc samples
  int samples = 0;
};

// Samples every output segment densely and compares its distance to the profile with the gap law at
// the closest point's arc length.
inline Exactness check_exactness(const Profile& profile, const GapLaw& law, const OffsetResult& r, int per_segment = 64) {
  Exactness e;
  const auto field = make_clearance_field(profile, law);
  for (const auto& c : r.contours)
    for (const auto& s : c)
      for (int k = 0; k <= per_segment; ++k) {
        const Eigen::Vector2d q = point_at(s, static_cast<double>(k) / per_segment);
        double sc = 0;
        const double d = profile_distance(*field, q, &sc);
        const double dev = d - gap_at(law, sc);
        ++e.samples;
        if (s.kind == SegmentKind::SharpJoin) {
          e.min_sharp = std::min(e.min_sharp, dev);
        } else if (s.kind == SegmentKind::Transition) {
          e.min_transition = std::min(e.min_transition, dev);
          e.transition_length += length(s) / (per_segment + 1);
        }
        else if (s.kind == SegmentKind::Fitted)
          e.max_fitted = std::max(e.max_fitted, std::abs(dev));
        else
          e.max_error = std::max(e.max_error, std::abs(dev));
      }
  return e;
}

// A common point at the ends of both segments: contours may touch at a junction node (the boundary of
// a region pinched to a point), but never cross.
inline bool touch_at_ends(const Crossing& x) {
  auto end = [](double t) { return t < 1e-9 || t > 1 - 1e-9; };
  return end(x.t1) && end(x.t2);
}

// Chains are closed and continuous, and no two non-neighbouring segments meet.
inline void expect_clean_contours(const OffsetResult& r) {
  for (const auto& c : r.contours) {
    ASSERT_GE(c.size(), 1u);
    for (size_t k = 0; k < c.size(); ++k) EXPECT_LE((c[k].b - c[(k + 1) % c.size()].a).norm(), 1e-9);
    for (size_t i = 0; i < c.size(); ++i)
      for (size_t j = i + 1; j < c.size(); ++j) {
        const bool neighbours = j == i + 1 || (i == 0 && j + 1 == c.size());
        for (const auto& x : intersect(c[i], c[j], 1e-9)) {
          if (neighbours && ((x.p - c[i].b).norm() < 1e-6 || (x.p - c[i].a).norm() < 1e-6)) continue;
          if (touch_at_ends(x)) continue;
          ADD_FAILURE() << "contour crosses itself at " << x.p.transpose();
        }
      }
  }
  for (size_t a = 0; a < r.contours.size(); ++a)
    for (size_t b = a + 1; b < r.contours.size(); ++b)
      for (const auto& s : r.contours[a])
        for (const auto& t : r.contours[b])
          for (const auto& x : intersect(s, t, 1e-9)) EXPECT_TRUE(touch_at_ends(x)) << "contours cross at " << x.p.transpose();
}

inline double total_area(const OffsetResult& r) {
  double a = 0;
  for (const auto& c : r.contours) a += signed_area(c);
  return a;
}

struct ClipperOutcome {
  double area = 0;  // signed sum, mm^2 (holes negative)
  int contours = 0;
};

// Clipper's offset of the polygonised profile (`poly_tol` mm), round joins at the same arc tolerance.
inline ClipperOutcome clipper_offset(const Profile& p, double gap, Side side, bool sharp = false, double poly_tol = 0.001) {
  const double scale = 1e6;
  ClipperLib::Path path = polygonise(p, poly_tol, scale);
  ClipperLib::ClipperOffset co(1e6, poly_tol * scale);
  co.AddPath(path, sharp ? ClipperLib::jtMiter : ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  co.Execute(out, (side == Side::Inside ? -gap : gap) * scale);
  ClipperOutcome o;
  for (const auto& q : out) o.area += ClipperLib::Area(q) / (scale * scale);
  o.contours = static_cast<int>(out.size());
  return o;
}

// This process's scratch folder, removed when the process ends (every test ran as a process of its own
// and left one folder behind).
inline const std::filesystem::path& temp_folder() {
  struct Folder {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("tf_offset_test_" + std::to_string(::getpid()));
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Folder folder;
  return folder.path;
}

inline std::string write_temp(const std::string& name, const std::string& text) {
  const auto f = temp_folder() / name;
  std::ofstream(f, std::ios::binary) << text;
  return f.string();
}

}  // namespace tf::offset::test
