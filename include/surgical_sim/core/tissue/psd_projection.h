#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Projects a symmetric matrix onto the positive semi-definite cone in place: eigen-decomposes
/// A = Q diag(d) Q^T and replaces d by max(d, 0). A is symmetrised first. Allocation-free.
/// Shapes: 9 x 9 (constitutive tangents) and 12 x 12 (Tet4 element stiffness).
void projectToPsd(Eigen::Matrix<double, 9, 9>& A);
void projectToPsd(Eigen::Matrix<double, 12, 12>& A);

}  // namespace surgical_sim::core
