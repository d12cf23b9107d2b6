#include "surgical_sim/core/tissue/model_factory.h"

#include <gtest/gtest.h>

#include <string>

#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

// EFG on the unit cube: integration cells of 0.5 m, one DOF cell whose 8 corners are the nodes.
EfgOptions efgOptions() {
  EfgOptions efg;
  efg.spacing = 0.5;
  return efg;
}

TEST(ModelFactory, BuildsEveryModelUnderItsName) {
  for (const auto& [kind, name] : kModelNames) {
    const auto model =
        makeTissueModel(kind, test::cubeSixTets(), test::testMaterial(), efgOptions());
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(model->name(), name);
    EXPECT_EQ(model->numNodes(), 8);
  }
  for (const auto& [kind, name] : kModelNames) {
    if (linearTetOnly(kind)) continue;
    const auto model = makeTissueModel(kind, test::toTet10(test::cubeSixTets()),
                                       test::testMaterial(), efgOptions());
    EXPECT_EQ(model->name(), name);
  }
}

TEST(ModelFactory, Tet4OnlyModelsRejectTet10) {
  const TetMesh tet10 = test::toTet10(test::singleTet());
  EXPECT_THROW(makeTissueModel(ModelKind::MassSpring, tet10, test::testMaterial()),
               std::invalid_argument);
  EXPECT_THROW(makeTissueModel(ModelKind::Ems, tet10, test::testMaterial()), std::invalid_argument);
}

TEST(ModelFactory, EfgWithoutSpacingThrowsNamingTheKey) {
  try {
    makeTissueModel(ModelKind::Efg, test::cubeSixTets(), test::testMaterial());
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("efg.spacing"), std::string::npos) << e.what();
  }
}

TEST(ModelFactory, InvalidMaterialThrows) {
  Material bad = test::testMaterial();
  bad.poisson_ratio = 0.5;
  for (const auto& [kind, name] : kModelNames) {
    EXPECT_THROW(makeTissueModel(kind, test::singleTet(), bad, efgOptions()), std::invalid_argument)
        << name;
  }
}

}  // namespace
}  // namespace surgical_sim::core
