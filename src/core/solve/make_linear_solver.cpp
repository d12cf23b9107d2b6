#include "surgical_sim/core/solve/make_linear_solver.h"

#include <stdexcept>

#include "surgical_sim/core/solve/background_cholesky_pcg_solver.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::core {

std::unique_ptr<LinearSolver> makeLinearSolver(const std::string& name, const PcgSettings& pcg) {
  if (name == "cholmod") return std::make_unique<CholmodSolver>();
  if (name == "pcg_jacobi") return std::make_unique<PcgSolver>(PcgPreconditioner::Jacobi, pcg);
  if (name == "pcg_block_jacobi") {
    return std::make_unique<PcgSolver>(PcgPreconditioner::BlockJacobi, pcg);
  }
  if (name == "pcg_ichol") {
    return std::make_unique<PcgSolver>(PcgPreconditioner::IncompleteCholesky, pcg);
  }
  if (name == "pcg_cholesky_reuse") {
    return std::make_unique<PcgSolver>(PcgPreconditioner::CholeskyReuse, pcg);
  }
  if (name == "pcg_cholesky_background") {
    return std::make_unique<BackgroundCholeskyPcgSolver>(pcg);
  }
  throw std::invalid_argument("solver.type = \"" + name +
                              "\" is unknown: must be one of cholmod, pcg_jacobi, "
                              "pcg_block_jacobi, pcg_ichol, pcg_cholesky_reuse, "
                              "pcg_cholesky_background");
}

}  // namespace surgical_sim::core
