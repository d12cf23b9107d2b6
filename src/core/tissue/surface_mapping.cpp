#include "surgical_sim/core/tissue/surface_mapping.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::core {

SurfaceMapping::SurfaceMapping(int slots, std::vector<int> vertices,
                               const Eigen::SparseMatrix<double, Eigen::RowMajor>& weights)
    : nodes_(static_cast<int>(weights.cols())), vertices_(std::move(vertices)) {
  if (weights.rows() != static_cast<Eigen::Index>(vertices_.size())) {
    throw std::invalid_argument("SurfaceMapping: " + std::to_string(weights.rows()) +
                                " weight rows for " + std::to_string(vertices_.size()) +
                                " vertices");
  }
  // Row k of W goes to slot vertices_[k]; an unlisted or bad slot is named by check().
  std::vector<int> row_of(static_cast<size_t>(std::max(slots, 0)), -1);
  for (size_t k = 0; k < vertices_.size(); ++k) {
    const int v = vertices_[k];
    if (v >= 0 && v < slots && row_of[static_cast<size_t>(v)] < 0)
      row_of[static_cast<size_t>(v)] = static_cast<int>(k);
  }
  start_.assign(static_cast<size_t>(std::max(slots, 0)) + 1, 0);
  for (int s = 0; s < slots; ++s) {
    const int k = row_of[static_cast<size_t>(s)];
    if (k >= 0) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(weights, k); it; ++it) {
        columns_.push_back(static_cast<int>(it.col()));
        weights_.push_back(it.value());
      }
    }
    start_[static_cast<size_t>(s) + 1] = static_cast<int>(columns_.size());
  }
  check(slots);
}

SurfaceMapping SurfaceMapping::fromRows(int nodes, std::vector<int> vertices,
                                        std::vector<int> start, std::vector<int> columns,
                                        std::vector<double> weights) {
  SurfaceMapping mapping;
  mapping.nodes_ = nodes;
  mapping.vertices_ = std::move(vertices);
  mapping.start_ = std::move(start);
  mapping.columns_ = std::move(columns);
  mapping.weights_ = std::move(weights);
  if (mapping.start_.empty() || mapping.start_.front() != 0 ||
      mapping.start_.back() != static_cast<int>(mapping.columns_.size()) ||
      mapping.weights_.size() != mapping.columns_.size() ||
      !std::is_sorted(mapping.start_.begin(), mapping.start_.end())) {
    throw std::invalid_argument("SurfaceMapping: the row ranges do not cover the " +
                                std::to_string(mapping.columns_.size()) + " entries (" +
                                std::to_string(mapping.weights_.size()) + " weights) in order");
  }
  mapping.check(mapping.numSlots());
  return mapping;
}

void SurfaceMapping::check(int slots) const {
  std::vector<char> listed(static_cast<size_t>(std::max(slots, 0)), 0);
  for (const int v : vertices_) {
    if (v < 0 || v >= slots || listed[static_cast<size_t>(v)]) {
      throw std::invalid_argument("SurfaceMapping: vertex " + std::to_string(v) +
                                  " is repeated or outside the " + std::to_string(slots) +
                                  " slots");
    }
    listed[static_cast<size_t>(v)] = 1;
  }
  for (int s = 0; s < slots; ++s) {
    const int begin = start_[static_cast<size_t>(s)], end = start_[static_cast<size_t>(s) + 1];
    if (end > begin && !listed[static_cast<size_t>(s)])
      throw std::invalid_argument("SurfaceMapping: slot " + std::to_string(s) +
                                  " has a row but is not a vertex");
    for (int k = begin; k < end; ++k) {
      const int node = columns_[static_cast<size_t>(k)];
      if (node < 0 || node >= nodes_)
        throw std::invalid_argument("SurfaceMapping: vertex " + std::to_string(s) +
                                    " maps to node " + std::to_string(node) +
                                    ", nodes = " + std::to_string(nodes_));
      if (!std::isfinite(weights_[static_cast<size_t>(k)]))
        throw std::invalid_argument("SurfaceMapping: weight of vertex " + std::to_string(s) +
                                    " on node " + std::to_string(node) + " is not finite");
    }
  }
}

SurfaceMapping SurfaceMapping::selection(int nodes, const std::vector<int>& vertices) {
  std::vector<int> start(static_cast<size_t>(std::max(nodes, 0)) + 1, 0);
  for (const int v : vertices) {
    if (v < 0 || v >= nodes) {
      throw std::invalid_argument("SurfaceMapping: vertex " + std::to_string(v) +
                                  " is not one of the model's " + std::to_string(nodes) + " nodes");
    }
    start[static_cast<size_t>(v) + 1] = 1;  // slot v has a row (fromRows names a repeat)
  }
  std::vector<int> columns;
  for (int s = 0; s < nodes; ++s) {
    if (start[static_cast<size_t>(s) + 1]) columns.push_back(s);
    start[static_cast<size_t>(s) + 1] = static_cast<int>(columns.size());
  }
  std::vector<double> ones(columns.size(), 1.0);
  return fromRows(nodes, vertices, std::move(start), std::move(columns), std::move(ones));
}

SurfaceMapping::Row SurfaceMapping::row(int slot) const {
  const int begin = start_[static_cast<size_t>(slot)];
  return {columns_.data() + begin, weights_.data() + begin,
          start_[static_cast<size_t>(slot) + 1] - begin};
}

Eigen::Vector3d SurfaceMapping::vertexValue(int slot, const Eigen::VectorXd& x) const {
  const Row r = row(slot);
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  for (int j = 0; j < r.size; ++j) value += r.weights[j] * x.segment<3>(3 * r.nodes[j]);
  return value;
}

void SurfaceMapping::apply(const Eigen::VectorXd& x, Eigen::VectorXd& x_s) const {
  if (x_s.size() != 3 * numSlots()) x_s.resize(3 * numSlots());
  for (int s = 0; s < numSlots(); ++s) x_s.segment<3>(3 * s) = vertexValue(s, x);
}

void SurfaceMapping::addVertexForce(int slot, const Eigen::Vector3d& f_v,
                                    Eigen::VectorXd& f) const {
  const Row r = row(slot);
  for (int j = 0; j < r.size; ++j) f.segment<3>(3 * r.nodes[j]) += r.weights[j] * f_v;
}

void SurfaceMapping::addTransposed(const Eigen::VectorXd& f_s, Eigen::VectorXd& f) const {
  for (const int v : vertices_) addVertexForce(v, f_s.segment<3>(3 * v), f);
}

Eigen::SparseMatrix<double> SurfaceMapping::matrix() const {
  std::vector<Eigen::Triplet<double>> entries;
  for (int s = 0; s < numSlots(); ++s) {
    const Row r = row(s);
    for (int j = 0; j < r.size; ++j) entries.emplace_back(s, r.nodes[j], r.weights[j]);
  }
  Eigen::SparseMatrix<double> W(numSlots(), nodes_);
  W.setFromTriplets(entries.begin(), entries.end());
  return W;
}

SurfaceMapping makeSurfaceMapping(const TissueModel& model, const TetMesh& mesh,
                                  const SurfaceMesh& surface) {
  if (const auto* efg = dynamic_cast<const EfgModel*>(&model)) {
    Eigen::Matrix3Xd rest(3, static_cast<Eigen::Index>(surface.nodes.size()));
    for (size_t k = 0; k < surface.nodes.size(); ++k)
      rest.col(static_cast<Eigen::Index>(k)) = mesh.nodes.col(surface.nodes[k]);
    return SurfaceMapping(mesh.numNodes(), surface.nodes, efg->interpolation(rest));
  }
  if (model.numNodes() != mesh.numNodes()) {
    throw std::invalid_argument("makeSurfaceMapping: model " + model.name() + " has " +
                                std::to_string(model.numNodes()) + " nodes, its mesh " +
                                std::to_string(mesh.numNodes()));
  }
  return SurfaceMapping::selection(mesh.numNodes(), surface.nodes);
}

}  // namespace surgical_sim::core
