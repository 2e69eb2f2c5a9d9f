// tiltfield gcode: the G-code reader (RS274/NGC and ISO dialects as CAM systems and controllers write them)
// into a Program of motion blocks for the verifier.
//
// In: program text and the machine (its axes and TCP codes). Out: the motion blocks with their source
// lines, in the program's units converted to mm (G20 inches are scaled), degrees for rotaries, feeds in
// mm/min (G94) or 1/min (G93), and warnings for what is read but not simulated.
//
// Read: G0 G1 G2 G3 (I J K offsets or R, planes G17/G18/G19, G90.1/G91.1 arc-centre modes), G20/G21,
// G90/G91, G93/G94, F, S, T, M3/M4/M5/M6, M2/M30 (end), X Y Z A B C, comments "( )" and ";", N numbers,
// "%" lines, O program numbers and block delete "/". Tool-centre-point control is switched on by G43.4,
// M128 or the machine's tcp_on_code and off by G49, M129 or tcp_off_code; while it is on, X Y Z are the
// tool tip in the part frame. Codes that are read but not simulated (work offsets, coolant, canned-cycle
// cancel, ...) and unknown G/M codes become warnings "file:line: ..." in Program::warnings.
// Errors (InputError with file, line and word): a number that is not a number, an axis word the machine
// does not have, a letter that is no RS274 word, expressions/parameters, G93 motion without F, an arc
// whose radius or centre is inconsistent.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/program.hpp"

namespace tf {

struct GcodeOptions {
  // Lines starting with "/" are skipped (the controller's block-delete switch on). Default on.
  bool block_delete = true;
  // Axis values before the first block. When absent, each axis starts at the first value the program
  // gives it (the machine is taken to be there already), so the first positioning move sweeps nothing
  // it does not program.
  std::optional<Joints> start;
  // Arc centres |start-centre| and |end-centre| may differ by this much (mm) before it is an error.
  double arc_tolerance = 0.002;
};

// Parses program text. `file` only names the source in errors and warnings.
Program parse_gcode(std::string_view text, const std::string& file, const MachineSpec& machine,
                    const GcodeOptions& options = {});

// Reads and parses a G-code file. Throws InputError when the file cannot be read or is invalid.
Program read_gcode(const std::filesystem::path& file, const MachineSpec& machine, const GcodeOptions& options = {});

}  // namespace tf
