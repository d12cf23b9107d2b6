#include "surgical_sim/core/tissue/psd_projection.h"

#include <Eigen/Eigenvalues>

namespace surgical_sim::core {
namespace {

template <int N>
void projectFixed(Eigen::Matrix<double, N, N>& A) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Matrix sym = 0.5 * (A + A.transpose());
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(sym);
  if (eig.eigenvalues().minCoeff() >= 0.0) {
    A = sym;
    return;
  }
  const Eigen::Matrix<double, N, 1> clamped = eig.eigenvalues().cwiseMax(0.0);
  A.noalias() = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

void projectToPsd(Eigen::Matrix<double, 9, 9>& A) { projectFixed<9>(A); }
void projectToPsd(Eigen::Matrix<double, 12, 12>& A) { projectFixed<12>(A); }

}  // namespace surgical_sim::core
