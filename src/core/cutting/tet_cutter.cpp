#include "surgical_sim/core/cutting/tet_cutter.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "index_at.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/union_find.h"
#include "surgical_sim/core/cutting/blade_edge_detection.h"
#include "surgical_sim/core/cutting/fragment_volume.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/tet_faces.h"

namespace surgical_sim::core {

namespace {

using cutting_index::at;
using cutting_index::intSize;
using cutting_index::toSize;

Eigen::Vector3d nodeAt(const Eigen::VectorXd& x, int node) { return x.segment<3>(3 * node); }

int localCornerOf(const TetMesh& mesh, int element, int node) {
  for (int i = 0; i < 4; ++i)
    if (mesh.elements(i, element) == node) return i;
  return -1;
}

/// 0, 1, ..., n - 1.
std::vector<int> allIds(int n) {
  std::vector<int> ids(toSize(n));
  std::iota(ids.begin(), ids.end(), 0);
  return ids;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Construction: connectivity of the original mesh.

TetCutter::TetCutter(const TetMesh& rest_mesh, double density, CutUpdateMode mode)
    : original_(rest_mesh), density_(density), mode_(mode) {
  if (rest_mesh.type != ElementType::Tet4)
    throw std::invalid_argument(std::string("TetCutter: mesh.type = ") + toString(rest_mesh.type) +
                                " is not supported (cutting needs tet4)");
  if (!std::isfinite(density) || density <= 0.0)
    throw std::invalid_argument("TetCutter: density = " + std::to_string(density) +
                                " kg/m^3 must be finite and > 0");
  requireValidMesh(rest_mesh);
  const int m = rest_mesh.numElements();
  const Eigen::Vector3d extent =
      rest_mesh.nodes.rowwise().maxCoeff() - rest_mesh.nodes.rowwise().minCoeff();
  tolerance_ = 1e-9 * extent.norm();
  buildEdges();
  buildStars();
  buildFaceNeighbours();
  element_volume_.resize(toSize(m));
  for (int e = 0; e < m; ++e) at(element_volume_, e) = signedVolume(rest_mesh, e);
  edge_cut_.assign(edges_.size(), 0);
  edge_s_.assign(edges_.size(), 0.0);
  removed_.assign(toSize(m), 0);
  element_stamp_.assign(toSize(m), 0);
  changed_stamp_.assign(toSize(m), 0);
  origin_stamp_.assign(toSize(rest_mesh.numNodes()), 0);
  rebuild();
}

void TetCutter::buildEdges() {
  // Unique edges sorted by their nodes, element -> edges and edge -> elements (CSR).
  const int m = original_.numElements();
  std::vector<std::array<int, 3>> keyed;  // (lo, hi, element * 6 + local edge)
  keyed.reserve(toSize(6 * m));
  for (int e = 0; e < m; ++e)
    for (int k = 0; k < 6; ++k) {
      const int a = original_.elements(kTetLocalEdges[k][0], e);
      const int b = original_.elements(kTetLocalEdges[k][1], e);
      keyed.push_back({std::min(a, b), std::max(a, b), 6 * e + k});
    }
  std::sort(keyed.begin(), keyed.end());
  element_edges_.resize(toSize(m));
  edge_offsets_.push_back(0);
  for (int i = 0; i < intSize(keyed); ++i) {
    const std::array<int, 3>& key = at(keyed, i);
    if (i == 0 || key[0] != at(keyed, i - 1)[0] || key[1] != at(keyed, i - 1)[1]) {
      if (i > 0) edge_offsets_.push_back(i);
      edges_.push_back({key[0], key[1]});
    }
    at(element_edges_, key[2] / 6)[key[2] % 6] = intSize(edges_) - 1;
    edge_elements_.push_back(key[2] / 6);
  }
  edge_offsets_.push_back(intSize(keyed));
}

void TetCutter::buildStars() {
  // Original node -> elements (CSR).
  const int m = original_.numElements(), n = original_.numNodes();
  vertex_offsets_.assign(toSize(n + 1), 0);
  for (int e = 0; e < m; ++e)
    for (int i = 0; i < 4; ++i) ++at(vertex_offsets_, original_.elements(i, e) + 1);
  for (int v = 0; v < n; ++v) at(vertex_offsets_, v + 1) += at(vertex_offsets_, v);
  vertex_elements_.resize(toSize(4 * m));
  std::vector<int> fill(vertex_offsets_.begin(), vertex_offsets_.end() - 1);
  for (int e = 0; e < m; ++e)
    for (int i = 0; i < 4; ++i) at(vertex_elements_, at(fill, original_.elements(i, e))++) = e;
}

void TetCutter::buildFaceNeighbours() {
  // Face neighbours (-1 on the original boundary).
  const int m = original_.numElements();
  face_neighbour_.assign(toSize(4 * m), {-1, -1});
  const TetFaceGroups groups = groupTetFaces(original_);
  for (int g = 0; g < groups.numGroups(); ++g) {
    const int begin = groups.group_offsets[g], size = groups.group_offsets[g + 1] - begin;
    if (size != 2) continue;
    const TetFace &f0 = at(groups.faces, begin), &f1 = at(groups.faces, begin + 1);
    at(face_neighbour_, 4 * f0.element + f0.local_face) = {f1.element, f1.local_face};
    at(face_neighbour_, 4 * f1.element + f1.local_face) = {f0.element, f0.local_face};
  }
  // Local corners, in the neighbour, of each interior face's corners.
  neighbour_corners_.assign(toSize(4 * m), {-1, -1, -1});
  for (int e = 0; e < m; ++e)
    for (int lf = 0; lf < 4; ++lf) {
      const int e2 = at(face_neighbour_, 4 * e + lf)[0];
      if (e2 < 0) continue;
      const std::array<int, 3> corners = tetFaceCorners(lf);
      for (int k = 0; k < 3; ++k)
        at(neighbour_corners_, 4 * e + lf)[k] = static_cast<std::int8_t>(
            localCornerOf(original_, e2, original_.elements(corners[k], e)));
    }
}

bool TetCutter::firstVisit(std::vector<int>& stamps, int i) const {
  int& s = at(stamps, i);
  if (s == stamp_) return false;
  s = stamp_;
  return true;
}

int TetCutter::realCorners(int c) const { return at(copies_, c).mask; }

// ---------------------------------------------------------------------------------------------
// Element splitting.

std::array<double, 6> TetCutter::localCutParameters(int element) const {
  std::array<double, 6> s{};
  for (int k = 0; k < 6; ++k) {
    const int id = at(element_edges_, element)[k];
    const int a = original_.elements(kTetLocalEdges[k][0], element);
    s[k] = a == at(edges_, id)[0] ? at(edge_s_, id) : 1.0 - at(edge_s_, id);
  }
  return s;
}

ElementSplit TetCutter::splitOriginal(int element) const {
  Eigen::Matrix<double, 3, 4> X;
  for (int i = 0; i < 4; ++i) X.col(i) = original_.nodes.col(original_.elements(i, element));
  std::array<bool, 6> cut{};
  for (int k = 0; k < 6; ++k) cut[k] = at(edge_cut_, at(element_edges_, element)[k]) != 0;
  return splitElement(X, cut, localCutParameters(element));
}

// ---------------------------------------------------------------------------------------------
// Gluing across faces.

std::array<int, 3> TetCutter::neighbourCorners(int element, int local_face) const {
  const std::array<std::int8_t, 3>& c = at(neighbour_corners_, 4 * element + local_face);
  return {c[0], c[1], c[2]};
}

TetCutter::FaceGlue TetCutter::glue(int copy, int local_face, int copy2,
                                    const std::array<int, 3>& corners2) const {
  const std::array<int, 3> corners = tetFaceCorners(local_face);
  const int mask = at(copies_, copy).mask, mask2 = at(copies_, copy2).mask;
  FaceGlue g;
  bool same = true, any = false;
  for (int k = 0; k < 3; ++k) {
    const bool r1 = mask & (1 << corners[k]);
    const bool r2 = mask2 & (1 << corners2[k]);
    same = same && r1 == r2;
    any = any || r1;
    g.corner[k] = r1 && r2;
  }
  g.whole = same && any;
  if (g.whole) g.corner = {true, true, true};
  return g;
}

bool TetCutter::continuesAcross(int copy, int local_face) const {
  const int e = at(copies_, copy).element;
  const int e2 = at(face_neighbour_, 4 * e + local_face)[0];
  if (e2 < 0) return false;
  const std::array<int, 3> corners2 = neighbourCorners(e, local_face);
  const CopyList& list2 = at(element_copies_, e2);
  for (int j = 0; j < list2.count; ++j)
    if (glue(copy, local_face, list2.ids[j], corners2).whole) return true;
  return false;
}

template <class Visit>
void TetCutter::forEachCopyPair(int element, int local_face, Visit&& visit) const {
  const int e2 = at(face_neighbour_, 4 * element + local_face)[0];
  const std::array<int, 3> corners2 = neighbourCorners(element, local_face);
  const CopyList &list = at(element_copies_, element), &list2 = at(element_copies_, e2);
  for (int i = 0; i < list.count; ++i)
    for (int j = 0; j < list2.count; ++j)
      visit(i, j, glue(list.ids[i], local_face, list2.ids[j], corners2));
}

template <class Visit>
void TetCutter::forEachStarCopy(int v, Visit&& visit) const {
  for (const int* p = starBegin(v); p != starEnd(v); ++p) {
    const int corner = localCornerOf(original_, *p, v);
    const CopyList& list = at(element_copies_, *p);
    for (int k = 0; k < list.count; ++k) visit(list.ids[k], corner);
  }
}

// ---------------------------------------------------------------------------------------------
// Full rebuild.

void TetCutter::rebuild() {
  ++full_rebuilds_;
  const Topology old{copies_, element_copies_, mesh_.elements};
  old_num_nodes_ = mesh_.numNodes();
  splitAllElements();
  UnionFind slots(4 * intSize(copies_));
  glueAllSlots(slots);
  assignNodes(numberSlotClasses(slots), old);
  resetDerived();
  refreshDerived(allIds(original_.numNodes()), allIds(original_.numElements()));
}

void TetCutter::splitAllElements() {
  const int m = original_.numElements();
  copies_.clear();
  element_copies_.assign(toSize(m), CopyList{});
  for (int e = 0; e < m; ++e) {
    if (at(removed_, e)) continue;
    const ElementSplit split = splitOriginal(e);
    CopyList& list = at(element_copies_, e);
    for (int k = 0; k < split.count; ++k) {
      list.ids[list.count++] = intSize(copies_);
      copies_.push_back({e, split.masks[k], split.fractions[k]});
    }
  }
}

void TetCutter::glueAllSlots(UnionFind& slots) const {
  for (int e = 0; e < original_.numElements(); ++e)
    for (int lf = 0; lf < 4; ++lf) {
      const int e2 = at(face_neighbour_, 4 * e + lf)[0];
      if (e2 < e) continue;  // each interior face once (and skips the boundary, e2 = -1)
      const std::array<int, 3> corners = tetFaceCorners(lf), corners2 = neighbourCorners(e, lf);
      const CopyList &list = at(element_copies_, e), &list2 = at(element_copies_, e2);
      forEachCopyPair(e, lf, [&](int i, int j, const FaceGlue& g) {
        for (int k = 0; k < 3; ++k)
          if (g.corner[k])
            slots.unite(4 * list.ids[i] + corners[k], 4 * list2.ids[j] + corners2[k]);
      });
    }
}

std::vector<int> TetCutter::numberSlotClasses(UnionFind& slots) {
  const int num_slots = 4 * intSize(copies_), n_orig = original_.numNodes();
  std::vector<int> node_of_root(toSize(num_slots), -1), slot_node(toSize(num_slots));
  std::vector<int> origin_of(toSize(n_orig), -1);  // per node before closing up
  std::vector<char> primary_used(toSize(n_orig), 0);
  for (int slot = 0; slot < num_slots; ++slot) {
    int& node = at(node_of_root, slots.find(slot));
    if (node < 0) {
      const int origin = original_.elements(slot % 4, at(copies_, slot / 4).element);
      if (!at(primary_used, origin)) {
        at(primary_used, origin) = 1;
        node = origin;
      } else {
        node = intSize(origin_of);
        origin_of.push_back(origin);
      }
      at(origin_of, node) = origin;
    }
    at(slot_node, slot) = node;
  }
  std::vector<int> compact(origin_of.size(), -1);
  node_origin_.clear();
  for (int v = 0; v < intSize(origin_of); ++v)
    if (v >= n_orig || at(primary_used, v)) {
      at(compact, v) = intSize(node_origin_);
      node_origin_.push_back(at(origin_of, v));
    }
  for (int& node : slot_node) node = at(compact, node);
  return slot_node;
}

int TetCutter::parentCopy(const Topology& old, const Copy& copy) const {
  if (old.copies.empty()) return -1;
  int parent = -1;
  const CopyList& list = at(old.element_copies, copy.element);
  for (int k = 0; k < list.count; ++k) {
    const int o = list.ids[k], mask = at(old.copies, o).mask;
    if ((mask & copy.mask) == copy.mask) parent = o;
    if (parent < 0 && (mask & copy.mask)) parent = o;
  }
  return parent;
}

void TetCutter::assignNodes(const std::vector<int>& slot_node, const Topology& old) {
  const int num_copies = intSize(copies_), n = intSize(node_origin_);
  parent_node_.assign(toSize(n), -1);
  mesh_.type = ElementType::Tet4;
  mesh_.elements.resize(4, num_copies);
  element_origin_.resize(toSize(num_copies));
  element_fraction_.resize(toSize(num_copies));
  for (int c = 0; c < num_copies; ++c) {
    const Copy& copy = at(copies_, c);
    const int parent_copy = parentCopy(old, copy);
    for (int i = 0; i < 4; ++i) {
      const int node = at(slot_node, 4 * c + i);
      mesh_.elements(i, c) = node;
      int& parent = at(parent_node_, node);
      if (parent < 0)
        parent = parent_copy >= 0 ? old.elements(i, parent_copy) : at(node_origin_, node);
    }
    at(element_origin_, c) = copy.element;
    at(element_fraction_, c) = copy.fraction;
  }
  mesh_.nodes.resize(3, n);
  origin_nodes_.assign(toSize(original_.numNodes()), {});
  for (int v = 0; v < n; ++v) {
    mesh_.nodes.col(v) = original_.nodes.col(at(node_origin_, v));
    at(origin_nodes_, at(node_origin_, v)).push_back(v);
  }
}

// ---------------------------------------------------------------------------------------------
// Incremental update.

bool TetCutter::updateIncrementally(const std::vector<int>& new_cut_edges) {
  ++stamp_;
  old_num_nodes_ = mesh_.numNodes();
  parent_node_.resize(toSize(old_num_nodes_));
  std::iota(parent_node_.begin(), parent_node_.end(), 0);
  std::vector<int> changed;
  std::vector<std::array<int, 2>> appended;
  for (int id : new_cut_edges)
    for (int p = at(edge_offsets_, id); p < at(edge_offsets_, id + 1); ++p) {
      const int e = at(edge_elements_, p);
      if (firstVisit(element_stamp_, e) && !at(removed_, e) && resplitElement(e, appended)) {
        changed.push_back(e);
        at(changed_stamp_, e) = stamp_;
      }
    }
  if (changed.empty()) return false;
  const int num_copies = intSize(copies_);
  mesh_.elements.conservativeResize(4, num_copies);
  for (const auto& [c, from] : appended) mesh_.elements.col(c) = mesh_.elements.col(from);
  copy_slot_.resize(toSize(num_copies));
  refreshAround(reclassifyStars(changed), changed);
  return true;
}

bool TetCutter::resplitElement(int element, std::vector<std::array<int, 2>>& appended) {
  const ElementSplit split = splitOriginal(element);
  CopyList& list = at(element_copies_, element);
  bool same = split.count == list.count;
  for (int k = 0; k < split.count && same; ++k) {
    const Copy& c = at(copies_, list.ids[k]);
    same = c.mask == split.masks[k] && c.fraction == split.fractions[k];
  }
  if (same) return false;
  const CopyList old = list;
  std::array<bool, 4> reused{};
  list.count = 0;
  for (int k = 0; k < split.count; ++k) {
    int j = 0;
    while (j < old.count && (at(copies_, old.ids[j]).mask & split.masks[k]) != split.masks[k]) ++j;
    int c = old.ids[j];
    if (reused[j]) {
      c = intSize(copies_);
      copies_.push_back({});
      appended.push_back({c, old.ids[j]});
    }
    reused[j] = true;
    list.ids[list.count++] = c;
  }
  for (int k = 0; k < split.count; ++k)
    at(copies_, list.ids[k]) = {element, split.masks[k], split.fractions[k]};
  return true;
}

std::vector<int> TetCutter::reclassifyStars(const std::vector<int>& changed) {
  std::vector<int> origins;
  for (int e : changed)
    for (int i = 0; i < 4; ++i)
      if (firstVisit(origin_stamp_, original_.elements(i, e)))
        origins.push_back(original_.elements(i, e));
  std::vector<StarClasses> stars(origins.size());
  std::vector<int> vanished;
  for (std::size_t k = 0; k < origins.size(); ++k) {
    starClasses(origins[k], stars[k]);
    vanished.insert(vanished.end(), stars[k].vanished.begin(), stars[k].vanished.end());
  }
  for (std::size_t k = 0; k < origins.size(); ++k) applyStarClasses(origins[k], stars[k]);
  std::sort(vanished.rbegin(), vanished.rend());  // highest first: the last node never vanished
  for (int node : vanished) {
    const int moved_origin = removeNode(node);
    if (firstVisit(origin_stamp_, moved_origin)) origins.push_back(moved_origin);
  }
  return origins;
}

void TetCutter::refreshAround(const std::vector<int>& origins, const std::vector<int>& changed) {
  const int n = intSize(node_origin_), num_copies = intSize(copies_);
  mesh_.nodes.conservativeResize(3, n);
  for (int v = 0; v < n; ++v)  // new nodes and nodes moved into a vanished one
    if (v >= old_num_nodes_ || at(parent_node_, v) != v)
      mesh_.nodes.col(v) = original_.nodes.col(at(node_origin_, v));
  lumped_mass_.conservativeResize(3 * n);
  element_origin_.resize(toSize(num_copies));
  element_fraction_.resize(toSize(num_copies));
  for (int e : changed) {
    const CopyList& list = at(element_copies_, e);
    for (int k = 0; k < list.count; ++k) {
      at(element_origin_, list.ids[k]) = e;
      at(element_fraction_, list.ids[k]) = at(copies_, list.ids[k]).fraction;
    }
  }
  ++stamp_;
  std::vector<int> around;  // elements around the changed corners (their nodes may have changed)
  for (int v : origins)
    for (const int* p = starBegin(v); p != starEnd(v); ++p)
      if (firstVisit(element_stamp_, *p)) around.push_back(*p);
  face_triangle_.resize(toSize(4 * num_copies), -1);
  refreshDerived(origins, around);
}

// ---------------------------------------------------------------------------------------------
// Node classification around one original node.

void TetCutter::starClasses(int v, StarClasses& out) {
  UnionFind classes = glueStarSlots(v, out);
  std::vector<int> kept_by, carried;
  labelStarClasses(classes, out, kept_by, carried);
  claimStarNodes(kept_by, carried, out);
}

UnionFind TetCutter::glueStarSlots(int v, StarClasses& out) {
  out.slots.clear();
  forEachStarCopy(v, [&](int copy, int corner) {
    at(copy_slot_, copy) = intSize(out.slots);
    out.slots.push_back({copy, corner});
  });
  UnionFind classes(intSize(out.slots));
  for (const int* p = starBegin(v); p != starEnd(v); ++p) {
    const int e = *p, corner = localCornerOf(original_, e, v);
    const CopyList& list = at(element_copies_, e);
    for (int lf = 0; lf < 4; ++lf) {
      const int e2 = at(face_neighbour_, 4 * e + lf)[0];
      if (lf == corner || e2 < e) continue;  // faces at v, each once, boundary skipped
      const std::array<int, 3> corners = tetFaceCorners(lf);
      const int k_v = corners[0] == corner ? 0 : corners[1] == corner ? 1 : 2;
      const CopyList& list2 = at(element_copies_, e2);
      forEachCopyPair(e, lf, [&](int i, int j, const FaceGlue& g) {
        if (g.corner[k_v]) classes.unite(at(copy_slot_, list.ids[i]), at(copy_slot_, list2.ids[j]));
      });
    }
  }
  return classes;
}

void TetCutter::labelStarClasses(UnionFind& classes, StarClasses& out, std::vector<int>& kept_by,
                                 std::vector<int>& carried) const {
  // Only the slots of unchanged copies keep their node; the slots of changed copies only carry
  // the node of the copy they come from.
  const int num_slots = intSize(out.slots);
  out.slot_class.assign(toSize(num_slots), -1);
  std::vector<int> class_of_root(toSize(num_slots), -1);
  for (int s = 0; s < num_slots; ++s) {
    const auto [copy, corner] = at(out.slots, s);
    const int node = mesh_.elements(corner, copy);
    int& cls = at(class_of_root, classes.find(s));
    if (cls < 0) {
      cls = intSize(kept_by);
      kept_by.push_back(-1);
      carried.push_back(node);
    }
    at(out.slot_class, s) = cls;
    int& kept = at(kept_by, cls);
    if (at(changed_stamp_, at(copies_, copy).element) != stamp_ && (kept < 0 || node < kept))
      kept = node;
  }
}

void TetCutter::claimStarNodes(const std::vector<int>& kept_by, const std::vector<int>& carried,
                               StarClasses& out) const {
  const int num_classes = intSize(kept_by);
  out.class_node.assign(toSize(num_classes), -1);
  out.class_parent.assign(toSize(num_classes), -1);
  std::vector<int> claimed;
  const auto isClaimed = [&claimed](int node) {
    return std::find(claimed.begin(), claimed.end(), node) != claimed.end();
  };
  for (int pass = 0; pass < 2; ++pass)
    for (int c = 0; c < num_classes; ++c) {
      if ((at(kept_by, c) >= 0) != (pass == 0)) continue;
      const int node = pass == 0 ? at(kept_by, c) : at(carried, c);
      if (isClaimed(node)) {
        at(out.class_parent, c) = node;
      } else {
        at(out.class_node, c) = node;
        claimed.push_back(node);
      }
    }
  out.vanished.clear();
  for (const auto& [copy, corner] : out.slots) {
    const int node = mesh_.elements(corner, copy);
    if (!isClaimed(node) &&
        std::find(out.vanished.begin(), out.vanished.end(), node) == out.vanished.end())
      out.vanished.push_back(node);
  }
}

void TetCutter::applyStarClasses(int v, const StarClasses& star) {
  std::vector<int> node = star.class_node;
  for (int c = 0; c < intSize(node); ++c) {
    if (at(node, c) >= 0) continue;
    at(node, c) = intSize(node_origin_);
    parent_node_.push_back(at(star.class_parent, c));
    node_origin_.push_back(v);
    at(origin_nodes_, v).push_back(at(node, c));
  }
  for (int s = 0; s < intSize(star.slots); ++s)
    mesh_.elements(at(star.slots, s)[1], at(star.slots, s)[0]) = at(node, at(star.slot_class, s));
}

int TetCutter::removeNode(int node) {
  const auto erase = [](std::vector<int>& list, int value) {
    list.erase(std::find(list.begin(), list.end(), value));
  };
  erase(at(origin_nodes_, at(node_origin_, node)), node);
  const int last = intSize(node_origin_) - 1, origin = at(node_origin_, last);
  if (node != last) {
    forEachStarCopy(origin, [&](int copy, int corner) {
      if (mesh_.elements(corner, copy) == last) mesh_.elements(corner, copy) = node;
    });
    std::vector<int>& nodes = at(origin_nodes_, origin);
    std::replace(nodes.begin(), nodes.end(), last, node);
    at(node_origin_, node) = origin;
    at(parent_node_, node) = parent_node_.back();
  }
  node_origin_.pop_back();
  parent_node_.pop_back();
  return origin;
}

// ---------------------------------------------------------------------------------------------
// Derived-data refresh.

void TetCutter::resetDerived() {
  const int n = mesh_.numNodes();
  lumped_mass_.setZero(3 * n);
  removed_mass_ = 0.0;
  triangles_.clear();
  triangle_face_.clear();
  triangle_cut_.clear();
  changed_triangles_.clear();
  surface_changed_nodes_.clear();
  node_triangles_.assign(toSize(n), 0);
  on_surface_.assign(toSize(n), 0);
  surface_.nodes.clear();
  surface_.triangles.resize(3, 0);
  face_triangle_.assign(toSize(4 * intSize(copies_)), -1);
  edge_representative_.assign(edges_.size(), {-1, -1});
}

void TetCutter::refreshDerived(const std::vector<int>& origins, const std::vector<int>& elements) {
  recomputeMasses(origins);
  refreshFaces(elements);
  refreshEdgeRepresentatives(elements);
  publishSurface();
}

void TetCutter::recomputeMasses(const std::vector<int>& origins) {
  for (int v : origins)
    for (int node : at(origin_nodes_, v)) lumped_mass_.segment<3>(3 * node).setZero();
  for (int v : origins) {
    const std::vector<int>& nodes = at(origin_nodes_, v);
    for (const int* p = starBegin(v); p != starEnd(v); ++p) {
      const int e = *p;
      const double quarter = 0.25 * density_ * at(element_volume_, e);
      const int corner = localCornerOf(original_, e, v);
      const CopyList& list = at(element_copies_, e);
      for (int k = 0; k < list.count; ++k)
        lumped_mass_.segment<3>(3 * mesh_.elements(corner, list.ids[k])).array() +=
            quarter * at(copies_, list.ids[k]).fraction;
      // A removed element's share goes to the lowest remaining node of the corner.
      if (!at(removed_, e)) continue;
      if (nodes.empty())
        removed_mass_ += quarter;
      else
        lumped_mass_.segment<3>(3 * *std::min_element(nodes.begin(), nodes.end())).array() +=
            quarter;
    }
  }
}

void TetCutter::countTriangle(const std::array<int, 3>& tri, int delta) {
  for (int node : tri) {
    if (node >= intSize(node_triangles_)) node_triangles_.resize(toSize(node + 1), 0);
    at(node_triangles_, node) += delta;
    surface_changed_nodes_.push_back(node);
  }
}

void TetCutter::setTriangle(int face_slot, bool present) {
  int& t = at(face_triangle_, face_slot);
  if (!present) {
    if (t < 0) return;
    countTriangle(at(triangles_, t), -1);
    at(triangles_, t) = triangles_.back();
    at(triangle_face_, t) = triangle_face_.back();
    at(triangle_cut_, t) = triangle_cut_.back();
    at(face_triangle_, at(triangle_face_, t)) = t;
    changed_triangles_.push_back(t);
    triangles_.pop_back();
    triangle_face_.pop_back();
    triangle_cut_.pop_back();
    at(face_triangle_, face_slot) = -1;
    return;
  }
  const int c = face_slot / 4, lf = face_slot % 4;
  const int e = at(copies_, c).element;
  const std::array<int, 3> corners = tetFaceCorners(lf);
  const std::array<int, 3> tri{mesh_.elements(corners[0], c), mesh_.elements(corners[1], c),
                               mesh_.elements(corners[2], c)};
  if (t < 0) {
    t = intSize(triangles_);
    triangles_.push_back(tri);
    triangle_face_.push_back(face_slot);
    triangle_cut_.push_back(at(face_neighbour_, 4 * e + lf)[0] >= 0);
  } else {
    if (at(triangles_, t) == tri) return;
    countTriangle(at(triangles_, t), -1);
    at(triangles_, t) = tri;
  }
  countTriangle(tri, +1);
  changed_triangles_.push_back(t);
}

void TetCutter::refreshFaces(const std::vector<int>& elements) {
  // A copy's face is on the surface unless a copy of the neighbour continues the material there.
  for (int e : elements) {
    const CopyList& list = at(element_copies_, e);
    for (int i = 0; i < list.count; ++i)
      for (int lf = 0; lf < 4; ++lf)
        setTriangle(4 * list.ids[i] + lf, !continuesAcross(list.ids[i], lf));
  }
}

void TetCutter::refreshEdgeRepresentatives(const std::vector<int>& elements) {
  for (int e : elements) {
    const CopyList& list = at(element_copies_, e);
    for (int i = 0; i < list.count; ++i) {
      const int c = list.ids[i], mask = at(copies_, c).mask;
      for (int k = 0; k < 6; ++k) {
        const int a = kTetLocalEdges[k][0], b = kTetLocalEdges[k][1];
        const int id = at(element_edges_, e)[k];
        if (at(edge_cut_, id) || !(mask & (1 << a)) || !(mask & (1 << b))) continue;
        const bool forward = original_.elements(a, e) == at(edges_, id)[0];
        at(edge_representative_, id) =
            forward ? std::array<int, 2>{mesh_.elements(a, c), mesh_.elements(b, c)}
                    : std::array<int, 2>{mesh_.elements(b, c), mesh_.elements(a, c)};
      }
    }
  }
}

void TetCutter::publishSurface() {
  // Only the triangles written since the last publication, and the surface nodes whose triangle
  // count crossed zero (merged into the sorted list), so the cost follows the change.
  const int num_triangles = intSize(triangles_);
  surface_.triangles.conservativeResize(3, num_triangles);
  for (int t : changed_triangles_)
    if (t < num_triangles)
      for (int k = 0; k < 3; ++k) surface_.triangles(k, t) = at(triangles_, t)[k];
  changed_triangles_.clear();
  const int n = mesh_.numNodes();
  on_surface_.resize(std::max(on_surface_.size(), node_triangles_.size()), 0);
  std::vector<int> joining;
  bool leaving = false;
  for (int v : surface_changed_nodes_) {
    const bool now = at(node_triangles_, v) > 0;
    char& was = at(on_surface_, v);
    if (now == static_cast<bool>(was)) continue;
    was = now ? 1 : 0;
    if (now)
      joining.push_back(v);
    else
      leaving = true;
  }
  surface_changed_nodes_.clear();
  if (leaving)
    surface_.nodes.erase(std::remove_if(surface_.nodes.begin(), surface_.nodes.end(),
                                        [this](int v) { return !at(on_surface_, v); }),
                         surface_.nodes.end());
  if (!joining.empty()) {
    std::sort(joining.begin(), joining.end());
    const auto middle = static_cast<std::ptrdiff_t>(surface_.nodes.size());
    surface_.nodes.insert(surface_.nodes.end(), joining.begin(), joining.end());
    std::inplace_merge(surface_.nodes.begin(), surface_.nodes.begin() + middle,
                       surface_.nodes.end());
  }
  node_triangles_.resize(toSize(n), 0);
  on_surface_.resize(toSize(n), 0);
  cut_faces_ = triangle_cut_;
  derived_valid_ = false;
}

// ---------------------------------------------------------------------------------------------
// Data derived on demand.

void TetCutter::derive() const {
  if (derived_valid_) return;
  deriveComponents();
  cut_triangles_.clear();
  for (int c = 0; c < mesh_.numElements(); ++c)
    if (at(copies_, c).mask != 0xF) deriveCutTriangles(c);
  derived_valid_ = true;
}

void TetCutter::deriveComponents() const {
  const int n = mesh_.numNodes();
  UnionFind pieces(n);
  for (int c = 0; c < mesh_.numElements(); ++c)
    for (int i = 1; i < 4; ++i) pieces.unite(mesh_.elements(0, c), mesh_.elements(i, c));
  node_component_.assign(toSize(n), -1);
  std::vector<int> label(toSize(n), -1);
  num_components_ = 0;
  for (int v = 0; v < n; ++v) {
    int& l = at(label, pieces.find(v));
    if (l < 0) l = num_components_++;
    at(node_component_, v) = l;
  }
}

void TetCutter::deriveCutTriangles(int c) const {
  // The crossing points on the edges from the copy's real corners to the others: a triangle
  // for 1 or 3 real corners, a quad for 2.
  const Copy& copy = at(copies_, c);
  const std::array<double, 6> s = localCutParameters(copy.element);
  const auto point = [&](int real, int other) {
    const double s_lo = s[toSize(tetLocalEdge(real, other))];
    return EmbeddedCutPoint{mesh_.elements(real, c), mesh_.elements(other, c),
                            real < other ? s_lo : 1.0 - s_lo};
  };
  std::array<int, 4> in{}, out{};
  int ni = 0, no = 0;
  for (int i = 0; i < 4; ++i) (copy.mask & (1 << i) ? in[ni++] : out[no++]) = i;
  std::vector<std::array<EmbeddedCutPoint, 3>> tris;
  if (ni == 1) tris.push_back({point(in[0], out[0]), point(in[0], out[1]), point(in[0], out[2])});
  if (ni == 3) tris.push_back({point(in[0], out[0]), point(in[1], out[0]), point(in[2], out[0])});
  if (ni == 2) {
    const EmbeddedCutPoint q[4] = {point(in[0], out[0]), point(in[1], out[0]), point(in[1], out[1]),
                                   point(in[0], out[1])};
    tris.push_back({q[0], q[1], q[2]});
    tris.push_back({q[0], q[2], q[3]});
  }
  Eigen::Vector3d real_centroid = Eigen::Vector3d::Zero();
  for (int k = 0; k < ni; ++k) real_centroid += mesh_.nodes.col(mesh_.elements(in[k], c)) / ni;
  for (auto& tri : tris) {  // oriented away from the real corners
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = (1.0 - tri[k].w) * mesh_.nodes.col(tri[k].node_a) +
             tri[k].w * mesh_.nodes.col(tri[k].node_b);
    if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[0] - real_centroid) < 0.0) std::swap(tri[1], tri[2]);
    cut_triangles_.push_back(tri);
  }
}

const std::vector<std::array<EmbeddedCutPoint, 3>>& TetCutter::cutTriangles() const {
  derive();
  return cut_triangles_;
}

const std::vector<int>& TetCutter::nodeComponent() const {
  derive();
  return node_component_;
}

int TetCutter::numComponents() const {
  derive();
  return num_components_;
}

// ---------------------------------------------------------------------------------------------
// Public operations.

CutUpdate TetCutter::cut(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                         const Eigen::VectorXd& x_end) {
  validateBladeSweep(sweep);
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(mesh_.numNodes());
  if (x_start.size() != size || x_end.size() != size)
    throw std::invalid_argument(
        "TetCutter::cut: positions have sizes " + std::to_string(x_start.size()) + " and " +
        std::to_string(x_end.size()) + ", expected 3 n = " + std::to_string(size));
  CutUpdate update;
  Stopwatch detect;
  std::vector<int> new_cut_edges;
  for (const BladeEdgeCrossing& crossing : detectBladeEdgeCrossings(
           sweep, x_start, x_end, edge_representative_, edge_cut_, tolerance_, outcode_)) {
    at(edge_cut_, crossing.edge) = 1;
    at(edge_s_, crossing.edge) = crossing.s;
    new_cut_edges.push_back(crossing.edge);
  }
  update.edges_cut = intSize(new_cut_edges);
  num_cut_edges_ += update.edges_cut;
  update.detect_seconds = detect.seconds();
  if (update.edges_cut == 0) return update;
  Stopwatch update_watch;
  update.topology_changed = applyCutEdges(new_cut_edges);
  update.update_seconds = update_watch.seconds();
  return update;
}

bool TetCutter::applyCutEdges(const std::vector<int>& new_cut_edges) {
  if (mode_ == CutUpdateMode::Incremental) return updateIncrementally(new_cut_edges);
  const Eigen::MatrixXi before = mesh_.elements;
  const Eigen::VectorXd mass_before = lumped_mass_;
  rebuild();
  return before.cols() != mesh_.elements.cols() || before != mesh_.elements ||
         mass_before != lumped_mass_;
}

CutUpdate TetCutter::removeElements(const std::vector<int>& elements) {
  CutUpdate update;
  for (int c : elements) {
    if (c < 0 || c >= mesh_.numElements())
      throw std::invalid_argument("TetCutter::removeElements: element " + std::to_string(c) +
                                  " is out of range [0, " + std::to_string(mesh_.numElements()) +
                                  ")");
    at(removed_, at(element_origin_, c)) = 1;
  }
  if (elements.empty()) return update;
  Stopwatch rebuild_watch;
  rebuild();
  update.topology_changed = true;
  update.update_seconds = rebuild_watch.seconds();
  return update;
}

std::vector<int> TetCutter::overstrainedElements(const Eigen::VectorXd& x,
                                                 double max_strain) const {
  std::vector<int> out;
  for (int c = 0; c < mesh_.numElements(); ++c) {
    Eigen::Matrix3d Dm, Ds;
    for (int k = 0; k < 3; ++k) {
      Dm.col(k) = mesh_.nodes.col(mesh_.elements(k + 1, c)) - mesh_.nodes.col(mesh_.elements(0, c));
      Ds.col(k) = nodeAt(x, mesh_.elements(k + 1, c)) - nodeAt(x, mesh_.elements(0, c));
    }
    const Eigen::Matrix3d F = Ds * Dm.inverse();
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    if (E.norm() > max_strain) out.push_back(c);
  }
  return out;
}

Eigen::VectorXd TetCutter::transfer(const Eigen::VectorXd& old_values) const {
  if (old_values.size() != 3 * static_cast<Eigen::Index>(old_num_nodes_))
    throw std::invalid_argument("TetCutter::transfer: vector of size " +
                                std::to_string(old_values.size()) +
                                ", expected 3 n_old = " + std::to_string(3 * old_num_nodes_));
  const int n = intSize(parent_node_);
  Eigen::VectorXd out(3 * static_cast<Eigen::Index>(n));
  for (int v = 0; v < n; ++v)
    out.segment<3>(3 * v) = old_values.segment<3>(3 * at(parent_node_, v));
  return out;
}

}  // namespace surgical_sim::core
