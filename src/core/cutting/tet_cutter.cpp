#include "surgical_sim/core/cutting/tet_cutter.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
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

TetCutter::TetCutter(const TetMesh& rest_mesh, double density)
    : original_(rest_mesh), density_(density) {
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
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i][0] != keyed[i - 1][0] || keyed[i][1] != keyed[i - 1][1]) {
      edges_.push_back({keyed[i][0], keyed[i][1]});
    }
    const int id = static_cast<int>(edges_.size()) - 1;
    element_edges_[static_cast<std::size_t>(keyed[i][2] / 6)][keyed[i][2] % 6] = id;
  }

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

  element_volume_.resize(static_cast<std::size_t>(m));
  for (int e = 0; e < m; ++e)
    element_volume_[static_cast<std::size_t>(e)] = signedVolume(rest_mesh, e);
  edge_cut_.assign(edges_.size(), 0);
  edge_s_.assign(edges_.size(), 0.0);
  removed_.assign(static_cast<std::size_t>(m), 0);
  rebuild();
}

int TetCutter::partition(int element, const std::vector<std::uint8_t>& cut,
                         std::array<int, 4>& masks) const {
  std::array<int, 4> comp{0, 1, 2, 3};
  for (int k = 0; k < 6; ++k) {
    if (cut[static_cast<std::size_t>(element_edges_[static_cast<std::size_t>(element)][k])])
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

void TetCutter::rebuild() {
  const int m = original_.numElements();
  // 2. One copy per fragment of every remaining element.
  const std::vector<Copy> old_copies = copies_;
  const std::vector<int> old_offsets = copy_offsets_;
  const Eigen::MatrixXi old_elements = mesh_.elements;
  old_num_nodes_ = mesh_.numNodes();
  copies_.clear();
  copy_offsets_.assign(static_cast<std::size_t>(m + 1), 0);
  for (int e = 0; e < m; ++e) {
    copy_offsets_[static_cast<std::size_t>(e)] = static_cast<int>(copies_.size());
    if (removed_[static_cast<std::size_t>(e)]) continue;
    std::array<int, 4> masks{};
    const int count = partition(e, edge_cut_, masks);
    Eigen::Matrix<double, 3, 4> X;
    for (int i = 0; i < 4; ++i) X.col(i) = original_.nodes.col(original_.elements(i, e));
    const std::array<double, 4> f = fragmentVolumeFractions(X, localCutParameters(e), masks, count);
    for (int k = 0; k < count; ++k) copies_.push_back({e, masks[k], f[k]});
  }
  copy_offsets_[static_cast<std::size_t>(m)] = static_cast<int>(copies_.size());
  const int num_copies = static_cast<int>(copies_.size());

  // 3. Glue copies across shared faces: all three corners when they hold the same real nodes on
  // the face (the material continues across it, virtual nodes included), otherwise only the
  // real nodes both hold (at a cut front, material on both sides still meets at these nodes).
  UnionFind slots(4 * num_copies);
  std::vector<char> face_glued(static_cast<std::size_t>(4 * num_copies), 0);  // (copy, local face)
  for (int e = 0; e < m; ++e)
    for (int lf = 0; lf < 4; ++lf) {
      const auto [e2, lf2] = face_neighbour_[static_cast<std::size_t>(4 * e + lf)];
      if (e2 < e) continue;  // each interior face once (and skips the boundary, e2 = -1)
      const std::array<int, 3> corners = tetFaceCorners(lf);
      std::array<int, 3> corners2{};
      for (int k = 0; k < 3; ++k)
        corners2[k] = localCornerOf(original_, e2, original_.elements(corners[k], e));
      for (int c = copy_offsets_[e]; c < copy_offsets_[e + 1]; ++c)
        for (int c2 = copy_offsets_[e2]; c2 < copy_offsets_[e2 + 1]; ++c2) {
          bool same = true, any = false;
          for (int k = 0; k < 3; ++k) {
            const bool r1 = copies_[c].mask & (1 << corners[k]);
            const bool r2 = copies_[c2].mask & (1 << corners2[k]);
            same = same && r1 == r2;
            any = any || r1;
          }
          if (same && any)
            face_glued[static_cast<std::size_t>(4 * c + lf)] =
                face_glued[static_cast<std::size_t>(4 * c2 + lf2)] = 1;
          for (int k = 0; k < 3; ++k) {
            const bool shared =
                (copies_[c].mask & (1 << corners[k])) && (copies_[c2].mask & (1 << corners2[k]));
            if ((same && any) || shared) slots.unite(4 * c + corners[k], 4 * c2 + corners2[k]);
          }
        }
    }

  // 4. Nodes are the classes of slots. The first class of each original node (in copy order) keeps
  // the original index, the others are numbered after them; indices of original nodes that lost
  // all their elements are closed up, keeping the order (an uncut mesh keeps its numbering).
  // Parents come from the old copy containing the fragment.
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
  parent_node_.assign(node_origin_.size(), -1);
  mesh_.type = ElementType::Tet4;
  mesh_.elements.resize(4, num_copies);
  element_origin_.resize(static_cast<std::size_t>(num_copies));
  element_fraction_.resize(static_cast<std::size_t>(num_copies));
  for (int c = 0; c < num_copies; ++c) {
    const Copy& copy = copies_[static_cast<std::size_t>(c)];
    int parent_copy = -1;
    if (!old_copies.empty()) {
      for (int o = old_offsets[copy.element]; o < old_offsets[copy.element + 1]; ++o) {
        const int om = old_copies[static_cast<std::size_t>(o)].mask;
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
  const int n = static_cast<int>(node_origin_.size());
  mesh_.nodes.resize(3, n);
  for (int v = 0; v < n; ++v) mesh_.nodes.col(v) = original_.nodes.col(node_origin_[v]);

  // 5. Masses: rho V_e f_c per copy, a quarter on each corner; removed elements' mass goes to a
  // remaining node of each corner.
  lumped_mass_.setZero(3 * n);
  std::vector<int> node_of_origin(static_cast<std::size_t>(original_.numNodes()), -1);
  for (int v = n - 1; v >= 0; --v) node_of_origin[static_cast<std::size_t>(node_origin_[v])] = v;
  removed_mass_ = 0.0;
  for (int c = 0; c < num_copies; ++c) {
    const Copy& copy = copies_[static_cast<std::size_t>(c)];
    const double quarter = 0.25 * density_ * element_volume_[copy.element] * copy.fraction;
    for (int i = 0; i < 4; ++i)
      lumped_mass_.segment<3>(3 * mesh_.elements(i, c)).array() += quarter;
  }
  for (int e = 0; e < m; ++e) {
    if (!removed_[static_cast<std::size_t>(e)]) continue;
    const double quarter = 0.25 * density_ * element_volume_[static_cast<std::size_t>(e)];
    for (int i = 0; i < 4; ++i) {
      const int v = node_of_origin[static_cast<std::size_t>(original_.elements(i, e))];
      if (v >= 0)
        lumped_mass_.segment<3>(3 * v).array() += quarter;
      else
        removed_mass_ += quarter;
    }
  }

  // 6. Surface: every face of a copy not glued to a neighbour, outward (as extractSurface());
  // a cut face if the original element had a neighbour there. Then connected components.
  int num_surface = 0;
  for (char glued : face_glued) num_surface += glued ? 0 : 1;
  surface_.triangles.resize(3, num_surface);
  std::vector<char> on_surface(static_cast<std::size_t>(n), 0);
  cut_faces_.assign(static_cast<std::size_t>(num_surface), false);
  for (int c = 0, t = 0; c < num_copies; ++c)
    for (int lf = 0; lf < 4; ++lf) {
      if (face_glued[static_cast<std::size_t>(4 * c + lf)]) continue;
      const std::array<int, 3> corners = tetFaceCorners(lf);
      for (int k = 0; k < 3; ++k) {
        surface_.triangles(k, t) = mesh_.elements(corners[k], c);
        on_surface[static_cast<std::size_t>(surface_.triangles(k, t))] = 1;
      }
      const int e = copies_[static_cast<std::size_t>(c)].element;
      cut_faces_[static_cast<std::size_t>(t)] =
          face_neighbour_[static_cast<std::size_t>(4 * e + lf)][0] >= 0;
      ++t;
    }
  surface_.nodes.clear();
  for (int v = 0; v < n; ++v)
    if (on_surface[static_cast<std::size_t>(v)]) surface_.nodes.push_back(v);
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

  // 7. Current nodes of each uncut edge (from a copy holding both ends as real nodes).
  edge_representative_.assign(edges_.size(), {-1, -1});
  for (int c = 0; c < num_copies; ++c) {
    const Copy& copy = copies_[static_cast<std::size_t>(c)];
    for (int k = 0; k < 6; ++k) {
      const int i = kTetLocalEdges[k][0], j = kTetLocalEdges[k][1];
      const auto id = static_cast<std::size_t>(element_edges_[copy.element][k]);
      if (edge_cut_[id] || !(copy.mask & (1 << i)) || !(copy.mask & (1 << j))) continue;
      const bool forward = original_.elements(i, copy.element) == edges_[id][0];
      edge_representative_[id] =
          forward ? std::array<int, 2>{mesh_.elements(i, c), mesh_.elements(j, c)}
                  : std::array<int, 2>{mesh_.elements(j, c), mesh_.elements(i, c)};
    }
  }

  // 8. Embedded cut surface of every split copy: the crossing points on the edges from its real
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
  Stopwatch detect;
  const Eigen::Vector3d blade_lo =
      sweep.start.rowwise().minCoeff().cwiseMin(sweep.end.rowwise().minCoeff()).array() -
      tolerance_;
  const Eigen::Vector3d blade_hi =
      sweep.start.rowwise().maxCoeff().cwiseMax(sweep.end.rowwise().maxCoeff()).array() +
      tolerance_;
  for (std::size_t id = 0; id < edges_.size(); ++id) {
    const auto [a, b] = edge_representative_[id];
    if (edge_cut_[id] || a < 0) continue;
    const Eigen::Vector3d a0 = nodeAt(x_start, a), b0 = nodeAt(x_start, b);
    const Eigen::Vector3d a1 = nodeAt(x_end, a), b1 = nodeAt(x_end, b);
    const Eigen::Vector3d lo = a0.cwiseMin(b0).cwiseMin(a1).cwiseMin(b1);
    const Eigen::Vector3d hi = a0.cwiseMax(b0).cwiseMax(a1).cwiseMax(b1);
    if ((lo.array() > blade_hi.array()).any() || (hi.array() < blade_lo.array()).any()) continue;
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
      ++update.edges_cut;
    }
  }
  num_cut_edges_ += update.edges_cut;
  update.detect_seconds = detect.seconds();
  if (update.edges_cut == 0) return update;
  Stopwatch rebuild_watch;
  const Eigen::MatrixXi before = mesh_.elements;
  rebuild();
  update.topology_changed = before.cols() != mesh_.elements.cols() || before != mesh_.elements;
  update.update_seconds = rebuild_watch.seconds();
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
