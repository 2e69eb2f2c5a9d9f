// Reading the collisions of a VERIFY.json for the re-planner.
#include <fstream>

#include <nlohmann/json.hpp>

#include "tiltfield/error.hpp"
#include "tiltfield/replan.hpp"

namespace tf {

namespace {
using nlohmann::json;

Eigen::Vector3d vec3(const json& o, const char* key, const std::string& file, const std::string& prefix) {
  const std::string field = prefix + "." + key;
  if (!o.contains(key)) throw InputError(file, 0, field, "missing (re-planning needs the block's tool poses)");
  const json& v = o[key];
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError(file, 0, field, "must be an array of 3 numbers");
  const Eigen::Vector3d r(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!r.allFinite()) throw InputError(file, 0, field, "must be finite");
  return r;
}

Eigen::Vector3d unit(const Eigen::Vector3d& v, const std::string& file, const std::string& field) {
  if (std::abs(v.norm() - 1.0) > 1e-3) throw InputError(file, 0, field, "not a unit vector");
  return v.normalized();
}
}  // namespace

std::vector<CollisionSite> read_collision_sites(const std::filesystem::path& verify_json) {
  const std::string file = verify_json.string();
  std::ifstream in(verify_json, std::ios::binary);
  if (!in) throw InputError(file, 0, "", "cannot open verification report");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(file, 0, "", std::string("invalid JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("collisions") || !j["collisions"].is_array())
    throw InputError(file, 0, "collisions", "missing (is this a tiltfield VERIFY.json?)");
  std::vector<CollisionSite> sites;
  const json& cs = j["collisions"];
  for (size_t i = 0; i < cs.size(); ++i) {
    const std::string p = "collisions[" + std::to_string(i) + "]";
    const json& c = cs[i];
    if (!c.is_object()) throw InputError(file, 0, p, "must be an object");
    CollisionSite s;
    auto integer = [&](const char* key) {
      if (!c.contains(key) || !c[key].is_number_integer()) throw InputError(file, 0, p + "." + key, "must be an integer");
      return c[key].get<int>();
    };
    auto text = [&](const char* key) {
      if (!c.contains(key) || !c[key].is_string()) throw InputError(file, 0, p + "." + key, "must be a string");
      return c[key].get<std::string>();
    };
    s.block = integer("block");
    s.line = integer("line");
    s.component = text("component");
    s.with = text("with");
    s.rapid = c.value("rapid", false);
    s.depth_mm = c.contains("depth_mm") && c["depth_mm"].is_number() ? c["depth_mm"].get<double>() : 0.0;
    s.start.tip = vec3(c, "start_tip", file, p);
    s.start.axis = unit(vec3(c, "start_axis", file, p), file, p + ".start_axis");
    s.end.tip = vec3(c, "end_tip", file, p);
    s.end.axis = unit(vec3(c, "end_axis", file, p), file, p + ".end_axis");
    sites.push_back(s);
  }
  return sites;
}

}  // namespace tf
