#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/cutting/element_split.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/tet_mesh.h"

namespace surgical_sim::core {

class UnionFind;

/// Result of one topology update of a TetCutter.
struct CutUpdate {
  /// Elements, nodes or masses changed. Then (and only then) the caller must rebuild the tissue
  /// model (new stiffness pattern: CHOLMOD re-analyses), the masses, the surface and the contact
  /// structures, and transfer the state with TetCutter::transfer(). A blade that crosses edges
  /// without separating any element's nodes (cut front inside the tissue) leaves it false.
  bool topology_changed = false;
  int edges_cut = 0;            ///< tissue edges newly crossed by the blade
  double detect_seconds = 0.0;  ///< continuous blade-edge detection, wall clock [s]
  double update_seconds = 0.0;  ///< topology update (elements, masses, surface), wall clock [s]
};

/// A point of the embedded cut surface: (1 - w) x[node_a] + w x[node_b], on an element edge.
struct EmbeddedCutPoint {
  int node_a = 0;  ///< node of the current mesh on the fragment's side (real node)
  int node_b = 0;  ///< node of the current mesh on the other side (virtual node of the copy)
  double w = 0.0;  ///< [-], in [0, 1]
};

/// How TetCutter applies a topology change.
enum class CutUpdateMode {
  /// Only the elements whose fragments changed, the nodes around them and their faces (the
  /// default: the cost follows the size of the change, not of the mesh).
  Incremental,
  /// Everything from scratch, O(m): the reference the incremental update is tested against.
  Rebuild,
};

/// Progressive cutting of a Tet4 mesh with the virtual node algorithm (Molino, Bao, Fedkiw 2004),
/// restricted to node-separating cuts.
///
/// The cutter keeps the original (uncut) mesh and, for each of its edges, whether the blade has
/// crossed it and where (parameter s from the lower-numbered node, the same in rest and deformed
/// configurations). Element e's corners are split into fragments, the connected components of its
/// 4 corners over its uncut edges; each fragment becomes a copy of the element that keeps its
/// real corners and gets virtual nodes for the others. Copies of neighbouring elements are glued
/// across their shared face: at all three corners when they hold the same real nodes on it (the
/// material continues, virtual nodes included), otherwise at the real nodes both hold. Nodes are
/// the classes of (copy, corner) under this gluing: a node is duplicated iff the cut disconnects
/// the material around it, so a complete cut leaves two pieces that share no node, and a partial
/// cut opens where it crossed and stays connected around its front, which ends on element faces
/// (an element the blade has entered without separating its corners is not split). The front's
/// edges carry 4 surface triangles (the two lips of the crack meet there); elsewhere the surface
/// is closed and manifold. Restriction (as in Molino et al.): an element is split by the pattern
/// of its cut edges (at most one cut surface per element); several cuts crossing inside one
/// element are merged into that pattern.
///
/// Masses: each copy weighs rho V_e times its fragment's material fraction
/// (fragmentVolumeFractions()), lumped equally on its 4 nodes, so the total mass is conserved
/// exactly. Each copy keeps the full element's stiffness (as in Molino et al.).
///
/// The simple mode of Chendeb (element removal, e.g. above a strain threshold) removes every
/// copy of an original element; its mass goes to the remaining nodes of its corners, or to
/// removedMass() when none remains.
///
/// A cut updates incrementally (CutUpdateMode::Incremental): the split elements get new copies
/// (new copies are appended, a fragment keeps its old copy's index), the node classes are
/// recomputed only around the corners of the split elements (a class keeps the node its
/// unchanged copies hold, a split-off class gets a new node appended, a node merged into another
/// is closed up by moving the last node into its index), and masses, faces, surface and edge
/// representatives only there. Other nodes and elements keep their indices, so transfer() maps
/// them to themselves and new nodes to the node they split from. The connected components and
/// the embedded cut surface are derived on demand. Element removal (and CutUpdateMode::Rebuild)
/// rebuilds everything in O(m) time (m original elements).
///
/// A cut runs four phases, each a separate function:
///  1. detection: detectBladeEdgeCrossings() marks the uncut edges the blade sweep crosses;
///  2. element splitting: splitElement() gives the fragments of each element at those edges;
///  3. node classification: the slots (copy, corner) glued across faces form the node classes,
///     around the changed corners (incremental) or everywhere (rebuild);
///  4. derived-data refresh: masses, faces, surface and edge representatives of the changed
///     nodes and elements (the same functions refresh everything in a rebuild).
class TetCutter {
 public:
  /// @param rest_mesh Tet4 mesh [m] passing requireValidMesh().
  /// @param density rho [kg/m^3], finite and > 0.
  /// @param mode how cuts update the topology (Incremental unless comparing against Rebuild).
  /// @throws std::invalid_argument for a Tet10 or invalid mesh or a bad density.
  TetCutter(const TetMesh& rest_mesh, double density,
            CutUpdateMode mode = CutUpdateMode::Incremental);

  /// Cuts with a blade sweep. Nodes move linearly from x_start to x_end over the step
  /// (deformed positions of the current mesh, tissue frame, size 3 n [m]); every uncut material
  /// edge is tested with edgeSweepCrossing() (tolerance 1e-9 of the mesh's bounding-box
  /// diagonal) after a swept-box rejection.
  /// @throws std::invalid_argument for a bad sweep or position vectors not of size 3 n.
  CutUpdate cut(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                const Eigen::VectorXd& x_end);

  /// Removes the original elements of the given current elements (all their copies).
  /// @throws std::invalid_argument for an index out of range.
  CutUpdate removeElements(const std::vector<int>& elements);

  /// Current elements whose Green strain E = (F^T F - I) / 2 has a Frobenius norm above
  /// max_strain [-] at deformed positions x (size 3 n) (Chendeb's removal criterion).
  std::vector<int> overstrainedElements(const Eigen::VectorXd& x, double max_strain) const;

  /// Current (virtual-node) mesh at rest [m]: copies of original elements, positively oriented.
  const TetMesh& mesh() const { return mesh_; }
  /// Lumped node mass [kg], size 3 n (value repeated for x, y, z).
  const Eigen::VectorXd& lumpedMass() const { return lumped_mass_; }
  /// Original node of each current node.
  const std::vector<int>& nodeOrigin() const { return node_origin_; }
  /// Original element of each current element.
  const std::vector<int>& elementOrigin() const { return element_origin_; }
  /// Real corners of current element c (bit i = local corner i; 0xF for an unsplit element).
  int realCorners(int c) const;
  /// Material fraction of each current element [-].
  const std::vector<double>& elementFraction() const { return element_fraction_; }
  /// Node-major vector (size 3 n_old, e.g. positions or velocities) of the mesh before the last
  /// topology change, mapped to the current nodes: each node takes the value of its parent.
  Eigen::VectorXd transfer(const Eigen::VectorXd& old_values) const;
  /// Outward boundary surface of the current mesh (closed for each piece).
  const SurfaceMesh& surface() const { return surface_; }
  /// For each surface triangle: true if it is not a face of the original boundary (it lies on a
  /// cut: either a face of a split element or a face exposed by element removal).
  const std::vector<bool>& cutFaces() const { return cut_faces_; }
  /// Embedded cut surface (the part of the blade's swept surface inside each split element, as
  /// seen by each copy), 3 points per triangle, oriented away from the copy's real nodes.
  /// Derived on the first call after a topology change, O(m) (not thread-safe).
  const std::vector<std::array<EmbeddedCutPoint, 3>>& cutTriangles() const;
  /// Connected component (0..numComponents()-1) of each current node. Derived on the first call
  /// after a topology change, O(m) (not thread-safe).
  const std::vector<int>& nodeComponent() const;
  int numComponents() const;
  /// Original edges crossed by the blade so far.
  int numCutEdges() const { return num_cut_edges_; }
  /// Mass [kg] of removed elements that had no remaining node to go to.
  double removedMass() const { return removed_mass_; }
  /// Full O(m) rebuilds so far: construction, element removal and CutUpdateMode::Rebuild cuts.
  int fullRebuilds() const { return full_rebuilds_; }

 private:
  struct Copy {
    int element;  ///< original element
    int mask;     ///< real corners (bit i = local corner i)
    double fraction;
  };
  /// Copies (current elements) of an original element: ids[0..count).
  struct CopyList {
    std::array<int, 4> ids{};
    int count = 0;
  };
  /// Gluing of two copies across an original interior face: whole (the material continues
  /// across it, all three corners glued) or at the corners real in both.
  struct FaceGlue {
    bool whole = false;
    std::array<bool, 3> corner{};
  };
  /// Copies and their corner nodes before a full rebuild (to find the new nodes' parents).
  struct Topology {
    std::vector<Copy> copies;
    std::vector<CopyList> element_copies;
    Eigen::MatrixXi elements;
  };
  /// Node classes of the slots (copy, corner at an original node) around that node.
  struct StarClasses {
    std::vector<std::array<int, 2>> slots;  ///< (copy, local corner)
    std::vector<int> slot_class;
    std::vector<int> class_node;    ///< node the class keeps, or -1 for a new node
    std::vector<int> class_parent;  ///< for a new node: the node it splits from
    std::vector<int> vanished;      ///< nodes no class keeps (merged into others)
  };

  // Construction: connectivity of the original mesh.
  void buildEdges();
  void buildStars();
  void buildFaceNeighbours();

  // Element splitting.
  /// Fragments of original element e under the edges cut so far (splitElement()).
  ElementSplit splitOriginal(int element) const;
  /// Cut parameter of each local edge of an original element, from its lower local corner.
  std::array<double, 6> localCutParameters(int element) const;
  /// Topology update of a cut that crossed new_cut_edges (per mode_); true if it changed.
  bool applyCutEdges(const std::vector<int>& new_cut_edges);

  // Full rebuild: every element split, every node classified, everything derived refreshed.
  void rebuild();
  /// Rebuild phase 1: copies_ and element_copies_ from the split of every remaining element.
  void splitAllElements();
  /// Rebuild phase 2a: unites the slots (4 copy + corner) glued across every interior face.
  void glueAllSlots(UnionFind& slots) const;
  /// Rebuild phase 2b: node of each slot class and node_origin_. The first class of each
  /// original node (in copy order) keeps the original index, the others are numbered after
  /// them; indices of original nodes that lost all their elements are closed up, keeping the
  /// order (an uncut mesh keeps its numbering). Returns the node of every slot.
  std::vector<int> numberSlotClasses(UnionFind& slots);
  /// Rebuild phase 2c: mesh_ elements and rest nodes, element data, origin_nodes_ and the
  /// parents (from the old copy containing each fragment) of the numbered slots.
  void assignNodes(const std::vector<int>& slot_node, const Topology& old);
  /// Old copy holding the fragment of `copy` (else one overlapping it), or -1 on construction.
  int parentCopy(const Topology& old, const Copy& copy) const;

  // Incremental update: only the split elements, the nodes around them and their faces.
  bool updateIncrementally(const std::vector<int>& new_cut_edges);
  /// Splitting: new fragments of one element; a fragment reuses the copy it comes from (the
  /// first fragment of it) or is appended to copies_ (with (new copy, copy whose nodes it
  /// starts from) in appended). False if the element's fragments did not change.
  bool resplitElement(int element, std::vector<std::array<int, 2>>& appended);
  /// Classification: node classes around every corner of the changed elements (all computed
  /// before any is applied), then the nodes that vanished are closed up. Returns the original
  /// nodes whose current nodes changed.
  std::vector<int> reclassifyStars(const std::vector<int>& changed);
  /// Refresh: rest positions, element data, masses, faces, surface and edge representatives
  /// around the given original nodes.
  void refreshAround(const std::vector<int>& origins, const std::vector<int>& changed);

  // Node classification around one original node v (its star).
  /// Classes around v under the current copies and the nodes they get.
  void starClasses(int v, StarClasses& out);
  /// Collects the slots of v's star into out.slots and unites those glued across its faces.
  UnionFind glueStarSlots(int v, StarClasses& out);
  /// Class of each slot; per class the (lowest) node of its slots in unchanged copies (or -1)
  /// and the node its first slot carries.
  void labelStarClasses(UnionFind& classes, StarClasses& out, std::vector<int>& kept_by,
                        std::vector<int>& carried) const;
  /// Classes with unchanged slots claim their node first, then the others the carried one; a
  /// class whose node is taken gets a new node split from it. Nodes of the star left unclaimed
  /// vanish (the change merged them into others).
  void claimStarNodes(const std::vector<int>& kept_by, const std::vector<int>& carried,
                      StarClasses& out) const;
  void applyStarClasses(int v, const StarClasses& star);
  /// Removes an unused node by moving the last node into its index; returns the moved node's
  /// origin (its star has to be refreshed).
  int removeNode(int node);

  // Gluing across faces.
  FaceGlue glue(int copy, int local_face, int copy2, const std::array<int, 3>& corners2) const;
  std::array<int, 3> neighbourCorners(int element, int local_face) const;
  /// True if a copy of the neighbour across the copy's local face continues the material.
  bool continuesAcross(int copy, int local_face) const;
  /// Calls visit(i, j, glue) for copy i of element and copy j of its neighbour across
  /// local_face (an interior face).
  template <class Visit>
  void forEachCopyPair(int element, int local_face, Visit&& visit) const;
  /// Calls visit(copy, corner) for every copy of every element around original node v, with
  /// corner the local corner at v.
  template <class Visit>
  void forEachStarCopy(int v, Visit&& visit) const;

  // Derived-data refresh (the same functions for the full rebuild and the incremental update).
  /// Empties masses, surface and edge representatives before refreshing everything.
  void resetDerived();
  /// Masses of the nodes of origins, faces and edge representatives of elements, then the
  /// surface.
  void refreshDerived(const std::vector<int>& origins, const std::vector<int>& elements);
  void refreshFaces(const std::vector<int>& elements);
  void refreshEdgeRepresentatives(const std::vector<int>& elements);
  void recomputeMasses(const std::vector<int>& origins);
  void publishSurface();
  /// Adds delta to the surface-triangle count of the triangle's nodes.
  void countTriangle(const std::array<int, 3>& tri, int delta);
  void setTriangle(int face_slot, bool present);
  /// Elements around original node v: vertex_elements_[vertex_offsets_[v], [v + 1]).
  const int* starBegin(int v) const { return vertex_elements_.data() + vertex_offsets_[v]; }
  const int* starEnd(int v) const { return vertex_elements_.data() + vertex_offsets_[v + 1]; }
  /// Marks i in a stamp vector; true the first time within the current stamp.
  bool firstVisit(std::vector<int>& stamps, int i) const;

  TetMesh original_;
  double density_;
  CutUpdateMode mode_;
  double tolerance_;                       ///< CCD distance tolerance [m]
  std::vector<std::array<int, 2>> edges_;  ///< original edges (lower node, higher node)
  std::vector<std::array<int, 6>> element_edges_;
  std::vector<int> edge_offsets_, edge_elements_;      ///< original edge -> elements (CSR)
  std::vector<int> vertex_offsets_, vertex_elements_;  ///< original node -> elements (CSR)
  std::vector<std::array<int, 2>> face_neighbour_;     ///< (element, local face) -> (element, face)
  /// (element, local face) -> local corners in the neighbour of the face's corners.
  std::vector<std::array<std::int8_t, 3>> neighbour_corners_;
  std::vector<double> element_volume_;
  std::vector<std::uint8_t> edge_cut_;
  std::vector<double> edge_s_;
  std::vector<std::uint8_t> removed_;
  int num_cut_edges_ = 0;
  int full_rebuilds_ = 0;
  double removed_mass_ = 0.0;

  std::vector<Copy> copies_;                    ///< one per current element
  std::vector<CopyList> element_copies_;        ///< per original element
  std::vector<std::vector<int>> origin_nodes_;  ///< current nodes of each original node
  TetMesh mesh_;
  Eigen::VectorXd lumped_mass_;
  std::vector<int> node_origin_, element_origin_, parent_node_;
  std::vector<double> element_fraction_;
  std::vector<std::array<int, 2>> edge_representative_;  ///< current nodes of an uncut edge
  /// Surface triangles, unordered: nodes, the face slot (4 copy + local face) they come from and
  /// whether they lie on a cut; face_triangle_ is the inverse (-1: glued face).
  std::vector<std::array<int, 3>> triangles_;
  std::vector<int> triangle_face_;
  std::vector<bool> triangle_cut_;
  std::vector<int> face_triangle_;
  std::vector<int> changed_triangles_;      ///< written since the last publishSurface()
  std::vector<int> node_triangles_;         ///< surface triangles at each node
  std::vector<int> surface_changed_nodes_;  ///< nodes whose count changed since then
  std::vector<char> on_surface_;            ///< node is in surface_.nodes
  SurfaceMesh surface_;
  std::vector<bool> cut_faces_;
  int old_num_nodes_ = 0;
  // Scratch of updateIncrementally() / starClasses() (stamps avoid clearing per update).
  mutable int stamp_ = 0;
  mutable std::vector<int> element_stamp_, origin_stamp_, changed_stamp_;
  std::vector<int> copy_slot_;
  std::vector<std::uint8_t> outcode_;  ///< cut(): detectBladeEdgeCrossings() scratch
  // Derived on demand (cached until the next topology change).
  mutable bool derived_valid_ = false;
  mutable std::vector<int> node_component_;
  mutable int num_components_ = 0;
  mutable std::vector<std::array<EmbeddedCutPoint, 3>> cut_triangles_;
  void derive() const;
  void deriveComponents() const;
  /// Appends the embedded cut triangles of a split copy to cut_triangles_.
  void deriveCutTriangles(int copy) const;
};

}  // namespace surgical_sim::core
