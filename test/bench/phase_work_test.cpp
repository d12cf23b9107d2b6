#include "surgical_sim/bench/phase_work.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::bench {
namespace {

/// The shape of `model` on a one-cell box (5 tet4, symmetric split), solved with `solver`.
WorkShape boxShape(ModelKind model, SolverKind solver) {
  const TetMesh mesh = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.01),
                               Eigen::Vector3i::Ones(), ElementType::Tet4);
  const auto tissue = makeTissueModel(model, mesh, Material::create(1e4, 0.3, 1000.0));
  WorkShape s;
  s.model = model;
  s.solver = solver;
  s.elements = mesh.numElements();
  s.dofs = 3.0 * tissue->numNodes();
  s.matrix_nonzeros = static_cast<double>(tissue->stiffnessPattern().nonZeros());
  std::tie(s.factor_nonzeros, s.factor_flops) = choleskyFactorSize(tissue->stiffnessPattern());
  return s;
}

TEST(PhaseWork, CorotationalTet4FormulasOnAOneCellBox) {
  const WorkShape s = boxShape(ModelKind::Corotational, SolverKind::Cholmod);
  ASSERT_EQ(s.elements, 5.0);
  ASSERT_EQ(s.dofs, 24.0);
  // The node pairs sharing a tet: the 12 cube edges and the 6 edges of the central tet (face
  // diagonals); 3 x 3 blocks: 8 diagonal + 2 * 18 off-diagonal.
  ASSERT_EQ(s.matrix_nonzeros, 9.0 * (8.0 + 36.0));
  const double nnz = s.matrix_nonzeros;
  const StepWork w = estimateStepWork(s);
  // a = 12: 14 * 144 + 300 flops and 8 * 12 + 28 * 144 + 16 * 12 bytes per element.
  EXPECT_DOUBLE_EQ(w.forces.flops, 5.0 * 2316.0);
  EXPECT_DOUBLE_EQ(w.forces.bytes, 5.0 * 4320.0);
  EXPECT_DOUBLE_EQ(w.assembly.flops, 2.0 * nnz);
  EXPECT_DOUBLE_EQ(w.assembly.bytes, 20.0 * nnz);
  // The factor holds at least A's lower triangle, at most the dense 24 x 24 one (300 entries).
  EXPECT_GE(s.factor_nonzeros, (nnz + 24.0) / 2.0);
  EXPECT_LE(s.factor_nonzeros, 300.0);
  EXPECT_GT(s.factor_flops, s.factor_nonzeros);
  EXPECT_DOUBLE_EQ(w.factorization.flops, s.factor_flops);
  EXPECT_DOUBLE_EQ(w.factorization.bytes, 16.0 * s.factor_nonzeros);
  EXPECT_DOUBLE_EQ(w.solve_iteration.flops, 4.0 * s.factor_nonzeros + 2.0 * nnz);
  EXPECT_DOUBLE_EQ(w.solve_iteration.bytes, 24.0 * s.factor_nonzeros + 12.0 * nnz);
}

TEST(PhaseWork, IterativeSolversCountTheProductVectorsAndPreconditioner) {
  WorkShape s = boxShape(ModelKind::Corotational, SolverKind::PcgJacobi);
  const double product = 2.0 * s.matrix_nonzeros, vectors = 10.0 * 24.0;
  EXPECT_DOUBLE_EQ(estimateStepWork(s).solve_iteration.flops, product + vectors + 24.0);
  s.solver = SolverKind::PcgCholeskyReuse;
  EXPECT_DOUBLE_EQ(estimateStepWork(s).solve_iteration.flops,
                   product + vectors + 4.0 * s.factor_nonzeros);
  EXPECT_DOUBLE_EQ(estimateStepWork(s).solve_iteration.bytes,
                   12.0 * s.matrix_nonzeros + 64.0 * 24.0 + 16.0 * s.factor_nonzeros);
  s.solver = SolverKind::PcgCholeskyWarped;  // plus W^T and W: 2 x (9 flops, 72 bytes) a node
  EXPECT_DOUBLE_EQ(estimateStepWork(s).solve_iteration.flops,
                   product + vectors + 4.0 * s.factor_nonzeros + 12.0 * 24.0);
  EXPECT_DOUBLE_EQ(estimateStepWork(s).solve_iteration.bytes,
                   12.0 * s.matrix_nonzeros + 64.0 * 24.0 + 16.0 * s.factor_nonzeros + 48.0 * 24.0);
  // Their factorization happens on some steps only, or on another thread: no estimate.
  EXPECT_TRUE(std::isnan(estimateStepWork(s).factorization.flops));
}

TEST(PhaseWork, GeneralLawsCountEveryQuadraturePointAndUnknownModelsAreNaN) {
  WorkShape s = boxShape(ModelKind::NeoHookean, SolverKind::Cholmod);
  const double a = 12.0;
  EXPECT_DOUBLE_EQ(estimateStepWork(s).forces.flops, 5.0 * (18 * a * a + 162 * a + 500));
  s.element_type = ElementType::Tet10;  // four points of 30 DOFs
  EXPECT_DOUBLE_EQ(estimateStepWork(s).forces.flops,
                   5.0 * 4.0 * (18.0 * 900.0 + 162.0 * 30.0 + 500.0));
  s.model = ModelKind::MassSpring;
  EXPECT_TRUE(std::isnan(estimateStepWork(s).forces.flops));
  EXPECT_TRUE(std::isnan(estimateStepWork(s).forces.bytes));
}

TEST(PhaseWork, FactorOfATridiagonalPatternIsNearlyItsLowerTriangle) {
  const int n = 50;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 4.0);
    if (i + 1 < n) {
      entries.emplace_back(i + 1, i, -1.0);
      entries.emplace_back(i, i + 1, -1.0);
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  const auto [lnz, flops] = choleskyFactorSize(A);
  // No fill; the supernodal factor stores a few explicit zeros (relaxed amalgamation).
  EXPECT_GE(lnz, 2.0 * n - 1.0);
  EXPECT_LE(lnz, 3.0 * n);
  EXPECT_GT(flops, lnz);
  EXPECT_LT(flops, 10.0 * lnz);
}

}  // namespace
}  // namespace surgical_sim::bench
