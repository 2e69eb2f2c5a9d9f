// tiltfield offset: lead moves and the NC programs (copy milling, ECM) and SVG plot of an offset result.
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include "tiltfield/offset/offset.hpp"

namespace tf::offset {

// A contour ready to run: the closed path (rotated to start in the middle of its longest segment) and the
// quarter-circle lead-in (ending tangentially at the start) and lead-out (leaving tangentially), both on
// the free side of the path. has_leads is false where no lead of at least 1/64 of the asked radius keeps
// its clearance; the tool then plunges onto the path's start.
struct RunContour {
  std::vector<Segment> path;
  Segment lead_in, lead_out;
  bool has_leads = false;
};

// lead_radius: asked radius of the lead arcs, mm (halved until the arcs keep a clearance >= 0).
std::vector<RunContour> plan_leads(const OffsetResult& result, const ClearanceField& field, double lead_radius);

// What the program headers report.
struct ProgramInfo {
  std::string profile_file;
  std::string gap_text;  // e.g. "0.5 mm" or "law gap.csv"
  std::string side = "inside";
  std::string corner = "round";
};

struct MillingOptions {
  double feed = 600;         // cutting feed, mm/min
  double plunge_feed = 200;  // Z feed down to the cutting depth, mm/min
  double spindle_rpm = 8000;
  double z_safe = 5;         // clearance height for rapid moves, mm
  double z_cut = 0;          // cutting depth of the section plane, mm
};

struct EcmOptions {
  double feed = 20;           // electrode feed along the path, mm/min
  double approach_feed = 100; // Z feed to the working height, mm/min
  double gap = 0.3;           // nominal electrode-workpiece gap, mm (the -d value)
  double voltage = 12;        // generator voltage at the nominal gap, V (analog output 0 via M68/M67)
  bool voltage_follows_gap = true;  // with a gap law: U = voltage * gap / nominal gap (constant field)
  std::string electrolyte_on = "M8", electrolyte_off = "M9";
  int generator_output = 0;   // digital output switched by M64/M65 P<n> (generator on/off)
  int voltage_channel = 0;    // analog output E<n> carrying the voltage set-point
  double flush_dwell_s = 2;   // electrolyte flow before the voltage is switched on, s
  double start_dwell_s = 1;   // dwell with voltage on before moving, s
  double end_dwell_s = 1;     // dwell after the generator is off, before the electrolyte stops, s
  double retract_every_mm = 0;  // > 0: every so many mm of path, voltage off, retract, flush, return
  double retract_height = 2;  // retract lift above the working height, mm
  double z_safe = 10;         // clearance height, mm
  double z_work = 0;          // working height of the electrode tip, mm
};

// Writes the milling program (G21 G17 G90, G1/G2/G3 with incremental I J, tool-centre path).
void write_milling_program(std::ostream& out, const std::vector<RunContour>& contours, const ProgramInfo& info,
                           const MillingOptions& options);
// Writes the ECM program: the same path, electrolyte on/off M-codes, voltage set-point, generator on/off,
// dwells and retracts (see docs/offset.md).
void write_ecm_program(std::ostream& out, const std::vector<RunContour>& contours, const ProgramInfo& info,
                       const EcmOptions& options);
// An SVG of the profile (black), the trajectory (blue; sharp-join extensions red) and the leads (grey).
void write_svg(std::ostream& out, const Profile& profile, const std::vector<RunContour>& contours);

}  // namespace tf::offset
