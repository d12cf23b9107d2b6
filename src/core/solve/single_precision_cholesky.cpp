#include "surgical_sim/core/solve/single_precision_cholesky.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {
namespace {

using Block = Eigen::Map<const Eigen::MatrixXf, 0, Eigen::OuterStride<>>;

template <typename T>
void copyArray(const void* from, size_t size, std::vector<T>& to) {
  const auto* begin = static_cast<const T*>(from);
  to.assign(begin, begin + size);
}

}  // namespace

bool SinglePrecisionCholesky::assign(const CholmodSolver& solver) {
  perm_.clear();
  const cholmod_factor* L = solver.numericFactor();
  if (L == nullptr || L->is_super == 0 || L->is_ll == 0 || L->xtype != CHOLMOD_REAL ||
      L->itype != CHOLMOD_INT) {
    return false;
  }
  const size_t supernodes = L->nsuper;
  copyArray(L->super, supernodes + 1, first_column_);
  copyArray(L->pi, supernodes + 1, row_start_);
  copyArray(L->px, supernodes + 1, value_start_);
  copyArray(L->s, static_cast<size_t>(row_start_.back()), rows_);
  const auto* x = static_cast<const double*>(L->x);
  values_.resize(static_cast<size_t>(value_start_.back()));
  for (size_t k = 0; k < values_.size(); ++k) {
    values_[k] = static_cast<float>(x[k]);
    if (!std::isfinite(values_[k])) return false;
  }
  size_t widest_below = 0;
  for (size_t s = 0; s < supernodes; ++s) {
    const int columns = first_column_[s + 1] - first_column_[s];
    const int height = row_start_[s + 1] - row_start_[s];
    widest_below = std::max(widest_below, static_cast<size_t>(height - columns));
    for (int j = 0; j < columns; ++j) {  // a pivot below float's normal range divides badly
      if (!(values_[static_cast<size_t>(value_start_[s] + j * height + j)] >=
            std::numeric_limits<float>::min())) {
        return false;
      }
    }
  }
  permuted_.resize(static_cast<Eigen::Index>(L->n));
  below_.resize(static_cast<Eigen::Index>(widest_below));
  copyArray(L->Perm, L->n, perm_);
  return true;
}

void SinglePrecisionCholesky::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  const Eigen::Index n = rows();
  const auto supernodes = static_cast<int>(first_column_.size()) - 1;
  // Solved for r / |r|_inf, so a residual of any magnitude stays in float's normal range.
  const double scale = r.cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    z = r;  // zero stays zero; non-finite propagates
    return;
  }
  for (Eigen::Index k = 0; k < n; ++k) permuted_[k] = static_cast<float>(r[perm_[k]] / scale);
  // Supernode s: its columns [first, first + columns) in the block's top rows, then the rows
  // below (indices `rows`).
  struct Supernode {
    int first, columns, below;
    const int* rows;
    Block block;
  };
  const auto supernode = [this](int s) {
    const int first = first_column_[s], columns = first_column_[s + 1] - first;
    const int height = row_start_[s + 1] - row_start_[s];
    return Supernode{
        first, columns, height - columns, rows_.data() + row_start_[s] + columns,
        Block(values_.data() + value_start_[s], height, columns, Eigen::OuterStride<>(height))};
  };
  // Forward: per supernode, its diagonal block, then the rows below it.
  for (int s = 0; s < supernodes; ++s) {
    const Supernode node = supernode(s);
    auto own = permuted_.segment(node.first, node.columns);
    node.block.topRows(node.columns).triangularView<Eigen::Lower>().solveInPlace(own);
    if (node.below == 0) continue;
    below_.head(node.below).noalias() = node.block.bottomRows(node.below) * own;
    for (int i = 0; i < node.below; ++i) permuted_[node.rows[i]] -= below_[i];
  }
  // Backward with L^T, supernodes in reverse.
  for (int s = supernodes - 1; s >= 0; --s) {
    const Supernode node = supernode(s);
    auto own = permuted_.segment(node.first, node.columns);
    if (node.below > 0) {
      for (int i = 0; i < node.below; ++i) below_[i] = permuted_[node.rows[i]];
      own.noalias() -= node.block.bottomRows(node.below).transpose() * below_.head(node.below);
    }
    node.block.topRows(node.columns).transpose().triangularView<Eigen::Upper>().solveInPlace(own);
  }
  z.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) z[perm_[k]] = scale * static_cast<double>(permuted_[k]);
}

}  // namespace surgical_sim::core
