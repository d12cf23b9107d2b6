#pragma once

#include <array>
#include <memory>
#include <string>

#include "surgical_sim/core/common/named_enum.h"
#include "surgical_sim/core/solve/linear_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"

namespace surgical_sim::core {

/// The linear solvers a scene can choose.
enum class SolverKind {
  Cholmod,
  PcgJacobi,
  PcgBlockJacobi,
  PcgIchol,
  PcgCholeskyReuse,
  PcgCholeskyBackground,
  PcgCholeskyWarped
};

/// Scene / CSV names.
inline constexpr std::array<EnumName<SolverKind>, 7> kSolverNames{{
    {SolverKind::Cholmod, "cholmod"},
    {SolverKind::PcgJacobi, "pcg_jacobi"},
    {SolverKind::PcgBlockJacobi, "pcg_block_jacobi"},
    {SolverKind::PcgIchol, "pcg_ichol"},
    {SolverKind::PcgCholeskyReuse, "pcg_cholesky_reuse"},
    {SolverKind::PcgCholeskyBackground, "pcg_cholesky_background"},
    {SolverKind::PcgCholeskyWarped, "pcg_cholesky_warped"},
}};
inline const char* solverName(SolverKind kind) { return enumName(kSolverNames, kind); }

/// Creates a linear solver: Cholmod (CholmodSolver; pcg settings ignored), PcgJacobi,
/// PcgBlockJacobi, PcgIchol, PcgCholeskyReuse, PcgCholeskyWarped (PcgSolver with the matching
/// preconditioner and pcg settings), PcgCholeskyBackground (BackgroundCholeskyPcgSolver with the
/// pcg settings).
/// @throws std::invalid_argument naming the offending "solver.*" setting if pcg is out of range
///         (PCG solvers only).
std::unique_ptr<LinearSolver> makeLinearSolver(SolverKind kind, const PcgSettings& pcg);

}  // namespace surgical_sim::core
