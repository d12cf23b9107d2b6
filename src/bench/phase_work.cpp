#include "surgical_sim/bench/phase_work.h"

#include <limits>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/solve/cholmod_solver.h"

namespace surgical_sim::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr PhaseWork kUnknown{kNaN, kNaN};

PhaseWork elementWork(const WorkShape& s) {
  const double a = 3.0 * nodesPerElement(s.element_type);
  if (s.model == ModelKind::Corotational && s.element_type == ElementType::Tet4)
    return {s.elements * (14.0 * a * a + 300.0),
            s.elements * (8.0 * a + 8.0 * a * a + 20.0 * a * a + 16.0 * a)};
  if (s.model == ModelKind::Corotational || s.model == ModelKind::Svk ||
      s.model == ModelKind::NeoHookean) {
    const double points = s.element_type == ElementType::Tet4 ? 1.0 : 4.0;
    return {s.elements * points * (18.0 * a * a + 162.0 * a + 500.0),
            s.elements * (8.0 * a + 8.0 * a * points + 20.0 * a * a + 16.0 * a)};
  }
  return kUnknown;
}

/// Work of applying the preconditioner once.
PhaseWork preconditionerWork(const WorkShape& s) {
  switch (s.solver) {
    case SolverKind::PcgJacobi:
      return {s.dofs, 24.0 * s.dofs};
    case SolverKind::PcgBlockJacobi:
      return {6.0 * s.dofs, 48.0 * s.dofs};
    case SolverKind::PcgIchol:
      return {2.0 * s.matrix_nonzeros, 12.0 * s.matrix_nonzeros};
    case SolverKind::PcgCholeskyReuse:
    case SolverKind::PcgCholeskyBackground:
      return {4.0 * s.factor_nonzeros, 16.0 * s.factor_nonzeros};
    case SolverKind::PcgCholeskyWarped:  // the factor's solves between W^T and W (3x3 per node)
      return {4.0 * s.factor_nonzeros + 12.0 * s.dofs, 16.0 * s.factor_nonzeros + 48.0 * s.dofs};
    case SolverKind::Cholmod:
      break;
  }
  return kUnknown;
}

}  // namespace

StepWork estimateStepWork(const WorkShape& s) {
  StepWork w;
  w.forces = elementWork(s);
  w.assembly = {2.0 * s.matrix_nonzeros, 20.0 * s.matrix_nonzeros};
  const PhaseWork product{2.0 * s.matrix_nonzeros, 12.0 * s.matrix_nonzeros};
  if (s.solver == SolverKind::Cholmod) {
    w.factorization = {s.factor_flops, 16.0 * s.factor_nonzeros};
    w.solve_iteration = {4.0 * s.factor_nonzeros + product.flops,
                         24.0 * s.factor_nonzeros + product.bytes};
  } else {
    w.factorization = kUnknown;
    const PhaseWork p = preconditionerWork(s);
    w.solve_iteration = {product.flops + 10.0 * s.dofs + p.flops,
                         product.bytes + 64.0 * s.dofs + p.bytes};
  }
  return w;
}

std::pair<double, double> choleskyFactorSize(const Eigen::SparseMatrix<double>& A) {
  CholmodSolver solver;  // METIS ordering, as the scenes' cholmod solver
  solver.analyzePattern(A);
  if (solver.factorNonzeros() <= 0.0) return {kNaN, kNaN};
  return {solver.factorNonzeros(), solver.factorFlops()};
}

}  // namespace surgical_sim::bench
