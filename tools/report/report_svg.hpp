// tiltfield report: small SVG charts (line plots with axes, ticks, units and a legend; a stacked bar of
// stage times). Static SVG, so the page shows its plots even with scripts blocked.
#pragma once
#include <string>
#include <vector>

namespace tf::reporting {

struct Series {
  std::string label;
  std::string color = "#1f77b4";
  std::vector<double> x, y;  // same length; a non-finite y breaks the line
  bool dashed = false;
  double width_px = 1.6;
};

struct Band {  // a shaded x range (e.g. a re-planned window)
  double x0 = 0.0, x1 = 0.0;
};

struct Marker {  // a short vertical tick at the bottom of the plot (e.g. a collision)
  double x = 0.0;
  std::string title;  // tooltip
};

struct HLine {  // a horizontal reference line (e.g. the safety distance)
  double y = 0.0;
  std::string label;
  std::string color = "#d62728";
};

struct LinePlot {
  std::string id;  // element id, also used by the page's hover read-out
  std::string title;
  std::string x_label;  // with unit, e.g. "arc length (mm)"
  std::string y_label;  // with unit
  std::vector<Series> series;
  std::vector<Band> bands;
  std::string band_label = "re-planned";
  std::vector<Marker> markers;
  std::string marker_label = "collision";
  std::string marker_color = "#d62728";
  std::vector<HLine> hlines;
  std::string empty_note = "no data";  // shown instead of the axes when no series has a finite point
  int width_px = 600;
  int height_px = 280;
};

// Lines longer than two points per horizontal pixel are reduced to the min and max of each pixel
// column, so spikes survive and the SVG stays small.
std::string render_line_plot(const LinePlot& plot);

struct BarPart {
  std::string label;
  double value = 0.0;
  std::string color;
};
// One horizontal stacked bar (e.g. seconds per stage) with a legend giving each part's value and unit.
std::string render_stacked_bar(const std::vector<BarPart>& parts, const std::string& unit, int width_px);

// "Nice" axis ticks (1, 2, 5 times a power of ten) covering [lo, hi], about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target);

// Escapes &, <, >, " and ' for HTML/SVG text and attributes.
std::string escape_html(const std::string& s);

}  // namespace tf::reporting
