#include "surgical_sim/core/cutting/efg_topology_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

namespace surgical_sim::core {

EfgTopologyGraph::EfgTopologyGraph(const EfgModel& model)
    : n_(model.numNodes()), m_(model.numIntegrationPoints()) {
  const EfgGrid& grid = model.grid();
  const double cell = 2.0 * grid.spacing;  // DOF grid side [m]
  // Particles by DOF grid index.
  const auto key = [](const Eigen::Vector3i& i) {
    return (static_cast<long long>(i.x()) << 42) ^ (static_cast<long long>(i.y()) << 21) ^
           static_cast<long long>(i.z());
  };
  std::unordered_map<long long, int> by_index;
  std::vector<Eigen::Vector3i> index(static_cast<size_t>(n_));
  for (int p = 0; p < n_; ++p) {
    index[static_cast<size_t>(p)] =
        ((grid.particles.col(p) - grid.origin) / cell).array().round().cast<int>();
    by_index.emplace(key(index[static_cast<size_t>(p)]), p);
  }
  const auto add = [&](int a, int b) {
    const Eigen::Vector3d pa = grid.particles.col(a);
    const Eigen::Vector3d pb =
        b < n_ ? Eigen::Vector3d(grid.particles.col(b)) : grid.integration_points.col(b - n_);
    links_.push_back({a, b, (pa - pb).norm()});
  };
  for (int p = 0; p < n_; ++p) {
    for (int axis = 0; axis < 3; ++axis) {
      const auto it =
          by_index.find(key(index[static_cast<size_t>(p)] + Eigen::Vector3i::Unit(axis)));
      if (it != by_index.end()) add(p, it->second);
    }
  }
  for (int e = 0; e < m_; ++e)
    for (Eigen::Index a = 0; a < grid.neighbours.rows(); ++a) add(grid.neighbours(a, e), ipNode(e));
  alive_.assign(links_.size(), 1);
  incident_.resize(static_cast<size_t>(numNodes()));
  for (size_t l = 0; l < links_.size(); ++l) {
    incident_[static_cast<size_t>(links_[l].a)].push_back(static_cast<int>(l));
    incident_[static_cast<size_t>(links_[l].b)].push_back(static_cast<int>(l));
  }
  distance_.assign(static_cast<size_t>(numNodes()), std::numeric_limits<double>::infinity());
  via_.assign(static_cast<size_t>(numNodes()), -1);
}

int EfgTopologyGraph::numSevered() const {
  return static_cast<int>(std::count(alive_.begin(), alive_.end(), 0));
}

int EfgTopologyGraph::components(std::vector<int>& labels) const {
  labels.assign(static_cast<size_t>(numNodes()), -1);
  int count = 0;
  std::vector<int> stack;
  for (int s = 0; s < numNodes(); ++s) {
    if (labels[static_cast<size_t>(s)] >= 0) continue;
    labels[static_cast<size_t>(s)] = count;
    stack.push_back(s);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (const int l : linksOf(v)) {
        const int w = otherEnd(l, v);
        if (alive(l) && labels[static_cast<size_t>(w)] < 0) {
          labels[static_cast<size_t>(w)] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return count;
}

}  // namespace surgical_sim::core
