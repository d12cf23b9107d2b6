#include "surgical_sim/core/tissue/fe_model.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "surgical_sim/core/tissue/block_sparsity.h"
#include "surgical_sim/core/tissue/fe_rest_data.h"
#include "surgical_sim/core/tissue/point_stiffness.h"
#include "surgical_sim/core/tissue/tissue_mesh_check.h"

namespace surgical_sim::core {
namespace {

template <int NPE>
using ElementMatrix = Eigen::Matrix<double, 3 * NPE, 3 * NPE>;
template <int NPE>
using Gradients = Eigen::Map<const Eigen::Matrix<double, NPE, 3>>;

template <int NPE>
Eigen::Matrix<double, 3, NPE> gatherNodes(const Eigen::VectorXd& x, const Eigen::MatrixXi& elements,
                                          int e) {
  Eigen::Matrix<double, 3, NPE> xe;
  for (int a = 0; a < NPE; ++a) xe.col(a) = x.segment<3>(3 * elements(a, e));
  return xe;
}

template <int NPE>
Eigen::Matrix<double, 3 * NPE, 1> gatherDofs(const Eigen::VectorXd& v,
                                             const Eigen::MatrixXi& elements, int e) {
  Eigen::Matrix<double, 3 * NPE, 1> ve;
  for (int a = 0; a < NPE; ++a) ve.template segment<3>(3 * a) = v.segment<3>(3 * elements(a, e));
  return ve;
}

// fe -= w P G^T: the nodal forces of one quadrature point.
template <int NPE>
void addPointForce(const Eigen::Matrix3d& P, const Gradients<NPE>& G, double w,
                   Eigen::Matrix<double, 3, NPE>& fe) {
  fe.noalias() -= (w * P) * G.transpose();
}

// f += fe at the nodes of element e.
template <int NPE>
void scatterForce(const Eigen::Matrix<double, 3, NPE>& fe, const Eigen::MatrixXi& elements, int e,
                  Eigen::VectorXd& f) {
  for (int a = 0; a < NPE; ++a) f.segment<3>(3 * elements(a, e)) += fe.col(a);
}

// Tet4 specialisation of addPointStiffness: with one point and dN_0/dX = -(g1 + g2 + g3), only
// the symmetric 3 x 3 blocks of nodes 1..3 are computed; node 0's blocks follow from the
// row / column sums (rigid translations are in the null space).
void tet4Stiffness(const Matrix9d& A, const Gradients<4>& G, double w, ElementMatrix<4>& Ke) {
  Eigen::Matrix<double, 9, 3> AG[3];
  for (int b = 0; b < 3; ++b) {
    AG[b].noalias() = (w * G(b + 1, 0)) * A.middleCols<3>(0);
    AG[b].noalias() += (w * G(b + 1, 1)) * A.middleCols<3>(3);
    AG[b].noalias() += (w * G(b + 1, 2)) * A.middleCols<3>(6);
  }
  Eigen::Matrix3d column_sum[3];
  for (int b = 0; b < 3; ++b) column_sum[b].setZero();
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      const Eigen::Matrix3d Kab = G(a + 1, 0) * AG[b].middleRows<3>(0) +
                                  G(a + 1, 1) * AG[b].middleRows<3>(3) +
                                  G(a + 1, 2) * AG[b].middleRows<3>(6);
      Ke.block<3, 3>(3 * (a + 1), 3 * (b + 1)) = Kab;
      column_sum[b] += Kab;
      if (b != a) {
        Ke.block<3, 3>(3 * (b + 1), 3 * (a + 1)) = Kab.transpose();
        column_sum[a] += Kab.transpose();
      }
    }
  }
  Eigen::Matrix3d corner = Eigen::Matrix3d::Zero();
  for (int b = 0; b < 3; ++b) {
    Ke.block<3, 3>(0, 3 * (b + 1)) = -column_sum[b];
    Ke.block<3, 3>(3 * (b + 1), 0) = -column_sum[b].transpose();
    corner += column_sum[b];
  }
  Ke.block<3, 3>(0, 0) = corner;
}

// Tet4 element stiffness of a rotated isotropic linear tangent (the corotational R K0 R^T): with
// h_a = R dN_a/dX, K_ab = w (mu (h_a . h_b) I + mu h_b h_a^T + lambda h_a h_b^T). h_0 is
// -(h_1 + h_2 + h_3), so rigid translations are in the null space as in tet4Stiffness.
void tet4RotatedLinearStiffness(const RotatedLinearStressAndTangent& point, const Gradients<4>& G,
                                double w, ElementMatrix<4>& Ke) {
  Eigen::Matrix<double, 3, 4> H;
  H.rightCols<3>().noalias() = point.R * G.bottomRows<3>().transpose();
  H.col(0) = -H.rightCols<3>().rowwise().sum();
  const double w_mu = w * point.mu;
  const double w_lambda = w * point.lambda;
  for (int a = 0; a < 4; ++a) {
    for (int b = a; b < 4; ++b) {
      Eigen::Matrix3d Kab = (w_mu * H.col(a).dot(H.col(b))) * Eigen::Matrix3d::Identity();
      Kab.noalias() += w_mu * H.col(b) * H.col(a).transpose();
      Kab.noalias() += w_lambda * H.col(a) * H.col(b).transpose();
      Ke.block<3, 3>(3 * a, 3 * b) = Kab;
      if (b != a) Ke.block<3, 3>(3 * b, 3 * a) = Kab.transpose();
    }
  }
}

}  // namespace

FeModel::FeModel(const TetMesh& mesh, const Material& material,
                 std::unique_ptr<HyperelasticLaw> law)
    : type_(mesh.type), law_(std::move(law)) {
  if (!law_) throw std::invalid_argument("FeModel: law must not be null");
  const Material mat = Material::validated(material);
  checkTissueMesh(mesh, law_->name(), /*allow_tet10=*/true);

  FeRestData rest = computeFeRestData(mesh, mat.density);
  nodes_per_element_ = nodesPerElement(type_);
  points_per_element_ = rest.points_per_element;
  const int n = mesh.numNodes();
  elements_ = mesh.elements;
  rest_positions_ = Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * n);
  rest_gradients_ = std::move(rest.rest_gradients);
  weight_det_j_ = std::move(rest.weight_det_j);
  body_weight_ = std::move(rest.body_weight);
  lumped_mass_ = std::move(rest.lumped_mass);
  setGroups(n, elements_);
}

Eigen::VectorXd FeModel::bodyForce(const Eigen::Vector3d& a) const {
  Eigen::VectorXd f(rest_positions_.size());
  for (Eigen::Index i = 0; i < body_weight_.size(); ++i) f.segment<3>(3 * i) = body_weight_(i) * a;
  return f;
}

template <int NPE, int NQ>
double FeModel::energyImpl(const Eigen::VectorXd& x) const {
  return schedule().sumOverChunks([&](int begin, int end) {
    double energy = 0.0;
    for (int e = begin; e < end; ++e) {
      const Eigen::Matrix<double, 3, NPE> xe = gatherNodes<NPE>(x, elements_, e);
      for (int q = 0; q < NQ; ++q) {
        const size_t k = static_cast<size_t>(e) * NQ + q;
        const Gradients<NPE> G(rest_gradients_.data() + k * NPE * 3);
        const Eigen::Matrix3d F = xe * G;
        energy += weight_det_j_[k] * law_->energyDensity(F);
      }
    }
    return energy;
  });
}

template <int NPE, int NQ>
void FeModel::forceImpl(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  schedule().forEachChunk([&](int begin, int end) {
    for (int e = begin; e < end; ++e) {
      const Eigen::Matrix<double, 3, NPE> xe = gatherNodes<NPE>(x, elements_, e);
      Eigen::Matrix<double, 3, NPE> fe = Eigen::Matrix<double, 3, NPE>::Zero();
      for (int q = 0; q < NQ; ++q) {
        const size_t k = static_cast<size_t>(e) * NQ + q;
        const Gradients<NPE> G(rest_gradients_.data() + k * NPE * 3);
        addPointForce<NPE>(law_->firstPiola(xe * G), G, weight_det_j_[k], fe);
      }
      scatterForce<NPE>(fe, elements_, e, f);
    }
  });
}

template <int NPE, int NQ, typename Sink>
double FeModel::stiffnessImpl(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                              bool with_energy, Sink&& sink) const {
  return schedule().sumOverChunks([&](int begin, int end) {
    double energy = 0.0;
    ElementMatrix<NPE> Ke;
    Eigen::Matrix<double, 3, NPE> fe;
    // The tangent at one point; with f, the stress from the same law call goes into fe.
    const auto point_tangent = [&](const Gradients<NPE>& G, const Eigen::Matrix3d& F,
                                   double w) -> Matrix9d {
      if (f == nullptr) return law_->tangent(F, mode);
      const StressAndTangent point = law_->stressAndTangent(F, mode);
      addPointForce<NPE>(point.P, G, w, fe);
      return point.dPdF;
    };
    for (int e = begin; e < end; ++e) {
      const Eigen::Matrix<double, 3, NPE> xe = gatherNodes<NPE>(x, elements_, e);
      fe.setZero();
      if constexpr (NPE == 4 && NQ == 1) {
        const Gradients<4> G(rest_gradients_.data() + static_cast<size_t>(e) * 12);
        const double w = weight_det_j_[e];
        const Eigen::Matrix3d F = xe * G;
        const std::optional<RotatedLinearStressAndTangent> rotated =
            mode == TangentMode::ProjectedSpd ? law_->rotatedLinearStressAndTangent(F)
                                              : std::nullopt;
        if (rotated) {
          tet4RotatedLinearStiffness(*rotated, G, w, Ke);
          if (f != nullptr) addPointForce<4>(rotated->P, G, w, fe);
          if (with_energy) energy += w * rotated->energy_density;
        } else {
          tet4Stiffness(point_tangent(G, F, w), G, w, Ke);
          if (with_energy) energy += w * law_->energyDensity(F);
        }
      } else {
        Ke.setZero();
        for (int q = 0; q < NQ; ++q) {
          const size_t k = static_cast<size_t>(e) * NQ + q;
          const Gradients<NPE> G(rest_gradients_.data() + k * NPE * 3);
          const double w = weight_det_j_[k];
          const Eigen::Matrix3d F = xe * G;
          addPointStiffness(point_tangent(G, F, w), G, w, Ke);
          if (with_energy) energy += w * law_->energyDensity(F);
        }
      }
      if (f != nullptr) scatterForce<NPE>(fe, elements_, e, *f);
      sink(e, Ke);
    }
    return energy;
  });
}

double FeModel::energy(const Eigen::VectorXd& x) const {
  return type_ == ElementType::Tet4 ? energyImpl<4, 1>(x) : energyImpl<10, 4>(x);
}

void FeModel::addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  if (type_ == ElementType::Tet4) {
    forceImpl<4, 1>(x, f);
  } else {
    forceImpl<10, 4>(x, f);
  }
}

void FeModel::addGroupStiffness(const Eigen::VectorXd& x, TangentMode mode, Eigen::VectorXd* f,
                                double* values) const {
  const auto sink = [&](int e, const auto& Ke) { scatterGroup(e, Ke, values); };
  if (type_ == ElementType::Tet4) {
    stiffnessImpl<4, 1>(x, mode, f, false, sink);
  } else {
    stiffnessImpl<10, 4>(x, mode, f, false, sink);
  }
}

double FeModel::addInternalForceStiffnessAndEnergy(const Eigen::VectorXd& x, TangentMode mode,
                                                   Eigen::VectorXd& f,
                                                   Eigen::SparseMatrix<double>& K) const {
  double* values = zeroedValues(K);
  const auto sink = [&](int e, const auto& Ke) { scatterGroup(e, Ke, values); };
  return type_ == ElementType::Tet4 ? stiffnessImpl<4, 1>(x, mode, &f, true, sink)
                                    : stiffnessImpl<10, 4>(x, mode, &f, true, sink);
}

void FeModel::applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                             Eigen::VectorXd& y) const {
  y.setZero(rest_positions_.size());
  const auto multiply = [&](int e, const auto& Ke) {
    constexpr int kNpe = static_cast<int>(std::decay_t<decltype(Ke)>::RowsAtCompileTime) / 3;
    const Eigen::Matrix<double, 3 * kNpe, 1> ye = Ke * gatherDofs<kNpe>(v, elements_, e);
    for (int a = 0; a < kNpe; ++a)
      y.segment<3>(3 * elements_(a, e)) += ye.template segment<3>(3 * a);
  };
  if (type_ == ElementType::Tet4) {
    stiffnessImpl<4, 1>(x, mode, nullptr, false, multiply);
  } else {
    stiffnessImpl<10, 4>(x, mode, nullptr, false, multiply);
  }
}

}  // namespace surgical_sim::core
