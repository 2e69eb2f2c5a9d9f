#include "report_svg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "tiltfield/core/io.hpp"

namespace tf::reporting {

std::string escape_html(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi <= lo || target < 1) return ticks;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {2.0, 5.0, 10.0})  // the step nearest to raw on a log scale
    if (std::abs(std::log(m * mag / raw)) < std::abs(std::log(step / raw))) step = m * mag;
  // Integer multiples, so the labels carry no accumulated rounding.
  for (long k = long(std::ceil(lo / step - 1e-9)); double(k) * step <= hi + step * 1e-9; ++k) ticks.push_back(double(k) * step);
  return ticks;
}

namespace {

// Decimals that show the tick step without noise (step 0.25 -> 2, step 50 -> 0).
int tick_decimals(const std::vector<double>& ticks) {
  if (ticks.size() < 2) return 2;
  const double step = ticks[1] - ticks[0];
  return std::clamp(int(std::ceil(-std::log10(step) - 1e-9)) + 1, 0, 6);
}

std::string tick_text(double v, int decimals) {
  if (std::abs(v) >= 1e5) {  // thousands separators keep large counts readable
    std::string s = fixed(std::round(v), 0);
    const size_t start = s[0] == '-' ? 1 : 0;
    for (int i = int(s.size()) - 3; i > int(start); i -= 3) s.insert(size_t(i), "\u2009");
    return s;
  }
  return fixed(v, decimals);
}

std::string num(double v) { return fixed(std::round(v * 10.0) / 10.0, 1); }

struct Frame {
  double left, top, width, height, x0, x1, y0, y1;
  double X(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double Y(double y) const { return top + height - (y - y0) / (y1 - y0) * height; }
};

// The SVG path of one series; min/max per pixel column when the series is dense.
std::string series_path(const Series& s, const Frame& f) {
  std::ostringstream d;
  const size_t n = std::min(s.x.size(), s.y.size());
  const bool dense = double(n) > 2.0 * f.width;
  bool pen_down = false;
  auto emit = [&](double x, double y) {
    d << (pen_down ? 'L' : 'M') << num(f.X(x)) << ',' << num(f.Y(y));
    pen_down = true;
  };
  auto drawable = [&](size_t i) { return i < n && std::isfinite(s.x[i]) && std::isfinite(s.y[i]); };
  if (!dense) {
    for (size_t i = 0; i < n; ++i) {
      if (!drawable(i)) {
        pen_down = false;
        continue;
      }
      const bool alone = !pen_down && !drawable(i + 1);
      emit(s.x[i], s.y[i]);
      if (alone) d << "h0";  // a lone point: a dot (the round cap of a zero-length line)
    }
    return d.str();
  }
  long column = std::numeric_limits<long>::min();
  size_t i_min = 0, i_max = 0;
  bool open = false;
  auto flush = [&] {
    if (!open) return;
    if (i_min == i_max) {
      emit(s.x[i_min], s.y[i_min]);
    } else {
      const size_t a = std::min(i_min, i_max), b = std::max(i_min, i_max);
      emit(s.x[a], s.y[a]);
      emit(s.x[b], s.y[b]);
    }
    open = false;
  };
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
      flush();
      pen_down = false;
      column = std::numeric_limits<long>::min();
      continue;
    }
    const long c = long(std::floor(f.X(s.x[i])));
    if (c != column) {
      flush();
      column = c;
      i_min = i_max = i;
      open = true;
    } else {
      if (s.y[i] < s.y[i_min]) i_min = i;
      if (s.y[i] > s.y[i_max]) i_max = i;
    }
  }
  flush();
  return d.str();
}

struct Extent {
  double x0, x1, y0, y1;
};

// The series' finite extent; x0 > x1 (infinite) when no point is finite.
Extent data_extent(const LinePlot& p) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : p.series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        x0 = std::min(x0, s.x[i]);
        x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, s.y[i]);
        y1 = std::max(y1, s.y[i]);
      }
  return {x0, x1, y0, y1};
}

// The plot area within the picture and its value ranges: the data and the reference lines, a flat
// range widened, y padded by 6 % either side.
Frame plot_frame(const LinePlot& p, const Extent& extent) {
  double x0 = extent.x0, x1 = extent.x1, y0 = extent.y0, y1 = extent.y1;
  for (const auto& h : p.hlines)
    if (std::isfinite(h.y)) {
      y0 = std::min(y0, h.y);
      y1 = std::max(y1, h.y);
    }
  if (x1 - x0 < 1e-12) {
    x0 -= 0.5;
    x1 += 0.5;
  }
  const double pad = y1 - y0 < 1e-12 ? std::max(1.0, std::abs(y0) * 0.1) : 0.06 * (y1 - y0);
  y0 -= pad;
  y1 += pad;
  return {64.0, 50.0, double(p.width_px) - 64.0 - 16.0, double(p.height_px) - 50.0 - 42.0, x0, x1, y0, y1};
}

// One swatch per series, then the band, markers and reference lines, wrapping by width.
void write_legend(std::ostringstream& o, const LinePlot& p) {
  const int W = p.width_px;
  double lx = 64.0, ly = 36.0;
  auto legend = [&](const std::string& swatch, const std::string& label) {
    const double w = 26.0 + 6.5 * double(label.size());
    if (lx + w > W - 8 && lx > 64.0) {
      lx = 64.0;
      ly += 14.0;
    }
    o << "<g transform=\"translate(" << num(lx) << ',' << num(ly) << ")\">" << swatch
      << "<text x=\"20\" y=\"4\" fill=\"#333\">" << escape_html(label) << "</text></g>";
    lx += w + 10.0;
  };
  for (const auto& s : p.series)
    legend("<line x1=\"0\" y1=\"0\" x2=\"16\" y2=\"0\" stroke=\"" + s.color + "\" stroke-width=\"2.5\"" +
               (s.dashed ? " stroke-dasharray=\"4 3\"" : "") + "/>",
           s.label);
  if (!p.bands.empty())
    legend("<rect x=\"0\" y=\"-5\" width=\"16\" height=\"10\" fill=\"#ff9f1c\" fill-opacity=\"0.25\"/>", p.band_label);
  if (!p.markers.empty())
    legend("<line x1=\"8\" y1=\"-6\" x2=\"8\" y2=\"6\" stroke=\"" + p.marker_color + "\" stroke-width=\"2\"/>",
           p.marker_label + " (" + std::to_string(p.markers.size()) + ")");
  for (const auto& h : p.hlines)
    legend("<line x1=\"0\" y1=\"0\" x2=\"16\" y2=\"0\" stroke=\"" + h.color +
               "\" stroke-width=\"1.5\" stroke-dasharray=\"6 3\"/>",
           h.label);
}

// The plot area, the shaded bands, grid lines at nice ticks with their labels, and the axis titles.
void write_axes(std::ostringstream& o, const LinePlot& p, const Frame& f) {
  o << "<rect class=\"plot-area\" x=\"" << num(f.left) << "\" y=\"" << num(f.top) << "\" width=\"" << num(f.width)
    << "\" height=\"" << num(f.height) << "\" fill=\"#fbfbfc\" stroke=\"#c8ccd2\"/>";
  for (const auto& b : p.bands) {
    const double a = std::clamp(f.X(std::min(b.x0, b.x1)), f.left, f.left + f.width);
    const double c = std::clamp(f.X(std::max(b.x0, b.x1)), f.left, f.left + f.width);
    o << "<rect class=\"band\" x=\"" << num(a) << "\" y=\"" << num(f.top) << "\" width=\"" << num(std::max(1.0, c - a))
      << "\" height=\"" << num(f.height) << "\" fill=\"#ff9f1c\" fill-opacity=\"0.25\"/>";
  }
  const auto xt = nice_ticks(f.x0, f.x1, std::max(2, int(f.width / 90.0)));
  const auto yt = nice_ticks(f.y0, f.y1, std::max(2, int(f.height / 45.0)));
  const int xd = tick_decimals(xt), yd = tick_decimals(yt);
  o << "<g stroke=\"#e3e6ea\">";
  for (double t : yt)
    o << "<line x1=\"" << num(f.left) << "\" x2=\"" << num(f.left + f.width) << "\" y1=\"" << num(f.Y(t))
      << "\" y2=\"" << num(f.Y(t)) << "\"/>";
  for (double t : xt)
    o << "<line y1=\"" << num(f.top) << "\" y2=\"" << num(f.top + f.height) << "\" x1=\"" << num(f.X(t))
      << "\" x2=\"" << num(f.X(t)) << "\"/>";
  o << "</g><g fill=\"#555\">";
  for (double t : yt)
    o << "<text x=\"" << num(f.left - 6) << "\" y=\"" << num(f.Y(t) + 4) << "\" text-anchor=\"end\">"
      << tick_text(t, yd) << "</text>";
  for (double t : xt)
    o << "<text x=\"" << num(f.X(t)) << "\" y=\"" << num(f.top + f.height + 16) << "\" text-anchor=\"middle\">"
      << tick_text(t, xd) << "</text>";
  o << "</g>";
  o << "<text x=\"" << num(f.left + f.width / 2) << "\" y=\"" << p.height_px - 8
    << "\" text-anchor=\"middle\" fill=\"#333\">" << escape_html(p.x_label) << "</text>";
  o << "<text transform=\"translate(16," << num(f.top + f.height / 2)
    << ") rotate(-90)\" text-anchor=\"middle\" fill=\"#333\">" << escape_html(p.y_label) << "</text>";
}

// Markers: one tick per pixel column at the bottom of the plot, its tooltip listing what fell there.
void write_markers(std::ostringstream& o, const LinePlot& p, const Frame& f) {
  std::map<long, std::vector<const Marker*>> columns;
  for (const auto& m : p.markers)
    if (std::isfinite(m.x)) columns[std::lround(f.X(std::clamp(m.x, f.x0, f.x1)))].push_back(&m);
  for (const auto& [col, ms] : columns) {
    std::string title = ms.front()->title;
    if (ms.size() > 1) title += " (+" + std::to_string(ms.size() - 1) + " more)";
    o << "<line class=\"marker\" x1=\"" << col << "\" x2=\"" << col << "\" y1=\"" << num(f.top + f.height)
      << "\" y2=\"" << num(f.top + f.height - 10) << "\" stroke=\"" << p.marker_color << "\" stroke-width=\"2\"><title>"
      << escape_html(title) << "</title></line>";
  }
}

// Reference lines, series and markers, clipped to the plot area.
void write_clipped_content(std::ostringstream& o, const LinePlot& p, const Frame& f) {
  const std::string clip = "clip-" + escape_html(p.id);
  o << "<defs><clipPath id=\"" << clip << "\"><rect x=\"" << num(f.left) << "\" y=\"" << num(f.top) << "\" width=\""
    << num(f.width) << "\" height=\"" << num(f.height) << "\"/></clipPath></defs><g clip-path=\"url(#" << clip
    << ")\">";
  for (const auto& h : p.hlines)
    if (std::isfinite(h.y))
      o << "<line class=\"hline\" x1=\"" << num(f.left) << "\" x2=\"" << num(f.left + f.width) << "\" y1=\""
        << num(f.Y(h.y)) << "\" y2=\"" << num(f.Y(h.y)) << "\" stroke=\"" << h.color
        << "\" stroke-width=\"1.5\" stroke-dasharray=\"6 3\"><title>" << escape_html(h.label) << "</title></line>";
  for (const auto& s : p.series) {
    const std::string d = series_path(s, f);
    if (d.empty()) continue;
    o << "<path class=\"series\" data-label=\"" << escape_html(s.label) << "\" d=\"" << d
      << "\" fill=\"none\" stroke=\"" << s.color << "\" stroke-width=\"" << fixed(s.width_px, 2)
      << "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"" << (s.dashed ? " stroke-dasharray=\"5 3\"" : "") << "><title>"
      << escape_html(s.label) << "</title></path>";
  }
  write_markers(o, p, f);
  o << "</g>";
}

}  // namespace

std::string render_line_plot(const LinePlot& p) {
  const Extent extent = data_extent(p);
  const int W = p.width_px, H = p.height_px;
  std::ostringstream o;
  o << "<svg class=\"plot\" id=\"" << escape_html(p.id) << "\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 "
    << W << ' ' << H << "\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"system-ui, sans-serif\" font-size=\"12\" role=\"img\">";
  o << "<title>" << escape_html(p.title) << "</title>";
  o << "<text x=\"8\" y=\"18\" font-size=\"14\" font-weight=\"600\" fill=\"#222\">" << escape_html(p.title)
    << "</text>";
  if (!(extent.x0 <= extent.x1)) {
    o << "<rect x=\"8\" y=\"30\" width=\"" << W - 16 << "\" height=\"" << H - 40
      << "\" fill=\"#f6f7f9\" stroke=\"#ddd\"/><text class=\"empty\" x=\"" << W / 2 << "\" y=\"" << H / 2 + 10
      << "\" text-anchor=\"middle\" fill=\"#888\">" << escape_html(p.empty_note) << "</text></svg>";
    return o.str();
  }
  const Frame f = plot_frame(p, extent);
  // The frame lets the page's script turn pointer positions back into values (hover read-out).
  o << "<metadata class=\"frame\" data-frame=\"" << num(f.left) << ',' << num(f.top) << ',' << num(f.width) << ','
    << num(f.height) << ',' << fixed(f.x0, 9) << ',' << fixed(f.x1, 9) << ',' << fixed(f.y0, 9) << ','
    << fixed(f.y1, 9) << "\" data-x-label=\"" << escape_html(p.x_label) << "\"/>";
  write_legend(o, p);
  write_axes(o, p, f);
  write_clipped_content(o, p, f);
  o << "</svg>";
  return o.str();
}

std::string render_stacked_bar(const std::vector<BarPart>& parts, const std::string& unit, int width_px) {
  double total = 0.0;
  for (const auto& part : parts) total += std::max(0.0, part.value);
  std::ostringstream o;
  const int H = 46;
  o << "<svg class=\"bar\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << width_px << ' ' << H << "\" width=\""
    << width_px << "\" height=\"" << H << "\" font-family=\"system-ui, sans-serif\" font-size=\"12\">";
  if (total <= 0.0) return o.str() + "</svg>";
  double x = 0.0;
  for (const auto& part : parts) {
    const double w = std::max(0.0, part.value) / total * width_px;
    o << "<rect x=\"" << num(x) << "\" y=\"0\" width=\"" << num(w) << "\" height=\"16\" fill=\"" << part.color
      << "\"><title>" << escape_html(part.label) << ": " << fixed(part.value, 2) << ' ' << unit << "</title></rect>";
    x += w;
  }
  double lx = 0.0, ly = 34.0;
  for (const auto& part : parts) {
    const std::string label = part.label + " " + fixed(part.value, part.value < 10 ? 2 : 1) + " " + unit;
    const double w = 18.0 + 6.6 * double(label.size());
    if (lx + w > width_px && lx > 0) break;  // the tooltips still carry every part
    o << "<rect x=\"" << num(lx) << "\" y=\"" << ly - 9 << "\" width=\"10\" height=\"10\" fill=\"" << part.color
      << "\"/><text x=\"" << num(lx + 14) << "\" y=\"" << ly << "\" fill=\"#333\">" << escape_html(label) << "</text>";
    lx += w + 8.0;
  }
  return o.str() + "</svg>";
}

}  // namespace tf::reporting
