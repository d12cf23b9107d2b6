#include "surgical_sim/core/mesh/tet_mesh.h"

#include <stdexcept>
#include <string>

namespace surgical_sim::core {

int nodesPerElement(ElementType type) {
  switch (type) {
    case ElementType::Tet4:
      return 4;
    case ElementType::Tet10:
      return 10;
  }
  throw std::invalid_argument("nodesPerElement: unknown ElementType value " +
                              std::to_string(static_cast<int>(type)));
}

const char* toString(ElementType type) {
  switch (type) {
    case ElementType::Tet4:
      return "tet4";
    case ElementType::Tet10:
      return "tet10";
  }
  return "unknown";
}

}  // namespace surgical_sim::core
