// `tiltfield offset`: offset-profile trajectory for copy milling or ECM (docs/offset.md).
#include <algorithm>
#include <cmath>
#include <memory>
#include <cctype>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/offset/offset.hpp"
#include "tiltfield/offset/offset_program.hpp"
#include "tiltfield/offset/offset_section.hpp"

namespace tf::cli {
namespace {
struct OffsetCliOptions {
  std::string profile, gap_law, side = "inside", corner = "round", target = "milling", out, svg, mesh, plane = "z=0",
      profile_out;
  double gap = 0, gap_blend = 0, lead = 2.0, fit_tolerance = 0.01;
  int loop = 1;
  offset::MillingOptions milling;
  offset::EcmOptions ecm;
};

constexpr double kMinRetractEveryMm = 0.1;

// A value as the message shows it (fixed() refuses what is not finite).
std::string shown(double v) { return std::isfinite(v) ? fixed(v, 9) : std::to_string(v); }

// Positive, and not so small that the program's 8 decimals write it as 0 (F0 is refused by the
// controller; S0 and Q0 run with the spindle or the generator off).
void check_positive(double v, const char* field) {
  if (!(v > 0) || !std::isfinite(v)) throw InputError("", 0, field, "must be a positive number, got " + shown(v));
  if (v < 5e-9) throw InputError("", 0, field, "is " + shown(v) + ": below 0.00000001, written as 0 by the program's 8 decimals");
}
void check_not_negative(double v, const char* field) {
  if (!(v >= 0) || !std::isfinite(v)) throw InputError("", 0, field, "must be a number >= 0, got " + shown(v));
}
// A value beyond a million (mm, mm/min, rpm, V, s) is a typo: a gap of 1e300 ended as a failed job naming
// no option, a --z-safe of 1e70 was written as a 63-digit number.
void check_length(double v, const char* field, const char* unit = "mm") {
  if (!(std::abs(v) > offset::kMaxLengthMm)) return;
  std::ostringstream msg;
  msg << "must be within +-" << fixed(offset::kMaxLengthMm, 0) << " " << unit << ", got " << v;
  throw InputError("", 0, field, msg.str());
}
void check_finite(double v, const char* field) {
  if (!std::isfinite(v)) throw InputError("", 0, field, "must be a finite number, got " + shown(v));
}

// Values that give a program the controller refuses (a zero feed, a negative dwell) or one that drives the
// tool into the part (rapids below the cutting plane, a "retract" downward) are refused before any work.
void check_program_options(const offset::MillingOptions& m, const offset::EcmOptions& e) {
  check_positive(m.feed, "feed");
  check_positive(m.plunge_feed, "plunge-feed");
  check_positive(m.spindle_rpm, "spindle");
  check_finite(m.z_cut, "z-cut");
  check_finite(m.z_safe, "z-safe");
  if (!(m.z_safe > m.z_cut)) throw InputError("", 0, "z-safe", "must lie above --z-cut (" + shown(m.z_cut) + ")");
  check_positive(e.feed, "ecm-feed");
  check_positive(e.voltage, "ecm-voltage");
  check_not_negative(e.flush_dwell_s, "ecm-flush");
  check_not_negative(e.start_dwell_s, "ecm-dwell");
  check_not_negative(e.end_dwell_s, "ecm-end-dwell");
  check_not_negative(e.retract_every_mm, "ecm-retract-every");
  // A retract every micrometre wrote a 1.25 GB program (black-box testing).
  if (e.retract_every_mm > 0 && e.retract_every_mm < kMinRetractEveryMm)
    throw InputError("", 0, "ecm-retract-every",
                     "is " + shown(e.retract_every_mm) + " mm: 0 (never) or at least " + fixed(kMinRetractEveryMm, 1) + " mm");
  check_positive(e.retract_height, "ecm-retract-height");
  check_finite(e.z_work, "ecm-z-work");
  check_finite(e.z_safe, "ecm-z-safe");
  if (!(e.z_safe > e.z_work))
    throw InputError("", 0, "ecm-z-safe", "must lie above --ecm-z-work (" + shown(e.z_work) + ")");
  const std::pair<double, const char*> lengths[] = {{m.z_cut, "z-cut"}, {m.z_safe, "z-safe"}, {e.retract_every_mm, "ecm-retract-every"},
                                                    {e.retract_height, "ecm-retract-height"}, {e.z_work, "ecm-z-work"}, {e.z_safe, "ecm-z-safe"}};
  for (const auto& [v, field] : lengths) check_length(v, field);
  for (const auto& [v, field] : {std::pair{m.feed, "feed"}, std::pair{m.plunge_feed, "plunge-feed"}, std::pair{e.feed, "ecm-feed"}})
    check_length(v, field, "mm/min");
  check_length(m.spindle_rpm, "spindle", "rpm");
  check_length(e.voltage, "ecm-voltage", "V");
  for (const auto& [v, field] : {std::pair{e.flush_dwell_s, "ecm-flush"}, std::pair{e.start_dwell_s, "ecm-dwell"}, std::pair{e.end_dwell_s, "ecm-end-dwell"}})
    check_length(v, field, "s");
}
// An M code for the electrolyte, as LinuxCNC reads it standalone: M7, M8, M9 (coolant) or a user M code
// M100-M199 (a program file of that name on the controller). The others stop or end the program, drive
// the spindle, change the tool, need P, Q or E words (M61-M68: M64 and M65 also drive the generator's own
// output), call or return (M98, M99) or are unknown (rs274 refuses them); they were accepted (black-box
// testing). Lower case is read as upper case.
std::string checked_mcode(const std::string& typed, const char* field) {
  std::string code;
  for (unsigned char c : typed) code += static_cast<char>(std::toupper(c));
  const bool digits = code.size() >= 2 && code.size() <= 4 &&
                      std::all_of(code.begin() + 1, code.end(), [](unsigned char c) { return std::isdigit(c); });
  if (code.empty() || code[0] != 'M' || !digits) {
    std::string shown_code;  // one line, whatever was typed
    for (unsigned char c : typed) shown_code += std::isprint(c) ? std::string(1, char(c)) : "?";
    throw InputError("", 0, field, "expected an M-code like M8, got '" + shown_code + "'");
  }
  const int m = std::stoi(code.substr(1));
  if (m == 7 || m == 8 || m == 9 || (m >= 100 && m <= 199)) return "M" + std::to_string(m);
  throw InputError("", 0, field,
                   code + " is not an electrolyte switch LinuxCNC runs on its own (it stops or ends the program, drives the spindle or "
                          "an output, needs other words, or is unknown); use M7, M8, M9 or a user M code M100-M199");
}

// The coolant codes' meaning: M9 stops coolant and M7 and M8 start it, so M9 cannot switch the electrolyte
// on nor M7 or M8 off, and one code cannot do both (black-box testing: "on M9, off M8" machined with the
// electrolyte off and left it running at the end).
void check_electrolyte_pair(const std::string& on, const std::string& off) {
  if (on == "M9") throw InputError("", 0, "ecm-electrolyte-on", "M9 switches coolant off: it cannot switch the electrolyte on");
  if (off == "M7" || off == "M8")
    throw InputError("", 0, "ecm-electrolyte-off", off + " switches coolant on: the electrolyte would not be switched off (M9 does)");
  if (on == off)
    throw InputError("", 0, "ecm-electrolyte-off", "is " + off + ", the code that switches the electrolyte on");
}

// Options of the other target are refused rather than ignored (black-box testing: --ecm-voltage with the
// milling target, --feed with ECM, had been dropped without a word).
void check_target_options(const CLI::App& cmd, const std::string& target) {
  static const char* const milling[] = {"--feed", "--plunge-feed", "--spindle", "--z-safe", "--z-cut"};
  static const char* const ecm[] = {"--ecm-feed", "--ecm-voltage", "--ecm-electrolyte-on", "--ecm-electrolyte-off",
                                    "--ecm-flush", "--ecm-dwell", "--ecm-end-dwell", "--ecm-retract-every",
                                    "--ecm-retract-height", "--ecm-z-work", "--ecm-z-safe"};
  const bool is_ecm = target == "ecm";
  for (const char* name : is_ecm ? std::vector<const char*>(std::begin(milling), std::end(milling))
                                 : std::vector<const char*>(std::begin(ecm), std::end(ecm)))
    if (cmd.count(name) > 0)
      throw InputError("", 0, name + 2, std::string("applies to --target ") + (is_ecm ? "milling" : "ecm") + ", not " + target);
}

// The smallest distance between a section loop (a polygon) and the contours, mm. The contours' arcs are
// sampled (33 points a segment) against the loop's edges, and the loop's points against the segments.
double loop_distance(const offset::SectionLoop& loop, const offset::OffsetResult& result) {
  double d = INFINITY;
  const size_t n = loop.points.size();
  for (const auto& contour : result.contours)
    for (const offset::Segment& s : contour)
      for (size_t i = 0; i < n; ++i) {
        const offset::Segment edge = offset::make_line(loop.points[i], loop.points[(i + 1) % n]);
        if (!offset::intersect(s, edge, 1e-9).empty()) return 0.0;
        d = std::min(d, offset::distance(s, edge.a));
        for (int k = 0; k <= 32; ++k) d = std::min(d, offset::distance(edge, offset::point_at(s, k / 32.0)));
      }
  return d;
}

// A mesh section's other loops are left out of the profile (one loop a run, --loop picks it): where the path
// comes closer to one than the smallest gap, it is refused, naming the loop; otherwise a warning says what
// was left out. A tube's bore had been dropped without a word and the inside path ran 1 mm from it at a gap
// of 2 (black-box testing).
void check_left_out_loops(const std::vector<offset::SectionLoop>& left_out, const offset::OffsetResult& result,
                          const offset::GapLaw& law, const OffsetCliOptions& o) {
  if (left_out.empty()) return;
  const double min_gap = *std::min_element(law.gap.begin(), law.gap.end());
  for (size_t k = 0; k < left_out.size(); ++k) {
    const offset::SectionLoop& l = left_out[k];
    const double d = loop_distance(l, result);
    if (d >= min_gap) continue;
    throw JobError("the " + o.side + " path comes " + fixed(d, 3) + " mm from a loop of the section left out (loop " +
                   std::to_string(k + 2 > static_cast<size_t>(o.loop) ? k + 2 : k + 1) + " by area, " + fixed(l.area, 3) + " mm2, " +
                   (l.inside ? "inside" : "outside") + " the profile, at (" + fixed(l.points.front().x(), 3) + ", " +
                   fixed(l.points.front().y(), 3) + ")): the offset takes one loop; a section with holes or near islands is not supported");
  }
  if (global_options().quiet) return;
  std::cerr << "warning: the section has " << left_out.size() << " other loop(s), left out (the largest " << fixed(left_out[0].area, 3)
            << " mm2 " << (left_out[0].inside ? "inside" : "outside") << " the profile); the path keeps the gap from them\n";
}

void run_offset(OffsetCliOptions o) {
  check_outputs_apart({{"-o", o.out}, {"--svg", o.svg}, {"--profile-out", o.profile_out}}, {o.profile, o.gap_law, o.mesh});
  check_positive(o.gap, "gap");
  check_program_options(o.milling, o.ecm);
  o.ecm.electrolyte_on = checked_mcode(o.ecm.electrolyte_on, "ecm-electrolyte-on");
  o.ecm.electrolyte_off = checked_mcode(o.ecm.electrolyte_off, "ecm-electrolyte-off");
  check_electrolyte_pair(o.ecm.electrolyte_on, o.ecm.electrolyte_off);
  check_not_negative(o.lead, "lead");
  check_not_negative(o.gap_blend, "gap-blend");
  check_length(o.gap, "gap");
  check_length(o.gap_blend, "gap-blend");
  check_length(o.lead, "lead");
  if (o.gap_blend > 0 && o.gap_law.empty()) throw InputError("", 0, "gap-blend", "blends the knots of a --gap-law; none is given");

  offset::Profile profile;
  std::vector<offset::SectionLoop> left_out;  // the section's other loops
  if (!o.mesh.empty()) {
    if (!o.profile.empty()) throw InputError("", 0, "PROFILE", "give either a PROFILE or --mesh, not both");
    check_positive(o.fit_tolerance, "fit-tolerance");
    const double z = offset::parse_plane(o.plane);
    offset::SectionOptions so;
    so.tolerance = o.fit_tolerance;
    so.loop = o.loop;
    profile = offset::profile_from_mesh(o.mesh, z, so, &left_out);
  } else {
    if (o.profile.empty()) throw InputError("", 0, "PROFILE", "a PROFILE file or --mesh PART --plane z=H is required");
    if (o.loop != 1) throw InputError("", 0, "loop", "picks a loop of a --mesh section; none is given");
    profile = offset::read_profile(o.profile);
  }

  offset::GapLaw law = offset::constant_gap(o.gap);
  if (!o.gap_law.empty()) {
    law = offset::read_gap_law(o.gap_law);
    law.blend = o.gap_blend;
  }
  offset::OffsetOptions oo;
  oo.side = o.side == "outside" ? offset::Side::Outside : offset::Side::Inside;
  oo.corner = o.corner == "sharp" ? offset::Corner::Sharp : offset::Corner::Round;
  const auto result = offset::offset_profile(profile, law, oo);
  if (result.contours.empty() && result.unresolved > 0)
    throw JobError("the " + o.side + " offset of this gap law could not be closed: near (" + fixed(result.unresolved_at.x(), 3) +
                   ", " + fixed(result.unresolved_at.y(), 3) + ") its boundary runs where the closest profile element changes "
                   "and the law differs across it, which the method does not build (docs/offset.md); a gentler law there works");
  if (result.contours.empty())
    throw JobError("the " + o.side + " offset at this gap is empty (the gap is too large for the profile)");
  if (result.unresolved > 0 && !global_options().quiet)
    std::cerr << "warning: near (" << fixed(result.unresolved_at.x(), 3) << ", " << fixed(result.unresolved_at.y(), 3)
              << ") the law's offset leaves a piece out where the closest profile element changes: the contours may miss "
                 "part of the region (never closer than the law)\n";
  check_left_out_loops(left_out, result, law, o);
  const auto field = offset::make_clearance_field(profile, law);
  const auto contours = offset::plan_leads(result, *field, o.lead);

  offset::ProgramInfo info;
  info.profile_file = o.mesh.empty() ? o.profile : o.mesh + " at " + o.plane;
  info.gap_text = o.gap_law.empty() ? fixed(o.gap, 6) + " mm" : "law " + o.gap_law;
  info.side = o.side;
  info.corner = o.corner;
  std::ostringstream program, svg;
  if (o.target == "ecm") {
    offset::EcmOptions ecm = o.ecm;
    ecm.gap = o.gap;
    ecm.voltage_follows_gap = ecm.voltage_follows_gap && !o.gap_law.empty();
    offset::write_ecm_program(program, contours, info, ecm);
  } else {
    offset::write_milling_program(program, contours, info, o.milling);
  }
  if (!o.svg.empty()) offset::write_svg(svg, profile, contours);
  // Everything is computed before the first file is written, so bad input leaves no output behind.
  write_file_atomic(o.out, [&](std::ostream& f) { f << program.str(); });
  if (!o.svg.empty()) write_file_atomic(o.svg, [&](std::ostream& f) { f << svg.str(); });
  if (!o.profile_out.empty())
    write_file_atomic(o.profile_out, [&](std::ostream& f) { f << offset::format_profile(profile); });
}
}  // namespace

void add_offset_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("offset", "offset-profile trajectory for copy milling or ECM");
  auto o = std::make_shared<OffsetCliOptions>();
  cmd->add_option("PROFILE", o->profile, "profile text file (START x y, then R DX DY [LONG] a line)");
  cmd->add_option("-d,--gap", o->gap, "gap (offset distance, tool radius or ECM gap), mm")->required()->check(number_at_least(0, true));
  cmd->add_option("--gap-law", o->gap_law, "CSV s,gap: gap along the profile's arc length (overrides -d's value)");
  cmd->add_option("--gap-blend", o->gap_blend, "half-width of the parabolic blend at gap-law knots, mm (0: linear)");
  cmd->add_option("--side", o->side, "inside or outside the figure")->check(CLI::IsMember({"inside", "outside"}));
  cmd->add_option("--corner", o->corner, "round (constant gap) or sharp (intersection joins)")
      ->check(CLI::IsMember({"round", "sharp"}));
  cmd->add_option("--target", o->target, "milling or ecm")->check(CLI::IsMember({"milling", "ecm"}));
  cmd->add_option("-o,--output", o->out, "NC program (.ngc)")->required()->check(output_file());
  cmd->add_option("--svg", o->svg, "SVG plot of profile and trajectory")->check(output_file());
  cmd->add_option("--mesh", o->mesh, "slice this part mesh instead of reading a PROFILE");
  cmd->add_option("--plane", o->plane, "section plane for --mesh, z=H")->capture_default_str();
  cmd->add_option("--fit-tolerance", o->fit_tolerance, "--mesh: line/arc fitting tolerance, mm")->default_val(0.01);
  cmd->add_option("--loop", o->loop, "--mesh: which loop of the section, by area (1: the largest)")
      ->default_val(1)
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--profile-out", o->profile_out, "also write the profile used (e.g. fitted from --mesh)")->check(output_file());
  cmd->add_option("--lead", o->lead, "lead-in/out arc radius, mm")->default_val(2.0);
  cmd->add_option("--feed", o->milling.feed, "milling feed, mm/min")->default_val(600);
  cmd->add_option("--plunge-feed", o->milling.plunge_feed, "milling plunge feed, mm/min")->default_val(200);
  cmd->add_option("--spindle", o->milling.spindle_rpm, "spindle speed, rpm")->default_val(8000);
  cmd->add_option("--z-safe", o->milling.z_safe, "clearance height, mm")->default_val(5);
  cmd->add_option("--z-cut", o->milling.z_cut, "milling depth (section plane height), mm")->default_val(0);
  cmd->add_option("--ecm-feed", o->ecm.feed, "ECM electrode feed, mm/min")->default_val(20);
  cmd->add_option("--ecm-voltage", o->ecm.voltage, "ECM voltage at the nominal gap, V")->default_val(12);
  cmd->add_option("--ecm-electrolyte-on", o->ecm.electrolyte_on, "M-code: electrolyte on")->default_val("M8");
  cmd->add_option("--ecm-electrolyte-off", o->ecm.electrolyte_off, "M-code: electrolyte off")->default_val("M9");
  cmd->add_option("--ecm-flush", o->ecm.flush_dwell_s, "electrolyte flush before voltage, s")->default_val(2);
  cmd->add_option("--ecm-dwell", o->ecm.start_dwell_s, "dwell with voltage on before moving, s")->default_val(1);
  cmd->add_option("--ecm-end-dwell", o->ecm.end_dwell_s, "dwell after voltage off, s")->default_val(1);
  cmd->add_option("--ecm-retract-every", o->ecm.retract_every_mm, "retract and flush every so many mm (0: never)")
      ->default_val(0);
  cmd->add_option("--ecm-retract-height", o->ecm.retract_height, "retract lift, mm")->default_val(2);
  cmd->add_option("--ecm-z-work", o->ecm.z_work, "ECM working height, mm")->default_val(0);
  cmd->add_option("--ecm-z-safe", o->ecm.z_safe, "ECM clearance height, mm")->default_val(10);
  for (const char* name : {"--gap-blend", "--fit-tolerance", "--lead", "--feed", "--plunge-feed", "--spindle", "--z-safe",
                           "--z-cut", "--ecm-feed", "--ecm-voltage", "--ecm-flush", "--ecm-dwell", "--ecm-end-dwell",
                           "--ecm-retract-every", "--ecm-retract-height", "--ecm-z-work", "--ecm-z-safe"})
    cmd->get_option(name)->check(finite_number());
  cmd->callback([o, cmd] {
    check_target_options(*cmd, o->target);
    run_offset(*o);
  });
}

}  // namespace tf::cli
