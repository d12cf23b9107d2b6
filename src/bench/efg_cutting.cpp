#include "surgical_sim/bench/efg_cutting.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include "surgical_sim/bench/beam_tip_deflection.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/mesh/surface_generators.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

namespace {

using Clock = std::chrono::steady_clock;

/// Golden ratio conjugate (sqrt 5 - 1) / 2 [-]: the cuts' low-discrepancy sequences.
const double kGolden = 0.5 * (std::sqrt(5.0) - 1.0);

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double totalMass(const EfgModel& m) { return m.lumpedMass().sum() / 3.0; }

void requirePositive(const char* name, double value) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw std::invalid_argument(std::string(name) + " = " + std::to_string(value) +
                                " must be finite and > 0");
}

/// True when some IP lies strictly below every plane in `planes`.
bool admitsAnIp(const EfgCutBody& body, const std::vector<CutPlane>& planes) {
  for (int e = 0; e < body.source().numIntegrationPoints(); ++e) {
    const Eigen::Vector3d X = body.source().ipRestPosition(e);
    if (std::all_of(planes.begin(), planes.end(),
                    [&](const CutPlane& p) { return (X - p.point).dot(p.normal) < 0.0; }))
      return true;
  }
  return false;
}

/// Sliver vertices known so far: per vertex id, the (plane count, IP) its planes admitted no IP
/// with ({-1, -1}: none). Planes are only added to a vertex (a reused slot starts empty), so a
/// set that admits no IP keeps admitting none while the count and the IP stay.
using SliverCache = std::vector<std::pair<std::size_t, int>>;

/// "" when every used surface vertex's IP lies strictly below each of the vertex's stored cut
/// planes, or no IP at all does (a sliver between cuts thinner than the IP spacing: the vertex
/// keeps the nearest IP, counted in `slivers`); else the first offending vertex. Adds the
/// (vertex, plane) pairs checked to `checked`.
std::string wrongSide(const EfgCutBody& body, SliverCache& cache, long long& checked,
                      int& slivers) {
  const EfgSurfaceCutter& surface = body.surface();
  cache.resize(static_cast<std::size_t>(surface.numVertices()), {0, -1});
  slivers = 0;
  for (int v = 0; v < surface.numVertices(); ++v) {
    if (!surface.vertexUsed(v)) continue;
    const int ip_index = surface.vertexIp(v);
    const Eigen::Vector3d ip = body.source().ipRestPosition(ip_index);
    const std::vector<CutPlane>& planes = surface.vertexPlanes(v);
    checked += static_cast<long long>(planes.size());
    std::pair<std::size_t, int>& known = cache[static_cast<std::size_t>(v)];
    if (known == std::pair{planes.size(), ip_index} && !planes.empty()) {
      ++slivers;
      continue;
    }
    for (const CutPlane& plane : planes) {
      const double beyond = (ip - plane.point).dot(plane.normal);
      if (beyond < 0.0) continue;
      if (!admitsAnIp(body, planes)) {
        known = {planes.size(), ip_index};
        ++slivers;
        break;
      }
      return "vertex " + std::to_string(v) + " mapped to IP " + std::to_string(ip_index) + " " +
             std::to_string(beyond) + " m beyond one of its " + std::to_string(planes.size()) +
             " cut planes while another IP is on its side of all";
    }
  }
  return "";
}

/// How close [spacings] a vertex's mapping row must place it to where it rests: MLS weights
/// reproduce a linear field to round-off, whatever the distance to the IP.
constexpr double kPlacedTolerance = 1e-6;

/// "" when every used surface vertex's mapping row places it where it rests (within `tolerance`
/// [m]); else the first vertex shown elsewhere.
std::string misplaced(const EfgCutBody& body, double tolerance) {
  const EfgSurfaceCutter& surface = body.surface();
  const Eigen::Matrix3Xd shown = body.surfacePositions(body.model().restPositions());
  const Eigen::Matrix3Xd rest = surface.restVertices();
  for (int v = 0; v < surface.numVertices(); ++v) {
    if (!surface.vertexUsed(v)) continue;
    const double d = (shown.col(v) - rest.col(v)).norm();
    if (!(d <= tolerance))
      return "vertex " + std::to_string(v) + " (IP " + std::to_string(surface.vertexIp(v)) +
             ") shown " + std::to_string(d) + " m from where it rests";
  }
  return "";
}

Material beamMaterial(const CutBeam& beam) {
  return Material::create(beam.young, beam.poisson, beam.density);
}

/// The T3(c) blade: along y, wider than the beam, from above it down to the axis.
BladeSweep beamSweep(const CutBeam& beam) {
  const double a = beam.side, x = 0.5 * beam.length;
  BladeSweep sweep;
  sweep.start.resize(3, 2);
  sweep.end.resize(3, 2);
  sweep.start << x, x, -2 * a, 2 * a, 2 * a, 2 * a;
  sweep.end << x, x, -2 * a, 2 * a, 1e-6 * a, 1e-6 * a;
  return sweep;
}

/// Mean time of 3 linearized implicit Euler steps (dt 0.01 s, CHOLMOD, analysis included in the
/// first, which is not counted) of `model` under `load` with `clamped` nodes fixed [ms].
double stepMs(const TissueModel& model, const std::vector<int>& clamped,
              const Eigen::Vector3d& load) {
  DynamicsProblem problem;
  problem.model = &model;
  problem.external_force = model.bodyForce(load);
  problem.dirichlet = clampNodes(clamped, model.restPositions());
  SimulationState state{model.restPositions(), Eigen::VectorXd::Zero(3 * model.numNodes()), 0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  integrator->step(problem, 0.01, state);
  const Clock::time_point t0 = Clock::now();
  for (int i = 0; i < 3; ++i) integrator->step(problem, 0.01, state);
  return msSince(t0) / 3.0;
}

/// Nodes of `model` at rest x <= 1e-9 length.
std::vector<int> clampedAtZero(const TissueModel& model, double length) {
  std::vector<int> clamped;
  for (int v = 0; v < model.numNodes(); ++v)
    if (model.restPositions()(3 * v) <= 1e-9 * length) clamped.push_back(v);
  return clamped;
}

}  // namespace

CutBeamRun cutBeamReference(const CutBeam& beam, int cells_along, int rings,
                            const Eigen::Vector3d& load) {
  if (cells_along < 2 || cells_along % 2 != 0)
    throw std::invalid_argument("cutBeamReference: cells_along = " + std::to_string(cells_along) +
                                " must be even and >= 2");
  const double a = beam.side, L = beam.length;
  TetMesh mesh = makeHexagonalBeam(a, L, cells_along, rings, ElementType::Tet10);
  std::vector<int> duplicate(static_cast<std::size_t>(mesh.numNodes()), -1);
  for (int e = 0; e < mesh.numElements(); ++e) {
    double cx = 0;
    for (int i = 0; i < 4; ++i) cx += mesh.nodes(0, mesh.elements(i, e)) / 4;
    if (cx < 0.5 * L) continue;
    for (Eigen::Index i = 0; i < mesh.elements.rows(); ++i) {
      const int v = mesh.elements(i, e);
      if (std::abs(mesh.nodes(0, v) - 0.5 * L) > 1e-9 * L || mesh.nodes(2, v) < 1e-9 * a) continue;
      int& d = duplicate[static_cast<std::size_t>(v)];
      if (d < 0) {
        d = static_cast<int>(mesh.nodes.cols());
        mesh.nodes.conservativeResize(3, d + 1);
        mesh.nodes.col(d) = mesh.nodes.col(v);
      }
      mesh.elements(i, e) = d;
    }
  }
  const auto model = makeTissueModel(ModelKind::Corotational, mesh, beamMaterial(beam));
  CutBeamRun run;
  run.tip = beamTipDeflection(*model, load);
  run.dofs = 3 * model->numNodes();
  run.size = mesh.numElements();
  run.step_ms = stepMs(*model, clampedAtZero(*model, L), load);
  return run;
}

CutBeamRun efgCutBeam(const CutBeam& beam, int k, const Eigen::Vector3d& load) {
  if (k < 1) throw std::invalid_argument("efgCutBeam: k = " + std::to_string(k) + " must be >= 1");
  const double L = beam.length, d = L / (4.0 * k + 2.0);
  const int along = 4 * k + 2;
  const TetMesh mesh = makeHexagonalBeam(beam.side, L, along,
                                         std::max(1, static_cast<int>(std::lround(beam.side / d))),
                                         ElementType::Tet4);
  EfgOptions options;
  options.spacing = d;
  EfgModel model(mesh, beamMaterial(beam), options);
  EfgVolumeCutter cutter(model);
  const EfgCutResult cut =
      cutter.cut(beamSweep(beam), model.restPositions(), model.restPositions());
  std::vector<int> clamped = clampedAtZero(model, L);
  clamped.insert(clamped.end(), cut.unused_particles.begin(), cut.unused_particles.end());
  std::vector<int> tip_nodes;
  for (int v = 0; v < mesh.numNodes(); ++v)
    if (mesh.nodes(0, v) >= L * (1.0 - 1e-9)) tip_nodes.push_back(v);
  Eigen::Matrix3Xd tip_points(3, static_cast<Eigen::Index>(tip_nodes.size()));
  for (std::size_t i = 0; i < tip_nodes.size(); ++i)
    tip_points.col(static_cast<Eigen::Index>(i)) = mesh.nodes.col(tip_nodes[i]);
  CutBeamRun run;
  run.tip = beamTipDeflection(model, load, clamped, model.interpolation(tip_points));
  run.dofs = 3 * model.numNodes();
  run.size = model.numIntegrationPoints();
  run.step_ms = stepMs(model, clamped, load);
  return run;
}

CutBeamRun tetCutBeam(const CutBeam& beam, int cells_along, int rings,
                      const Eigen::Vector3d& load) {
  const TetMesh mesh =
      makeHexagonalBeam(beam.side, beam.length, cells_along, rings, ElementType::Tet4);
  TetCutter cutter(mesh, beam.density);
  const Eigen::VectorXd x =
      Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * mesh.numNodes());
  cutter.cut(beamSweep(beam), x, x);
  const auto model = makeCutTissueModel(ModelKind::Corotational, cutter, beamMaterial(beam));
  CutBeamRun run;
  run.tip = beamTipDeflection(*model, load);
  run.dofs = 3 * model->numNodes();
  run.size = cutter.mesh().numElements();
  run.step_ms = stepMs(*model, clampedAtZero(*model, beam.length), load);
  return run;
}

EfgCutBody::EfgCutBody(const TriMesh& surface, const Material& material, const EfgOptions& options,
                       double front_width)
    : model_(surface, material, options), volume_(model_), x_(model_.restPositions()) {
  surface_ =
      std::make_unique<EfgSurfaceCutter>(surface, source_, EfgSurfaceCutOptions{front_width, 1e-9});
  std::vector<int> all(static_cast<std::size_t>(surface_->numVertices()));
  for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<int>(v);
  refreshRows(all);
}

namespace {

/// Gives m at least n columns, doubling: a position buffer grows in amortized O(1) a vertex.
void reserveColumns(Eigen::Matrix3Xd& m, Eigen::Index n) {
  if (m.cols() < n) m.conservativeResize(3, std::max(n, 2 * m.cols()));
}

}  // namespace

void EfgCutBody::refreshRows(const std::vector<int>& vertices) {
  const auto n = static_cast<std::size_t>(surface_->numVertices());
  const auto had = static_cast<Eigen::Index>(row_particles_.size());
  row_particles_.resize(n);
  row_weights_.resize(n);
  for (const int v : vertices)
    surface_->mappingRow(v, row_particles_[static_cast<std::size_t>(v)],
                         row_weights_[static_cast<std::size_t>(v)]);
  if (!cut_yet_) return;
  reserveColumns(end_, static_cast<Eigen::Index>(n));
  end_.middleCols(had, static_cast<Eigen::Index>(n) - had).setZero();  // free until remapped
  for (const int v : vertices) end_.col(v) = vertexPosition(v, x_);
}

Eigen::Vector3d EfgCutBody::vertexPosition(int v, const Eigen::VectorXd& x) const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  const std::vector<int>& particles = row_particles_[static_cast<std::size_t>(v)];
  const std::vector<double>& weights = row_weights_[static_cast<std::size_t>(v)];
  for (std::size_t a = 0; a < particles.size(); ++a)
    p += weights[a] * x.segment<3>(3 * particles[a]);
  return p;
}

void EfgCutBody::fillPositions(const Eigen::VectorXd& x, Eigen::Matrix3Xd& out) const {
  for (std::size_t v = 0; v < row_particles_.size(); ++v)
    out.col(static_cast<Eigen::Index>(v)) = vertexPosition(static_cast<int>(v), x);
}

Eigen::Matrix3Xd EfgCutBody::surfacePositions(const Eigen::VectorXd& x) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(row_particles_.size()));
  fillPositions(x, out);
  return out;
}

EfgCutBody::Update EfgCutBody::cut(const BladeSweep& sweep, const Eigen::VectorXd& x_start,
                                   const Eigen::VectorXd& x_end) {
  Update u;
  Clock::time_point t0 = Clock::now();
  // The start's positions are the last end's when the particles start where the last cut left
  // them (the rows of the vertices it remapped are refreshed there).
  const auto n = static_cast<Eigen::Index>(row_particles_.size());
  if (cut_yet_ && x_start.size() == x_.size() && x_start == x_) {
    std::swap(start_, end_);
  } else {
    reserveColumns(start_, n);
    fillPositions(x_start, start_);
  }
  reserveColumns(end_, n);
  fillPositions(x_end, end_);
  cut_yet_ = true;
  u.times.positions_ms = msSince(t0);
  t0 = Clock::now();
  u.volume = volume_.cut(sweep, x_start, x_end);
  u.times.volume_ms = msSince(t0);
  x_ = x_end;
  t0 = Clock::now();
  const EfgParticleMotion motion{x_start, x_end, u.volume.changed_ips};
  u.surface = surface_->cut(sweep, start_.leftCols(n), end_.leftCols(n), &motion);
  u.times.surface_ms = msSince(t0);
  u.times.detect_ms = 1e3 * (u.volume.detect_seconds + u.surface.detect_seconds);
  t0 = Clock::now();
  refreshRows(u.surface.remapped);
  if (!u.volume.changed_ips.empty()) {
    const std::vector<int> remapped = surface_->remapVerticesOfIps(u.volume.changed_ips);
    u.remapped_after_volume = static_cast<int>(remapped.size());
    refreshRows(remapped);
  }
  u.times.remap_ms = msSince(t0);
  return u;
}

namespace {

/// Checks the settings runEfgProgressiveCuts() and runEfgCutIndependence() share.
void checkRunSettings(const EfgCutRunSettings& settings) {
  requirePositive("spacing", settings.spacing);
  requirePositive("front_width", settings.front_width);
  requirePositive("dt", settings.dt);
  if (settings.settle_steps < 0)
    throw std::invalid_argument("settle_steps = " + std::to_string(settings.settle_steps) +
                                " must be >= 0");
  if (settings.cuts < 1 || settings.sweeps_per_cut < 1)
    throw std::invalid_argument("cuts and sweeps_per_cut must be >= 1 (got " +
                                std::to_string(settings.cuts) + ", " +
                                std::to_string(settings.sweeps_per_cut) + ")");
  if (!(settings.depth > 0.0 && settings.depth <= 2.0))
    throw std::invalid_argument("depth = " + std::to_string(settings.depth) + " must be in (0, 2]");
  if (!(settings.blade_length >= 0.0) || !std::isfinite(settings.blade_length))
    throw std::invalid_argument("blade_length = " + std::to_string(settings.blade_length) +
                                " must be finite and >= 0");
}

/// Sizes of `model` cut from the surface `liver`.
EfgCutRunInfo runInfo(const EfgModel& model, const TriMesh& liver) {
  return {model.numIntegrationPoints(), model.numNodes(), static_cast<int>(liver.triangles.cols())};
}

/// The liver-like body of `settings` (surface `liver`).
std::unique_ptr<EfgCutBody> makeRunBody(const EfgCutRunSettings& settings, const TriMesh& liver) {
  EfgOptions options;
  options.spacing = settings.spacing;
  return std::make_unique<EfgCutBody>(liver, Material::create(settings.young, 0.45, 1000.0),
                                      options, settings.front_width);
}

/// The cuts' blades: half length [m] and the height range they descend [m].
struct RunBlade {
  double half = 0.0, z_from = 0.0, z_to = 0.0;

  /// From above the body's top down `settings.depth` of its height.
  RunBlade(const EfgCutRunSettings& settings, const TriMesh& liver) {
    half = settings.blade_length > 0.0 ? 0.5 * settings.blade_length : 3.0 * settings.semi_axes.x();
    setRange(settings, liver.vertices.row(2).maxCoeff(), liver.vertices.row(2).minCoeff());
  }

  /// From above the top of the body's vertices within the blade's reach of `centre` (x, y) down
  /// `settings.depth` of their height there.
  RunBlade(const EfgCutRunSettings& settings, const TriMesh& liver, const Eigen::Vector3d& centre)
      : RunBlade(settings, liver) {
    double top = -std::numeric_limits<double>::infinity(), bottom = -top;
    for (Eigen::Index v = 0; v < liver.vertices.cols(); ++v) {
      if ((liver.vertices.col(v).head<2>() - centre.head<2>()).norm() > half) continue;
      top = std::max(top, liver.vertices(2, v));
      bottom = std::min(bottom, liver.vertices(2, v));
    }
    if (top >= bottom) setRange(settings, top, bottom);
  }

  void setRange(const EfgCutRunSettings& settings, double top, double bottom) {
    z_from = top + 0.1 * settings.semi_axes.z();
    z_to = top - settings.depth * (top - bottom);
  }

  /// Sweep s of `sweeps` of the blade centred at `centre` (x, y) along the unit `along`.
  BladeSweep sweep(const Eigen::Vector3d& centre, const Eigen::Vector3d& along, int s,
                   int sweeps) const {
    const double z0 = z_from + (z_to - z_from) * s / sweeps;
    const double z1 = z_from + (z_to - z_from) * (s + 1) / sweeps;
    BladeSweep out;
    out.start.resize(3, 2);
    out.end.resize(3, 2);
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d p = centre + (k ? half : -half) * along;
      out.start.col(k) = Eigen::Vector3d(p.x(), p.y(), z0);
      out.end.col(k) = Eigen::Vector3d(p.x(), p.y(), z1);
    }
    return out;
  }
};

/// Direction of cut c's blade in the horizontal plane: c x 137.5 deg about z.
Eigen::Vector3d goldenDirection(int c) {
  const double angle = c * 2.0 * M_PI * (1.0 - kGolden);
  return {std::cos(angle), std::sin(angle), 0.0};
}

}  // namespace

std::vector<EfgCutSweepRecord> runEfgProgressiveCuts(const EfgCutRunSettings& settings,
                                                     EfgCutRunInfo* info) {
  checkRunSettings(settings);
  const Eigen::Vector3d semi = settings.semi_axes;
  const TriMesh liver = makeLiverSurface(semi, settings.surface_subdivisions);
  const RunBlade blade(settings, liver);
  const std::unique_ptr<EfgCutBody> body_ptr = makeRunBody(settings, liver);
  EfgCutBody& body = *body_ptr;
  const EfgModel& model = body.model();
  const double mass0 = totalMass(model);
  const Eigen::Matrix3Xd& X = model.grid().particles;
  if (info) *info = runInfo(model, liver);

  DynamicsProblem problem;
  problem.model = &model;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  std::vector<char> fixed(static_cast<std::size_t>(model.numNodes()), 0);
  const double clamp_z = X.row(2).minCoeff() + 2.0 * settings.spacing;
  for (int p = 0; p < model.numNodes(); ++p) fixed[static_cast<std::size_t>(p)] = X(2, p) < clamp_z;
  SimulationState state{model.restPositions(), Eigen::VectorXd::Zero(3 * model.numNodes()), 0.0};
  const auto setConstraints = [&] {
    std::vector<int> nodes;
    for (int p = 0; p < model.numNodes(); ++p)
      if (fixed[static_cast<std::size_t>(p)]) nodes.push_back(p);
    problem.dirichlet = clampNodes(nodes, state.x);
    problem.external_force = model.bodyForce(g);
  };
  setConstraints();
  PcgSettings pcg;
  // The factor-reusing solvers refresh when it pays (the cap of 1000 calls is rarely reached).
  pcg.adaptive_refresh = true;
  pcg.refresh_interval = 1000;
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(settings.solver, pcg));

  // One implicit step, its wall time in ms [ms]; stepOk: converged, positions finite.
  const auto timedStep = [&](double& ms) {
    const Clock::time_point t0 = Clock::now();
    const StepReport report = integrator->step(problem, settings.dt, state);
    ms = msSince(t0);
    return report;
  };
  const auto stepOk = [&](const StepReport& report) {
    return report.status == StepStatus::Ok && state.x.allFinite();
  };
  if (settings.simulate && settings.settle_steps > 0) {
    double settled_ms = 0.0;
    for (int i = 0; i < settings.settle_steps; ++i) {
      double ms = 0.0;
      const StepReport report = timedStep(ms);
      if (i >= settings.settle_steps / 2) settled_ms += ms;
      if (!stepOk(report))
        throw std::runtime_error("runEfgProgressiveCuts: settle step " + std::to_string(i) +
                                 " failed (" + toString(report.status) + ")");
    }
    if (info)
      info->settled_step_ms = settled_ms / (settings.settle_steps - settings.settle_steps / 2);
  }
  std::vector<EfgCutSweepRecord> records;
  for (int c = 0; c < settings.cuts; ++c) {
    const Eigen::Vector3d along = goldenDirection(c);
    const Eigen::Vector3d normal(-along.y(), along.x(), 0.0);
    const Eigen::Vector3d centre = semi.x() * (std::fmod(c * kGolden, 1.0) - 0.5) * normal;
    for (int s = 0; s < settings.sweeps_per_cut; ++s) {
      const BladeSweep sweep = blade.sweep(centre, along, s, settings.sweeps_per_cut);
      EfgCutSweepRecord r;
      r.cut = c;
      r.sweep = s;
      Eigen::VectorXd x_start = state.x;
      if (settings.simulate) {
        const StepReport report = timedStep(r.step_ms);
        r.linear_iterations = report.linear_iterations;
        r.phases = report.phases;
        r.finite = stepOk(report);
        r.max_displacement = (state.x - model.restPositions())
                                 .reshaped(3, model.numNodes())
                                 .colwise()
                                 .norm()
                                 .maxCoeff();
      }
      const EfgCutBody::Update u = body.cut(sweep, x_start, state.x);
      if (!u.volume.changed_ips.empty()) {
        for (const int p : u.volume.unused_particles) fixed[static_cast<std::size_t>(p)] = 1;
        setConstraints();
        integrator->modelChanged();  // same DOFs; the solver keeps what it can
      }
      r.severed_links = static_cast<int>(u.volume.severed_links.size());
      r.changed_ips = static_cast<int>(u.volume.changed_ips.size());
      r.crossed_edges = u.surface.crossed_edges;
      r.ignored_crossings = u.surface.ignored_crossings;
      r.remapped = static_cast<int>(u.surface.remapped.size()) + u.remapped_after_volume;
      r.triangles = static_cast<int>(body.surface().triangles().cols());
      r.dofs = 3 * model.numNodes();
      r.pieces = body.volume().pieces();
      r.mass_error = std::abs(totalMass(model) - mass0) / mass0;
      r.times = u.times;
      records.push_back(r);
      if (!r.finite) return records;
    }
  }
  return records;
}

std::vector<EfgProbeSweepRecord> runEfgCutIndependence(const EfgCutRunSettings& settings,
                                                       int background_cuts,
                                                       EfgCutIndependenceInfo* info) {
  checkRunSettings(settings);
  if (settings.simulate)
    throw std::invalid_argument(
        "runEfgCutIndependence: simulate must be false (the bodies stay at rest)");
  if (background_cuts < 0)
    throw std::invalid_argument("background_cuts = " + std::to_string(background_cuts) +
                                " must be >= 0");
  const Eigen::Vector3d semi = settings.semi_axes;
  if (!(settings.blade_length > 0.0 && settings.blade_length < 0.8 * semi.x()))
    throw std::invalid_argument(
        "runEfgCutIndependence: blade_length = " + std::to_string(settings.blade_length) +
        " must be in (0, 0.8 semi_axes.x): each cut stays in its half");
  const TriMesh liver = makeLiverSurface(semi, settings.surface_subdivisions);
  // Cut c's centre: x in side x [0.4, 0.7] a, y in [-0.4, 0.4] b (a 2D golden sequence), so a
  // blade shorter than 0.8 a stays on its side of x = 0; it descends from above the body's top
  // there (the body thins towards x < 0).
  const auto centre = [&](int c, double side) {
    const double u = std::fmod(0.5 + c * 0.7548776662466927, 1.0);
    const double v = std::fmod(0.5 + c * 0.5698402909980532, 1.0);
    return Eigen::Vector3d(side * semi.x() * (0.4 + 0.3 * u), semi.y() * 0.8 * (v - 0.5), 0.0);
  };
  // Cut c's sweeps on the side x < 0 (side -1) or x > 0 (side 1).
  const auto sweeps = [&](int c, double side) {
    const Eigen::Vector3d at = centre(c, side);
    const RunBlade blade(settings, liver, at);
    std::vector<BladeSweep> out;
    for (int s = 0; s < settings.sweeps_per_cut; ++s)
      out.push_back(blade.sweep(at, goldenDirection(c), s, settings.sweeps_per_cut));
    return out;
  };
  const std::array<std::unique_ptr<EfgCutBody>, 2> bodies = {makeRunBody(settings, liver),
                                                             makeRunBody(settings, liver)};
  const Eigen::VectorXd x = bodies[0]->model().restPositions();
  double background_ms = 0.0;
  for (int c = 0; c < background_cuts; ++c)
    for (const BladeSweep& sweep : sweeps(c, -1.0))
      background_ms += bodies[1]->cut(sweep, x, x).times.update();
  if (info) {
    info->run = runInfo(bodies[0]->model(), liver);
    info->background_triangles = bodies[1]->surface().numTriangles();
    info->background_pieces = bodies[1]->volume().pieces();
    info->background_update_ms =
        background_cuts > 0
            ? background_ms / (static_cast<double>(background_cuts) * settings.sweeps_per_cut)
            : 0.0;
  }
  std::vector<EfgProbeSweepRecord> records;
  for (int c = 0; c < settings.cuts; ++c) {
    const std::vector<BladeSweep> probes = sweeps(c, 1.0);
    for (int s = 0; s < settings.sweeps_per_cut; ++s) {
      const BladeSweep& probe = probes[static_cast<std::size_t>(s)];
      EfgProbeSweepRecord r;
      r.cut = c;
      r.sweep = s;
      // Alternating which body goes first, so neither always meets the caches the other left.
      const int first = static_cast<int>(records.size() % 2);
      for (int k : {first, 1 - first}) {
        const EfgCutBody::Update u = bodies[static_cast<std::size_t>(k)]->cut(probe, x, x);
        EfgProbeSweepRecord::Body& b = r.body[static_cast<std::size_t>(k)];
        b.severed_links = static_cast<int>(u.volume.severed_links.size());
        b.crossed_edges = u.surface.crossed_edges;
        b.remapped = static_cast<int>(u.surface.remapped.size()) + u.remapped_after_volume;
        b.triangles = bodies[static_cast<std::size_t>(k)]->surface().numTriangles();
        b.times = u.times;
      }
      records.push_back(r);
    }
  }
  return records;
}

EfgCutFuzzReport runEfgCutFuzz(const EfgCutFuzzSettings& settings) {
  if (settings.sweeps < 1)
    throw std::invalid_argument("runEfgCutFuzz: sweeps = " + std::to_string(settings.sweeps) +
                                " must be >= 1");
  requirePositive("spacing", settings.spacing);
  const Eigen::Vector3d semi = settings.semi_axes;
  const TriMesh liver = makeLiverSurface(semi, settings.surface_subdivisions);
  EfgOptions options;
  options.spacing = settings.spacing;
  EfgCutBody body(liver, Material::create(5e3, 0.45, 1000.0), options, 2.0 * settings.spacing);
  const EfgModel& model = body.model();
  const double mass0 = totalMass(model);
  std::mt19937 rng(settings.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto point = [&] {
    return Eigen::Vector3d(semi.x() * u(rng), semi.y() * u(rng), semi.z() * u(rng));
  };
  EfgCutFuzzReport report;
  SliverCache slivers;
  double total_ms = 0.0;
  for (int i = 0; i < settings.sweeps && report.failure.empty(); ++i) {
    const int points = rng() % 2 ? 3 : 2;
    BladeSweep sweep;
    sweep.start.resize(3, points);
    for (int k = 0; k < points; ++k) sweep.start.col(k) = 1.2 * point();
    sweep.end = sweep.start.colwise() + 0.5 * point();
    const Eigen::Vector3d shift = 0.005 * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    Eigen::VectorXd x = model.restPositions();
    for (int p = 0; p < model.numNodes(); ++p) x.segment<3>(3 * p) += shift;
    const EfgCutBody::Update up = body.cut(sweep, x, x);
    total_ms += up.times.update();
    report.sweeps = i + 1;
    report.severed_links += static_cast<int>(up.volume.severed_links.size());
    report.crossed_edges += up.surface.crossed_edges;
    const auto fail = [&](const std::string& what) {
      report.failure = "sweep " + std::to_string(i) + ": " + what;
    };
    const double error = std::abs(totalMass(model) - mass0) / mass0;
    report.max_mass_error = std::max(report.max_mass_error, error);
    if (!model.lumpedMass().allFinite()) fail("non-finite mass");
    if (!(error <= 1e-12)) fail("mass error " + std::to_string(error));
    for (const int e : up.volume.changed_ips)
      if (!model.shapeValues(e).allFinite() || !model.shapeGradients(e).allFinite())
        fail("non-finite shape functions at IP " + std::to_string(e));
    const Eigen::Matrix3Xi tris = body.surface().triangles();
    const SurfaceClosure closure = checkSurfaceClosure(tris);
    if (closure.open_edges != 0 || closure.pinched_edges != 0)
      fail(std::to_string(closure.open_edges) + " open and " +
           std::to_string(closure.pinched_edges) + " pinched surface edges");
    if (!body.surfacePositions(x).allFinite()) fail("non-finite surface positions");
    if (report.failure.empty()) {
      const std::string side =
          wrongSide(body, slivers, report.planes_checked, report.sliver_vertices);
      if (!side.empty()) fail(side);
    }
    if (report.failure.empty()) {
      const std::string place = misplaced(body, kPlacedTolerance * settings.spacing);
      if (!place.empty()) fail(place);
    }
    if (report.failure.empty() && settings.passed) settings.passed(report.sweeps);
  }
  const EfgSurfaceCutter& surface = body.surface();
  report.pieces = body.volume().pieces();
  report.triangles = static_cast<int>(surface.triangles().cols());
  report.mean_update_ms = total_ms / report.sweeps;
  return report;
}

}  // namespace surgical_sim::bench
