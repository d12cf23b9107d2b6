#include <gtest/gtest.h>

#include <random>

#include "surgical_sim/core/robot/equivalent_spring.h"
#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {
namespace {

Eigen::Matrix<double, 6, 6> someCompliance() {
  Eigen::Matrix<double, 6, 6> A;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 36; ++i) A.data()[i] = u(rng);
  Eigen::Matrix<double, 6, 6> C = A * A.transpose() + 2.0 * Eigen::Matrix<double, 6, 6>::Identity();
  return 1e-3 * C;
}

void perturb(RigidNodePose& p, int c, double h) {
  if (c < 3)
    p.p_BN[c] += h;
  else
    p.q_BN = expRotation(h * Eigen::Vector3d::Unit(c - 3)) * p.q_BN;
}

struct Pair {
  RigidNodePose a, b;
};

Pair deformed(double scale) {
  Pair p;
  p.a.p_BN = Eigen::Vector3d(0.1, -0.2, 0.05);
  p.a.q_BN = expRotation(Eigen::Vector3d(0.3, -0.5, 0.8));
  const Eigen::Vector3d rel(0.02 + 0.003 * scale, 0.004 * scale, -0.002 * scale);
  p.b.p_BN = p.a.p_BN + p.a.q_BN * rel;
  p.b.q_BN = p.a.q_BN * expRotation(scale * Eigen::Vector3d(0.4, -0.3, 0.6));
  return p;
}

TEST(EquivalentSpring, RigidMotionOfThePairGivesNoForce) {
  const EquivalentSpring s(someCompliance(), Eigen::Vector3d(0.02, 0, 0),
                           Eigen::Quaterniond::Identity());
  RigidNodePose a, b;
  b.p_BN = Eigen::Vector3d(0.02, 0, 0);
  const Eigen::Quaterniond R = expRotation(Eigen::Vector3d(1.0, -2.0, 0.5));
  const Eigen::Vector3d t(0.3, 0.1, -0.7);
  a.p_BN = R * a.p_BN + t;
  b.p_BN = R * b.p_BN + t;
  a.q_BN = R;
  b.q_BN = R;
  Eigen::Matrix<double, 12, 1> f;
  const double e = s.evaluate(a, b, &f, nullptr, SpringTangent::Exact);
  EXPECT_NEAR(e, 0.0, 1e-20);
  EXPECT_LT(f.norm(), 1e-12);
}

TEST(EquivalentSpring, ForceIsMinusEnergyGradientAndStiffnessIsForceDerivative) {
  const EquivalentSpring s(someCompliance(), Eigen::Vector3d(0.02, 0, 0),
                           Eigen::Quaterniond::Identity());
  for (double scale : {0.0, 0.3, 1.0}) {
    const Pair p = deformed(scale);
    Eigen::Matrix<double, 12, 1> f;
    Eigen::Matrix<double, 12, 12> K;
    s.evaluate(p.a, p.b, &f, &K, SpringTangent::Exact);
    const double h = 1e-6;
    Eigen::Matrix<double, 12, 1> f_fd;
    Eigen::Matrix<double, 12, 12> K_fd;
    for (int d = 0; d < 12; ++d) {
      Pair plus = p, minus = p;
      perturb(d < 6 ? plus.a : plus.b, d % 6, h);
      perturb(d < 6 ? minus.a : minus.b, d % 6, -h);
      Eigen::Matrix<double, 12, 1> fp, fm;
      const double ep = s.evaluate(plus.a, plus.b, &fp, nullptr, SpringTangent::Exact);
      const double em = s.evaluate(minus.a, minus.b, &fm, nullptr, SpringTangent::Exact);
      f_fd[d] = -(ep - em) / (2 * h);
      K_fd.col(d) = -(fp - fm) / (2 * h);
    }
    EXPECT_LT((f - f_fd).norm(), 1e-6 * (f.norm() + 1e-3)) << "scale " << scale;
    EXPECT_LT((K - K_fd).norm(), 1e-6 * K.norm()) << "scale " << scale;
  }
}

TEST(EquivalentSpring, RestStiffnessIsCondensedStiffness) {
  const Eigen::Matrix<double, 6, 6> C = someCompliance();
  const EquivalentSpring s(C, Eigen::Vector3d(0.02, 0, 0), Eigen::Quaterniond::Identity());
  RigidNodePose a, b;
  b.p_BN = Eigen::Vector3d(0.02, 0, 0);
  Eigen::Matrix<double, 12, 12> K;
  s.evaluate(a, b, nullptr, &K, SpringTangent::Exact);
  EXPECT_LT((K.block<6, 6>(6, 6) - C.inverse()).norm(), 1e-9 * K.norm());
}

TEST(EquivalentSpring, RejectsNonPositiveCompliance) {
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Identity();
  C(2, 2) = -1.0;
  EXPECT_THROW(EquivalentSpring(C, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()),
               std::invalid_argument);
  C = Eigen::Matrix<double, 6, 6>::Identity();
  C(0, 1) = 0.5;
  EXPECT_THROW(EquivalentSpring(C, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()),
               std::invalid_argument);
}

TEST(So3, LogInvertsExpAndInverseJacobianMatchesFiniteDifferences) {
  const Eigen::Vector3d phi(0.7, -1.1, 0.4), w(0.2, 0.5, -0.3);
  const Eigen::Matrix3d R = expRotation(phi).toRotationMatrix();
  EXPECT_LT((logRotation(R) - phi).norm(), 1e-12);
  const double h = 1e-7;
  const Eigen::Vector3d fd = (logRotation(R * expRotation(h * w).toRotationMatrix()) -
                              logRotation(R * expRotation(-h * w).toRotationMatrix())) /
                             (2 * h);
  EXPECT_LT((rightJacobianInverse(phi) * w - fd).norm(), 1e-7);
}

}  // namespace
}  // namespace surgical_sim::core
