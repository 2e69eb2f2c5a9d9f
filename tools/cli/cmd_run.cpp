// tiltfield run [SCENE] [-o DIR]: the main job (see job.hpp).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "job.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::cli {

namespace {
// Before the work: no output may replace a file the scene was read from (`run -o` into the scene's folder
// replaced its stock mesh, and the next run cut nothing), nor be renamed onto a folder.
// Returns whether it made the output folder (to be taken away again if the job stops on bad input).
bool check_run_outputs(const Scene& scene, const std::filesystem::path& dir) {
  std::vector<std::pair<std::string, std::string>> outputs;
  for (const char* name : kRunOutputs) {
    const std::string path = (dir / name).string();
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "-o", "is a folder, not a file name");
    outputs.emplace_back("-o", path);
  }
  check_outputs_apart(outputs, scene_inputs(scene));
  // A folder that cannot be written is bad input, found before the work: it had failed with exit 1 after
  // the plan (black-box testing).
  std::error_code ec;
  const bool existed = std::filesystem::exists(dir, ec);
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string(), 0, "-o", "cannot make the output folder (" + ec.message() + ")");
  const std::filesystem::path probe = dir / ".tiltfield-write-test";
  {
    std::ofstream test(probe);
    if (!test) throw InputError(dir.string(), 0, "-o", "cannot write in the output folder");
  }
  std::filesystem::remove(probe, ec);
  return !existed;
}
}  // namespace

void add_run_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "the main job: plan, post, verify, re-plan what collides, verify again, report");
  struct Args {
    std::string scene, dir = "out";
    JobOptions options;
    bool fail_on_collision = false;
  };
  static Args a;  // CLI11 binds options to storage living as long as the app
  cmd->add_option("SCENE", a.scene, "scene JSON (default: the bundled impeller)");
  cmd->add_option("-o,--output", a.dir, "output folder")->capture_default_str();
  cmd->add_option("--resolution", a.options.resolution_mm, "verification dexel spacing, mm")->capture_default_str()
      ->check(number_at_least(0, true));
  cmd->add_option("--rounds", a.options.max_rounds, "re-plan rounds at most")->capture_default_str()->check(CLI::Range(0, 20));
  // Exit 1 when collisions are left is the default now; the flag stays so that scripts keep working.
  cmd->add_flag("--fail-on-collision", a.fail_on_collision, "(the default) exit 1 when collisions are left");
  cmd->callback([] {
    const Scene scene = load_scene(a.scene.empty() ? bundled_scene("impeller") : std::filesystem::path(a.scene));
    require_for_planning(scene);
    // The verification's spacing is checked before the plan (a spacing too fine or too coarse for the stock
    // had stopped the job after planning).
    check_verify_resolution(scene, a.options.resolution_mm);
    const bool made = check_run_outputs(scene, a.dir);
    a.options.out_dir = a.dir;
    a.options.progress = terminal_progress();
    JobSummary s;
    try {
      s = run_job(scene, a.options);
    } catch (const InputError&) {
      // Bad input leaves no output: a folder this run made and left empty goes too.
      std::error_code ec;
      if (made && std::filesystem::is_empty(a.dir, ec)) std::filesystem::remove(a.dir, ec);
      throw;
    }
    std::cout << format_summary(s, scene);
    if (s.collisions_final > 0)
      throw JobError(std::to_string(s.collisions_final) + " collision(s) left after re-planning (see `left` above)");
  });
}

}  // namespace tf::cli
