// The report in a real browser: headless Chromium (Debian's chromium package) opens report.html of the
// synthetic job through tests/report/check_report.mjs (playwright-core), which checks that the plots and
// the WebGL canvas rendered with no console errors and no request leaving the file.
//
// Without chromium (or without the viewer/npm build) the test is skipped, unless CI=true: then it fails
// (tests/support/browser.hpp).
// The page and its screenshot stay in build/report_test/ for a look.
#include <gtest/gtest.h>

#include "browser.hpp"
#include "report_fixture.hpp"

namespace tf::test {
namespace {

TEST(ReportBrowser, PlotsAndWebGlCanvasRenderInHeadlessChromium) {
  TF_REQUIRE_BROWSER();
  const std::filesystem::path dir = std::filesystem::path(TILTFIELD_BINARY_DIR) / "report_test";
  std::filesystem::create_directories(dir);
  std::filesystem::remove(dir / "screenshot.png");
  auto job = synthetic_job();
  label_stock(*job);  // so that the colourings by block and by tool are there too
  reporting::write_html_report(job->inputs, dir / "report.html");

  const CliResult r = check_report_in_browser(dir / "report.html", dir / "screenshot.png", "--min-plots=6 --expect-stock");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\"viewer\":\"ready\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"colorings\":[\"deviation\",\"block\",\"tool\"]"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "screenshot.png"));
}

}  // namespace
}  // namespace tf::test
