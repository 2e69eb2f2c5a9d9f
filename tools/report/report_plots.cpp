// tiltfield report: which plots the page shows and what goes into each.
#include <algorithm>
#include <cmath>
#include <limits>

#include "report_internal.hpp"
#include "report_svg.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::reporting {

std::vector<double> arc_length(const OrientedPath& path) {
  std::vector<double> s(path.rows.size(), 0.0);
  for (size_t i = 1; i < path.rows.size(); ++i) s[i] = s[i - 1] + (path.rows[i].p - path.rows[i - 1].p).norm();
  return s;
}

std::string collision_kind(const Collision& c) {
  return std::string(to_string(c.component)) + " \u2013 " + std::string(to_string(c.with));
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kBlue = "#1f77b4";
const char* const kOrange = "#ff7f0e";
const char* const kGreen = "#2ca02c";
const char* const kPurple = "#9467bd";
const char* const kGrey = "#9aa0a6";

std::vector<Band> row_bands(const std::vector<RowWindow>& windows, const std::vector<double>& s) {
  std::vector<Band> bands;
  if (s.empty()) return bands;
  const int last = int(s.size()) - 1;
  for (const auto& w : windows) {
    const int a = std::clamp(std::min(w.first, w.last), 0, last), b = std::clamp(std::max(w.first, w.last), 0, last);
    bands.push_back({s[size_t(a)], s[size_t(b)]});
  }
  return bands;
}

std::vector<Marker> collision_markers(const std::vector<Collision>& collisions) {
  std::vector<Marker> markers;
  for (const auto& c : collisions)
    markers.push_back({double(c.block), "block " + std::to_string(c.block) + ", line " + std::to_string(c.line) + ": " +
                                            collision_kind(c) + ", " + fixed(c.depth_mm, 3) + " mm" +
                                            (c.rapid ? " (rapid)" : "")});
  return markers;
}

LinePlot orientation_plot(const ReportInputs& in, const std::vector<double>& s) {
  LinePlot p;
  p.id = "plot-orientation";
  p.title = "Tool orientation along the path";
  p.x_label = "arc length along the path (mm)";
  p.y_label = "angle (deg)";
  p.empty_note = "no oriented path";
  if (!in.oriented) return p;
  const auto& rows = in.oriented->rows;
  Series lead{"lead", kBlue, s, {}}, tilt{"tilt", kOrange, s, {}};
  for (const auto& r : rows) {
    lead.y.push_back(r.lead_deg);
    tilt.y.push_back(r.tilt_deg);
  }
  // The whole inclination from the surface normal, when the input path's normals line up with the rows.
  const auto& path = in.scene->path.rows;
  if (path.size() == rows.size()) {
    Series incl{"axis to surface normal", kGrey, s, {}};
    incl.dashed = true;
    incl.width_px = 1.2;
    for (size_t i = 0; i < rows.size(); ++i) {
      const double c = std::clamp(rows[i].axis.normalized().dot(path[i].n.normalized()), -1.0, 1.0);
      incl.y.push_back(std::acos(c) * 180.0 / M_PI);
    }
    p.series.push_back(std::move(incl));
  }
  p.series.push_back(std::move(lead));
  p.series.push_back(std::move(tilt));
  p.bands = row_bands(in.replanned, s);
  return p;
}

LinePlot clearance_plot(const ReportInputs& in, const std::vector<double>& s) {
  LinePlot p;
  p.id = "plot-clearance";
  p.title = "Clearance of the tool to the check surfaces";
  p.x_label = "arc length along the path (mm)";
  p.y_label = "clearance (mm)";
  p.empty_note = in.oriented ? "no finite clearance (no check surfaces near the tool)" : "no oriented path";
  if (!in.oriented) return p;
  if (in.first_plan && in.first_plan->rows.size() == in.oriented->rows.size()) {
    Series first{"first plan", kGrey, s, {}};
    first.dashed = true;
    for (const auto& r : in.first_plan->rows) first.y.push_back(clearance_measured(r.clearance_mm) ? r.clearance_mm : kNaN);
    p.series.push_back(std::move(first));
  }
  Series fin{in.first_plan ? "final plan" : "clearance", kGreen, s, {}};
  for (const auto& r : in.oriented->rows) fin.y.push_back(clearance_measured(r.clearance_mm) ? r.clearance_mm : kNaN);
  p.series.push_back(std::move(fin));
  p.hlines.push_back({in.scene->planner.safety_distance,
                      "safety distance " + fixed(in.scene->planner.safety_distance, 3) + " mm", "#d62728"});
  p.bands = row_bands(in.replanned, s);
  return p;
}

LinePlot rotary_plot(const ReportInputs& in) {
  LinePlot p;
  p.id = "plot-rotary";
  p.title = "Rotary axes of the posted program";
  p.x_label = "block";
  p.y_label = "axis position (deg)";
  p.empty_note = "no posted program";
  if (in.axes.empty()) return p;
  std::string letters;
  if (in.scene->machine) {
    letters = in.scene->machine->rotary_axes();
  } else {
    for (char l : {'A', 'B', 'C'})
      if (std::any_of(in.axes.begin(), in.axes.end(), [l](const BlockAxes& b) { return b.joints.rotary(l) != 0.0; }))
        letters += l;
  }
  if (letters.empty()) p.empty_note = "the machine has no rotary axes";
  const char* colors[] = {kBlue, kOrange, kPurple};
  for (size_t k = 0; k < letters.size() && k < 3; ++k) {
    Series s{std::string(1, letters[k]), colors[k], {}, {}};
    for (const auto& b : in.axes) {
      s.x.push_back(b.block);
      s.y.push_back(b.joints.rotary(letters[k]));
    }
    p.series.push_back(std::move(s));
  }
  p.markers = collision_markers(in.collisions);
  return p;
}

LinePlot block_plot(const ReportInputs& in, std::string id, std::string title, std::string y_label,
                    std::vector<std::pair<std::string, double BlockRow::*>> fields) {
  LinePlot p;
  p.id = std::move(id);
  p.title = std::move(title);
  p.x_label = "block";
  p.y_label = std::move(y_label);
  p.empty_note = in.blocks.empty() ? "no verification data" : "no block has a value (nothing engaged, or --no-engagement)";
  if (in.blocks.empty()) return p;
  const char* colors[] = {kBlue, kOrange, kGreen};
  for (size_t k = 0; k < fields.size(); ++k) {
    Series s{fields[k].first, colors[k % 3], {}, {}};
    for (const auto& b : in.blocks) {
      s.x.push_back(b.block);
      s.y.push_back(std::isfinite(b.*fields[k].second) ? b.*fields[k].second : kNaN);
    }
    p.series.push_back(std::move(s));
  }
  p.markers = collision_markers(in.collisions);
  return p;
}

}  // namespace

std::vector<std::string> build_plots(const ReportInputs& in) {
  const std::vector<double> s = in.oriented ? arc_length(*in.oriented) : std::vector<double>{};
  std::vector<LinePlot> plots;
  plots.push_back(orientation_plot(in, s));
  plots.push_back(clearance_plot(in, s));
  plots.push_back(rotary_plot(in));
  plots.push_back(block_plot(in, "plot-mrr", "Material removal rate", "MRR (mm\u00b3/min)",
                             {{"material removal rate", &BlockRow::mrr_mm3_min}}));
  plots.push_back(block_plot(in, "plot-area", "Engaged area of the cutter", "engaged area (mm\u00b2)",
                             {{"engaged area", &BlockRow::engaged_area_mm2}}));
  plots.push_back(block_plot(in, "plot-angles", "Engagement angles", "angle (deg)",
                             {{"entry", &BlockRow::entry_deg}, {"exit", &BlockRow::exit_deg}}));
  std::vector<std::string> svgs;
  for (const auto& p : plots) svgs.push_back(render_line_plot(p));
  return svgs;
}

}  // namespace tf::reporting
