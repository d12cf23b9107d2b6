#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

/// A point embedded in a Tet4 mesh: fixed barycentric weights on the corners of the element that
/// contains it at rest, so it follows the deformed mesh as p(x) = sum_a weights[a] x_corners[a].
struct EmbeddedPoint {
  Eigen::Vector4i corners;  ///< node indices of the containing element
  Eigen::Vector4d weights;  ///< barycentric weights [-], sum 1, each >= -1e-9

  /// Current position [m] from the stacked node positions x (size 3 numNodes) [m].
  Eigen::Vector3d position(const Eigen::VectorXd& x) const {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) p += weights[a] * x.segment<3>(3 * corners[a]);
    return p;
  }
};

/// First element of `mesh` containing p (boundary included, tolerance 1e-9 in barycentric
/// coordinates); nullopt if none. Linear search over the elements (set-up time only).
std::optional<EmbeddedPoint> embedPoint(const TetMesh& mesh, const Eigen::Vector3d& p);

/// embedPoint for every point.
/// @param name parameter name used in the error, e.g. "tendon.eyelets".
/// @throws std::invalid_argument "<name>[i] lies in no element of the mesh".
std::vector<EmbeddedPoint> embedPoints(const TetMesh& mesh,
                                       const std::vector<Eigen::Vector3d>& points,
                                       const std::string& name);

}  // namespace surgical_sim::core
