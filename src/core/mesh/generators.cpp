#include "surgical_sim/core/mesh/generators.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

/// Local corner pairs of the Tet10 mid-edge nodes 4..9 (Gmsh order).
constexpr std::array<std::array<int, 2>, 6> kTet10Edges{
    {{{0, 1}}, {{1, 2}}, {{0, 2}}, {{0, 3}}, {{2, 3}}, {{1, 3}}}};

void requireAtLeastOne(const std::string& name, int value) {
  if (value < 1) {
    throw std::invalid_argument(name + " = " + std::to_string(value) + " must be >= 1");
  }
}

void requireCells(const std::string& function, const Eigen::Vector3i& cells) {
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) requireAtLeastOne(function + ": cells." + axes[a], cells[a]);
}

void requirePositiveVector(const std::string& name, const Eigen::Vector3d& v) {
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) requirePositive(name + "." + axes[a], v[a], "m");
}

void requireElementType(const std::string& function, ElementType type) {
  if (type != ElementType::Tet4 && type != ElementType::Tet10) {
    throw std::invalid_argument(function + ": type = " + std::to_string(static_cast<int>(type)) +
                                " is not a known ElementType (expected Tet4 or Tet10)");
  }
}

double signedCornerVolume(const Eigen::Matrix3Xd& nodes, const std::array<int, 4>& tet) {
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.col(k) = nodes.col(tet[k + 1]) - nodes.col(tet[0]);
  return edges.determinant() / 6.0;
}

/// Fills mesh.elements from a list of tets, swapping two corners of negatively oriented ones.
void setOrientedElements(TetMesh& mesh, const std::vector<std::array<int, 4>>& tets) {
  mesh.elements.resize(4, static_cast<Eigen::Index>(tets.size()));
  for (std::size_t e = 0; e < tets.size(); ++e) {
    std::array<int, 4> tet = tets[e];
    if (signedCornerVolume(mesh.nodes, tet) < 0.0) std::swap(tet[2], tet[3]);
    for (int k = 0; k < 4; ++k) mesh.elements(k, static_cast<Eigen::Index>(e)) = tet[k];
  }
}

/// How boxTet4() splits each hexahedral cell.
enum class GridSplit {
  Alternating5,  ///< 5 tets: the central tet on the 4 corners whose grid indices sum to an even
                 ///< number, one corner tet at each of the other 4 corners
  KuhnUniform,   ///< 6 tets around the main diagonal +x+y+z in every cell
  KuhnAwayFromCentre,  ///< 6 tets around a diagonal mirrored about the box centre: it points
                       ///< away from the centre along each axis (conforming too, since its
                       ///< direction along an axis depends only on the cell's index along that
                       ///< axis)
};

/// The 5 tets of the cell with min corner `cell`, as grid points (`node` numbers them).
template <class NodeIndex>
void appendAlternating5(const std::array<int, 3>& cell, const NodeIndex& node,
                        std::vector<std::array<int, 4>>& tets) {
  // Cell corners c = (a, b, d), a, b, d in {0, 1}; `even` holds those with an even index sum.
  std::array<int, 4> even{};
  int num_even = 0;
  for (int c = 0; c < 8; ++c) {
    const std::array<int, 3> g{cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2)};
    if ((g[0] + g[1] + g[2]) % 2 != 0) {
      // Corner tet: the odd corner and its 3 edge neighbours (all even).
      std::array<int, 4> tet{node(g), 0, 0, 0};
      for (int a = 0; a < 3; ++a) {
        std::array<int, 3> neighbour = g;
        neighbour[a] += (c >> a) & 1 ? -1 : 1;
        tet[a + 1] = node(neighbour);
      }
      tets.push_back(tet);
    } else {
      even[num_even++] = node(g);
    }
  }
  tets.push_back(even);
}

/// The 6 Kuhn tets of the cell with min corner `cell`: one per axis order (a, b, c), walking from
/// one end of the cell's main diagonal along the a, b and c edges to the other end.
template <class NodeIndex>
void appendKuhn6(const std::array<int, 3>& cell, const Eigen::Vector3i& cells, GridSplit split,
                 const NodeIndex& node, std::vector<std::array<int, 4>>& tets) {
  constexpr std::array<std::array<int, 3>, 6> kAxisOrders{
      {{{0, 1, 2}}, {{0, 2, 1}}, {{1, 0, 2}}, {{1, 2, 0}}, {{2, 0, 1}}, {{2, 1, 0}}}};
  std::array<int, 3> start = cell;
  std::array<int, 3> step{1, 1, 1};
  for (int a = 0; a < 3; ++a) {
    if (split == GridSplit::KuhnAwayFromCentre && 2 * cell[a] + 1 < cells[a]) {
      start[a] = cell[a] + 1;
      step[a] = -1;
    }
  }
  for (const auto& order : kAxisOrders) {
    std::array<int, 3> corner = start;
    std::array<int, 4> tet{};
    tet[0] = node(corner);
    for (int s = 0; s < 3; ++s) {
      corner[order[s]] += step[order[s]];
      tet[s + 1] = node(corner);
    }
    tets.push_back(tet);
  }
}

/// Tet4 grid of a box, without argument checks.
TetMesh boxTet4(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& size,
                const Eigen::Vector3i& cells, GridSplit split) {
  const int nx = cells.x() + 1;
  const int ny = cells.y() + 1;
  const int nz = cells.z() + 1;
  const auto node = [nx, ny](const std::array<int, 3>& g) {
    return g[0] + nx * (g[1] + ny * g[2]);
  };
  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, static_cast<Eigen::Index>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d fraction(static_cast<double>(i) / cells.x(),
                                       static_cast<double>(j) / cells.y(),
                                       static_cast<double>(k) / cells.z());
        mesh.nodes.col(node({i, j, k})) = min_corner + size.cwiseProduct(fraction);
      }
    }
  }
  std::vector<std::array<int, 4>> tets;
  tets.reserve(6 * static_cast<std::size_t>(cells.prod()));
  for (int k = 0; k < cells.z(); ++k) {
    for (int j = 0; j < cells.y(); ++j) {
      for (int i = 0; i < cells.x(); ++i) {
        if (split == GridSplit::Alternating5) {
          appendAlternating5({i, j, k}, node, tets);
        } else {
          appendKuhn6({i, j, k}, cells, split, node, tets);
        }
      }
    }
  }
  setOrientedElements(mesh, tets);
  return mesh;
}

GridSplit gridSplit(const std::string& function, CellSplit split) {
  switch (split) {
    case CellSplit::Symmetric:
      return GridSplit::Alternating5;
    case CellSplit::Diagonal:
      return GridSplit::KuhnUniform;
  }
  throw std::invalid_argument(function + ": split = " + std::to_string(static_cast<int>(split)) +
                              " is not a known CellSplit (expected Symmetric or Diagonal)");
}

TetMesh withElementType(const TetMesh& tet4, ElementType type) {
  return type == ElementType::Tet10 ? promoteToTet10(tet4) : tet4;
}

/// Cross-section of makeHexagonalBeam: node positions (y, z) and triangles.
struct HexagonSection {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::array<int, 3>> triangles;
};

HexagonSection hexagonSection(double side, int rings) {
  const double h = std::sqrt(3.0) / 2.0;
  const std::array<Eigen::Vector2d, 6> corners{
      Eigen::Vector2d(1.0, 0.0),  Eigen::Vector2d(0.5, h),   Eigen::Vector2d(-0.5, h),
      Eigen::Vector2d(-1.0, 0.0), Eigen::Vector2d(-0.5, -h), Eigen::Vector2d(0.5, -h)};
  // Node (r, s, t): ring r, sector s, position t in 0..r along the sector's outer edge.
  const auto id = [](int r, int s, int t) {
    return r == 0 ? 0 : 1 + 3 * r * (r - 1) + (s * r + t) % (6 * r);
  };
  HexagonSection section;
  section.points.push_back(Eigen::Vector2d::Zero());
  for (int r = 1; r <= rings; ++r) {
    for (int s = 0; s < 6; ++s) {
      for (int t = 0; t < r; ++t) {
        section.points.push_back(side / rings * ((r - t) * corners[s] + t * corners[(s + 1) % 6]));
      }
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < 6; ++s) {
      for (int t = 0; t <= r; ++t) {
        section.triangles.push_back({id(r, s, t), id(r + 1, s, t), id(r + 1, s, t + 1)});
      }
      for (int t = 0; t < r; ++t) {
        section.triangles.push_back({id(r, s, t), id(r + 1, s, t + 1), id(r, s, t + 1)});
      }
    }
  }
  return section;
}

/// Thickness taper t of makeOrganBlob: z is scaled by 1 - t u_x^2.
constexpr double kOrganTaper = 0.25;

/// Smooth cube-to-sphere map, applied to a point q of the cube surface (max-norm 1): the point
/// of the unit sphere q_x sqrt(1 - q_y^2/2 - q_z^2/2 + q_y^2 q_z^2/3) (and cyclic).
Eigen::Vector3d cubeSurfaceToSphere(const Eigen::Vector3d& q) {
  const Eigen::Vector3d q2 = q.cwiseProduct(q);
  return {q.x() * std::sqrt(1.0 - q2.y() / 2.0 - q2.z() / 2.0 + q2.y() * q2.z() / 3.0),
          q.y() * std::sqrt(1.0 - q2.z() / 2.0 - q2.x() / 2.0 + q2.z() * q2.x() / 3.0),
          q.z() * std::sqrt(1.0 - q2.x() / 2.0 - q2.y() / 2.0 + q2.x() * q2.y() / 3.0)};
}

/// Cube [-1,1]^3 onto the unit ball, then the tapered shape of makeOrganBlob (unscaled).
Eigen::Vector3d organShape(const Eigen::Vector3d& p) {
  const double r = p.cwiseAbs().maxCoeff();
  const Eigen::Vector3d u =
      r > 0.0 ? Eigen::Vector3d(r * cubeSurfaceToSphere(p / r)) : Eigen::Vector3d::Zero();
  return {u.x(), u.y(), (1.0 - kOrganTaper * u.x() * u.x()) * u.z()};
}

}  // namespace

TetMesh makeBox(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& size,
                const Eigen::Vector3i& cells, ElementType type, CellSplit split) {
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    requireFinite(std::string("makeBox: min_corner.") + axes[a], min_corner[a], "m");
  }
  requirePositiveVector("makeBox: size", size);
  requireCells("makeBox", cells);
  requireElementType("makeBox", type);
  return withElementType(boxTet4(min_corner, size, cells, gridSplit("makeBox", split)), type);
}

TetMesh makeBeam(double length, double width, double height, const Eigen::Vector3i& cells,
                 ElementType type, CellSplit split) {
  requirePositive("makeBeam: length", length, "m");
  requirePositive("makeBeam: width", width, "m");
  requirePositive("makeBeam: height", height, "m");
  requireCells("makeBeam", cells);
  requireElementType("makeBeam", type);
  const Eigen::Vector3d min_corner(0.0, -width / 2.0, -height / 2.0);
  return withElementType(boxTet4(min_corner, Eigen::Vector3d(length, width, height), cells,
                                 gridSplit("makeBeam", split)),
                         type);
}

TetMesh makeHexagonalBeam(double side, double length, int cells_along, int rings,
                          ElementType type) {
  requirePositive("makeHexagonalBeam: side", side, "m");
  requirePositive("makeHexagonalBeam: length", length, "m");
  requireAtLeastOne("makeHexagonalBeam: cells_along", cells_along);
  requireAtLeastOne("makeHexagonalBeam: rings", rings);
  requireElementType("makeHexagonalBeam", type);
  const HexagonSection section = hexagonSection(side, rings);
  const int n2d = static_cast<int>(section.points.size());
  TetMesh mesh;
  mesh.type = ElementType::Tet4;
  mesh.nodes.resize(3, static_cast<Eigen::Index>(n2d) * (cells_along + 1));
  for (int layer = 0; layer <= cells_along; ++layer) {
    const double x = length * layer / cells_along;
    for (int i = 0; i < n2d; ++i) {
      mesh.nodes.col(layer * n2d + i) << x, section.points[i].x(), section.points[i].y();
    }
  }
  // Prism (a, b, c) x (bottom, top) with a < b < c: each quad side is cut along the diagonal
  // from its lower-numbered bottom node, which both neighbouring prisms agree on.
  std::vector<std::array<int, 4>> tets;
  tets.reserve(3 * section.triangles.size() * static_cast<std::size_t>(cells_along));
  for (int layer = 0; layer < cells_along; ++layer) {
    for (std::array<int, 3> tri : section.triangles) {
      std::sort(tri.begin(), tri.end());
      const int a0 = layer * n2d + tri[0], b0 = layer * n2d + tri[1], c0 = layer * n2d + tri[2];
      const int a1 = a0 + n2d, b1 = b0 + n2d, c1 = c0 + n2d;
      tets.push_back({a0, b0, c0, c1});
      tets.push_back({a0, b0, b1, c1});
      tets.push_back({a0, a1, b1, c1});
    }
  }
  setOrientedElements(mesh, tets);
  return withElementType(mesh, type);
}

TetMesh makeOrganBlob(const Eigen::Vector3d& semi_axes, int cells_per_axis, ElementType type) {
  requirePositiveVector("makeOrganBlob: semi_axes", semi_axes);
  requireAtLeastOne("makeOrganBlob: cells_per_axis", cells_per_axis);
  requireElementType("makeOrganBlob", type);
  // Diagonals pointing away from the centre make the planes |x| = |y| etc., where the ball map
  // below has kinks, faces between tets instead of cutting through them.
  TetMesh mesh = withElementType(
      boxTet4(Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(2.0),
              Eigen::Vector3i::Constant(cells_per_axis), GridSplit::KuhnAwayFromCentre),
      type);
  for (int i = 0; i < mesh.numNodes(); ++i) {
    mesh.nodes.col(i) = organShape(mesh.nodes.col(i)).cwiseProduct(semi_axes);
  }
  return mesh;
}

TetMesh promoteToTet10(const TetMesh& tet4) {
  if (tet4.type != ElementType::Tet4) {
    throw std::invalid_argument(std::string("promoteToTet10: mesh type is ") + toString(tet4.type) +
                                ", expected tet4");
  }
  const int n = tet4.numNodes();
  if (tet4.elements.rows() != 4) {
    throw std::invalid_argument("promoteToTet10: elements has " +
                                std::to_string(tet4.elements.rows()) + " rows, expected 4");
  }
  for (int e = 0; e < tet4.numElements(); ++e) {
    for (int k = 0; k < 4; ++k) {
      const int v = tet4.elements(k, e);
      if (v < 0 || v >= n) {
        throw std::invalid_argument("promoteToTet10: element " + std::to_string(e) +
                                    " references node " + std::to_string(v) + " but the mesh has " +
                                    std::to_string(n) + " nodes");
      }
    }
  }
  std::unordered_map<std::int64_t, int> edge_node;
  edge_node.reserve(static_cast<std::size_t>(tet4.numElements()) * 2);
  std::vector<Eigen::Vector3d> mid_points;
  TetMesh mesh;
  mesh.type = ElementType::Tet10;
  mesh.elements.resize(10, tet4.numElements());
  mesh.elements.topRows(4) = tet4.elements;
  for (int e = 0; e < tet4.numElements(); ++e) {
    for (int m = 0; m < 6; ++m) {
      const int p = tet4.elements(kTet10Edges[m][0], e);
      const int q = tet4.elements(kTet10Edges[m][1], e);
      const std::int64_t key =
          static_cast<std::int64_t>(std::min(p, q)) * n + static_cast<std::int64_t>(std::max(p, q));
      const auto inserted = edge_node.emplace(key, n + static_cast<int>(mid_points.size()));
      if (inserted.second) mid_points.push_back(0.5 * (tet4.nodes.col(p) + tet4.nodes.col(q)));
      mesh.elements(4 + m, e) = inserted.first->second;
    }
  }
  mesh.nodes.resize(3, n + static_cast<int>(mid_points.size()));
  mesh.nodes.leftCols(n) = tet4.nodes;
  for (std::size_t i = 0; i < mid_points.size(); ++i) {
    mesh.nodes.col(n + static_cast<int>(i)) = mid_points[i];
  }
  return mesh;
}

}  // namespace surgical_sim::core
