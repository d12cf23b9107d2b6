#include "surgical_sim/core/contact/lcp_active_set.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace surgical_sim::core {
namespace {

/// Diagonal regularization of W_AA relative to its mean diagonal [-].
constexpr double kActiveSetRegularization = 1e-10;

}  // namespace

LcpActiveSetWorkspace::LcpActiveSetWorkspace(Eigen::Index capacity)
    : factor_(capacity, capacity), solution_(capacity) {
  active_.reserve(static_cast<size_t>(capacity));
  in_set_.assign(static_cast<size_t>(capacity), 0);
}

PgsReport refineLcpActiveSet(const Eigen::Ref<const Eigen::MatrixXd>& W,
                             const Eigen::Ref<const Eigen::VectorXd>& q, double tolerance,
                             int max_pivots, Eigen::Ref<Eigen::VectorXd> lambda,
                             LcpActiveSetWorkspace& workspace, const LcpColumnSource& source) {
  PgsReport report;
  const Eigen::Index m = q.size();
  if (m > workspace.factor_.rows()) return report;
  std::vector<char>& in_set = workspace.in_set_;
  std::vector<Eigen::Index>& active = workspace.active_;
  for (Eigen::Index i = 0; i < m; ++i) in_set[static_cast<size_t>(i)] = lambda[i] > 0.0;

  for (int pivot = 0; pivot <= max_pivots; ++pivot) {
    active.clear();
    for (Eigen::Index i = 0; i < m; ++i) {
      if (in_set[static_cast<size_t>(i)]) active.push_back(i);
    }
    const auto a = static_cast<Eigen::Index>(active.size());
    if (source) {
      for (const Eigen::Index j : active) {
        if (!source(j)) return report;
      }
    }
    auto lambda_a = workspace.solution_.head(a);
    if (a > 0) {
      Eigen::Ref<Eigen::MatrixXd> Waa = workspace.factor_.topLeftCorner(a, a);
      double trace = 0.0;
      for (Eigen::Index r = 0; r < a; ++r) {
        for (Eigen::Index c = 0; c < a; ++c) Waa(r, c) = W(active[r], active[c]);
        lambda_a[r] = -q[active[r]];
        trace += Waa(r, r);
      }
      Waa.diagonal().array() += kActiveSetRegularization * trace / static_cast<double>(a);
      Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(Waa);
      if (llt.info() != Eigen::Success) return report;
      llt.solveInPlace(lambda_a);
    }
    // Drop the most negative multiplier first; the gaps are only meaningful with lambda_A >= 0.
    Eigen::Index worst = -1;
    double worst_value = 0.0;
    for (Eigen::Index r = 0; r < a; ++r) {
      if (lambda_a[r] < worst_value) {
        worst_value = lambda_a[r];
        worst = active[r];
      }
    }
    if (worst >= 0) {
      in_set[static_cast<size_t>(worst)] = 0;
      continue;
    }
    worst_value = -tolerance;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (in_set[static_cast<size_t>(i)]) continue;
      double gap = q[i];
      for (Eigen::Index r = 0; r < a; ++r) gap += W(i, active[r]) * lambda_a[r];
      if (gap < worst_value) {
        worst_value = gap;
        worst = i;
      }
    }
    if (worst >= 0) {
      in_set[static_cast<size_t>(worst)] = 1;
      continue;
    }
    lambda.setZero();
    for (Eigen::Index r = 0; r < a; ++r) lambda[active[r]] = lambda_a[r];
    report.iterations = pivot;
    report.residual = lcpMinMapResidual(W, q, lambda);
    report.converged = true;
    return report;
  }
  return report;
}

}  // namespace surgical_sim::core
