// tiltfield core: the verification report, its files and their one reader.
//
// The verifier (tiltfield_dexel, with engagement from tiltfield_engagement) fills a VerifyReport; the
// re-planner, the feed schedule, the HTML report and the command line read it, from memory or back from
// the files written here:
//   VERIFY.json  the headline figures, collisions (with the tool poses at their block's start and end, so
//                the re-planner can find the path rows without the program), gouges, engagement summary
//   blocks.csv   one row per motion block: block,line,removed_mm3,mrr_mm3_min,entry_deg,exit_deg,
//                engaged_area_mm2,collision, then axial_depth_mm,radial_width_mm,pairs,tool
//   engagement   one row per entry/exit pair and height (optional)
// Units: mm, mm^3, mm^2, deg, minutes, mm^3/min. Every file is written atomically. Readers throw
// InputError naming the file, the line (CSV) and the field.
#pragma once
#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/tool.hpp"

namespace tf {

// What a tool component met.
enum class HitWith { Stock, Check, Fixture };
std::string_view to_string(HitWith w);  // "stock", "check", "fixture"

// A tool component inside the stock (a non-cutting part, or any part on a rapid), a check surface or a
// fixture during one block.
struct Collision {
  int block = 0;  // 1-based motion block
  int line = 0;   // 1-based G-code line, 0 when unknown
  ToolComponent component = ToolComponent::Holder;
  HitWith with = HitWith::Stock;
  bool rapid = false;
  double depth_mm = 0.0;  // penetration estimate (see docs/verifier.md)
  // The tool's pose at the start and the end of the block (part frame), so that a re-planner can find
  // the path rows involved without the program. `has_poses` is false for a collision read from a
  // VERIFY.json that does not carry them (they are an addition to the documented format).
  ToolPose start, end;
  bool has_poses = true;
  int tool = 0;  // the tool in the spindle (Block::tool); 0 as well for a VERIFY.json without the field
};

// A machine axis beyond its limit (MachineSpec::limits) at the end of a block or, in an arc, at an
// extreme point of its plane: a controller stops there.
struct AxisLimitExcess {
  int block = 0, line = 0;
  char axis = 'X';
  double value = 0.0;           // mm or deg, machine coordinates
  double min = 0.0, max = 0.0;  // the limit it leaves
};

struct Gouge {
  int block = 0, line = 0;
  double depth_mm = 0.0;  // deepest over-cut of the block, normal to the design, mm
};

// One entry/exit pair of the cutter-workpiece engagement at one height along the tool axis.
struct EngagementPair {
  double height_mm = 0.0;  // above the tool tip, along the axis
  double entry_deg = 0.0;  // in [0, 360)
  double exit_deg = 0.0;   // in [0, 360); below entry when the pair runs through 0
};

// The engagement of a feed block at its end (tiltfield/engagement/engagement.hpp says how it is measured
// and the angle convention).
struct Engagement {
  // The smallest arc holding every engaged angle at every height (empty: NaN). exit - entry, mod 360, is
  // the block's engagement angle; 0 and 360 for a full turn.
  double entry_deg = std::numeric_limits<double>::quiet_NaN();
  double exit_deg = std::numeric_limits<double>::quiet_NaN();
  double area_mm2 = 0.0;         // engaged area on the tool surface
  double axial_depth_mm = 0.0;   // height extent of the engaged surface along the axis
  double radial_width_mm = 0.0;  // its extent along n (normal to feed and axis)
  int max_pairs = 0;             // the most pairs at one height
  std::vector<EngagementPair> pairs;  // every height's pairs (when the measurement keeps them)
  bool engaged() const { return area_mm2 > 0.0; }
  double angle_deg() const;  // exit - entry in (0, 360], 0 when not engaged
};

struct BlockResult {
  int block = 0, line = 0;
  int tool = 0;          // the tool in the spindle (Block::tool)
  double removed_mm3 = 0.0;
  double minutes = 0.0;  // block time from its feed (rapids at the machine's rapid feed)
  double dwell_minutes = 0.0;  // the dwell before the block's motion (Block::dwell_s); the block takes both
  bool collision = false;
  int substeps = 1;
  bool rapid = false;
  FeedMode feed_mode = FeedMode::PerMinute;
  double feed = 0.0;       // the programmed F in force (mm/min, or 1/min for inverse time)
  double path_mm = 0.0;    // the length the feed refers to (tip path, XYZ path, or rotary degrees)
  Engagement engagement;   // at the block's end (feed blocks, when engagement is measured)
  // Material removal rate at the programmed feed, mm^3/min (0 when the block takes no time).
  double mrr() const { return minutes > 0 ? removed_mm3 / minutes : 0.0; }
};

struct ExcessStats {
  size_t samples = 0;  // design crossings inside the stock's bounds that were measured
  double mean_mm = 0.0, p95_mm = 0.0, max_mm = 0.0;
};

// The stock mesh that came with the report (`verify --stock-mesh`, `--html`): an addition to the spec's
// report. The mesh is the dual-contoured dexel surface decimated within `max_error_mm` (the bound asked
// for, not a measurement: every full-mesh vertex within it of the compact faces, the compact faces sampled
// within half of it of the full mesh; tiltfield/core/mesh_simplify.hpp); 0 means the full mesh.
struct StockMeshStats {
  double max_error_mm = 0.0;
  size_t vertices = 0, faces = 0;
  size_t bytes = 0;                          // as a binary PLY (the file's size when one was written)
  size_t full_vertices = 0, full_faces = 0;  // the dual-contoured mesh before decimation
  double mesh_seconds = 0.0;                 // dual contouring
  double decimate_seconds = 0.0;
};

struct VerifyReport {
  int blocks = 0;
  // False where the scene has no design surface: no gouges, max_gouge_mm or excess were computed (VERIFY.json
  // writes them as null, not as zeros that read as checked).
  bool design_checked = true;
  double removed_volume_mm3 = 0.0;
  double stock_volume_start_mm3 = 0.0, stock_volume_end_mm3 = 0.0;
  std::vector<Collision> collisions;
  std::vector<Gouge> gouges;
  std::vector<AxisLimitExcess> axis_limits;  // each axis once per block
  double max_gouge_mm = 0.0;
  double resolution_mm = 0.0;
  size_t rays = 0;           // rays of the three grids
  size_t material_rays = 0;  // of which carrying stock at the start
  double seconds = 0.0;
  double engagement_seconds = 0.0;     // of `seconds`, spent measuring engagement
  double sweep_error_mm = 0.0;         // largest sub-step error bound of the cutting parts
  double holder_sweep_error_mm = 0.0;  // the same for shank and holder
  double sweep_tolerance_mm = 0.0;     // the bounds asked for (--tolerance, --holder-tolerance)
  double holder_tolerance_mm = 0.0;
  double gouge_tolerance_mm = 0.0;      // over-cuts listed as gouges beyond this (--gouge-tolerance)
  double collision_tolerance_mm = 0.0;  // overlaps up to this deep are contact (--collision-tolerance)
  size_t memory_bytes = 0;             // tri-dexel stock at the end
  bool stopped_early = false;
  ExcessStats excess;
  std::vector<BlockResult> per_block;  // not in VERIFY.json: blocks.csv carries it
  std::vector<std::string> warnings;
  std::optional<StockMeshStats> stock_mesh;  // VERIFY.json's "stock_mesh", when a mesh was made
};

// One row of blocks.csv. NaN: not computed (an empty cell): the MRR of a block that takes no time, the
// angles of a block that engages nothing. `axial_depth_mm`, `radial_width_mm` and `pairs` are NaN / -1
// when the file has no such column (the eight documented columns only), `tool` -1.
struct BlockRow {
  int block = 0;  // as the verifier numbers them, from 1
  int line = 0;   // 1-based G-code line, 0 when unknown
  double removed_mm3 = std::numeric_limits<double>::quiet_NaN();
  double mrr_mm3_min = std::numeric_limits<double>::quiet_NaN();
  double entry_deg = std::numeric_limits<double>::quiet_NaN();
  double exit_deg = std::numeric_limits<double>::quiet_NaN();
  double engaged_area_mm2 = std::numeric_limits<double>::quiet_NaN();
  bool collision = false;
  double axial_depth_mm = std::numeric_limits<double>::quiet_NaN();
  double radial_width_mm = std::numeric_limits<double>::quiet_NaN();
  int pairs = -1;
  int tool = -1;
};

// The blocks.csv row of a block result.
BlockRow block_row(const BlockResult& block);

// VERIFY.json: the documented fields, then the tool and the tool poses of each collision, the stock
// volumes, sweep error bounds, excess material statistics, memory, the program's time (motion and dwells,
// `program_minutes`), an engagement/MRR summary over the feed blocks and the stock mesh's bound and sizes
// (when there is one).
void write_verify_json(const VerifyReport& report, const std::filesystem::path& file);
// blocks.csv: the documented columns, then axial_depth_mm, radial_width_mm, pairs (the most entry/exit
// pairs at one height) and tool (Block::tool).
void write_blocks_csv(const VerifyReport& report, const std::filesystem::path& file);
// Every entry/exit pair at every height: block,line,height_mm,entry_deg,exit_deg (needs the pairs kept).
void write_engagement_csv(const VerifyReport& report, const std::filesystem::path& file);

// Reads a VERIFY.json back: every figure write_verify_json writes except the engagement summary and the
// program's time (per_block stays empty; blocks.csv has the blocks). The documented fields are required in a
// collision or gouge (block, line, component, with, rapid, depth_mm); the figures are optional (NaN, or
// 0 for counts, when absent), the collision poses too (Collision::has_poses), and a collision's tool (0).
VerifyReport read_verify_json(const std::filesystem::path& file);

// Reads blocks.csv (the eight documented columns required, the four extra ones optional; collision 0/1 or
// true/false; an empty number cell is NaN).
std::vector<BlockRow> read_blocks_csv(const std::filesystem::path& file);

}  // namespace tf
