#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/cutting/efg_surface_cutter.h"
#include "surgical_sim/core/cutting/efg_volume_cutter.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// A meshless (EFG) body cut by both cutters: the model, its EfgVolumeCutter and an
/// EfgSurfaceCutter on its explicit surface, the model serving as the surface cutter's
/// EfgModelSource (IP current positions sum_a phi_a x_a of the positions last passed to cut()).
/// The surface vertices follow the particles through cached mapping rows, refreshed for the
/// vertices each cut reports remapped. Not copyable (the cutters hold references).
class EfgCutBody final {
 public:
  /// Wall time of the phases of one cut() [ms].
  struct Times {
    /// Surface vertex positions at the step end: the mapping a display does every step, cut or
    /// not (the start's are the last end's when the step continues the last cut's).
    double positions_ms = 0.0;
    double volume_ms = 0.0;   ///< EfgVolumeCutter::cut
    double surface_ms = 0.0;  ///< EfgSurfaceCutter::cut
    double remap_ms = 0.0;    ///< remapVerticesOfIps and the mapping-row refresh
    /// Crossing detection of both cutters (part of volume_ms and surface_ms) [ms].
    double detect_ms = 0.0;
    /// The cut update: volume, surface and remapping (without the positions) [ms].
    double update() const { return volume_ms + surface_ms + remap_ms; }
    /// The topology update: the cut update without the crossing detection [ms].
    double topology() const { return update() - detect_ms; }
  };
  /// What one cut() changed.
  struct Update {
    core::EfgCutResult volume;
    core::EfgSurfaceCutStep surface;
    int remapped_after_volume = 0;  ///< vertices remapped because their IP changed
    Times times;
  };

  /// @param surface closed rest surface [m] (the body's boundary and the cut surface's start).
  /// @param front_width w of the surface cutter [m] (EfgSurfaceCutOptions).
  /// @throws std::invalid_argument from EfgModel or EfgSurfaceCutter for bad input.
  EfgCutBody(const core::TriMesh& surface, const core::Material& material,
             const core::EfgOptions& options, double front_width);
  EfgCutBody(const EfgCutBody&) = delete;
  EfgCutBody& operator=(const EfgCutBody&) = delete;

  /// One sweep in the frame order tool -> CCD -> topology, surface and mapping: the surface
  /// vertex positions at x_start (the last call's end positions when x_start is the last call's
  /// x_end) and x_end, the volume cut, the surface cut, then the vertices of the IPs the volume
  /// cut changed are remapped.
  /// @param x_start, x_end particle positions at the step start and end [m], size 3n.
  /// @throws std::invalid_argument as the cutters (sweep or position sizes).
  Update cut(const core::BladeSweep& sweep, const Eigen::VectorXd& x_start,
             const Eigen::VectorXd& x_end);
  /// Surface vertex positions [m], 3 x surface().numVertices(), for particle positions x.
  Eigen::Matrix3Xd surfacePositions(const Eigen::VectorXd& x) const;

  const core::EfgModel& model() const { return model_; }
  /// The surface cutter's mapping source (the model at the positions last passed to cut()).
  const core::EfgMappingSource& source() const { return source_; }
  const core::EfgVolumeCutter& volume() const { return volume_; }
  const core::EfgSurfaceCutter& surface() const { return *surface_; }

 private:
  /// Refreshes the cached mapping rows of `vertices` (and sizes the cache) and their cached end
  /// positions.
  void refreshRows(const std::vector<int>& vertices);
  /// Position of surface vertex v for particle positions x [m], by its cached row.
  Eigen::Vector3d vertexPosition(int v, const Eigen::VectorXd& x) const;
  /// The surface vertex positions for particle positions x into out's leading columns [m] (out
  /// has at least as many columns as vertices).
  void fillPositions(const Eigen::VectorXd& x, Eigen::Matrix3Xd& out) const;

  core::EfgModel model_;
  core::EfgVolumeCutter volume_;
  std::unique_ptr<core::EfgSurfaceCutter> surface_;
  Eigen::VectorXd x_;  ///< particle positions the IPs follow [m]
  core::EfgModelSource source_{model_, x_};
  std::vector<std::vector<int>> row_particles_;
  std::vector<std::vector<double>> row_weights_;
  /// Surface vertex positions at a cut's start and (after the first cut, in the leading
  /// surface().numVertices() columns) at x_ [m]; buffers with room to grow.
  Eigen::Matrix3Xd start_, end_;
  bool cut_yet_ = false;  ///< cut() was called: end_ holds the positions at x_
};

/// Progressive cuts of the liver-like EFG body (makeLiverSurface), optionally simulated.
struct EfgCutRunSettings {
  Eigen::Vector3d semi_axes{0.075, 0.05, 0.03};  ///< liver semi-axes [m]
  int surface_subdivisions = 5;                  ///< makeLiverSurface level
  double spacing = 0.005;                        ///< EFG integration cell side d [m], > 0
  double front_width = 0.005;                    ///< surface cut front width w [m], > 0
  int cuts = 10;                                 ///< cuts, >= 1
  int sweeps_per_cut = 10;                       ///< blade steps per cut, >= 1
  double depth = 0.5;  ///< fraction of the body's height each cut descends below its top (0, 2]
  /// Blade edge length [m], >= 0; 0: six times semi_axes.x (every cut spans the body).
  double blade_length = 0.0;
  bool simulate = true;  ///< one implicit Euler step per sweep under gravity
  /// With simulate: uncut steps before the first cut (the body sags onto its clamp) [-], >= 0
  int settle_steps = 0;
  /// Linear solver of the steps (PcgSettings with adaptive_refresh, refresh_interval 1000; after a
  /// cut the integrator is told modelChanged(): cholmod re-analyses a changed pattern and the
  /// factor-reusing solvers keep their factor).
  core::SolverKind solver = core::SolverKind::Cholmod;
  double dt = 0.01;    ///< time step [s], > 0
  double young = 5e3;  ///< [Pa]
};

/// One sweep of runEfgProgressiveCuts().
struct EfgCutSweepRecord {
  int cut = 0;
  int sweep = 0;
  int severed_links = 0;
  int changed_ips = 0;
  int crossed_edges = 0;
  /// Surface edges the blade crossed that the running cut could not take (EfgSurfaceCutStep):
  /// mostly the sheets of earlier cuts the blade passes through.
  int ignored_crossings = 0;
  int remapped = 0;  ///< surface vertices remapped (surface cut and volume-cut IPs)
  int triangles = 0;
  int dofs = 0;
  int pieces = 0;
  double mass_error = 0.0;  ///< |total mass - initial| / initial [-]
  EfgCutBody::Times times;
  double step_ms = 0.0;  ///< implicit step incl. the re-analysis after a cut (0 if not simulated)
  int linear_iterations = 0;    ///< of the step's linear solve (1 for cholmod; 0 if not simulated)
  core::StepPhaseTimes phases;  ///< the step's split (0 if not simulated) [s]
  double max_displacement = 0.0;  ///< largest particle distance from rest after the step [m]
  bool finite = true;             ///< the step converged (status ok) and the positions are finite
};

/// Model sizes of runEfgProgressiveCuts().
struct EfgCutRunInfo {
  int ips = 0;
  int particles = 0;
  int surface_triangles = 0;  ///< before the cuts
  /// Mean step of the second half of the settle steps: the uncut body's step [ms] (0 without)
  double settled_step_ms = 0.0;
};

/// cuts x sweeps_per_cut sweeps: cut i is a straight blade (blade_length, centred) in the vertical
/// plane at angle i x 137.5 deg about z, offset from the centre by a golden-ratio sequence within
/// +-a/2, descending from above the top to depth x height below it in sweeps_per_cut equal steps.
/// With simulate: the particles with rest z below the lowest particle + 2 spacing are clamped,
/// particles the cuts leave unused are pinned where they are, gravity -z; settle_steps steps
/// without a cut, then each sweep steps the dynamics first and cuts with the step's motion.
/// @throws std::runtime_error if a settle step fails.
/// @throws std::invalid_argument naming the setting out of range.
std::vector<EfgCutSweepRecord> runEfgProgressiveCuts(const EfgCutRunSettings& settings,
                                                     EfgCutRunInfo* info = nullptr);

/// One probe sweep of runEfgCutIndependence(), on each body.
struct EfgProbeSweepRecord {
  struct Body {
    int severed_links = 0;
    int crossed_edges = 0;
    int remapped = 0;   ///< surface vertices remapped (surface cut and volume-cut IPs)
    int triangles = 0;  ///< after the sweep
    EfgCutBody::Times times;
  };
  int cut = 0;
  int sweep = 0;
  std::array<Body, 2> body;  ///< the fresh body, the body after the background cuts
};

/// Sizes of runEfgCutIndependence().
struct EfgCutIndependenceInfo {
  EfgCutRunInfo run;                  ///< the body (no settle steps)
  int background_triangles = 0;       ///< surface triangles after the background cuts
  int background_pieces = 0;          ///< pieces after the background cuts
  double background_update_ms = 0.0;  ///< mean cut update of a background sweep [ms]
};

/// Whether a cut's cost depends on the cuts made before it elsewhere: two copies of the body of
/// `settings` at rest; the second first takes `background_cuts` cuts in the half x < 0 (blade c
/// along c x 137.5 deg, centred at x in -[0.4, 0.7] a, y in [-0.4, 0.4] b by a 2D golden
/// sequence, descending from above the body's top within the blade's reach down settings.depth
/// of its height there), then both take the same settings.cuts probe cuts, mirrored into the
/// half x > 0, sweep by sweep, alternating which body goes first.
/// @throws std::invalid_argument naming the setting out of range, simulate set, or a
///         blade_length not in (0, 0.8 a) (a blade must stay in its half).
std::vector<EfgProbeSweepRecord> runEfgCutIndependence(const EfgCutRunSettings& settings,
                                                       int background_cuts,
                                                       EfgCutIndependenceInfo* info = nullptr);

/// Random sweeps over the liver-like EFG body, both cutters (the fuzz of issue 19).
struct EfgCutFuzzSettings {
  int sweeps = 0;                                ///< >= 1
  unsigned seed = 0;                             ///< std::mt19937 seed
  Eigen::Vector3d semi_axes{0.075, 0.05, 0.03};  ///< liver semi-axes [m]
  int surface_subdivisions = 4;                  ///< makeLiverSurface level
  double spacing = 0.008;                        ///< EFG integration cell side d [m], > 0
  /// Called with the number of sweeps done after each sweep that passed every check (optional).
  std::function<void(int)> passed;
};

/// Outcome of runEfgCutFuzz().
struct EfgCutFuzzReport {
  int sweeps = 0;                ///< sweeps run (stops at the first failure)
  std::string failure;           ///< "" or "sweep i: <problem>"
  double max_mass_error = 0.0;   ///< max relative total-mass error [-]
  int severed_links = 0;         ///< in total
  int crossed_edges = 0;         ///< surface edges cut in total
  int pieces = 0;                ///< at the end
  int triangles = 0;             ///< surface triangles at the end
  long long planes_checked = 0;  ///< (vertex, stored cut plane) pairs checked, all sweeps
  /// Vertices whose cut planes leave no IP on their side (a sliver between cuts thinner than the
  /// IP spacing; mapped to the nearest IP, SurfaceRemapper's last relaxation), after the last
  /// sweep.
  int sliver_vertices = 0;
  double mean_update_ms = 0.0;  ///< mean cut() time [ms]
};

/// Each sweep moves a random 2- or 3-point blade polyline inside the body's box by a random
/// translation while the tissue moves by a random rigid shift of up to 5 mm (the cut sees the
/// shifted positions). After every sweep: masses and shape values finite, total mass equal to the
/// initial one (relative 1e-12), the surface closed and edge-manifold (checkSurfaceClosure, no
/// open or pinched edge), and every used surface vertex's IP strictly below each of the vertex's
/// stored cut planes (on the vertex's own side of every cut near it) whenever some IP is (else
/// the vertex counts in sliver_vertices), and every used vertex's mapping row placing it where
/// it rests (within 1e-6 of the spacing), however far its IP.
/// @throws std::invalid_argument for sweeps < 1 or spacing <= 0.
EfgCutFuzzReport runEfgCutFuzz(const EfgCutFuzzSettings& settings);

/// T3(c) (BENCHMARKS.md): hexagonal beam of side a and length L along x (makeHexagonalBeam),
/// clamped at x = 0, cut at x = L / 2 through half the width: the blade, along y and wider than
/// the beam, descends from above the beam to the axis (z = 0).
struct CutBeam {
  double side = 0.01;    ///< a [m]
  double length = 0.1;   ///< L [m]
  double young = 1e8;    ///< [Pa]
  double poisson = 0.3;  ///< [-]
  double density = 1000.0;
};

/// One cut beam's answer under one load.
struct CutBeamRun {
  double tip = 0.0;      ///< mean tip displacement along the load [m] (NaN: no equilibrium)
  int dofs = 0;          ///< 3 x nodes (or particles)
  int size = 0;          ///< elements (tet) or integration points (EFG)
  double step_ms = 0.0;  ///< one linearized implicit Euler step (dt 0.01 s, CHOLMOD) [ms]
};

/// Reference: corotational Tet10 mesh (cells_along even, so x = L / 2 is a node layer) whose
/// nodes of that layer with z > 0 are duplicated for the elements beyond it (the cut as
/// duplicated nodes); tip at the nodes of x = L (beamTipDeflection).
/// @throws std::invalid_argument for an odd cells_along.
CutBeamRun cutBeamReference(const CutBeam& beam, int cells_along, int rings,
                            const Eigen::Vector3d& load);
/// EFG beam (integration cells of side d = L / (4 k + 2), so the particle layers hold x = 0 and
/// x = L and the cut lies half-way between two of them), cut by EfgVolumeCutter; the x = 0
/// particles and those the cut leaves unused are clamped; tip measured at the x = L nodes of a
/// Tet4 beam mesh of d-sized cells through EfgModel::interpolation.
/// @throws std::invalid_argument for k < 1.
CutBeamRun efgCutBeam(const CutBeam& beam, int k, const Eigen::Vector3d& load);
/// The tet cutter (virtual nodes) on a corotational Tet4 beam (cells_along odd: the cut crosses
/// mid-element), tip at the x = L nodes.
CutBeamRun tetCutBeam(const CutBeam& beam, int cells_along, int rings, const Eigen::Vector3d& load);

}  // namespace surgical_sim::bench
