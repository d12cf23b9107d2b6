#pragma once
// Estimated floating-point work and memory traffic of the phases of an implicit step
// (StepPhaseTimes) and of a step-compliance solve, from the sizes of the mesh, the stiffness
// pattern and the Cholesky factor. Estimates, not counts: each formula below names what it
// counts; the benches divide them by the measured phase times to give achieved GFLOP/s and GB/s.
// A phase with no formula (a model or solver without one) is NaN.

#include <Eigen/SparseCore>
#include <utility>

#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// Floating-point operations (an FMA counts 2) and bytes moved to or from memory of one
/// occurrence of a phase.
struct PhaseWork {
  double flops = 0.0;
  double bytes = 0.0;
};

/// Sizes the estimates need.
struct WorkShape {
  ModelKind model = ModelKind::Corotational;
  ElementType element_type = ElementType::Tet4;
  SolverKind solver = SolverKind::Cholmod;
  double elements = 0.0;         ///< tetrahedra
  double dofs = 0.0;             ///< n, rows of the system matrix
  double matrix_nonzeros = 0.0;  ///< stored entries of the (full, symmetric) stiffness pattern
  /// Entries of the Cholesky factor L as CHOLMOD stores it (METIS ordering; supernodal, with
  /// the explicit zeros of relaxed amalgamation).
  double factor_nonzeros = 0.0;
  double factor_flops = 0.0;  ///< flops of its numeric factorization (CHOLMOD's count)
};

/// Per-occurrence work of each phase; NaN fields where there is no formula.
struct StepWork {
  /// One force-and-tangent evaluation of every element (StepPhaseTimes::forces), with
  /// a = 3 * nodes per element DOFs per element:
  ///  - corotational tet4 (R K0 R^T blockwise): 14 a^2 + 300 flops (rotation of the rest
  ///    stiffness 12 a^2, element force 2 a^2, polar decomposition ~300); bytes 8 a (positions)
  ///    + 8 a^2 (K0) + 20 a^2 (read-modify-write of K's entries and their scatter indices)
  ///    + 16 a (force);
  ///  - other hyperelastic laws, per quadrature point (tet4: 1, tet10: 4): 18 a^2 + 162 a + 500
  ///    flops (G^T C G with the 9 x 9 tangent C, law and projection ~500); bytes 8 a + 8 a per
  ///    point (rest gradients) + 20 a^2 + 16 a;
  ///  - mass_spring, ems, efg: NaN.
  PhaseWork forces;
  /// One system assembly A = c_M M + c_K K with its Dirichlet projection
  /// (StepPhaseTimes::assembly): 2 flops and 20 bytes (K value and index, A value) per nonzero.
  PhaseWork assembly;
  /// One numeric factorization (StepPhaseTimes::factorization), cholmod only: CHOLMOD's flop
  /// count; 16 bytes per factor entry (written once, read once). NaN for the iterative solvers
  /// (their set-up refactorizes only on some steps, or on another thread).
  PhaseWork factorization;
  /// One linear iteration (StepPhaseTimes::linear_solve / StepReport::linear_iterations):
  ///  - cholmod (one direct solve): two triangular solves, 4 flops and 24 bytes per factor entry,
  ///    plus the residual's matrix-vector product, 2 flops and 12 bytes per nonzero;
  ///  - pcg_*: the product with A (2 flops, 12 bytes per nonzero), five vector updates and dot
  ///    products (10 flops, 64 bytes per DOF) and the preconditioner: jacobi 1 flop, 24 bytes per
  ///    DOF; block_jacobi 6 flops, 48 bytes per DOF; ichol as the product with A;
  ///    cholesky_reuse / cholesky_background two single-precision triangular solves, 4 flops and
  ///    16 bytes per factor entry; cholesky_warped these plus the node rotations W^T and W
  ///    (3 x 3 per node, twice), 12 flops and 48 bytes per DOF.
  PhaseWork solve_iteration;
};

/// The estimates for `shape`.
StepWork estimateStepWork(const WorkShape& shape);

/// Entries of the Cholesky factor of the pattern of A (symmetric, full storage) and the flops of
/// its numeric factorization, from the symbolic analysis of the scenes' cholmod solver
/// (CholmodSolver, METIS ordering). Returns {lnz, flops}; {NaN, NaN} if the analysis fails.
std::pair<double, double> choleskyFactorSize(const Eigen::SparseMatrix<double>& A);

}  // namespace surgical_sim::bench
