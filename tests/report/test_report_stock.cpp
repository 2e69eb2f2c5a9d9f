// The report's stock: coloured by deviation, by the block that last cut it and by tool; the stock mesh's
// bound and size; what the page says when the scene has no design surface.
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "report/report_internal.hpp"
#include "report_fixture.hpp"

namespace tf::test {
namespace {

using namespace tf::reporting;

nlohmann::json stock_layer(const ReportInputs& in, const ReportOptions& options = {}) {
  const nlohmann::json data = build_scene_json(in, options);
  for (const auto& l : data["layers"])
    if (l["id"] == "stock") return l;
  return {};
}

std::vector<uint32_t> labels_of(const nlohmann::json& mesh) {
  const std::vector<unsigned char> bytes = unbase64(mesh["labels"].get<std::string>());
  std::vector<uint32_t> out(bytes.size() / sizeof(uint32_t));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(uint32_t));
  return out;
}

TEST(ReportStock, WithoutDesignTheToolColouringComesFirstThenTheBlocks) {
  auto job = synthetic_job();
  job->scene.design = Mesh();
  job->inputs.stock_deviation_mm.clear();
  label_stock(*job);
  const nlohmann::json stock = stock_layer(job->inputs);
  ASSERT_EQ(stock["colorings"].size(), 2u);
  EXPECT_EQ(stock["colorings"][0]["kind"], "tool") << "two tools cut: by tool first";
  EXPECT_EQ(stock["colorings"][1]["kind"], "block");
  EXPECT_EQ(stock["label"], "Machined stock, coloured by tool that last cut");
  const auto& blocks = stock["colorings"][1]["blocks"];
  EXPECT_EQ(blocks["ids"], nlohmann::json({10, 100}));
  EXPECT_EQ(blocks["lines"], nlohmann::json({30, 120})) << "the synthetic program's block b is on line b + 20";
  EXPECT_EQ(blocks["tools"], nlohmann::json({1, 2}));
  EXPECT_EQ(stock["colorings"][0]["tools"], nlohmann::json({1, 2}));
  EXPECT_EQ(labels_of(stock["mesh"]), job->inputs.stock_block) << "small enough to go whole";
  EXPECT_FALSE(stock["mesh"].contains("values"));
  const std::string html = render_html_report(job->inputs);
  EXPECT_NE(html.find("The scene has no design surface, so the stock cannot be coloured by its deviation"),
            std::string::npos);
}

TEST(ReportStock, WithDesignTheDeviationFirstAndOneToolNoToolColouring) {
  auto job = synthetic_job();
  label_stock(*job);
  nlohmann::json stock = stock_layer(job->inputs);
  ASSERT_EQ(stock["colorings"].size(), 3u);
  EXPECT_EQ(stock["colorings"][0]["kind"], "deviation");
  EXPECT_EQ(stock["colorings"][1]["kind"], "block");
  EXPECT_EQ(stock["colorings"][2]["kind"], "tool");
  for (auto& a : job->inputs.axes) a.tool = 3;
  stock = stock_layer(job->inputs);
  ASSERT_EQ(stock["colorings"].size(), 2u) << "one tool: colouring by it would say nothing";
  EXPECT_EQ(stock["colorings"][1]["kind"], "block");
}

TEST(ReportStock, DecimatedStockKeepsLabelsOfItsOwnPlaces) {
  auto job = synthetic_job();
  label_stock(*job);
  ReportOptions opt;
  opt.max_triangles = 3000;
  const nlohmann::json stock = stock_layer(job->inputs, opt);
  ASSERT_LT(stock["mesh"]["triangles"].get<size_t>(), job->stock.n_faces());
  const std::vector<uint32_t> labels = labels_of(stock["mesh"]);
  ASSERT_EQ(labels.size(), stock["mesh"]["vertices"].get<size_t>());
  // A cluster takes one of its own vertices' labels, never a mean of 10 and 100.
  const std::set<uint32_t> seen(labels.begin(), labels.end());
  EXPECT_EQ(seen, (std::set<uint32_t>{0, 10, 100}));
  job->inputs.stock_block.pop_back();
  EXPECT_THROW(build_scene_json(job->inputs, opt), std::invalid_argument);
}

TEST(ReportStock, StockMeshCardGivesTheBoundAndSizes) {
  auto job = synthetic_job();
  StockMeshStats m{.max_error_mm = 0.01, .vertices = 152993, .faces = 276367, .bytes = 5428866,
                   .full_vertices = 2996240, .full_faces = 5962760, .mesh_seconds = 15.0, .decimate_seconds = 146.0};
  job->inputs.stock_mesh = m;
  const std::string html = render_html_report(job->inputs);
  EXPECT_NE(html.find("Stock mesh"), std::string::npos);
  EXPECT_NE(html.find("152\u2009993"), std::string::npos);
  EXPECT_NE(html.find("decimated within 0.01 mm of the full mesh, 276\u2009367 faces, 5.43 MB PLY (full mesh: 2\u2009996\u2009240 "
                      "vertices, 5\u2009962\u2009760 faces)"),
            std::string::npos);
  m.max_error_mm = 0.0;
  job->inputs.stock_mesh = m;
  EXPECT_NE(render_html_report(job->inputs).find("the full mesh, "), std::string::npos);
}

}  // namespace
}  // namespace tf::test
