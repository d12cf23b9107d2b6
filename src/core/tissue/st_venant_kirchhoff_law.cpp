#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"

#include "surgical_sim/core/tissue/psd_projection.h"

namespace surgical_sim::core {

StVenantKirchhoffLaw::StVenantKirchhoffLaw(const Material& material) {
  const Material m = Material::validated(material);
  mu_ = m.mu();
  lambda_ = m.lambda();
}

double StVenantKirchhoffLaw::energyDensity(const Eigen::Matrix3d& F) const {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  const double tr = E.trace();
  return 0.5 * lambda_ * tr * tr + mu_ * E.squaredNorm();
}

Eigen::Matrix3d StVenantKirchhoffLaw::firstPiola(const Eigen::Matrix3d& F) const {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d S = lambda_ * E.trace() * Eigen::Matrix3d::Identity() + 2.0 * mu_ * E;
  return F * S;
}

Matrix9d StVenantKirchhoffLaw::firstPiolaDerivative(const Eigen::Matrix3d& F) const {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d S = lambda_ * E.trace() * Eigen::Matrix3d::Identity() + 2.0 * mu_ * E;
  Matrix9d dPdF;
  for (int l = 0; l < 3; ++l) {
    for (int k = 0; k < 3; ++k) {
      // dF = e_k e_l^T: F^T dF has column l equal to row k of F (as a column).
      Eigen::Matrix3d FtdF = Eigen::Matrix3d::Zero();
      FtdF.col(l) = F.row(k).transpose();
      const Eigen::Matrix3d dE = 0.5 * (FtdF + FtdF.transpose());
      const Eigen::Matrix3d dS =
          lambda_ * dE.trace() * Eigen::Matrix3d::Identity() + 2.0 * mu_ * dE;
      Eigen::Matrix3d dP = F * dS;
      dP.row(k) += S.row(l);  // dF S = e_k (row l of S)
      dPdF.col(k + 3 * l) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
    }
  }
  return dPdF;
}

Matrix9d StVenantKirchhoffLaw::projectedFirstPiolaDerivative(const Eigen::Matrix3d& F) const {
  Matrix9d dPdF = firstPiolaDerivative(F);
  projectToPsd(dPdF);
  return dPdF;
}

}  // namespace surgical_sim::core
