#include "surgical_sim/core/tissue/tissue_mesh_check.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace surgical_sim::core {

double signedTetVolume(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                       const Eigen::Vector3d& p2, const Eigen::Vector3d& p3) {
  return (p1 - p0).dot((p2 - p0).cross(p3 - p0)) / 6.0;
}

void checkTissueMesh(const TetMesh& mesh, const std::string& model, bool allow_tet10) {
  const bool tet10 = mesh.type == ElementType::Tet10;
  if (tet10 && !allow_tet10) {
    throw std::invalid_argument("tissue.model = '" + model +
                                "' requires tet4 elements (mesh.type = tet10 is not supported)");
  }
  const int npe = tet10 ? 10 : 4;
  if (mesh.numElements() == 0) {
    throw std::invalid_argument("mesh.elements is empty: a tissue model needs >= 1 element");
  }
  if (mesh.elements.rows() != npe) {
    std::ostringstream msg;
    msg << "mesh.elements has " << mesh.elements.rows() << " rows, expected " << npe << " for "
        << (tet10 ? "tet10" : "tet4");
    throw std::invalid_argument(msg.str());
  }
  if (!mesh.nodes.allFinite()) throw std::invalid_argument("mesh.nodes must all be finite [m]");
  for (int e = 0; e < mesh.numElements(); ++e) {
    for (int a = 0; a < npe; ++a) {
      const int node = mesh.elements(a, e);
      if (node < 0 || node >= mesh.numNodes()) {
        std::ostringstream msg;
        msg << "mesh.elements: element " << e << " references node " << node
            << ", out of range [0, " << mesh.numNodes() << ")";
        throw std::invalid_argument(msg.str());
      }
    }
    const Eigen::Vector3d p0 = mesh.nodes.col(mesh.elements(0, e));
    const Eigen::Vector3d p1 = mesh.nodes.col(mesh.elements(1, e));
    const Eigen::Vector3d p2 = mesh.nodes.col(mesh.elements(2, e));
    const Eigen::Vector3d p3 = mesh.nodes.col(mesh.elements(3, e));
    const double volume = signedTetVolume(p0, p1, p2, p3);
    // sqrt is monotonic: one root of the longest squared edge.
    const double l_max = std::sqrt(
        std::max({(p1 - p0).squaredNorm(), (p2 - p0).squaredNorm(), (p3 - p0).squaredNorm(),
                  (p2 - p1).squaredNorm(), (p3 - p2).squaredNorm(), (p3 - p1).squaredNorm()}));
    if (!(6.0 * volume > 1e-10 * l_max * l_max * l_max)) {
      std::ostringstream msg;
      msg << "mesh.elements: element " << e << " is " << (volume < 0.0 ? "inverted" : "degenerate")
          << " (signed rest volume " << volume << " m^3; must be > 0 with 6 V / l_max^3 > 1e-10)";
      throw std::invalid_argument(msg.str());
    }
  }
}

}  // namespace surgical_sim::core
