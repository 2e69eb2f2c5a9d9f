// tiltfield: 5-axis tool-axis planning, posting and verification. See README.md.
#include <algorithm>
#include <iostream>
#include <new>
#include <string>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"tiltfield: 5-axis tool-axis planning, posting and verification (mm, deg, mm/min)", "tiltfield"};
  app.set_version_flag("--version", std::string("tiltfield ") + TILTFIELD_VERSION);
  app.add_flag("-q,--quiet", tf::cli::global_options().quiet, "no progress output");
  app.require_subcommand(1);
  // `tiltfield verify ... --quiet` as well as `tiltfield --quiet verify ...`: a sub-command hands the
  // options it does not know to this one (set before the sub-commands are made, which inherit it).
  app.fallthrough();
  tf::cli::add_run_command(app);
  tf::cli::add_plan_command(app);
  tf::cli::add_post_command(app);
  tf::cli::add_verify_command(app);
  tf::cli::add_replan_command(app);
  tf::cli::add_offset_command(app);
  tf::cli::add_grind_command(app);
  tf::cli::add_scene_command(app);
  tf::cli::add_check_command(app);
  // An empty value (`--gouge-tolerance ""`, `--mesh-tolerance=`) reads as 0 to CLI11: refused here, where
  // an option without a range of its own would take it (black-box testing).
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const size_t eq = a.find('=');
    std::string field;
    if (a.empty()) field = i > 1 && argv[i - 1][0] == '-' ? argv[i - 1] : "argument " + std::to_string(i);
    else if (a.rfind("--", 0) == 0 && eq + 1 == a.size()) field = a.substr(0, eq);
    if (!field.empty()) {
      std::cerr << "tiltfield: field '" << field << "': empty value\n";
      return 2;
    }
  }
  // The first word that is not an option must name a command: CLI11 says only "A subcommand is
  // required" of a misspelt one (black-box testing).
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.empty() || a[0] == '-') continue;
    const auto commands = app.get_subcommands([](const CLI::App*) { return true; });
    if (std::none_of(commands.begin(), commands.end(), [&](const CLI::App* c) { return c->check_name(a); })) {
      std::string names;
      for (const CLI::App* c : commands) names += (names.empty() ? "" : ", ") + c->get_name();
      std::cerr << "tiltfield: unknown command '" << a << "' (commands: " << names << ")\n";
      return 2;
    }
    break;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "tiltfield: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const tf::InputError& e) {
    std::cerr << "tiltfield: " << e.what() << "\n";
    return 2;
  } catch (const tf::JobError& e) {
    std::cerr << "tiltfield: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "tiltfield: out of memory: the job needs more than this machine has (a coarser resolution or spacing?)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tiltfield: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
