#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace surgical_sim::core {

/// What surface cutting needs from a meshless (EFG) model, all in the rest configuration unless
/// stated: its integration points (IPs), each IP's particle set and the MLS weights of that set
/// at a point. Implementations must be consistent between calls while a cutter uses them (a
/// volume cut changes ipParticles(); the cutter is then told which IPs changed).
class EfgMappingSource {
 public:
  virtual ~EfgMappingSource() = default;
  /// Number of IPs, fixed for the source's lifetime.
  virtual int numIntegrationPoints() const = 0;
  /// Number of particles (model nodes), fixed for the source's lifetime.
  virtual int numParticles() const = 0;
  /// Rest position of particle p [m].
  virtual Eigen::Vector3d particleRestPosition(int p) const = 0;
  /// Rest position of IP `ip` [m].
  virtual Eigen::Vector3d ipRestPosition(int ip) const = 0;
  /// Current position of IP `ip` [m] (the model's state when the cutter is called).
  virtual Eigen::Vector3d ipPosition(int ip) const = 0;
  /// Position of IP `ip` for particle positions x [m] (size 3 x numParticles()): its shape
  /// values at the IP times its particles' positions (ipPosition at the current positions).
  virtual Eigen::Vector3d ipPositionAt(int ip, const Eigen::VectorXd& x) const = 0;
  /// L1 norm of IP `ip`'s shape values at the IP [-]: it moves at most this many times its
  /// particles' largest motion.
  virtual double ipWeightNorm(int ip) const = 0;
  /// Particles of IP `ip` (its neighbour set, model node indices, sorted increasing).
  virtual const std::vector<int>& ipParticles(int ip) const = 0;
  /// MLS weights [-] of IP `ip`'s particle set evaluated at rest point X [m]: particles and
  /// weights resized to the set's size.
  virtual void pointWeights(int ip, const Eigen::Vector3d& X, std::vector<int>& particles,
                            std::vector<double>& weights) const = 0;
};

class EfgModel;

/// An EfgModel and particle positions x [m] (a reference, read at each call) as a mapping source:
/// IP ip is at sum_a phi_a x_a over its current particles. Both must outlive the source.
class EfgModelSource final : public EfgMappingSource {
 public:
  EfgModelSource(const EfgModel& model, const Eigen::VectorXd& x) : model_(model), x_(x) {}
  int numIntegrationPoints() const override;
  int numParticles() const override;
  Eigen::Vector3d particleRestPosition(int p) const override;
  Eigen::Vector3d ipRestPosition(int ip) const override;
  Eigen::Vector3d ipPosition(int ip) const override;
  Eigen::Vector3d ipPositionAt(int ip, const Eigen::VectorXd& x) const override;
  double ipWeightNorm(int ip) const override;
  const std::vector<int>& ipParticles(int ip) const override;
  void pointWeights(int ip, const Eigen::Vector3d& X, std::vector<int>& particles,
                    std::vector<double>& weights) const override;

 private:
  const EfgModel& model_;
  const Eigen::VectorXd& x_;
};

/// A half-space stored on a surface vertex when a cut passes nearby (rest configuration): a
/// valid IP lies strictly below it, (X_ip - point) . normal < 0.
struct CutPlane {
  Eigen::Vector3d point;   ///< [m]
  Eigen::Vector3d normal;  ///< unit, pointing away from the vertex's own side
};

/// Criteria relaxed to find an IP (0 = none relaxed).
enum class RemapRelaxation {
  kNone = 0,           ///< shared particles, below the tangent plane, below the cut planes
  kTangent = 1,        ///< tangent plane dropped (bad normals)
  kShared = 2,         ///< shared-particle test dropped, tangent plane kept
  kTangentShared = 3,  ///< cut planes only
  kNearest = 4,        ///< nearest IP whatever the criteria
};

/// Result of SurfaceRemapper::find().
struct RemapResult {
  int ip = -1;
  RemapRelaxation relaxation = RemapRelaxation::kNone;
};

/// Nearest valid IP for a surface vertex (Magnoux's remapping criteria, rest configuration):
///   1. the IP shares at least one particle with the IP of every 1-ring vertex;
///   2. it lies below the tangent plane at the vertex, (X_ip - X) . n < 0;
///   3. it lies below every cut plane stored on the vertex.
/// Among valid IPs the nearest to X wins. When none is valid the criteria are relaxed in the
/// order of RemapRelaxation (cut planes, which keep a vertex on its own side, are dropped last),
/// first over the IPs within one grid cell (4 IPs a cell, about 1.6 IP spacings), then over
/// every IP below the cut planes. Uses a uniform grid of the IP rest positions built once
/// (O(IPs)): the second search halves boxes of cells down to cells, skipping those wholly above
/// a cut plane, and the nearest IP is found in cubes of cells growing about X.
class SurfaceRemapper {
 public:
  /// @throws std::invalid_argument when the source has no IP or an IP position is not finite.
  explicit SurfaceRemapper(const EfgMappingSource& source);

  /// @param X vertex rest position [m]. @param normal outward unit normal, or zero to skip
  /// criterion 2. @param planes the vertex's cut planes. @param ring_ips IPs of its 1-ring
  /// vertices (any order, repeats allowed).
  RemapResult find(const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
                   const std::vector<CutPlane>& planes, const std::vector<int>& ring_ips) const;
  /// find() with the first search's IPs given: `near` = nearby(X).
  RemapResult find(const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
                   const std::vector<CutPlane>& planes, const std::vector<int>& ring_ips,
                   const std::vector<int>& near) const;
  /// The IPs find() searches first for X: those within one grid cell, nearest first.
  std::vector<int> nearby(const Eigen::Vector3d& X) const;

 private:
  bool valid(int ip, const Eigen::Vector3d& X, const Eigen::Vector3d& normal,
             const std::vector<CutPlane>& planes, const std::vector<int>& ring_ips,
             int level) const;
  /// IPs within `radius` >= 0 of X, nearest first.
  std::vector<int> candidates(const Eigen::Vector3d& X, double radius) const;
  /// Grid cell of X, clamped to the grid.
  Eigen::Vector3i cellAt(const Eigen::Vector3d& X) const;
  /// Flat index of grid cell c.
  int cellIndex(const Eigen::Vector3i& c) const;
  /// Calls f(cell, ip) for every IP in the grid cells c with lo <= c <= hi, cell by cell.
  template <class F>
  void forIpsInCells(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const F& f) const;
  /// Appends (squared distance to X [m^2], IP) for the IPs below `planes` in the box of grid
  /// cells [lo, hi) (non-empty): a box wholly above a plane is skipped, a plane the box lies
  /// wholly below is dropped, and the box is halved along its longest side down to single cells
  /// while a plane is left.
  void collectBelow(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, const Eigen::Vector3d& X,
                    const std::vector<CutPlane>& planes,
                    std::vector<std::pair<double, int>>& below) const;
  /// The IP nearest to X (the lowest index among equally near ones).
  int nearest(const Eigen::Vector3d& X) const;

  const EfgMappingSource& source_;
  std::vector<Eigen::Vector3d> ip_rest_;
  Eigen::Vector3d origin_;
  Eigen::Vector3i dims_;
  double cell_ = 0.0;            ///< grid cell size [m]
  std::vector<int> cell_start_;  ///< CSR over cells
  std::vector<int> cell_ips_;
};

}  // namespace surgical_sim::core
