// Static tip deflection of (cut) cantilevers against closed forms (T3).
#include "surgical_sim/bench/beam_tip_deflection.h"

#include <Eigen/Dense>
#include <cmath>

#include <gtest/gtest.h>

#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::bench {
namespace {

TEST(BeamTipDeflection, AxialBodyForceStretchMatchesTheClosedForm) {
  // T3(b): tip u = rho g L^2 / (2 E) for nu = 0 (no lateral contraction at the clamp).
  const double L = 0.1, E = 1e7, rho = 1000.0, g = 9.81;
  const TetMesh beam = makeHexagonalBeam(0.01, L, 10, 1, ElementType::Tet4);
  const auto model = makeTissueModel(ModelKind::Corotational, beam, Material::create(E, 0.0, rho));
  const double u = beamTipDeflection(*model, Eigen::Vector3d(g, 0, 0));
  EXPECT_NEAR(u, rho * g * L * L / (2 * E), 1e-3 * rho * g * L * L / (2 * E));
}

TEST(BeamTipDeflection, HalfWidthCutAtMidLengthIncreasesTheBendDeflection) {
  // T3(c): hexagonal beam, side a, length 10 a, clamped at x = 0, body force along -z; a blade
  // along y enters from the top and stops at the axis (half the width) at mid-length.
  const double a = 0.01, L = 0.1;
  const TetMesh beam = makeHexagonalBeam(a, L, 20, 2, ElementType::Tet4);
  const Material material = Material::create(1e5, 0.3, 1000.0);
  const Eigen::Vector3d load(0, 0, -9.81);
  TetCutter uncut(beam, 1000.0);
  const double w_uncut =
      beamTipDeflection(*makeCutTissueModel(ModelKind::Corotational, uncut, material), load);
  TetCutter cut(beam, 1000.0);
  Eigen::Map<const Eigen::VectorXd> x(beam.nodes.data(), 3 * beam.numNodes());
  const double x_cut = 0.5 * L + 0.25 * L / 20;  // blade along y, from z = 2a down to the axis
  BladeSweep blade;
  blade.start = (Eigen::Matrix3Xd(3, 2) << x_cut, x_cut, -2 * a, 2 * a, 2 * a, 2 * a).finished();
  blade.end =
      (Eigen::Matrix3Xd(3, 2) << x_cut, x_cut, -2 * a, 2 * a, 1e-4 * a, 1e-4 * a).finished();
  cut.cut(blade, x, x);
  EXPECT_EQ(cut.numComponents(), 1);
  const double w_cut =
      beamTipDeflection(*makeCutTissueModel(ModelKind::Corotational, cut, material), load);
  ASSERT_TRUE(std::isfinite(w_uncut) && std::isfinite(w_cut));
  EXPECT_GT(w_uncut, 0.0);
  EXPECT_GT(w_cut, 1.05 * w_uncut);
  EXPECT_NEAR(cut.lumpedMass().sum(), uncut.lumpedMass().sum(), 1e-12 * uncut.lumpedMass().sum());
}

}  // namespace
}  // namespace surgical_sim::bench
