#include "surgical_sim/core/robot/chamber_pressure_model.h"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace surgical_sim::core {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

}  // namespace

ChamberPressureModel::ChamberPressureModel(const TetMesh& mesh,
                                           const std::vector<Eigen::Vector3d>& vertices,
                                           const std::vector<Eigen::Vector3i>& triangles)
    : points_(embedPoints(mesh, vertices, "chamber_pressure.vertices")), triangles_(triangles) {
  const int n = mesh.numNodes();
  rest_.resize(3 * n);
  for (int i = 0; i < n; ++i) rest_.segment<3>(3 * i) = mesh.nodes.col(i);
  mass_ = Eigen::VectorXd::Zero(3 * n);
  std::vector<Eigen::Triplet<double>> t;
  for (size_t k = 0; k < triangles_.size(); ++k) {
    const Eigen::Vector3i& tri = triangles_[k];
    if (tri.minCoeff() < 0 || tri.maxCoeff() >= static_cast<int>(points_.size()))
      throw std::invalid_argument("chamber_pressure.triangles[" + std::to_string(k) +
                                  "] has a vertex index out of range");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b)
            for (int c = 0; c < 3; ++c)
              for (int d = 0; d < 3; ++d)
                t.emplace_back(3 * points_[tri[i]].corners[a] + c,
                               3 * points_[tri[j]].corners[b] + d, 0.0);
  }
  pattern_.resize(3 * n, 3 * n);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
}

double ChamberPressureModel::volume(const Eigen::VectorXd& x) const {
  double six_v = 0.0;
  for (const Eigen::Vector3i& tri : triangles_)
    six_v += points_[tri[0]].position(x).dot(
        points_[tri[1]].position(x).cross(points_[tri[2]].position(x)));
  return six_v / 6.0;
}

Eigen::VectorXd ChamberPressureModel::bodyForce(const Eigen::Vector3d&) const {
  return Eigen::VectorXd::Zero(rest_.size());
}

double ChamberPressureModel::energy(const Eigen::VectorXd& x) const {
  return -pressure_ * volume(x);
}

void ChamberPressureModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  for (const Eigen::Vector3i& tri : triangles_) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = points_[tri[k]].position(x);
    // dV/dp_k = p_{k+1} x p_{k+2} / 6 (the triangle's area-weighted normal / 3 plus terms that
    // cancel over the closed surface).
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d g = (pressure_ / 6.0) * p[(k + 1) % 3].cross(p[(k + 2) % 3]);
      const EmbeddedPoint& e = points_[tri[k]];
      for (int a = 0; a < 4; ++a) f.segment<3>(3 * e.corners[a]) += e.weights[a] * g;
    }
  }
}

template <class Visit>
void ChamberPressureModel::forEachVolumeHessianBlock(const Eigen::VectorXd& x, int t,
                                                     Visit&& visit) const {
  const Eigen::Vector3i& tri = triangles_[t];
  Eigen::Vector3d p[3];
  for (int k = 0; k < 3; ++k) p[k] = points_[tri[k]].position(x);
  // d2(p0.(p1 x p2)/6)/dp_k dp_{k+1} = -[p_{k+2}]x / 6 and its transpose for (k+1, k).
  for (int k = 0; k < 3; ++k) {
    const int i = k, j = (k + 1) % 3;
    const Eigen::Matrix3d H = -skew(p[(k + 2) % 3]) / 6.0;
    visit(points_[tri[i]], points_[tri[j]], H);
    visit(points_[tri[j]], points_[tri[i]], Eigen::Matrix3d(H.transpose()));
  }
}

void ChamberPressureModel::assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                             Eigen::SparseMatrix<double>& K) const {
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  if (mode != TangentMode::Exact) return;
  for (int t = 0; t < static_cast<int>(triangles_.size()); ++t)
    forEachVolumeHessianBlock(
        x, t, [&](const EmbeddedPoint& pi, const EmbeddedPoint& pj, const Eigen::Matrix3d& H) {
          for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b)
              for (int c = 0; c < 3; ++c)
                for (int d = 0; d < 3; ++d)
                  K.coeffRef(3 * pi.corners[a] + c, 3 * pj.corners[b] + d) -=
                      pressure_ * pi.weights[a] * pj.weights[b] * H(c, d);
        });
}

void ChamberPressureModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                          const Eigen::VectorXd& v, Eigen::VectorXd& y) const {
  y.setZero();
  if (mode != TangentMode::Exact) return;
  for (int t = 0; t < static_cast<int>(triangles_.size()); ++t)
    forEachVolumeHessianBlock(
        x, t, [&](const EmbeddedPoint& pi, const EmbeddedPoint& pj, const Eigen::Matrix3d& H) {
          const Eigen::Vector3d g = -pressure_ * H * pj.position(v);
          for (int a = 0; a < 4; ++a) y.segment<3>(3 * pi.corners[a]) += pi.weights[a] * g;
        });
}

}  // namespace surgical_sim::core
