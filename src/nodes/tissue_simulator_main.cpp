// tissue_simulator: steps a tissue scene and publishes its surface, contact models and stats.
#include "surgical_sim/ros/run_node.h"
#include "surgical_sim/ros/tissue_simulator_node.h"

int main(int argc, char** argv) {
  return surgical_sim::ros_layer::runNode<surgical_sim::ros_layer::TissueSimulatorNode>(
      argc, argv, "tissue_simulator");
}
