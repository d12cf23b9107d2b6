// The trocar of urdf/active_trocar.urdf, for the haptics tests.
#pragma once

#include <string>

#include "surgical_sim/core/common/text_file.h"
#include "surgical_sim/core/haptics/trocar_urdf.h"

namespace surgical_sim::core {

inline std::string shippedTrocarUrdfText() {
  return readTextFile(std::string(SURGICAL_SIM_SOURCE_DIR) + "/urdf/active_trocar.urdf");
}

inline TrocarUrdf shippedTrocar() {
  return readTrocarUrdf(shippedTrocarUrdfText(), TrocarUrdfNames::forTrocar("trocar"));
}

inline TrocarDeviceConfig shippedDeviceConfig() {
  return makeTrocarDeviceConfig(shippedTrocar(), chendebPrototypeMotors());
}

}  // namespace surgical_sim::core
