#include "surgical_sim/core/robot/section_condensation.h"

#include <stdexcept>
#include <vector>

#include <Eigen/SparseCore>

#include "surgical_sim/core/solve/cholmod_solver.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {

Eigen::Matrix<double, 6, 6> condenseSection(const TetMesh& mesh, const Material& material,
                                            double proximal_face_x, double distal_face_x,
                                            const Eigen::Vector3d& p_PD) {
  if (!(distal_face_x > proximal_face_x))
    throw std::invalid_argument("condenseSection: distal_face_x must be > proximal_face_x");
  const auto model = makeTissueModel(ModelKind::Corotational, mesh, material);
  Eigen::SparseMatrix<double> K = model->stiffnessPattern();
  model->assembleStiffness(model->restPositions(), TangentMode::Exact, K);

  const int n = mesh.numNodes();
  const double tol = 1e-9 * std::max(1.0, std::abs(distal_face_x - proximal_face_x));
  enum Kind { Clamped, Distal, Interior };
  std::vector<Kind> kind(n);
  std::vector<int> slot(n, -1);
  int n_interior = 0, n_clamped = 0, n_distal = 0;
  for (int i = 0; i < n; ++i) {
    const double x = mesh.nodes(0, i);
    if (x <= proximal_face_x + tol) {
      kind[i] = Clamped;
      ++n_clamped;
    } else if (x >= distal_face_x - tol) {
      kind[i] = Distal;
      ++n_distal;
    } else {
      kind[i] = Interior;
      slot[i] = n_interior++;
    }
  }
  if (n_clamped == 0 || n_distal == 0)
    throw std::invalid_argument("condenseSection: a section face holds no node");
  const int q = 3 * n_interior;  // first rigid DOF
  const int N = q + 6;

  // Row map of a global DOF: list of (reduced index, coefficient), at most 6 entries.
  struct Map {
    int count = 0;
    int index[6];
    double coef[6];
  };
  const auto mapOf = [&](int dof) {
    Map m;
    const int node = dof / 3, c = dof % 3;
    if (kind[node] == Interior) {
      m.count = 1;
      m.index[0] = 3 * slot[node] + c;
      m.coef[0] = 1.0;
    } else if (kind[node] == Distal) {
      // T = [I, -[r]x], r = p - p_PD: row c.
      const Eigen::Vector3d r = mesh.nodes.col(node) - p_PD;
      Eigen::Matrix3d skew;
      skew << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
      m.count = 6;
      for (int k = 0; k < 3; ++k) {
        m.index[k] = q + k;
        m.coef[k] = (k == c) ? 1.0 : 0.0;
        m.index[3 + k] = q + 3 + k;
        m.coef[3 + k] = -skew(c, k);
      }
    }
    return m;
  };
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(K.nonZeros() + 36 * 64);
  for (int col = 0; col < K.outerSize(); ++col) {
    const Map mc = mapOf(col);
    if (mc.count == 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, col); it; ++it) {
      const Map mr = mapOf(static_cast<int>(it.row()));
      for (int a = 0; a < mr.count; ++a)
        for (int b = 0; b < mc.count; ++b) {
          const double v = mr.coef[a] * it.value() * mc.coef[b];
          if (v != 0.0) triplets.emplace_back(mr.index[a], mc.index[b], v);
        }
    }
  }
  Eigen::SparseMatrix<double> Kmix(N, N);
  Kmix.setFromTriplets(triplets.begin(), triplets.end());
  Kmix.makeCompressed();

  CholmodSolver solver;
  solver.analyzePattern(Kmix);
  if (!solver.factorize(Kmix))
    throw std::invalid_argument(
        "condenseSection: the mixed stiffness is not positive definite (section mesh does not "
        "connect its faces?)");
  Eigen::Matrix<double, 6, 6> C;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(N), sol(N);
  for (int k = 0; k < 6; ++k) {
    rhs.setZero();
    rhs[q + k] = 1.0;
    solver.solve(rhs, sol);
    C.col(k) = sol.tail<6>();
  }
  return 0.5 * (C + C.transpose());
}

}  // namespace surgical_sim::core
