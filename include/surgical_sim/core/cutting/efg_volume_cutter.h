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
///    edgeSweepCrossing (so a static blade in moving tissue cuts). Broad phase over blocks of
///    links (those whose particle end a rests in one cube of side 2 particle spacings): with
///    D the box of the displacements x - X (start and end of the step) of the particles that
///    move the block's ends (its particle ends and its IP ends' current particles), centre c and
///    half-sides h, a particle end stays within h of X + c and an IP end e within
///    L h + u |c| + r of X_e + c, where L = max(1, ||phi_e||_1), u = |sum_a phi_a - 1| and
///    r = |sum_a phi_a X_a - X_e| (the reproduction residual), each the largest over the block's
///    IP ends. Only the blocks whose rest box of their links' ends, so moved and grown, meets the
///    box and the slab (the four corners' extent along the swept quad's normal) of one segment's
///    sweep have their alive links tested: those whose rest box, so moved and grown, and whose
///    motion box (of their ends' four positions) meet the sweep's box, against each segment whose
///    box and slab that motion meets. The bound holds however far a link stretches, so no
///    crossed link is missed; tissue at rest or translating only tests the links near the
///    blade. A block whose rest box, grown by the box of all the particles' displacements and by
///    (L - 1) H + u C + r (H: that box's half-sides, C: its largest corner magnitudes), misses the
///    sweep's box is skipped before its movers are read (static or translating tissue: all but
///    the blocks near the blade). A cut recomputes L, u, r and the moving particles of the blocks
///    holding links of its changed IPs.
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

  /// Broad-phase block: the links whose end a (a particle) lies in one cube of the particle grid.
  struct Block {
    std::vector<int> links;                             ///< ascending
    std::vector<int> particles;                         ///< the links' particle ends
    std::vector<int> ips;                               ///< the links' IP ends
    Eigen::Vector3d rest_lo = Eigen::Vector3d::Zero();  ///< box of the ends' rest positions [m]
    Eigen::Vector3d rest_hi = Eigen::Vector3d::Zero();  ///< [m]
    /// Blocks holding the particles that move an end: particles, and the IPs' current particles.
    std::vector<int> movers;
    double gain = 1.0;         ///< max(1, largest ||phi_e||_1 of the IP ends) [-]
    double unity_error = 0.0;  ///< largest |sum_a phi_a - 1| of the IP ends [-]
    double residual = 0.0;     ///< largest |sum_a phi_a X_a - X_e| (max norm) of the IP ends [m]
  };
  /// Recomputes block's movers (each once, in no particular order), gain, unity error and
  /// residual from its IPs' bounds (ip_bounds_). Linear in its ends' movers.
  void refreshBlock(Block& block);
  /// What an IP end adds to the bound of a block holding one of its links.
  struct IpBound {
    std::vector<int> movers;   ///< blocks of its current particles, ascending
    double gain = 1.0;         ///< ||phi||_1 [-]
    double unity_error = 0.0;  ///< |sum_a phi_a - 1| [-]
    double residual = 0.0;     ///< |sum_a phi_a X_a - X_e| (max norm) [m]
  };
  /// Recomputes ip_bounds_[e] from IP e's current particles and shape values.
  void refreshIpBound(int e);

  EfgModel& model_;
  EfgTopologyGraph graph_;
  std::vector<Block> blocks_;
  std::vector<IpBound> ip_bounds_;  ///< per IP
  /// Block of each particle's rest position (a link is in the block of its end a).
  std::vector<int> particle_block_;
  /// refreshBlock scratch: per block, the call that last listed it as a mover (mover_mark_).
  std::vector<int> mover_marks_;
  int mover_mark_ = 0;
  /// Broad-phase scratch: per block b, the box of its particles' displacements at the step start
  /// and end (columns 2b: lower, 2b + 1: upper corner) [m].
  Eigen::Matrix3Xd block_motion_;
  int pieces_ = 0;               ///< labels with volume IPs
  std::vector<int> labels_;      ///< piece label per graph node (graph components)
  std::vector<int> volume_ips_;  ///< per label, its IPs holding volume
  std::vector<int> tree_of_;     ///< splitPieces scratch per graph node, -1 outside a search
  int samples_ = 4;              ///< volume samples per axis of the mid-cell redistribution
  /// Remaining volume samples (samples_^3) of the cells a cut has crossed, per IP (empty if none).
  std::vector<std::vector<char>> sample_masks_;
  std::vector<char> has_indirect_;  ///< per IP: uses a particle it has no alive link to
  /// Per IP: the links of the shortest paths its last selection settled its nodes by (empty:
  /// never selected, or isolated).
  std::vector<std::vector<int>> search_links_;
  /// Per link: the IPs whose search_links_ hold it.
  std::vector<std::vector<int>> searchers_;
  /// Per IP: a link of its search_links_ was severed since that search.
  std::vector<char> search_dirty_;
  /// Narrow-phase scratch: per IP, the cut() call that last computed its positions at the step
  /// start and end (ip_x_ columns 2e and 2e + 1) [-], [m].
  std::vector<long long> ip_x_call_;
  Eigen::Matrix3Xd ip_x_;
  long long calls_ = 0;
};

}  // namespace surgical_sim::core
