// A 10,000-element profile offset: tiltfield's exact line/arc offset against Clipper's ClipperOffset on
// the same profile polygonised at 0.001 mm (round joins, arc tolerance 0.001 mm).
#include <benchmark/benchmark.h>

#include <cmath>
#include <polyclipping/clipper.hpp>
#include <sstream>

#include "offset/clipper_reference.hpp"
#include "tiltfield/offset/offset.hpp"

namespace {
using namespace tf::offset;
using tf::offset::test::polygonise;

// A wavy closed profile (radius 200 +- 5 mm, 50 waves) of n elements, lines and arcs alternating; the
// arcs bulge by chord/40, alternately to the left and the right.
Profile wavy_profile(int n) {
  std::vector<Eigen::Vector2d> pts;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * M_PI * k / n;
    const double r = 200 + 5 * std::sin(50 * t);
    pts.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  std::ostringstream s;
  s.precision(17);
  s << "START " << pts[0].x() << " " << pts[0].y() << "\n";
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d d = pts[(k + 1) % n] - pts[k];
    double R = 0;
    if (k % 2 == 1) R = (k % 4 == 1 ? 5.0 : -5.0) * d.norm();
    s << R << " " << d.x() << " " << d.y() << "\n";
  }
  Profile p = parse_profile(s.str(), "wavy");
  validate_profile(p);
  return p;
}

const Profile& profile() {
  static const Profile p = wavy_profile(10000);
  return p;
}

void BM_TiltfieldOffset(benchmark::State& state) {
  const double gap = static_cast<double>(state.range(0));
  size_t segments = 0, contours = 0, crossings = 0, raw = 0;
  for (auto _ : state) {
    const auto r = offset_profile(profile(), constant_gap(gap), {});
    contours = r.contours.size();
    crossings = static_cast<size_t>(r.crossings);
    raw = static_cast<size_t>(r.raw_segments);
    segments = 0;
    for (const auto& c : r.contours) segments += c.size();
    benchmark::DoNotOptimize(segments);
  }
  state.counters["elements_in"] = static_cast<double>(profile().elements.size());
  state.counters["segments_out"] = static_cast<double>(segments);
  state.counters["contours"] = static_cast<double>(contours);
  state.counters["crossings"] = static_cast<double>(crossings);
  state.counters["raw_segments"] = static_cast<double>(raw);
}
BENCHMARK(BM_TiltfieldOffset)->Arg(2)->Arg(5)->Unit(benchmark::kMillisecond);

void BM_ClipperOffset(benchmark::State& state) {
  const double gap = static_cast<double>(state.range(0));
  const double scale = 1e6;
  const ClipperLib::Path path = polygonise(profile(), 0.001, scale);
  size_t vertices = 0, contours = 0;
  for (auto _ : state) {
    ClipperLib::ClipperOffset co(2.0, 0.001 * scale);
    co.AddPath(path, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    ClipperLib::Paths out;
    co.Execute(out, -gap * scale);
    contours = out.size();
    vertices = 0;
    for (const auto& q : out) vertices += q.size();
    benchmark::DoNotOptimize(vertices);
  }
  state.counters["vertices_in"] = static_cast<double>(path.size());
  state.counters["vertices_out"] = static_cast<double>(vertices);
  state.counters["contours"] = static_cast<double>(contours);
}
BENCHMARK(BM_ClipperOffset)->Arg(2)->Arg(5)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
