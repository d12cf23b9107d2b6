#include "surgical_sim/core/robot/summed_tissue_model.h"

#include <algorithm>
#include <stdexcept>

namespace surgical_sim::core {

SummedTissueModel::SummedTissueModel(std::vector<std::unique_ptr<TissueModel>> parts)
    : parts_(std::move(parts)) {
  if (parts_.empty())
    throw std::invalid_argument("summed_tissue_model.parts must hold at least one model");
  const Eigen::VectorXd& x0 = parts_[0]->restPositions();
  for (const auto& p : parts_)
    if (!p || p->restPositions().size() != x0.size() ||
        (p->restPositions() - x0).cwiseAbs().maxCoeff() > 0.0)
      throw std::invalid_argument("summed_tissue_model.parts must share the same rest nodes");
  mass_ = Eigen::VectorXd::Zero(x0.size());
  for (const auto& p : parts_) mass_ += p->lumpedMass();
  pattern_ = parts_[0]->stiffnessPattern();
  for (size_t i = 1; i < parts_.size(); ++i) pattern_ = pattern_ + parts_[i]->stiffnessPattern();
  pattern_.makeCompressed();
  for (const auto& p : parts_) {
    const Eigen::SparseMatrix<double>& P = p->stiffnessPattern();
    part_k_.push_back(P);
    std::vector<int> map(P.nonZeros());
    for (int col = 0; col < P.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(P, col); it; ++it) {
        const int* begin = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[col];
        const int* end = pattern_.innerIndexPtr() + pattern_.outerIndexPtr()[col + 1];
        const int* pos = std::lower_bound(begin, end, static_cast<int>(it.row()));
        map[&it.value() - P.valuePtr()] = static_cast<int>(pos - pattern_.innerIndexPtr());
      }
    scatter_.push_back(std::move(map));
  }
  work_.resize(x0.size());
}

Eigen::VectorXd SummedTissueModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f = parts_[0]->bodyForce(a);
  for (size_t i = 1; i < parts_.size(); ++i) f += parts_[i]->bodyForce(a);
  return f;
}

double SummedTissueModel::energy(const Eigen::VectorXd& x) const {
  double e = 0.0;
  for (const auto& p : parts_) e += p->energy(x);
  return e;
}

void SummedTissueModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  for (const auto& p : parts_) p->addInternalForce(x, f);
}

void SummedTissueModel::assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                          Eigen::SparseMatrix<double>& K) const {
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  for (size_t i = 0; i < parts_.size(); ++i) {
    parts_[i]->assembleStiffness(x, mode, part_k_[i]);
    const double* v = part_k_[i].valuePtr();
    for (size_t k = 0; k < scatter_[i].size(); ++k) K.valuePtr()[scatter_[i][k]] += v[k];
  }
}

void SummedTissueModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                       const Eigen::VectorXd& v, Eigen::VectorXd& y) const {
  y.setZero();
  for (const auto& p : parts_) {
    p->applyStiffness(x, mode, v, work_);
    y += work_;
  }
}

}  // namespace surgical_sim::core
