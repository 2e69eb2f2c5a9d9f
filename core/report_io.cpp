// Writing the verification report's files: VERIFY.json, blocks.csv and the engagement pairs.
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <ostream>

#include "tiltfield/core/io.hpp"
#include "tiltfield/core/report.hpp"

namespace tf {

namespace {
// Numbers through tf::fixed (never scientific notation) as raw JSON numbers.
nlohmann::ordered_json num(double v, int decimals = 6) { return nlohmann::ordered_json::parse(fixed(v, decimals)); }

nlohmann::ordered_json vec(const Eigen::Vector3d& v, int decimals) {
  return nlohmann::ordered_json::array({num(v.x(), decimals), num(v.y(), decimals), num(v.z(), decimals)});
}

nlohmann::ordered_json collision_json(const Collision& c) {
  nlohmann::ordered_json o;
  o["block"] = c.block;
  o["line"] = c.line;
  o["component"] = std::string(to_string(c.component));
  o["with"] = std::string(to_string(c.with));
  o["rapid"] = c.rapid;
  o["depth_mm"] = num(c.depth_mm, 4);
  o["tool"] = c.tool;
  if (c.has_poses) {
    o["start_tip"] = vec(c.start.tip, 4);
    o["start_axis"] = vec(c.start.axis, 6);
    o["end_tip"] = vec(c.end.tip, 4);
    o["end_axis"] = vec(c.end.axis, 6);
  }
  return o;
}

// Engagement and MRR over the feed blocks (per-block values are in blocks.csv).
nlohmann::ordered_json engagement_summary_json(const VerifyReport& r) {
  size_t engaged = 0, multi = 0;
  double max_angle = 0.0, max_area = 0.0, max_ap = 0.0, max_ae = 0.0, max_mrr = 0.0, cut_min = 0.0, cut_mm3 = 0.0;
  for (const BlockResult& b : r.per_block) {
    const Engagement& e = b.engagement;
    if (e.engaged()) ++engaged;
    if (e.max_pairs > 1) ++multi;
    max_angle = std::max(max_angle, e.angle_deg());
    max_area = std::max(max_area, e.area_mm2);
    max_ap = std::max(max_ap, e.axial_depth_mm);
    max_ae = std::max(max_ae, e.radial_width_mm);
    if (!b.rapid) max_mrr = std::max(max_mrr, b.mrr());
    if (!b.rapid && b.removed_mm3 > 0) {
      cut_min += b.minutes;
      cut_mm3 += b.removed_mm3;
    }
  }
  return {{"blocks_engaged", engaged},
          {"blocks_with_several_pairs", multi},
          {"max_angle_deg", num(max_angle, 3)},
          {"max_area_mm2", num(max_area, 4)},
          {"max_axial_depth_mm", num(max_ap, 4)},
          {"max_radial_width_mm", num(max_ae, 4)},
          {"max_mrr_mm3_min", num(max_mrr, 2)},
          {"mean_mrr_mm3_min", num(cut_min > 0 ? cut_mm3 / cut_min : 0.0, 2)},
          {"cutting_minutes", num(cut_min, 4)},
          {"seconds", num(r.engagement_seconds, 3)}};
}

std::string cell(double v, int decimals) { return std::isnan(v) ? std::string() : fixed(v, decimals); }
}  // namespace

void write_verify_json(const VerifyReport& r, const std::filesystem::path& file) {
  nlohmann::ordered_json j;
  j["blocks"] = r.blocks;
  j["removed_volume_mm3"] = num(r.removed_volume_mm3, 4);
  j["collisions"] = nlohmann::ordered_json::array();
  for (const Collision& c : r.collisions) j["collisions"].push_back(collision_json(c));
  j["gouges"] = nlohmann::ordered_json::array();
  for (const Gouge& g : r.gouges)
    j["gouges"].push_back({{"block", g.block}, {"line", g.line}, {"depth_mm", num(g.depth_mm, 4)}});
  if (r.design_checked) j["max_gouge_mm"] = num(r.max_gouge_mm, 4);
  else j["max_gouge_mm"] = nullptr;
  j["design_checked"] = r.design_checked;
  j["resolution_mm"] = num(r.resolution_mm, 6);
  j["rays"] = r.rays;
  j["seconds"] = num(r.seconds, 3);
  j["material_rays"] = r.material_rays;
  j["stock_volume_start_mm3"] = num(r.stock_volume_start_mm3, 4);
  j["stock_volume_end_mm3"] = num(r.stock_volume_end_mm3, 4);
  j["sweep_error_mm"] = num(r.sweep_error_mm, 6);
  j["holder_sweep_error_mm"] = num(r.holder_sweep_error_mm, 6);
  j["sweep_tolerance_mm"] = num(r.sweep_tolerance_mm, 6);
  j["holder_tolerance_mm"] = num(r.holder_tolerance_mm, 6);
  j["gouge_tolerance_mm"] = num(r.gouge_tolerance_mm, 6);
  j["collision_tolerance_mm"] = num(r.collision_tolerance_mm, 6);
  if (r.design_checked)
    j["excess"] = {{"samples", r.excess.samples},
                   {"mean_mm", num(r.excess.mean_mm, 4)},
                   {"p95_mm", num(r.excess.p95_mm, 4)},
                   {"max_mm", num(r.excess.max_mm, 4)}};
  else
    j["excess"] = nullptr;
  double program_minutes = 0.0;
  for (const BlockResult& b : r.per_block) program_minutes += b.minutes + b.dwell_minutes;
  j["program_minutes"] = num(program_minutes, 4);
  j["stopped_at_first_collision"] = r.stopped_early;
  j["memory_mb"] = num(r.memory_bytes / 1048576.0, 1);
  j["engagement"] = engagement_summary_json(r);
  if (r.stock_mesh) {
    const StockMeshStats& m = *r.stock_mesh;
    j["stock_mesh"] = {{"max_error_mm", num(m.max_error_mm, 6)}, {"vertices", m.vertices},
                       {"faces", m.faces},                        {"bytes", m.bytes},
                       {"full_vertices", m.full_vertices},        {"full_faces", m.full_faces},
                       {"mesh_seconds", num(m.mesh_seconds, 3)},  {"decimate_seconds", num(m.decimate_seconds, 3)}};
  }
  j["axis_limits"] = nlohmann::ordered_json::array();
  auto bound = [](double v) { return std::isfinite(v) ? num(v, 4) : nlohmann::ordered_json(); };  // null: none
  for (const AxisLimitExcess& e : r.axis_limits)
    j["axis_limits"].push_back({{"block", e.block}, {"line", e.line}, {"axis", std::string(1, e.axis)},
                                {"value", num(e.value, 4)}, {"min", bound(e.min)}, {"max", bound(e.max)}});
  j["warnings"] = r.warnings;
  const std::string text = j.dump(2);
  write_file_atomic(file, [&](std::ostream& out) { out << text << "\n"; });
}

void write_blocks_csv(const VerifyReport& report, const std::filesystem::path& file) {
  write_file_atomic(file, [&](std::ostream& out) {
    out << "block,line,removed_mm3,mrr_mm3_min,entry_deg,exit_deg,engaged_area_mm2,collision,axial_depth_mm,"
           "radial_width_mm,pairs,tool\n";
    for (const BlockResult& b : report.per_block) {
      const BlockRow r = block_row(b);
      out << r.block << ',' << r.line << ',' << cell(r.removed_mm3, 4) << ',' << cell(r.mrr_mm3_min, 2) << ','
          << cell(r.entry_deg, 3) << ',' << cell(r.exit_deg, 3) << ',' << cell(r.engaged_area_mm2, 4) << ','
          << (r.collision ? 1 : 0) << ',' << cell(r.axial_depth_mm, 4) << ',' << cell(r.radial_width_mm, 4) << ','
          << (r.pairs >= 0 ? std::to_string(r.pairs) : std::string()) << ',' << r.tool << "\n";
    }
  });
}

void write_engagement_csv(const VerifyReport& r, const std::filesystem::path& file) {
  write_file_atomic(file, [&](std::ostream& out) {
    out << "block,line,height_mm,entry_deg,exit_deg\n";
    for (const BlockResult& b : r.per_block)
      for (const EngagementPair& p : b.engagement.pairs)
        out << b.block << ',' << b.line << ',' << fixed(p.height_mm, 4) << ',' << fixed(p.entry_deg, 3) << ','
            << fixed(p.exit_deg, 3) << "\n";
  });
}

}  // namespace tf
