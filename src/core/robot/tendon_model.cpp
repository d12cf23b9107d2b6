#include "surgical_sim/core/robot/tendon_model.h"

#include <Eigen/Dense>
#include <stdexcept>

#include "surgical_sim/core/robot/embedded_point.h"

namespace surgical_sim::core {

TendonModel::TendonModel(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& eyelets) {
  if (eyelets.size() < 2) throw std::invalid_argument("tendon.eyelets must hold at least 2 points");
  const int n = mesh.numNodes();
  rest_.resize(3 * n);
  for (int i = 0; i < n; ++i) rest_.segment<3>(3 * i) = mesh.nodes.col(i);
  mass_ = Eigen::VectorXd::Zero(3 * n);
  for (const EmbeddedPoint& e : embedPoints(mesh, eyelets, "tendon.eyelets")) {
    corners_.push_back(e.corners);
    weights_.push_back(e.weights);
  }
  std::vector<Eigen::Triplet<double>> t;
  for (size_t k = 0; k + 1 < corners_.size(); ++k)
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        for (int c = 0; c < 3; ++c)
          for (int d = 0; d < 3; ++d) {
            const int na = a < 4 ? corners_[k][a] : corners_[k + 1][a - 4];
            const int nb = b < 4 ? corners_[k][b] : corners_[k + 1][b - 4];
            t.emplace_back(3 * na + c, 3 * nb + d, 0.0);
          }
  pattern_.resize(3 * n, 3 * n);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
}

Eigen::Vector3d TendonModel::eyelet(const Eigen::VectorXd& x, int k) const {
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  for (int a = 0; a < 4; ++a) e += weights_[k][a] * x.segment<3>(3 * corners_[k][a]);
  return e;
}

Eigen::VectorXd TendonModel::bodyForce(const Eigen::Vector3d&) const {
  return Eigen::VectorXd::Zero(rest_.size());
}

double TendonModel::energy(const Eigen::VectorXd& x) const {
  double length = 0.0;
  for (size_t k = 0; k + 1 < corners_.size(); ++k)
    length += (eyelet(x, k + 1) - eyelet(x, k)).norm();
  return tension_ * length;
}

void TendonModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  for (int k = 0; k + 1 < static_cast<int>(corners_.size()); ++k) {
    const Eigen::Vector3d u = (eyelet(x, k + 1) - eyelet(x, k)).normalized();
    for (int a = 0; a < 4; ++a) {
      f.segment<3>(3 * corners_[k][a]) += tension_ * weights_[k][a] * u;
      f.segment<3>(3 * corners_[k + 1][a]) -= tension_ * weights_[k + 1][a] * u;
    }
  }
}

void TendonModel::assembleStiffness(const Eigen::VectorXd& x, TangentMode,
                                    Eigen::SparseMatrix<double>& K) const {
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  for (int k = 0; k + 1 < static_cast<int>(corners_.size()); ++k) {
    const Eigen::Vector3d d = eyelet(x, k + 1) - eyelet(x, k);
    const double l = d.norm();
    const Eigen::Vector3d u = d / l;
    const Eigen::Matrix3d G = tension_ / l * (Eigen::Matrix3d::Identity() - u * u.transpose());
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const int na = a < 4 ? corners_[k][a] : corners_[k + 1][a - 4];
        const int nb = b < 4 ? corners_[k][b] : corners_[k + 1][b - 4];
        const double wa = a < 4 ? -weights_[k][a] : weights_[k + 1][a - 4];
        const double wb = b < 4 ? -weights_[k][b] : weights_[k + 1][b - 4];
        for (int c = 0; c < 3; ++c)
          for (int e = 0; e < 3; ++e) K.coeffRef(3 * na + c, 3 * nb + e) += wa * wb * G(c, e);
      }
  }
}

void TendonModel::applyStiffness(const Eigen::VectorXd& x, TangentMode, const Eigen::VectorXd& v,
                                 Eigen::VectorXd& y) const {
  y.setZero();
  for (int k = 0; k + 1 < static_cast<int>(corners_.size()); ++k) {
    const Eigen::Vector3d d = eyelet(x, k + 1) - eyelet(x, k);
    const double l = d.norm();
    const Eigen::Vector3d u = d / l;
    const Eigen::Vector3d dv = eyelet(v, k + 1) - eyelet(v, k);
    const Eigen::Vector3d g = tension_ / l * (dv - u * u.dot(dv));
    for (int a = 0; a < 4; ++a) {
      y.segment<3>(3 * corners_[k][a]) -= weights_[k][a] * g;
      y.segment<3>(3 * corners_[k + 1][a]) += weights_[k + 1][a] * g;
    }
  }
}

}  // namespace surgical_sim::core
