#include "surgical_sim/core/mesh/gmsh_reader.h"

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "surgical_sim/core/mesh/length_unit.h"
#include "surgical_sim/core/mesh/mesh_check.h"

namespace surgical_sim::core {
namespace {

std::string dataPath(const std::string& name) {
  return std::string(SURGICAL_SIM_SOURCE_DIR) + "/test/data/" + name;
}

/// The two-tet mesh of the test files: unit corner tet plus a tet on its slanted face, scaled
/// by 10 mm, node tag 99 unused.
Eigen::Matrix3Xd expectedTwoTetNodesMetres() {
  Eigen::Matrix3Xd nodes(3, 5);
  nodes << 0, 1, 0, 0, 1,  //
      0, 0, 1, 0, 1,       //
      0, 0, 0, 1, 1;
  return 0.01 * nodes;
}

TEST(GmshReader, ReadsVersion22KeepingTetsAndDroppingUnusedNodes) {
  const TetMesh mesh = readGmsh(dataPath("two_tets_v22.msh"), lengthUnitToMetres("mm"));
  ASSERT_EQ(mesh.type, ElementType::Tet4);
  ASSERT_EQ(mesh.numNodes(), 5);
  ASSERT_EQ(mesh.numElements(), 2);
  EXPECT_TRUE(mesh.nodes.isApprox(expectedTwoTetNodesMetres(), 1e-15));
  Eigen::Matrix<int, 4, 2> elements;
  elements << 0, 1, 1, 2, 2, 3, 3, 4;
  EXPECT_EQ(mesh.elements, elements);
  // 1/6 + 1/3 of (1 cm)^3.
  EXPECT_NEAR(meshVolume(mesh), 0.5e-6, 1e-18);
  EXPECT_NO_THROW(requireValidMesh(mesh));
}

TEST(GmshReader, Versions22And41GiveIdenticalMeshes) {
  const TetMesh v22 = readGmsh(dataPath("two_tets_v22.msh"), 0.001);
  const TetMesh v41 = readGmsh(dataPath("two_tets_v41.msh"), 0.001);
  EXPECT_EQ(v22.type, v41.type);
  EXPECT_EQ(v22.nodes, v41.nodes);
  EXPECT_EQ(v22.elements, v41.elements);
}

TEST(GmshReader, MillimetreFileScaledEqualsMetreFile) {
  const TetMesh mm = readGmsh(dataPath("two_tets_v22.msh"), lengthUnitToMetres("mm"));
  const TetMesh raw = readGmsh(dataPath("two_tets_v22.msh"), 1.0);
  const TetMesh m = readGmsh(dataPath("two_tets_metres_v22.msh"), lengthUnitToMetres("m"));
  EXPECT_TRUE(mm.nodes.isApprox(m.nodes, 1e-15));
  EXPECT_TRUE(mm.nodes.isApprox(raw.nodes * 0.001, 1e-15));
  EXPECT_EQ(mm.elements, m.elements);
  EXPECT_NEAR(meshVolume(raw) * 1e-9, meshVolume(mm), 1e-20);
}

TEST(GmshReader, ReadsTet10InGmshNodeOrder) {
  const TetMesh mesh = readGmsh(dataPath("tet10_v22.msh"), 1.0);
  ASSERT_EQ(mesh.type, ElementType::Tet10);
  ASSERT_EQ(mesh.numNodes(), 10);
  ASSERT_EQ(mesh.numElements(), 1);
  const int edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  for (int m = 0; m < 6; ++m) {
    const Eigen::Vector3d midpoint = 0.5 * (mesh.nodes.col(mesh.elements(edges[m][0], 0)) +
                                            mesh.nodes.col(mesh.elements(edges[m][1], 0)));
    EXPECT_TRUE(mesh.nodes.col(mesh.elements(4 + m, 0)).isApprox(midpoint)) << "mid node " << 4 + m;
  }
  EXPECT_NEAR(signedVolume(mesh, 0), 1.0 / 6.0, 1e-15);
}

struct MalformedFile {
  std::string file;
  int line;
  std::string what;
};

class GmshReaderMalformed : public ::testing::TestWithParam<MalformedFile> {};

TEST_P(GmshReaderMalformed, ThrowsWithFileLineAndReason) {
  const MalformedFile& c = GetParam();
  const std::string path = dataPath(c.file);
  try {
    readGmsh(path, 0.001);
    FAIL() << "expected std::runtime_error for " << c.file;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ":" + std::to_string(c.line) + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(c.what), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Files, GmshReaderMalformed,
    ::testing::Values(MalformedFile{"truncated.msh", 8, "unexpected end of file in $Nodes section"},
                      MalformedFile{"bad_number.msh", 7, "bad number '1.0x'"},
                      MalformedFile{"unknown_node_tag.msh", 19, "unknown node tag 77"},
                      MalformedFile{"binary.msh", 2, "binary MSH files are not supported"},
                      MalformedFile{"unsupported_version.msh", 2, "unsupported MSH version '3.0'"},
                      MalformedFile{"mixed_tet4_tet10.msh", 20,
                                    "mixes 4-node (type 4) and 10-node"},
                      MalformedFile{"no_tets.msh", 13, "no tetrahedra"},
                      MalformedFile{"pyramid.obj", 1, "not a Gmsh mesh file"}));

/// Writes `text` to a file `name` in the test temporary directory; returns its path.
std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// readGmsh(path) must throw std::runtime_error starting with "path:" and containing `what`.
void expectRejected(const std::string& path, const std::string& what) {
  try {
    readGmsh(path, 1.0);
    FAIL() << "expected std::runtime_error for " << path;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ":", 0), 0u) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

const char* const kFormat22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";

TEST(GmshReader, UnknownSectionWithoutEndNamesTheSection) {
  // "$Nodes" with one flipped bit: the reader skips the unknown section to the end of the file.
  const std::string path =
      writeTemp("flipped_nodes.msh", std::string(kFormat22) +
                                         "$Nmdes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n"
                                         "$Elements\n1\n1 4 0 1 2 1 2\n$EndElements\n");
  expectRejected(path, "section $Nmdes (line 4) has no $EndNmdes");
}

TEST(GmshReader, CountsBeyondTheFileSizeAreRejectedBeforeReading) {
  expectRejected(
      writeTemp("huge_nodes.msh", std::string(kFormat22) + "$Nodes\n5000000\n1 0 0 0\n$EndNodes\n"),
      "node count = 5000000 cannot fit in the");
  expectRejected(writeTemp("absurd_nodes.msh",
                           std::string(kFormat22) + "$Nodes\n9000000000000\n1 0 0 0\n$EndNodes\n"),
                 "node count = 9000000000000 exceeds the limit of 100000000");
  expectRejected(
      writeTemp("negative_elements.msh", std::string(kFormat22) + "$Elements\n-3\n$EndElements\n"),
      "element count = -3 must be >= 0");
  expectRejected(writeTemp("huge_blocks.msh",
                           "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4000000 1 4\n0 1 0 "
                           "4000000\n1\n2\n$EndNodes\n"),
                 "number of nodes = 4000000 cannot fit in the");
}

TEST(GmshReader, DuplicateElementTagIsRejected) {
  expectRejected(
      writeTemp("duplicate_element.msh",
                std::string(kFormat22) + "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
                                         "$EndNodes\n$Elements\n2\n7 4 0 1 2 3 4\n7 4 0 2 3 4 5\n"
                                         "$EndElements\n"),
      "element tag 7 is defined twice");
}

TEST(GmshReader, NonFiniteCoordinateIsRejected) {
  expectRejected(
      writeTemp("nan_node.msh", std::string(kFormat22) + "$Nodes\n1\n1 nan 0 0\n$EndNodes\n"),
      "bad number 'nan' for node x");
  expectRejected(
      writeTemp("inf_node.msh", std::string(kFormat22) + "$Nodes\n1\n1 0 1e999 0\n$EndNodes\n"),
      "bad number '1e999' for node y");
}

TEST(GmshReader, TruncationAtEverySectionLineIsRejected) {
  // Every prefix of a shipped file that ends just before or just after a '$' line (except the
  // whole file) lacks $EndElements, so it must be rejected naming the file.
  for (const std::string name : {"two_tets_v22.msh", "two_tets_v41.msh", "tet10_v22.msh"}) {
    std::ifstream in(dataPath(name));
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::string prefix;
    for (std::size_t l = 0; l + 1 < lines.size(); ++l) {
      const bool section_line = lines[l][0] == '$';
      if (section_line && l > 0) {
        SCOPED_TRACE(name + " before line " + std::to_string(l + 1));
        expectRejected(writeTemp("cut_" + name, prefix), "");
      }
      prefix += lines[l] + "\n";
      if (section_line) {
        SCOPED_TRACE(name + " after line " + std::to_string(l + 1));
        expectRejected(writeTemp("cut_" + name, prefix), "");
      }
    }
  }
}

TEST(GmshReader, MissingFileThrowsNamingIt) {
  const std::string path = dataPath("does_not_exist.msh");
  try {
    readGmsh(path, 1.0);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot open file");
  }
}

TEST(GmshReader, RejectsNonPositiveUnit) {
  EXPECT_THROW(readGmsh(dataPath("two_tets_v22.msh"), 0.0), std::invalid_argument);
  EXPECT_THROW(readGmsh(dataPath("two_tets_v22.msh"), -1e-3), std::invalid_argument);
}

TEST(GmshReader, ShippedLiverLobeIsValidAndOrganSized) {
  const TetMesh mesh =
      readGmsh(std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/meshes/liver_lobe.msh",
               lengthUnitToMetres("mm"));
  EXPECT_EQ(mesh.type, ElementType::Tet4);
  EXPECT_GE(mesh.numNodes(), 1000);
  EXPECT_LE(mesh.numNodes(), 3000);
  EXPECT_NO_THROW(requireValidMesh(mesh));
  // Right lobe ellipsoid (50, 50, 30) mm fused with a left lobe (45, 35, 18) mm: between the
  // larger lobe alone (3.14e-4 m^3) and the sum of both (4.33e-4 m^3).
  const double volume = meshVolume(mesh);
  EXPECT_GT(volume, 3.0e-4);
  EXPECT_LT(volume, 4.33e-4);
  const Eigen::Vector3d extent = mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff();
  EXPECT_NEAR(extent.x(), 0.143, 0.005);
  EXPECT_NEAR(extent.y(), 0.100, 0.005);
  EXPECT_NEAR(extent.z(), 0.060, 0.005);
}

}  // namespace
}  // namespace surgical_sim::core
