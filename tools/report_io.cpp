// tiltfield report: readers for the verifier's outputs (blocks.csv, verify.json), for callers that have
// the files rather than the values in memory.
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "report.hpp"
#include "tiltfield/error.hpp"
#include "tiltfield/gcode.hpp"
#include "tiltfield/io.hpp"

namespace tf::reporting {

std::vector<BlockRow> read_blocks_csv(const std::filesystem::path& file) {
  const CsvTable t = read_csv(file);
  const std::string name = file.string();
  const char* columns[] = {"block", "line", "removed_mm3", "mrr_mm3_min", "entry_deg", "exit_deg", "engaged_area_mm2", "collision"};
  int col[8];
  for (int k = 0; k < 8; ++k) {
    col[k] = t.column(columns[k]);
    if (col[k] < 0) throw InputError(name, 1, columns[k], "missing column");
  }
  std::vector<BlockRow> rows;
  rows.reserve(t.rows.size());
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const auto& cells = t.rows[r];
    const int line = t.lines[r];
    auto number = [&](int k) {
      const std::string& cell = cells[size_t(col[k])];
      return cell.empty() && k >= 2 ? std::numeric_limits<double>::quiet_NaN() : parse_number(cell, name, line, columns[k]);
    };
    auto integer = [&](int k) {
      const double v = number(k);
      if (v != double(long(v)) || v < 0) throw InputError(name, line, columns[k], "expected a whole number >= 0");
      return int(v);
    };
    BlockRow b;
    b.block = integer(0);
    b.line = integer(1);
    b.removed_mm3 = number(2);
    b.mrr_mm3_min = number(3);
    b.entry_deg = number(4);
    b.exit_deg = number(5);
    b.engaged_area_mm2 = number(6);
    const std::string& c = cells[size_t(col[7])];
    if (c == "1" || c == "true") b.collision = true;
    else if (c == "0" || c == "false") b.collision = false;
    else throw InputError(name, line, "collision", "expected 0, 1, true or false, found '" + c + "'");
    rows.push_back(b);
  }
  return rows;
}

namespace {

template <class T>
T field(const nlohmann::json& j, const char* key, const std::string& file, const std::string& where) {
  if (!j.contains(key)) throw InputError(file, 0, where + key, "missing field");
  try {
    return j.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(file, 0, where + key, "wrong type");
  }
}

double optional_number(const nlohmann::json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) return -1.0;
  if (!j[key].is_number()) throw InputError(file, 0, key, "expected a number");
  return j[key].get<double>();
}

}  // namespace

VerifyData read_verify_json(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(name, 0, "", "cannot open file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(name, 0, "", std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw InputError(name, 0, "", "expected a JSON object");
  VerifyData v;
  v.removed_volume_mm3 = optional_number(j, "removed_volume_mm3", name);
  v.max_gouge_mm = optional_number(j, "max_gouge_mm", name);
  v.resolution_mm = optional_number(j, "resolution_mm", name);
  v.seconds = optional_number(j, "seconds", name);
  for (const char* list : {"collisions", "gouges"})
    if (j.contains(list) && !j[list].is_array()) throw InputError(name, 0, list, "expected an array");
  if (j.contains("collisions"))
    for (size_t i = 0; i < j["collisions"].size(); ++i) {
      const auto& c = j["collisions"][i];
      const std::string where = "collisions[" + std::to_string(i) + "].";
      v.collisions.push_back({field<int>(c, "block", name, where), field<int>(c, "line", name, where),
                              field<std::string>(c, "component", name, where), field<std::string>(c, "with", name, where),
                              field<bool>(c, "rapid", name, where), field<double>(c, "depth_mm", name, where)});
    }
  if (j.contains("gouges"))
    for (size_t i = 0; i < j["gouges"].size(); ++i) {
      const auto& g = j["gouges"][i];
      const std::string where = "gouges[" + std::to_string(i) + "].";
      v.gouges.push_back({field<int>(g, "block", name, where), field<int>(g, "line", name, where),
                          field<double>(g, "depth_mm", name, where)});
    }
  return v;
}

std::vector<BlockAxes> block_axes(const Program& program) {
  std::vector<BlockAxes> axes;
  axes.reserve(program.blocks.size());
  for (size_t i = 0; i < program.blocks.size(); ++i) {
    const Block& b = program.blocks[i];
    axes.push_back({int(i) + 1, b.line, b.target, b.motion == Motion::Rapid, b.tcp});
  }
  return axes;
}

std::unique_ptr<RunFolder> load_run_folder(const Scene& scene, const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  auto run = std::make_unique<RunFolder>();
  ReportInputs& in = run->inputs;
  in.scene = &scene;
  if (fs::exists(dir / "oriented.csv")) {
    run->oriented = read_oriented_csv(dir / "oriented.csv");
    in.oriented = &run->oriented;
  }
  if (fs::exists(dir / "program.ngc"))
    in.axes = block_axes(read_gcode(dir / "program.ngc", scene.machine.value_or(MachineSpec{})));
  if (fs::exists(dir / "verify.json")) {
    VerifyData v = read_verify_json(dir / "verify.json");
    in.collisions = std::move(v.collisions);
    in.gouges = std::move(v.gouges);
    in.summary.removed_volume_mm3 = v.removed_volume_mm3;
    in.summary.max_gouge_mm = v.max_gouge_mm;
    in.summary.resolution_mm = v.resolution_mm;
  }
  if (fs::exists(dir / "blocks.csv")) in.blocks = read_blocks_csv(dir / "blocks.csv");
  if (fs::exists(dir / "stock.ply")) {
    run->stock = load_mesh(dir / "stock.ply");
    in.stock = &run->stock;
    in.stock_deviation_mm = stock_deviation(run->stock, scene.design);
  }
  return run;
}

}  // namespace tf::reporting
