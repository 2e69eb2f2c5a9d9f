// tiltfield verifier (internal): the tools a program runs with. Per tool number (Block::tool) its convex
// parts for the sweeps, its forward kinematics (the machine with its own gauge length) and the Tool itself
// (for the engagement probe). The scene's library tools by number; every other number is the scene's
// `tool`, moved by the caller's forward map.
#pragma once
#include <vector>

#include "tiltfield/core/scene.hpp"
#include "tiltfield/dexel/sweep.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::sim {

class ToolSet {
 public:
  ToolSet(const Scene& scene, const ForwardFn& forward, const SweepOptions& sweep);
  const Tool& tool(int number) const { return entry(number).tool; }
  const std::vector<ToolPart>& parts(int number) const { return entry(number).parts; }
  const ForwardFn& forward(int number) const { return entry(number).forward; }

 private:
  struct Entry {
    int number;  // -1 for the scene's tool
    Tool tool;
    std::vector<ToolPart> parts;
    ForwardFn forward;
  };
  const Entry& entry(int number) const;
  std::vector<Entry> entries_;  // [0]: the scene's tool, then the library in file order
};

}  // namespace tf::sim
