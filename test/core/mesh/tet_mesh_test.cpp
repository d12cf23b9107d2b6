#include "surgical_sim/core/mesh/tet_mesh.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace surgical_sim::core {
namespace {

TEST(TetMesh, NodesPerElementMatchesElementType) {
  EXPECT_EQ(nodesPerElement(ElementType::Tet4), 4);
  EXPECT_EQ(nodesPerElement(ElementType::Tet10), 10);
}

TEST(TetMesh, ToStringNamesElementType) {
  EXPECT_EQ(std::string(toString(ElementType::Tet4)), "tet4");
  EXPECT_EQ(std::string(toString(ElementType::Tet10)), "tet10");
}

TEST(TetMesh, NodesPerElementRejectsInvalidEnumValue) {
  EXPECT_THROW(nodesPerElement(static_cast<ElementType>(7)), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
