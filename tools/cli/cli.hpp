// tiltfield CLI: what every sub-command file shares.
//
// Each cmd_*.cpp defines one add_*_command(CLI::App&) that registers its options and a callback. The
// callback throws tf::InputError (exit 2), tf::JobError (exit 1) or returns normally (exit 0); main()
// maps them, so no command prints its own error line or calls exit().
#pragma once
#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tiltfield/engagement/feed_schedule.hpp"
#include "tiltfield/core/progress.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf::cli {

struct GlobalOptions {
  bool quiet = false;
};

// The options shared by all commands (--quiet); valid for the process' lifetime.
GlobalOptions& global_options();

// A progress callback that draws a bar on stderr when stderr is a terminal and --quiet is off.
Progress terminal_progress();

// The air feed of a feed schedule: the machine's max_feed unless `option` (--air-feed) is given, and then
// `value`, which must be positive (the library's 0, "keep the programmed feed", is no value to give here;
// -1, 0 and nan had fallen back to the default without a word, black-box testing), and between
// `min_feed` and `machine_max_feed`.
double scheduled_air_feed(const CLI::Option& option, double value, double machine_max_feed, double min_feed);

// The link gap the scene's planner options give ("planner": {"link_gap_mm": ...}), for the post: the
// planner's and the post's must agree (the scene's had reached the planner only); nullopt when not set.
std::optional<double> scene_link_gap(const Scene& scene);

// One line on stderr (unless --quiet) summing up a feed schedule, then its warnings.
void print_feed_schedule(const std::string& who, const FeedScheduleOptions& options, const FeedSchedule& schedule);

// Throws InputError naming `option` and `path` when the file could not be written there (its folder is
// missing or not writable), so that a command refuses it before its long work; an empty path is not asked.
// "holder in fixture", "ball in stock (rapid)": a collision's kind as the commands print it.
std::string collision_kind(const Collision& c);

void check_output_file(const std::string& option, const std::string& path);
// Throws InputError (naming the option and the path) when an output would replace one of the command's
// input files or another output of the same run: the output is renamed onto its name at the end, so the
// input would be lost. `outputs`: (option, path); empty paths are not asked.
void check_outputs_apart(const std::vector<std::pair<std::string, std::string>>& outputs,
                         const std::vector<std::string>& inputs);
// The files `scene` was read from (scene file, meshes, path, machine) after `others`: inputs that
// check_outputs_apart protects (`run -o` into the scene's folder had replaced its stock mesh).
std::vector<std::string> scene_inputs(const Scene& scene, std::vector<std::string> others = {});
// The same test as a validator of an output option, so that a command's parse refuses the name (exit 2)
// before its work.
CLI::Validator output_file();
// A finite number above (strictly) or at least `lowest`; the message quotes what was given (CLI11's own
// range validators print the largest double in full).
CLI::Validator number_at_least(double lowest, bool strictly);
// Any finite number (CLI11 read an empty string as 0).
CLI::Validator finite_number();

// The bundled scene `name` ("impeller", "pocket", "block"), generated at build time next to the
// executable (build/scenes/NAME/scene.json). Throws InputError when it is missing.
std::filesystem::path bundled_scene(const std::string& name);

// The memory this machine has available now (Linux: MemAvailable of /proc/meminfo), bytes; 0 when unknown.
double available_memory_bytes();

void add_run_command(CLI::App& app);
void add_plan_command(CLI::App& app);
void add_post_command(CLI::App& app);
void add_verify_command(CLI::App& app);
void add_replan_command(CLI::App& app);
void add_offset_command(CLI::App& app);
void add_grind_command(CLI::App& app);
void add_scene_command(CLI::App& app);
void add_check_command(CLI::App& app);

}  // namespace tf::cli
