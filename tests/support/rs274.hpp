// LinuxCNC's interpreter as a test judge. rs274 keeps its tool data in one shared memory-mapped file, so
// two runs at once (ctest -j) break each other ("tool not found", bus errors); every test runs it under
// one lock.
#pragma once
#include <string>

namespace tf::test {

// The shell command that runs `rs274 -g ARGS` alone.
inline std::string rs274_command(const std::string& args) {
  return "flock /tmp/tiltfield-rs274.lock rs274 -g " + args;
}

}  // namespace tf::test
