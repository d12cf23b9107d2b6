// connective_case: the rigid-node beams behind connective_bench (T1 / T5).
#include "surgical_sim/bench/connective_case.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace surgical_sim::bench {
namespace {

/// The T1 steel cantilever with `nodes` rigid nodes per axis: its tip deflection [m].
double t1Deflection(const Eigen::Vector3i& nodes) {
  const RigidNodeBeamSpec spec = t1CantileverSpec(nodes);
  const RigidNodeBeamResult r = runRigidNodeBeam(spec);
  EXPECT_EQ(r.status, StepStatus::Ok);
  EXPECT_EQ(r.nodes, nodes.prod());
  EXPECT_EQ(r.samples, 27 * spec.cells.prod());
  EXPECT_EQ(r.dofs, 6 * r.nodes);
  return -r.tip;
}

/// T1 at a coarse length resolution: the deflection converges towards the FE answer 0.1501 m
/// from below (coarse cross-sections are too stiff in bending) as the cross-section is refined.
TEST(ConnectiveCase, T1CantileverConvergesFromBelowWithTheCrossSection) {
  const double reference = 0.1501;
  const double coarse = t1Deflection(Eigen::Vector3i(13, 3, 3));
  const double fine = t1Deflection(Eigen::Vector3i(13, 5, 5));
  EXPECT_LT(coarse, fine);
  EXPECT_LT(fine, reference);
  EXPECT_GT(coarse, 0.9 * reference);
}

/// A small stiff cantilever (2 x 0.2 x 0.2 m, 3 x 3 rigid nodes across): trilinear and tet
/// weights both sag less than the Euler-Bernoulli deflection q L^4 / (8 E I) (a coarse
/// cross-section is too stiff in bending), trilinear within 6 %, the stiffer linear tets within
/// 20 %; the timed implicit Euler steps report their time split.
TEST(ConnectiveCase, TrilinearAndTetWeightsMatchBeamTheoryInTheLinearRange) {
  RigidNodeBeamSpec spec;
  spec.size = Eigen::Vector3d(2.0, 0.2, 0.2);
  spec.material = Material::create(1e9, 0.3, 1000.0);
  spec.cells = Eigen::Vector3i(10, 2, 2);
  const double q = 1000.0 * 9.81 * 0.2 * 0.2;                // N/m
  const double I = 0.2 * std::pow(0.2, 3) / 12.0;            // m^4
  const double beam = q * std::pow(2.0, 4) / (8 * 1e9 * I);  // m
  spec.weights = RigidNodeWeights::Trilinear;
  const RigidNodeBeamResult trilinear = runRigidNodeBeam(spec);
  spec.weights = RigidNodeWeights::Tet;
  spec.timed_steps = 2;
  const RigidNodeBeamResult tet = runRigidNodeBeam(spec);
  ASSERT_EQ(trilinear.status, StepStatus::Ok);
  ASSERT_EQ(tet.status, StepStatus::Ok);
  EXPECT_EQ(trilinear.nodes, tet.nodes);  // the same rigid nodes: (cells + 1) per axis
  EXPECT_LT(-trilinear.tip, beam);
  EXPECT_GT(-trilinear.tip, 0.94 * beam);
  EXPECT_LT(-tet.tip, -trilinear.tip);
  EXPECT_GT(-tet.tip, 0.8 * beam);
  EXPECT_TRUE(std::isnan(trilinear.ms_per_step));  // none timed
  EXPECT_GE(tet.ms_per_step, tet.forces_ms + tet.factor_ms);
}

TEST(ConnectiveCase, BadSpecNamesTheField) {
  RigidNodeBeamSpec spec;
  spec.cells.y() = 0;
  try {
    runRigidNodeBeam(spec);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cells[1] = 0"), std::string::npos) << e.what();
  }
  spec = RigidNodeBeamSpec();
  spec.time_step = 0.0;
  EXPECT_THROW(runRigidNodeBeam(spec), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::bench
