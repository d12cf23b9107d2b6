#include "surgical_sim/core/robot/pressure_chamber_actuator.h"

#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

PressureChamberActuator::PressureChamberActuator(const PressureChamberDescription& chamber,
                                                 const ContinuumRobotDescription& robot,
                                                 int angular_segments, int axial_segments)
    : name_(chamber.name),
      lower_(chamber.pressure_min),
      upper_(chamber.pressure_max),
      first_gap_(chamber.first_gap) {
  requireInRange("pressure_chamber.angular_segments", angular_segments, 3, 4096, "");
  requireInRange("pressure_chamber.axial_segments", axial_segments, 1, 4096, "");
  const int M = angular_segments;
  const double half_t = 0.5 * robot.vertebra_thickness;
  const double ell = robot.vertebra_spacing - robot.vertebra_thickness;
  const Eigen::Vector3d axis(0.0, chamber.radial_offset * std::cos(chamber.angle),
                             chamber.radial_offset * std::sin(chamber.angle));
  for (int gap = chamber.first_gap; gap <= chamber.last_gap; ++gap) {
    piece_begin_.push_back(static_cast<int>(triangles_.size()));
    vertex_begin_.push_back(static_cast<int>(vertices_.size()));
    const int base = static_cast<int>(vertices_.size());
    const auto add = [&](double t, const Eigen::Vector3d& yz) {
      Vertex v;
      v.node_a = gap;
      v.t = t;
      const double x_local = half_t + t * ell;  // from node a
      v.a_A = Eigen::Vector3d(x_local, 0.0, 0.0) + yz;
      v.b_B = Eigen::Vector3d(x_local - robot.vertebra_spacing, 0.0, 0.0) + yz;
      vertices_.push_back(v);
    };
    for (int s = 0; s <= axial_segments; ++s)
      for (int j = 0; j < M; ++j) {
        const double a = 2.0 * M_PI * j / M;
        add(static_cast<double>(s) / axial_segments,
            axis + chamber.radius * Eigen::Vector3d(0.0, std::cos(a), std::sin(a)));
      }
    const int c0 = static_cast<int>(vertices_.size());
    add(0.0, axis);
    const int c1 = static_cast<int>(vertices_.size());
    add(1.0, axis);
    const auto ring = [&](int s, int j) { return base + s * M + (j % M); };
    for (int s = 0; s < axial_segments; ++s)
      for (int j = 0; j < M; ++j) {
        triangles_.emplace_back(ring(s, j), ring(s, j + 1), ring(s + 1, j + 1));
        triangles_.emplace_back(ring(s, j), ring(s + 1, j + 1), ring(s + 1, j));
      }
    for (int j = 0; j < M; ++j) {
      triangles_.emplace_back(c0, ring(0, j + 1), ring(0, j));
      triangles_.emplace_back(c1, ring(axial_segments, j), ring(axial_segments, j + 1));
    }
  }
  piece_begin_.push_back(static_cast<int>(triangles_.size()));
  vertex_begin_.push_back(static_cast<int>(vertices_.size()));
  const size_t per_gap = static_cast<size_t>(vertex_begin_[1] - vertex_begin_[0]);
  r_a_.resize(per_gap);
  r_b_.resize(per_gap);
  p_.resize(per_gap);
  f_.resize(per_gap);
}

Eigen::Vector3d PressureChamberActuator::position(const std::vector<RigidNodePose>& nodes,
                                                  const Vertex& v) const {
  const RigidNodePose& A = nodes[v.node_a];
  const RigidNodePose& B = nodes[v.node_a + 1];
  return (1.0 - v.t) * (A.p_BN + A.q_BN * v.a_A) + v.t * (B.p_BN + B.q_BN * v.b_B);
}

std::vector<Eigen::Vector3d> PressureChamberActuator::vertexPositions(
    const std::vector<RigidNodePose>& nodes) const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(vertices_.size());
  for (const Vertex& v : vertices_) out.push_back(position(nodes, v));
  return out;
}

double PressureChamberActuator::measure(const std::vector<RigidNodePose>& nodes) const {
  double six_v = 0.0;
  for (const Eigen::Vector3i& tri : triangles_) {
    const Eigen::Vector3d p0 = position(nodes, vertices_[tri[0]]);
    const Eigen::Vector3d p1 = position(nodes, vertices_[tri[1]]);
    const Eigen::Vector3d p2 = position(nodes, vertices_[tri[2]]);
    six_v += p0.dot(p1.cross(p2));
  }
  return six_v / 6.0;
}

void PressureChamberActuator::addPieceGradient(const std::vector<RigidNodePose>& nodes, int piece,
                                               double scale,
                                               Eigen::Matrix<double, 12, 1>& g12) const {
  const RigidNodePose& A = nodes[first_gap_ + piece];
  const RigidNodePose& B = nodes[first_gap_ + piece + 1];
  const int v0 = vertex_begin_[piece], nv = vertex_begin_[piece + 1] - v0;
  const Eigen::Matrix3d R_A = A.q_BN.toRotationMatrix(), R_B = B.q_BN.toRotationMatrix();
  for (int i = 0; i < nv; ++i) {
    const Vertex& v = vertices_[v0 + i];
    r_a_[i] = R_A * v.a_A;
    r_b_[i] = R_B * v.b_B;
    p_[i] = (1.0 - v.t) * (A.p_BN + r_a_[i]) + v.t * (B.p_BN + r_b_[i]);
    f_[i].setZero();
  }
  for (int t = piece_begin_[piece]; t < piece_begin_[piece + 1]; ++t) {
    const Eigen::Vector3i tri = triangles_[t].array() - v0;
    // Area-weighted outward normal / 3 = d(volume)/d(vertex) share of this triangle.
    const Eigen::Vector3d f =
        (scale / 6.0) * (p_[tri[1]] - p_[tri[0]]).cross(p_[tri[2]] - p_[tri[0]]);
    for (int k = 0; k < 3; ++k) f_[tri[k]] += f;
  }
  for (int i = 0; i < nv; ++i) {
    const double t = vertices_[v0 + i].t;
    g12.segment<3>(0) += (1.0 - t) * f_[i];
    g12.segment<3>(3) += (1.0 - t) * r_a_[i].cross(f_[i]);
    g12.segment<3>(6) += t * f_[i];
    g12.segment<3>(9) += t * r_b_[i].cross(f_[i]);
  }
}

}  // namespace surgical_sim::core
