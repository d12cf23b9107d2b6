#include "surgical_sim/core/mesh/length_unit.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace surgical_sim::core {
namespace {

TEST(LengthUnit, KnownUnitsConvertToMetres) {
  EXPECT_EQ(lengthUnitToMetres("m"), 1.0);
  EXPECT_EQ(lengthUnitToMetres("cm"), 0.01);
  EXPECT_EQ(lengthUnitToMetres("mm"), 0.001);
  EXPECT_EQ(lengthUnitToMetres("um"), 1e-6);
}

TEST(LengthUnit, UnknownUnitThrowsNamingIt) {
  for (const std::string unit : {"inch", "", "MM", "km"}) {
    try {
      lengthUnitToMetres(unit);
      FAIL() << "expected std::invalid_argument for '" << unit << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()),
                "unknown length unit '" + unit + "' (expected m, cm, mm or um)");
    }
  }
}

}  // namespace
}  // namespace surgical_sim::core
