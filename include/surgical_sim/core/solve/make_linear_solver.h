#pragma once

#include <memory>
#include <string>

#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core {

/// Creates a linear solver by name: "cholmod" (CholmodSolver; pcg settings ignored),
/// "pcg_jacobi", "pcg_block_jacobi", "pcg_ichol", "pcg_cholesky_reuse" (PcgSolver with the
/// matching preconditioner and pcg settings), "pcg_cholesky_background"
/// (BackgroundCholeskyPcgSolver with the pcg settings).
/// @throws std::invalid_argument naming "solver.type" for an unknown name, or naming the
///         offending "solver.*" setting if pcg is out of range (PCG solvers only).
std::unique_ptr<LinearSolver> makeLinearSolver(const std::string& name, const PcgSettings& pcg);

}  // namespace surgical_sim::core
