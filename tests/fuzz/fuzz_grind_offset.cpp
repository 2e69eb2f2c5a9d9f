// libFuzzer target of the grinding and offset readers: the first byte picks one, the rest is its text:
// a grinding program (parse_grind_program), a grinding scene (load_grind_scene, its program given inline
// or as the fixed file prog.ngc), an offset profile (parse_profile, then validate_profile) or a gap law CSV
// (read_gap_law). Whatever the text, a reader returns or throws tf::InputError naming the file; anything
// else is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tiltfield/core/error.hpp"
#include "tiltfield/grind/grind.hpp"
#include "tiltfield/offset/offset.hpp"

namespace {
namespace fs = std::filesystem;

void write(const fs::path& p, const char* data, size_t size) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(data, long(size));
}

fs::path folder() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("tiltfield-fuzz-grind-" + std::to_string(::getpid()));
    fs::create_directories(d);
    const std::string prog = "OP fluting a\nG0 X0 Y40 Z30\nG1 Y21.5 F100\n";
    write(d / "prog.ngc", prog.data(), prog.size());
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const unsigned kind = data[0] % 4u;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  // A scene naming a program outside the folder could name a device that never ends.
  if (kind == 1 && (text.find('/') != std::string::npos || text.find('\\') != std::string::npos)) return 0;
  try {
    switch (kind) {
      case 0:
        tf::grind::parse_grind_program(text, "prog.ngc", tf::grind::Axes{});
        break;
      case 1: {
        const fs::path file = folder() / "grind.json";
        write(file, text.data(), text.size());
        tf::grind::load_grind_scene(file);
        break;
      }
      case 2:
        tf::offset::validate_profile(tf::offset::parse_profile(text, "profile.txt"));
        break;
      default: {
        const fs::path file = folder() / "law.csv";
        write(file, text.data(), text.size());
        tf::offset::read_gap_law(file);
        break;
      }
    }
  } catch (const tf::InputError& e) {
    if (e.file().empty()) std::abort();
  }
  return 0;
}
