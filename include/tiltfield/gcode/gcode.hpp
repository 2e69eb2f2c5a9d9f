// tiltfield gcode: the G-code reader (RS274/NGC and ISO dialects as CAM systems and controllers write them)
// into a Program of motion blocks for the verifier, moving as LinuxCNC's interpreter moves.
//
// In: program text, the machine (its axes and TCP codes) and the scene's tool library and work offsets
// (GcodeOptions, gcode_options(scene)). Out: the motion blocks with their source lines, in mm (G20 inches
// are scaled), degrees for rotaries, feeds in mm/min (G94) or 1/min (G93), dwells in seconds, and warnings
// for what is read but not simulated.
//
// Read (docs/verifier.md, "G-code reader", has the details): G0 G1 G2 G3 (I J K or R, P turns, planes
// G17/G18/G19, G90.1/G91.1), G4 dwell, G20/G21, G90/G91, G93/G94, G53, G54-G59.3, G92 G92.1 G92.2 G92.3,
// G10 L2/L20, G28/G30, G43 H/G49 tool length offsets, canned cycles G73 G74 G81-G86 G89 with G98/G99 and
// G80, G33 and G33.1 (straight moves at K per spindle turn), G5 and G5.1 splines (as chords), F, S, T, M3/M4/M5, M6, M61, M0/M1, M7/M8/M9,
// M2/M30 (end), X Y Z A B C, polar coordinates @ ^, comments "( )" and ";", N numbers, "%" lines (reading
// stops at the second), O program numbers, block delete "/", parameters and expressions, O-word
// subroutines (in the program or in files, subroutine_dirs) and control flow, Fanuc M98/M99.
// Tool-centre-point control is switched on by G43.4, M128 or the machine's tcp_on_code and off by G49
// (G43.4 only), M129 or tcp_off_code; while it is on, X Y Z are the tool tip in the part frame.
// Codes that are read but not simulated and unknown G/M codes become warnings "file:line: ..." in
// Program::warnings. Errors (InputError with file, line and word): a number that is not an RS274 number
// (no exponent: "1e3" is the word E3), an axis word the machine does not have, a letter that is no RS274
// word, parameters, expressions and O-word subroutines or control flow, G93 motion without F, an arc whose
// radius or centre is inconsistent, a canned cycle LinuxCNC refuses, a tool the scene's library lacks.
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/scene.hpp"

namespace tf {

struct GcodeOptions {
  // Lines starting with "/" are skipped (the controller's block-delete switch on). Default off: they run,
  // as on LinuxCNC when it starts and under rs274.
  bool block_delete = false;
  // Axis values before the first block. When absent, each axis starts at the first value the program
  // gives it (the machine is taken to be there already), so the first positioning move sweeps nothing
  // it does not program; an axis a block needs before that (an incremental word, an arc's start) is at
  // program 0, where RS274/NGC starts.
  std::optional<Joints> start;
  // Arc centres |start-centre| and |end-centre| may differ by this much (mm; in G20 programs 2.54 times
  // as much), or by 0.1 % of the radius, before it is an error: LinuxCNC's tolerances (2 sqrt 2 x 0.01 mm,
  // 0.001 inch), so that arcs written to two decimals pass.
  double arc_tolerance = 0.0283;
  // Work offsets by code ("G54" ... "G59.3"): X Y Z mm, A B C deg, added to the programmed coordinates
  // (G54 is in force from the start, as on LinuxCNC). A code the program selects that is absent here
  // counts as zero, with a warning naming it. Default: none.
  std::map<std::string, WorkOffset> work_offsets;
  // Gauge length (mm) of each tool number of the scene's library. Empty: the scene's one tool
  // (`tool_length`) answers every T and H number.
  std::map<int, double> tool_lengths;
  double tool_length = 0.0;  // the scene's `tool`: gauge length, mm
  int start_tool = 0;        // the tool number in the spindle before the first M6 (Block::tool)
  // Directories searched in order for the file <name>.ngc (lower case) of a subroutine O<name> that a
  // program calls but does not define, as LinuxCNC searches PROGRAM_PREFIX and then SUBROUTINE_PATH;
  // read_gcode puts the program's own directory first. Default: none.
  std::vector<std::filesystem::path> subroutine_dirs;
  // Lines a program's loops and calls may run beyond the file's own count (each pass of a loop counts its
  // lines again) before the program is refused as one whose loop does not end. Default 10 000 000.
  long max_lines_run = 10'000'000;
};

// The options for programs run on `scene`: its work offsets, tool library and tool.
GcodeOptions gcode_options(const Scene& scene);

// Parses program text. `file` only names the source in errors and warnings.
Program parse_gcode(std::string_view text, const std::string& file, const MachineSpec& machine,
                    const GcodeOptions& options = {});

// Reads and parses a G-code file. Throws InputError when the file cannot be read or is invalid.
Program read_gcode(const std::filesystem::path& file, const MachineSpec& machine, const GcodeOptions& options = {});

}  // namespace tf
