#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::core {

/// Topology (visibility) graph of an EfgModel: graph nodes 0 .. n-1 are the particles, n .. n+m-1
/// the integration points (IPs). Links join each particle to its grid neighbours along each axis
/// (6-neighbour on the DOF grid of side 2 d) and each IP to the particles of its initial
/// neighbourhood (EfgGrid::neighbours). Every link has its rest length [m] and is alive until
/// sever() removes it (restore() undoes that for a rejected cut). Rest configuration only; the
/// graph never adds nodes or links.
class EfgTopologyGraph {
 public:
  struct Link {
    int a = 0;                 ///< graph node (a particle)
    int b = 0;                 ///< graph node (a particle, or an IP for an IP-particle link)
    double rest_length = 0.0;  ///< [m]
  };

  /// Builds the graph of `model`'s particles and initial neighbourhoods. Allocates; time linear
  /// in the particles and IP neighbours.
  explicit EfgTopologyGraph(const EfgModel& model);

  int numParticles() const { return n_; }
  int numIntegrationPoints() const { return m_; }
  int numNodes() const { return n_ + m_; }
  /// Graph node of IP e.
  int ipNode(int e) const { return n_ + e; }
  const std::vector<Link>& links() const { return links_; }
  /// Links touching graph node v (alive or not).
  const std::vector<int>& linksOf(int v) const { return incident_[static_cast<size_t>(v)]; }
  int otherEnd(int link, int v) const {
    const Link& l = links_[static_cast<size_t>(link)];
    return l.a == v ? l.b : l.a;
  }
  bool alive(int link) const { return alive_[static_cast<size_t>(link)] != 0; }
  /// Removes `link` (no effect if already severed).
  void sever(int link) { alive_[static_cast<size_t>(link)] = 0; }
  /// Makes a severed `link` alive again (undoes sever() when a cut is rejected).
  void restore(int link) { alive_[static_cast<size_t>(link)] = 1; }
  int numSevered() const;

  /// Dijkstra search from graph node `source` over alive links weighted by their rest lengths:
  /// calls visit(node, distance [m], link) for every reached node in order of increasing distance
  /// (source first, at 0, link -1), `link` the last link of the node's shortest path (the first
  /// found among equal ones), until visit returns false. Cost grows with the nodes reached, not the
  /// graph (work arrays are reused; not for concurrent calls).
  template <class Visit>
  void searchFrom(int source, const Visit& visit) const;

  /// Connected components over alive links: labels (size numNodes(), in [0, count)) and count.
  /// Linear in the graph.
  int components(std::vector<int>& labels) const;

 private:
  int n_ = 0;
  int m_ = 0;
  std::vector<Link> links_;
  std::vector<char> alive_;
  std::vector<std::vector<int>> incident_;
  mutable std::vector<double> distance_;  ///< Dijkstra work array, +inf outside a search
  mutable std::vector<int> via_;          ///< Dijkstra work array: the link of distance_
  mutable std::vector<int> touched_;
  mutable std::vector<std::pair<double, int>> heap_;  ///< Dijkstra queue (min-heap)
};

template <class Visit>
void EfgTopologyGraph::searchFrom(int source, const Visit& visit) const {
  const std::greater<> later;  // min-heap on (distance, node)
  heap_.clear();
  distance_[static_cast<size_t>(source)] = 0.0;
  touched_.push_back(source);
  heap_.emplace_back(0.0, source);
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const auto [d, v] = heap_.back();
    heap_.pop_back();
    if (d > distance_[static_cast<size_t>(v)]) continue;
    if (!visit(v, d, v == source ? -1 : via_[static_cast<size_t>(v)])) break;
    for (const int l : linksOf(v)) {
      if (!alive(l)) continue;
      const int w = otherEnd(l, v);
      const double dw = d + links_[static_cast<size_t>(l)].rest_length;
      double& best = distance_[static_cast<size_t>(w)];
      if (dw < best) {
        if (std::isinf(best)) touched_.push_back(w);
        best = dw;
        via_[static_cast<size_t>(w)] = l;
        heap_.emplace_back(dw, w);
        std::push_heap(heap_.begin(), heap_.end(), later);
      }
    }
  }
  for (const int v : touched_)
    distance_[static_cast<size_t>(v)] = std::numeric_limits<double>::infinity();
  touched_.clear();
}

}  // namespace surgical_sim::core
