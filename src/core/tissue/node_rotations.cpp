// TissueModel::nodeRotations of the models with deformation gradients at integration points: the
// rotation of node i is the signed polar rotation of sum_p w_p F_p over the points p whose shape
// functions include node i.
#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/tissue/efg_model.h"
#include "surgical_sim/core/tissue/fe_model.h"
#include "surgical_sim/core/tissue/signed_svd.h"

namespace surgical_sim::core {
namespace {

/// Sizes moments to n zero matrices.
void startMoments(int n, std::vector<Eigen::Matrix3d>& moments) {
  moments.resize(static_cast<size_t>(n));
  for (Eigen::Matrix3d& M : moments) M.setZero();
}

/// Adds w F to the moments of the point's nodes, F = sum_a x_{nodes[a]} G.row(a), G the count x 3
/// column-major rest gradients [1/m], w the point's weight [m^3].
void addPointMoment(const Eigen::VectorXd& x, const int* nodes, int count, const double* gradients,
                    double w, std::vector<Eigen::Matrix3d>& moments) {
  const Eigen::Map<const Eigen::MatrixXd> G(gradients, count, 3);
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  for (int a = 0; a < count; ++a) F.noalias() += x.segment<3>(3 * nodes[a]) * G.row(a);
  for (int a = 0; a < count; ++a) moments[static_cast<size_t>(nodes[a])] += w * F;
}

/// Replaces each moment by its signed polar rotation (identity for a zero moment).
void finishRotations(std::vector<Eigen::Matrix3d>& moments) {
  for (Eigen::Matrix3d& M : moments) {
    M = M.isZero(0.0) ? Eigen::Matrix3d::Identity() : computeSignedRotation(M);
  }
}

}  // namespace

bool FeModel::nodeRotations(const Eigen::VectorXd& x,
                            std::vector<Eigen::Matrix3d>& rotations) const {
  startMoments(numNodes(), rotations);
  const size_t stride = static_cast<size_t>(nodes_per_element_) * 3;
  for (int e = 0; e < elements_.cols(); ++e) {
    for (int q = 0; q < points_per_element_; ++q) {
      const size_t k = static_cast<size_t>(e) * points_per_element_ + q;
      addPointMoment(x, &elements_(0, e), nodes_per_element_, rest_gradients_.data() + k * stride,
                     weight_det_j_[k], rotations);
    }
  }
  finishRotations(rotations);
  return true;
}

bool EfgModel::nodeRotations(const Eigen::VectorXd& x,
                             std::vector<Eigen::Matrix3d>& rotations) const {
  startMoments(numNodes(), rotations);
  for (int e = 0; e < numIntegrationPoints(); ++e) {
    const std::vector<int>& particles = ipParticles(e);
    addPointMoment(x, particles.data(), static_cast<int>(particles.size()),
                   shapeGradients(e).data(), grid_.volumes(e), rotations);
  }
  finishRotations(rotations);
  return true;
}

}  // namespace surgical_sim::core
