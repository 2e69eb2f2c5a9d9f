// Cross-section machining: per section and per operation, the wheel's plane sections
// at consecutive increments are hulled pairwise and the union of the hulls is subtracted with Clipper.
// Material removal commutes, so one subtraction per section and operation is exact.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <sstream>
#include <string>
#include <polyclipping/clipper.hpp>
#include <unordered_map>

#include "tiltfield/core/error.hpp"
#include "section_contours.hpp"
#include "wheel_section.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::grind {
namespace {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;
using detail::PoseInfo;

constexpr double kScale = 1e6;  // Clipper units per mm (1 nm)
constexpr size_t kMergeEvery = 4096;  // hulls held before they are merged

struct PointHash {
  size_t operator()(const IntPoint& p) const {
    return std::hash<long long>()(p.X * 0x9E3779B97F4A7C15LL ^ (p.Y + (p.Y << 21)));
  }
};

// One section during simulation: Clipper paths and the label of each path's edges.
struct Slice {
  Paths paths;
  std::vector<std::vector<int>> labels;
};

IntPoint to_int(const Eigen::Vector2d& p) {
  return {static_cast<cInt>(std::llround(p.x() * kScale)), static_cast<cInt>(std::llround(p.y() * kScale))};
}

// True when q lies on the segment a-b within `tol` Clipper units.
bool on_segment(const IntPoint& a, const IntPoint& b, const IntPoint& q, double tol) {
  const double dx = double(b.X - a.X), dy = double(b.Y - a.Y), qx = double(q.X - a.X), qy = double(q.Y - a.Y);
  const double len2 = dx * dx + dy * dy;
  if (len2 == 0.0) return qx * qx + qy * qy <= tol * tol;
  const double cr = dx * qy - dy * qx;
  if (cr * cr > tol * tol * len2) return false;
  const double dot = dx * qx + dy * qy;
  return dot >= -tol * std::sqrt(len2) && dot <= len2 + tol * std::sqrt(len2);
}

// Labels the edges of `result` (the old slice minus new cuts): an edge lying on an old edge keeps that
// edge's label, any other edge was made by the cut and gets `label`. Candidate old edges are those at
// either end of the new edge; the new edge's midpoint must lie on one (within the cleaning tolerance, as
// cleaning may have dropped the old vertex between a cut point and the next old vertex).
std::vector<std::vector<int>> relabel(const Slice& old, const Paths& result, int label, double clean) {
  struct Link {
    IntPoint prev, next;
    int prev_label, next_label;
  };
  std::unordered_map<IntPoint, Link, PointHash> links;
  for (size_t i = 0; i < old.paths.size(); ++i) {
    const Path& p = old.paths[i];
    const size_t n = p.size();
    for (size_t k = 0; k < n; ++k)
      links[p[k]] = {p[(k + n - 1) % n], p[(k + 1) % n], old.labels[i][(k + n - 1) % n], old.labels[i][k]};
  }
  const double tol = 2.0 * clean + 3.0;
  std::vector<std::vector<int>> labels(result.size());
  for (size_t i = 0; i < result.size(); ++i) {
    const Path& p = result[i];
    labels[i].resize(p.size(), label);
    for (size_t k = 0; k < p.size(); ++k) {
      const IntPoint &a = p[(k)], &b = p[(k + 1) % p.size()];
      const IntPoint m{(a.X + b.X) / 2, (a.Y + b.Y) / 2};
      for (const IntPoint* end : {&a, &b}) {
        auto it = links.find(*end);
        if (it == links.end()) continue;
        const Link& l = it->second;
        if (on_segment(*end, l.next, m, tol)) {
          labels[i][k] = l.next_label;
          break;
        }
        if (on_segment(l.prev, *end, m, tol)) {
          labels[i][k] = l.prev_label;
          break;
        }
      }
    }
  }
  return labels;
}

// Points of the blank's circle polygon: chords within tol of the circle, at least 16.
int circle_points(const Blank& blank, double tol) {
  const double dphi = 2.0 * std::acos(std::max(-1.0, 1.0 - tol / blank.radius));
  return std::max(16, static_cast<int>(std::ceil(2.0 * M_PI / std::max(dphi, 1e-6))));
}

// Gaps between the sections: the spacing, the last gap shrunk to end at the blank's length.
int section_gaps(const Blank& blank, double spacing) {
  return std::max(1, static_cast<int>(std::ceil(blank.length / spacing - 1e-9)));
}

Path blank_circle(const Blank& blank, double tol) {
  const int n = circle_points(blank, tol);
  const double r = blank.radius;
  Path p;
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * M_PI * i / n;
    p.push_back(to_int({r * std::cos(phi), r * std::sin(phi)}));
  }
  return p;
}

// The wheel poses of one operation: the increments of all its moves, chained, starting where the previous
// operation ended.
std::vector<PoseInfo> operation_poses(const Operation& op, const Axes& before, const GrindScene& scene,
                                      double step) {
  std::vector<PoseInfo> poses{detail::pose_info(wheel_pose(before), scene.wheel, scene.blank, before.a)};
  poses.front().a = before.a, poses.front().w = before.w;
  Axes from = before;
  for (const Move& m : op.moves) {
    const int n = increments(from, m.target, scene.blank, step);
    if (n > kMaxIncrements) {
      std::ostringstream msg;
      msg << "this move needs more than " << kMaxIncrements << " increments of --step " << step
          << " mm; split it or give a larger --step";
      throw InputError(scene.program, m.line, "", msg.str());
    }
    for (int i = 1; i <= n; ++i) {
      const Axes axes = interpolate(from, m.target, double(i) / n);
      PoseInfo p = detail::pose_info(wheel_pose(axes), scene.wheel, scene.blank, axes.a);
      p.a = axes.a, p.w = axes.w;
      // Of a run of poses where the wheel cannot reach the blank only the first and the last are kept: the
      // pairs inside it are skipped by the sections anyway (both far), and a long move in the air would
      // otherwise hold millions of them.
      const size_t k = poses.size();
      if (p.far && k >= 2 && poses[k - 1].far && poses[k - 2].far) poses[k - 1] = p;
      else poses.push_back(p);
    }
    from = m.target;
  }
  return poses;
}

// Sutherland-Hodgman clip of a convex polygon to an axis-aligned box.
std::vector<Eigen::Vector2d> clip_to_box(std::vector<Eigen::Vector2d> poly, double x0, double x1, double y0,
                                         double y1) {
  auto clip = [&](int axis, double v, bool keep_below) {
    std::vector<Eigen::Vector2d> out;
    const size_t n = poly.size();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d &p = poly[i], &q = poly[(i + 1) % n];
      const bool pin = keep_below ? p[axis] <= v : p[axis] >= v;
      const bool qin = keep_below ? q[axis] <= v : q[axis] >= v;
      if (pin) out.push_back(p);
      if (pin != qin) out.push_back(p + (q - p) * ((v - p[axis]) / (q[axis] - p[axis])));
    }
    poly = std::move(out);
  };
  clip(0, x0, false);
  if (poly.size() >= 3) clip(0, x1, true);
  if (poly.size() >= 3) clip(1, y0, false);
  if (poly.size() >= 3) clip(1, y1, true);
  return poly;
}

// Regions as outer boundaries each with its holes. A hole is kept with its boundary: alone in a batch
// (its winding -1 is filled under NonZero) it would grind away the material it holds (review).
using Regions = std::vector<Paths>;

void add_regions(const ClipperLib::PolyNode& node, double clean, Regions& out) {
  for (const ClipperLib::PolyNode* outer : node.Childs) {
    Paths region{outer->Contour};
    for (const ClipperLib::PolyNode* hole : outer->Childs) {
      region.push_back(hole->Contour);
      add_regions(*hole, clean, out);  // islands inside the hole
    }
    detail::clean_contours(region, clean);
    if (region.front().size() < 3) continue;
    region.erase(std::remove_if(region.begin() + 1, region.end(), [](const Path& p) { return p.size() < 3; }), region.end());
    out.push_back(std::move(region));
  }
}

// Union of many overlapping regions, by a tree of small unions: consecutive hulls overlap heavily, and
// Clipper's cost grows with the number of edges active at once, so small batches are much faster.
Regions union_tree(Regions regions, double clean) {
  constexpr size_t kBatch = 8;
  while (regions.size() > 1) {
    Regions next;
    for (size_t i = 0; i < regions.size(); i += kBatch) {
      ClipperLib::Clipper c;
      for (size_t k = i; k < std::min(regions.size(), i + kBatch); ++k) c.AddPaths(regions[k], ClipperLib::ptSubject, true);
      ClipperLib::PolyTree tree;
      c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
      add_regions(tree, clean, next);
    }
    if (next.size() >= regions.size()) return next;  // disjoint pieces: nothing left to merge
    regions = std::move(next);
  }
  return regions;
}

// Cuts one operation into one section: returns whether anything was removed.
bool cut_section(Slice& slice, double z0, const std::vector<PoseInfo>& poses, const Wheel& wheel,
                 const std::vector<Eigen::Vector2d>& trig, const SectionOptions& opt, int label) {
  if (slice.paths.empty()) return false;
  double bx0 = 1e300, bx1 = -1e300, by0 = 1e300, by1 = -1e300;
  for (const Path& p : slice.paths)
    for (const IntPoint& q : p) {
      bx0 = std::min(bx0, q.X / kScale), bx1 = std::max(bx1, q.X / kScale);
      by0 = std::min(by0, q.Y / kScale), by1 = std::max(by1, q.Y / kScale);
    }
  // Radius of the material around the blank axis: a wheel farther than this from (0, 0, z0) cannot cut.
  double reach = 0.0;
  for (const Path& p : slice.paths)
    for (const IntPoint& q : p) reach = std::max(reach, std::hypot(double(q.X), double(q.Y)) / kScale);
  const Eigen::Vector3d axis_point(0.0, 0.0, z0);
  const double margin = 0.01 * (bx1 - bx0 + by1 - by0) + 0.01;
  Regions clips;
  std::vector<Eigen::Vector2d> cur, prev, pts;
  std::vector<int> cur_ids, prev_ids;
  std::vector<std::vector<Eigen::Vector2d>> swept;
  long prev_index = -2;
  auto section_at = [&](size_t k, std::vector<Eigen::Vector2d>& out, std::vector<int>& ids) {
    out.clear();
    ids.clear();
    const PoseInfo& p = poses[k];
    if (p.far || z0 < p.z_lo || z0 > p.z_hi || detail::distance_bound(p, wheel, axis_point) > reach) return;
    detail::wheel_section_points(p, wheel.profile, z0, trig, out, &ids);
  };
  size_t merge_at = kMergeEvery;
  // Only the part over the section matters; the rest of the wheel's section only slows Clipper down.
  auto add_clip = [&](const std::vector<Eigen::Vector2d>& poly) {
    double px0 = 1e300, px1 = -1e300, py0 = 1e300, py1 = -1e300;
    for (const auto& q : poly)
      px0 = std::min(px0, q.x()), px1 = std::max(px1, q.x()), py0 = std::min(py0, q.y()), py1 = std::max(py1, q.y());
    if (px1 < bx0 || px0 > bx1 || py1 < by0 || py0 > by1) return;  // beside the section's material
    const std::vector<Eigen::Vector2d> part = clip_to_box(poly, bx0 - margin, bx1 + margin, by0 - margin, by1 + margin);
    if (part.size() < 3) return;
    Path path;
    path.reserve(part.size());
    for (const auto& q : part) path.push_back(to_int(q));
    // Rounded to the integer grid a sliver may have turned over: under the union's NonZero rule a
    // clockwise piece would cancel the cover of another, so it is turned back, or dropped when it has no
    // area to speak of.
    const double area = ClipperLib::Area(path);
    if (std::abs(area) <= opt.clean_tolerance * kScale * opt.clean_tolerance * kScale) return;
    if (area < 0) std::reverse(path.begin(), path.end());
    clips.push_back({std::move(path)});
    // Merged as they come: a long move's hundreds of thousands of hulls had been held until the end, about
    // 7 KB each (1.7 GB for one move of A99999 W99999, black-box testing). The union is the same.
    if (clips.size() >= merge_at) {
      clips = union_tree(std::move(clips), opt.clean_tolerance * kScale);
      merge_at = std::max(kMergeEvery, 2 * clips.size());  // many disjoint pieces: merge less often
    }
  };
  for (size_t k = 0; k + 1 < poses.size(); ++k) {
    const PoseInfo &p0 = poses[k], &p1 = poses[k + 1];
    if ((p0.far && p1.far) || z0 < std::min(p0.z_lo, p1.z_lo) || z0 > std::max(p0.z_hi, p1.z_hi)) continue;
    if (prev_index == static_cast<long>(k)) {
      std::swap(prev, cur);
      std::swap(prev_ids, cur_ids);
    } else {
      section_at(k, prev, prev_ids);
    }
    section_at(k + 1, cur, cur_ids);
    prev_index = static_cast<long>(k + 1);
    pts.assign(prev.begin(), prev.end());
    pts.insert(pts.end(), cur.begin(), cur.end());
    if (pts.size() < 3) continue;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& q : pts) {
      x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x()), y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
    }
    if (x1 < bx0 || x0 > bx1 || y1 < by0 || y0 > by1) continue;
    // A section that turns between the poses: its own sweep, where the hull of both would cut a chord
    // into the material the wheel leaves; a moving one (and a turning one none of whose edges can be
    // followed): the hull, exact for a convex section that only moves.
    const bool turns = p0.a != p1.a || p0.w != p1.w;
    if (turns && prev.size() >= 3 && cur.size() >= 3 && detail::turning_sweep(prev, prev_ids, cur, cur_ids, swept)) {
      for (const auto& poly : swept) add_clip(poly);
      continue;
    }
    add_clip(detail::convex_hull(pts));
  }
  if (clips.empty()) return false;
  clips = union_tree(std::move(clips), opt.clean_tolerance * kScale);
  Paths removed;
  for (Paths& region : clips) removed.insert(removed.end(), region.begin(), region.end());
  ClipperLib::Clipper c;
  c.StrictlySimple(true);
  c.AddPaths(slice.paths, ClipperLib::ptSubject, true);
  c.AddPaths(removed, ClipperLib::ptClip, true);
  Paths result;
  c.Execute(ClipperLib::ctDifference, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  result = detail::tidy_contours(std::move(result), opt.clean_tolerance * kScale);
  result.erase(std::remove_if(result.begin(), result.end(), [](const Path& p) { return p.size() < 3; }),
               result.end());
  slice.labels = relabel(slice, result, label, opt.clean_tolerance * kScale);
  slice.paths = std::move(result);
  return true;
}

Section to_section(const Slice& s, double z) {
  Section out;
  out.z = z;
  for (size_t i = 0; i < s.paths.size(); ++i) {
    Contour c;
    c.hole = !ClipperLib::Orientation(s.paths[i]);
    for (const IntPoint& p : s.paths[i]) c.points.emplace_back(p.X / kScale, p.Y / kScale);
    c.labels = s.labels[i];
    out.contours.push_back(std::move(c));
  }
  return out;
}

}  // namespace

double minimum_section_bytes(const GrindScene& scene, const SectionOptions& opt) {
  return (section_gaps(scene.blank, opt.spacing) + 1.0) * circle_points(scene.blank, opt.chord_tolerance) * 400.0;
}

// Rings along a profile's sloping segments at most this far apart (the shorter of the two sides): a V-wheel
// plunge's removed volume is within 0.15 % of its closed form at 0.1 mm and moves by 0.07 % at 0.008 mm; a
// rounded wheel's corners are finer already (the bundled end mill moved by 0.001 %, at three times the time).
constexpr double kProfileRingStep = 0.1;  // mm

SectionStack simulate_sections(const GrindScene& scene, const SectionOptions& opt, const Progress& progress) {
  SectionStack stack;
  stack.blank = scene.blank;
  stack.op_labels.push_back("blank");
  for (const Operation& op : scene.operations) stack.op_labels.push_back(op.kind + ": " + op.label);
  const double l = scene.blank.length;
  const int n = section_gaps(scene.blank, opt.spacing);
  // Poses once per operation, shared by all sections.
  std::vector<std::vector<PoseInfo>> poses;
  Axes before = scene.start;
  for (const Operation& op : scene.operations) {
    poses.push_back(operation_poses(op, before, scene, opt.step));
    before = op.moves.back().target;
  }
  const std::vector<Eigen::Vector2d> trig = detail::generator_table(detail::generator_count(scene.wheel.radius, opt));
  Wheel wheel = scene.wheel;
  wheel.profile = detail::rings_along_profile(wheel.profile, kProfileRingStep);
  const Path circle = blank_circle(scene.blank, opt.chord_tolerance);
  stack.sections.resize(n + 1);
  std::atomic<int> done{0}, ground{0};
  std::mutex report_mutex;
  const double blank_area = std::abs(ClipperLib::Area(circle));
  tbb::parallel_for(0, n + 1, [&](int i) {
    const double z = i == n ? l : l * i / n;
    Slice slice{{circle}, {std::vector<int>(circle.size(), 0)}};
    bool cut = false;
    for (size_t k = 0; k < poses.size(); ++k)
      cut |= cut_section(slice, z, poses[k], wheel, trig, opt, static_cast<int>(k) + 1);
    double area = 0;
    for (const Path& p : slice.paths) area += ClipperLib::Area(p);
    if (cut && area < blank_area * (1 - 1e-9)) ++ground;
    stack.sections[i] = to_section(slice, z);
    const int d = ++done;
    if (progress && (d % 16 == 0 || d == n + 1)) {
      std::lock_guard<std::mutex> lock(report_mutex);
      progress("grind", double(d) / (n + 1));
    }
  });
  stack.sections_ground = ground;
  return stack;
}

double section_area(const Section& s) {
  double area = 0.0;
  for (const Contour& c : s.contours) {
    const size_t n = c.points.size();
    for (size_t i = 0; i < n; ++i) {
      const auto &p = c.points[i], &q = c.points[(i + 1) % n];
      area += 0.5 * (p.x() * q.y() - q.x() * p.y());
    }
  }
  return area;
}

}  // namespace tf::grind
