#include "surgical_sim/core/robot/embedded_point.h"

#include <Eigen/Dense>

namespace surgical_sim::core {

std::optional<EmbeddedPoint> embedPoint(const TetMesh& mesh, const Eigen::Vector3d& p) {
  for (int e = 0; e < mesh.numElements(); ++e) {
    Eigen::Matrix3d D;
    const Eigen::Vector3d x0 = mesh.nodes.col(mesh.elements(0, e));
    for (int a = 0; a < 3; ++a) D.col(a) = mesh.nodes.col(mesh.elements(a + 1, e)) - x0;
    const Eigen::Vector3d b = D.partialPivLu().solve(p - x0);
    const double b0 = 1.0 - b.sum();
    if (b.minCoeff() >= -1e-9 && b0 >= -1e-9)
      return EmbeddedPoint{mesh.elements.col(e).head<4>(), Eigen::Vector4d(b0, b[0], b[1], b[2])};
  }
  return std::nullopt;
}

}  // namespace surgical_sim::core
