// The planner's options: defaults derived from the tool and the feed, overrides from the scene.
#include <algorithm>
#include <cmath>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/tilt/plan.hpp"

namespace tf {

PlanOptions derive_plan_options(const Tool& tool, const PlannerBasics& basics, double feed_mm_min) {
  PlanOptions o;
  const double R = tool.radius();
  o.response_length_mm = 4.0 * R;
  o.influence_mm = R + basics.safety_distance;
  o.field_cell_mm = std::clamp(R / 2.0, 0.25, 4.0);
  o.sample_spacing_mm = std::clamp(R / 2.0, 0.25, 4.0);
  o.correction_window_mm = 2.0 * o.response_length_mm;
  o.link_gap_mm = default_link_gap(tool);
  o.min_gap_mm = o.influence_mm / 20.0;
  const double v = std::max(feed_mm_min, 1e-6) / 60.0;  // mm/s
  const double wn = v / o.response_length_mm;
  o.attraction = o.inertia * wn * wn;
  o.damping = 2.0 * o.damping_ratio * o.inertia * wn;
  return o;
}

namespace {
struct Reader {
  const nlohmann::json& j;
  const std::string& file;
  double number(const char* key, double fallback, bool positive) const {
    if (!j.contains(key)) return fallback;
    const auto& v = j.at(key);
    const std::string field = std::string("planner.") + key;
    if (!v.is_number()) throw InputError(file, 0, field, "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw InputError(file, 0, field, "must be finite");
    if (positive && !(x > 0)) throw InputError(file, 0, field, "must be positive");
    if (!positive && x < 0) throw InputError(file, 0, field, "must not be negative");
    return x;
  }
  // A count: a whole number from `least` to `most` (checked before the conversion, which is undefined
  // outside int's range).
  int count(const char* key, int fallback, int least, int most) const {
    if (!j.contains(key)) return fallback;
    const double x = number(key, fallback, false);
    const std::string field = std::string("planner.") + key;
    if (x != std::floor(x) || x < least || x > most)
      throw InputError(file, 0, field,
                       "must be a whole number from " + std::to_string(least) + " to " + std::to_string(most));
    return static_cast<int>(x);
  }
};
}  // namespace

PlanOptions parse_plan_options(const nlohmann::json& j, const std::string& file, const Tool& tool,
                               const PlannerBasics& basics, double feed_mm_min) {
  if (!j.is_object()) throw InputError(file, 0, "planner", "must be a JSON object");
  static const char* const kKeys[] = {
      // shared with the scene loader (PlannerBasics)
      "lead_deg", "tilt_deg", "safety_distance", "shank_clearance", "holder_clearance", "fixture_clearance",
      "max_tilt_deg", "comment",
      // the planner's own
      "method", "smooth", "response_length_mm", "damping_ratio", "inertia", "attraction", "damping", "influence_mm",
      "repulsion_gain", "min_gap_mm", "max_substep_deg", "field_cell_mm", "sample_spacing_mm",
      "correction_window_mm", "correction_margin_mm", "correction_iterations", "between_rows_tolerance_mm", "link_gap_mm",
      "end_dip_tolerance_mm",
      "pointwise_step_deg",
      "smooth_weight", "smooth_deviation_weight", "smooth_iterations"};
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* k : kKeys) known |= it.key() == k;
    if (!known) throw InputError(file, 0, "planner." + it.key(), "unknown key (see docs/planner.md)");
  }
  PlanOptions o = derive_plan_options(tool, basics, feed_mm_min);
  const Reader r{j, file};
  if (j.contains("method")) {
    const auto& m = j.at("method");
    if (!m.is_string()) throw InputError(file, 0, "planner.method", "must be \"dynamic\" or \"pointwise\"");
    const std::string s = m.get<std::string>();
    if (s == "dynamic") o.method = PlanMethod::Dynamic;
    else if (s == "pointwise") o.method = PlanMethod::Pointwise;
    else throw InputError(file, 0, "planner.method", "must be \"dynamic\" or \"pointwise\", not \"" + s + "\"");
  }
  if (j.contains("smooth")) {
    if (!j.at("smooth").is_boolean()) throw InputError(file, 0, "planner.smooth", "must be true or false");
    o.smooth = j.at("smooth").get<bool>();
  }
  // The derived gains follow the dynamics' own keys unless given explicitly.
  o.response_length_mm = r.number("response_length_mm", o.response_length_mm, true);
  o.damping_ratio = r.number("damping_ratio", o.damping_ratio, false);
  o.inertia = r.number("inertia", o.inertia, true);
  const double v = std::max(feed_mm_min, 1e-6) / 60.0;
  const double wn = v / o.response_length_mm;
  o.attraction = r.number("attraction", o.inertia * wn * wn, false);
  o.damping = r.number("damping", 2.0 * o.damping_ratio * o.inertia * wn, false);
  o.influence_mm = r.number("influence_mm", o.influence_mm, true);
  o.repulsion_gain = r.number("repulsion_gain", o.repulsion_gain, false);
  o.min_gap_mm = r.number("min_gap_mm", o.influence_mm / 20.0, true);
  if (o.min_gap_mm >= o.influence_mm)
    throw InputError(file, 0, "planner.min_gap_mm", "must be smaller than influence_mm");
  o.max_substep_deg = r.number("max_substep_deg", o.max_substep_deg, true);
  o.field_cell_mm = r.number("field_cell_mm", o.field_cell_mm, true);
  o.sample_spacing_mm = r.number("sample_spacing_mm", o.sample_spacing_mm, true);
  o.correction_window_mm = r.number("correction_window_mm", 2.0 * o.response_length_mm, false);
  o.correction_margin_mm = r.number("correction_margin_mm", o.correction_margin_mm, false);
  o.correction_iterations = r.count("correction_iterations", o.correction_iterations, 0, 100);
  o.between_rows_tolerance_mm = r.number("between_rows_tolerance_mm", o.between_rows_tolerance_mm, true);
  o.link_gap_mm = r.number("link_gap_mm", o.link_gap_mm, true);
  o.end_dip_tolerance_mm = r.number("end_dip_tolerance_mm", o.end_dip_tolerance_mm, true);
  o.pointwise_step_deg = r.number("pointwise_step_deg", o.pointwise_step_deg, true);
  o.smooth_weight = r.number("smooth_weight", o.smooth_weight, true);
  o.smooth_deviation_weight = r.number("smooth_deviation_weight", o.smooth_deviation_weight, true);
  o.smooth_iterations = r.count("smooth_iterations", o.smooth_iterations, 1, 100000);
  // Guard against settings that would make the job explode in memory or time.
  if (o.field_cell_mm < 0.05) throw InputError(file, 0, "planner.field_cell_mm", "must be at least 0.05 mm");
  if (o.sample_spacing_mm < 0.05) throw InputError(file, 0, "planner.sample_spacing_mm", "must be at least 0.05 mm");
  if (o.between_rows_tolerance_mm < 0.001)
    throw InputError(file, 0, "planner.between_rows_tolerance_mm", "must be at least 0.001 mm");
  // Above the dip a tilted end's contact keeps by design, or every tilted row would count as dipping
  // (found in review: 0.0005 mm set every lead to about 0).
  if (!(o.end_dip_tolerance_mm >= 1.5 * Tool::kContactDipMm))
    throw InputError(file, 0, "planner.end_dip_tolerance_mm",
                     "must be at least 0.0015 mm (a tilted end's contact lies 0.001 mm below the surface by design)");
  if (o.pointwise_step_deg > 10) throw InputError(file, 0, "planner.pointwise_step_deg", "at most 10 degrees");
  return o;
}

}  // namespace tf
