// tiltfield: the one progress callback every long loop reports through.
#pragma once
#include <functional>
#include <string_view>

namespace tf {

// stage: a short name ("plan", "verify"); fraction in [0, 1]. An empty function means no reporting.
// Loops call it at most every few hundred iterations, so the callback may be slow-ish (terminal I/O).
using Progress = std::function<void(std::string_view stage, double fraction)>;

inline void report(const Progress& progress, std::string_view stage, double fraction) {
  if (progress) progress(stage, fraction);
}

}  // namespace tf
