// trocar_device: the 5-DoF active trocar with its 1 kHz haptic loop (joint commands in, motor
// efforts, joint states and the tool-tip pose out).
#include "surgical_sim/ros/run_node.h"
#include "surgical_sim/ros/trocar_device_node.h"

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::TrocarDeviceNode>(
      argc, argv, "trocar_device");
}
