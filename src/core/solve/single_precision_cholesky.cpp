#include "surgical_sim/core/solve/single_precision_cholesky.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {
namespace {

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
  for (Eigen::VectorXf& below : below_) below.resize(static_cast<Eigen::Index>(widest_below));
  for (Eigen::VectorXf& top_update : top_update_)
    top_update.resize(static_cast<Eigen::Index>(L->n));
  splitTree();
  if (threads_ > 1 && !pool_) pool_ = std::make_shared<ThreadPool>(threads_);
  copyArray(L->Perm, L->n, perm_);
  return true;
}

SinglePrecisionCholesky::SinglePrecisionCholesky(int threads) {
  requireInRange("threads", threads, 1, kMaxThreads, "");
  threads_ = std::min(threads, 2);
}

void SinglePrecisionCholesky::splitTree() {
  const auto supernodes = static_cast<int>(first_column_.size()) - 1;
  const int n = first_column_.back();
  std::vector<int> owner(static_cast<size_t>(n));
  std::vector<int> parent(static_cast<size_t>(supernodes), -1);
  std::vector<std::vector<int>> children(static_cast<size_t>(supernodes));
  std::vector<double> work(static_cast<size_t>(supernodes));  // subtree factor entries
  std::vector<int> candidates;
  for (int s = 0; s < supernodes; ++s) {
    const Supernode node = supernode(s);
    for (int c = node.first; c < node.first + node.columns; ++c) owner[static_cast<size_t>(c)] = s;
    work[static_cast<size_t>(s)] += static_cast<double>(node.below + node.columns) * node.columns;
  }
  for (int s = 0; s < supernodes; ++s) {  // children have lower indices than their parent
    const Supernode node = supernode(s);
    if (node.below == 0) {
      candidates.push_back(s);
      continue;
    }
    const int p = owner[static_cast<size_t>(*std::min_element(node.rows, node.rows + node.below))];
    parent[static_cast<size_t>(s)] = p;
    children[static_cast<size_t>(p)].push_back(s);
    work[static_cast<size_t>(p)] += work[static_cast<size_t>(s)];
  }
  // Descend along the heaviest subtree until no subtree holds more than half the work left.
  std::vector<int> bin(static_cast<size_t>(supernodes), 2);
  const auto heavier = [&](int a, int b) {
    return work[static_cast<size_t>(a)] > work[static_cast<size_t>(b)] ||
           (work[static_cast<size_t>(a)] == work[static_cast<size_t>(b)] && a < b);
  };
  for (;;) {
    if (candidates.empty()) break;
    const auto heaviest = std::min_element(candidates.begin(), candidates.end(), heavier);
    double total = 0.0;
    for (const int c : candidates) total += work[static_cast<size_t>(c)];
    const int h = *heaviest;
    if (2.0 * work[static_cast<size_t>(h)] <= total || children[static_cast<size_t>(h)].empty())
      break;
    candidates.erase(heaviest);
    candidates.insert(candidates.end(), children[static_cast<size_t>(h)].begin(),
                      children[static_cast<size_t>(h)].end());
  }
  std::sort(candidates.begin(), candidates.end(), heavier);
  double bin_work[2] = {0.0, 0.0};
  for (const int c : candidates) {
    const int b = bin_work[1] < bin_work[0] ? 1 : 0;
    bin[static_cast<size_t>(c)] = b;
    bin_work[b] += work[static_cast<size_t>(c)];
  }
  for (int s = supernodes - 1; s >= 0; --s) {  // parents first: a subtree takes its root's bin
    const int p = parent[static_cast<size_t>(s)];
    if (bin[static_cast<size_t>(s)] == 2 && p >= 0 && bin[static_cast<size_t>(p)] != 2)
      bin[static_cast<size_t>(s)] = bin[static_cast<size_t>(p)];
  }
  for (std::vector<int>& order : order_) order.clear();
  top_rows_.clear();
  in_top_.assign(static_cast<size_t>(n), 0);
  for (int s = 0; s < supernodes; ++s) {
    const int b = bin[static_cast<size_t>(s)];
    order_[b].push_back(s);
    if (b != 2) continue;
    for (int c = first_column_[s]; c < first_column_[s + 1]; ++c) {
      top_rows_.push_back(c);
      in_top_[static_cast<size_t>(c)] = 1;
    }
  }
}

SinglePrecisionCholesky::Supernode SinglePrecisionCholesky::supernode(int s) const {
  const int first = first_column_[s], columns = first_column_[s + 1] - first;
  const int height = row_start_[s + 1] - row_start_[s];
  return Supernode{
      first, columns, height - columns, rows_.data() + row_start_[s] + columns,
      Block(values_.data() + value_start_[s], height, columns, Eigen::OuterStride<>(height))};
}

void SinglePrecisionCholesky::forward(int bin) {
  Eigen::VectorXf& below = below_[bin];
  for (const int s : order_[bin]) {
    const Supernode node = supernode(s);
    auto own = permuted_.segment(node.first, node.columns);
    node.block.topRows(node.columns).triangularView<Eigen::Lower>().solveInPlace(own);
    if (node.below == 0) continue;
    below.head(node.below).noalias() = node.block.bottomRows(node.below) * own;
    if (bin == 2) {
      for (int i = 0; i < node.below; ++i) permuted_[node.rows[i]] -= below[i];
      continue;
    }
    Eigen::VectorXf& top_update = top_update_[bin];
    for (int i = 0; i < node.below; ++i) {
      const int row = node.rows[i];
      if (in_top_[static_cast<size_t>(row)] != 0) {
        top_update[row] += below[i];
      } else {
        permuted_[row] -= below[i];
      }
    }
  }
}

void SinglePrecisionCholesky::backward(int bin) {
  Eigen::VectorXf& below = below_[bin];
  for (auto s = order_[bin].rbegin(); s != order_[bin].rend(); ++s) {
    const Supernode node = supernode(*s);
    auto own = permuted_.segment(node.first, node.columns);
    if (node.below > 0) {
      for (int i = 0; i < node.below; ++i) below[i] = permuted_[node.rows[i]];
      own.noalias() -= node.block.bottomRows(node.below).transpose() * below.head(node.below);
    }
    node.block.topRows(node.columns).transpose().triangularView<Eigen::Upper>().solveInPlace(own);
  }
}

void SinglePrecisionCholesky::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  const Eigen::Index n = rows();
  // Solved for r / |r|_inf, so a residual of any magnitude stays in float's normal range.
  const double scale = r.cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    z = r;  // zero stays zero; non-finite propagates
    return;
  }
  for (Eigen::Index k = 0; k < n; ++k) permuted_[k] = static_cast<float>(r[perm_[k]] / scale);
  for (Eigen::VectorXf& top_update : top_update_) {
    for (const int row : top_rows_) top_update[row] = 0.0F;
  }
  bothBins([this](int bin) { forward(bin); });
  for (const int row : top_rows_) {
    permuted_[row] -= top_update_[0][row];
    permuted_[row] -= top_update_[1][row];
  }
  forward(2);
  backward(2);
  bothBins([this](int bin) { backward(bin); });
  z.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) z[perm_[k]] = scale * static_cast<double>(permuted_[k]);
}

}  // namespace surgical_sim::core
