// Reading the verification report's files back: VERIFY.json and blocks.csv.
#include <cmath>
#include <limits>
#include <optional>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/internal/json_fields.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/report.hpp"

namespace tf {

namespace {
using nlohmann::json;
namespace jf = json_fields;

int whole_number(const json& o, const char* key, const std::string& file, const std::string& prefix) {
  const std::string field = jf::join(prefix, key);
  if (!o.contains(key)) throw InputError(file, 0, field, "missing");
  if (!o[key].is_number_integer()) throw InputError(file, 0, field, "must be a whole number");
  return o[key].get<int>();
}

template <class Enum>
Enum named(const json& o, const char* key, std::initializer_list<Enum> values, const std::string& file,
           const std::string& prefix) {
  const std::string field = jf::join(prefix, key);
  if (!o.contains(key)) throw InputError(file, 0, field, "missing");
  const std::string text = jf::string(o[key], file, field);
  std::string allowed;
  for (Enum v : values) {
    if (text == to_string(v)) return v;
    allowed += (allowed.empty() ? "" : ", ") + std::string(to_string(v));
  }
  throw InputError(file, 0, field, "'" + text + "' is not one of " + allowed);
}

bool boolean(const json& o, const char* key, const std::string& file, const std::string& prefix) {
  const std::string field = jf::join(prefix, key);
  if (!o.contains(key)) throw InputError(file, 0, field, "missing");
  if (!o[key].is_boolean()) throw InputError(file, 0, field, "must be true or false");
  return o[key].get<bool>();
}

Eigen::Vector3d unit_vec3(const json& o, const char* key, const std::string& file, const std::string& prefix) {
  const std::string field = jf::join(prefix, key);
  const Eigen::Vector3d v = jf::vec3(o[key], file, field);
  if (std::abs(v.norm() - 1.0) > 1e-3) throw InputError(file, 0, field, "not a unit vector");
  return v.normalized();
}

// The block's tool poses: all four fields or none (has_poses false).
void read_poses(const json& o, const std::string& file, const std::string& prefix, Collision& c) {
  const char* keys[] = {"start_tip", "start_axis", "end_tip", "end_axis"};
  int present = 0;
  for (const char* k : keys) present += o.contains(k) ? 1 : 0;
  c.has_poses = present == 4;
  if (present == 0) return;
  for (const char* k : keys)
    if (!o.contains(k)) throw InputError(file, 0, jf::join(prefix, k), "missing (the other tool poses are given)");
  c.start.tip = jf::vec3(o["start_tip"], file, jf::join(prefix, "start_tip"));
  c.start.axis = unit_vec3(o, "start_axis", file, prefix);
  c.end.tip = jf::vec3(o["end_tip"], file, jf::join(prefix, "end_tip"));
  c.end.axis = unit_vec3(o, "end_axis", file, prefix);
}

Collision read_collision(const json& o, const std::string& file, const std::string& prefix) {
  jf::require_object(o, file, prefix);
  Collision c;
  c.block = whole_number(o, "block", file, prefix);
  c.line = whole_number(o, "line", file, prefix);
  if (c.block < 0) throw InputError(file, 0, jf::join(prefix, "block"), "must be a whole number >= 0");
  if (c.line < 0) throw InputError(file, 0, jf::join(prefix, "line"), "must be a whole number >= 0");
  c.component = named(o, "component", {ToolComponent::Ball, ToolComponent::Flute, ToolComponent::Shank, ToolComponent::Holder},
                      file, prefix);
  c.with = named(o, "with", {HitWith::Stock, HitWith::Check, HitWith::Fixture}, file, prefix);
  c.rapid = boolean(o, "rapid", file, prefix);
  c.depth_mm = jf::required_number(o, "depth_mm", file, prefix);
  if (c.depth_mm < 0) throw InputError(file, 0, jf::join(prefix, "depth_mm"), "must be >= 0 (a depth into the obstacle)");
  if (o.contains("tool")) c.tool = whole_number(o, "tool", file, prefix);
  if (c.tool < 0) throw InputError(file, 0, jf::join(prefix, "tool"), "must be a whole number >= 0");
  read_poses(o, file, prefix, c);
  return c;
}

Gouge read_gouge(const json& o, const std::string& file, const std::string& prefix) {
  jf::require_object(o, file, prefix);
  const Gouge g{whole_number(o, "block", file, prefix), whole_number(o, "line", file, prefix),
                jf::required_number(o, "depth_mm", file, prefix)};
  if (g.depth_mm < 0) throw InputError(file, 0, jf::join(prefix, "depth_mm"), "must be >= 0 (a depth below the design)");
  return g;
}

const json* array_field(const json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) return nullptr;
  if (!j[key].is_array()) throw InputError(file, 0, key, "must be an array");
  return &j[key];
}

size_t count_or_zero(const json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) return 0;
  if (!j[key].is_number_unsigned()) throw InputError(file, 0, key, "must be a whole number >= 0");
  return j[key].get<size_t>();
}

void read_figures(const json& j, const std::string& file, VerifyReport& r) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.blocks = j.contains("blocks") ? whole_number(j, "blocks", file, "") : 0;
  r.removed_volume_mm3 = jf::number_or(j, "removed_volume_mm3", nan, file, "");
  if (j.contains("design_checked")) r.design_checked = boolean(j, "design_checked", file, "");
  r.max_gouge_mm = j.contains("max_gouge_mm") && j["max_gouge_mm"].is_null() ? nan : jf::number_or(j, "max_gouge_mm", nan, file, "");
  r.resolution_mm = jf::number_or(j, "resolution_mm", nan, file, "");
  r.seconds = jf::number_or(j, "seconds", nan, file, "");
  r.rays = count_or_zero(j, "rays", file);
  r.material_rays = count_or_zero(j, "material_rays", file);
  r.stock_volume_start_mm3 = jf::number_or(j, "stock_volume_start_mm3", nan, file, "");
  r.stock_volume_end_mm3 = jf::number_or(j, "stock_volume_end_mm3", nan, file, "");
  r.sweep_error_mm = jf::number_or(j, "sweep_error_mm", nan, file, "");
  r.holder_sweep_error_mm = jf::number_or(j, "holder_sweep_error_mm", nan, file, "");
  r.sweep_tolerance_mm = jf::number_or(j, "sweep_tolerance_mm", nan, file, "");
  r.holder_tolerance_mm = jf::number_or(j, "holder_tolerance_mm", nan, file, "");
  r.gouge_tolerance_mm = jf::number_or(j, "gouge_tolerance_mm", nan, file, "");
  r.collision_tolerance_mm = jf::number_or(j, "collision_tolerance_mm", nan, file, "");
  r.memory_bytes = static_cast<size_t>(jf::number_or(j, "memory_mb", 0.0, file, "") * 1048576.0);
  if (j.contains("stopped_at_first_collision")) r.stopped_early = boolean(j, "stopped_at_first_collision", file, "");
  if (j.contains("excess") && !j["excess"].is_null()) {
    const json& e = j["excess"];
    jf::require_object(e, file, "excess");
    r.excess.samples = count_or_zero(e, "samples", file);
    r.excess.mean_mm = jf::number_or(e, "mean_mm", 0.0, file, "excess");
    r.excess.p95_mm = jf::number_or(e, "p95_mm", 0.0, file, "excess");
    r.excess.max_mm = jf::number_or(e, "max_mm", 0.0, file, "excess");
  }
  if (j.contains("stock_mesh")) {
    const json& m = j["stock_mesh"];
    jf::require_object(m, file, "stock_mesh");
    StockMeshStats s;
    s.max_error_mm = jf::number_or(m, "max_error_mm", 0.0, file, "stock_mesh");
    if (!(s.max_error_mm >= 0.0)) throw InputError(file, 0, "stock_mesh.max_error_mm", "must be a number of mm >= 0");
    auto count = [&](const char* key) {
      if (m.contains(key) && !m[key].is_number_unsigned())
        throw InputError(file, 0, std::string("stock_mesh.") + key, "must be a whole number >= 0");
      return count_or_zero(m, key, file);
    };
    s.vertices = count("vertices");
    s.faces = count("faces");
    s.bytes = count("bytes");
    s.full_vertices = count("full_vertices");
    s.full_faces = count("full_faces");
    s.mesh_seconds = jf::number_or(m, "mesh_seconds", 0.0, file, "stock_mesh");
    s.decimate_seconds = jf::number_or(m, "decimate_seconds", 0.0, file, "stock_mesh");
    r.stock_mesh = s;
  }
  r.engagement_seconds = j.contains("engagement") && j["engagement"].is_object()
                             ? jf::number_or(j["engagement"], "seconds", 0.0, file, "engagement")
                             : 0.0;
}
}  // namespace

VerifyReport read_verify_json(const std::filesystem::path& path) {
  const std::string file = path.string();
  const json j = jf::parse_file(file, "verification report");
  jf::require_object(j, file, "");
  // Every report `verify` writes lists its collisions, if only as []: a file without them is another one.
  if (!j.contains("collisions")) throw InputError(file, 0, "collisions", "missing: not a verification report (VERIFY.json)");
  VerifyReport r;
  read_figures(j, file, r);
  if (const json* cs = array_field(j, "collisions", file))
    for (size_t i = 0; i < cs->size(); ++i)
      r.collisions.push_back(read_collision((*cs)[i], file, "collisions[" + std::to_string(i) + "]"));
  if (const json* gs = array_field(j, "gouges", file))
    for (size_t i = 0; i < gs->size(); ++i)
      r.gouges.push_back(read_gouge((*gs)[i], file, "gouges[" + std::to_string(i) + "]"));
  if (const json* ws = array_field(j, "warnings", file))
    for (size_t i = 0; i < ws->size(); ++i)
      r.warnings.push_back(jf::string((*ws)[i], file, "warnings[" + std::to_string(i) + "]"));
  return r;
}

std::vector<BlockRow> read_blocks_csv(const std::filesystem::path& path) {
  const CsvTable t = read_csv(path);
  const std::string file = path.string();
  const char* columns[] = {"block",    "line",     "removed_mm3",      "mrr_mm3_min",    "entry_deg",      "exit_deg",
                           "engaged_area_mm2", "collision", "axial_depth_mm", "radial_width_mm", "pairs", "tool"};
  constexpr int kRequired = 8, kColumns = 12;
  int col[kColumns];
  for (int k = 0; k < kColumns; ++k) {
    col[k] = t.column(columns[k]);
    if (col[k] < 0 && k < kRequired) throw InputError(file, 1, columns[k], "missing column");
  }
  std::vector<BlockRow> rows;
  rows.reserve(t.rows.size());
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const auto& cells = t.rows[r];
    const int line = t.lines[r];
    auto number = [&](int k) {
      if (col[k] < 0) return std::numeric_limits<double>::quiet_NaN();
      const std::string& cell = cells[size_t(col[k])];
      return cell.empty() && k >= 2 ? std::numeric_limits<double>::quiet_NaN() : parse_number(cell, file, line, columns[k]);
    };
    auto whole = [&](int k) {
      const double v = number(k);
      if (!(v >= 0 && v <= std::numeric_limits<int>::max()) || v != std::floor(v)) throw InputError(file, line, columns[k], "expected a whole number >= 0");
      return int(v);
    };
    BlockRow b;
    b.block = whole(0);
    b.line = whole(1);
    b.removed_mm3 = number(2);
    b.mrr_mm3_min = number(3);
    b.entry_deg = number(4);
    b.exit_deg = number(5);
    b.engaged_area_mm2 = number(6);
    const std::string& c = cells[size_t(col[7])];
    if (c == "1" || c == "true") b.collision = true;
    else if (c == "0" || c == "false") b.collision = false;
    else throw InputError(file, line, "collision", "expected 0, 1, true or false, found '" + c + "'");
    b.axial_depth_mm = number(8);
    b.radial_width_mm = number(9);
    b.pairs = col[10] < 0 || std::isnan(number(10)) ? -1 : whole(10);
    b.tool = col[11] < 0 || std::isnan(number(11)) ? -1 : whole(11);
    rows.push_back(b);
  }
  return rows;
}

}  // namespace tf
