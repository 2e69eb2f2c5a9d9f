// SVG view of the sections: small multiples, edges coloured by the operation that made them.
#include <algorithm>
#include <ostream>
#include <string>

#include "tiltfield/core/io.hpp"
#include "tiltfield/grind/sections.hpp"

namespace tf::grind {
namespace {
std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}
}  // namespace

void write_sections_svg(const SectionStack& stack, const std::filesystem::path& file, int panels) {
  static const char* const kPalette[] = {"#555555", "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e",
                                         "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
                                         "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173",
                                         "#3182bd"};
  const int n = static_cast<int>(stack.sections.size());
  const int count = std::max(1, std::min(panels, n));
  const int cols = std::min(count, 6), rows = (count + cols - 1) / cols;
  const double cell = 180.0, r = stack.blank.radius * 1.05, scale = 0.5 * (cell - 30.0) / r;
  write_file_atomic(file, [&](std::ostream& out) {
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fixed(cols * cell, 1) << "\" height=\""
        << fixed(rows * cell + 20.0 * static_cast<double>(stack.op_labels.size()), 1)
        << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (int p = 0; p < count; ++p) {
      const int k = count == 1 ? 0 : static_cast<int>(std::lround(double(p) * (n - 1) / (count - 1)));
      const Section& s = stack.sections[k];
      const double cx = (p % cols + 0.5) * cell, cy = (p / cols) * cell + 15.0 + 0.5 * (cell - 15.0);
      out << "<text x=\"" << fixed(cx, 1) << "\" y=\"" << fixed((p / cols) * cell + 14.0, 1)
          << "\" text-anchor=\"middle\">z = " << fixed(s.z, 3) << " mm</text>\n";
      out << "<circle cx=\"" << fixed(cx, 2) << "\" cy=\"" << fixed(cy, 2) << "\" r=\""
          << fixed(stack.blank.radius * scale, 2) << "\" fill=\"none\" stroke=\"#dddddd\" stroke-dasharray=\"3,3\"/>\n";
      for (const Contour& c : s.contours) {
        const size_t m = c.points.size();
        for (size_t i = 0; i < m;) {  // one polyline per run of equal labels
          size_t j = i;
          while (j + 1 < m && c.labels[j + 1] == c.labels[i]) ++j;
          out << "<polyline fill=\"none\" stroke-width=\"1.2\" stroke=\"" << kPalette[c.labels[i] % 16] << "\" points=\"";
          for (size_t t = i; t <= j + 1; ++t) {
            const auto& q = c.points[t % m];
            out << fixed(cx + q.x() * scale, 2) << "," << fixed(cy - q.y() * scale, 2) << " ";
          }
          out << "\"/>\n";
          i = j + 1;
        }
      }
    }
    for (size_t l = 0; l < stack.op_labels.size(); ++l)
      out << "<text x=\"10\" y=\"" << fixed(rows * cell + 15.0 + 20.0 * static_cast<double>(l), 1) << "\" fill=\""
          << kPalette[l % 16] << "\">" << l << ": " << escape(stack.op_labels[l]) << "</text>\n";
    out << "</svg>\n";
  });
}

}  // namespace tf::grind
