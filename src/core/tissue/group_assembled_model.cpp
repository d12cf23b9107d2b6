#include "surgical_sim/core/tissue/group_assembled_model.h"

#include <algorithm>
#include <stdexcept>

namespace surgical_sim::core {

void GroupAssembledModel::assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                            Eigen::SparseMatrix<double>& K) const {
  addGroupStiffness(x, mode, nullptr, zeroedValues(K));
}

void GroupAssembledModel::addInternalForceAndStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                                       Eigen::VectorXd& f,
                                                       Eigen::SparseMatrix<double>& K) const {
  addGroupStiffness(x, mode, &f, zeroedValues(K));
}

void GroupAssembledModel::setGroups(int num_nodes, const Eigen::MatrixXi& groups) {
  Eigen::SparseMatrix<double> pattern = makeBlockPattern(num_nodes, groups);
  pattern_.swap(pattern);  // Eigen's SparseMatrix has no move assignment: it would copy
  scatter_ = BlockScatterMap(pattern_, groups);
  schedule_ = GroupSchedule(num_nodes, groups, defaultThreadCount());
}

void GroupAssembledModel::growPattern(const std::vector<std::vector<int>>& added) {
  const auto size = 3 * static_cast<Eigen::Index>(added.size());
  if (pattern_.rows() == 0) pattern_.resize(size, size);
  growBlockPattern(added, pattern_);
}

double* GroupAssembledModel::zeroedValues(Eigen::SparseMatrix<double>& K) const {
  if (K.rows() != pattern_.rows() || K.cols() != pattern_.cols() ||
      K.nonZeros() != pattern_.nonZeros() || !K.isCompressed()) {
    throw std::invalid_argument(name() + " model: K must have stiffnessPattern()");
  }
  double* values = K.valuePtr();
  std::fill(values, values + K.nonZeros(), 0.0);
  return values;
}

}  // namespace surgical_sim::core
