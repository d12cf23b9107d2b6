#include "surgical_sim/core/connective/rigid_node_model.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {
namespace {

#if defined(__x86_64__)
/// C(i, j) += sum_r X(r, i) X(r, j) on every 4 x 4 tile of C that touches its upper triangle,
/// with AVX2 + FMA: X is rows x n row-major, C is n x n column-major, n a multiple of 4 (entries
/// below the diagonal inside diagonal tiles are written too).
__attribute__((target("avx2,fma"))) void upperRankUpdateAvx2(int rows, int n, const double* X,
                                                             double* C) {
  for (int j = 0; j < n; j += 4) {
    for (int i = 0; i <= j; i += 4) {
      double* c = C + static_cast<std::ptrdiff_t>(j) * n + i;
      __m256d c0 = _mm256_loadu_pd(c), c1 = _mm256_loadu_pd(c + n);
      __m256d c2 = _mm256_loadu_pd(c + 2 * n), c3 = _mm256_loadu_pd(c + 3 * n);
      for (int r = 0; r < rows; ++r) {
        const double* x = X + static_cast<std::ptrdiff_t>(r) * n;
        const __m256d xi = _mm256_loadu_pd(x + i);
        c0 = _mm256_fmadd_pd(xi, _mm256_broadcast_sd(x + j), c0);
        c1 = _mm256_fmadd_pd(xi, _mm256_broadcast_sd(x + j + 1), c1);
        c2 = _mm256_fmadd_pd(xi, _mm256_broadcast_sd(x + j + 2), c2);
        c3 = _mm256_fmadd_pd(xi, _mm256_broadcast_sd(x + j + 3), c3);
      }
      _mm256_storeu_pd(c, c0);
      _mm256_storeu_pd(c + n, c1);
      _mm256_storeu_pd(c + 2 * n, c2);
      _mm256_storeu_pd(c + 3 * n, c3);
    }
  }
}
#endif

/// upperRankUpdateAvx2 where the CPU has AVX2 and FMA (checked once) and n is a multiple of 4;
/// false (nothing done) otherwise.
bool fastUpperRankUpdate(int rows, int n, const double* X, double* C) {
#if defined(__x86_64__)
  static const bool supported = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (!supported || n % 4 != 0) return false;
  upperRankUpdateAvx2(rows, n, X, C);
  return true;
#else
  return false;
#endif
}

/// Voigt index pairs (00, 11, 22, 12, 02, 01).
constexpr int kVoigtRow[6] = {0, 1, 2, 1, 0, 0};
constexpr int kVoigtCol[6] = {0, 1, 2, 2, 2, 1};

/// d{E}/dq_a (6 x 6): with B_j = [g_j I, -[a_j]x] the rows of dF_j / dq_a,
/// normal j: F_j^T B_j; shear (j, k): F_k^T B_j + F_j^T B_k (engineering shear).
Matrix6d strainJacobian(const Eigen::Matrix3d& F, const Eigen::Vector3d& g,
                        const Eigen::Matrix3d& A) {
  Matrix6d M;
  for (int v = 0; v < 6; ++v) {
    const int j = kVoigtRow[v], k = kVoigtCol[v];
    if (j == k) {
      M.block<1, 3>(v, 0) = g[j] * F.col(j).transpose();
      M.block<1, 3>(v, 3) = A.col(j).cross(F.col(j)).transpose();
    } else {
      M.block<1, 3>(v, 0) = (g[j] * F.col(k) + g[k] * F.col(j)).transpose();
      M.block<1, 3>(v, 3) = (A.col(j).cross(F.col(k)) + A.col(k).cross(F.col(j))).transpose();
    }
  }
  return M;
}

/// m += sign [u]x (a 3 x 3 block expression).
template <typename Block>
void addSkew(double sign, const Eigen::Vector3d& u, Block&& m) {
  m(0, 1) -= sign * u.z();
  m(0, 2) += sign * u.y();
  m(1, 0) += sign * u.z();
  m(1, 2) -= sign * u.x();
  m(2, 0) -= sign * u.y();
  m(2, 1) += sign * u.x();
}

/// Green-Lagrange strain E = (F^T F - I) / 2.
Eigen::Matrix3d greenLagrange(const Eigen::Matrix3d& F) {
  return 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
}

Vector6d toVoigtStress(const Eigen::Matrix3d& S) {
  Vector6d s;
  for (int v = 0; v < 6; ++v) s[v] = S(kVoigtRow[v], kVoigtCol[v]);
  return s;
}

/// J_a^T J_b with J = [I, -[r]x], the velocity of a point at offset r from a rigid node.
Matrix6d bodyJacobianProduct(const Eigen::Vector3d& r_a, const Eigen::Vector3d& r_b) {
  Matrix6d block;
  block.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity();
  block.topRightCorner<3, 3>() = -skew(r_b);
  block.bottomLeftCorner<3, 3>() = skew(r_a);
  block.bottomRightCorner<3, 3>() = -skew(r_a) * skew(r_b);
  return block;
}

std::string sampleName(int s) { return "RigidNodeModel: sample " + std::to_string(s); }

}  // namespace

RigidNodeModel::RigidNodeModel(const RigidNodeConfiguration& rest,
                               const std::vector<RigidNodeSample>& samples)
    : rest_(rest), samples_(samples) {
  checkRigidNodeConfiguration(rest_, "RigidNodeModel: rest configuration");
  const int n = rest_.numNodes();
  if (n == 0 || samples_.empty()) {
    std::ostringstream msg;
    msg << "RigidNodeModel: " << n << " rigid nodes and " << samples_.size()
        << " samples: need at least one of each";
    throw std::invalid_argument(msg.str());
  }
  rest_rotation_transposed_.resize(n);
  for (int i = 0; i < n; ++i)
    rest_rotation_transposed_[i] = rest_.q_TN[i].toRotationMatrix().transpose();

  std::vector<std::vector<int>> adjacent(n);
  pair_begin_.assign(1, 0);
  for (int s = 0; s < numSamples(); ++s) {
    const RigidNodeSample& sample = samples_[s];
    const std::string name = sampleName(s);
    if (!sample.rest_position.allFinite()) {
      std::ostringstream msg;
      msg << name << " rest_position (" << sample.rest_position.transpose() << ") m is not finite";
      throw std::invalid_argument(msg.str());
    }
    requirePositive(name + " volume", sample.volume, "m^3");
    requireNonNegative(name + " lambda", sample.lambda, "Pa");
    requirePositive(name + " mu", sample.mu, "Pa");
    requirePositive(name + " density", sample.density, "kg/m^3");
    checkSampleWeights(sample.weights, n, name + " weights");
    const int k = static_cast<int>(sample.weights.nodes.size());
    if (k > kMaxSampleNeighbours) {
      std::ostringstream msg;
      msg << name << " has " << k << " rigid-node neighbours: at most " << kMaxSampleNeighbours;
      throw std::invalid_argument(msg.str());
    }
    for (int a = 0; a < k; ++a) {
      Pair pair;
      pair.node = sample.weights.nodes[a];
      pair.weight = sample.weights.weights[a];
      pair.gradient = sample.weights.gradients[a];
      pair.local_offset =
          rest_rotation_transposed_[pair.node] * (sample.rest_position - rest_.p_TN[pair.node]);
      pairs_.push_back(pair);
      for (int b = 0; b < k; ++b) adjacent[pair.node].push_back(sample.weights.nodes[b]);
    }
    pair_begin_.push_back(static_cast<int>(pairs_.size()));
  }

  run_ends_.resize(numSamples());
  for (int s = 0; s < numSamples(); ++s)
    run_ends_[s] =
        s + 1 == numSamples() || samples_[s + 1].weights.nodes != samples_[s].weights.nodes;

  std::vector<Eigen::Triplet<double>> triplets;
  for (int i = 0; i < n; ++i) {
    std::vector<int>& row = adjacent[i];
    if (row.empty()) {
      std::ostringstream msg;
      msg << "RigidNodeModel: rigid node " << i
          << " is a neighbour of no sample (its 6 DOFs would have no stiffness)";
      throw std::invalid_argument(msg.str());
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (int j : row)
      for (int c = 0; c < kRigidNodeDofs; ++c)
        for (int r = 0; r < kRigidNodeDofs; ++r)
          triplets.emplace_back(kRigidNodeDofs * j + r, kRigidNodeDofs * i + c, 0.0);
  }
  pattern_.resize(numDofs(), numDofs());
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();

  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  auto first = [&](int row_node, int column_node) {
    const int column = kRigidNodeDofs * column_node;
    return static_cast<int>(std::lower_bound(inner + outer[column], inner + outer[column + 1],
                                             kRigidNodeDofs * row_node) -
                            inner);
  };
  column_length_.resize(n);
  diagonal_first_.resize(n);
  for (int i = 0; i < n; ++i) {
    column_length_[i] = outer[kRigidNodeDofs * i + 1] - outer[kRigidNodeDofs * i];
    diagonal_first_[i] = first(i, i);
  }
  block_begin_.assign(1, 0);
  for (int s = 0; s < numSamples(); ++s) {
    for (int a = pair_begin_[s]; a < pair_begin_[s + 1]; ++a)
      for (int b = pair_begin_[s]; b < pair_begin_[s + 1]; ++b)
        block_first_.push_back(first(pairs_[a].node, pairs_[b].node));
    block_begin_.push_back(static_cast<int>(block_first_.size()));
  }
}

double RigidNodeModel::totalVolume() const {
  double v = 0.0;
  for (const RigidNodeSample& s : samples_) v += s.volume;
  return v;
}

double RigidNodeModel::totalMass() const {
  double m = 0.0;
  for (const RigidNodeSample& s : samples_) m += s.density * s.volume;
  return m;
}

Eigen::Vector3d RigidNodeModel::mapPoint(const RigidNodeConfiguration& q, const SampleWeights& w,
                                         const Eigen::Vector3d& rest_point) const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (size_t a = 0; a < w.nodes.size(); ++a) {
    const int i = w.nodes[a];
    const Eigen::Vector3d local = rest_rotation_transposed_[i] * (rest_point - rest_.p_TN[i]);
    p += w.weights[a] * (q.p_TN[i] + q.q_TN[i] * local);
  }
  return p;
}

Eigen::Vector3d RigidNodeModel::samplePosition(const RigidNodeConfiguration& q, int s) const {
  return mapPoint(q, samples_[s].weights, samples_[s].rest_position);
}

int RigidNodeModel::sampleFrame(const RigidNodeConfiguration& q, int s, Eigen::Matrix3d* A,
                                Eigen::Vector3d* r, Eigen::Matrix3d& F) const {
  const int begin = pair_begin_[s], k = pair_begin_[s + 1] - begin;
  // sum grad w = 0, so positions enter relative to the first neighbour (exact translation
  // invariance at any distance from the origin).
  const Eigen::Vector3d origin = q.p_TN[pairs_[begin].node];
  F.setZero();
  for (int a = 0; a < k; ++a) {
    const Pair& pair = pairs_[begin + a];
    const Eigen::Matrix3d R = q.q_TN[pair.node].toRotationMatrix();
    r[a] = R * pair.local_offset;
    A[a] =
        r[a] * pair.gradient.transpose() + pair.weight * R * rest_rotation_transposed_[pair.node];
    F += (q.p_TN[pair.node] - origin) * pair.gradient.transpose() + A[a];
  }
  return k;
}

SampleKinematics RigidNodeModel::sampleKinematics(const RigidNodeConfiguration& q, int s) const {
  Eigen::Matrix3d A[kMaxSampleNeighbours];
  Eigen::Vector3d r[kMaxSampleNeighbours];
  SampleKinematics out;
  const int k = sampleFrame(q, s, A, r, out.F);
  for (int a = 0; a < k; ++a) {
    const Eigen::Vector3d& g = pairs_[pair_begin_[s] + a].gradient;
    Eigen::Matrix<double, 9, 6> B;
    for (int j = 0; j < 3; ++j) {
      B.block<3, 3>(3 * j, 0) = g[j] * Eigen::Matrix3d::Identity();
      B.block<3, 3>(3 * j, 3) = -skew(A[a].col(j));
    }
    out.B.push_back(B);
    out.M.push_back(strainJacobian(out.F, g, A[a]));
  }
  return out;
}

Vector6d RigidNodeModel::sampleStress(int s, const Eigen::Matrix3d& F) const {
  const Eigen::Matrix3d E = greenLagrange(F);
  const RigidNodeSample& sample = samples_[s];
  return toVoigtStress(sample.lambda * E.trace() * Eigen::Matrix3d::Identity() +
                       2.0 * sample.mu * E);
}

double RigidNodeModel::energy(const RigidNodeConfiguration& q) const {
  Eigen::Matrix3d A[kMaxSampleNeighbours];
  Eigen::Vector3d r[kMaxSampleNeighbours];
  double W = 0.0;
  for (int s = 0; s < numSamples(); ++s) {
    Eigen::Matrix3d F;
    sampleFrame(q, s, A, r, F);
    const Eigen::Matrix3d E = greenLagrange(F);
    const RigidNodeSample& sample = samples_[s];
    W +=
        sample.volume * (0.5 * sample.lambda * E.trace() * E.trace() + sample.mu * E.squaredNorm());
  }
  return W;
}

void RigidNodeModel::checkVector(const Eigen::VectorXd& f, const char* what) const {
  if (f.size() != numDofs()) {
    std::ostringstream msg;
    msg << "RigidNodeModel::" << what << ": vector size " << f.size() << " must be " << numDofs()
        << " (6 per rigid node)";
    throw std::invalid_argument(msg.str());
  }
}

void RigidNodeModel::checkMatrix(const Eigen::SparseMatrix<double>& K, const char* what) const {
  if (K.rows() != numDofs() || K.cols() != numDofs() || !K.isCompressed() ||
      K.nonZeros() != pattern_.nonZeros()) {
    std::ostringstream msg;
    msg << "RigidNodeModel::" << what << ": matrix " << K.rows() << " x " << K.cols() << " with "
        << K.nonZeros() << " entries must have stiffnessPattern() (" << numDofs() << " x "
        << numDofs() << ", " << pattern_.nonZeros() << " entries, compressed)";
    throw std::invalid_argument(msg.str());
  }
}

void RigidNodeModel::scatter(int s, int a, int b, const Matrix6d& Kab, double* values) const {
  const int k = pair_begin_[s + 1] - pair_begin_[s];
  double* block = values + block_first_[block_begin_[s] + a * k + b];
  const int length = column_length_[pairs_[pair_begin_[s] + b].node];
  for (int c = 0; c < kRigidNodeDofs; ++c)
    for (int r = 0; r < kRigidNodeDofs; ++r) block[c * length + r] += Kab(r, c);
}

void RigidNodeModel::evaluate(const RigidNodeConfiguration& q,
                              const RigidNodeTangentOptions* options, Eigen::VectorXd* f,
                              Eigen::SparseMatrix<double>* K) const {
  constexpr int kMaxDofs = kRigidNodeDofs * kMaxSampleNeighbours;
  // Rows of the material factor X of the samples of a run, flushed when full.
  constexpr int kStackedSamples = 16;
  using Local = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDofs, kMaxDofs>;
  Eigen::Matrix3d A[kMaxSampleNeighbours];
  Eigen::Vector3d r[kMaxSampleNeighbours];
  Eigen::Vector3d SG[kMaxSampleNeighbours];  // v S grad w_a
  Eigen::Matrix3d AS[kMaxSampleNeighbours];  // v A_a S
  // Blocks a <= b of a run of samples with the same rigid nodes, scattered once per run:
  // geometric (full blocks) and material (upper triangle, X^T X).
  Local geometric, material;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, 7 * kStackedSamples,
                kMaxDofs>
      stacked;
  int stacked_rows = 0;
  auto flush = [&]() {
    if (stacked_rows == 0) return;
    if (!fastUpperRankUpdate(stacked_rows, static_cast<int>(material.rows()), stacked.data(),
                             material.data())) {
      material.selfadjointView<Eigen::Upper>().rankUpdate(
          stacked.topRows(stacked_rows).transpose());
    }
    stacked_rows = 0;
  };
  bool run_started = false;
  double* values = nullptr;
  if (K != nullptr) {
    K->coeffs().setZero();
    values = K->valuePtr();
  }
  for (int s = 0; s < numSamples(); ++s) {
    const RigidNodeSample& sample = samples_[s];
    Eigen::Matrix3d F;
    const int k = sampleFrame(q, s, A, r, F);
    const int begin = pair_begin_[s];
    const Eigen::Matrix3d E = greenLagrange(F);
    const Eigen::Matrix3d S =
        sample.lambda * E.trace() * Eigen::Matrix3d::Identity() + 2.0 * sample.mu * E;
    const Eigen::Matrix3d P = F * S;
    const double v = sample.volume;
    if (f != nullptr) {
      // -M^T {S} v = -v (P grad w, sum_j a_j x P_j): the virtual work {S}.d{E} = P : dF.
      for (int a = 0; a < k; ++a) {
        const int i = pairs_[begin + a].node;
        f->segment<3>(kRigidNodeDofs * i) -= v * P * pairs_[begin + a].gradient;
        Eigen::Vector3d torque = Eigen::Vector3d::Zero();
        for (int j = 0; j < 3; ++j) torque += A[a].col(j).cross(P.col(j));
        f->segment<3>(kRigidNodeDofs * i + 3) -= v * torque;
      }
    }
    if (K == nullptr) continue;
    const int dofs = kRigidNodeDofs * k;
    if (!run_started) {
      geometric.setZero(dofs, dofs);
      material.setZero(dofs, dofs);
      stacked.resize(7 * kStackedSamples, dofs);
    }
    run_started = true;
    if (options->material) {
      // v M^T C M = X^T X with C = lambda 1 1^T (normal block) + diag(2mu, 2mu, 2mu, mu, mu, mu):
      // rows sqrt(v d_i) M_i and sqrt(v lambda) (M_0 + M_1 + M_2).
      if (stacked_rows + 7 > stacked.rows()) flush();
      const double normal = std::sqrt(2.0 * sample.mu * v), shear = std::sqrt(sample.mu * v);
      const double trace = std::sqrt(sample.lambda * v);
      for (int a = 0; a < k; ++a) {
        const Matrix6d M = strainJacobian(F, pairs_[begin + a].gradient, A[a]);
        auto block = stacked.block<7, kRigidNodeDofs>(stacked_rows, kRigidNodeDofs * a);
        block.topRows<3>() = normal * M.topRows<3>();
        block.middleRows<3>(3) = shear * M.bottomRows<3>();
        block.row(6) = trace * M.topRows<3>().colwise().sum();
      }
      stacked_rows += 7;
    }
    if (options->geometric) {
      for (int a = 0; a < k; ++a) {
        SG[a] = v * (S * pairs_[begin + a].gradient);
        AS[a] = v * A[a] * S;
      }
      // K_ba = K_ab^T but for the rotation term on a == b: blocks a <= b, mirrored.
      for (int a = 0; a < k; ++a) {
        const Eigen::Vector3d& ga = pairs_[begin + a].gradient;
        for (int b = a; b < k; ++b) {
          // v sum_jl S_jl B_aj^T B_bl with B_j = [g_j I, -[a_j]x].
          auto G = geometric.block<6, 6>(kRigidNodeDofs * a, kRigidNodeDofs * b);
          G.topLeftCorner<3, 3>().diagonal().array() += ga.dot(SG[b]);
          addSkew(-1.0, A[b] * SG[a], G.topRightCorner<3, 3>());
          addSkew(1.0, A[a] * SG[b], G.bottomLeftCorner<3, 3>());
          G.bottomRightCorner<3, 3>().noalias() -= A[b] * AS[a].transpose();
          G.bottomRightCorner<3, 3>().diagonal().array() += AS[a].cwiseProduct(A[b]).sum();
          if (a == b) {
            // The rotation of a_j itself: v sum_j [P_j]x [a_j]x.
            Eigen::Matrix3d theta = v * (A[a] * P.transpose() -
                                         P.cwiseProduct(A[a]).sum() * Eigen::Matrix3d::Identity());
            if (options->symmetrize) theta = 0.5 * (theta + theta.transpose()).eval();
            G.bottomRightCorner<3, 3>() += theta;
          }
        }
      }
    }
    if (!run_ends_[s]) continue;
    flush();
    material.triangularView<Eigen::StrictlyLower>() = material.transpose();
    for (int a = 0; a < k; ++a) {
      for (int b = a; b < k; ++b) {
        const Matrix6d G = geometric.block<6, 6>(kRigidNodeDofs * a, kRigidNodeDofs * b) +
                           material.block<6, 6>(kRigidNodeDofs * a, kRigidNodeDofs * b);
        scatter(s, a, b, G, values);
        if (b != a) scatter(s, b, a, G.transpose(), values);
      }
    }
    run_started = false;
  }
}

void RigidNodeModel::addInternalForce(const RigidNodeConfiguration& q, Eigen::VectorXd& f) const {
  checkVector(f, "addInternalForce");
  evaluate(q, nullptr, &f, nullptr);
}

void RigidNodeModel::assembleStiffness(const RigidNodeConfiguration& q,
                                       const RigidNodeTangentOptions& options,
                                       Eigen::SparseMatrix<double>& K) const {
  checkMatrix(K, "assembleStiffness");
  evaluate(q, &options, nullptr, &K);
}

void RigidNodeModel::addInternalForceAndStiffness(const RigidNodeConfiguration& q,
                                                  const RigidNodeTangentOptions& options,
                                                  Eigen::VectorXd& f,
                                                  Eigen::SparseMatrix<double>& K) const {
  checkVector(f, "addInternalForceAndStiffness");
  checkMatrix(K, "addInternalForceAndStiffness");
  evaluate(q, &options, &f, &K);
}

void RigidNodeModel::addBodyForce(const RigidNodeConfiguration& q, const Eigen::Vector3d& a,
                                  Eigen::VectorXd& f) const {
  checkVector(f, "addBodyForce");
  for (int s = 0; s < numSamples(); ++s) {
    const double m = samples_[s].density * samples_[s].volume;
    for (int p = pair_begin_[s]; p < pair_begin_[s + 1]; ++p) {
      const Pair& pair = pairs_[p];
      const Eigen::Vector3d r = q.q_TN[pair.node] * pair.local_offset;
      f.segment<3>(kRigidNodeDofs * pair.node) += m * pair.weight * a;
      f.segment<3>(kRigidNodeDofs * pair.node + 3) += m * pair.weight * r.cross(a);
    }
  }
}

double RigidNodeModel::bodyForcePotential(const RigidNodeConfiguration& q,
                                          const Eigen::Vector3d& a) const {
  double potential = 0.0;
  for (int s = 0; s < numSamples(); ++s)
    potential -= samples_[s].density * samples_[s].volume * a.dot(samplePosition(q, s));
  return potential;
}

void RigidNodeModel::addBodyForceStiffness(const RigidNodeConfiguration& q,
                                           const Eigen::Vector3d& a, bool symmetrize,
                                           Eigen::SparseMatrix<double>& K) const {
  checkMatrix(K, "addBodyForceStiffness");
  double* values = K.valuePtr();
  for (int s = 0; s < numSamples(); ++s) {
    const double m = samples_[s].density * samples_[s].volume;
    for (int p = pair_begin_[s]; p < pair_begin_[s + 1]; ++p) {
      const Pair& pair = pairs_[p];
      const Eigen::Vector3d r = q.q_TN[pair.node] * pair.local_offset;
      // -d(r x a)/dtheta = -[a]x [r]x = -(r a^T - (a.r) I).
      Eigen::Matrix3d block = r * a.transpose() - a.dot(r) * Eigen::Matrix3d::Identity();
      if (symmetrize) block = 0.5 * (block + block.transpose()).eval();
      double* diagonal = values + diagonal_first_[pair.node];
      const int length = column_length_[pair.node];
      for (int c = 0; c < 3; ++c)
        for (int rr = 0; rr < 3; ++rr)
          diagonal[(c + 3) * length + rr + 3] -= m * pair.weight * block(rr, c);
    }
  }
}

void RigidNodeModel::assembleMass(const RigidNodeConfiguration& q,
                                  Eigen::SparseMatrix<double>& M) const {
  checkMatrix(M, "assembleMass");
  M.coeffs().setZero();
  Eigen::Vector3d r[kMaxSampleNeighbours];
  for (int s = 0; s < numSamples(); ++s) {
    const double m = samples_[s].density * samples_[s].volume;
    const int begin = pair_begin_[s], k = pair_begin_[s + 1] - begin;
    for (int a = 0; a < k; ++a)
      r[a] = q.q_TN[pairs_[begin + a].node] * pairs_[begin + a].local_offset;
    for (int a = 0; a < k; ++a) {
      for (int b = 0; b < k; ++b) {
        const double scale = m * pairs_[begin + a].weight * pairs_[begin + b].weight;
        scatter(s, a, b, scale * bodyJacobianProduct(r[a], r[b]), M.valuePtr());
      }
    }
  }
}

void RigidNodeModel::assembleNodeMass(const RigidNodeConfiguration& q,
                                      Eigen::SparseMatrix<double>& M) const {
  checkMatrix(M, "assembleNodeMass");
  M.coeffs().setZero();
  for (int s = 0; s < numSamples(); ++s) {
    const double m = samples_[s].density * samples_[s].volume;
    for (int a = 0; a < pair_begin_[s + 1] - pair_begin_[s]; ++a) {
      const Pair& pair = pairs_[pair_begin_[s] + a];
      // m w J^T J = m w [I, -[r]x; [r]x, |r|^2 I - r r^T], straight into node i's diagonal block.
      const Eigen::Vector3d r = q.q_TN[pair.node] * pair.local_offset;
      const double mw = m * pair.weight;
      const Eigen::Matrix3d inertia =
          mw * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
      double* block = M.valuePtr() + diagonal_first_[pair.node];
      const int length = column_length_[pair.node];
      const Eigen::Matrix3d moment = skew(mw * r);
      for (int j = 0; j < 3; ++j) {
        block[j * length + j] += mw;
        for (int i = 0; i < 3; ++i) {
          block[(j + 3) * length + i] -= moment(i, j);
          block[j * length + i + 3] += moment(i, j);
          block[(j + 3) * length + i + 3] += inertia(i, j);
        }
      }
    }
  }
}

}  // namespace surgical_sim::core
