#include "surgical_sim/core/robot/continuum_robot_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/robot/cable_actuator.h"
#include "surgical_sim/core/robot/pressure_chamber_actuator.h"
#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {
namespace {

constexpr double kGravity = 9.81;  // [m/s^2]

void applyStep(const std::vector<RigidNodePose>& from, const Eigen::VectorXd& step, double alpha,
               std::vector<RigidNodePose>& to) {
  to[0] = from[0];
  for (size_t k = 1; k < from.size(); ++k) {
    const int i = 6 * static_cast<int>(k - 1);
    to[k].p_BN = from[k].p_BN + alpha * step.segment<3>(i);
    to[k].q_BN = (expRotation(alpha * step.segment<3>(i + 3)) * from[k].q_BN).normalized();
  }
}

}  // namespace

ContinuumRobotModel::ContinuumRobotModel(const ContinuumRobotDescription& description,
                                         const SectionCompliances& compliances)
    : description_(description), tangent_(std::max(1, description.num_vertebrae)) {
  validateContinuumRobotDescription(description_);
  const int n = description_.num_vertebrae;
  if (static_cast<int>(compliances.compliance.size()) != n)
    throw std::invalid_argument("continuum_robot.compliances: expected one compliance per gap (" +
                                std::to_string(n) + "), got " +
                                std::to_string(compliances.compliance.size()));
  const double s = description_.vertebra_spacing;
  rest_.resize(n + 1);
  for (int k = 0; k <= n; ++k) rest_[k].p_BN = Eigen::Vector3d(k * s, 0.0, 0.0);
  for (int k = 0; k < n; ++k)
    springs_.emplace_back(compliances.compliance[k], Eigen::Vector3d(s, 0.0, 0.0),
                          Eigen::Quaterniond::Identity());
  for (const auto& c : description_.chambers)
    actuators_.push_back(std::make_unique<PressureChamberActuator>(c, description_, 12, 1));
  for (const auto& c : description_.cables)
    actuators_.push_back(std::make_unique<CableActuator>(c));
  mass_.assign(n + 1, description_.vertebra_mass);
  const double ell = s - description_.vertebra_thickness;
  for (int k = 0; k < n; ++k) {
    const double r_o = description_.outerRadiusAt((k + 0.5) * s);
    const double r_i = description_.inner_radius;
    const double m = description_.material.density * M_PI * (r_o * r_o - r_i * r_i) * ell;
    mass_[k] += 0.5 * m;
    mass_[k + 1] += 0.5 * m;
  }
  nodes_ = rest_;
  trial_ = rest_;
  backup_ = rest_;
  // Round-off floor of the residual: 1e-13 of the force that stretches a section by its length.
  double k_max = 0.0;
  for (const EquivalentSpring& sp : springs_) k_max = std::max(k_max, sp.stiffness().norm());
  force_floor_ = 1e-13 * k_max * s;
  for (const auto& act : actuators_) {
    load_hessian_begin_.push_back(static_cast<int>(load_hessian_.size()));
    load_hessian_.resize(load_hessian_.size() + act->numPieces());
  }
  full_.resize(6 * (n + 1));
  step_.resize(6 * n);
  residual_.resize(6 * n);
}

void ContinuumRobotModel::setNodes(const std::vector<RigidNodePose>& nodes) {
  if (nodes.size() != nodes_.size())
    throw std::invalid_argument("continuum_robot.nodes: expected " + std::to_string(nodes_.size()) +
                                " poses");
  nodes_ = nodes;
  nodes_[0] = rest_[0];
  load_hessian_valid_ = false;
}

void ContinuumRobotModel::reset() {
  nodes_ = rest_;
  tip_force_.setZero();
  load_hessian_valid_ = false;
}

double ContinuumRobotModel::potential(const std::vector<RigidNodePose>& nodes,
                                      const Eigen::VectorXd& actuation) const {
  double pi = 0.0;
  for (size_t k = 0; k < springs_.size(); ++k)
    pi += springs_[k].evaluate(nodes[k], nodes[k + 1], nullptr, nullptr, SpringTangent::Exact);
  if (description_.gravity_enabled)
    for (size_t k = 1; k < nodes.size(); ++k) pi += mass_[k] * kGravity * nodes[k].p_BN.z();
  for (size_t a = 0; a < actuators_.size(); ++a)
    if (actuation[a] != 0.0) pi -= actuation[a] * actuators_[a]->measure(nodes);
  pi -= tip_force_.dot(nodes.back().p_BN);
  return pi;
}

void ContinuumRobotModel::generalizedForce(const std::vector<RigidNodePose>& nodes,
                                           const Eigen::VectorXd& actuation,
                                           Eigen::VectorXd& force) const {
  force.setZero();
  Eigen::Matrix<double, 12, 1> f;
  for (size_t k = 0; k < springs_.size(); ++k) {
    springs_[k].evaluate(nodes[k], nodes[k + 1], &f, nullptr, SpringTangent::Exact);
    force.segment<12>(6 * k) += f;
  }
  if (description_.gravity_enabled)
    for (size_t k = 1; k < nodes.size(); ++k) force[6 * k + 2] -= mass_[k] * kGravity;
  for (size_t a = 0; a < actuators_.size(); ++a)
    if (actuation[a] != 0.0) actuators_[a]->addGradient(nodes, actuation[a], force);
  force.segment<3>(6 * (nodes.size() - 1)) += tip_force_;
}

void ContinuumRobotModel::computeLoadHessians() {
  // d^2 m_piece / dq^2 of each actuator piece (unit actuation) by forward differences of its
  // gradient (relative error ~1e-6, ample for a Newton tangent), symmetrized. A piece's measure
  // is invariant under a common translation of its two rigid nodes (it depends on relative
  // geometry only), so its gradient is too: the columns of the distal node's translation are
  // minus those of the proximal node's, and are not differenced.
  const double h_x = 1e-6 * description_.vertebra_spacing, h_r = 1e-6;
  Eigen::Matrix<double, 12, 1> g0, g;
  for (int a = 0; a < numActuators(); ++a) {
    const ChainActuator& act = *actuators_[a];
    for (int piece = 0; piece < act.numPieces(); ++piece) {
      const int i0 = act.pieceFirstNode(piece);
      Eigen::Matrix<double, 12, 12>& H = load_hessian_[load_hessian_begin_[a] + piece];
      g0.setZero();
      act.addPieceGradient(nodes_, piece, 1.0, g0);
      trial_[i0] = nodes_[i0];
      trial_[i0 + 1] = nodes_[i0 + 1];
      for (int d = 0; d < 12; ++d) {
        if (d >= 6 && d < 9) {
          H.col(d) = -H.col(d - 6);
          continue;
        }
        const int node = i0 + d / 6, c = d % 6;
        const double h = c < 3 ? h_x : h_r;
        RigidNodePose& p = trial_[node];
        if (c < 3)
          p.p_BN[c] += h;
        else
          p.q_BN = expRotation(h * Eigen::Vector3d::Unit(c - 3)) * p.q_BN;
        g.setZero();
        act.addPieceGradient(trial_, piece, 1.0, g);
        H.col(d) = (g - g0) / h;
        p = nodes_[node];
      }
      if (i0 == 0) H.topRows<6>().setZero(), H.leftCols<6>().setZero();
      H = 0.5 * (H + H.transpose()).eval();
    }
  }
  load_hessian_valid_ = true;
}

bool ContinuumRobotModel::assembleTangent(SpringTangent mode, const Eigen::VectorXd& actuation) {
  tangent_.setZero();
  Eigen::Matrix<double, 12, 12> K;
  const auto addBlock = [&](int first_node, const Eigen::Matrix<double, 12, 12>& Ks) {
    tangent_.diagonal(first_node) += Ks.block<6, 6>(6, 6);
    if (first_node > 0) {
      tangent_.diagonal(first_node - 1) += Ks.block<6, 6>(0, 0);
      tangent_.lower(first_node - 1) += Ks.block<6, 6>(6, 0);
    }
  };
  for (int k = 0; k < static_cast<int>(springs_.size()); ++k) {
    springs_[k].evaluate(nodes_[k], nodes_[k + 1], nullptr, &K, mode);
    addBlock(k, 0.5 * (K + K.transpose()));
  }
  if (mode == SpringTangent::Exact)  // load stiffness -lambda d^2m/dq^2 (cached unit Hessians)
    for (int a = 0; a < numActuators(); ++a) {
      if (actuation[a] == 0.0) continue;
      const ChainActuator& act = *actuators_[a];
      for (int piece = 0; piece < act.numPieces(); ++piece)
        addBlock(act.pieceFirstNode(piece),
                 -actuation[a] * load_hessian_[load_hessian_begin_[a] + piece]);
    }
  return tangent_.factorize();
}

bool ContinuumRobotModel::factorizeTangent(const Eigen::VectorXd& actuation) {
  computeLoadHessians();
  return factorizeCachedTangent(actuation);
}

bool ContinuumRobotModel::factorizeCachedTangent(const Eigen::VectorXd& actuation) {
  if (!load_hessian_valid_) computeLoadHessians();
  return assembleTangent(SpringTangent::Exact, actuation) ||
         assembleTangent(SpringTangent::GaussNewton, actuation);
}

void ContinuumRobotModel::actuatorJacobianRow(int a, Eigen::Ref<Eigen::VectorXd> row) {
  full_.setZero();
  actuators_[a]->addGradient(nodes_, 1.0, full_);
  row = full_.tail(numDofs());
}

ModelSolveReport ContinuumRobotModel::solveEquilibrium(const Eigen::VectorXd& actuation,
                                                       const ModelSolveSettings& settings) {
  ModelSolveReport report;
  report.status = StepStatus::NotConverged;
  backup_ = nodes_;
  const auto restore = [&](StepStatus s) {
    nodes_ = backup_;
    report.status = s;
    return report;
  };
  Eigen::Matrix<double, 12, 1> f;
  for (int it = 0; it <= settings.max_iterations; ++it) {
    generalizedForce(nodes_, actuation, full_);
    const double r = full_.tail(numDofs()).norm();
    double scale = r + tip_force_.norm();
    for (size_t k = 0; k < springs_.size(); ++k) {
      springs_[k].evaluate(nodes_[k], nodes_[k + 1], &f, nullptr, SpringTangent::Exact);
      scale += f.norm();
    }
    report.residual = r;
    report.iterations = it;
    if (!std::isfinite(r)) return restore(StepStatus::NonFinite);
    if (r <= settings.relative_tolerance * scale + force_floor_) {
      report.status = StepStatus::Ok;
      return report;
    }
    if (it == settings.max_iterations) break;
    step_ = full_.tail(numDofs());
    residual_ = step_;
    if (!factorizeCachedTangent(actuation)) return restore(StepStatus::SolverFailed);
    tangent_.solve(step_);
    // Full step if it lowers the residual; otherwise Armijo backtracking on the potential.
    applyStep(nodes_, step_, 1.0, trial_);
    generalizedForce(trial_, actuation, full_);
    bool accepted = full_.allFinite() && full_.tail(numDofs()).norm() < r;
    if (!accepted) {
      const double slope = -step_.dot(residual_);
      const double pi0 = potential(nodes_, actuation);
      double alpha = 1.0;
      for (int h = 0; h < 30 && !accepted; ++h, alpha *= 0.5) {
        applyStep(nodes_, step_, alpha, trial_);
        const double pi = potential(trial_, actuation);
        accepted = std::isfinite(pi) && pi <= pi0 + 1e-4 * alpha * slope;
      }
    }
    if (!accepted) break;
    nodes_.swap(trial_);
  }
  return report;
}

}  // namespace surgical_sim::core
