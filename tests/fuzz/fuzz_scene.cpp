// libFuzzer target of the scene reader (parse_scene, with gcode_options for its tool library and work
// offsets). The input is the scene's JSON text; it may name the small files of a fixed folder
// (design.stl, stock.stl, path.csv, path.apt, machine.json). Inputs holding a '/' or '\' are skipped: a path
// out of that folder could name a device that never ends. Whatever the text, the reader returns a scene or
// throws tf::InputError naming a file, and the scene file's errors name a field or a line; anything else
// is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/scene.hpp"
#include "tiltfield/gcode/gcode.hpp"

namespace {

namespace fs = std::filesystem;

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// The folder of files a fuzzed scene may refer to, made once per process.
fs::path scene_folder() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("tiltfield-fuzz-scene-" + std::to_string(::getpid()));
    fs::create_directories(d);
    const std::string box =
        "solid b\n"
        "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
        "facet normal 0 0 -1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\n"
        "facet normal 0 0 1\nouter loop\nvertex 0 0 1\nvertex 1 0 1\nvertex 0 1 1\nendloop\nendfacet\n"
        "facet normal 0 0 1\nouter loop\nvertex 1 0 1\nvertex 1 1 1\nvertex 0 1 1\nendloop\nendfacet\n"
        "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
        "facet normal 0 -1 0\nouter loop\nvertex 1 0 0\nvertex 1 0 1\nvertex 0 0 1\nendloop\nendfacet\n"
        "facet normal 0 1 0\nouter loop\nvertex 0 1 0\nvertex 0 1 1\nvertex 1 1 0\nendloop\nendfacet\n"
        "facet normal 0 1 0\nouter loop\nvertex 1 1 0\nvertex 0 1 1\nvertex 1 1 1\nendloop\nendfacet\n"
        "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
        "facet normal -1 0 0\nouter loop\nvertex 0 1 0\nvertex 0 0 1\nvertex 0 1 1\nendloop\nendfacet\n"
        "facet normal 1 0 0\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 1 0 1\nendloop\nendfacet\n"
        "facet normal 1 0 0\nouter loop\nvertex 1 1 0\nvertex 1 1 1\nvertex 1 0 1\nendloop\nendfacet\n"
        "endsolid b\n";
    write(d / "design.stl", box);
    write(d / "stock.stl", box);
    write(d / "path.csv", "x,y,z,nx,ny,nz,feed\n0.5,0.5,1.5,0,0,1,900\n0.6,0.5,1.5,0,0,1,900\n");
    write(d / "path.apt", "FEDRAT/800\nGOTO/0.5,0.5,1.0,0,0,1\nGOTO/0.7,0.5,1.0,0,0,1\n");
    write(d / "machine.json", R"({"kinematics": "table-table-bc", "pivot": [0, 0, 0], "limits": {"B": [-90, 90]}})");
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (text.find('/') != std::string::npos || text.find('\\') != std::string::npos) return 0;
  const fs::path file = scene_folder() / "scene.json";
  try {
    const tf::Scene scene = tf::parse_scene(text, file);
    const tf::GcodeOptions options = tf::gcode_options(scene);
    if (!(options.tool_length > 0.0)) std::abort();
  } catch (const tf::InputError& e) {
    if (e.file().empty()) std::abort();
    if (e.file() == file.string() && e.field().empty() && e.line() < 1) std::abort();
  }
  return 0;
}
