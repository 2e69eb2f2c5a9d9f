// tiltfield: the machine description (the kinematic chain's type, offsets, limits and output dialect).
//
// The kinematics themselves (forward and inverse) live in one place, kinematics.hpp, used by the
// post-processor and the verifier alike.
#pragma once
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace tf {

enum class KinematicsType { XYZ, TableTableAC, TableTableBC, HeadTableBC, HeadHeadAC };
std::string_view to_string(KinematicsType k);

enum class OutputMode { Joint, Tcp };
enum class TcpStyle { G43_4, M128 };

struct AxisLimit {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool contains(double v) const { return v >= min && v <= max; }
};

struct MachineSpec {
  std::string name = "machine";
  KinematicsType kinematics = KinematicsType::XYZ;
  // Table-table machines: a point on the C axis, in machine coordinates with the part frame's origin at
  // the machine origin when both rotaries are at 0 (LinuxCNC's xyzac-trt/xyzbc-trt x-rot-point,
  // y-rot-point, z-rot-point). mm.
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
  // Table-table machines: the tilting axis (A or B) passes through pivot + tilt_offset (LinuxCNC's
  // x-offset, y-offset, z-offset; the component along the tilting axis has no effect). mm.
  Eigen::Vector3d tilt_offset = Eigen::Vector3d::Zero();
  // Head machines: distance from the spindle nose (gauge line) to the head's rotation centre, along
  // the tool axis, mm (the "pivot length").
  double head_pivot_length = 0.0;
  // Head-table machines: the table's rotation centre in machine coordinates, mm.
  Eigen::Vector3d table_center = Eigen::Vector3d::Zero();
  // Per axis letter (X Y Z A B C). A rotary axis that is absent here is continuous.
  std::map<char, AxisLimit> limits;
  OutputMode output = OutputMode::Joint;
  TcpStyle tcp_style = TcpStyle::G43_4;
  // Optional M-code that switches tool-centre-point control on/off for a TCP program (e.g. "M128").
  std::string tcp_on_code;
  std::string tcp_off_code;
  double max_feed = 10000.0;   // mm/min
  double rapid_feed = 20000.0; // mm/min, for time estimates
  double max_rotary_feed = 7200.0;  // deg/min, the rotaries' top speed (bounds inverse-time feeds)
  double safe_z = 50.0;        // retract height above the part's highest point along the tool axis, mm

  // The rotary axis letters this machine has, in the order they appear in G-code (e.g. "AC").
  std::string rotary_axes() const;
  bool has_axis(char letter) const;
};

// Reads a machine JSON file. Throws InputError naming the file and field (unknown kinematics name,
// limits with min > max, a non-finite offset, an unknown key, ...).
MachineSpec read_machine_json(const std::filesystem::path& file);
// The same, from an already-parsed JSON object; `file` and `prefix` only name the place in errors.
MachineSpec parse_machine_json(const nlohmann::json& object, const std::string& file, const std::string& prefix);

}  // namespace tf
