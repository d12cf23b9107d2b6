#pragma once

#include <Eigen/Core>

#include "surgical_sim/core/tissue/hyperelastic_law.h"

namespace surgical_sim::core {

/// Ke += w G^T A G for one quadrature point, with G = d vec(F) / d x_e the map from the k nodal
/// positions to the deformation gradient F = x_e grad: Ke(3a+i, 3b+j) += w sum_kl grad(a,k)
/// A(i+3k, j+3l) grad(b,l), computed block-wise without forming the 9 x 3k matrix G.
/// @param A tangent dP/dF [Pa] (HyperelasticLaw layout).
/// @param grad rest shape-function gradients dN_a/dX [1/m], k x 3.
/// @param w quadrature weight times rest volume [m^3].
/// @param Ke element matrix [N/m], 3k x 3k (added to).
template <typename Gradients, typename ElementMatrix>
void addPointStiffness(const Matrix9d& A, const Gradients& grad, double w, ElementMatrix& Ke) {
  const auto k = static_cast<int>(grad.rows());
  for (int b = 0; b < k; ++b) {
    Eigen::Matrix<double, 9, 3> AG = (w * grad(b, 0)) * A.template middleCols<3>(0);
    AG.noalias() += (w * grad(b, 1)) * A.template middleCols<3>(3);
    AG.noalias() += (w * grad(b, 2)) * A.template middleCols<3>(6);
    for (int a = 0; a < k; ++a) {
      Ke.template block<3, 3>(3 * a, 3 * b) += grad(a, 0) * AG.template middleRows<3>(0) +
                                               grad(a, 1) * AG.template middleRows<3>(3) +
                                               grad(a, 2) * AG.template middleRows<3>(6);
    }
  }
}

}  // namespace surgical_sim::core
