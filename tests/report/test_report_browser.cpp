// The report in a real browser: headless Chromium (Debian's chromium package) opens report.html of the
// synthetic job through tests/report/check_report.mjs (playwright-core), which checks that the plots and
// the WebGL canvas rendered with no console errors and no request leaving the file.
//
// Without chromium (or without the viewer/npm build) the test is skipped, unless CI=true: then it fails.
// The page and its screenshot stay in build/report_test/ for a look.
#include <gtest/gtest.h>

#include <cstdlib>

#include "report_fixture.hpp"
#include "test_support.hpp"

namespace tf::test {
namespace {

bool on_ci() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

TEST(ReportBrowser, PlotsAndWebGlCanvasRenderInHeadlessChromium) {
  const std::string chromium = std::getenv("CHROMIUM") ? std::getenv("CHROMIUM") : "/usr/bin/chromium";
  const std::filesystem::path node_modules = std::filesystem::path(TILTFIELD_BINARY_DIR) / "report_npm" / "node_modules";
  std::string missing;
  if (!reporting::viewer_built_in()) missing = "this build has no 3-D viewer (TILTFIELD_REPORT_VIEWER=OFF)";
  else if (!std::filesystem::exists(chromium)) missing = chromium + " not found (apt-get install chromium chromium-driver)";
  else if (!std::filesystem::exists(node_modules / "playwright-core")) missing = "playwright-core not installed in " + node_modules.string();
  else if (run_command("node --version").exit_code != 0) missing = "node not found";
  if (!missing.empty()) {
    if (on_ci()) FAIL() << "CI=true and " << missing;
    GTEST_SKIP() << missing;
  }

  const std::filesystem::path dir = std::filesystem::path(TILTFIELD_BINARY_DIR) / "report_test";
  std::filesystem::create_directories(dir);
  std::filesystem::remove(dir / "screenshot.png");
  auto job = synthetic_job();
  reporting::write_html_report(job->inputs, dir / "report.html");

  const std::string cmd = "TILTFIELD_NODE_MODULES='" + node_modules.string() + "' CHROMIUM='" + chromium + "' node '" +
                          TILTFIELD_SOURCE_DIR + "/tests/report/check_report.mjs' '" + (dir / "report.html").string() +
                          "' '" + (dir / "screenshot.png").string() + "' --min-plots=6";
  const CliResult r = run_command(cmd);
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("\"viewer\":\"ready\""), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "screenshot.png"));
}

}  // namespace
}  // namespace tf::test
