// libFuzzer target of the scene's tool library and work offsets and of the G-code reader running with
// them. The input is two JSON values separated by the first newline: the scene's "tools" and its
// "work_offsets" (an empty part leaves the key out). They are set into a fixed scene as JSON values, so an
// input cannot add other keys (files). The scene is parsed, then two programs that change tools, take
// tool length offsets and select every work offset are read with its options. Only results or
// tf::InputError naming the scene's field or the program's line may come out.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace {

const char* const kPrograms[] = {
    "G21 G90 G17\nT1 M6\nG43 H1\nG54 G0 X0 Y0 Z10\nG55 G1 X1 F100\nT2 M6\nG43 H2 Z5\nG81 X2 Y2 Z-1 R1\n"
    "G56 X3\nG80\nG57 G0 X1\nG58 Y1\nG59 Z3\nG59.1 X2\nG59.2 Y2\nG59.3 Z4\nG49 G0 Z20\nT3 M6\nG43\nG0 X0\nM30\n",
    "G21 G90\nT2 M6\nG54 G0 X0 Y0 Z50 A0 C0\nG43.4 H2\nG1 X1 Y2 Z3 A10 C20 F100\nT1 M6\nG43.4 H1\nG1 X2\n"
    "G49\nG53 G0 Z40\nG28\nM30\n",
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t cut = text.find('\n');
  const std::string tools = text.substr(0, cut);
  const std::string offsets = cut == std::string::npos ? std::string() : text.substr(cut + 1);
  nlohmann::json scene = nlohmann::json::parse(R"({"stock": {"box": {"min": [0, 0, 0], "max": [10, 10, 10]}},
                                                   "machine": {"kinematics": "table-table-ac"}})");
  if (!tools.empty()) {
    const nlohmann::json v = nlohmann::json::parse(tools, nullptr, false);
    if (v.is_discarded()) return 0;
    scene["tools"] = v;
  } else {
    scene["tool"] = nlohmann::json::parse(R"({"type": "ball", "radius": 2})");
  }
  if (!offsets.empty()) {
    const nlohmann::json v = nlohmann::json::parse(offsets, nullptr, false);
    if (v.is_discarded()) return 0;
    scene["work_offsets"] = v;
  }
  tf::Scene s;
  try {
    s = tf::parse_scene(scene.dump(), "fuzz.json");
  } catch (const tf::InputError& e) {
    if (e.file() != "fuzz.json" || e.field().empty()) std::abort();
    return 0;
  }
  const tf::GcodeOptions options = tf::gcode_options(s);
  for (const char* program : kPrograms) {
    try {
      const tf::Program p = tf::parse_gcode(program, "fuzz.ngc", *s.machine, options);
      for (const tf::Block& b : p.blocks)
        if (!std::isfinite(b.target.x + b.target.y + b.target.z + b.target.a + b.target.c)) std::abort();
    } catch (const tf::InputError& e) {
      if (e.file() != "fuzz.ngc" || e.line() < 1) std::abort();
    }
  }
  return 0;
}
