#include "surgical_sim/core/mesh/surface_reader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/mesh/line_tokenizer.h"

namespace surgical_sim::core {
namespace {

constexpr std::size_t kStlHeaderBytes = 84;    ///< 80-byte header + uint32 triangle count
constexpr std::size_t kStlTriangleBytes = 50;  ///< normal, 3 vertices (12 floats) + uint16

TriMesh toTriMesh(const std::vector<Eigen::Vector3d>& vertices,
                  const std::vector<std::array<int, 3>>& triangles, double metres_per_unit) {
  TriMesh mesh;
  mesh.vertices.resize(3, static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    mesh.vertices.col(static_cast<Eigen::Index>(i)) = vertices[i] * metres_per_unit;
  }
  mesh.triangles.resize(3, static_cast<Eigen::Index>(triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) mesh.triangles(k, static_cast<Eigen::Index>(t)) = triangles[t][k];
  }
  return mesh;
}

/// Resolves one OBJ face corner ("i", "i/t", "i//n", "i/t/n") to a 0-based vertex index.
int objVertexIndex(const LineTokenizer& in, const std::string& corner, int num_vertices) {
  const std::string index_text = corner.substr(0, corner.find('/'));
  const long long index = in.toInteger(index_text, "face vertex index");
  const long long resolved = index > 0 ? index - 1 : num_vertices + index;
  if (index == 0 || resolved < 0 || resolved >= num_vertices) {
    in.fail("face vertex index " + index_text + " is out of range (" +
            std::to_string(num_vertices) + " vertices defined so far)");
  }
  return static_cast<int>(resolved);
}

/// STL triangles with vertices welded by exact position.
struct WeldedSurface {
  std::map<std::array<double, 3>, int> index;  ///< exact position -> vertex index
  std::vector<Eigen::Vector3d> vertices;       ///< file units, in order of first appearance
  std::vector<std::array<int, 3>> triangles;
};

int weldVertex(WeldedSurface& surface, const Eigen::Vector3d& p) {
  const auto inserted = surface.index.emplace(std::array<double, 3>{p.x(), p.y(), p.z()},
                                              static_cast<int>(surface.vertices.size()));
  if (inserted.second) surface.vertices.push_back(p);
  return inserted.first->second;
}

/// Adds a triangle unless it collapses after welding.
void addWeldedTriangle(WeldedSurface& surface, const std::array<Eigen::Vector3d, 3>& corners) {
  const std::array<int, 3> t{weldVertex(surface, corners[0]), weldVertex(surface, corners[1]),
                             weldVertex(surface, corners[2])};
  if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) surface.triangles.push_back(t);
}

float littleEndianFloat(const unsigned char* bytes) {
  const std::uint32_t bits =
      static_cast<std::uint32_t>(bytes[0]) | (static_cast<std::uint32_t>(bytes[1]) << 8) |
      (static_cast<std::uint32_t>(bytes[2]) << 16) | (static_cast<std::uint32_t>(bytes[3]) << 24);
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

void readBinaryStl(const std::string& path, const std::vector<unsigned char>& bytes,
                   std::size_t count, WeldedSurface& welded) {
  for (std::size_t t = 0; t < count; ++t) {
    const unsigned char* record = bytes.data() + kStlHeaderBytes + t * kStlTriangleBytes;
    std::array<Eigen::Vector3d, 3> corners;
    for (std::size_t c = 0; c < 3; ++c) {
      for (std::size_t k = 0; k < 3; ++k) {
        // Skip the 12-byte facet normal; 3 little-endian floats per vertex.
        const float value = littleEndianFloat(record + 12 * (c + 1) + 4 * k);
        if (!std::isfinite(value)) {
          throw std::runtime_error(path + ": triangle " + std::to_string(t) +
                                   " has a non-finite coordinate");
        }
        corners[c][static_cast<Eigen::Index>(k)] = value;
      }
    }
    addWeldedTriangle(welded, corners);
  }
}

void readAsciiStl(const std::string& path, WeldedSurface& welded) {
  LineTokenizer in(path);
  std::array<Eigen::Vector3d, 3> corners;
  int num_corners = -1;  // -1 outside a facet
  while (in.next()) {
    const std::string& keyword = in.tokens()[0];
    if (keyword == "facet") {
      if (num_corners >= 0) in.fail("'facet' inside a facet (missing 'endfacet')");
      num_corners = 0;
    } else if (keyword == "vertex") {
      if (num_corners < 0) in.fail("'vertex' outside a facet");
      if (num_corners == 3) in.fail("facet has more than 3 vertices");
      in.requireTokens(4, "vertex x y z");
      const auto& t = in.tokens();
      corners[num_corners++] = {in.toDouble(t[1], "vertex x"), in.toDouble(t[2], "vertex y"),
                                in.toDouble(t[3], "vertex z")};
    } else if (keyword == "endfacet") {
      if (num_corners != 3) {
        in.fail("facet has " + std::to_string(std::max(num_corners, 0)) + " vertices, expected 3");
      }
      addWeldedTriangle(welded, corners);
      num_corners = -1;
    } else if (keyword != "solid" && keyword != "outer" && keyword != "endloop" &&
               keyword != "endsolid") {
      in.fail("unexpected keyword '" + keyword + "' in ASCII STL");
    }
  }
  if (num_corners >= 0) in.fail("unexpected end of file inside a facet");
  if (welded.triangles.empty()) in.fail("no triangles in the file");
}

}  // namespace

TriMesh readObj(const std::string& path, double metres_per_unit) {
  requirePositive("readObj: metres_per_unit", metres_per_unit, "m");
  LineTokenizer in(path);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  while (in.next()) {
    const auto& t = in.tokens();
    if (t[0] == "v") {
      in.requireTokens(4, "vertex x y z");
      vertices.emplace_back(in.toDouble(t[1], "vertex x"), in.toDouble(t[2], "vertex y"),
                            in.toDouble(t[3], "vertex z"));
    } else if (t[0] == "f") {
      in.requireTokens(4, "a face (3 or more corners)");
      const int n = static_cast<int>(vertices.size());
      std::vector<int> corners;
      for (std::size_t k = 1; k < t.size(); ++k) corners.push_back(objVertexIndex(in, t[k], n));
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        triangles.push_back({corners[0], corners[k], corners[k + 1]});
      }
    }
  }
  if (triangles.empty()) in.fail("no faces in the file");
  return toTriMesh(vertices, triangles, metres_per_unit);
}

TriMesh readStl(const std::string& path, double metres_per_unit) {
  requirePositive("readStl: metres_per_unit", metres_per_unit, "m");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error(path + ": cannot open file");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)),
                                         std::istreambuf_iterator<char>());
  WeldedSurface welded;
  std::size_t announced = 0;
  if (bytes.size() >= kStlHeaderBytes) {
    announced = static_cast<std::size_t>(bytes[80]) | (static_cast<std::size_t>(bytes[81]) << 8) |
                (static_cast<std::size_t>(bytes[82]) << 16) |
                (static_cast<std::size_t>(bytes[83]) << 24);
  }
  const bool binary_size_matches = bytes.size() >= kStlHeaderBytes &&
                                   bytes.size() == kStlHeaderBytes + announced * kStlTriangleBytes;
  std::size_t first = 0;
  while (first < bytes.size() && std::isspace(bytes[first])) ++first;
  const bool starts_with_solid =
      bytes.size() >= first + 5 && std::memcmp(bytes.data() + first, "solid", 5) == 0;
  if (binary_size_matches) {
    readBinaryStl(path, bytes, announced, welded);
    if (welded.triangles.empty()) throw std::runtime_error(path + ": no triangles in the file");
  } else if (starts_with_solid) {
    readAsciiStl(path, welded);
  } else if (bytes.size() >= kStlHeaderBytes) {
    throw std::runtime_error(path + ": truncated binary STL: header announces " +
                             std::to_string(announced) + " triangles (" +
                             std::to_string(kStlHeaderBytes + announced * kStlTriangleBytes) +
                             " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
  } else {
    throw std::runtime_error(path + ": not an STL file (too short for binary, no 'solid')");
  }
  return toTriMesh(welded.vertices, welded.triangles, metres_per_unit);
}

}  // namespace surgical_sim::core
