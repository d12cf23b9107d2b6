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

  /// dx = scale A^-1 f (f's Dirichlet entries zeroed, mask[i] != 0). `factorize()` assembles and
  /// factorizes A in `solver` for a stale step and returns false on failure (the compliance is
  /// then unavailable until the next step). False as well if unavailable, if f's size is not the
  /// mask's, or if the solve fails or is not finite.
  template <class Factorize>
  bool apply(LinearSolver& solver, const std::vector<std::uint8_t>& mask, const Eigen::VectorXd& f,
             Eigen::VectorXd& dx, Factorize&& factorize) {
    if (state_ == State::Unavailable || static_cast<size_t>(f.size()) != mask.size()) return false;
    if (state_ == State::Stale) {
      if (!factorize()) {
        state_ = State::Unavailable;
        return false;
      }
      state_ = State::Factorized;
    }
    rhs_ = scale_ * f;
    for (Eigen::Index i = 0; i < f.size(); ++i) {
      if (mask[static_cast<size_t>(i)] != 0) rhs_[i] = 0.0;
    }
    dx.setZero(f.size());
    return solver.solve(rhs_, dx).ok && dx.allFinite();
  }

 private:
  enum class State { Unavailable, Stale, Factorized };
  void mark(State state, double scale) {
    state_ = state;
    scale_ = scale;
  }

  State state_ = State::Unavailable;
  double scale_ = 0.0;
  Eigen::VectorXd rhs_;  ///< projected right-hand side (work vector)
};

}  // namespace surgical_sim::core
