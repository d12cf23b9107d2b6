#include "surgical_sim/core/tissue/model_factory.h"

#include <gtest/gtest.h>

#include <string>

#include "tissue_test_util.h"

namespace surgical_sim::core {
namespace {

TEST(ModelFactory, BuildsEveryModelByName) {
  for (const std::string name : {"mass_spring", "corotational", "svk", "ems", "neo_hookean"}) {
    const auto model = makeTissueModel(name, test::cubeSixTets(), test::testMaterial());
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(model->name(), name);
    EXPECT_EQ(model->numNodes(), 8);
  }
  for (const std::string name : {"corotational", "svk", "neo_hookean"}) {
    const auto model =
        makeTissueModel(name, test::toTet10(test::cubeSixTets()), test::testMaterial());
    EXPECT_EQ(model->name(), name);
  }
}

TEST(ModelFactory, UnknownNameThrowsWithTheExpectedList) {
  try {
    makeTissueModel("foo", test::singleTet(), test::testMaterial());
    FAIL() << "unknown model accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "tissue.model = 'foo' is unknown (expected mass_spring, corotational, svk, ems, "
                 "neo_hookean)");
  }
}

TEST(ModelFactory, Tet4OnlyModelsRejectTet10) {
  const TetMesh tet10 = test::toTet10(test::singleTet());
  EXPECT_THROW(makeTissueModel("mass_spring", tet10, test::testMaterial()), std::invalid_argument);
  EXPECT_THROW(makeTissueModel("ems", tet10, test::testMaterial()), std::invalid_argument);
}

TEST(ModelFactory, InvalidMaterialThrows) {
  Material bad = test::testMaterial();
  bad.poisson_ratio = 0.5;
  for (const std::string name : {"mass_spring", "corotational", "svk", "ems", "neo_hookean"}) {
    EXPECT_THROW(makeTissueModel(name, test::singleTet(), bad), std::invalid_argument) << name;
  }
}

}  // namespace
}  // namespace surgical_sim::core
