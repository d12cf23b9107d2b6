#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/cutting/efg_topology_graph.h"
#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::core {

/// What one EfgVolumeCutter::cut changed.
struct EfgCutResult {
  std::vector<int> severed_links;  ///< links of graph() severed by this cut
  /// IPs whose particles, kernel distances or volume changed (ascending).
  std::vector<int> changed_ips;
  /// IPs that can no longer see 4 non-coplanar particles (a slice thinner than the particle
  /// spacing): their volume went to the nearest IP on their side, they keep volume 0 (ascending).
  std::vector<int> isolated_ips;
  /// Particles that no IP with volume uses any more since this cut, including those only an IP
  /// isolated by this cut used (zero mass and stiffness: the caller constrains them, e.g. to
  /// follow their old neighbours, or the system is singular). Ascending.
  std::vector<int> unused_particles;
  int pieces = 0;               ///< connected pieces holding volume after the cut
  bool pieces_changed = false;  ///< pieces differs from before the cut
  double detect_seconds = 0.0;  ///< crossing detection (broad and narrow phase), wall clock [s]
};

/// Progressive volume cutting of an EfgModel (Magnoux): the blade's swept surface severs the links
/// of the topology graph it crosses, and the IPs that lost a link re-select their particles by
/// graph distance. No DOF is added; every edit is in the rest configuration.
///
/// One cut(sweep, x_start, x_end):
/// 1. Crossing: each alive link, with both ends moving linearly from x_start to x_end (an IP at
///    sum_a phi_a x_a of its current particles), is tested against every blade segment with
///    edgeSweepCrossing (so a static blade in moving tissue cuts). Broad phase: only the links of
///    particles whose motion box meets the sweep's box and whose motion meets the slab of one
///    segment's sweep (its four corners' extent along the swept quad's normal), both grown by
///    3 x the link's rest length, and whose own motion box (of its ends' four positions) meets
///    the sweep's box, are tested against each segment whose box and slab that motion meets (a
///    link stretched to more than 3 x its rest length can be missed).
/// 2. Re-selection, for each IP with a severed link and each IP with indirect particles near a
///    severed link: a Dijkstra search from the IP over the alive links (rest lengths) lists the
///    visible particles by graph distance r. They are taken in that order, skipping one that would
///    leave too few free places to make the set non-coplanar, up to options().neighbours; then,
///    while the MLS moment matrix (kernel w(r / h), h = kernel_support x max r) has a condition
///    number above 1e8 or is singular, the next visible particle is added, up to
///    EfgOptions::kMaxNeighbours. Kernel distance = graph distance (>= Euclidean); its gradient
///    uses the Euclidean direction (computeMlsShapeFunctions with detours).
/// 3. Mid-cell volume: when a cut crosses IP e's own cell, the plane through the rest crossing
///    points of e's severed links (or, with fewer than 3 non-collinear points, normal to their mean
///    direction) splits the cell's volume samples; the share beyond the plane (the cell's volume
///    taken as uniform over its remaining samples) moves to the nearest IP of a neighbouring cell
///    on that side. An isolated IP (no acceptable set within kMaxNeighbours visible particles)
///    hands all its volume to the nearest IP it still reaches in the graph (else the nearest
///    neighbouring-cell IP) and keeps its old particles with volume 0. Volume moves between IPs
///    only, so the total mass is conserved.
/// 4. EfgModel::setNeighbourhoods for the changed IPs (the model's stiffness pattern is rebuilt).
/// 5. Pieces: a cut can only split the pieces holding a severed link. A breadth-first search from
///    each end of the severed links over alive links, the searches merging where they meet, stops
///    once at most one unmerged search per old piece still grows; each search that ran out of
///    nodes is a new piece. Cost: the nodes reached, at most about twice the smaller side of a
///    split (a cut that splits nothing stops where its ends' searches meet around the cut).
/// A cut that severs nothing changes nothing.
class EfgVolumeCutter {
 public:
  /// Keeps a reference to `model`, which must outlive the cutter and be changed only through it.
  explicit EfgVolumeCutter(EfgModel& model);

  /// @param sweep blade motion over the step, tissue rest frame [m] (validateBladeSweep).
  /// @param x_start, x_end particle positions at the step start and end [m], size 3n each.
  /// @throws std::invalid_argument naming "blade_sweep.*", "x_start" or "x_end" (size or
  ///         non-finite), or from EfgModel::setNeighbourhoods when a changed IP cannot be
  ///         applied (the cut is rejected); the model and the cutter are unchanged then.
  EfgCutResult cut(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                   const Eigen::VectorXd& x_end);

  const EfgTopologyGraph& graph() const { return graph_; }
  const EfgModel& model() const { return model_; }
  /// Connected pieces holding volume (see EfgCutResult::pieces).
  int pieces() const { return pieces_; }
  /// Particles with zero lumped mass (no IP with volume uses them: material left on the other
  /// side of a cut), ascending; the caller constrains them. Linear in the particles.
  std::vector<int> unusedParticles() const;
  /// The IPs holding volume that a cut has re-selected and whose particles or kernel distances
  /// differ from a new selection on the current graph, ascending (empty: every re-selection is
  /// current). One graph search per such IP: a check for tests and campaigns.
  std::vector<int> staleNeighbourhoods() const;
  /// Piece label of each particle (graph component), size n; particles of one piece share it.
  std::vector<int> particlePieces() const;

 private:
  struct Selection;
  /// Particles (by graph distance) for IP e, or an empty selection if e is isolated.
  Selection select(int e) const;
  /// Whether IP e's particles and kernel distances are those of `selection` (to round-off).
  bool holds(int e, const Selection& selection) const;
  /// Moves IP e's count of pieces_ (change +1: e holds volume, -1: it no longer does).
  void addVolumeIp(int e, int change);
  /// Relabels the pieces the severed links split (searches from their ends, see cut()).
  void splitPieces(const std::vector<int>& severed);
  /// Cell (i, j, k) of IP e.
  Eigen::Vector3i cellOf(int e) const;
  /// IP of cell c, or -1 (dropped or outside the grid).
  int ipAt(const Eigen::Vector3i& c) const;

  EfgModel& model_;
  EfgTopologyGraph graph_;
  double max_link_length_ = 0.0;  ///< [m]
  int pieces_ = 0;                ///< labels with volume IPs
  std::vector<int> labels_;       ///< piece label per graph node (graph components)
  std::vector<int> volume_ips_;   ///< per label, its IPs holding volume
  std::vector<int> tree_of_;      ///< splitPieces scratch per graph node, -1 outside a search
  int samples_ = 4;               ///< volume samples per axis of the mid-cell redistribution
  /// Remaining volume samples (samples_^3) of the cells a cut has crossed, per IP (empty if none).
  std::vector<std::vector<char>> sample_masks_;
  std::vector<char> has_indirect_;  ///< per IP: uses a particle it has no alive link to
  /// Per IP: the graph nodes its last selection settled (empty: never selected, or isolated).
  std::vector<std::vector<int>> search_nodes_;
  /// Per graph node: the IPs whose search_nodes_ hold it.
  std::vector<std::vector<int>> searchers_;
  /// Per IP: a link at a node of its search_nodes_ was severed since that search.
  std::vector<char> search_dirty_;
  /// Narrow-phase scratch: per IP, the cut() call that last computed its positions at the step
  /// start and end (ip_x_ columns 2e and 2e + 1) [-], [m].
  std::vector<char> link_mark_;  ///< broad-phase scratch per link, all 0 between calls
  std::vector<long long> ip_x_call_;
  Eigen::Matrix3Xd ip_x_;
  long long calls_ = 0;
};

}  // namespace surgical_sim::core
