// libFuzzer target of the G-code reader (parse_gcode). The first byte picks the machine (3-axis, a
// table-table AC machine with M428/M429 TCP codes, a head-table BC machine), whether the scene has a tool
// library and work offsets, the block-delete switch and a given start position; the rest is the program.
// Whatever the bytes, the reader returns finite blocks or throws tf::InputError naming the file and a
// line; anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "tiltfield/core/error.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace {

tf::MachineSpec machine(int kind) {
  tf::MachineSpec m;
  if (kind == 1) {
    m.kinematics = tf::KinematicsType::TableTableAC;
    m.tcp_on_code = "M428";
    m.tcp_off_code = "M429";
  } else if (kind == 2) {
    m.kinematics = tf::KinematicsType::HeadTableBC;
  }
  return m;
}

bool finite(const tf::Block& b) {
  const double v[] = {b.target.x, b.target.y, b.target.z, b.target.a, b.target.b, b.target.c,
                      b.arc_center.x(), b.arc_center.y(), b.arc_center.z(), b.feed, b.dwell_s, b.spindle_rpm};
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return b.dwell_s >= 0.0 && b.feed >= 0.0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int mode = data[0];
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  tf::GcodeOptions options;
  options.max_lines_run = 100000;  // a loop that does not end is refused within the fuzzer's time limit
  if ((mode / 3) % 2) {
    options.tool_lengths = {{1, 50.0}, {2, 80.0}, {7, 12.5}};
    options.tool_length = 50.0;
    options.start_tool = 1;
    options.work_offsets = {{"G54", {100, 50, -30, 0, 0, 0}}, {"G59.3", {-1, 2, -3, 0, 0, 45}}};
  }
  options.block_delete = (mode / 6) % 2 == 0;
  if ((mode / 12) % 2) options.start = tf::Joints{1, 2, 3, 0, 0, 0};
  try {
    const tf::Program p = tf::parse_gcode(text, "fuzz.ngc", machine(mode % 3), options);
    for (const tf::Block& b : p.blocks)
      if (!finite(b) || b.line < 1) std::abort();
  } catch (const tf::InputError& e) {
    if (e.file() != "fuzz.ngc" || e.line() < 1) std::abort();
  }
  return 0;
}
