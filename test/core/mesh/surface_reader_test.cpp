#include "surgical_sim/core/mesh/surface_reader.h"

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "surgical_sim/core/mesh/surface_inside.h"

namespace surgical_sim::core {
namespace {

std::string dataPath(const std::string& name) {
  return std::string(SURGICAL_SIM_SOURCE_DIR) + "/test/data/" + name;
}

/// True if every edge is used by exactly two triangles, once in each direction.
bool isClosedAndConsistent(const TriMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (int t = 0; t < mesh.triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) ++directed[{mesh.triangles(k, t), mesh.triangles((k + 1) % 3, t)}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1 || directed.count({edge.second, edge.first}) != 1) return false;
  }
  return true;
}

TEST(ObjReader, FanTriangulatesPolygonsAndResolvesAllIndexForms) {
  const TriMesh mesh = readObj(dataPath("pyramid.obj"), 0.01);
  ASSERT_EQ(mesh.vertices.cols(), 5);
  ASSERT_EQ(mesh.triangles.cols(), 6);
  EXPECT_TRUE(mesh.vertices.col(4).isApprox(Eigen::Vector3d(0.005, 0.005, 0.01)));
  // Quad "1 4 3 2" -> (0,3,2), (0,2,1); "f -4 -3 -1" after 5 vertices -> (1,2,4).
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 3, 2));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(0, 2, 1));
  EXPECT_EQ(mesh.triangles.col(3), Eigen::Vector3i(1, 2, 4));
  EXPECT_TRUE(isClosedAndConsistent(mesh));
  // Square pyramid, base 1 cm x 1 cm, height 1 cm: V = 1/3 cm^3, outward (positive).
  EXPECT_NEAR(enclosedVolume(mesh), 1e-6 / 3.0, 1e-20);
}

TEST(StlReader, AsciiAndBinaryGiveTheSameWeldedTetrahedron) {
  const TriMesh ascii = readStl(dataPath("tetrahedron_ascii.stl"), 1.0);
  const TriMesh binary = readStl(dataPath("tetrahedron_binary.stl"), 1.0);
  ASSERT_EQ(ascii.vertices.cols(), 4);  // 12 facet corners welded into 4 vertices
  ASSERT_EQ(ascii.triangles.cols(), 4);
  EXPECT_EQ(ascii.vertices, binary.vertices);
  EXPECT_EQ(ascii.triangles, binary.triangles);
  EXPECT_TRUE(isClosedAndConsistent(ascii));
  EXPECT_NEAR(enclosedVolume(ascii), 1.0 / 6.0, 1e-15);
}

TEST(StlReader, ScalesMillimetresToMetres) {
  const TriMesh mesh = readStl(dataPath("tetrahedron_binary.stl"), 0.001);
  EXPECT_NEAR(mesh.vertices.maxCoeff(), 0.001, 1e-18);
  EXPECT_NEAR(enclosedVolume(mesh), 1e-9 / 6.0, 1e-24);
}

void expectRuntimeError(const std::function<void()>& read, const std::string& prefix,
                        const std::string& what) {
  try {
    read();
    FAIL() << "expected std::runtime_error starting with " << prefix;
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
  }
}

TEST(SurfaceReaders, MalformedFilesThrowWithFileAndLine) {
  const std::string bad_obj = dataPath("bad_index.obj");
  expectRuntimeError([&] { readObj(bad_obj, 1.0); }, bad_obj + ":5: ",
                     "face vertex index 4 is out of range (3 vertices defined so far)");
  const std::string bad_facet = dataPath("bad_facet.stl");
  expectRuntimeError([&] { readStl(bad_facet, 1.0); },
                     bad_facet + ":7: ", "facet has 2 vertices, expected 3");
  const std::string truncated = dataPath("truncated_binary.stl");
  expectRuntimeError([&] { readStl(truncated, 1.0); }, truncated + ": ",
                     "truncated binary STL: header announces 4 triangles");
  const std::string no_faces = dataPath("two_tets_v22.msh");
  expectRuntimeError([&] { readObj(no_faces, 1.0); }, no_faces + ":24: ", "no faces");
  const std::string missing = dataPath("missing.stl");
  expectRuntimeError([&] { readStl(missing, 1.0); }, missing + ": ", "cannot open file");
}

TEST(SurfaceReaders, RejectNonPositiveUnit) {
  EXPECT_THROW(readObj(dataPath("pyramid.obj"), 0.0), std::invalid_argument);
  EXPECT_THROW(readStl(dataPath("tetrahedron_ascii.stl"), -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
