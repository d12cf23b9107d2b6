#include "surgical_sim/core/robot/tube_mesh.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

TetMesh makeTubeMesh(const std::vector<double>& stations, double inner_radius,
                     double outer_radius_start, double outer_radius_end, int radial_layers,
                     int circumferential_segments) {
  if (stations.size() < 2)
    throw std::invalid_argument("makeTubeMesh: stations must hold at least 2 positions");
  for (size_t s = 0; s < stations.size(); ++s) {
    requireFinite("makeTubeMesh: stations[" + std::to_string(s) + "]", stations[s], "m");
    if (s > 0 && stations[s] <= stations[s - 1])
      throw std::invalid_argument("makeTubeMesh: stations must be strictly increasing");
  }
  requirePositive("makeTubeMesh: inner_radius", inner_radius, "m");
  requireInRange("makeTubeMesh: outer_radius_start", outer_radius_start, inner_radius * 1.000001,
                 1e6, "m");
  requireInRange("makeTubeMesh: outer_radius_end", outer_radius_end, inner_radius * 1.000001, 1e6,
                 "m");
  requireInRange("makeTubeMesh: radial_layers", radial_layers, 1, 1000, "");
  requireInRange("makeTubeMesh: circumferential_segments", circumferential_segments, 6, 100000, "");

  const int n_st = static_cast<int>(stations.size());
  const int R = radial_layers;
  const int C = circumferential_segments;
  const double x0 = stations.front();
  const double span = stations.back() - x0;
  const auto index = [&](int s, int i, int j) { return (s * (R + 1) + i) * C + (j % C); };

  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, n_st * (R + 1) * C);
  for (int s = 0; s < n_st; ++s) {
    const double t = (stations[s] - x0) / span;
    const double r_out = outer_radius_start + (outer_radius_end - outer_radius_start) * t;
    for (int i = 0; i <= R; ++i) {
      const double r = inner_radius + (r_out - inner_radius) * i / R;
      for (int j = 0; j < C; ++j) {
        const double a = 2.0 * M_PI * j / C;
        mesh.nodes.col(index(s, i, j)) =
            Eigen::Vector3d(stations[s], r * std::cos(a), r * std::sin(a));
      }
    }
  }
  // Kuhn split: one tet per permutation of the (r, theta, x) axes, from corner 000 to 111.
  static constexpr int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                      {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  mesh.elements.resize(4, 6 * R * C * (n_st - 1));
  int e = 0;
  for (int s = 0; s + 1 < n_st; ++s)
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j)
        for (const auto& perm : kPerm) {
          int offset[3] = {0, 0, 0};
          Eigen::Vector4i tet;
          tet[0] = index(s, i, j);
          for (int k = 0; k < 3; ++k) {
            offset[perm[k]] = 1;
            tet[k + 1] = index(s + offset[2], i + offset[0], j + offset[1]);
          }
          const Eigen::Vector3d a = mesh.nodes.col(tet[1]) - mesh.nodes.col(tet[0]);
          const Eigen::Vector3d b = mesh.nodes.col(tet[2]) - mesh.nodes.col(tet[0]);
          const Eigen::Vector3d c = mesh.nodes.col(tet[3]) - mesh.nodes.col(tet[0]);
          if (a.cross(b).dot(c) < 0.0) std::swap(tet[1], tet[2]);
          mesh.elements.col(e++) = tet;
        }
  return mesh;
}

}  // namespace surgical_sim::core
