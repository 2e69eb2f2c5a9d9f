// tiltfield post: the post-processor: an oriented path -> Program (machine axes, linearised) -> text.
//
// In: an OrientedPath and a PostJob (machine, tool, feed, part bounds for the safe heights, and optionally
// the stock, fixtures and check surfaces the transit moves must clear). Out: a Program of motion blocks
// (joint solutions through the machine's inverse kinematics, the nearest to the previous row, bisected
// until the tip stays within tip_tolerance_mm of the straight segment and the axis within
// axis_tolerance_deg of the great circle; approach, retract and links between rows farther apart than
// link_gap_mm, lifted only as far as the obstacles need), then RS274/NGC text (joint or TCP dialect, G93
// inverse time on rotary joint moves) or APT CLDATA. Units: mm, deg, mm/min. Defaults in PostOptions.
// See docs/post.md.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/progress.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/core/tool.hpp"

namespace tf {

enum class Dialect { Joint, Tcp, Apt };
// How the C axis moves while the tool axis is within the pole tolerance of the pole (C is free there):
// held at the value before the pole, or interpolated (by path length) from the value before to the one
// after, so that it does not swing at the exit.
enum class PoleMode { Interpolate, Hold };

struct PostOptions {
  std::optional<Dialect> dialect;      // default: the machine's `output` (joint or tcp)
  std::optional<TcpStyle> tcp_style;   // default: the machine's `tcp_style`
  double tip_tolerance_mm = 0.01;      // largest tip deviation from the straight segment between rows
  double axis_tolerance_deg = 0.1;     // largest tool-axis deviation from the great-circle interpolation
  double pole_tolerance_deg = 0.1;     // singular-pole cone half-angle (see PoleMode), deg
  PoleMode pole_mode = PoleMode::Interpolate;
  double spindle_rpm = 10000.0;        // S word, rev/min
  int tool_number = 1;                 // T and H words
  double plunge_feed_fraction = 0.5;   // approach feed = this fraction of the first row's feed
  // Consecutive rows whose tool tips are farther apart than this are not cut through but linked:
  // retract, rapid(s), approach and a feed plunge. Default (nullopt): kLinkGapToolRadii x the tool
  // radius (at least 1 mm), above any cutting step of the bundled scenes (<= 2 radii). mm, > 0.
  std::optional<double> link_gap_mm;
};

// The link gap in effect for these options and tool, mm.
double effective_link_gap(const PostOptions& options, const Tool& tool);

// What the post needs to know besides the path.
struct PostJob {
  MachineSpec machine;
  Tool tool;
  double feed = 1000.0;               // mm/min, for rows without their own feed
  Eigen::AlignedBox3d part_bounds;    // stock, design and fixtures, part frame, mm (for safe heights)
  std::string title = "tiltfield";    // a comment line in the program header
  // What the approach, retract and link moves are checked against, part frame. All empty: every retract
  // lifts to part_bounds' extent along the axis plus safe_z (the behaviour without obstacles). Otherwise
  // a retract lifts only until the tool body clears all of them by safe_z (never above that extent) and
  // a link's rapid runs at the lowest height whose swept motion clears them (docs/post.md).
  Mesh stock;                               // closed: a solid (no faces: not checked)
  std::vector<const Mesh*> fixtures;        // distance only; the meshes outlive the job
  std::vector<const Mesh*> check_surfaces;  // distance only; the meshes outlive the job
  // The scene's G54 (X Y Z mm, A B C deg): the program runs in G54, and the controller adds it to every
  // axis word, so the writer subtracts it from the machine positions it writes.
  WorkOffset work_offset{};
};

// Fills the job from the scene for a program whose tool is `tool_number`: the machine (the scene must
// name one), the tool (the library's tool of that number when the scene has a library: its gauge length
// is what the controller's G43 H takes; otherwise the scene's tool), the feed, the part bounds, the
// transit obstacles and the G54 offset. Throws InputError (field "--tool-number") for a number the library
// lacks.
void set_post_job(PostJob& job, const Scene& scene, int tool_number);

// Fills job.stock, job.fixtures and job.check_surfaces from the scene (the stock as a closed mesh,
// pointers to the scene's fixtures and check surfaces: the scene must outlive the job).
void set_transit_obstacles(PostJob& job, const Scene& scene);

// A row that cannot be posted (unreachable pose, axis out of limits). The CLI turns it into exit 2
// naming the file line of that row.
class PostRowError : public std::runtime_error {
 public:
  PostRowError(size_t row, const std::string& what) : std::runtime_error(what), row_(row) {}
  size_t row() const { return row_; }  // 0-based index into OrientedPath::rows

 private:
  size_t row_;
};

// Posts the path. Joint dialect: every block is in machine axes and linearised to the tolerances;
// tcp dialect: tip in the part frame (Block::tcp), linearised for the axis only; apt: the program
// holds the tool tips and axes as tcp blocks (A/B/C left 0, see post_apt_poses). Throws PostRowError
// for an unreachable row, JobError when a segment cannot be linearised.
Program post_program(const OrientedPath& path, const PostJob& job, const PostOptions& options,
                     const Progress& progress = {});

// The dialect in effect for these options and machine.
Dialect effective_dialect(const PostOptions& options, const MachineSpec& machine);

// Writes a program as RS274/NGC text (joint or tcp dialect; G93 inverse time on rotary joint moves).
// No scientific notation; 4 decimals for mm, 4 for degrees.
void write_gcode(std::ostream& out, const Program& program, const PostJob& job, const PostOptions& options);

// Writes the path as APT CLDATA (GOTO/x,y,z,i,j,k with the tool tip and axis, MULTAX/ON, FEDRAT).
void write_apt(std::ostream& out, const OrientedPath& path, const PostJob& job, const PostOptions& options);

// ---- linearisation (planner/post/linearize.cpp); exposed for the tests ----

// Deviation of joint-linear motion from the intended motion over one block, sampled at `samples`
// interior points s: tip distance |tip(s) - lerp(tip0, tip1, s)| (mm) and axis angle
// angle(axis(s), slerp(axis0, axis1, s)) (deg), where tip(s), axis(s) = forward(lerp(j0, j1, s)).
struct Deviation {
  double tip_mm = 0.0;
  double axis_deg = 0.0;
};
Deviation joint_deviation(const Kinematics& kin, const Joints& j0, const Joints& j1, const ToolPose& p0,
                          const ToolPose& p1, int samples);

}  // namespace tf
