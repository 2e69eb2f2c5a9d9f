// tiltfield report: the page. Summary header and cards, the 3-D view's container and data, the plots,
// the tables; everything inline so report.html opens offline.
#include "report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <sstream>
#include <stdexcept>

#include "report_internal.hpp"
#include "report_svg.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::reporting {

bool viewer_built_in() { return !viewer_script().empty(); }

namespace {

std::string thousands(double v, int decimals) {
  std::string s = fixed(v, decimals);
  const size_t dot = s.find('.');
  const size_t end = dot == std::string::npos ? s.size() : dot;
  const size_t start = s[0] == '-' ? 1 : 0;
  for (long i = long(end) - 3; i > long(start); i -= 3) s.insert(size_t(i), "\u2009");
  return s;
}

std::string known(double v, int decimals) { return v >= 0.0 && std::isfinite(v) ? thousands(v, decimals) : "\u2013"; }
std::string known(int v) { return v >= 0 ? std::to_string(v) : "\u2013"; }

struct Card {
  std::string label, value, unit, detail, tone;  // tone: "", "good", "bad", "warn"
};

std::string card_html(const Card& c) {
  std::string h = "<div class=\"card " + c.tone + "\"><div class=\"label\">" + escape_html(c.label) +
                  "</div><div class=\"value\">" + escape_html(c.value);
  if (!c.unit.empty()) h += "<span class=\"unit\"> " + escape_html(c.unit) + "</span>";
  h += "</div>";
  if (!c.detail.empty()) h += "<div class=\"detail\">" + escape_html(c.detail) + "</div>";
  return h + "</div>";
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

std::string tool_text(const Tool& t) {
  std::string s = std::string(t.type_name()) + " R" + fixed(t.radius(), 3);
  if (const auto* bull = std::get_if<BullCutter>(&t.cutter)) s += " r" + fixed(bull->corner_radius, 3);
  return s + ", gauge length " + fixed(t.length, 2) + " mm, " + std::to_string(t.holder.size()) + " holder segment" +
         (t.holder.size() == 1 ? "" : "s");
}

std::string megabytes(size_t bytes) { return fixed(double(bytes) / 1e6, bytes < 10000000 ? 2 : 1) + " MB"; }

// The stock mesh's size and the bound it was decimated within.
Card stock_mesh_card(const StockMeshStats& m) {
  std::string detail = m.max_error_mm > 0.0 ? "decimated within " + fixed(m.max_error_mm, 4) + " mm of the full mesh, " +
                                                  thousands(double(m.faces), 0) + " faces, " + megabytes(m.bytes) +
                                                  " PLY (full mesh: " + thousands(double(m.full_vertices), 0) +
                                                  " vertices, " + thousands(double(m.full_faces), 0) + " faces)"
                                            : "the full mesh, " + thousands(double(m.faces), 0) + " faces, " +
                                                  megabytes(m.bytes) + " PLY";
  return {"Stock mesh", thousands(double(m.vertices), 0), "vertices", detail, ""};
}

// What the 3-D view's stock shows, and what it cannot (no design: no deviation colours).
std::string stock_caption(const ReportInputs& in) {
  if (!in.stock || in.stock->n_faces() == 0) return "No simulated stock: the raw stock is shown (hidden at first).";
  std::string c;
  if (in.stock_deviation_mm.empty())
    c = in.scene->design.n_faces() == 0
            ? "The scene has no design surface, so the stock cannot be coloured by its deviation from one. "
            : "The stock's deviation from the design was not computed. ";
  if (!in.stock_block.empty())
    c += "Colours by block or tool show the last block to cut each place; choose the colouring under the stock's "
         "layer switch, and hover the stock to read the block, its G-code line and tool.";
  else if (in.stock_deviation_mm.empty())
    c += "The stock is shown in one colour.";
  return c;
}

std::vector<Card> cards(const ReportInputs& in) {
  const Scene& scene = *in.scene;
  const Summary& s = in.summary;
  std::vector<Card> out;
  const size_t rows = in.oriented ? in.oriented->rows.size() : scene.path.rows.size();
  out.push_back({"Path rows", rows ? std::to_string(rows) : "\u2013", "", rows ? "" : "no path in the scene", ""});
  const size_t blocks = std::max(in.axes.size(), in.blocks.size());
  out.push_back({"Program blocks", blocks ? std::to_string(blocks) : "\u2013", "", "", ""});
  const int left = int(in.collisions.size());
  std::string detail = "found " + known(s.collisions_found) + ", fixed " + known(s.collisions_fixed);
  if (s.collisions_new > 0) detail += ", " + std::to_string(s.collisions_new) + " new from re-planning";
  out.push_back({"Collisions left", std::to_string(left), "", detail, left ? "bad" : "good"});
  double max_gouge = s.max_gouge_mm;
  for (const auto& g : in.gouges) max_gouge = std::max(max_gouge, g.depth_mm);
  if (scene.design.n_faces() == 0 && in.gouges.empty())
    out.push_back({"Gouges", "\u2013", "", "no design surface to check", ""});
  else
    out.push_back({"Gouges", std::to_string(in.gouges.size()), "",
                   in.gouges.empty() ? "" : "deepest " + known(max_gouge, 3) + " mm", in.gouges.empty() ? "good" : "bad"});
  double clearance = s.min_clearance_mm;
  if (clearance < 0.0 && in.oriented) {
    clearance = std::numeric_limits<double>::infinity();
    for (const auto& r : in.oriented->rows)
      if (clearance_measured(r.clearance_mm)) clearance = std::min(clearance, r.clearance_mm);
    if (!std::isfinite(clearance)) clearance = -1.0;
  }
  const double safety = scene.planner.safety_distance;
  if (clearance >= kNoObstacleClearance)  // the plan's "no obstacle", not a distance
    out.push_back({"Min clearance", "none", "", "no check surface or fixture", ""});
  else
    out.push_back({"Min clearance", known(clearance, 3), clearance >= 0.0 ? "mm" : "",
                   "safety distance " + fixed(safety, 3) + " mm",
                   clearance < 0.0 ? "" : clearance + 1e-9 >= safety ? "good" : "warn"});
  // Whole mm3 hide what a finishing pass on a small part removes (0.0158 mm3 read 0: black-box testing).
  const double removed = s.removed_volume_mm3;
  out.push_back({"Removed volume", known(removed, removed >= 100.0 ? 0 : removed >= 1.0 ? 2 : 4), s.removed_volume_mm3 >= 0.0 ? "mm\u00b3" : "",
                 s.resolution_mm > 0.0 ? "dexel spacing " + fixed(s.resolution_mm, 3) + " mm" : "", ""});
  double total = 0.0;
  for (const auto& st : s.stages) total += st.seconds;
  out.push_back({"Run time", s.stages.empty() ? "\u2013" : fixed(total, total < 10 ? 2 : 1), s.stages.empty() ? "" : "s",
                 std::to_string(s.stages.size()) + " stages", ""});
  if (in.stock_mesh) out.push_back(stock_mesh_card(*in.stock_mesh));
  return out;
}

// The footnote of a table cut at its row limit.
std::string more_rows(size_t n, const char* what, const std::string& report_json) {
  return "<p class=\"more\">" + std::to_string(n) + " more " + what +
         (report_json.empty() ? std::string(" are not listed here.") : " are listed in " + escape_html(report_json) + ".") + "</p>";
}

std::string collision_table(const ReportInputs& in, size_t max_rows) {
  std::ostringstream o;
  o << "<h2 id=\"collisions\">Collisions <span class=\"count\">" << in.collisions.size() << "</span></h2>";
  if (in.collisions.empty()) return o.str() + "<p class=\"none\">No collisions in the final program.</p>";
  std::map<std::string, int> kinds;
  for (const auto& c : in.collisions) ++kinds[collision_kind(c)];
  o << "<div class=\"chips\">";
  for (const auto& [k, n] : kinds) o << "<span class=\"chip\">" << escape_html(k) << " <b>" << n << "</b></span>";
  o << "</div><div class=\"table-wrap\"><table><thead><tr><th>block</th><th>G-code line</th><th>component</th>"
       "<th>with</th><th>motion</th><th class=\"num\">depth (mm)</th></tr></thead><tbody>";
  std::vector<const Collision*> sorted;
  for (const auto& c : in.collisions) sorted.push_back(&c);
  std::stable_sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->block < b->block; });
  for (size_t i = 0; i < sorted.size() && i < max_rows; ++i) {
    const Collision& c = *sorted[i];
    o << "<tr><td>" << c.block << "</td><td>" << c.line << "</td><td>" << to_string(c.component) << "</td><td>"
      << to_string(c.with) << "</td><td>" << (c.rapid ? "<span class=\"rapid\">rapid</span>" : "feed")
      << "</td><td class=\"num\">" << fixed(c.depth_mm, 4) << "</td></tr>";
  }
  o << "</tbody></table></div>";
  if (sorted.size() > max_rows)
    o << more_rows(sorted.size() - max_rows, "collisions", in.report_json);
  return o.str();
}

std::string gouge_table(const ReportInputs& in, size_t max_rows) {
  std::ostringstream o;
  const bool unchecked = in.scene->design.n_faces() == 0 && in.gouges.empty();
  o << "<h2 id=\"gouges\">Gouges <span class=\"count\">" << (unchecked ? std::string("\u2013") : std::to_string(in.gouges.size()))
    << "</span></h2>";
  if (in.gouges.empty())
    return o.str() + (in.scene->design.n_faces() == 0
                          ? "<p class=\"more\">The scene has no design surface: gouges were not checked.</p>"
                          : "<p class=\"none\">No gouges: the tool stays off the design surface.</p>");
  std::vector<const Gouge*> sorted;
  for (const auto& g : in.gouges) sorted.push_back(&g);
  std::stable_sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->block < b->block; });
  o << "<div class=\"table-wrap\"><table><thead><tr><th>block</th><th>G-code line</th><th class=\"num\">depth (mm)</th>"
       "</tr></thead><tbody>";
  for (size_t i = 0; i < sorted.size() && i < max_rows; ++i)
    o << "<tr><td>" << sorted[i]->block << "</td><td>" << sorted[i]->line << "</td><td class=\"num\">"
      << fixed(sorted[i]->depth_mm, 4) << "</td></tr>";
  o << "</tbody></table></div>";
  if (sorted.size() > max_rows) o << more_rows(sorted.size() - max_rows, "gouges", in.report_json);
  return o.str();
}

// JSON inside <script>: "</" would end the element early; "<\/" is the same JSON string.
std::string script_safe(std::string s) {
  for (size_t i = s.find("</"); i != std::string::npos; i = s.find("</", i + 3)) s.replace(i, 2, "<\\/");
  return s;
}

}  // namespace

std::string render_html_report(const ReportInputs& in, const ReportOptions& options) {
  if (!in.scene) throw std::invalid_argument("report: ReportInputs::scene is required");
  const Scene& scene = *in.scene;
  const std::string title = in.summary.title.empty() ? scene.file.stem().string() : in.summary.title;
  const int left = int(in.collisions.size());

  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
       "<meta name=\"generator\" content=\"tiltfield " TILTFIELD_VERSION "\">"
    << "<title>tiltfield report \u2013 " << escape_html(title) << "</title><style>" << report_css() << "</style></head><body>\n";

  o << "<header class=\"top\"><div class=\"heading\"><div class=\"kicker\">tiltfield report</div><h1>" << escape_html(title)
    << "</h1><div class=\"sub\">" << escape_html(scene.file.string());
  if (scene.machine)
    o << " \u00b7 machine " << escape_html(scene.machine->name) << " (" << to_string(scene.machine->kinematics) << ")";
  o << " \u00b7 tool " << escape_html(tool_text(scene.tool)) << " \u00b7 " << utc_now() << "</div>";
  if (!in.summary.note.empty()) o << "<div class=\"note\">" << escape_html(in.summary.note) << "</div>";
  o << "</div><div class=\"status " << (left || !in.gouges.empty() ? "bad" : "good") << "\">"
    << (left ? std::to_string(left) + (left == 1 ? " collision left" : " collisions left")
             : in.gouges.empty() && scene.design.n_faces() > 0 ? "no collisions, no gouges" : "no collisions")
    << (!in.gouges.empty() ? " \u00b7 " + std::to_string(in.gouges.size()) + (in.gouges.size() == 1 ? " gouge" : " gouges") : "")
    << "</div></header>\n";

  o << "<section class=\"cards\">";
  for (const auto& c : cards(in)) o << card_html(c);
  o << "</section>\n";
  if (!in.summary.stages.empty()) {
    static const char* colors[] = {"#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#9c755f"};
    std::vector<BarPart> parts;
    for (size_t i = 0; i < in.summary.stages.size(); ++i)
      parts.push_back({in.summary.stages[i].name, in.summary.stages[i].seconds, colors[i % 8]});
    o << "<section class=\"panel stages\"><h2>Time per stage</h2>" << render_stacked_bar(parts, "s", 1300) << "</section>\n";
  }

  o << "<section class=\"panel\"><h2>3-D view</h2><div class=\"viewer-wrap\"><div id=\"tf-viewer\" class=\"viewer\">"
    << "<div class=\"viewer-msg\">"
    << (viewer_built_in() ? "Loading the 3-D view\u2026 (needs JavaScript and WebGL)"
                          : "This tiltfield was built without the 3-D viewer (npm was not available at build time; "
                            "see docs/report.md).")
    << "</div></div><aside class=\"viewer-side\"><div id=\"tf-layers\" class=\"layers\"></div>"
    << "<div id=\"tf-legends\"></div><div class=\"hint\">Drag to orbit, right-drag to pan, wheel to zoom; "
       "double-click resets the view.</div></aside></div>";
  if (const std::string caption = stock_caption(in); !caption.empty())
    o << "<p class=\"caption\" id=\"stock-caption\">" << escape_html(caption) << "</p>";
  o << "</section>\n";

  o << "<section class=\"panel\"><h2>Along the path and per block</h2><div class=\"plots\">";
  for (const auto& svg : build_plots(in)) o << "<figure>" << svg << "</figure>";
  o << "</div><p class=\"caption\">Shaded: rows the re-planner changed. Red ticks: blocks with a collision (hover "
       "for details). Dense lines show the minimum and maximum per pixel.</p></section>\n";

  o << "<section class=\"panel tables\"><div>" << collision_table(in, options.max_table_rows) << "</div><div>"
    << gouge_table(in, options.max_table_rows) << "</div></section>\n";
  o << "<footer>tiltfield " TILTFIELD_VERSION " \u00b7 units: mm, deg, mm/min \u00b7 motion blocks are numbered from 1 in "
       "program order, as the verifier numbers them; G-code lines from 1.</footer>\n";

  if (viewer_built_in()) {
    o << "<script type=\"application/json\" id=\"tf-scene-data\">" << script_safe(build_scene_json(in, options).dump())
      << "</script>\n<script>" << viewer_script() << "</script>\n";
  }
  o << "</body></html>\n";
  return o.str();
}

void write_html_report(const ReportInputs& inputs, const std::filesystem::path& out_html, const ReportOptions& options) {
  const std::string page = render_html_report(inputs, options);
  write_file_atomic(out_html, [&](std::ostream& out) { out << page; });
}

}  // namespace tf::reporting
