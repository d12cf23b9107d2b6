#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/solve/linear_solver.h"

namespace surgical_sim::core {

/// The step compliance S f = scale A^-1 f of an implicit integrator (Integrator::
/// applyStepCompliance), A the system matrix of its last successful step, whose factorization
/// the integrator's solver either still holds (markFactorized) or builds on first use
/// (markStale). Dirichlet DOFs of f are ignored and get dx = 0.
class StepCompliance {
 public:
  /// No usable step (set-up, reset, a failed or running step).
  void invalidate() { state_ = State::Unavailable; }
  /// A successful step whose factorization the solver still holds; scale e.g. dt^2.
  void markFactorized(double scale) { mark(State::Factorized, scale); }
  /// A successful step; the factorization at its end point is built by apply() when needed.
  void markStale(double scale) { mark(State::Stale, scale); }

  /// dx = scale A^-1 f (f's Dirichlet entries zeroed, mask[i] != 0). dx on entry, if it has f's
  /// size and is finite, starts an iterative solver (its Dirichlet entries zeroed; otherwise the
  /// start is zero); the solver's tolerance, relative to |scale f|, is the same from any start.
  /// `factorize()` assembles and factorizes A in `solver` for a stale step and returns false on
  /// failure (the compliance is then unavailable until the next step). False as well if
  /// unavailable, if f's size is not the mask's, or if the solve fails or is not finite.
  template <class Factorize>
  bool apply(LinearSolver& solver, const std::vector<std::uint8_t>& mask, const Eigen::VectorXd& f,
             Eigen::VectorXd& dx, Factorize&& factorize) {
    last_iterations_ = 0;
    if (state_ == State::Unavailable || static_cast<size_t>(f.size()) != mask.size()) return false;
    if (state_ == State::Stale) {
      if (!factorize()) {
        state_ = State::Unavailable;
        return false;
      }
      state_ = State::Factorized;
    }
    rhs_ = scale_ * f;
    if (dx.size() != f.size() || !dx.allFinite()) dx.setZero(f.size());
    for (Eigen::Index i = 0; i < f.size(); ++i) {
      if (mask[static_cast<size_t>(i)] == 0) continue;
      rhs_[i] = 0.0;
      dx[i] = 0.0;
    }
    const LinearSolveReport report = solver.solve(rhs_, dx);
    last_iterations_ = report.iterations;
    return report.ok && dx.allFinite();
  }
  /// Linear-solver iterations of the last apply() (0 if it did not reach the solve).
  int lastIterations() const { return last_iterations_; }

 private:
  enum class State { Unavailable, Stale, Factorized };
  void mark(State state, double scale) {
    state_ = state;
    scale_ = scale;
  }

  State state_ = State::Unavailable;
  double scale_ = 0.0;
  Eigen::VectorXd rhs_;  ///< projected right-hand side (work vector)
  int last_iterations_ = 0;
};

}  // namespace surgical_sim::core
