#include "surgical_sim/core/tissue/efg_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "surgical_sim/core/tissue/efg_shape_functions.h"
#include "surgical_sim/core/tissue/point_stiffness.h"
#include "surgical_sim/core/tissue/signed_svd.h"

namespace surgical_sim::core {
namespace {

// Compile-time neighbour count K (8) or Eigen::Dynamic (up to EfgOptions::kMaxNeighbours).
constexpr int maxNeighbours(int K) { return K == Eigen::Dynamic ? EfgOptions::kMaxNeighbours : K; }
constexpr int dofs(int K) { return K == Eigen::Dynamic ? Eigen::Dynamic : 3 * K; }

template <int K>
using NodeMatrix = Eigen::Matrix<double, 3, K, Eigen::ColMajor, 3, maxNeighbours(K)>;
template <int K>
using GradientMap =
    Eigen::Map<const Eigen::Matrix<double, K, 3, Eigen::ColMajor, maxNeighbours(K), 3>>;
template <int K>
using ElementMatrix = Eigen::Matrix<double, dofs(K), dofs(K), Eigen::ColMajor, 3 * maxNeighbours(K),
                                    3 * maxNeighbours(K)>;

template <int K>
NodeMatrix<K> gather(const Eigen::VectorXd& v, const Eigen::MatrixXi& neighbours, int e) {
  NodeMatrix<K> ve(3, neighbours.rows());
  for (int a = 0; a < ve.cols(); ++a) ve.col(a) = v.segment<3>(3 * neighbours(a, e));
  return ve;
}

template <int K>
void scatter(const NodeMatrix<K>& fe, const Eigen::MatrixXi& neighbours, int e,
             Eigen::VectorXd& f) {
  for (int a = 0; a < fe.cols(); ++a) f.segment<3>(3 * neighbours(a, e)) += fe.col(a);
}

template <int K>
using RankVector = Eigen::Matrix<double, dofs(K), 1, Eigen::ColMajor, 3 * maxNeighbours(K), 1>;

// The fixed-R tangent R K0 R^T of isotropic linear elasticity summed over the points of a group,
// from L = sum_p w_p vec(H_p) vec(H_p)^T with H_p = R_p grad_p^T (3 x k, vec: entry 3 a + i =
// H(i, a)). Per point, block (a, b) is w (mu (h_a . h_b) I + mu h_b h_a^T + lambda h_a h_b^T),
// so the sum is Ke_ab = lambda L_ab + mu L_ba + mu tr(L_ab) I (L_ab: the 3 x 3 block of L).
template <int K>
void rotatedLinearStiffness(const ElementMatrix<K>& L, double mu, double lambda,
                            ElementMatrix<K>& Ke) {
  const Eigen::Index k = L.rows() / 3;
  for (Eigen::Index a = 0; a < k; ++a) {
    for (Eigen::Index b = 0; b < k; ++b) {
      const auto Lab = L.template block<3, 3>(3 * a, 3 * b);
      Ke.template block<3, 3>(3 * a, 3 * b) =
          lambda * Lab + mu * L.template block<3, 3>(3 * b, 3 * a);
      Ke.template block<3, 3>(3 * a, 3 * b).diagonal().array() += mu * Lab.trace();
    }
  }
}

}  // namespace

EfgModel::EfgModel(const TetMesh& mesh, const Material& material, const EfgOptions& options)
    : EfgModel(buildEfgGrid(mesh, options), material, options) {}

EfgModel::EfgModel(const TriMesh& surface, const Material& material, const EfgOptions& options)
    : EfgModel(buildEfgGrid(surface, options), material, options) {}

EfgModel::EfgModel(EfgGrid grid, const Material& material, const EfgOptions& options)
    : options_(options),
      law_(Material::validated(material)),
      mu_(material.mu()),
      lambda_(material.lambda()),
      grid_(std::move(grid)),
      k_(options.neighbours) {
  const int n = static_cast<int>(grid_.particles.cols());
  const int m = static_cast<int>(grid_.integration_points.cols());
  // Canonical order, so that IPs with the same particles have identical columns.
  for (int e = 0; e < m; ++e)
    std::sort(grid_.neighbours.col(e).begin(), grid_.neighbours.col(e).end());
  rest_positions_ = Eigen::Map<const Eigen::VectorXd>(grid_.particles.data(), 3 * n);
  body_weight_ = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd node_mass = Eigen::VectorXd::Zero(n);
  shape_values_.resize(static_cast<size_t>(m) * k_);
  gradients_.resize(static_cast<size_t>(m) * k_ * 3);
  matching_.resize(static_cast<size_t>(m) * k_ * 3);
  Eigen::Matrix3Xd points(3, k_);
  for (int e = 0; e < m; ++e) {
    const Eigen::Vector3d x_e = grid_.integration_points.col(e);
    for (int a = 0; a < k_; ++a) points.col(a) = grid_.particles.col(grid_.neighbours(a, e));
    const Eigen::Matrix3Xd rel = points.colwise() - x_e;
    const double h = options_.kernel_support * rel.colwise().norm().maxCoeff();  // [m]
    const MlsShapeFunctions mls = computeMlsShapeFunctions(x_e, points, h);
    support_.push_back(h);
    if (mls.status != MlsStatus::Ok) {
      throw std::invalid_argument("EfgModel: integration point " + std::to_string(e) + " at (" +
                                  std::to_string(x_e.x()) + ", " + std::to_string(x_e.y()) + ", " +
                                  std::to_string(x_e.z()) + ") m: MLS moment matrix " +
                                  toString(mls.status) +
                                  " (check efg.neighbours and efg.kernel_support)");
    }
    Eigen::Map<Eigen::VectorXd>(shape_values_.data() + static_cast<size_t>(e) * k_, k_) = mls.phi;
    Eigen::Map<Eigen::MatrixXd>(gradients_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3) =
        mls.grad;
    // Shape matching: kernel weights, weighted centroid and the normalised moments.
    Eigen::VectorXd w(k_);
    for (int a = 0; a < k_; ++a) w(a) = quarticSplineKernel(rel.col(a).norm() / h);
    w /= w.sum();
    const Eigen::Matrix3Xd q = points.colwise() - points * w;
    const double moment = (q * w.asDiagonal() * q.transpose()).trace() / 3.0;  // [m^2]
    Eigen::Map<Eigen::MatrixXd>(matching_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3) =
        (q * w.asDiagonal()).transpose() / moment;

    const double mass = material.density * grid_.volumes(e);
    const double phi2 = mls.phi.squaredNorm();
    for (int a = 0; a < k_; ++a) {
      const int node = grid_.neighbours(a, e);
      body_weight_(node) += mass * mls.phi(a);
      node_mass(node) += mass * mls.phi(a) * mls.phi(a) / phi2;
    }
  }
  lumped_mass_.resize(3 * n);
  for (int i = 0; i < n; ++i) lumped_mass_.segment<3>(3 * i).setConstant(node_mass(i));
  groupIntegrationPoints();
  setGroups(n, group_nodes_);
}

void EfgModel::groupIntegrationPoints() {
  const Eigen::MatrixXi& nb = grid_.neighbours;  // columns sorted
  group_ips_.resize(static_cast<size_t>(nb.cols()));
  std::iota(group_ips_.begin(), group_ips_.end(), 0);
  const auto column = [&](int e) { return nb.col(e); };
  std::stable_sort(group_ips_.begin(), group_ips_.end(), [&](int a, int b) {
    return std::lexicographical_compare(column(a).begin(), column(a).end(), column(b).begin(),
                                        column(b).end());
  });
  group_first_.clear();
  std::vector<int> first_ips;
  for (int p = 0; p < static_cast<int>(group_ips_.size()); ++p) {
    if (p == 0 || column(group_ips_[static_cast<size_t>(p)]) !=
                      column(group_ips_[static_cast<size_t>(p) - 1])) {
      group_first_.push_back(p);
      first_ips.push_back(group_ips_[static_cast<size_t>(p)]);
    }
  }
  group_first_.push_back(static_cast<int>(group_ips_.size()));
  group_nodes_.resize(nb.rows(), static_cast<Eigen::Index>(first_ips.size()));
  for (size_t g = 0; g < first_ips.size(); ++g)
    group_nodes_.col(static_cast<Eigen::Index>(g)) = nb.col(first_ips[g]);
}

Eigen::Map<const Eigen::VectorXd> EfgModel::shapeValues(int e) const {
  return {shape_values_.data() + static_cast<size_t>(e) * k_, k_};
}

Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3>> EfgModel::shapeGradients(int e) const {
  return {gradients_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3};
}

Eigen::SparseMatrix<double> EfgModel::interpolation(const Eigen::Matrix3Xd& points) const {
  std::vector<Eigen::Triplet<double>> weights;
  Eigen::Matrix3Xd neighbours(3, k_);
  for (int i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    const Eigen::Vector3d cell = ((p - grid_.origin) / grid_.spacing).array().floor();
    int e = -1;
    if (cell.allFinite() && (cell.array() >= 0.0).all() &&
        (cell.array() < grid_.cells.cast<double>().array()).all()) {
      const Eigen::Vector3i c = cell.cast<int>();
      e = grid_.ip_of_cell[static_cast<size_t>(c.x() + grid_.cells.x() *
                                                           (c.y() + grid_.cells.y() * c.z()))];
    }
    if (e < 0) {
      (grid_.integration_points.colwise() - p).colwise().squaredNorm().minCoeff(&e);
    }
    for (int a = 0; a < k_; ++a) neighbours.col(a) = grid_.particles.col(grid_.neighbours(a, e));
    const MlsShapeFunctions mls =
        computeMlsShapeFunctions(p, neighbours, support_[static_cast<size_t>(e)]);
    // A point far outside its IP's support: the IP's own weights.
    const Eigen::VectorXd phi =
        mls.status == MlsStatus::Ok ? mls.phi : Eigen::VectorXd(shapeValues(e));
    for (int a = 0; a < k_; ++a) weights.emplace_back(i, grid_.neighbours(a, e), phi(a));
  }
  Eigen::SparseMatrix<double> W(points.cols(), grid_.particles.cols());
  W.setFromTriplets(weights.begin(), weights.end());
  return W;
}

Eigen::VectorXd EfgModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f(rest_positions_.size());
  for (Eigen::Index i = 0; i < body_weight_.size(); ++i) f.segment<3>(3 * i) = body_weight_(i) * a;
  return f;
}

template <typename Nodes>
Eigen::Matrix3d EfgModel::matchingRotation(const Nodes& xe, int e) const {
  const Eigen::Map<const Eigen::MatrixXd> weights(
      matching_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3);
  return computeSignedRotation(xe * weights);
}

Eigen::Matrix3d EfgModel::rotatedStress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const {
  const Eigen::Matrix3d G = R.transpose() * F;
  const Eigen::Matrix3d eps = 0.5 * (G + G.transpose()) - Eigen::Matrix3d::Identity();
  return R * (2.0 * mu_ * eps + lambda_ * eps.trace() * Eigen::Matrix3d::Identity());
}

double EfgModel::matchingEnergyDensity(const Eigen::Matrix3d& F, const Eigen::Matrix3d& R) const {
  const Eigen::Matrix3d RtF = R.transpose() * F;
  const Eigen::Matrix3d eps = 0.5 * (RtF + RtF.transpose()) - Eigen::Matrix3d::Identity();
  return mu_ * eps.squaredNorm() + 0.5 * lambda_ * eps.trace() * eps.trace();
}

template <int K>
double EfgModel::energyImpl(const Eigen::VectorXd& x) const {
  double energy = 0.0;
  for (int g = 0; g < group_nodes_.cols(); ++g) {
    const NodeMatrix<K> xe = gather<K>(x, group_nodes_, g);
    for (int p = group_first_[g]; p < group_first_[g + 1]; ++p) {
      const int e = group_ips_[p];
      const GradientMap<K> G(gradients_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3);
      const Eigen::Matrix3d F = xe * G;
      const double psi = options_.rotation == EfgRotation::Polar
                             ? law_.energyDensity(F)
                             : matchingEnergyDensity(F, matchingRotation(xe, e));
      energy += grid_.volumes(e) * psi;
    }
  }
  return energy;
}

template <int K>
void EfgModel::forceImpl(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  for (int g = 0; g < group_nodes_.cols(); ++g) {
    const NodeMatrix<K> xe = gather<K>(x, group_nodes_, g);
    NodeMatrix<K> fe = NodeMatrix<K>::Zero(3, k_);
    for (int p = group_first_[g]; p < group_first_[g + 1]; ++p) {
      const int e = group_ips_[p];
      const GradientMap<K> G(gradients_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3);
      const Eigen::Matrix3d F = xe * G;
      const Eigen::Matrix3d P = options_.rotation == EfgRotation::Polar
                                    ? law_.firstPiola(F)
                                    : rotatedStress(F, matchingRotation(xe, e));
      fe.noalias() -= (grid_.volumes(e) * P) * G.transpose();
    }
    scatter<K>(fe, group_nodes_, g, f);
  }
}

template <int K, typename Sink>
void EfgModel::stiffnessImpl(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                             double* energy, Sink&& sink) const {
  if (energy != nullptr) *energy = 0.0;
  // Rotated linear tangents (shape matching, projected polar) accumulate L (see
  // rotatedLinearStiffness) over the group; the exact polar tangent accumulates Ke directly.
  const bool rotated_linear =
      options_.rotation == EfgRotation::ShapeMatching || mode == TangentMode::ProjectedSpd;
  ElementMatrix<K> Ke(3 * k_, 3 * k_);
  ElementMatrix<K> L(3 * k_, 3 * k_);
  NodeMatrix<K> fe(3, k_);
  NodeMatrix<K> H(3, k_);
  for (int g = 0; g < group_nodes_.cols(); ++g) {
    const NodeMatrix<K> xe = gather<K>(x, group_nodes_, g);
    (rotated_linear ? L : Ke).setZero();
    fe.setZero();
    for (int p = group_first_[g]; p < group_first_[g + 1]; ++p) {
      const int e = group_ips_[p];
      const GradientMap<K> G(gradients_.data() + static_cast<size_t>(e) * k_ * 3, k_, 3);
      const double w = grid_.volumes(e);
      const Eigen::Matrix3d F = xe * G;
      Eigen::Matrix3d P;
      if (rotated_linear) {
        Eigen::Matrix3d R;
        if (options_.rotation == EfgRotation::ShapeMatching) {
          R = matchingRotation(xe, e);
          P = rotatedStress(F, R);
          if (energy != nullptr) *energy += w * matchingEnergyDensity(F, R);
        } else {
          const RotatedLinearStressAndTangent point = *law_.rotatedLinearStressAndTangent(F);
          R = point.R;
          P = point.P;
          if (energy != nullptr) *energy += w * point.energy_density;
        }
        H.noalias() = R * G.transpose();
        const Eigen::Map<const RankVector<K>> h(H.data(), 3 * k_);
        L.noalias() += (w * h) * h.transpose();
      } else {
        const StressAndTangent point = law_.stressAndTangent(F, mode);
        P = point.P;
        if (energy != nullptr) *energy += w * law_.energyDensity(F);
        addPointStiffness(point.dPdF, G, w, Ke);
      }
      if (f != nullptr) fe.noalias() -= (w * P) * G.transpose();
    }
    if (rotated_linear) rotatedLinearStiffness<K>(L, mu_, lambda_, Ke);
    if (f != nullptr) scatter<K>(fe, group_nodes_, g, *f);
    sink(g, Ke);
  }
}

double EfgModel::energy(const Eigen::VectorXd& x) const {
  return k_ == 8 ? energyImpl<8>(x) : energyImpl<Eigen::Dynamic>(x);
}

void EfgModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  if (k_ == 8) {
    forceImpl<8>(x, f);
  } else {
    forceImpl<Eigen::Dynamic>(x, f);
  }
}

void EfgModel::addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                 double* values) const {
  addGroupStiffnessAndEnergy(x, mode, f, values, nullptr);
}

void EfgModel::addGroupStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                          Eigen::VectorXd* f, double* values,
                                          double* energy) const {
  const auto sink = [&](int g, const auto& Ke) { scatterGroup(g, Ke, values); };
  if (k_ == 8) {
    stiffnessImpl<8>(x, mode, f, energy, sink);
  } else {
    stiffnessImpl<Eigen::Dynamic>(x, mode, f, energy, sink);
  }
}

double EfgModel::addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                                    Eigen::VectorXd& f,
                                                    Eigen::SparseMatrix<double>& K) const {
  double energy = 0.0;
  addGroupStiffnessAndEnergy(x, mode, &f, zeroedValues(K), &energy);
  return energy;
}

void EfgModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                              Eigen::VectorXd& y) const {
  y.setZero(rest_positions_.size());
  const auto multiply = [&](int g, const auto& Ke) {
    constexpr int kSize = std::decay_t<decltype(Ke)>::RowsAtCompileTime;
    constexpr int kK = kSize == Eigen::Dynamic ? Eigen::Dynamic : kSize / 3;
    const NodeMatrix<kK> ve = gather<kK>(v, group_nodes_, g);
    const Eigen::Map<const RankVector<kK>> vv(ve.data(), 3 * k_);
    const RankVector<kK> ye = Ke * vv;
    for (int a = 0; a < k_; ++a)
      y.segment<3>(3 * group_nodes_(a, g)) += ye.template segment<3>(3 * a);
  };
  if (k_ == 8) {
    stiffnessImpl<8>(x, mode, nullptr, nullptr, multiply);
  } else {
    stiffnessImpl<Eigen::Dynamic>(x, mode, nullptr, nullptr, multiply);
  }
}

}  // namespace surgical_sim::core
