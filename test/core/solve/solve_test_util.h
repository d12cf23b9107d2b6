#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "spring_lattice_model.h"
#include "surgical_sim/core/solve/dynamics_problem.h"
#include "surgical_sim/core/solve/linear_solver.h"

namespace surgical_sim::core::test {

/// Linear solver stub whose factorization always fails (failure-path tests).
class FailingLinearSolver final : public LinearSolver {
 public:
  std::string name() const override { return "failing"; }
  void analyzePattern(const Eigen::SparseMatrix<double>&) override {}
  bool factorize(const Eigen::SparseMatrix<double>&) override { return false; }
  LinearSolveReport solve(const Eigen::VectorXd&, Eigen::VectorXd&) override { return {}; }
};

/// Expects f() to throw std::invalid_argument whose message contains name.
template <class F>
void expectInvalidArgumentNaming(F&& f, const std::string& name) {
  try {
    f();
    ADD_FAILURE() << "expected std::invalid_argument naming " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

/// Sparse SPD test matrix (3n x 3n): projected tangent of a randomly perturbed nonlinear lattice
/// plus a varying positive diagonal.
inline Eigen::SparseMatrix<double> spdTestMatrix(unsigned seed, double perturbation = 0.02) {
  SpringLatticeModel model =
      SpringLatticeModel::lattice(3, 3, 2, 0.1, 1000.0, 0.1, SpringLatticeModel::Law::Nonlinear);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += perturbation * u(rng);
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  model.assembleStiffness(x, TangentMode::ProjectedSpd, K);
  for (Eigen::Index i = 0; i < K.rows(); ++i) K.coeffRef(i, i) += 10.0 + 5.0 * u(rng);
  return K;
}

/// SPD matrix of a lattice at pseudo-time t: the projected tangent at the rest positions
/// perturbed by 0.02 sin(1.3 i + t) plus the diagonal 10 + 5 sin(0.7 i); changes slowly with t.
inline Eigen::SparseMatrix<double> perturbedTangent(const SpringLatticeModel& model, double t) {
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += 0.02 * std::sin(1.3 * i + t);
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  model.assembleStiffness(x, TangentMode::ProjectedSpd, K);
  for (Eigen::Index i = 0; i < K.rows(); ++i) K.coeffRef(i, i) += 10.0 + 5.0 * std::sin(0.7 * i);
  return K;
}

/// The lattice split like a cut by the half-plane x = x_cut, y < y_end: the nodes on it get copies
/// holding their springs towards x > x_cut (SpringLatticeModel::split).
inline SpringLatticeModel crackedLattice(const SpringLatticeModel& model, double x_cut,
                                         double y_end) {
  std::vector<int> nodes;
  const Eigen::VectorXd& rest = model.restPositions();
  for (int a = 0; a < model.numNodes(); ++a) {
    if (std::abs(rest[3 * a] - x_cut) < 1e-9 && rest[3 * a + 1] < y_end) nodes.push_back(a);
  }
  return model.split(nodes, [x_cut](const Eigen::Vector3d& p) { return p.x() > x_cut + 1e-9; });
}

/// The DOFs (x, y, z) of every node whose rest coordinate `axis` equals value.
inline std::vector<int> dofsOfNodesAt(const TissueModel& model, int axis, double value) {
  std::vector<int> dofs;
  const Eigen::VectorXd& rest = model.restPositions();
  for (int a = 0; a < model.numNodes(); ++a) {
    if (std::abs(rest[3 * a + axis] - value) < 1e-12) {
      for (int c = 0; c < 3; ++c) dofs.push_back(3 * a + c);
    }
  }
  return dofs;
}

/// Problem with zero external force, no damping; Dirichlet DOFs held at their rest positions.
inline DynamicsProblem makeProblem(const TissueModel& model, const std::vector<int>& fixed) {
  DynamicsProblem problem;
  problem.model = &model;
  problem.external_force = Eigen::VectorXd::Zero(model.restPositions().size());
  problem.dirichlet.dofs = fixed;
  problem.dirichlet.positions.resize(static_cast<Eigen::Index>(fixed.size()));
  for (size_t k = 0; k < fixed.size(); ++k) {
    problem.dirichlet.positions[static_cast<Eigen::Index>(k)] = model.restPositions()[fixed[k]];
  }
  return problem;
}

/// makeProblem with the nodes at z = 0 held, under the body acceleration a [m/s^2].
inline DynamicsProblem clampedUnderBodyForce(const TissueModel& model, const Eigen::Vector3d& a) {
  DynamicsProblem problem = makeProblem(model, dofsOfNodesAt(model, 2, 0.0));
  problem.external_force = model.bodyForce(a);
  return problem;
}

/// State at rest: x = rest positions, v = 0, time 0.
inline SimulationState restState(const TissueModel& model) {
  SimulationState state;
  state.x = model.restPositions();
  state.v = Eigen::VectorXd::Zero(state.x.size());
  return state;
}

/// Total linear momentum sum_i m_i v_i [kg m/s].
inline Eigen::Vector3d momentum(const TissueModel& model, const Eigen::VectorXd& v) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int a = 0; a < model.numNodes(); ++a) {
    p += model.lumpedMass()[3 * a] * v.segment<3>(3 * a);
  }
  return p;
}

}  // namespace surgical_sim::core::test
