#pragma once

// Random rigid-node layouts and configurations shared by the connective-tissue tests.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "surgical_sim/core/connective/rigid_node_model.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"
#include "surgical_sim/core/connective/rigid_node_shape_functions.h"
#include "surgical_sim/core/connective/rigid_node_state.h"
#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core::test {

inline Eigen::Vector3d randomVector(std::mt19937& rng, double amplitude) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

/// num_nodes rigid nodes at random positions in [0, scale]^3 with random rest orientations and
/// num_samples samples between them with Shepard weights on `neighbours` nodes (lambda 1.3 kPa,
/// mu 0.7 kPa, 1000 kg/m^3, volume (scale / 4)^3 each).
inline RigidNodeLayout randomLayout(unsigned seed, int num_nodes, int num_samples, int neighbours,
                                    double scale = 1.0) {
  std::mt19937 rng(seed);
  RigidNodeLayout layout;
  for (int i = 0; i < num_nodes; ++i) {
    layout.rest.p_TN.push_back(scale * (randomVector(rng, 0.5) + Eigen::Vector3d::Constant(0.5)));
    layout.rest.q_TN.push_back(expRotation(randomVector(rng, 2.0)));
  }
  for (int s = 0; s < num_samples; ++s) {
    RigidNodeSample sample;
    sample.rest_position = scale * (randomVector(rng, 0.5) + Eigen::Vector3d::Constant(0.5));
    sample.volume = std::pow(0.25 * scale, 3);
    sample.lambda = 1.3e3;
    sample.mu = 0.7e3;
    sample.density = 1000.0;
    sample.weights = shepardWeights(layout.rest.p_TN, sample.rest_position, neighbours, 2.0);
    layout.samples.push_back(sample);
  }
  return layout;
}

/// rest with every node moved by a random translation (|.| <= amplitude scale per axis) and
/// rotated by a random rotation vector (|.| <= amplitude rad per axis).
inline RigidNodeConfiguration perturbed(const RigidNodeConfiguration& rest, unsigned seed,
                                        double amplitude, double scale = 1.0) {
  std::mt19937 rng(seed);
  RigidNodeConfiguration q = rest;
  for (int i = 0; i < q.numNodes(); ++i) {
    q.p_TN[i] += scale * randomVector(rng, amplitude);
    q.q_TN[i] = expRotation(randomVector(rng, amplitude)) * q.q_TN[i];
  }
  return q;
}

/// Every node moved by the rigid motion x -> R x + t.
inline RigidNodeConfiguration rigidlyMoved(const RigidNodeConfiguration& rest,
                                           const Eigen::Quaterniond& R, const Eigen::Vector3d& t) {
  RigidNodeConfiguration q = rest;
  for (int i = 0; i < q.numNodes(); ++i) {
    q.p_TN[i] = R * rest.p_TN[i] + t;
    q.q_TN[i] = R * rest.q_TN[i];
  }
  return q;
}

/// call() throws std::invalid_argument whose message contains text.
inline void expectInvalidArgument(const std::function<void()>& call, const std::string& text) {
  try {
    call();
    ADD_FAILURE() << "no exception, expected one naming '" << text << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

/// q (+) h e_dof.
inline RigidNodeConfiguration displaced(const RigidNodeConfiguration& q, int dof, double h) {
  RigidNodeConfiguration out = q;
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(kRigidNodeDofs * q.numNodes());
  dq[dof] = h;
  applyRigidNodeIncrement(dq, 1.0, out);
  return out;
}

}  // namespace surgical_sim::core::test
