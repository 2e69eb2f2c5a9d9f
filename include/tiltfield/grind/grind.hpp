// tiltfield grind: the 6-axis tool grinder of the cross-section grinding simulator (docs/grinding.md):
// its scene (blank, wheel, program) and kinematics.
//
// Frames. The blank frame B: the blank is the cylinder x^2 + y^2 <= r^2, 0 <= z <= l; z = 0 is the clamped
// (shank) end, z = l the free end (tip). The machine frame M: y vertical, at W = U = A = 0 it coincides with B.
// Axes (mm, deg):
//   X, Y, Z  the grinding wheel's centre in M;
//   U        slide of the blank along its own axis (after the W swivel), +U moves the blank toward +z;
//   A        rotation of the blank about its own axis (right-handed about +z);
//   W        swivel of the workhead (blank axis) about the vertical axis M.y through M's origin.
// The wheel spindle axis is fixed along M.x. A blank point p_B sits in M at Ry(W) * (Rz(A) * p_B + U * z).
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace tf::grind {

struct Blank {
  double radius = 0.0;  // mm
  double length = 0.0;  // mm, along +z from 0
};

// A wheel is a solid of revolution about its spindle axis: at axial offset t in [-thickness/2, thickness/2]
// from its mid-plane its radius is rho(t). `profile` holds (t, rho) samples, t increasing, rho concave in t
// (a convex wheel; concave form wheels are refused by the loader because the hull step assumes convexity).
struct Wheel {
  double radius = 0.0;       // mm, outer radius
  double thickness = 0.0;    // mm
  double edge_radius = 0.0;  // mm, rounding of both rim corners (0: sharp corners)
  std::vector<Eigen::Vector2d> profile;  // (t, rho), built by make_wheel_profile or given in the scene
};

// One position of the six axes.
struct Axes {
  double x = 0, y = 0, z = 0, u = 0, a = 0, w = 0;  // mm, mm, mm, mm, deg, deg
};

// One motion block: linear interpolation of every axis from the previous position to `target`.
struct Move {
  Axes target;
  int line = 0;        // 1-based line in the program text
  bool rapid = false;  // G0 (the simulation removes material on rapids too: a rapid through stock is a crash)
};

// A labelled group of moves (one cut or one grinding operation: fluting, gashing, od_sharpening,
// end_face, notching). Edges of the sections created by an operation carry its index + 1 as label.
struct Operation {
  std::string kind;   // one of the five kinds above
  std::string label;  // free text, e.g. "flute 1"
  int line = 0;       // line of its OP statement
  std::vector<Move> moves;
};

struct GrindScene {
  Blank blank;
  Wheel wheel;
  Axes start;  // axis position before the first block (scene "start", default all zero)
  std::vector<Operation> operations;
  std::string file;     // the scene path as given
  std::string program;  // the program's name in messages: its file, or the scene's inline lines
};

// Samples the rim of a wheel with rounded corners: rings every `max_step` mm along the flat rim and every
// few degrees around each corner (chord error <= chord_tolerance mm). Out: (t, rho), t increasing.
std::vector<Eigen::Vector2d> make_wheel_profile(double radius, double thickness, double edge_radius,
                                                double chord_tolerance = 0.002, double max_step = 0.25);

// Reads a grinding scene JSON (format in docs/grinding.md) and its program. Throws InputError naming the
// file and the field or line on anything missing, negative, unknown or not a number.
GrindScene load_grind_scene(const std::filesystem::path& file);

// Parses the G-code-like program text into operations; `start` is the position before the first block.
// `file` names the source in errors. Throws InputError(file, line, word, ...).
std::vector<Operation> parse_grind_program(const std::string& text, const std::string& file, const Axes& start);

// The wheel's pose relative to the blank: centre (mm) and unit spindle axis, in the blank frame B.
struct WheelPose {
  Eigen::Vector3d centre;
  Eigen::Vector3d axis;
};
WheelPose wheel_pose(const Axes& axes);

// Axes at fraction s in [0, 1] of the straight joint-space move from `from` to `to`.
Axes interpolate(const Axes& from, const Axes& to, double s);

// Number of equal increments for a move so that no point of the blank (radius r, length l) moves by more
// than `step` mm relative to the wheel within one increment. At least 1; kMaxIncrements + 1 for a move that
// would need more (the simulation refuses it rather than take coarser steps than asked).
inline constexpr int kMaxIncrements = 10'000'000;
int increments(const Axes& from, const Axes& to, const Blank& blank, double step);

// The largest axis values a program or the scene's start may give: linear axes (X, Y, Z, U) within
// +-kMaxTravelMm, rotary axes (A, W) within +-kMaxTurnDeg. A value beyond them is a typo (a lost decimal
// point), not a grinder's travel; every move is split into increments of --step, so a stray 1e9 would
// otherwise run for hours.
inline constexpr double kMaxTravelMm = 1e5;
inline constexpr double kMaxTurnDeg = 1e5;

}  // namespace tf::grind
