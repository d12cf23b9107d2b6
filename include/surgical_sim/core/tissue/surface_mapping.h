#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Linear map from a tissue model's DOFs to the positions of its surface vertices: a sparse
/// weight matrix W (vertex slots x model nodes, weight w on each of the 3 coordinates),
/// applied to positions x_s = W x and, transposed, to forces and constraint rows: a force f_s on
/// the vertices acts on the model as f = W^T f_s, with the same virtual work
/// f_s . dx_s = (W^T f_s) . dx. Vertices are addressed by slot: their node index in the scene's
/// tet mesh (SurfaceMesh::triangles and SurfaceMesh::nodes), so numSlots() is the mesh's node
/// count; only the slots in vertices() have a row, every other slot maps to 0.
/// apply / vertexValue / addVertexForce / addTransposed allocate nothing (apply once its output
/// has its size).
class SurfaceMapping {
 public:
  /// Model nodes and weights [-] of one slot's row.
  struct Row {
    const int* nodes;
    const double* weights;
    int size;
  };

  SurfaceMapping() = default;
  /// W from its rows: row k of `weights` (vertices.size() x model nodes) is the row of slot
  /// vertices[k].
  /// @throws std::invalid_argument for a slot outside [0, slots), a repeated slot, a row count
  ///         other than vertices.size() or a non-finite weight.
  SurfaceMapping(int slots, std::vector<int> vertices,
                 const Eigen::SparseMatrix<double, Eigen::RowMajor>& weights);
  /// W from rows already laid out per slot: slot s's entries are columns[k], weights[k] for k in
  /// [start[s], start[s + 1]), start.size() - 1 slots; `vertices` lists the slots with a row, and
  /// every other slot's range is empty. Linear in the slots and entries, no sort (a cut surface's
  /// mapping, rebuilt at each cut).
  /// @throws std::invalid_argument for a slot outside [0, slots), a repeated slot, a row of a slot
  ///         not listed, ranges that do not cover the entries in order, a node outside
  ///         [0, nodes) or a non-finite weight.
  static SurfaceMapping fromRows(int nodes, std::vector<int> vertices, std::vector<int> start,
                                 std::vector<int> columns, std::vector<double> weights);
  /// The identity on `vertices` of a model whose nodes are the mesh's nodes (slot i = node i,
  /// weight 1): x_s = x on the vertices, bit for bit.
  /// @throws std::invalid_argument for a vertex outside [0, nodes).
  static SurfaceMapping selection(int nodes, const std::vector<int>& vertices);

  int numSlots() const { return static_cast<int>(start_.size()) - 1; }
  int numNodes() const { return nodes_; }
  /// Slots with a row, in the order given at construction.
  const std::vector<int>& vertices() const { return vertices_; }
  Row row(int slot) const;

  /// x_s = W x [m]: x size 3 numNodes(), x_s resized to 3 numSlots() (slots without a row: 0).
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& x_s) const;
  /// (W x) at `slot`.
  Eigen::Vector3d vertexValue(int slot, const Eigen::VectorXd& x) const;
  /// f += W^T f_v for a force f_v [N] on vertex `slot` alone (f size 3 numNodes()).
  void addVertexForce(int slot, const Eigen::Vector3d& f_v, Eigen::VectorXd& f) const;
  /// f += W^T f_s (f_s size 3 numSlots(), f size 3 numNodes()).
  void addTransposed(const Eigen::VectorXd& f_s, Eigen::VectorXd& f) const;
  /// W, numSlots() x numNodes(). Allocates (tests, diagnostics).
  Eigen::SparseMatrix<double> matrix() const;

 private:
  /// Checks the tables set by the constructor or fromRows() (see there) for `slots` slots.
  void check(int slots) const;

  int nodes_ = 0;
  std::vector<int> vertices_;
  std::vector<int> start_ = {0};  ///< per slot, its first entry; size numSlots() + 1
  std::vector<int> columns_;      ///< model node of each entry
  std::vector<double> weights_;   ///< weight of each entry [-]
};

/// The surface mapping of `model`, built on `mesh`, onto `surface` (a surface of `mesh`, e.g.
/// extractSurface(mesh)): for an EfgModel the MLS weights of the surface nodes' rest positions
/// (EfgModel::interpolation: rows sum to 1, linear motions of the particles are reproduced
/// exactly); any other model has the mesh's nodes as its DOFs and gets the selection of the
/// surface nodes. Allocates.
/// @throws std::invalid_argument when a model other than EFG does not have the mesh's node count.
SurfaceMapping makeSurfaceMapping(const TissueModel& model, const TetMesh& mesh,
                                  const SurfaceMesh& surface);

}  // namespace surgical_sim::core
