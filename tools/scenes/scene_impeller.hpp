// tiltfield scene generators: a parametric centrifugal impeller (hub, blades, optional splitters, stock,
// a hub-finishing zig-zag path in one channel), the default scene of `tiltfield run`.
//
// Frame: the impeller axis is +z, the hub's bottom face at z = 0, mm. Angles are in degrees in the
// options and radians in the functions below.
//
// Hub meridian (r, z) as a function of the elliptic angle phi in [0, pi/2] (a concave quarter ellipse
// centred at (outlet_radius, inlet_z)):
//   r(phi) = outlet_radius - (outlet_radius - inlet_radius) cos(phi)
//   z(phi) = inlet_z - (inlet_z - outlet_z) sin(phi)
// from the inlet (phi = 0, tangent vertical) to the outlet (phi = pi/2, tangent horizontal). The hub solid
// is closed by a nose cylinder r = inlet_radius up to nose_z and its cap, the rim r = outlet_radius down to
// z = 0 and the bottom face.
//
// The meridional parameter is m = phi / (pi/2) in [0, 1] (inlet to outlet). A blade's camber surface over
// m and span s in [0, 1] is the meridional point P(m, s) = hub(m) + s (shroud(m) - hub(m)), where the
// shroud (blade tip) curve is the quarter ellipse with the same centre and semi-axes reduced by the blade
// heights (inlet_height radially at the inlet, outlet_height axially at the outlet), at the angle
//   theta = theta_k + wrap * w(m) + s h(m) tan(lean) / r(P),   w(m) = m + 0.6 m (1 - m),
// h(m) = |shroud(m) - hub(m)|. At the inlet and the outlet the span direction is exactly the hub normal
// (radial, axial); in between it is the straight line to the shroud point, which unlike the exact hub
// normal never folds over (hub normals converge at the hub's centre of curvature, only
// (inlet_z - outlet_z)^2 / (outlet_radius - inlet_radius) = 25.6 mm from the inlet by default).
// w(m) makes the blade steeper at the inlet than at the outlet (w'(0) = 1.6, w'(1) = 0.4).
// The blade's faces are the camber surface offset by +-thickness(s)/2 along its unit normal; thickness
// goes linearly from thickness_hub (s = 0) to thickness_tip (s = 1); the blade extends below the hub
// surface (s < 0) so that its bottom is blade_sink mm deep along the hub normal.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "scene_writer.hpp"
#include "tiltfield/core/mesh.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace tf::scenes {

struct ImpellerOptions {
  // Blades.
  int blades = 7;                 // main blades, >= 2
  bool splitters = false;         // a splitter blade mid-way between consecutive main blades
  double splitter_start = 0.4;    // meridional parameter m where the splitters begin, in (0, 0.9)
  double lean_deg = 15.0;         // blade lean: tilt of the span line toward +theta, deg, in (-45, 45)
  double wrap_deg = 60.0;         // total wrap angle of the camber line from inlet to outlet, deg
  double inlet_height = 25.0;     // blade height at the inlet (radial), mm, < outlet_radius - inlet_radius
  double outlet_height = 12.0;    // blade height at the outlet (axial), mm, < inlet_z - outlet_z
  double thickness_hub = 2.5;     // blade thickness at the hub, mm
  double thickness_tip = 1.2;     // blade thickness at the tip, mm
  double blade_sink = 1.0;        // depth of the blade bottom below the hub surface, mm
  // Hub.
  double inlet_radius = 20.0;     // mm
  double inlet_z = 40.0;          // mm
  double outlet_radius = 60.0;    // mm
  double outlet_z = 8.0;          // mm
  double nose_z = 48.0;           // top of the nose cylinder, mm, > inlet_z
  double tolerance = 0.002;       // chordal tolerance of the hub mesh (the design surface), mm
  double blade_tolerance = 0.01;  // chordal tolerance of the blade meshes (check surfaces), mm
  // Stock.
  double allowance = 0.5;         // finishing allowance of the stock over the hub surface, mm
  double stock_tolerance = 0.01;  // chordal tolerance of the stock mesh, mm
  // Path and tool (ball end mill).
  double tool_radius = 3.0;       // ball radius = flute and shank radius, mm
  double step = 0.5;              // spacing of the cutter locations along a pass, mm
  int passes = 9;                 // passes across the channel, >= 1
  double m_start = 0.03;          // first meridional parameter of a pass
  double m_end = 0.97;            // last meridional parameter of a pass
  double ball_clearance = 1.2;    // least distance of the ball to any blade, mm (above the scene's 1.0 mm safety distance, which binds the ball too)
  double feed = 1500.0;           // mm/min
};

// Throws InputError("scene impeller", 0, "--option", what) for the first option out of range.
void validate_impeller_options(const ImpellerOptions& o);

// The analytic impeller: hub, blades and their parametrisation (see the header comment).
class ImpellerModel {
 public:
  explicit ImpellerModel(const ImpellerOptions& options);  // options must be valid
  const ImpellerOptions& options() const { return o_; }

  // Hub meridian at m: point (r, z), outward unit normal (nr, nz), derivative d(r, z)/dm.
  Eigen::Vector2d hub_rz(double m) const;
  Eigen::Vector2d hub_normal_rz(double m) const;
  Eigen::Vector2d hub_tangent_rz(double m) const;
  // Hub surface point and outward unit normal at meridional parameter m and angle theta (rad).
  Eigen::Vector3d hub_point(double m, double theta) const;
  Eigen::Vector3d hub_normal(double m, double theta) const;

  // Blades: index 0..blades-1 are the main blades (theta_k = 2 pi k / blades), blades..2 blades-1 the
  // splitters when enabled (theta_k + pi / blades).
  int blade_count() const;
  bool is_splitter(int blade) const { return blade >= o_.blades; }
  double blade_m_start(int blade) const { return is_splitter(blade) ? o_.splitter_start : 0.0; }
  // Meridional point of the camber surface at (m, s) and the span length h(m).
  Eigen::Vector2d camber_rz(double m, double s) const;
  double span_length(double m) const;
  // Span parameter of the blade bottom (negative: below the hub surface by blade_sink along the normal).
  double sink_span(double m) const;
  // Camber angle theta (rad) of blade `blade` at (m, s).
  double camber_theta(int blade, double m, double s) const;
  Eigen::Vector3d camber_point(int blade, double m, double s) const;
  // Unit normal of the camber surface, d/ds x d/dm normalised (toward +theta where the meridional
  // direction dominates).
  Eigen::Vector3d camber_normal(int blade, double m, double s) const;
  double thickness(double s) const;
  // A blade face point: side +1 or -1, sigma in [0, 1] from the bottom (sink) to the tip.
  Eigen::Vector3d face_point(int blade, int side, double m, double sigma) const;
  double span_of(double m, double sigma) const { return sink_span(m) + sigma * (1.0 - sink_span(m)); }

 private:
  ImpellerOptions o_;
  double a_, b_;  // hub ellipse semi-axes (radial, axial)
};

// Meshes (closed, outward faces). The hub follows `tolerance`, the blades `blade_tolerance`, the stock
// `stock_tolerance`.
Mesh impeller_hub_mesh(const ImpellerModel& model);
Mesh impeller_blade_mesh(const ImpellerModel& model, int blade);
Mesh impeller_blades_mesh(const ImpellerModel& model);  // all blades, one closed shell each
Mesh impeller_stock_mesh(const ImpellerModel& model);

struct ImpellerPathReport {
  double min_ball_clearance = 0.0;  // least distance of the ball (sphere) to the blades over all rows, mm
  int nominal_axis_hits = 0;        // rows where the tool along the hub normal meets a blade
  int passes = 0;
};

// The zig-zag hub finishing path in the channel between blade 0 and blade 1 (blade 0 and its splitter
// when splitters are on): passes along the flow from m_start to m_end, alternating, linked across the
// channel at the ends, cutter locations every <= step mm (measured on the ball centres). Each row is the
// analytic hub point + tool_radius * analytic hub normal. `blades` is the blade mesh the ball is kept
// ball_clearance away from (measured exactly against the mesh). Throws InputError naming --tool-radius
// when the channel is too narrow for the ball, JobError if the passes cannot be made clear.
ToolPath impeller_path(const ImpellerModel& model, const Mesh& blades, ImpellerPathReport* report = nullptr);

// The whole scene; `machine` is the machine JSON object (see machine_json()).
SceneBundle make_impeller_scene(const ImpellerOptions& options, const nlohmann::json& machine);

}  // namespace tf::scenes
