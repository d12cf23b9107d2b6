#include "surgical_sim/core/haptics/trocar_joints.h"

namespace surgical_sim::core {

const char* trocarJointName(int joint) {
  switch (joint) {
    case kTrocarPitch:
      return "pitch";
    case kTrocarYaw:
      return "yaw";
    case kTrocarSpin:
      return "spin";
    case kTrocarInsertion:
      return "insertion";
    case kTrocarGrip:
      return "grip";
    default:
      return "unknown";
  }
}

}  // namespace surgical_sim::core
