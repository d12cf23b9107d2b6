#include "surgical_sim/core/mesh/mesh_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "surgical_sim/core/common/union_find.h"
#include "surgical_sim/core/mesh/tet_faces.h"

namespace surgical_sim::core {
namespace {

constexpr double kDegenerateVolumeRatio = 1e-12;  ///< |V| / (mean edge length)^3
constexpr double kDuplicateDistanceRatio = 1e-9;  ///< distance / bounding-box diagonal
constexpr int kErrorsInException = 5;
constexpr int kFloatingPiecesListed = 5;

std::string formatValue(double value) {
  std::ostringstream s;
  s.precision(3);
  s << value;
  return s.str();
}

/// Checks node indices and repeats; returns true if the element's indices are usable.
bool checkElementIndices(const TetMesh& mesh, int e, std::vector<MeshIssue>& issues) {
  const int npe = static_cast<int>(mesh.elements.rows());
  for (int k = 0; k < npe; ++k) {
    const int v = mesh.elements(k, e);
    if (v < 0 || v >= mesh.numNodes()) {
      issues.push_back({MeshIssueKind::IndexOutOfRange, true, e,
                        "element " + std::to_string(e) + " references node " + std::to_string(v) +
                            " (local " + std::to_string(k) + ") but the mesh has " +
                            std::to_string(mesh.numNodes()) + " nodes"});
      return false;
    }
  }
  for (int k = 0; k < npe; ++k) {
    for (int l = k + 1; l < npe; ++l) {
      if (mesh.elements(k, e) == mesh.elements(l, e)) {
        issues.push_back({MeshIssueKind::RepeatedNodeInElement, true, e,
                          "element " + std::to_string(e) + " lists node " +
                              std::to_string(mesh.elements(k, e)) + " twice (local " +
                              std::to_string(k) + " and " + std::to_string(l) + ")"});
        return false;
      }
    }
  }
  return true;
}

void checkElementVolume(const TetMesh& mesh, int e, std::vector<MeshIssue>& issues) {
  double edge_sum = 0.0;
  for (int k = 0; k < 4; ++k) {
    for (int l = k + 1; l < 4; ++l) {
      edge_sum +=
          (mesh.nodes.col(mesh.elements(k, e)) - mesh.nodes.col(mesh.elements(l, e))).norm();
    }
  }
  const double mean_edge = edge_sum / 6.0;
  const double volume = signedVolume(mesh, e);
  const std::string name = "element " + std::to_string(e);
  if (!std::isfinite(volume)) {
    issues.push_back({MeshIssueKind::DegenerateElement, true, e,
                      name + " has a non-finite signed volume (" + formatValue(volume) + ")"});
  } else if (std::abs(volume) < kDegenerateVolumeRatio * mean_edge * mean_edge * mean_edge) {
    issues.push_back({MeshIssueKind::DegenerateElement, true, e,
                      name + " is degenerate (signed volume " + formatValue(volume) +
                          " m^3, mean edge length " + formatValue(mean_edge) + " m)"});
  } else if (volume < 0.0) {
    issues.push_back({MeshIssueKind::InvertedElement, true, e,
                      name + " is inverted (signed volume " + formatValue(volume) + " m^3)"});
  }
}

/// Finds pairs of distinct nodes closer than kDuplicateDistanceRatio * bounding-box diagonal with
/// a hash grid of cells 4 tolerances wide: a node is compared with the nodes of its own cell and
/// of the neighbouring cells it is within a tolerance of (at most 8 cells).
void checkDuplicateNodes(const TetMesh& mesh, std::vector<MeshIssue>& issues) {
  const int n = mesh.numNodes();
  if (n < 2 || !mesh.nodes.allFinite()) return;
  const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff();
  const Eigen::Vector3d hi = mesh.nodes.rowwise().maxCoeff();
  const double tolerance = kDuplicateDistanceRatio * (hi - lo).norm();
  const double cell = tolerance > 0.0 ? 4.0 * tolerance : 1.0;
  using Key = std::array<std::int64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = std::hash<std::int64_t>()(k[0]);
      h = h * 1000003u ^ std::hash<std::int64_t>()(k[1]);
      return h * 1000003u ^ std::hash<std::int64_t>()(k[2]);
    }
  };
  // Cell -> first node; next_in_cell chains the other nodes of the cell.
  std::unordered_map<Key, int, KeyHash> first_in_cell;
  first_in_cell.reserve(static_cast<std::size_t>(n));
  std::vector<int> next_in_cell(static_cast<std::size_t>(n), -1);
  std::vector<Eigen::Vector3d> scaled(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    scaled[i] = (mesh.nodes.col(i) - lo) / cell;
    const Key key{static_cast<std::int64_t>(std::floor(scaled[i].x())),
                  static_cast<std::int64_t>(std::floor(scaled[i].y())),
                  static_cast<std::int64_t>(std::floor(scaled[i].z()))};
    const auto inserted = first_in_cell.emplace(key, i);
    if (!inserted.second) {
      next_in_cell[i] = inserted.first->second;
      inserted.first->second = i;
    }
  }
  const double margin = tolerance / cell;
  for (int i = 0; i < n; ++i) {
    std::array<std::array<std::int64_t, 2>, 3> offsets{};  // per axis: 0 and maybe -1 or +1
    std::array<int, 3> num_offsets{};
    Key key{};
    for (int a = 0; a < 3; ++a) {
      key[a] = static_cast<std::int64_t>(std::floor(scaled[i][a]));
      const double fraction = scaled[i][a] - static_cast<double>(key[a]);
      offsets[a][num_offsets[a]++] = 0;
      if (fraction <= margin) offsets[a][num_offsets[a]++] = -1;
      if (fraction >= 1.0 - margin) offsets[a][num_offsets[a]++] = 1;
    }
    for (int ox = 0; ox < num_offsets[0]; ++ox) {
      for (int oy = 0; oy < num_offsets[1]; ++oy) {
        for (int oz = 0; oz < num_offsets[2]; ++oz) {
          const auto it = first_in_cell.find(
              Key{key[0] + offsets[0][ox], key[1] + offsets[1][oy], key[2] + offsets[2][oz]});
          if (it == first_in_cell.end()) continue;
          for (int j = it->second; j >= 0; j = next_in_cell[j]) {
            if (j >= i) continue;  // report each pair once, at its higher index
            const double distance = (mesh.nodes.col(i) - mesh.nodes.col(j)).norm();
            if (distance <= tolerance) {
              issues.push_back({MeshIssueKind::DuplicateNode, true, i,
                                "node " + std::to_string(i) + " duplicates node " +
                                    std::to_string(j) + " (distance " + formatValue(distance) +
                                    " m, tolerance " + formatValue(tolerance) + " m)"});
            }
          }
        }
      }
    }
  }
}

void checkUnreferencedNodes(const TetMesh& mesh, std::vector<MeshIssue>& issues) {
  std::vector<bool> used(static_cast<std::size_t>(mesh.numNodes()), false);
  for (int e = 0; e < mesh.numElements(); ++e) {
    for (int k = 0; k < mesh.elements.rows(); ++k) {
      const int v = mesh.elements(k, e);
      if (v >= 0 && v < mesh.numNodes()) used[v] = true;
    }
  }
  for (int i = 0; i < mesh.numNodes(); ++i) {
    if (!used[i]) {
      issues.push_back({MeshIssueKind::UnreferencedNode, false, i,
                        "node " + std::to_string(i) + " is not used by any element"});
    }
  }
}

/// Faces shared by more than two elements.
void checkNonManifoldFaces(const TetFaceGroups& groups, std::vector<MeshIssue>& issues) {
  for (int g = 0; g < groups.numGroups(); ++g) {
    const int begin = groups.group_offsets[g];
    const int end = groups.group_offsets[g + 1];
    if (end - begin <= 2) continue;
    const TetFace& first = groups.faces[begin];
    std::string elements;
    for (int f = begin; f < end; ++f) {
      elements += (f == begin ? "" : ", ") + std::to_string(groups.faces[f].element);
    }
    issues.push_back({MeshIssueKind::NonManifoldFace, true, first.element,
                      "face (" + std::to_string(first.nodes[0]) + ", " +
                          std::to_string(first.nodes[1]) + ", " + std::to_string(first.nodes[2]) +
                          ") is shared by " + std::to_string(end - begin) + " elements (" +
                          elements + ")"});
  }
}

/// Edges of the surface (faces of exactly one element) with other than 2 surface triangles.
void checkSurfaceEdges(const TetFaceGroups& groups, std::vector<MeshIssue>& issues) {
  std::vector<std::pair<int, int>> edges;
  for (int g = 0; g < groups.numGroups(); ++g) {
    if (groups.group_offsets[g + 1] - groups.group_offsets[g] != 1) continue;
    const TetFace& face = groups.faces[groups.group_offsets[g]];
    for (int k = 0; k < 3; ++k) {
      const int a = face.nodes[k];
      const int b = face.nodes[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t begin = 0, end = 0; begin < edges.size(); begin = end) {
    while (end < edges.size() && edges[end] == edges[begin]) ++end;
    const std::size_t count = end - begin;
    if (count != 2) {
      const auto& [a, b] = edges[begin];
      issues.push_back({MeshIssueKind::NonManifoldEdge, true, a,
                        "surface edge (" + std::to_string(a) + ", " + std::to_string(b) + ") has " +
                            std::to_string(count) + " surface triangles, expected 2"});
    }
  }
}

void addScaleWarning(const TetMesh& mesh, std::vector<std::string>& warnings) {
  if (mesh.numNodes() == 0) return;
  const double diagonal =
      (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).norm();
  if (diagonal > kMaxPlausibleMeshDiagonal) {
    warnings.push_back("mesh bounding-box diagonal is " + formatValue(diagonal) + " m, above " +
                       formatValue(kMaxPlausibleMeshDiagonal) +
                       " m: is the mesh unit right (e.g. mm read as m)?");
  } else if (diagonal < kMinPlausibleMeshDiagonal) {
    warnings.push_back("mesh bounding-box diagonal is " + formatValue(diagonal) + " m, below " +
                       formatValue(kMinPlausibleMeshDiagonal) +
                       " m: is the mesh unit right (e.g. m read as mm)?");
  }
}

void addFloatingPieceWarnings(const TetMesh& mesh, const std::vector<int>& fixed_dofs,
                              std::vector<std::string>& warnings) {
  const int n = mesh.numNodes();
  UnionFind pieces(n);
  for (int e = 0; e < mesh.numElements(); ++e) {
    for (int k = 1; k < mesh.elements.rows(); ++k)
      pieces.unite(mesh.elements(0, e), mesh.elements(k, e));
  }
  std::vector<bool> held(static_cast<std::size_t>(n), false);
  for (int dof : fixed_dofs) {
    if (dof >= 0 && dof / 3 < n) held[static_cast<std::size_t>(pieces.find(dof / 3))] = true;
  }
  // Per piece root: node and element counts and lowest node (pieces in order of their lowest
  // element).
  std::vector<int> nodes_in(static_cast<std::size_t>(n), 0);
  std::vector<int> lowest_node(static_cast<std::size_t>(n), -1);
  std::vector<int> elements_in(static_cast<std::size_t>(n), 0);
  std::vector<int> roots;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const int root = pieces.find(mesh.elements(0, e));
    if (elements_in[static_cast<std::size_t>(root)]++ == 0) roots.push_back(root);
  }
  for (int i = 0; i < n; ++i) {
    const auto root = static_cast<std::size_t>(pieces.find(i));
    if (nodes_in[root]++ == 0) lowest_node[root] = i;
  }
  int floating = 0;
  for (int root : roots) {
    if (held[static_cast<std::size_t>(root)]) continue;
    if (floating++ < kFloatingPiecesListed) {
      warnings.push_back("mesh piece with " + std::to_string(nodes_in[root]) + " nodes and " +
                         std::to_string(elements_in[root]) + " elements (lowest node " +
                         std::to_string(lowest_node[root]) +
                         ") has no fixed node: it floats freely (rigid-body motion)");
    }
  }
  if (floating > kFloatingPiecesListed) {
    warnings.push_back(std::to_string(floating - kFloatingPiecesListed) +
                       " more mesh pieces have no fixed node");
  }
}

}  // namespace

double signedVolume(const TetMesh& mesh, int element) {
  if (element < 0 || element >= mesh.numElements()) {
    throw std::invalid_argument("signedVolume: element = " + std::to_string(element) +
                                " is out of range [0, " + std::to_string(mesh.numElements()) + ")");
  }
  const Eigen::Vector3d x0 = mesh.nodes.col(mesh.elements(0, element));
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.col(k) = mesh.nodes.col(mesh.elements(k + 1, element)) - x0;
  return edges.determinant() / 6.0;
}

double meshVolume(const TetMesh& mesh) {
  double volume = 0.0;
  for (int e = 0; e < mesh.numElements(); ++e) volume += signedVolume(mesh, e);
  return volume;
}

std::vector<MeshIssue> checkMesh(const TetMesh& mesh) {
  std::vector<MeshIssue> issues;
  const int npe = nodesPerElement(mesh.type);
  if (mesh.elements.rows() != npe && mesh.numElements() > 0) {
    issues.push_back({MeshIssueKind::IndexOutOfRange, true, 0,
                      std::string("elements has ") + std::to_string(mesh.elements.rows()) +
                          " rows but a " + toString(mesh.type) + " element has " +
                          std::to_string(npe) + " nodes"});
    return issues;
  }
  bool all_indices_valid = true;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const std::size_t before = issues.size();
    if (checkElementIndices(mesh, e, issues)) {
      checkElementVolume(mesh, e, issues);
    } else if (issues[before].kind == MeshIssueKind::IndexOutOfRange) {
      all_indices_valid = false;
    }
  }
  checkDuplicateNodes(mesh, issues);
  checkUnreferencedNodes(mesh, issues);
  if (all_indices_valid) {
    const TetFaceGroups groups = groupTetFaces(mesh);
    checkNonManifoldFaces(groups, issues);
    checkSurfaceEdges(groups, issues);
  }
  return issues;
}

std::vector<std::string> meshWarnings(const TetMesh& mesh, const std::vector<int>& fixed_dofs) {
  std::vector<std::string> warnings;
  addScaleWarning(mesh, warnings);
  addFloatingPieceWarnings(mesh, fixed_dofs, warnings);
  return warnings;
}

void requireValidMesh(const TetMesh& mesh) {
  const std::vector<MeshIssue> issues = checkMesh(mesh);
  int errors = 0;
  std::string listed;
  for (const MeshIssue& issue : issues) {
    if (!issue.is_error) continue;
    if (errors < kErrorsInException) listed += (errors == 0 ? "" : "; ") + issue.message;
    ++errors;
  }
  if (errors == 0) return;
  if (errors > kErrorsInException) listed += "; ...";
  throw std::invalid_argument("invalid mesh (" + std::to_string(mesh.numNodes()) + " nodes, " +
                              std::to_string(mesh.numElements()) + " " + toString(mesh.type) +
                              " elements): " + std::to_string(errors) + " errors: " + listed);
}

}  // namespace surgical_sim::core
