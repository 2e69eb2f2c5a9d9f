// tiltfield tests: temporary folders, small files, and running the built `tiltfield` binary.
#pragma once
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace tf::test {

// A fresh folder under the system temp dir, removed with its contents at the end of the scope.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("tiltfield-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

inline void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
}

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

struct CliResult {
  int exit_code = -1;
  std::string out;  // stdout and stderr, merged
};

// Runs a shell command; stdout and stderr merged, stdin empty.
inline CliResult run_command(const std::string& command) {
  CliResult r;
  FILE* p = ::popen((command + " 2>&1 < /dev/null").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs the built binary with `args` (a shell-quoted argument string), in `cwd` when given.
inline CliResult run_tiltfield(const std::string& args, const std::filesystem::path& cwd = {}) {
  std::string cmd;
  if (!cwd.empty()) cmd = "cd '" + cwd.string() + "' && ";
  return run_command(cmd + "'" + TILTFIELD_EXE + "' --quiet " + args);
}

// LinuxCNC's interpreter (Debian package linuxcnc-uspace) is an independent reader of our programs.
// Missing, a test is skipped, unless CI=true, where .ci/run installs it and its absence is a failure.
#define TF_REQUIRE_RS274()                                                                            \
  do {                                                                                                \
    if (::tf::test::run_command("command -v rs274").exit_code != 0) {                                 \
      const char* ci = std::getenv("CI");                                                             \
      if (ci && std::string(ci) == "true") FAIL() << "rs274 (linuxcnc-uspace) is missing under CI";   \
      GTEST_SKIP() << "rs274 not installed (apt-get install --no-install-recommends linuxcnc-uspace)"; \
    }                                                                                                 \
  } while (0)

// Counts the lines of text (a trailing newline does not start a new line).
inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  if (!s.empty() && s.back() != '\n') ++n;
  return n;
}

}  // namespace tf::test
