// The HTML report: the page's content, the plots, mesh packing, the input readers.
#include <gtest/gtest.h>

#include <regex>

#include "report_fixture.hpp"
#include "report/report_internal.hpp"
#include "report/report_mesh.hpp"
#include "report/report_svg.hpp"
#include "test_support.hpp"
#include "tiltfield/core/error.hpp"

namespace tf::test {
namespace {

using namespace tf::reporting;

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
  return n;
}

// The JSON the viewer reads, cut out of the page.
nlohmann::json scene_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"tf-scene-data\">";
  const size_t a = html.find(open);
  if (a == std::string::npos) return {};
  const size_t b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

const nlohmann::json* layer(const nlohmann::json& data, const std::string& id) {
  for (const auto& l : data["layers"])
    if (l["id"] == id) return &l;
  return nullptr;
}

TEST(Report, PageHasSummaryPlotsTablesAndViewerData) {
  auto job = synthetic_job();
  const std::string html = render_html_report(job->inputs);
  EXPECT_NE(html.find("synthetic wavy surface"), std::string::npos);
  EXPECT_NE(html.find("3 collisions left"), std::string::npos);
  EXPECT_NE(html.find("found 14, fixed 11"), std::string::npos);
  EXPECT_NE(html.find("123\u2009457"), std::string::npos) << "removed volume with thousands separator";
  {  // A finishing pass on a small part: its volume in four decimals, not "0" (black-box testing).
    auto small = synthetic_job();
    small->inputs.summary.removed_volume_mm3 = 0.0158;
    EXPECT_NE(render_html_report(small->inputs).find(">0.0158<"), std::string::npos);
  }
  // Six plots, all with lines: nothing in the synthetic job is missing.
  EXPECT_EQ(count(html, "<svg class=\"plot\""), 6);
  EXPECT_EQ(count(html, "<text class=\"empty\""), 0);
  for (const char* id : {"plot-orientation", "plot-clearance", "plot-rotary", "plot-mrr", "plot-area", "plot-angles"})
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
  // Rotary plot of a table-table-ac machine: A and C; collision ticks on the per-block plots.
  EXPECT_NE(html.find("data-label=\"A\""), std::string::npos);
  EXPECT_NE(html.find("data-label=\"C\""), std::string::npos);
  EXPECT_EQ(html.find("data-label=\"B\""), std::string::npos);
  EXPECT_GE(count(html, "class=\"marker\""), 4 * 2) << "at least two distinct collision columns on 4 plots";
  EXPECT_EQ(count(html, "class=\"band\""), 2 * 2) << "two re-planned windows on the two path plots";
  // Tables: three collisions, one gouge, with their lines.
  EXPECT_EQ(count(html, "<td>shank</td>"), 2);
  EXPECT_EQ(count(html, "<td>holder</td>"), 1);
  EXPECT_NE(html.find("<tr><td>130</td><td>150</td>"), std::string::npos);

  if (!viewer_built_in()) GTEST_SKIP() << "built without the 3-D viewer";
  const auto data = scene_data(html);
  ASSERT_TRUE(data.is_object());
  for (const char* id : {"stock", "check", "design", "path", "axes", "collisions", "gouges", "tool"})
    EXPECT_NE(layer(data, id), nullptr) << id;
  const auto& stock = *layer(data, "stock");
  EXPECT_EQ(stock["mesh"]["triangles"], job->stock.n_faces()) << "small enough: not decimated";
  const auto values = unbase64(stock["mesh"]["values"].get<std::string>());
  ASSERT_EQ(values.size(), job->stock.n_vertices() * sizeof(float));
  const float* v = reinterpret_cast<const float*>(values.data());
  EXPECT_NEAR(v[5], job->inputs.stock_deviation_mm[5], 1e-6);
  // The deviation ramp spans the field (-0.35 .. 0.25 mm) give or take the 1 % tails.
  ASSERT_EQ(stock["colorings"].size(), 1u) << "no blocks given: the deviation only";
  EXPECT_EQ(stock["colorings"][0]["kind"], "deviation");
  EXPECT_NEAR(stock["colorings"][0]["range"][0].get<double>(), -0.35, 0.02);
  EXPECT_NEAR(stock["colorings"][0]["range"][1].get<double>(), 0.25, 0.02);
  EXPECT_EQ(layer(data, "collisions")->at("titles").size(), 3u);
  EXPECT_EQ(unbase64(layer(data, "axes")->at("positions")).size(), 150u * 6 * sizeof(float));
  EXPECT_NE(html.find("<script>"), std::string::npos);
  EXPECT_EQ(count(html, "</script"), 2) << "the embedded script and JSON never close their element early";
}

TEST(Report, MissingStagesSayWhatIsMissing) {
  auto job = synthetic_job();
  ReportInputs in;
  in.scene = &job->scene;
  in.summary.note = "plan not run <yet>";
  const std::string html = render_html_report(in);
  EXPECT_EQ(count(html, "<svg class=\"plot\""), 6);
  EXPECT_EQ(count(html, "<text class=\"empty\""), 6);
  EXPECT_NE(html.find("no oriented path"), std::string::npos);
  EXPECT_NE(html.find("no posted program"), std::string::npos);
  EXPECT_NE(html.find("no verification data"), std::string::npos);
  EXPECT_NE(html.find("plan not run &lt;yet&gt;"), std::string::npos) << "text is escaped";
  EXPECT_NE(html.find("No collisions in the final program."), std::string::npos);
  if (viewer_built_in()) {
    const auto data = scene_data(html);
    EXPECT_NE(layer(data, "raw-stock"), nullptr) << "no machined stock: the raw stock is offered instead";
    EXPECT_NE(layer(data, "path"), nullptr) << "the input path is drawn when there is no oriented path";
    EXPECT_EQ(layer(data, "axes"), nullptr);
  }
}

TEST(Report, WritesAtomicallyAndRejectsBadInputs) {
  auto job = synthetic_job();
  TempDir dir;
  write_html_report(job->inputs, dir / "report.html");
  EXPECT_GT(std::filesystem::file_size(dir / "report.html"), 10000u);
  EXPECT_THROW(write_html_report(job->inputs, dir / "missing-folder" / "report.html"), std::exception);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing-folder"));
  ReportInputs none;
  EXPECT_THROW(render_html_report(none), std::invalid_argument);
  job->inputs.stock_deviation_mm.pop_back();
  if (viewer_built_in()) {
    EXPECT_THROW(write_html_report(job->inputs, dir / "bad.html"), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.html"));
  }
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().filename(), "report.html") << "no temporary left behind";
}

TEST(Report, TriangleBudgetSparesSmallMeshes) {
  if (!viewer_built_in()) GTEST_SKIP() << "built without the 3-D viewer";
  auto job = synthetic_job();
  ReportOptions opt;
  opt.max_triangles = 4000;  // stock 10800 + design 4800 + boss ~200 triangles
  const auto data = scene_data(render_html_report(job->inputs, opt));
  const auto& check = *layer(data, "check");
  EXPECT_EQ(check["mesh"]["triangles"], check["original_triangles"]) << "below its share: kept whole";
  size_t total = 0;
  for (const auto& l : data["layers"])
    if (l["kind"] == "mesh") total += l["mesh"]["triangles"].get<size_t>();
  EXPECT_LE(total, opt.max_triangles);
  EXPECT_GE(total, opt.max_triangles / 3);
  EXPECT_LT(layer(data, "stock")->at("mesh")["triangles"].get<size_t>(), job->stock.n_faces());
}

// A collision "with fixture" names a part the view has to show (black-box testing: fixtures were not drawn).
TEST(Report, FixturesAreDrawn) {
  if (!viewer_built_in()) GTEST_SKIP() << "built without the 3-D viewer";
  auto job = synthetic_job();
  EXPECT_EQ(layer(scene_data(render_html_report(job->inputs)), "fixtures"), nullptr) << "none in the scene";
  job->scene.fixtures.push_back(boss());
  const auto data = scene_data(render_html_report(job->inputs));
  const auto* fixtures = layer(data, "fixtures");
  ASSERT_NE(fixtures, nullptr);
  EXPECT_EQ((*fixtures)["mesh"]["triangles"], boss().n_faces());
}

TEST(Report, LongTablesAreCut) {
  auto job = synthetic_job();
  for (int i = 0; i < 40; ++i) job->inputs.collisions.push_back(collision(i, i + 1, ToolComponent::Ball, HitWith::Stock, true, 0.1));
  ReportOptions opt;
  opt.max_table_rows = 10;
  const std::string html = render_html_report(job->inputs, opt);
  EXPECT_NE(html.find("33 more collisions are listed in verify.json."), std::string::npos);
  EXPECT_NE(html.find("ball \u2013 stock <b>40</b>"), std::string::npos);
}

TEST(ReportMesh, Base64AndPacking) {
  EXPECT_EQ(base64("", 0), "");
  EXPECT_EQ(base64("f", 1), "Zg==");
  EXPECT_EQ(base64("fo", 2), "Zm8=");
  EXPECT_EQ(base64("foo", 3), "Zm9v");
  EXPECT_EQ(base64("foobar", 6), "Zm9vYmFy");
  const IndexedMesh m = to_indexed(wavy_surface(4, 3), nullptr);
  const auto j = encode_mesh(m);
  EXPECT_EQ(j["index_bits"], 16);
  const auto q = unbase64(j["positions"]);
  ASSERT_EQ(q.size(), m.V.size() * 3 * 2);
  const auto* u = reinterpret_cast<const uint16_t*>(q.data());
  for (size_t i = 0; i < m.V.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      const double back = j["origin"][a].get<double>() + u[3 * i + a] * j["scale"][a].get<double>();
      EXPECT_NEAR(back, m.V[i][a], 60.0 / 65535.0) << "quantised within half a step of the largest extent";
    }
  const auto idx = unbase64(j["indices"]);
  ASSERT_EQ(idx.size(), m.F.size() * 3 * 2);
  EXPECT_EQ(reinterpret_cast<const uint16_t*>(idx.data())[5], m.F[1][2]);
}

TEST(ReportSvg, TicksAreNice) {
  EXPECT_EQ(nice_ticks(0, 10, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  const auto t = nice_ticks(-0.3, 0.25, 5);
  ASSERT_EQ(t.size(), 6u);
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], -0.3 + 0.1 * double(i), 1e-12);
  EXPECT_TRUE(nice_ticks(1, 1, 5).empty());
}

TEST(ReportSvg, DenseSeriesAreReducedButSpikesSurvive) {
  LinePlot p;
  p.id = "dense";
  Series s;
  s.label = "noise";
  for (int i = 0; i < 100000; ++i) {
    s.x.push_back(i);
    s.y.push_back(i == 61234 ? 10.0 : std::sin(i * 0.001));
  }
  p.series.push_back(s);
  const std::string svg = render_line_plot(p);
  // Plain string search: std::regex recurses per character and overflows the stack on a path this long
  // under ASan.
  const size_t series = svg.find("class=\"series\"");
  ASSERT_NE(series, std::string::npos);
  const size_t d_at = svg.find(" d=\"", series);
  ASSERT_NE(d_at, std::string::npos);
  const size_t d_end = svg.find('"', d_at + 4);
  ASSERT_NE(d_end, std::string::npos);
  const std::string d = svg.substr(d_at + 4, d_end - d_at - 4);
  const int points = count(d, "L") + count(d, "M");
  EXPECT_LT(points, 4 * p.width_px);
  EXPECT_GT(points, p.width_px);
  // The spike is the series' maximum: it must reach the top of the data range (y px 50 + 6 % padding).
  double top = 1e9;
  for (size_t i = 0; i < d.size(); ++i) {
    if (d[i] != 'M' && d[i] != 'L') continue;
    const size_t comma = d.find(',', i);
    if (comma == std::string::npos) break;
    top = std::min(top, std::stod(d.substr(comma + 1)));
  }
  EXPECT_NEAR(top, 50.0 + 0.06 / 1.12 * (p.height_px - 92), 0.2);
  // NaN breaks the line into two sub-paths.
  LinePlot gap;
  gap.series.push_back({"gap", "#000", {0, 1, 2, 3}, {0, 1, std::nan(""), 3}});
  const std::string g = render_line_plot(gap);
  EXPECT_EQ(count(g, "M"), count(render_line_plot(LinePlot{}), "M") + 2);
  // The lone point after the gap is a dot (a zero-length line with round caps): a one-row path drew nothing.
  EXPECT_EQ(count(g, "h0"), 1);
  EXPECT_NE(g.find("stroke-linecap=\"round\""), std::string::npos);
}

// The plan's "no obstacle" clearance (1000000 mm) is no distance: the clearance plot had been drawn from 0 to
// a million, and the tightest row named with it (black-box testing).
TEST(Report, NoObstacleClearanceIsNotPlotted) {
  auto job = synthetic_job();
  for (auto& r : job->oriented.rows) r.clearance_mm = kNoObstacleClearance;
  for (auto& r : job->first_plan.rows) r.clearance_mm = kNoObstacleClearance;
  job->inputs.summary.min_clearance_mm = kNoObstacleClearance;
  const std::string html = render_html_report(job->inputs);
  const size_t at = html.find("id=\"plot-clearance\"");
  ASSERT_NE(at, std::string::npos);
  const std::string plot = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_NE(plot.find("no finite clearance"), std::string::npos) << plot;
  EXPECT_EQ(plot.find("class=\"series\""), std::string::npos) << plot;
  EXPECT_EQ(html.find("clearance 1000000"), std::string::npos) << "the tightest row is not named by it";
}

TEST(ReportIo, RunFolder) {
  auto job = synthetic_job();
  TempDir dir;
  write_oriented_csv(job->oriented, dir / "oriented.csv");
  write_text(dir / "program.ngc", "G21 G90 G94\nG0 X0 Y0 Z50 A0 C0\nG1 X1 Y2 Z40 A10 C20 F1000\nG1 X2 Y2 Z40 A12 C25\nM2\n");
  write_text(dir / "verify.json", R"({"removed_volume_mm3": 5, "collisions": [{"block": 2, "line": 3,
    "component": "shank", "with": "check", "rapid": false, "depth_mm": 0.5}], "gouges": []})");
  write_text(dir / "blocks.csv", "block,line,removed_mm3,mrr_mm3_min,entry_deg,exit_deg,engaged_area_mm2,collision\n"
                                 "1,2,0,,,,,0\n2,3,1,60,,,,1\n3,4,1,60,,,,0\n");
  write_mesh(job->stock, dir / "stock.ply");
  const auto run = load_run_folder(job->scene, dir.path());
  const ReportInputs& in = run->inputs;
  ASSERT_EQ(in.oriented, &run->oriented);
  EXPECT_EQ(run->oriented.rows.size(), job->oriented.rows.size());
  ASSERT_EQ(in.axes.size(), 3u);
  EXPECT_EQ(in.axes[0].block, 1);
  EXPECT_TRUE(in.axes[0].rapid);
  EXPECT_EQ(in.axes[1].line, 3);
  EXPECT_DOUBLE_EQ(in.axes[1].joints.c, 20.0);
  ASSERT_EQ(in.collisions.size(), 1u);
  EXPECT_EQ(in.blocks.size(), 3u);
  ASSERT_EQ(in.stock_deviation_mm.size(), job->stock.n_vertices());
  // The stock is the design raised by 0.3 sin(x/7) - 0.05: its deviation is that, to the grids' difference.
  double worst = 0.0;
  for (auto vh : run->stock.vertices()) {
    const double x = run->stock.point(vh)[0];
    worst = std::max(worst, std::abs(in.stock_deviation_mm[size_t(vh.idx())] - (0.3 * std::sin(x / 7.0) - 0.05)));
  }
  EXPECT_LT(worst, 0.06);
  const std::string html = render_html_report(in);
  EXPECT_NE(html.find("no block has a value (nothing engaged, or --no-engagement)"), std::string::npos);
  EXPECT_NE(html.find("1 collision left"), std::string::npos);
  // Nothing there: an empty report, not an error.
  TempDir empty;
  EXPECT_EQ(load_run_folder(job->scene, empty.path())->inputs.oriented, nullptr);
}

}  // namespace
}  // namespace tf::test
