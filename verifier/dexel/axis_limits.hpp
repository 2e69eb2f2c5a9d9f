// tiltfield dexel (internal): the machine's axes against their limits, block by block.
#pragma once
#include "tiltfield/core/machine.hpp"
#include "tiltfield/core/program.hpp"
#include "tiltfield/core/report.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf::sim {

// Block b (the index-th, 1-based) from joints `from`: each machine axis beyond machine.limits at its end,
// or, in an arc, at the extreme points of its plane, is added once to rep.axis_limits. Under TCP the
// machine's X Y Z come from `forward` (the block's tool); between a TCP block's ends they are not checked.
// Joint moves interpolate linearly, so their ends bound them. `nose_above_tip` (mm): what the machine's Z
// lies above a non-TCP block's tip Z (a 3-axis program under tool length offsets: the gauge length).
void check_axis_limits(const MachineSpec& machine, const Block& b, const Joints& from, int index,
                       const ForwardFn& forward, VerifyReport& rep, double nose_above_tip = 0.0);

}  // namespace tf::sim
