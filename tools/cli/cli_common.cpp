#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/tilt/plan.hpp"

namespace tf::cli {
namespace fs = std::filesystem;

GlobalOptions& global_options() {
  static GlobalOptions options;  // the process' command line: one per process by nature
  return options;
}

double scheduled_air_feed(const CLI::Option& option, double value, double machine_max_feed, double min_feed) {
  if (option.count() == 0) return machine_max_feed;
  if (!(value > 0.0) || !std::isfinite(value)) throw InputError("", 0, "--air-feed", "must be a positive number of mm/min");
  // Below the slowest cutting feed it is a typo; below the written precision it had been left out silently.
  if (value < min_feed) {
    std::ostringstream msg;
    msg << std::setprecision(10) << value << " mm/min is below --min-feed, " << min_feed << " mm/min";
    throw InputError("", 0, "--air-feed", msg.str());
  }
  // The controller would clamp it to its own; a program written for it should say what it runs.
  if (value > machine_max_feed) {
    std::ostringstream msg;
    msg << std::setprecision(10) << value << " mm/min is above the machine's max_feed, " << machine_max_feed << " mm/min";
    throw InputError("", 0, "--air-feed", msg.str());
  }
  return value;
}

void print_feed_schedule(const std::string& who, const FeedScheduleOptions& o, const FeedSchedule& fs) {
  if (global_options().quiet) return;
  std::cerr << who << ": feeds scheduled for " << fixed(o.max_mrr, 1) << " mm3/min: " << fs.slowed << " blocks slowed, "
            << fs.sped_up << " air blocks at " << fixed(o.air_feed, 0) << " mm/min\n";
  for (const std::string& w : fs.warnings) std::cerr << "warning: " << w << "\n";
}

std::optional<double> scene_link_gap(const Scene& scene) {
  if (!scene.planner_json.contains("link_gap_mm")) return std::nullopt;
  return parse_plan_options(scene.planner_json, scene.file.string(), scene.tool, scene.planner, scene.feed).link_gap_mm;
}

std::string collision_kind(const Collision& c) {
  std::string kind = std::string(to_string(c.component)) + " in " + std::string(to_string(c.with));
  return c.rapid ? kind + " (rapid)" : kind;
}

void check_output_file(const std::string& option, const std::string& path) {
  if (path.empty()) return;
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!fs::is_directory(folder, ec) || ::access(folder.c_str(), W_OK) != 0)
    throw InputError(path, 0, option, "cannot be written: folder '" + folder.string() + "' is missing or not writable");
  // The output is renamed onto the name at the end: a folder there would fail only after the work.
  if (fs::is_directory(path, ec)) throw InputError(path, 0, option, "is a folder, not a file name");
}

namespace {
// Whether two paths name one file: the same file where both exist, else the same normalised path.
bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}
}  // namespace

void check_outputs_apart(const std::vector<std::pair<std::string, std::string>>& outputs,
                         const std::vector<std::string>& inputs) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const auto& [option, path] = outputs[k];
    if (path.empty()) continue;
    for (const std::string& in : inputs)
      if (!in.empty() && same_file(path, in))
        throw InputError(path, 0, option, "is the input file '" + in + "': writing it would replace it");
    for (size_t m = 0; m < k; ++m)
      if (!outputs[m].second.empty() && same_file(path, outputs[m].second))
        throw InputError(path, 0, option, "is also the file of " + outputs[m].first + ": give each output its own name");
  }
}

std::vector<std::string> scene_inputs(const Scene& scene, std::vector<std::string> others) {
  for (const fs::path& f : scene.files) others.push_back(f.string());
  return others;
}

CLI::Validator output_file() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        try {
          check_output_file("", path);
        } catch (const InputError& e) {
          return e.what();
        }
        return {};
      },
      "FILE");
}

namespace {
// The number a whole option text spells, when finite.
std::optional<double> finite_text(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || !end || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}
}  // namespace

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return finite_text(text) ? std::string() : "must be a finite number, got '" + text + "'";
      },
      "NUMBER");
}

CLI::Validator number_at_least(double lowest, bool strictly) {
  return CLI::Validator(
      [lowest, strictly](std::string& text) -> std::string {
        const std::optional<double> v = finite_text(text);
        if (v && (strictly ? *v > lowest : *v >= lowest)) return {};
        return "must be a number " + std::string(strictly ? "above " : "of at least ") + fixed(lowest, 0) + ", got '" + text + "'";
      },
      strictly ? "POSITIVE" : "NONNEGATIVE");
}

Progress terminal_progress() {
  if (global_options().quiet || !::isatty(STDERR_FILENO)) return {};
  return [last = -1](std::string_view stage, double fraction) mutable {
    const int pct = static_cast<int>(fraction * 100.0 + 0.5);
    if (pct == last) return;
    last = pct;
    const int width = 30, filled = pct * width / 100;
    std::fprintf(stderr, "\r%-8.*s [%.*s%*s] %3d%%", static_cast<int>(stage.size()), stage.data(), filled,
                 "##############################", width - filled, "", pct);
    if (pct >= 100) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

fs::path bundled_scene(const std::string& name) {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path scene = (ec ? fs::path(".") : exe.parent_path()) / "scenes" / name / "scene.json";
  if (!fs::exists(scene))
    throw InputError(scene.string(), 0, "", "bundled scene not found (build the 'bundled_scenes' target)");
  return scene;
}

namespace {
// A number in a file of its own (a cgroup's memory.max, memory.current); 0 when absent or "max".
double number_in(const char* file) {
  std::ifstream in(file);
  double v = 0;
  return in >> v ? v : 0.0;
}
}  // namespace

double available_memory_bytes() {
  double available = 0;
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0;
  while (in >> key >> kb) {
    if (key == "MemAvailable:") {
      available = kb * 1024.0;
      break;
    }
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  // A container's own limit (cgroup v2), below the host's memory.
  if (const double limit = number_in("/sys/fs/cgroup/memory.max"); limit > 0) {
    const double left = std::max(0.0, limit - number_in("/sys/fs/cgroup/memory.current"));
    available = available > 0 ? std::min(available, left) : left;
  }
  return available;
}

}  // namespace tf::cli
