// tiltfield dexel: the verifier's simulation: tri-dexel material removal of a program on the scene's machine.
//
// In: the scene (stock, tool, check surfaces, fixtures, design), a Program and the machine's forward
// kinematics. Out: a VerifyReport (tiltfield/core/report.hpp: removed volume per block and in all,
// collisions of each tool component with the stock, check surfaces and fixtures, gouges against the
// design, sweep error bounds) and the stock after the program, which reconstruct_stock turns into a
// closed mesh. Per block the swept volume of every convex tool part is intersected exactly with the rays
// of three orthogonal grids (sweep.hpp) and subtracted from their material intervals, in parallel over
// tiles of rays. Units: mm, mm^3, minutes. Defaults: 0.1 mm lattice, 0.01 mm sweep tolerance.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/progress.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/sweep.hpp"
#include "tiltfield/dexel/tridexel.hpp"

namespace tf {

// Joint values -> tool pose in the part frame (Kinematics::forward, or a stand-in in tests).
using ForwardFn = std::function<ToolPose(const Joints&)>;

// The forward map of a 3-axis machine (tip = X Y Z, axis +Z), for scenes without rotary axes.
ToolPose forward_xyz(const Joints& j);

// The scene's machine (3-axis when the scene names none) through the shared Kinematics, with the gauge
// length of the scene's tool, or of `tool`.
ForwardFn scene_forward(const Scene& scene);
ForwardFn scene_forward(const Scene& scene, const Tool& tool);

// Measures a feed block's engagement at its end, for the tool in the spindle: `stock` is the stock as it
// was before the block where the engagement reads (its rays near the end pose's cutting surface: the cut
// defers its changes there until the probe returns; elsewhere they may be made already), `before`
// the pose a short time before the end, `end` the end pose, and `removed` the box (part frame, mm)
// holding all the material the block's cutting parts removed, outside which nothing can be engaged.
// Called only for feed blocks that removed material. tiltfield_engagement's engagement_probe() makes one;
// the simulation itself does not depend on it.
using EngagementProbe = std::function<Engagement(const Tool& tool, const TriDexel& stock, const ToolPose& before,
                                                 const ToolPose& end, const Eigen::AlignedBox3d& removed)>;

struct VerifyOptions {
  double resolution = 0.1;               // lattice spacing (distance between neighbouring rays), mm
  SweepOptions sweep;                    // sub-step tolerance of 5-axis sweeps
  bool stop_at_first_collision = false;  // stop after the first block that collides
  double collision_tolerance = 0.001;    // overlaps up to this deep (mm) are contact, not collision
  // Over-cuts deeper than this (mm), and than the block's sweep bound (sweep_error_mm), are listed as gouges.
  double gouge_tolerance = 0.01;
  bool check_gouges = true;              // against the scene's design surface (when it has one)
  // Called for every feed block that removed material (empty: no engagement measured, the
  // BlockResult::engagement stay empty). The command line sets it unless --no-engagement.
  EngagementProbe engagement;
  Progress progress;                     // stage "verify"
  // Fill VerifyResult::last_block (4 bytes a ray), for colouring the stock by the block or tool that cut it.
  bool record_last_block = false;
};

// Per grid d, per ray in TriDexel::grid(d) order: the 1-based motion block that last changed the ray's
// material, 0 where no block did.
using LastBlocks = std::array<std::vector<uint32_t>, 3>;

struct VerifyResult {
  VerifyReport report;
  TriDexel stock;         // the stock after the simulated blocks
  LastBlocks last_block;  // empty unless VerifyOptions::record_last_block
};

// Simulates `program` on the scene's stock, each block with the tool in its spindle (Block::tool): a tool
// of the scene's library by number, otherwise the scene's `tool`. `forward` maps the program's joint
// values to tool poses for the scene's tool; library tools use the scene's machine with their own gauge
// length (scene_forward). TCP blocks take their tip from X Y Z and only the axis from the forward map.
// Throws InputError for a scene that cannot be simulated (no stock, bad resolution).
VerifyResult verify_program(const Scene& scene, const Program& program, const ForwardFn& forward,
                            const VerifyOptions& options = {});

// Throws InputError (field "resolution") where verify_program would refuse the lattice spacing `h` mm for
// the scene: not positive, coarser than a quarter of the stock's thinnest side, or more than 2e8 rays. For
// a job that plans before it verifies, to refuse a bad spacing before any work.
void check_verify_resolution(const Scene& scene, double h);

// Options for the stock mesh.
struct StockMeshOptions {
  // Vertices move onto a local sphere (or plane) fitted to the exact dexel ends around them where it fits
  // within 5 % of the spacing (smooth regions); edges and corners keep the mass point of their crossings.
  bool smooth = true;
  // Each level splits every triangle in four, new points on the fitted surfaces (0: none).
  int refine = 0;
  bool colour_by_deviation = true;  // per-vertex colour from the signed distance to the design
  double colour_range_mm = 0.0;     // deviation mapped to full red/blue; 0: the largest |deviation|, >= 0.05
  Progress progress;                // stage "mesh"
};

// A closed triangle mesh of the tri-dexel stock (dual contouring on the lattice: one vertex a cell with
// crossings, placed from the exact dexel ends on its edges, one quad a crossing lattice edge).
// With a design mesh and colour_by_deviation, vertices get colours: blue = below the design (gouge),
// green = on it, red = material left.
Mesh reconstruct_stock(const TriDexel& stock, const Mesh* design, const StockMeshOptions& options = {});

}  // namespace tf
