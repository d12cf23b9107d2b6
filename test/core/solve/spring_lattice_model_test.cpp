// Finite-difference checks of the test double itself, so that the integrator tests built on it
// check physics rather than a buggy fixture.
#include <gtest/gtest.h>

#include <random>

#include "spring_lattice_model.h"

namespace surgical_sim::core::test {
namespace {

void checkDerivatives(SpringLatticeModel::Law law) {
  SpringLatticeModel model = SpringLatticeModel::lattice(2, 2, 2, 0.1, 500.0, 0.1, law);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  model.addInternalForce(x, f);
  Eigen::SparseMatrix<double> K = model.stiffnessPattern();
  model.assembleStiffness(x, TangentMode::Exact, K);
  const double h = 1e-6;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    EXPECT_NEAR(-(model.energy(xp) - model.energy(xm)) / (2 * h), f[i], 1e-6);
    Eigen::VectorXd fp = Eigen::VectorXd::Zero(x.size()), fm = fp;
    model.addInternalForce(xp, fp);
    model.addInternalForce(xm, fm);
    const Eigen::VectorXd column = -(fp - fm) / (2 * h);
    EXPECT_LT((column - Eigen::MatrixXd(K).col(i)).norm(), 1e-5);
  }
  Eigen::VectorXd v = Eigen::VectorXd::Random(x.size()), y;
  model.applyStiffness(x, TangentMode::Exact, v, y);
  EXPECT_LT((y - K * v).norm(), 1e-10 * (K * v).norm());
  // Internal forces sum to zero (momentum), rigid translations are in K's null space.
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (int a = 0; a < model.numNodes(); ++a) sum += f[3 * a + c];
    EXPECT_NEAR(sum, 0.0, 1e-12);
  }
}

TEST(SpringLatticeModel, LinearDerivativesMatchFiniteDifferences) {
  checkDerivatives(SpringLatticeModel::Law::Linear);
}

TEST(SpringLatticeModel, NonlinearDerivativesMatchFiniteDifferences) {
  checkDerivatives(SpringLatticeModel::Law::Nonlinear);
}

}  // namespace
}  // namespace surgical_sim::core::test
