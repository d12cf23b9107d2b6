#include "surgical_sim/core/cutting/tet_cutter.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/union_find.h"
#include "surgical_sim/core/cutting/edge_sweep_ccd.h"
#include "surgical_sim/core/cutting/fragment_volume.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/tet_faces.h"

namespace surgical_sim::core {

namespace {

Eigen::Vector3d nodeAt(const Eigen::VectorXd& x, int node) { return x.segment<3>(3 * node); }

int localCornerOf(const TetMesh& mesh, int element, int node) {
  for (int i = 0; i < 4; ++i)
    if (mesh.elements(i, element) == node) return i;
  return -1;
}

}  // namespace

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

  // Unique edges and element -> edges.
  std::vector<std::array<int, 3>> keyed;  // (lo, hi, element * 6 + local edge)
  keyed.reserve(static_cast<std::size_t>(6 * m));
  for (int e = 0; e < m; ++e)
    for (int k = 0; k < 6; ++k) {
      const int a = rest_mesh.elements(kTetLocalEdges[k][0], e);
      const int b = rest_mesh.elements(kTetLocalEdges[k][1], e);
      keyed.push_back({std::min(a, b), std::max(a, b), 6 * e + k});
    }
  std::sort(keyed.begin(), keyed.end());
  element_edges_.resize(static_cast<std::size_t>(m));
  edge_offsets_.push_back(0);
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i][0] != keyed[i - 1][0] || keyed[i][1] != keyed[i - 1][1]) {
      if (i > 0) edge_offsets_.push_back(static_cast<int>(i));
      edges_.push_back({keyed[i][0], keyed[i][1]});
    }
    const int id = static_cast<int>(edges_.size()) - 1;
    element_edges_[static_cast<std::size_t>(keyed[i][2] / 6)][keyed[i][2] % 6] = id;
    edge_elements_.push_back(keyed[i][2] / 6);
  }
  edge_offsets_.push_back(static_cast<int>(keyed.size()));

  // Original node -> elements.
  const int n = rest_mesh.numNodes();
  vertex_offsets_.assign(static_cast<std::size_t>(n + 1), 0);
  for (int e = 0; e < m; ++e)
    for (int i = 0; i < 4; ++i)
      ++vertex_offsets_[static_cast<std::size_t>(rest_mesh.elements(i, e) + 1)];
  for (int v = 0; v < n; ++v) vertex_offsets_[v + 1] += vertex_offsets_[v];
  vertex_elements_.resize(static_cast<std::size_t>(4 * m));
  std::vector<int> fill(vertex_offsets_.begin(), vertex_offsets_.end() - 1);
  for (int e = 0; e < m; ++e)
    for (int i = 0; i < 4; ++i)
      vertex_elements_[static_cast<std::size_t>(fill[rest_mesh.elements(i, e)]++)] = e;

  // Face neighbours (-1 on the original boundary).
  face_neighbour_.assign(static_cast<std::size_t>(4 * m), {-1, -1});
  const TetFaceGroups groups = groupTetFaces(rest_mesh);
  for (int g = 0; g < groups.numGroups(); ++g) {
    const int begin = groups.group_offsets[g], size = groups.group_offsets[g + 1] - begin;
    const TetFace& f0 = groups.faces[static_cast<std::size_t>(begin)];
    if (size != 2) continue;
    const TetFace& f1 = groups.faces[static_cast<std::size_t>(begin + 1)];
    face_neighbour_[static_cast<std::size_t>(4 * f0.element + f0.local_face)] = {f1.element,
                                                                                 f1.local_face};
    face_neighbour_[static_cast<std::size_t>(4 * f1.element + f1.local_face)] = {f0.element,
                                                                                 f0.local_face};
  }

  // Local corners, in the neighbour, of each interior face's corners.
  neighbour_corners_.assign(static_cast<std::size_t>(4 * m), {-1, -1, -1});
  for (int e = 0; e < m; ++e)
    for (int lf = 0; lf < 4; ++lf) {
      const int e2 = face_neighbour_[static_cast<std::size_t>(4 * e + lf)][0];
      if (e2 < 0) continue;
      const std::array<int, 3> corners = tetFaceCorners(lf);
      for (int k = 0; k < 3; ++k)
        neighbour_corners_[static_cast<std::size_t>(4 * e + lf)][k] = static_cast<std::int8_t>(
            localCornerOf(rest_mesh, e2, rest_mesh.elements(corners[k], e)));
    }

  element_volume_.resize(static_cast<std::size_t>(m));
  for (int e = 0; e < m; ++e)
    element_volume_[static_cast<std::size_t>(e)] = signedVolume(rest_mesh, e);
  edge_cut_.assign(edges_.size(), 0);
  edge_s_.assign(edges_.size(), 0.0);
  removed_.assign(static_cast<std::size_t>(m), 0);
  element_stamp_.assign(static_cast<std::size_t>(m), 0);
  changed_stamp_.assign(static_cast<std::size_t>(m), 0);
  origin_stamp_.assign(static_cast<std::size_t>(n), 0);
  rebuild();
}

bool TetCutter::firstVisit(std::vector<int>& stamps, int i) const {
  int& s = stamps[static_cast<std::size_t>(i)];
  if (s == stamp_) return false;
  s = stamp_;
  return true;
}

int TetCutter::partition(int element, std::array<int, 4>& masks) const {
  std::array<int, 4> comp{0, 1, 2, 3};
  for (int k = 0; k < 6; ++k) {
    if (edge_cut_[static_cast<std::size_t>(element_edges_[static_cast<std::size_t>(element)][k])])
      continue;
    const int from = comp[kTetLocalEdges[k][1]], to = comp[kTetLocalEdges[k][0]];
    for (int& c : comp)
      if (c == from) c = to;
  }
  int count = 0;
  std::array<int, 4> label{-1, -1, -1, -1};
  masks = {0, 0, 0, 0};
  for (int i = 0; i < 4; ++i) {
    int& l = label[comp[i]];
    if (l < 0) l = count++;
    masks[l] |= 1 << i;
  }
  return count;
}

std::array<double, 6> TetCutter::localCutParameters(int element) const {
  std::array<double, 6> s{};
  for (int k = 0; k < 6; ++k) {
    const int id = element_edges_[static_cast<std::size_t>(element)][k];
    const int a = original_.elements(kTetLocalEdges[k][0], element);
    s[k] = a == edges_[static_cast<std::size_t>(id)][0]
               ? edge_s_[static_cast<std::size_t>(id)]
               : 1.0 - edge_s_[static_cast<std::size_t>(id)];
  }
  return s;
}

std::array<int, 3> TetCutter::neighbourCorners(int element, int local_face) const {
  const std::array<std::int8_t, 3>& c =
      neighbour_corners_[static_cast<std::size_t>(4 * element + local_face)];
  return {c[0], c[1], c[2]};
}

TetCutter::FaceGlue TetCutter::glue(int copy, int local_face, int copy2,
                                    const std::array<int, 3>& corners2) const {
  const std::array<int, 3> corners = tetFaceCorners(local_face);
  const int mask = copies_[static_cast<std::size_t>(copy)].mask;
  const int mask2 = copies_[static_cast<std::size_t>(copy2)].mask;
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

void TetCutter::rebuild() {
  ++full_rebuilds_;
  const int m = original_.numElements();
  // 1. One copy per fragment of every remaining element.
  const std::vector<Copy> old_copies = copies_;
  const std::vector<CopyList> old_lists = element_copies_;
  const Eigen::MatrixXi old_elements = mesh_.elements;
  old_num_nodes_ = mesh_.numNodes();
  copies_.clear();
  element_copies_.assign(static_cast<std::size_t>(m), CopyList{});
  for (int e = 0; e < m; ++e) {
    if (removed_[static_cast<std::size_t>(e)]) continue;
    std::array<int, 4> masks{};
    const int count = partition(e, masks);
    Eigen::Matrix<double, 3, 4> X;
    for (int i = 0; i < 4; ++i) X.col(i) = original_.nodes.col(original_.elements(i, e));
    const std::array<double, 4> f = fragmentVolumeFractions(X, localCutParameters(e), masks, count);
    CopyList& list = element_copies_[static_cast<std::size_t>(e)];
    for (int k = 0; k < count; ++k) {
      list.ids[static_cast<std::size_t>(list.count++)] = static_cast<int>(copies_.size());
      copies_.push_back({e, masks[k], f[k]});
    }
  }
  const int num_copies = static_cast<int>(copies_.size());

  // 2. Nodes are the classes of slots (copy, corner) glued across shared faces (glue()). The
  // first class of each original node (in copy order) keeps the original index, the others are
  // numbered after them; indices of original nodes that lost all their elements are closed up,
  // keeping the order (an uncut mesh keeps its numbering). Parents come from the old copy
  // containing the fragment.
  UnionFind slots(4 * num_copies);
  for (int e = 0; e < m; ++e)
    for (int lf = 0; lf < 4; ++lf) {
      const int e2 = face_neighbour_[static_cast<std::size_t>(4 * e + lf)][0];
      if (e2 < e) continue;  // each interior face once (and skips the boundary, e2 = -1)
      const std::array<int, 3> corners = tetFaceCorners(lf), corners2 = neighbourCorners(e, lf);
      const CopyList &list = element_copies_[static_cast<std::size_t>(e)],
                     &list2 = element_copies_[static_cast<std::size_t>(e2)];
      for (int i = 0; i < list.count; ++i)
        for (int j = 0; j < list2.count; ++j) {
          const FaceGlue g = glue(list.ids[i], lf, list2.ids[j], corners2);
          for (int k = 0; k < 3; ++k)
            if (g.corner[k])
              slots.unite(4 * list.ids[i] + corners[k], 4 * list2.ids[j] + corners2[k]);
        }
    }
  const int n_orig = original_.numNodes();
  std::vector<int> node_of_root(static_cast<std::size_t>(4 * num_copies), -1);
  std::vector<int> slot_node(static_cast<std::size_t>(4 * num_copies));
  std::vector<int> origin_of(static_cast<std::size_t>(n_orig), -1);  // extended below
  std::vector<char> primary_used(static_cast<std::size_t>(n_orig), 0);
  int extra = 0;
  for (int c = 0; c < num_copies; ++c)
    for (int i = 0; i < 4; ++i) {
      int& node = node_of_root[static_cast<std::size_t>(slots.find(4 * c + i))];
      if (node < 0) {
        const int origin = original_.elements(i, copies_[static_cast<std::size_t>(c)].element);
        if (!primary_used[static_cast<std::size_t>(origin)]) {
          primary_used[static_cast<std::size_t>(origin)] = 1;
          node = origin;
        } else {
          node = n_orig + extra++;
          origin_of.push_back(origin);
        }
        origin_of[static_cast<std::size_t>(node)] = origin;
      }
      slot_node[static_cast<std::size_t>(4 * c + i)] = node;
    }
  std::vector<int> compact(origin_of.size(), -1);
  node_origin_.clear();
  for (std::size_t v = 0; v < origin_of.size(); ++v)
    if (v >= static_cast<std::size_t>(n_orig) || primary_used[v]) {
      compact[v] = static_cast<int>(node_origin_.size());
      node_origin_.push_back(origin_of[v]);
    }
  const int n = static_cast<int>(node_origin_.size());
  parent_node_.assign(static_cast<std::size_t>(n), -1);
  mesh_.type = ElementType::Tet4;
  mesh_.elements.resize(4, num_copies);
  element_origin_.resize(static_cast<std::size_t>(num_copies));
  element_fraction_.resize(static_cast<std::size_t>(num_copies));
  for (int c = 0; c < num_copies; ++c) {
    const Copy& copy = copies_[static_cast<std::size_t>(c)];
    int parent_copy = -1;
    if (!old_copies.empty()) {
      const CopyList& old = old_lists[static_cast<std::size_t>(copy.element)];
      for (int k = 0; k < old.count; ++k) {
        const int o = old.ids[k], om = old_copies[static_cast<std::size_t>(o)].mask;
        if ((om & copy.mask) == copy.mask) parent_copy = o;
        if (parent_copy < 0 && (om & copy.mask)) parent_copy = o;
      }
    }
    for (int i = 0; i < 4; ++i) {
      const int node =
          compact[static_cast<std::size_t>(slot_node[static_cast<std::size_t>(4 * c + i)])];
      mesh_.elements(i, c) = node;
      int& parent = parent_node_[static_cast<std::size_t>(node)];
      if (parent < 0) parent = parent_copy >= 0 ? old_elements(i, parent_copy) : node_origin_[node];
    }
    element_origin_[static_cast<std::size_t>(c)] = copy.element;
    element_fraction_[static_cast<std::size_t>(c)] = copy.fraction;
  }
  mesh_.nodes.resize(3, n);
  origin_nodes_.assign(static_cast<std::size_t>(n_orig), {});
  for (int v = 0; v < n; ++v) {
    mesh_.nodes.col(v) = original_.nodes.col(node_origin_[v]);
    origin_nodes_[static_cast<std::size_t>(node_origin_[v])].push_back(v);
  }

  // 3. Masses, faces and edge representatives of everything.
  std::vector<int> all_elements(static_cast<std::size_t>(m)),
      all_origins(static_cast<std::size_t>(n_orig));
  std::iota(all_elements.begin(), all_elements.end(), 0);
  std::iota(all_origins.begin(), all_origins.end(), 0);
  lumped_mass_.setZero(3 * n);
  removed_mass_ = 0.0;
  recomputeMasses(all_origins);
  triangles_.clear();
  triangle_face_.clear();
  triangle_cut_.clear();
  changed_triangles_.clear();
  surface_changed_nodes_.clear();
  node_triangles_.assign(static_cast<std::size_t>(n), 0);
  on_surface_.assign(static_cast<std::size_t>(n), 0);
  surface_.nodes.clear();
  surface_.triangles.resize(3, 0);
  face_triangle_.assign(static_cast<std::size_t>(4 * num_copies), -1);
  refreshFaces(all_elements);
  edge_representative_.assign(edges_.size(), {-1, -1});
  refreshEdgeRepresentatives(all_elements);
  publishSurface();
}

void TetCutter::starClasses(int v, StarClasses& out) {
  out.slots.clear();
  for (const int* p = starBegin(v); p != starEnd(v); ++p) {
    const CopyList& list = element_copies_[static_cast<std::size_t>(*p)];
    const int corner = localCornerOf(original_, *p, v);
    for (int k = 0; k < list.count; ++k) {
      copy_slot_[static_cast<std::size_t>(list.ids[k])] = static_cast<int>(out.slots.size());
      out.slots.push_back({list.ids[k], corner});
    }
  }
  UnionFind classes(static_cast<int>(out.slots.size()));
  for (const int* p = starBegin(v); p != starEnd(v); ++p) {
    const int e = *p;
    const int corner = localCornerOf(original_, e, v);
    for (int lf = 0; lf < 4; ++lf) {
      const int e2 = face_neighbour_[static_cast<std::size_t>(4 * e + lf)][0];
      if (lf == corner || e2 < e) continue;  // faces at v, each once, boundary skipped
      const std::array<int, 3> corners = tetFaceCorners(lf), corners2 = neighbourCorners(e, lf);
      const int k_v = corners[0] == corner ? 0 : corners[1] == corner ? 1 : 2;
      const CopyList &list = element_copies_[static_cast<std::size_t>(e)],
                     &list2 = element_copies_[static_cast<std::size_t>(e2)];
      for (int i = 0; i < list.count; ++i)
        for (int j = 0; j < list2.count; ++j)
          if (glue(list.ids[i], lf, list2.ids[j], corners2).corner[k_v])
            classes.unite(copy_slot_[static_cast<std::size_t>(list.ids[i])],
                          copy_slot_[static_cast<std::size_t>(list2.ids[j])]);
    }
  }
  // A class keeps the (lowest) node of its slots in unchanged copies; the slots of changed
  // copies only carry the node of the copy they come from.
  out.slot_class.assign(out.slots.size(), -1);
  std::vector<int> kept_by;  // per class: node of its unchanged slots, or -1
  std::vector<int> carried;  // per class: node carried by its first slot
  std::vector<int> class_of_root(out.slots.size(), -1);
  for (std::size_t s = 0; s < out.slots.size(); ++s) {
    const auto [copy, corner] = out.slots[s];
    const int node = mesh_.elements(corner, copy);
    int& cls = class_of_root[static_cast<std::size_t>(classes.find(static_cast<int>(s)))];
    if (cls < 0) {
      cls = static_cast<int>(kept_by.size());
      kept_by.push_back(-1);
      carried.push_back(node);
    }
    out.slot_class[s] = cls;
    const int element = copies_[static_cast<std::size_t>(copy)].element;
    int& kept = kept_by[static_cast<std::size_t>(cls)];
    if (changed_stamp_[static_cast<std::size_t>(element)] != stamp_ && (kept < 0 || node < kept))
      kept = node;
  }
  // Classes with unchanged slots claim their node first, then the others the carried one; a
  // class whose node is taken gets a new node split from it. Nodes left unclaimed vanish (the
  // change merged them into others).
  const std::size_t num_classes = kept_by.size();
  out.class_node.assign(num_classes, -1);
  out.class_parent.assign(num_classes, -1);
  std::vector<int> claimed;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t c = 0; c < num_classes; ++c) {
      if ((kept_by[c] >= 0) != (pass == 0)) continue;
      const int node = pass == 0 ? kept_by[c] : carried[c];
      if (std::find(claimed.begin(), claimed.end(), node) != claimed.end()) {
        out.class_parent[c] = node;
      } else {
        out.class_node[c] = node;
        claimed.push_back(node);
      }
    }
  out.vanished.clear();
  for (const auto& [copy, corner] : out.slots) {
    const int node = mesh_.elements(corner, copy);
    if (std::find(claimed.begin(), claimed.end(), node) == claimed.end() &&
        std::find(out.vanished.begin(), out.vanished.end(), node) == out.vanished.end())
      out.vanished.push_back(node);
  }
}

void TetCutter::applyStarClasses(int v, const StarClasses& star) {
  std::vector<int> node = star.class_node;
  for (std::size_t c = 0; c < node.size(); ++c) {
    if (node[c] >= 0) continue;
    node[c] = static_cast<int>(node_origin_.size());
    parent_node_.push_back(star.class_parent[c]);
    node_origin_.push_back(v);
    origin_nodes_[static_cast<std::size_t>(v)].push_back(node[c]);
  }
  for (std::size_t s = 0; s < star.slots.size(); ++s)
    mesh_.elements(star.slots[s][1], star.slots[s][0]) =
        node[static_cast<std::size_t>(star.slot_class[s])];
}

int TetCutter::removeNode(int node) {
  const auto erase = [](std::vector<int>& list, int value) {
    list.erase(std::find(list.begin(), list.end(), value));
  };
  erase(origin_nodes_[static_cast<std::size_t>(node_origin_[node])], node);
  const int last = static_cast<int>(node_origin_.size()) - 1, origin = node_origin_[last];
  if (node != last) {
    for (const int* p = starBegin(origin); p != starEnd(origin); ++p) {
      const int corner = localCornerOf(original_, *p, origin);
      const CopyList& list = element_copies_[static_cast<std::size_t>(*p)];
      for (int k = 0; k < list.count; ++k)
        if (mesh_.elements(corner, list.ids[k]) == last) mesh_.elements(corner, list.ids[k]) = node;
    }
    std::replace(origin_nodes_[static_cast<std::size_t>(origin)].begin(),
                 origin_nodes_[static_cast<std::size_t>(origin)].end(), last, node);
    node_origin_[node] = origin;
    parent_node_[static_cast<std::size_t>(node)] = parent_node_.back();
  }
  node_origin_.pop_back();
  parent_node_.pop_back();
  return origin;
}

void TetCutter::recomputeMasses(const std::vector<int>& origins) {
  for (int v : origins)
    for (int node : origin_nodes_[static_cast<std::size_t>(v)])
      lumped_mass_.segment<3>(3 * node).setZero();
  for (int v : origins) {
    const std::vector<int>& nodes = origin_nodes_[static_cast<std::size_t>(v)];
    for (const int* p = starBegin(v); p != starEnd(v); ++p) {
      const int e = *p;
      const double quarter = 0.25 * density_ * element_volume_[static_cast<std::size_t>(e)];
      const int corner = localCornerOf(original_, e, v);
      const CopyList& list = element_copies_[static_cast<std::size_t>(e)];
      for (int k = 0; k < list.count; ++k)
        lumped_mass_.segment<3>(3 * mesh_.elements(corner, list.ids[k])).array() +=
            quarter * copies_[static_cast<std::size_t>(list.ids[k])].fraction;
      // A removed element's share goes to the lowest remaining node of the corner.
      if (!removed_[static_cast<std::size_t>(e)]) continue;
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
    if (static_cast<std::size_t>(node) >= node_triangles_.size())
      node_triangles_.resize(static_cast<std::size_t>(node) + 1, 0);
    node_triangles_[static_cast<std::size_t>(node)] += delta;
    surface_changed_nodes_.push_back(node);
  }
}

void TetCutter::setTriangle(int face_slot, bool present) {
  int& t = face_triangle_[static_cast<std::size_t>(face_slot)];
  if (!present) {
    if (t < 0) return;
    countTriangle(triangles_[static_cast<std::size_t>(t)], -1);
    triangles_[static_cast<std::size_t>(t)] = triangles_.back();
    triangle_face_[static_cast<std::size_t>(t)] = triangle_face_.back();
    triangle_cut_[static_cast<std::size_t>(t)] = triangle_cut_.back();
    face_triangle_[static_cast<std::size_t>(triangle_face_[static_cast<std::size_t>(t)])] = t;
    changed_triangles_.push_back(t);
    triangles_.pop_back();
    triangle_face_.pop_back();
    triangle_cut_.pop_back();
    face_triangle_[static_cast<std::size_t>(face_slot)] = -1;
    return;
  }
  const int c = face_slot / 4, lf = face_slot % 4;
  const int e = copies_[static_cast<std::size_t>(c)].element;
  const std::array<int, 3> corners = tetFaceCorners(lf);
  const std::array<int, 3> tri{mesh_.elements(corners[0], c), mesh_.elements(corners[1], c),
                               mesh_.elements(corners[2], c)};
  if (t < 0) {
    t = static_cast<int>(triangles_.size());
    triangles_.push_back(tri);
    triangle_face_.push_back(face_slot);
    triangle_cut_.push_back(face_neighbour_[static_cast<std::size_t>(4 * e + lf)][0] >= 0);
  } else {
    if (triangles_[static_cast<std::size_t>(t)] == tri) return;
    countTriangle(triangles_[static_cast<std::size_t>(t)], -1);
    triangles_[static_cast<std::size_t>(t)] = tri;
  }
  countTriangle(tri, +1);
  changed_triangles_.push_back(t);
}

void TetCutter::refreshFaces(const std::vector<int>& elements) {
  // A copy's face is on the surface unless a copy of the neighbour continues the material there.
  for (int e : elements) {
    const CopyList& list = element_copies_[static_cast<std::size_t>(e)];
    for (int i = 0; i < list.count; ++i)
      for (int lf = 0; lf < 4; ++lf) {
        const int e2 = face_neighbour_[static_cast<std::size_t>(4 * e + lf)][0];
        bool glued = false;
        if (e2 >= 0) {
          const std::array<int, 3> corners2 = neighbourCorners(e, lf);
          const CopyList& list2 = element_copies_[static_cast<std::size_t>(e2)];
          for (int j = 0; j < list2.count && !glued; ++j)
            glued = glue(list.ids[i], lf, list2.ids[j], corners2).whole;
        }
        setTriangle(4 * list.ids[i] + lf, !glued);
      }
  }
}

void TetCutter::refreshEdgeRepresentatives(const std::vector<int>& elements) {
  for (int e : elements) {
    const CopyList& list = element_copies_[static_cast<std::size_t>(e)];
    for (int i = 0; i < list.count; ++i) {
      const int c = list.ids[i], mask = copies_[static_cast<std::size_t>(c)].mask;
      for (int k = 0; k < 6; ++k) {
        const int a = kTetLocalEdges[k][0], b = kTetLocalEdges[k][1];
        const auto id = static_cast<std::size_t>(element_edges_[static_cast<std::size_t>(e)][k]);
        if (edge_cut_[id] || !(mask & (1 << a)) || !(mask & (1 << b))) continue;
        const bool forward = original_.elements(a, e) == edges_[id][0];
        edge_representative_[id] =
            forward ? std::array<int, 2>{mesh_.elements(a, c), mesh_.elements(b, c)}
                    : std::array<int, 2>{mesh_.elements(b, c), mesh_.elements(a, c)};
      }
    }
  }
}

void TetCutter::publishSurface() {
  // Only the triangles written since the last publication, and the surface nodes whose triangle
  // count crossed zero (merged into the sorted list), so the cost follows the change.
  const auto num_triangles = static_cast<Eigen::Index>(triangles_.size());
  surface_.triangles.conservativeResize(3, num_triangles);
  for (int t : changed_triangles_)
    if (t < num_triangles)
      for (int k = 0; k < 3; ++k)
        surface_.triangles(k, t) = triangles_[static_cast<std::size_t>(t)][k];
  changed_triangles_.clear();
  const int n = mesh_.numNodes();
  on_surface_.resize(std::max(on_surface_.size(), node_triangles_.size()), 0);
  std::vector<int> joining;
  bool leaving = false;
  for (int v : surface_changed_nodes_) {
    const bool now = node_triangles_[static_cast<std::size_t>(v)] > 0;
    char& was = on_surface_[static_cast<std::size_t>(v)];
    if (now == static_cast<bool>(was)) continue;
    was = now ? 1 : 0;
    if (now)
      joining.push_back(v);
    else
      leaving = true;
  }
  surface_changed_nodes_.clear();
  if (leaving)
    surface_.nodes.erase(
        std::remove_if(surface_.nodes.begin(), surface_.nodes.end(),
                       [this](int v) { return !on_surface_[static_cast<std::size_t>(v)]; }),
        surface_.nodes.end());
  if (!joining.empty()) {
    std::sort(joining.begin(), joining.end());
    const auto middle = static_cast<std::ptrdiff_t>(surface_.nodes.size());
    surface_.nodes.insert(surface_.nodes.end(), joining.begin(), joining.end());
    std::inplace_merge(surface_.nodes.begin(), surface_.nodes.begin() + middle,
                       surface_.nodes.end());
  }
  node_triangles_.resize(static_cast<std::size_t>(n), 0);
  on_surface_.resize(static_cast<std::size_t>(n), 0);
  cut_faces_ = triangle_cut_;
  derived_valid_ = false;
}

bool TetCutter::updateIncrementally(const std::vector<int>& new_cut_edges) {
  ++stamp_;
  old_num_nodes_ = mesh_.numNodes();
  parent_node_.resize(static_cast<std::size_t>(old_num_nodes_));
  std::iota(parent_node_.begin(), parent_node_.end(), 0);
  // 1. New fragments of the elements at the new cut edges; a fragment reuses the copy it comes
  // from (the first fragment of it) or is appended.
  std::vector<int> changed;
  std::vector<std::array<int, 2>> appended;  // (new copy, copy whose nodes it starts from)
  for (int id : new_cut_edges)
    for (int p = edge_offsets_[id]; p < edge_offsets_[id + 1]; ++p) {
      const int e = edge_elements_[static_cast<std::size_t>(p)];
      if (!firstVisit(element_stamp_, e) || removed_[static_cast<std::size_t>(e)]) continue;
      std::array<int, 4> masks{};
      const int count = partition(e, masks);
      Eigen::Matrix<double, 3, 4> X;
      for (int i = 0; i < 4; ++i) X.col(i) = original_.nodes.col(original_.elements(i, e));
      const std::array<double, 4> f =
          fragmentVolumeFractions(X, localCutParameters(e), masks, count);
      CopyList& list = element_copies_[static_cast<std::size_t>(e)];
      bool same = count == list.count;
      for (int k = 0; k < count && same; ++k) {
        const Copy& c = copies_[static_cast<std::size_t>(list.ids[k])];
        same = c.mask == masks[k] && c.fraction == f[k];
      }
      if (same) continue;
      changed.push_back(e);
      changed_stamp_[static_cast<std::size_t>(e)] = stamp_;
      const CopyList old = list;
      std::array<bool, 4> reused{};
      list.count = 0;
      for (int k = 0; k < count; ++k) {
        int j = 0;
        while (j < old.count &&
               (copies_[static_cast<std::size_t>(old.ids[j])].mask & masks[k]) != masks[k])
          ++j;
        int c = old.ids[j];
        if (reused[j]) {
          c = static_cast<int>(copies_.size());
          copies_.push_back({});
          appended.push_back({c, old.ids[j]});
        }
        reused[j] = true;
        list.ids[k] = c;
        ++list.count;
      }
      for (int k = 0; k < count; ++k)
        copies_[static_cast<std::size_t>(list.ids[k])] = {e, masks[k], f[k]};
    }
  if (changed.empty()) return false;
  const int num_copies = static_cast<int>(copies_.size());
  mesh_.elements.conservativeResize(4, num_copies);
  for (const auto& [c, from] : appended) mesh_.elements.col(c) = mesh_.elements.col(from);
  copy_slot_.resize(static_cast<std::size_t>(num_copies));

  // 2. Node classes around every corner of the changed elements (all computed before any is
  // applied), then the nodes that vanished are closed up by moving the last node into them.
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

  // 3. Everything derived from the nodes, around them.
  const int n = static_cast<int>(node_origin_.size());
  mesh_.nodes.conservativeResize(3, n);
  for (int v = 0; v < n; ++v)  // new nodes and nodes moved into a vanished one
    if (v >= old_num_nodes_ || parent_node_[static_cast<std::size_t>(v)] != v)
      mesh_.nodes.col(v) = original_.nodes.col(node_origin_[v]);
  lumped_mass_.conservativeResize(3 * n);
  recomputeMasses(origins);
  element_origin_.resize(static_cast<std::size_t>(num_copies));
  element_fraction_.resize(static_cast<std::size_t>(num_copies));
  for (int e : changed) {
    const CopyList& list = element_copies_[static_cast<std::size_t>(e)];
    for (int k = 0; k < list.count; ++k) {
      element_origin_[static_cast<std::size_t>(list.ids[k])] = e;
      element_fraction_[static_cast<std::size_t>(list.ids[k])] =
          copies_[static_cast<std::size_t>(list.ids[k])].fraction;
    }
  }
  ++stamp_;
  std::vector<int> around;  // elements around the changed corners (their nodes may have changed)
  for (int v : origins)
    for (const int* p = starBegin(v); p != starEnd(v); ++p)
      if (firstVisit(element_stamp_, *p)) around.push_back(*p);
  face_triangle_.resize(static_cast<std::size_t>(4 * num_copies), -1);
  refreshFaces(around);
  refreshEdgeRepresentatives(around);
  publishSurface();
  return true;
}

void TetCutter::derive() const {
  if (derived_valid_) return;
  const int n = mesh_.numNodes(), num_copies = mesh_.numElements();
  UnionFind pieces(n);
  for (int c = 0; c < num_copies; ++c)
    for (int i = 1; i < 4; ++i) pieces.unite(mesh_.elements(0, c), mesh_.elements(i, c));
  node_component_.assign(static_cast<std::size_t>(n), -1);
  std::vector<int> label(static_cast<std::size_t>(n), -1);
  num_components_ = 0;
  for (int v = 0; v < n; ++v) {
    int& l = label[static_cast<std::size_t>(pieces.find(v))];
    if (l < 0) l = num_components_++;
    node_component_[static_cast<std::size_t>(v)] = l;
  }

  // Embedded cut surface of every split copy: the crossing points on the edges from its real
  // corners to the others (a triangle for 1 or 3 real corners, a quad for 2).
  cut_triangles_.clear();
  for (int c = 0; c < num_copies; ++c) {
    const Copy& copy = copies_[static_cast<std::size_t>(c)];
    if (copy.mask == 0xF) continue;
    const std::array<double, 6> s = localCutParameters(copy.element);
    auto point = [&](int real, int other) {
      const double s_lo = s[static_cast<std::size_t>(tetLocalEdge(real, other))];
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
      const EmbeddedCutPoint q[4] = {point(in[0], out[0]), point(in[1], out[0]),
                                     point(in[1], out[1]), point(in[0], out[1])};
      tris.push_back({q[0], q[1], q[2]});
      tris.push_back({q[0], q[2], q[3]});
    }
    Eigen::Vector3d real_centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < ni; ++k) real_centroid += mesh_.nodes.col(mesh_.elements(in[k], c)) / ni;
    for (auto& tri : tris) {
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = (1.0 - tri[k].w) * mesh_.nodes.col(tri[k].node_a) +
               tri[k].w * mesh_.nodes.col(tri[k].node_b);
      if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[0] - real_centroid) < 0.0)
        std::swap(tri[1], tri[2]);
      cut_triangles_.push_back(tri);
    }
  }
  derived_valid_ = true;
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

CutUpdate TetCutter::cut(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                         const Eigen::VectorXd& x_end) {
  validateBladeSweep(sweep);
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(mesh_.numNodes());
  if (x_start.size() != size || x_end.size() != size)
    throw std::invalid_argument(
        "TetCutter::cut: positions have sizes " + std::to_string(x_start.size()) + " and " +
        std::to_string(x_end.size()) + ", expected 3 n = " + std::to_string(size));
  CutUpdate update;
  std::vector<int> new_cut_edges;
  Stopwatch detect;
  const Eigen::Vector3d blade_lo =
      sweep.start.rowwise().minCoeff().cwiseMin(sweep.end.rowwise().minCoeff()).array() -
      tolerance_;
  const Eigen::Vector3d blade_hi =
      sweep.start.rowwise().maxCoeff().cwiseMax(sweep.end.rowwise().maxCoeff()).array() +
      tolerance_;
  // Swept-box rejection with outcodes: bit 2d (2d + 1) when a node stays below (above) the
  // blade's box along axis d; an edge's swept box misses the blade's iff its nodes share a bit.
  outcode_.resize(static_cast<std::size_t>(mesh_.numNodes()));
  for (int v = 0; v < mesh_.numNodes(); ++v) {
    const Eigen::Vector3d p0 = nodeAt(x_start, v), p1 = nodeAt(x_end, v);
    std::uint8_t code = 0;
    for (int d = 0; d < 3; ++d) {
      if (p0[d] < blade_lo[d] && p1[d] < blade_lo[d]) code |= 1 << (2 * d);
      if (p0[d] > blade_hi[d] && p1[d] > blade_hi[d]) code |= 1 << (2 * d + 1);
    }
    outcode_[static_cast<std::size_t>(v)] = code;
  }
  for (std::size_t id = 0; id < edges_.size(); ++id) {
    const auto [a, b] = edge_representative_[id];
    if (edge_cut_[id] || a < 0 ||
        (outcode_[static_cast<std::size_t>(a)] & outcode_[static_cast<std::size_t>(b)]))
      continue;
    const Eigen::Vector3d a0 = nodeAt(x_start, a), b0 = nodeAt(x_start, b);
    const Eigen::Vector3d a1 = nodeAt(x_end, a), b1 = nodeAt(x_end, b);
    double best_t = 2.0;
    for (Eigen::Index k = 0; k + 1 < sweep.start.cols(); ++k) {
      const auto hit =
          edgeSweepCrossing(sweep.start.col(k), sweep.start.col(k + 1), sweep.end.col(k),
                            sweep.end.col(k + 1), a0, b0, a1, b1, tolerance_);
      if (hit && hit->t < best_t) {
        best_t = hit->t;
        edge_s_[id] = hit->s;
      }
    }
    if (best_t <= 1.0) {
      edge_cut_[id] = 1;
      new_cut_edges.push_back(static_cast<int>(id));
    }
  }
  update.edges_cut = static_cast<int>(new_cut_edges.size());
  num_cut_edges_ += update.edges_cut;
  update.detect_seconds = detect.seconds();
  if (update.edges_cut == 0) return update;
  Stopwatch update_watch;
  if (mode_ == CutUpdateMode::Incremental) {
    update.topology_changed = updateIncrementally(new_cut_edges);
  } else {
    const Eigen::MatrixXi before = mesh_.elements;
    const Eigen::VectorXd mass_before = lumped_mass_;
    rebuild();
    update.topology_changed = before.cols() != mesh_.elements.cols() || before != mesh_.elements ||
                              mass_before != lumped_mass_;
  }
  update.update_seconds = update_watch.seconds();
  return update;
}

CutUpdate TetCutter::removeElements(const std::vector<int>& elements) {
  CutUpdate update;
  for (int c : elements) {
    if (c < 0 || c >= mesh_.numElements())
      throw std::invalid_argument("TetCutter::removeElements: element " + std::to_string(c) +
                                  " is out of range [0, " + std::to_string(mesh_.numElements()) +
                                  ")");
    removed_[static_cast<std::size_t>(element_origin_[static_cast<std::size_t>(c)])] = 1;
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
  Eigen::VectorXd out(3 * static_cast<Eigen::Index>(parent_node_.size()));
  for (std::size_t v = 0; v < parent_node_.size(); ++v)
    out.segment<3>(3 * static_cast<Eigen::Index>(v)) = old_values.segment<3>(3 * parent_node_[v]);
  return out;
}

}  // namespace surgical_sim::core
