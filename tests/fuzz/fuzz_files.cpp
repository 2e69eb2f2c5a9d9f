// libFuzzer target of core's file readers that the scene target does not feed with fuzzed text: the input
// path CSV, APT CLDATA, the oriented path CSV, the machine JSON, the verification report (replan's input)
// and blocks.csv. The first byte picks the reader, the rest is the file's text. Whatever the text, a reader
// returns or throws tf::InputError naming the file; anything else (a crash, a sanitizer report, another
// exception) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/oriented_path.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/core/tool.hpp"
#include "tiltfield/core/toolpath.hpp"

namespace {
namespace fs = std::filesystem;

fs::path folder() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("tiltfield-fuzz-files-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

void read_as(unsigned kind, const fs::path& file) {
  switch (kind) {
    case 0:
      tf::read_toolpath_csv(file);
      break;
    case 1: {
      tf::Tool tool;  // the default ball: APT's tips become ball centres
      tf::read_toolpath_apt(file, tool);
      break;
    }
    case 2:
      tf::read_oriented_csv(file);
      break;
    case 3:
      tf::read_machine_json(file);
      break;
    case 4:
      tf::read_verify_json(file);
      break;
    default:
      tf::read_blocks_csv(file);
      break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const unsigned kind = data[0] % 6u;
  const char* const names[] = {"path.csv", "path.apt", "oriented.csv", "machine.json", "verify.json", "blocks.csv"};
  const fs::path file = folder() / names[kind];
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data) + 1, long(size - 1));
  try {
    read_as(kind, file);
  } catch (const tf::InputError& e) {
    if (e.file().empty()) std::abort();
  }
  return 0;
}
