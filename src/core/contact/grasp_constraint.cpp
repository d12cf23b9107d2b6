#include "surgical_sim/core/contact/grasp_constraint.h"

#include <algorithm>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

GraspConstraint::GraspConstraint(double grasp_radius) : grasp_radius_(grasp_radius) {
  requirePositive("tool.grasp_radius", grasp_radius, "m");
}

void GraspConstraint::update(bool closed, const Eigen::Isometry3d& X_ST,
                             const SurfaceMapping& mapping, const Eigen::VectorXd& x,
                             const std::vector<std::uint8_t>& fixed_mask) {
  if (closed == closed_) return;
  closed_ = closed;
  nodes_.clear();
  p_TN_.clear();
  if (!closed) return;
  const Eigen::Isometry3d X_TS = X_ST.inverse();
  const double radius_squared = grasp_radius_ * grasp_radius_;
  for (const int vertex : mapping.vertices()) {
    if ((mapping.vertexValue(vertex, x) - X_ST.translation()).squaredNorm() > radius_squared)
      continue;
    const SurfaceMapping::Row row = mapping.row(vertex);
    for (int j = 0; j < row.size; ++j) {
      const int node = row.nodes[j];
      const auto d = static_cast<size_t>(3 * node);
      if (row.weights[j] == 0.0 || fixed_mask[d] != 0 || fixed_mask[d + 1] != 0 ||
          fixed_mask[d + 2] != 0 || std::find(nodes_.begin(), nodes_.end(), node) != nodes_.end())
        continue;
      nodes_.push_back(node);
      p_TN_.push_back(X_TS * x.segment<3>(3 * node));
    }
  }
}

void GraspConstraint::appendDofs(std::vector<int>& dofs) const {
  if (!closed_) return;
  for (const int node : nodes_) {
    for (int c = 0; c < 3; ++c) dofs.push_back(3 * node + c);
  }
}

void GraspConstraint::writeTargets(const Eigen::Isometry3d& X_ST,
                                   Eigen::Ref<Eigen::VectorXd> positions) const {
  if (!closed_) return;
  for (size_t k = 0; k < nodes_.size(); ++k) {
    positions.segment<3>(static_cast<Eigen::Index>(3 * k)) = X_ST * p_TN_[k];
  }
}

Eigen::Vector3d GraspConstraint::toolForce(const Eigen::VectorXd& force) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  if (!closed_) return sum;
  for (const int node : nodes_) sum += force.segment<3>(3 * node);
  return sum;
}

}  // namespace surgical_sim::core
