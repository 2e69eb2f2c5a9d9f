#include <memory>

#include "tiltfield/core/kinematics.hpp"
#include "tiltfield/dexel/verify.hpp"

namespace tf {

ForwardFn scene_forward(const Scene& scene) { return scene_forward(scene, scene.tool); }

ForwardFn scene_forward(const Scene& scene, const Tool& tool) {
  const MachineSpec machine = scene.machine.value_or(MachineSpec{});
  if (machine.kinematics == KinematicsType::XYZ) return forward_xyz;
  auto kin = std::make_shared<const Kinematics>(machine, tool.length);
  return [kin](const Joints& j) { return kin->forward(j); };
}

}  // namespace tf
