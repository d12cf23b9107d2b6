#include "surgical_sim/core/tissue/mass_spring_model.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "surgical_sim/core/tissue/block_sparsity.h"
#include "surgical_sim/core/tissue/tissue_mesh_check.h"

namespace surgical_sim::core {
namespace {

constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {2, 3}, {1, 3}};

}  // namespace

MassSpringModel::MassSpringModel(const TetMesh& mesh, const Material& material) {
  const Material mat = Material::validated(material);
  checkTissueMesh(mesh, "mass_spring", /*allow_tet10=*/false);
  const int n = mesh.numNodes();
  rest_positions_ = Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * n);
  lumped_mass_ = Eigen::VectorXd::Zero(3 * n);

  // (edge, volume) records, then merged per unique edge.
  std::vector<std::pair<std::pair<int, int>, double>> records;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const auto node = [&](int a) { return mesh.elements(a, e); };
    const double volume = signedTetVolume(mesh.nodes.col(node(0)), mesh.nodes.col(node(1)),
                                          mesh.nodes.col(node(2)), mesh.nodes.col(node(3)));
    for (int a = 0; a < 4; ++a)
      lumped_mass_.segment<3>(3 * node(a)).array() += mat.density * volume / 4;
    for (const auto& edge : kTetEdges) {
      const int i = node(edge[0]);
      const int j = node(edge[1]);
      records.push_back({{std::min(i, j), std::max(i, j)}, volume});
    }
  }
  std::sort(records.begin(), records.end());
  std::vector<std::pair<int, int>> edges;
  std::vector<double> volume_sum;
  for (const auto& rec : records) {
    if (edges.empty() || edges.back() != rec.first) {
      edges.push_back(rec.first);
      volume_sum.push_back(0.0);
    }
    volume_sum.back() += rec.second;
  }
  const int s = static_cast<int>(edges.size());
  springs_.resize(2, s);
  stiffness_.resize(s);
  rest_length_.resize(s);
  for (int j = 0; j < s; ++j) {
    springs_(0, j) = edges[j].first;
    springs_(1, j) = edges[j].second;
    const double length = (mesh.nodes.col(edges[j].second) - mesh.nodes.col(edges[j].first)).norm();
    rest_length_(j) = length;
    stiffness_(j) = mat.young_modulus * volume_sum[j] / (length * length);  // Chendeb eq. 2.7
  }
  setGroups(n, springs_);
}

Eigen::VectorXd MassSpringModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f(lumped_mass_.size());
  for (Eigen::Index i = 0; i < f.size() / 3; ++i) f.segment<3>(3 * i) = lumped_mass_(3 * i) * a;
  return f;
}

double MassSpringModel::energy(const Eigen::VectorXd& x) const {
  double energy = 0.0;
  for (int j = 0; j < springs_.cols(); ++j) {
    const double l = (x.segment<3>(3 * springs_(1, j)) - x.segment<3>(3 * springs_(0, j))).norm();
    energy += 0.5 * stiffness_(j) * (l - rest_length_(j)) * (l - rest_length_(j));
  }
  return energy;
}

void MassSpringModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  for (int j = 0; j < springs_.cols(); ++j) {
    const Eigen::Vector3d d = x.segment<3>(3 * springs_(1, j)) - x.segment<3>(3 * springs_(0, j));
    const double l = d.norm();
    if (l == 0.0) continue;  // coincident ends: the direction (and force) is undefined; skip
    const Eigen::Vector3d f1 = -stiffness_(j) * (l - rest_length_(j)) / l * d;
    f.segment<3>(3 * springs_(1, j)) += f1;
    f.segment<3>(3 * springs_(0, j)) -= f1;
  }
}

Eigen::Matrix3d MassSpringModel::springBlock(const Eigen::VectorXd& x, int j,
                                             TangentMode mode) const {
  const Eigen::Vector3d d = x.segment<3>(3 * springs_(1, j)) - x.segment<3>(3 * springs_(0, j));
  // A vanishing length is clamped at 1e-12 L0 (the exact Hessian diverges there).
  const double l = std::max(d.norm(), 1e-12 * rest_length_(j));
  const Eigen::Vector3d n = d / l;
  const double ratio = rest_length_(j) / l;
  double transverse = 1.0 - ratio;
  if (mode == TangentMode::ProjectedSpd) transverse = std::max(transverse, 0.0);
  return stiffness_(j) * (transverse * Eigen::Matrix3d::Identity() + ratio * n * n.transpose());
}

void MassSpringModel::addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                        Eigen::VectorXd* f, double* values) const {
  if (f != nullptr) addInternalForce(x, *f);
  for (int j = 0; j < springs_.cols(); ++j) {
    const Eigen::Matrix3d H = springBlock(x, j, mode);
    Eigen::Matrix<double, 6, 6> Ke;  // [H -H; -H H]
    Ke << H, -H, -H, H;
    scatterGroup(j, Ke, values);
  }
}

void MassSpringModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode,
                                     const Eigen::VectorXd& v, Eigen::VectorXd& y) const {
  y.setZero(rest_positions_.size());
  for (int j = 0; j < springs_.cols(); ++j) {
    const Eigen::Vector3d Hdv = springBlock(x, j, mode) * (v.segment<3>(3 * springs_(1, j)) -
                                                           v.segment<3>(3 * springs_(0, j)));
    y.segment<3>(3 * springs_(1, j)) += Hdv;
    y.segment<3>(3 * springs_(0, j)) -= Hdv;
  }
}

}  // namespace surgical_sim::core
