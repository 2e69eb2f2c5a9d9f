// tiltfield: the verifier: tri-dexel material-removal simulation of a program on the scene's machine,
// with collisions, gouges, per-block removal and the report files (spec: "Verification report").
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tiltfield/engagement.hpp"
#include "tiltfield/kinematics.hpp"
#include "tiltfield/program.hpp"
#include "tiltfield/progress.hpp"
#include "tiltfield/scene.hpp"
#include "tiltfield/sweep.hpp"
#include "tiltfield/tridexel.hpp"

namespace tf {

// Joint values -> tool pose in the part frame (Kinematics::forward, or a stand-in in tests).
using ForwardFn = std::function<ToolPose(const Joints&)>;

// The forward map of a 3-axis machine (tip = X Y Z, axis +Z), for scenes without rotary axes.
ToolPose forward_xyz(const Joints& j);

// The scene's machine (3-axis when the scene names none) through the shared Kinematics, with the tool's
// gauge length.
ForwardFn scene_forward(const Scene& scene);

struct VerifyOptions {
  double resolution = 0.1;               // lattice spacing (distance between neighbouring rays), mm
  SweepOptions sweep;                    // sub-step tolerance of 5-axis sweeps
  bool stop_at_first_collision = false;  // stop after the first block that collides
  double collision_tolerance = 0.001;    // overlaps up to this deep (mm) are contact, not collision
  double gouge_tolerance = 0.01;         // over-cuts deeper than this (mm) are listed as gouges
  bool check_gouges = true;              // against the scene's design surface (when it has one)
  bool engagement = true;                // engagement angles, area and depths per feed block
  EngagementOptions engagement_options;
  Progress progress;                     // stage "verify"
};

enum class HitWith { Stock, Check, Fixture };
std::string_view to_string(HitWith w);

struct Collision {
  int block = 0;  // 1-based motion block
  int line = 0;   // G-code line
  ToolComponent component = ToolComponent::Holder;
  HitWith with = HitWith::Stock;
  bool rapid = false;
  double depth_mm = 0.0;  // penetration estimate (see docs/verifier.md)
  // The tool's pose at the start and the end of the block (part frame), so that a re-planner can find
  // the path rows involved without the program.
  ToolPose start, end;
};

struct Gouge {
  int block = 0, line = 0;
  double depth_mm = 0.0;  // deepest over-cut of the block, normal to the design, mm
};

struct BlockResult {
  int block = 0, line = 0;
  double removed_mm3 = 0.0;
  double minutes = 0.0;  // block time from its feed (rapids at the machine's rapid feed)
  bool collision = false;
  int substeps = 1;
  bool rapid = false;
  FeedMode feed_mode = FeedMode::PerMinute;
  double feed = 0.0;       // the programmed F in force (mm/min, or 1/min for inverse time)
  double path_mm = 0.0;    // the length the feed refers to (tip path, XYZ path, or rotary degrees)
  Engagement engagement;   // at the block's end (feed blocks, VerifyOptions::engagement)
  // Material removal rate at the programmed feed, mm^3/min (0 when the block takes no time).
  double mrr() const { return minutes > 0 ? removed_mm3 / minutes : 0.0; }
};

struct ExcessStats {
  size_t samples = 0;  // design crossings inside the stock's bounds that were measured
  double mean_mm = 0.0, p95_mm = 0.0, max_mm = 0.0;
};

struct VerifyReport {
  int blocks = 0;
  double removed_volume_mm3 = 0.0;
  double stock_volume_start_mm3 = 0.0, stock_volume_end_mm3 = 0.0;
  std::vector<Collision> collisions;
  std::vector<Gouge> gouges;
  double max_gouge_mm = 0.0;
  double resolution_mm = 0.0;
  size_t rays = 0;           // rays of the three grids
  size_t material_rays = 0;  // of which carrying stock at the start
  double seconds = 0.0;
  double engagement_seconds = 0.0;     // of `seconds`, spent measuring engagement
  double sweep_error_mm = 0.0;         // largest sub-step error bound of the cutting parts
  double holder_sweep_error_mm = 0.0;  // the same for shank and holder
  size_t memory_bytes = 0;             // tri-dexel stock at the end
  bool stopped_early = false;
  ExcessStats excess;
  std::vector<BlockResult> per_block;
  std::vector<std::string> warnings;
};

struct VerifyResult {
  VerifyReport report;
  TriDexel stock;  // the stock after the simulated blocks
};

// Simulates `program` on the scene's stock with the scene's tool. `forward` maps the program's joint
// values to tool poses; TCP blocks take their tip from X Y Z and only the axis from forward().
// Throws InputError for a scene that cannot be simulated (no stock, bad resolution).
VerifyResult verify_program(const Scene& scene, const Program& program, const ForwardFn& forward,
                            const VerifyOptions& options = {});

// The spec's VERIFY.json and blocks.csv (written atomically). blocks.csv has the spec's columns, then
// axial_depth_mm, radial_width_mm and pairs (the most entry/exit pairs at one height).
void write_verify_json(const VerifyReport& report, const std::filesystem::path& file);
void write_blocks_csv(const VerifyReport& report, const std::filesystem::path& file);
// Every entry/exit pair at every height: block,line,height_mm,entry_deg,exit_deg (needs
// EngagementOptions::keep_pairs).
void write_engagement_csv(const VerifyReport& report, const std::filesystem::path& file);

// Options for the stock mesh.
struct StockMeshOptions {
  // Vertices move onto a local sphere (or plane) fitted to the exact dexel ends around them where it fits
  // within 5 % of the spacing (smooth regions); edges and corners keep the mass point of their crossings.
  bool smooth = true;
  // Each level splits every triangle in four, new points on the fitted surfaces (0: none).
  int refine = 0;
  bool colour_by_deviation = true;  // per-vertex colour from the signed distance to the design
  double colour_range_mm = 0.0;     // deviation mapped to full red/blue; 0: the largest |deviation|, >= 0.05
};

// A closed triangle mesh of the tri-dexel stock (dual contouring on the lattice: one vertex a cell with
// crossings, placed from the exact dexel ends on its edges, one quad a crossing lattice edge).
// With a design mesh and colour_by_deviation, vertices get colours: blue = below the design (gouge),
// green = on it, red = material left.
Mesh reconstruct_stock(const TriDexel& stock, const Mesh* design, const StockMeshOptions& options = {});

}  // namespace tf
