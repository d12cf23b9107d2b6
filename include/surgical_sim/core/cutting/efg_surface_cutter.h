#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/cutting/surface_remap.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/surface_mapping.h"

namespace surgical_sim::core {

/// Parameters of EfgSurfaceCutter.
struct EfgSurfaceCutOptions {
  double front_width = 0.0;  ///< w [m] > 0: desired largest width of an exposed-surface triangle
  double tolerance = 0.0;    ///< blade-edge contact distance [m], >= 0 (edgeSweepCrossing)
  /// Rebuild the committed surface's edge tables and clusters from scratch when a cut is
  /// committed (O(t log t)) instead of updating the edges of the replaced and new triangles in
  /// place (the reference the update is tested against; both cut the same way).
  bool rebuild_tables = false;
};

/// What one EfgSurfaceCutter::cut() call changed.
struct EfgSurfaceCutStep {
  int crossed_edges = 0;  ///< surface edges cut this step
  /// Crossings not cut: they would start a second front, or their edge is shorter than
  /// EfgSurfaceCutter::minSplitEdge().
  int ignored_crossings = 0;
  bool completed = false;  ///< the cut closed this step (its fronts met, no transient left)
  bool crack = false;  ///< the blade left a running cut without closing it: the cut is kept as a
                       ///< crack (its front and tip vertices stay, shared by both lips)
  std::vector<int> remapped;  ///< vertices whose mapping row changed or that are new, sorted
  /// Crossing detection (outcodes, clusters, edge and vertex-IP tests), wall clock [s].
  double detect_seconds = 0.0;
};

/// The particle positions a step's vertex positions come from (EfgSurfaceCutter::cut): every used
/// vertex v is at the sum of mappingRow(v)'s weights times these particles' positions, and the
/// source's current IP positions are at `end`.
struct EfgParticleMotion {
  const Eigen::VectorXd& start;  ///< at the step start [m], size 3 x source numParticles()
  const Eigen::VectorXd& end;    ///< at the step end [m], same size
  /// IPs whose particles or shape values changed since the last cut() (a volume cut's
  /// changed_ips, before remapVerticesOfIps).
  const std::vector<int>& changed_ips;
};

/// Progressive cutting of the explicit surface of a meshless (EFG) body (Magnoux §4.2.4, §5.2).
///
/// State: the triangle surface (rest and, given by the caller each step, current vertex
/// positions), per vertex its IP, its mapping row (EfgMappingSource::pointWeights at its rest
/// position) and its stored cut planes. Vertex ids are stable; a vertex without triangles is a
/// free slot (vertexUsed()), reused later.
///
/// One cut at a time. A cut starts when the blade crosses a surface edge and ends when its two
/// ends meet. While it runs:
/// - Crossings: blade polyline segments vs the committed surface's uncut edges, both moving
///   linearly over the step (edgeSweepCrossing, current configuration). Broad phase: one pass
///   gives each vertex an outcode against the blade's swept box (and, for a one-segment blade,
///   against the slab its sweep lies in); edge clusters (up to 32 edges in Morton order, built
///   when edges are created) whose vertices all share a bit are skipped, so only the clusters
///   touching the swept box are tested edge by edge. Given the particle motion
///   (EfgParticleMotion), the pass over the positions is skipped: with rows w, a vertex moves
///   from its position at reference particle positions x_ref by at most |w|_1 x the particles'
///   largest motion from x_ref, and an IP by its shape values' L1 norm times it. So each cluster
///   keeps its vertices' box at x_ref, the box of them and their IPs, and the largest of these
///   norms (groups of consecutive clusters keep the union), and only the clusters whose boxes so
///   grown meet the swept box and slab have their vertices' outcodes computed or their segments
///   to their IPs tested. A cluster's bound is refreshed when one of its vertices' rest position
///   or row or its IP's shape values change (its group's grows); x_ref starts at the rest
///   positions and moves to the step end, refitting every box, once a particle is half a mean
///   particle spacing from it.
///   Ties in
///   time go by the edges' vertex ids. A crossing is kept as its edge parameter s and applied
///   in the rest configuration.
/// - Each crossed edge gets a pair of vertices at s, one per side. The crossed triangles form
///   one path whose two end (tip) triangles hold a blade-tip vertex at the blade's piercing
///   point: a triangle cut through becomes 3 triangles, a tip triangle 4. A crossing is accepted
///   only in a tip triangle (or, for the first, anywhere), so the path stays one strip.
/// - The exposed surface is meshed by a front (Alg. 1): transient vertices on the blade between
///   the two tips (shared by both sides, where the lips meet), a chain behind it (path crossings
///   and the last row of fixed vertices), a strip between chain and front rebuilt each step.
///   The front has k >= 2 segments (frontSegmentCount: split above w, merge below w/2); when an
///   interior transient vertex is farther than w from the chain, a row of fixed vertices is
///   dropped at the transient positions and the strip behind it is fixed. Each side has its own
///   sheet with its own vertices (crossing copies, fixed rows), oppositely oriented.
/// - Every strip that stays (a fixed row's, a crack's, a completed cut's fill) is graded: while
///   one of its chains has more than twice the other's vertices plus two, a row of new vertex
///   pairs halves it (gradedStrip), so a long chain of crossings facing a short front gets no
///   fan, and no vertex of a committed sheet has more than a few triangles. (Fans made later
///   cuts cross thousands of thin triangles at one spot: each crossing then ends in a longer
///   chain and a larger fan, and the surface of a region cut over and over ran away.)
/// - Transient rest positions interpolate linearly between the two tips' rest positions (exact
///   for a straight blade under a locally affine deformation).
/// - Completion: the last chain closes into a polygon, filled by a strip from the last fixed row
///   (without a row: the polygon's first half) to the rest of the polygon;
///   transient vertices are freed and the tables are updated in the cut's size: the replaced
///   triangles' slots are freed and the new triangles take the smallest free slots (triangle
///   and edge ids are stable), an edge left without triangles is freed, the new triangles find
///   their kept edges through the vertices' triangle lists, and the new edges form new
///   clusters (rebuild_tables: edges and clusters from scratch, O(t log t)).
/// - A step whose blade pierces neither tip triangle (the blade left the body) ends the cut as a
///   crack: the surface is committed as it is, front and tip vertices stay, shared by both lips.
/// Remapping (SurfaceRemapper criteria): new vertices; the endpoints and copies of a cut edge,
/// each with a plane through the crossing whose normal is the cut's (the side A sheet's normal
/// there, or the edge direction if that does not separate the endpoints); a fixed row vertex with
/// its sheet's normal; a committed vertex whose segment to its IP the blade crosses (plane
/// through the crossing, normal along vertex -> IP; tested for the vertices whose segment's hull
/// over the step, its two positions and the IP's current one, has a box meeting the swept box);
/// tips and transient vertices each
/// step; remapVerticesOfIps() after a volume cut (first ignoring neighbours on the changed IPs in
/// the 1-ring test, then once more with every neighbour's new IP for those still on a changed IP).
/// The surface stays closed and edge-manifold at every step (checkSurfaceClosure).
class EfgSurfaceCutter {
 public:
  /// Vertex positions, 3 x numVertices() [m]: a matrix, or the leading columns of a larger one (a
  /// caller's buffer with room to grow).
  using Positions = Eigen::Ref<const Eigen::Matrix3Xd>;

  /// @param surface closed, edge-manifold, outward-oriented rest surface [m].
  /// @param source the EFG model side; must outlive the cutter.
  /// @throws std::invalid_argument for bad options (names the field and range), a surface that
  ///         is empty, not finite, has out-of-range or repeated triangle indices, or is not
  ///         closed and edge-manifold, or a source without IPs.
  EfgSurfaceCutter(const TriMesh& surface, const EfgMappingSource& source,
                   const EfgSurfaceCutOptions& options);

  /// One step: finds the crossings of `sweep` (tissue frame, current configuration) and updates
  /// surface, front and mapping. No crossing and no running cut: nothing changes. Cost: one pass
  /// over the positions and one over the clusters, the edges of the clusters the swept box
  /// touches, the running cut's size (also when a step ends a cut, see the class comment).
  /// With `motion`, the cost of the broad phase is one pass over the particles and one over the
  /// clusters' bounds instead of the pass over the positions, and only the positions of the
  /// vertices of clusters near the sweep are read (and checked).
  /// @param x_start, x_end current vertex positions at the step start and end [m], shape
  ///        3 x numVertices() (free slots: any finite value).
  /// @param motion the particle positions x_start and x_end are mapped from (optional).
  /// @throws std::invalid_argument for a sweep failing validateBladeSweep, positions of the
  ///         wrong shape or not finite, or particle positions of the wrong size or not finite.
  EfgSurfaceCutStep cut(const BladeSweep& sweep, const Positions& x_start, const Positions& x_end,
                        const EfgParticleMotion* motion = nullptr);

  /// Remaps every vertex mapped to one of `changed_ips` (their particle sets changed after a
  /// volume cut). @return the remapped vertices, sorted.
  /// @throws std::invalid_argument for an IP out of range.
  std::vector<int> remapVerticesOfIps(const std::vector<int>& changed_ips);

  int numVertices() const { return static_cast<int>(verts_.size()); }
  bool vertexUsed(int v) const;
  /// Rest positions [m], shape 3 x numVertices().
  Eigen::Matrix3Xd restVertices() const;
  /// Current triangles (vertex ids), shape 3 x numTriangles(), outward-oriented.
  Eigen::Matrix3Xi triangles() const;
  int numTriangles() const;
  int vertexIp(int v) const;
  /// Edges shorter than this are not split: 0.1 w, or half the input surface's shortest edge if
  /// less. Cuts through one place (crossing the sheets of earlier cuts at grazing angles) would
  /// otherwise split ever shorter edges, and the surface would grow without bound [m].
  double minSplitEdge() const { return min_split_edge_; }
  const std::vector<CutPlane>& vertexPlanes(int v) const;
  /// The other side's vertex of a crossing or fixed-row vertex, -1 for any other vertex.
  int twin(int v) const;
  /// True while a cut is running (transient vertices exist).
  bool cutActive() const { return active_; }
  /// Transient (front and tip) vertices of the running cut.
  std::vector<int> transientVertices() const;
  /// Mapping row of vertex v (particles, MLS weights [-]).
  void mappingRow(int v, std::vector<int>& particles, std::vector<double>& weights) const;
  /// The surface mapping onto a model with `nodes` particles (slot = vertex id, every used
  /// vertex has a row). @throws std::invalid_argument when a row names a particle >= nodes.
  SurfaceMapping mapping(int nodes) const;

 private:
  struct Crossing {
    int edge = 0;
    double s = 0.0;    ///< along edges_[edge] from its first vertex
    int a_end = 0;     ///< endpoint (0/1) of the edge on side A
    int copy[2] = {};  ///< vertex on the side of endpoint 0 / 1
  };
  struct Vertex {
    Eigen::Vector3d rest = Eigen::Vector3d::Zero();
    int ip = -1;
    int ip_slot = -1;  ///< its index in ip_vertices_[ip] (-1 without an IP)
    int twin = -1;
    bool used = true;
    /// No IP lies below all its planes, so it keeps the nearest IP: planes are only added to a
    /// vertex (a reused slot starts empty) and IPs keep their rest positions, so it stays one.
    bool sliver = false;
    std::vector<CutPlane> planes;
    std::vector<int> particles;
    std::vector<double> weights;
  };

  /// Motion bound of a cluster's used vertices (see cut()): their box at ref_x_ [m], the box of
  /// them and their IPs [m], its round-off margin [m], and the largest L1 norm of their rows and
  /// their IPs' shape values [-].
  struct ClusterBound {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    Eigen::Vector3d segment_lo = Eigen::Vector3d::Zero(), segment_hi = Eigen::Vector3d::Zero();
    double margin = 0.0, row_norm = 0.0;
  };

  /// Maps vertex v to IP ip (-1: none), keeping ip_vertices_ and segment_tested_.
  void setIp(int v, int ip);
  /// Notes that v's rest position or row changed: the bounds of its clusters are stale.
  void touch(int v);
  /// Drops every cluster, group and super-group bound: the next refreshClusterBounds()
  /// recomputes them all.
  void forgetBounds();
  /// Recomputes the bounds of the clusters created or touched since the last call.
  void refreshClusterBounds();
  /// Sets b's box and margin: cluster c's used vertices at ref_x_.
  void clusterBox(int c, ClusterBound& b) const;
  /// A bound holding nothing (boxes from +inf to -inf, zero norm and margin).
  static ClusterBound emptyBound();
  /// Grows `into` to hold b.
  static void unite(ClusterBound& into, const ClusterBound& b);
  /// Sets each of `groups` to the union of its kGroupClusters consecutive `members`.
  static void uniteGroups(const std::vector<ClusterBound>& members,
                          std::vector<ClusterBound>& groups);
  /// Moves the reference to particle positions x and recomputes every cluster's, group's and
  /// super-group's box.
  void refit(const Eigen::VectorXd& x);
  /// The particles' largest distance from ref_x_ at the step start and end into motion_ [m]
  /// (refitting first when it exceeds refit_distance_).
  /// @throws std::invalid_argument for positions of the wrong size or not finite.
  void measureMotion(const EfgParticleMotion& motion);
  /// Sets segment_tested_[v] from v's IP and committed triangles.
  void updateSegmentTested(int v);
  /// Ends the running cut (its triangles join the committed surface) and updates the tables.
  void commit();
  /// Edge tables (ids in sorted order) and clusters of the current triangle slots from scratch.
  void buildTables();
  /// Removes triangle slot t from its edges' triangles; an edge left without one is freed.
  void unlinkEdges(int t);
  /// Links the new triangle in slot t to its edges: an edge of a linked triangle, else a new
  /// edge (its id appended to `fresh`).
  void linkEdges(int t, std::vector<int>& fresh);
  /// Bounding box (lower, upper corner) of the edges' rest vertices [m].
  std::array<Eigen::Vector3d, 2> edgeBox() const;
  /// Morton code of edge e's midpoint in cluster_box_ (10 bits per axis, clamped to it).
  std::uint32_t mortonCode(int e) const;
  /// New clusters of up to kClusterEdges of `edges` each, in their Morton order.
  void addClusters(const std::vector<int>& edges);
  int newVertex(Eigen::Vector3d rest);
  void freeVertex(int v);
  bool accept(int edge, double s);
  /// Moves tip `end` to where the blade pierces its triangle; false when it does not.
  bool placeTip(int end, const BladeSweep& sweep, const Positions& x_end);
  /// Resamples the front, drops a fixed row when due; appends the new vertices to `created`.
  void updateFront(std::vector<int>& created);
  /// Rebuilds the running cut's triangles; a crack's or a completed cut's sheet is graded
  /// (gradedStrip), its new vertices appended to `created`.
  void rebuild(bool crack, std::vector<int>& created);
  /// A new pair of fixed sheet vertices at `rest`, twins of each other, both appended to
  /// `created`. @return the side A vertex. `rest` is taken by value: it may be a vertex's, and
  /// verts_ may reallocate.
  int newPair(Eigen::Vector3d rest, std::vector<int>& created);
  /// Appends the sheet strip between `behind` and `ahead` (appendStrip's conventions, side A
  /// vertices) to `out`, first halving the denser chain towards the other with rows of new
  /// vertex pairs (halvingRow, gradingLevels), so a long chain of crossings facing a short front
  /// or row makes no fan at one vertex.
  void gradedStrip(std::vector<int> behind, std::vector<int> ahead, std::vector<int>& created,
                   std::vector<std::array<int, 3>>& out);
  std::function<Eigen::Vector3d(int)> restOf() const;
  /// Orders generated_of_ entries by vertex (for equal_range on a vertex id).
  struct GeneratedOrder {
    bool operator()(const std::pair<int, int>& a, int v) const { return a.first < v; }
    bool operator()(int v, const std::pair<int, int>& a) const { return v < a.first; }
  };
  /// Range of generated_of_ for vertex v, in generated_ order.
  std::pair<std::vector<std::pair<int, int>>::const_iterator,
            std::vector<std::pair<int, int>>::const_iterator>
  generatedOf(int v) const;
  /// Calls f(triangle) for every current triangle holding v.
  template <class F>
  void forIncident(int v, const F& f) const;
  std::vector<int> chain() const;
  int crossingCopy(int c, int vertex) const;
  int crossedCount(int tri) const;
  Eigen::Vector3d vertexNormal(int v) const;
  /// Unit normal of the side A sheet at v (zero when v is on no side A sheet triangle): the
  /// cut's normal, pointing from side A to side B.
  Eigen::Vector3d sheetNormal(int v) const;
  /// Remaps v; the 1-ring test ignores neighbours on IPs flagged in `excluded`. A sliver keeps
  /// its IP and only refreshes its weights (its IP's particles may have changed). For a vertex
  /// remapped twice: `near` keeps its first search's IPs between the calls
  /// (SurfaceRemapper::nearby, filled when empty), and with `weights_current` its weights already
  /// belong to its IP as it is now and are kept if it keeps that IP.
  void remap(int v, const std::vector<std::uint8_t>* excluded = nullptr,
             std::vector<int>* near = nullptr, bool weights_current = false);
  void addPlane(int v, const Eigen::Vector3d& point, const Eigen::Vector3d& normal);

  const EfgMappingSource& source_;
  EfgSurfaceCutOptions options_;
  /// Shorter edges are not split (their crossings are ignored): repeated cuts through one place
  /// refine the surface down to this length and no further [m].
  double min_split_edge_ = 0.0;
  SurfaceRemapper remapper_;
  std::vector<Vertex> verts_;  ///< per vertex id
  std::vector<int> free_;
  std::vector<std::vector<int>> ip_vertices_;  ///< per IP, the used vertices mapped to it
  // Committed surface (changes only at commit). Triangle and edge ids are stable: a removed
  // one's slot is reused.
  std::vector<std::array<int, 3>> tris_;       ///< per slot (replaced_: free or being replaced)
  std::vector<int> tri_free_;                  ///< free triangle slots, descending
  int live_tris_ = 0;                          ///< committed triangles
  std::vector<std::array<int, 2>> edges_;      ///< (lower, higher vertex); free slot {-1, -1}
  std::vector<int> edge_free_;                 ///< free edge slots
  std::vector<std::array<int, 3>> tri_edges_;  ///< edge k = (tri[k], tri[k+1]); free: -1
  std::vector<std::array<int, 2>> edge_tris_;  ///< lower triangle id first; -1: none
  std::vector<std::vector<int>> vertex_tris_;  ///< per vertex, its committed triangles, ascending
  /// Broad-phase clusters: per cluster its edges and (a superset of) their vertices, the
  /// latter as cluster_vert_ids_[cluster_vert_begin_[c] .. cluster_vert_begin_[c + 1]).
  std::vector<std::vector<int>> cluster_edges_;
  std::vector<int> cluster_vert_begin_ = {0}, cluster_vert_ids_;
  std::vector<int> edge_cluster_;                  ///< per edge slot, its cluster (free: -1)
  std::array<Eigen::Vector3d, 2> cluster_box_;     ///< box of the Morton codes [m]
  std::vector<std::vector<int>> vertex_clusters_;  ///< per vertex, the clusters listing it
  std::vector<ClusterBound> cluster_bounds_;       ///< per cluster (fewer: the rest are new)
  /// Per group of kGroupClusters consecutive clusters, the union of their bounds; per
  /// super-group of kGroupClusters consecutive groups, the union of theirs. A cut's new clusters
  /// are appended, so a group can span cuts far apart: the detection skips whole super-groups
  /// first, and its pass over the groups stays short on a surface of millions of triangles.
  std::vector<ClusterBound> group_bounds_, super_bounds_;
  std::vector<int> touched_;     ///< vertices touched since the last refresh
  Eigen::VectorXd ref_x_;        ///< reference particle positions of the bounds [m], size 3n
  double refit_distance_ = 0.0;  ///< [m]
  double motion_ = 0.0;          ///< the particles' largest distance from ref_x_ this step [m]
  // Running cut.
  bool active_ = false;
  std::vector<Crossing> crossings_;
  std::vector<int> edge_crossing_;  ///< per committed edge, its crossing or -1
  std::vector<int> path_;           ///< crossings from the L end to the R end
  std::array<int, 2> tip_tri_ = {-1, -1};
  std::array<int, 2> tip_vertex_ = {-1, -1};
  std::array<Eigen::Vector3d, 2> tip_bary_;
  std::vector<int> row_;                         ///< fixed row, side A vertices, L to R
  std::array<int, 2> row_attach_ = {-1, -1};     ///< crossings the row's ends attach to
  std::vector<int> front_;                       ///< interior transient vertices, L to R
  std::vector<std::array<int, 3>> fixed_sheet_;  ///< side A sheet triangles behind the chain
  std::vector<std::uint8_t> replaced_;           ///< per triangle slot: free or being replaced
  std::vector<int> cut_tris_;                    ///< committed triangles replaced by splits
  std::vector<std::array<int, 3>> generated_;    ///< triangles of the running cut
  /// (vertex, index in generated_) of each corner of the running cut's triangles, sorted.
  std::vector<std::pair<int, int>> generated_of_;
  std::vector<std::uint8_t> outcode_;  ///< per vertex, broad-phase scratch of cut()
  /// Per vertex: 1 when it is on the committed surface and mapped (its segment to its IP is
  /// tested against the blade), else 0.
  std::vector<std::uint8_t> segment_tested_;
  /// Per IP, the cut() call that last computed its current position ip_x_ [-], [m].
  std::vector<long long> ip_x_call_;
  std::vector<Eigen::Vector3d> ip_x_;
  long long calls_ = 0;
  std::vector<std::uint8_t> vertex_mark_;  ///< per vertex, cut() scratch, all 0 between uses
  int sheet_start_ = 0;  ///< first sheet triangle in generated_ (side A, B alternating)
  bool completed_ = false;
};

}  // namespace surgical_sim::core
