#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "surgical_sim/core/contact/projected_gauss_seidel.h"

namespace surgical_sim::core {

/// Makes column j of the W of refineLcpActiveSet available (it may compute it on demand: the
/// refinement reads only the columns of active contacts); false if it cannot (the refinement then
/// stops, not converged).
using LcpColumnSource = std::function<bool(Eigen::Index j)>;

/// Preallocated storage of refineLcpActiveSet for up to `capacity` contacts.
class LcpActiveSetWorkspace {
 public:
  explicit LcpActiveSetWorkspace(Eigen::Index capacity = 0);

 private:
  friend PgsReport refineLcpActiveSet(const Eigen::Ref<const Eigen::MatrixXd>&,
                                      const Eigen::Ref<const Eigen::VectorXd>&, double, int,
                                      Eigen::Ref<Eigen::VectorXd>, LcpActiveSetWorkspace&,
                                      const LcpColumnSource&);
  Eigen::MatrixXd factor_;
  Eigen::VectorXd solution_;
  std::vector<Eigen::Index> active_;
  std::vector<char> in_set_;
};

/// Principal-pivoting refinement of the LCP 0 <= lambda _|_ q + W lambda >= 0 (W symmetric
/// positive semi-definite [m/N], q [m]) started from the support of `lambda`, typically a
/// projected Gauss-Seidel iterate: with the active set A it solves W_AA lambda_A = -q_A exactly
/// (Cholesky; a diagonal regularization of 1e-10 x mean diag(W_AA) keeps redundant contacts
/// solvable), then drops the most negative multiplier or adds the most violated gap
/// (q + W lambda)_i < -tolerance, one change at a time, for at most max_pivots changes.
/// On success `lambda` holds the solution (inactive entries 0) and the report is converged with
/// the min-map residual of solveLcpProjectedGaussSeidel; otherwise `lambda` is left untouched and
/// the report is not converged. Allocation-free while q.size() <= the workspace capacity (larger
/// problems are refused: report not converged, lambda untouched). With a column source, only the
/// columns of W it has made available (source(j) before column j of an active contact is read)
/// need to hold W's values; the min-map residual then reads W lambda, which needs no other column.
PgsReport refineLcpActiveSet(const Eigen::Ref<const Eigen::MatrixXd>& W,
                             const Eigen::Ref<const Eigen::VectorXd>& q, double tolerance,
                             int max_pivots, Eigen::Ref<Eigen::VectorXd> lambda,
                             LcpActiveSetWorkspace& workspace,
                             const LcpColumnSource& source = nullptr);

}  // namespace surgical_sim::core
