// tiltfield: the main job (`tiltfield run`): plan, post, verify, re-plan what collides, verify again,
// and write every output file and the report.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "tiltfield/core/progress.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {

// The files `run` writes into its output folder, by name.
inline constexpr const char* kRunOutputs[] = {"oriented.csv", "program.ngc", "verify.json",
                                              "blocks.csv",   "stock.ply",   "report.html"};

struct JobOptions {
  std::filesystem::path out_dir = "out";
  double resolution_mm = 0.1;  // tri-dexel spacing of the verification, mm
  int max_rounds = 3;          // re-plan rounds at most; a round that does not reduce the collisions ends them
  bool write_report = true;    // report.html
  Progress progress;
};

struct StageSeconds {
  double plan = 0, post = 0, verify = 0, replan = 0, mesh = 0, report = 0;  // mesh: stock.ply, made and written
};

// Collisions left after the last round, grouped by kind and by why they were not fixed.
struct LeftCollisions {
  std::string kind;    // e.g. "holder in fixture", "ball in check (rapid)"
  std::string reason;  // why re-planning did not remove them
  size_t count = 0;
  size_t first_row = 0, last_row = 0;  // the path rows they span
};

struct JobSummary {
  size_t rows = 0;
  size_t nominal_colliding_rows = 0;  // rows the nominal axis leaves below the safety distance
  size_t uncleared_rows = 0;          // rows the planner could not clear
  // A flat or bull end against the design: rows whose lead the planner changed, rows still dipping, mm.
  size_t end_lead_rows = 0, end_turned_rows = 0, end_dipping_rows = 0;
  double max_end_dip_mm = 0;
  double min_clearance_mm = 0;        // of the final oriented path
  size_t blocks = 0;
  size_t collisions_first = 0;  // in the first verification
  size_t collisions_final = 0;  // in the last one
  size_t collisions_new = 0;    // of those, on rows no collision of the first touched: brought by re-planning
  size_t gouges_final = 0;
  double max_gouge_mm = 0;
  int rounds = 0;                // re-plan rounds done
  size_t rows_replanned = 0;
  std::vector<LeftCollisions> left;
  std::string replan_not_posted;  // why the last re-planned path could not be posted (the round not kept)
  // What the last re-plan left below its clearance (rows, motions between rows), or empty.
  std::string replan_shortfall;
  double removed_volume_mm3 = 0;
  StageSeconds seconds;
  std::vector<std::string> files;  // written, in order
};

// Runs the whole job on `scene`, writing oriented.csv, program.ngc, verify.json, blocks.csv, stock.ply
// and report.html into options.out_dir (created when missing; each file written atomically).
JobSummary run_job(const Scene& scene, const JobOptions& options);

// The one-screen summary `tiltfield run` prints.
std::string format_summary(const JobSummary& summary, const Scene& scene);

}  // namespace tf
