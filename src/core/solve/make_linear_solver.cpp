#include "surgical_sim/core/solve/make_linear_solver.h"

#include <stdexcept>

#include "surgical_sim/core/solve/background_cholesky_pcg_solver.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {

std::unique_ptr<LinearSolver> makeLinearSolver(SolverKind kind, const PcgSettings& pcg) {
  switch (kind) {
    case SolverKind::Cholmod:
      return std::make_unique<CholmodSolver>();
    case SolverKind::PcgJacobi:
      return std::make_unique<PcgSolver>(PcgPreconditioner::Jacobi, pcg);
    case SolverKind::PcgBlockJacobi:
      return std::make_unique<PcgSolver>(PcgPreconditioner::BlockJacobi, pcg);
    case SolverKind::PcgIchol:
      return std::make_unique<PcgSolver>(PcgPreconditioner::IncompleteCholesky, pcg);
    case SolverKind::PcgCholeskyReuse:
      return std::make_unique<PcgSolver>(PcgPreconditioner::CholeskyReuse, pcg);
    case SolverKind::PcgCholeskyBackground:
      return std::make_unique<BackgroundCholeskyPcgSolver>(pcg);
    case SolverKind::PcgCholeskyWarped:
      return std::make_unique<PcgSolver>(PcgPreconditioner::CholeskyWarped, pcg);
  }
  throw std::invalid_argument("makeLinearSolver: invalid SolverKind");
}

}  // namespace surgical_sim::core
