#include "surgical_sim/core/robot/embedded_point.h"

#include <Eigen/Dense>
#include <stdexcept>

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

std::vector<EmbeddedPoint> embedPoints(const TetMesh& mesh,
                                       const std::vector<Eigen::Vector3d>& points,
                                       const std::string& name) {
  std::vector<EmbeddedPoint> out;
  for (size_t k = 0; k < points.size(); ++k) {
    const std::optional<EmbeddedPoint> point = embedPoint(mesh, points[k]);
    if (!point)
      throw std::invalid_argument(name + "[" + std::to_string(k) +
                                  "] lies in no element of the mesh");
    out.push_back(*point);
  }
  return out;
}

}  // namespace surgical_sim::core
