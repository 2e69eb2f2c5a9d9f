// tiltfield tests: a report.html opened in Debian's headless Chromium through tests/report/check_report.mjs
// (playwright-core from the build's report_npm). Shared by the report's browser test and the integration
// test of `verify --html`.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "report/report.hpp"
#include "test_support.hpp"

namespace tf::test {

inline std::string chromium_path() { return std::getenv("CHROMIUM") ? std::getenv("CHROMIUM") : "/usr/bin/chromium"; }

inline std::filesystem::path report_node_modules() {
  return std::filesystem::path(TILTFIELD_BINARY_DIR) / "report_npm" / "node_modules";
}

// What is missing to open a report in the browser ("" when nothing is).
inline std::string browser_missing() {
  if (!reporting::viewer_built_in()) return "this build has no 3-D viewer (TILTFIELD_REPORT_VIEWER=OFF)";
  if (!std::filesystem::exists(chromium_path())) return chromium_path() + " not found (apt-get install chromium chromium-driver)";
  if (!std::filesystem::exists(report_node_modules() / "playwright-core"))
    return "playwright-core not installed in " + report_node_modules().string();
  if (run_command("node --version").exit_code != 0) return "node not found";
  return "";
}

// Skips the test when the browser is missing, unless CI=true: then it fails.
#define TF_REQUIRE_BROWSER()                                                         \
  do {                                                                               \
    const std::string missing_ = ::tf::test::browser_missing();                      \
    if (!missing_.empty()) {                                                         \
      const char* ci_ = std::getenv("CI");                                           \
      if (ci_ && std::string(ci_) == "true") FAIL() << "CI=true and " << missing_;   \
      GTEST_SKIP() << missing_;                                                      \
    }                                                                                \
  } while (0)

// Runs check_report.mjs on `html` (screenshot to `png`, extra options such as "--min-plots=6").
inline CliResult check_report_in_browser(const std::filesystem::path& html, const std::filesystem::path& png,
                                         const std::string& options) {
  return run_command("TILTFIELD_NODE_MODULES='" + report_node_modules().string() + "' CHROMIUM='" + chromium_path() +
                     "' node '" + TILTFIELD_SOURCE_DIR + "/tests/report/check_report.mjs' '" + html.string() + "' '" +
                     png.string() + "' " + options);
}

}  // namespace tf::test
