#include "surgical_sim/core/mesh/gmsh_reader.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/mesh/line_tokenizer.h"

namespace surgical_sim::core {
namespace {

enum class MshVersion { V2, V41 };

/// Largest node or element count of one section or block: indices are int.
constexpr long long kMaxEntities = 100'000'000;
/// Fewest bytes one announced entry (node, element, block, tag) occupies in the file: a digit
/// and a line break or space.
constexpr long long kMinBytesPerEntry = 2;

/// Nodes and tetrahedra as read, before compaction. Node indices refer to file order.
struct RawMesh {
  std::vector<Eigen::Vector3d> node_positions;    ///< file units
  std::unordered_map<long long, int> node_index;  ///< Gmsh node tag -> file-order index
  std::vector<int> element_nodes;                 ///< flat, nodes_per_element per element
  std::unordered_set<long long> element_tags;     ///< tags of all elements read (any type)
  int nodes_per_element = 0;                      ///< 0 until the first tetrahedron
};

/// Number of nodes of a Gmsh tetrahedron type (4 -> 4, 11 -> 10), 0 for any other type.
int tetNodesOfGmshType(long long gmsh_type) {
  if (gmsh_type == 4) return 4;
  if (gmsh_type == 11) return 10;
  return 0;
}

long long toNonNegative(const LineTokenizer& in, const std::string& token,
                        const std::string& what) {
  const long long value = in.toInteger(token, what);
  if (value < 0) in.fail(what + " = " + token + " must be >= 0");
  return value;
}

/// Parses a count of entries announced for the lines that follow and checks, before anything is
/// read or allocated for them, that it is >= 0, at most kMaxEntities and that the rest of the
/// file can hold that many entries.
long long toCount(LineTokenizer& in, const std::string& token, const std::string& what) {
  const long long value = toNonNegative(in, token, what);
  if (value > kMaxEntities) {
    in.fail(what + " = " + token + " exceeds the limit of " + std::to_string(kMaxEntities));
  }
  const long long remaining = in.bytesRemaining();
  if (value > remaining / kMinBytesPerEntry) {
    in.fail(what + " = " + token + " cannot fit in the " + std::to_string(remaining) +
            " bytes left in the file");
  }
  return value;
}

/// Advances to the next line of `section`, failing on end of file or on a '$' line.
void nextInSection(LineTokenizer& in, const std::string& section, const std::string& expected) {
  if (!in.next()) {
    in.fail("unexpected end of file in " + section + " section (expected " + expected + ")");
  }
  if (in.tokens()[0][0] == '$') {
    in.fail(section + " section ends early: expected " + expected + ", got '" + in.tokens()[0] +
            "'");
  }
}

void expectLine(LineTokenizer& in, const std::string& keyword) {
  if (!in.next()) in.fail("unexpected end of file: missing " + keyword);
  if (in.tokens()[0] != keyword) in.fail("expected " + keyword + ", got '" + in.tokens()[0] + "'");
}

/// Skips an unknown section whose header line has just been read.
void skipSection(LineTokenizer& in, const std::string& section) {
  const int header_line = in.lineNumber();
  const std::string end = "$End" + section.substr(1);
  while (in.next()) {
    if (in.tokens()[0] == end) return;
  }
  in.fail("section " + section + " (line " + std::to_string(header_line) + ") has no " + end);
}

MshVersion readMeshFormat(LineTokenizer& in) {
  if (!in.next() || in.tokens()[0] != "$MeshFormat") {
    in.fail("not a Gmsh mesh file: expected $MeshFormat on the first line");
  }
  nextInSection(in, "$MeshFormat", "version, file type and data size");
  in.requireTokens(3, "version, file type and data size");
  const std::string& version = in.tokens()[0];
  MshVersion result = MshVersion::V2;
  if (version == "2.2" || version == "2.1" || version == "2.0" || version == "2") {
    result = MshVersion::V2;
  } else if (version == "4.1") {
    result = MshVersion::V41;
  } else {
    in.fail("unsupported MSH version '" + version + "' (expected 2.2 or 4.1)");
  }
  if (in.toInteger(in.tokens()[1], "file type") != 0) {
    in.fail("binary MSH files are not supported (file type " + in.tokens()[1] +
            "); export as ASCII");
  }
  expectLine(in, "$EndMeshFormat");
  return result;
}

void addNode(const LineTokenizer& in, RawMesh& raw, long long tag, const Eigen::Vector3d& p) {
  const int index = static_cast<int>(raw.node_positions.size());
  if (!raw.node_index.emplace(tag, index).second) {
    in.fail("node tag " + std::to_string(tag) + " is defined twice");
  }
  raw.node_positions.push_back(p);
}

/// Records the tag of the element on the current line (tokens()[0]).
void addElementTag(const LineTokenizer& in, RawMesh& raw) {
  const long long tag = in.toInteger(in.tokens()[0], "element tag");
  if (!raw.element_tags.insert(tag).second) {
    in.fail("element tag " + std::to_string(tag) + " is defined twice");
  }
}

Eigen::Vector3d readPosition(const LineTokenizer& in, std::size_t first) {
  const auto& t = in.tokens();
  return {in.toDouble(t[first], "node x"), in.toDouble(t[first + 1], "node y"),
          in.toDouble(t[first + 2], "node z")};
}

/// Appends the tetrahedron whose node tags are tokens()[first..] of the current line.
void addTet(const LineTokenizer& in, RawMesh& raw, long long gmsh_type, std::size_t first) {
  const int npe = tetNodesOfGmshType(gmsh_type);
  if (raw.nodes_per_element != 0 && raw.nodes_per_element != npe) {
    in.fail("file mixes 4-node (type 4) and 10-node (type 11) tetrahedra");
  }
  raw.nodes_per_element = npe;
  const auto& t = in.tokens();
  if (t.size() != first + static_cast<std::size_t>(npe)) {
    const long long got = static_cast<long long>(t.size()) - static_cast<long long>(first);
    in.fail("tetrahedron of Gmsh type " + std::to_string(gmsh_type) + " needs " +
            std::to_string(npe) + " node tags, got " + std::to_string(got));
  }
  for (int k = 0; k < npe; ++k) {
    const long long tag = in.toInteger(t[first + k], "element node tag");
    const auto it = raw.node_index.find(tag);
    if (it == raw.node_index.end()) {
      in.fail("element references unknown node tag " + std::to_string(tag));
    }
    raw.element_nodes.push_back(it->second);
  }
}

void readNodesV2(LineTokenizer& in, RawMesh& raw) {
  nextInSection(in, "$Nodes", "the node count");
  const long long count = toCount(in, in.tokens()[0], "node count");
  for (long long i = 0; i < count; ++i) {
    nextInSection(in, "$Nodes", "node " + std::to_string(i + 1) + " of " + std::to_string(count));
    in.requireTokens(4, "node tag and x y z");
    addNode(in, raw, in.toInteger(in.tokens()[0], "node tag"), readPosition(in, 1));
  }
  expectLine(in, "$EndNodes");
}

void readElementsV2(LineTokenizer& in, RawMesh& raw) {
  nextInSection(in, "$Elements", "the element count");
  const long long count = toCount(in, in.tokens()[0], "element count");
  for (long long i = 0; i < count; ++i) {
    nextInSection(in, "$Elements",
                  "element " + std::to_string(i + 1) + " of " + std::to_string(count));
    in.requireTokens(3, "element tag, type and number of tags");
    addElementTag(in, raw);
    const long long type = in.toInteger(in.tokens()[1], "element type");
    const long long num_tags = toNonNegative(in, in.tokens()[2], "number of element tags");
    if (tetNodesOfGmshType(type) != 0)
      addTet(in, raw, type, 3 + static_cast<std::size_t>(num_tags));
  }
  expectLine(in, "$EndElements");
}

void readNodesV41(LineTokenizer& in, RawMesh& raw) {
  nextInSection(in, "$Nodes", "numEntityBlocks numNodes minNodeTag maxNodeTag");
  in.requireTokens(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
  const long long blocks = toCount(in, in.tokens()[0], "number of node blocks");
  const long long total = toCount(in, in.tokens()[1], "number of nodes");
  long long read = 0;
  for (long long b = 0; b < blocks; ++b) {
    const std::string block_name = "node block " + std::to_string(b + 1);
    nextInSection(in, "$Nodes", block_name + " header");
    in.requireTokens(4, "entityDim entityTag parametric numNodesInBlock");
    const long long count = toCount(in, in.tokens()[3], "number of nodes in block");
    std::vector<long long> tags;
    while (static_cast<long long>(tags.size()) < count) {
      nextInSection(in, "$Nodes", "node tags of " + block_name);
      for (const std::string& token : in.tokens()) tags.push_back(in.toInteger(token, "node tag"));
    }
    if (static_cast<long long>(tags.size()) != count) {
      in.fail(block_name + " has " + std::to_string(tags.size()) + " node tags, expected " +
              std::to_string(count));
    }
    for (long long i = 0; i < count; ++i) {
      nextInSection(in, "$Nodes", "coordinates of node tag " + std::to_string(tags[i]));
      in.requireTokens(3, "node x y z");
      addNode(in, raw, tags[i], readPosition(in, 0));
    }
    read += count;
  }
  if (read != total) {
    in.fail("$Nodes header announces " + std::to_string(total) + " nodes but its blocks hold " +
            std::to_string(read));
  }
  expectLine(in, "$EndNodes");
}

void readElementsV41(LineTokenizer& in, RawMesh& raw) {
  nextInSection(in, "$Elements", "numEntityBlocks numElements minElementTag maxElementTag");
  in.requireTokens(4, "numEntityBlocks numElements minElementTag maxElementTag");
  const long long blocks = toCount(in, in.tokens()[0], "number of element blocks");
  for (long long b = 0; b < blocks; ++b) {
    nextInSection(in, "$Elements", "element block " + std::to_string(b + 1) + " header");
    in.requireTokens(4, "entityDim entityTag elementType numElementsInBlock");
    const long long type = in.toInteger(in.tokens()[2], "element type");
    const long long count = toCount(in, in.tokens()[3], "number of elements in block");
    for (long long i = 0; i < count; ++i) {
      nextInSection(in, "$Elements",
                    "element " + std::to_string(i + 1) + " of " + std::to_string(count) +
                        " in block " + std::to_string(b + 1));
      addElementTag(in, raw);
      if (tetNodesOfGmshType(type) != 0) addTet(in, raw, type, 1);
    }
  }
  expectLine(in, "$EndElements");
}

/// Keeps only the nodes used by tetrahedra, in file order, scaled to metres.
/// @throws std::runtime_error "path: ..." if a scaled coordinate overflows.
TetMesh compact(const RawMesh& raw, double metres_per_unit, const std::string& path) {
  const int npe = raw.nodes_per_element;
  std::vector<int> new_index(raw.node_positions.size(), -1);
  for (int node : raw.element_nodes) new_index[node] = 0;
  int used = 0;
  for (int& index : new_index) {
    if (index == 0) index = used++;
  }
  TetMesh mesh;
  mesh.type = npe == 4 ? ElementType::Tet4 : ElementType::Tet10;
  mesh.nodes.resize(3, used);
  for (std::size_t i = 0; i < new_index.size(); ++i) {
    if (new_index[i] >= 0) mesh.nodes.col(new_index[i]) = raw.node_positions[i] * metres_per_unit;
  }
  const int num_elements = static_cast<int>(raw.element_nodes.size()) / npe;
  mesh.elements.resize(npe, num_elements);
  for (int e = 0; e < num_elements; ++e) {
    for (int k = 0; k < npe; ++k) mesh.elements(k, e) = new_index[raw.element_nodes[e * npe + k]];
  }
  if (!mesh.nodes.allFinite()) {
    throw std::runtime_error(path + ": node coordinates overflow after scaling to metres");
  }
  return mesh;
}

}  // namespace

TetMesh readGmsh(const std::string& path, double metres_per_unit) {
  requirePositive("readGmsh: metres_per_unit", metres_per_unit, "m");
  LineTokenizer in(path);
  const MshVersion version = readMeshFormat(in);
  RawMesh raw;
  while (in.next()) {
    const std::string section = in.tokens()[0];  // a copy: reading on clears tokens()
    if (section[0] != '$') {
      in.fail("expected a section header such as $Nodes, got '" + section + "'");
    }
    if (section == "$Nodes") {
      version == MshVersion::V2 ? readNodesV2(in, raw) : readNodesV41(in, raw);
    } else if (section == "$Elements") {
      version == MshVersion::V2 ? readElementsV2(in, raw) : readElementsV41(in, raw);
    } else {
      skipSection(in, section);
    }
  }
  if (raw.nodes_per_element == 0) {
    in.fail("no tetrahedra (Gmsh element type 4 or 11) in the file");
  }
  return compact(raw, metres_per_unit, path);
}

}  // namespace surgical_sim::core
