// The tools a program runs with: parts and forward kinematics per tool number.
#include "tool_set.hpp"

namespace tf::sim {

ToolSet::ToolSet(const Scene& scene, const ForwardFn& forward, const SweepOptions& sweep) {
  entries_.push_back({-1, scene.tool, tool_parts(scene.tool, sweep), forward});
  for (const ToolEntry& e : scene.tools)
    entries_.push_back({e.number, e.tool, tool_parts(e.tool, sweep), scene_forward(scene, e.tool)});
}

const ToolSet::Entry& ToolSet::entry(int number) const {
  for (size_t i = 1; i < entries_.size(); ++i)
    if (entries_[i].number == number) return entries_[i];
  return entries_.front();
}

}  // namespace tf::sim
