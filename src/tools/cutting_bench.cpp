// P2 cutting benchmark (BENCHMARKS.md). Usage:
//   cutting_bench [--out DIR] [--fuzz N] [--no-plot]
//   cutting_bench --efg [--only PART] [--out DIR] [--fuzz N] [--cuts N] [--background N]
//                 [--no-step] [--no-plot]
// Writes into DIR (default "report"):
//   cutting_update.csv  per blade sweep: update mode (incremental, or the full rebuild it is
//                       tested against), mesh size, detection and topology-update time [ms]
//                       (progressive cuts through the organ blob at ~2k, 10k and 20k elements;
//                       10 parallel cuts of 60 sweeps of 1 mm each, 600 sweeps per size)
//   cutting_step.csv    per step of the palpation scene at ~10k elements while a blade cuts
//                       through it, for the direct and the real-time solver: step, cut,
//                       integrate time [ms], linear iterations
//   cutting_error.csv   cut-surface error (distance to the blade's swept plane) of the embedded
//                       cut surface and of the element faces of the cut, against update time
//   cutting_t3c.csv     T3(c) bend and stretch tip displacement of hexagonal beams cut at
//                       mid-length through half the width, EFG and tet cutter, against a fine
//                       Tet10 reference modelling the cut as duplicated nodes, with ms/step
//   cutting_fuzz.csv    the fuzz campaign (N random sweeps over the organ, default 1000)
//   cutting_*.png       plots (scripts/plot_cutting.py) unless --no-plot
// With --efg, the meshless (EFG) cutters on the liver-like body (makeLiverSurface) instead:
//   efg_cut_update.csv       per blade sweep at ~20k IPs with a 327,680-triangle surface (static
//                            tissue), run "update" (a 2 cm scalpel, ~1.1 mm a sweep) and
//                            "update_span" (a blade spanning the body): time of each phase of
//                            the cut update and of the surface positions [ms]
//   efg_cut_progressive.csv  per sweep of N progressive cuts (default 1000, a 2 cm scalpel, 10
//                            sweeps each) at ~10k IPs with a 20,480-triangle surface, one
//                            implicit Euler step per sweep (--solver, default cholmod) after 2 s
//                            of uncut steps: phase times, step time and its phases [ms], DOFs,
//                            mass error (--no-step: the body stays at rest, no step)
//   efg_cut_independence.csv per sweep of 20 probe cuts (as above, at rest) on a fresh body and on
//                            one that first took N cuts (--background) in its other half: the
//                            phase times of each (column body: fresh, after)
//   cutting_t3c.csv          as above
//   efg_cut_node.csv         per step of the node's path (TissueSimulation) on
//                            config/scenes/liver_efg.yaml: 10 scalpel cuts between settled
//                            steps; step, cut and integration times [ms], triangles, pieces
//   efg_cut_fuzz.csv         the EFG fuzz campaign (N random sweeps, both cutters)
//   efg_cut_*.png            plots (scripts/plot_efg_cutting.py) unless --no-plot
// Prints a summary. Exit code 1 if the fuzz campaign fails.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "package_dirs.h"
#include "surgical_sim/bench/cut_fuzz.h"
#include "surgical_sim/bench/efg_cutting.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace ss = surgical_sim::bench;

namespace {

const Eigen::Vector3d kOrgan(0.075, 0.05, 0.03);  // organ blob semi-axes [m]

/// Blade along y (wider than the organ) at x [m], moving down from z_from to z_to [m].
ss::BladeSweep bladeDown(double x, double z_from, double z_to) {
  ss::BladeSweep s;
  s.start.resize(3, 2);
  s.end.resize(3, 2);
  s.start << x, x, -0.1, 0.1, z_from, z_from;
  s.end << x, x, -0.1, 0.1, z_to, z_to;
  return s;
}

Eigen::VectorXd restVector(const ss::TetMesh& mesh) {
  return Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * mesh.numNodes());
}

double mean(const std::vector<double>& v, std::size_t from, std::size_t to) {
  double s = 0.0;
  for (std::size_t i = from; i < to; ++i) s += v[i];
  return to > from ? s / static_cast<double>(to - from) : NAN;
}

FILE* openCsv(const std::string& dir, const std::string& name, const char* header) {
  FILE* f = std::fopen((dir + "/" + name).c_str(), "w");
  if (!f) {
    std::cerr << "cutting_bench: cannot write " << dir << "/" << name << "\n";
    std::exit(2);
  }
  std::fprintf(f, "%s\n", header);
  return f;
}

/// 10 parallel cuts, each from the top to the bottom of the organ in 1 mm steps (a blade at
/// 10 cm/s with 10 ms steps; static tissue), with the incremental update and with the full
/// rebuild it is tested against.
void updateTimes(const std::string& dir) {
  FILE* csv =
      openCsv(dir, "cutting_update.csv",
              "mode,elements,sweep,edges_cut,topology_changed,detect_ms,update_ms,total_ms");
  for (int cells : {7, 12, 15})
    for (const ss::CutUpdateMode mode :
         {ss::CutUpdateMode::Incremental, ss::CutUpdateMode::Rebuild}) {
      const char* name = mode == ss::CutUpdateMode::Incremental ? "incremental" : "rebuild";
      surgical_sim::tools::progress("cutting_bench", std::string("update times, ") + name + ", " +
                                                         std::to_string(cells) + " cells");
      ss::TetCutter cutter(ss::makeOrganBlob(kOrgan, cells, ss::ElementType::Tet4), 1000.0, mode);
      const int elements = cutter.mesh().numElements();
      std::vector<double> changing;  // total time of sweeps that changed the topology [ms]
      int sweep = 0;
      for (int cut = 0; cut < 10; ++cut) {
        const double x = -0.055 + 0.0113 * cut + 0.0007;
        for (int k = 0; k < 60; ++k, ++sweep) {
          const double z0 = 0.03 - 0.001 * k, z1 = z0 - 0.001;
          const Eigen::VectorXd x_rest = restVector(cutter.mesh());
          const ss::CutUpdate u = cutter.cut(bladeDown(x, z0, z1), x_rest, x_rest);
          const double total = 1e3 * (u.detect_seconds + u.update_seconds);
          if (u.topology_changed) changing.push_back(total);
          std::fprintf(csv, "%s,%d,%d,%d,%d,%.4f,%.4f,%.4f\n", name, elements, sweep, u.edges_cut,
                       u.topology_changed ? 1 : 0, 1e3 * u.detect_seconds, 1e3 * u.update_seconds,
                       total);
        }
      }
      const std::size_t n = changing.size(), tenth = std::max<std::size_t>(1, n / 10);
      std::printf(
          "update  %6d elements, %-11s: %zu topology changes in %d sweeps, %d pieces, %d elements "
          "after; mean %.3f ms, first tenth %.3f ms, last tenth %.3f ms\n",
          elements, name, n, sweep, cutter.numComponents(), cutter.mesh().numElements(),
          mean(changing, 0, n), mean(changing, 0, tenth), mean(changing, n - tenth, n));
    }
  std::fclose(csv);
}

/// Palpation scene at 12 cells per axis (10,368 elements): 40 steps at rest, then a blade
/// descends through the organ in 1 mm steps over 60 steps, then 20 more steps; with the direct
/// solver of the scene (CHOLMOD, refactorized every step) and with the real-time one
/// (pcg_cholesky_background).
void stepTimes(const std::string& dir) {
  FILE* csv = openCsv(dir, "cutting_step.csv",
                      "solver,elements,step,cutting,topology_changed,step_ms,cut_ms,integrate_ms,"
                      "linear_iterations,pieces");
  for (const ss::SolverKind solver :
       {ss::SolverKind::Cholmod, ss::SolverKind::PcgCholeskyBackground}) {
    surgical_sim::tools::progress("cutting_bench",
                                  std::string("step times, ") + ss::solverName(solver));
    ss::RuntimeScene scene =
        ss::loadRuntimeScene(surgical_sim::tools::configDir() + "/scenes/palpation.yaml");
    scene.resolution = Eigen::Vector3i(12, 0, 0);
    scene.solver = solver;
    ss::TissueSimulation sim(scene);
    std::vector<double> cutting_steps, plain_steps, cut_parts;
    for (int step = 0; step < 120; ++step) {
      const bool cutting = step >= 40 && step < 100;
      if (cutting) {
        const double z0 = 0.03 - 0.001 * (step - 40);
        sim.requestCut(bladeDown(0.0031, z0, z0 - 0.001));
      }
      const ss::SimulationStepStats s = sim.step();
      (cutting ? cutting_steps : plain_steps).push_back(1e3 * s.step_seconds);
      if (s.topology_changed) cut_parts.push_back(1e3 * s.cut_seconds);
      std::fprintf(csv, "%s,%d,%d,%d,%d,%.4f,%.4f,%.4f,%d,%d\n", ss::solverName(solver),
                   sim.mesh().numElements(), step, cutting ? 1 : 0, s.topology_changed ? 1 : 0,
                   1e3 * s.step_seconds, 1e3 * s.cut_seconds, 1e3 * s.integrate_seconds,
                   s.report.linear_iterations, sim.numComponents());
    }
    // Steady state without cutting: after the tissue settled (steps 10-39).
    const std::vector<double> settled(plain_steps.begin() + 10, plain_steps.begin() + 40);
    std::printf(
        "step    %6d elements, %-23s: %.2f ms/step without cutting, %.2f ms/step while cutting "
        "(max %.2f ms; topology update, model and contact rebuild %.2f ms per change), %d pieces "
        "at the end\n",
        sim.mesh().numElements(), ss::solverName(solver), mean(settled, 0, settled.size()),
        mean(cutting_steps, 0, cutting_steps.size()),
        *std::max_element(cutting_steps.begin(), cutting_steps.end()),
        mean(cut_parts, 0, cut_parts.size()), sim.numComponents());
  }
  std::fclose(csv);
}

/// One oblique planar cut through the organ at several resolutions: distance of the embedded cut
/// surface and of the faces of the cut to the swept plane.
void surfaceError(const std::string& dir) {
  FILE* csv = openCsv(dir, "cutting_error.csv",
                      "elements,update_ms,embedded_max_m,embedded_rms_m,faces_max_m,faces_rms_m");
  // Blade along (0, 1, 0.3) moving along (0.2, 0, -1): the swept surface is the plane through
  // p0 with normal n.
  const Eigen::Vector3d p0(0.0131, -0.1, 0.05), along = Eigen::Vector3d(0, 1, 0.3).normalized();
  const Eigen::Vector3d motion(0.02, 0, -0.1);
  const Eigen::Vector3d n = along.cross(motion).normalized();
  for (int cells : {4, 6, 8, 10, 12, 15}) {
    surgical_sim::tools::progress("cutting_bench",
                                  "cut-surface error, " + std::to_string(cells) + " cells");
    ss::TetCutter cutter(ss::makeOrganBlob(kOrgan, cells, ss::ElementType::Tet4), 1000.0);
    ss::BladeSweep sweep;
    sweep.start.resize(3, 2);
    sweep.end.resize(3, 2);
    sweep.start << p0, p0 + 0.25 * along;
    sweep.end = sweep.start.colwise() + motion;
    const Eigen::VectorXd x = restVector(cutter.mesh());
    const ss::CutUpdate u = cutter.cut(sweep, x, x);
    auto distance = [&](const Eigen::Vector3d& p) { return std::abs(n.dot(p - p0)); };
    double emb_max = 0, emb_sq = 0, face_max = 0, face_sq = 0;
    int emb_n = 0, face_n = 0;
    const ss::TetMesh& mesh = cutter.mesh();
    for (const auto& tri : cutter.cutTriangles())
      for (const ss::EmbeddedCutPoint& p : tri) {
        const double d =
            distance((1 - p.w) * mesh.nodes.col(p.node_a) + p.w * mesh.nodes.col(p.node_b));
        emb_max = std::max(emb_max, d);
        emb_sq += d * d;
        ++emb_n;
      }
    const ss::SurfaceMesh& surface = cutter.surface();
    for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
      if (!cutter.cutFaces()[static_cast<std::size_t>(t)]) continue;
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) c += mesh.nodes.col(surface.triangles(k, t)) / 3.0;
      const double d = distance(c);
      face_max = std::max(face_max, d);
      face_sq += d * d;
      ++face_n;
    }
    const double ms = 1e3 * (u.detect_seconds + u.update_seconds);
    std::fprintf(csv, "%d,%.4f,%.3e,%.3e,%.3e,%.3e\n", mesh.numElements(), ms, emb_max,
                 std::sqrt(emb_sq / std::max(emb_n, 1)), face_max,
                 std::sqrt(face_sq / std::max(face_n, 1)));
    std::printf(
        "error   %6d elements: update %.2f ms, embedded max %.2e m, element faces rms %.2e m\n",
        mesh.numElements(), ms, emb_max, std::sqrt(face_sq / std::max(face_n, 1)));
  }
  std::fclose(csv);
}

/// T3(c): hexagonal beam (side a = 1 cm, length 10 a, E = 100 MPa) cut at mid-length from the top
/// down to the axis, bent by a transverse and stretched by an axial body force: the EFG cutter
/// (three cell sizes) and the tet cutter (three meshes) against a fine Tet10 mesh modelling the
/// cut as duplicated nodes.
void t3c(const std::string& dir) {
  const ss::CutBeam beam;
  FILE* csv = openCsv(dir, "cutting_t3c.csv",
                      "cutter,resolution,dofs,size,load,tip_m,reference_tip_m,error_rel,step_ms,"
                      "reference_dofs");
  const std::pair<const char*, Eigen::Vector3d> loads[] = {{"bend", {0, 0, -9.81}},
                                                           {"stretch", {9.81, 0, 0}}};
  for (const auto& [load_name, load] : loads) {
    surgical_sim::tools::progress("cutting_bench", std::string("T3(c) reference, ") + load_name);
    const ss::CutBeamRun ref = ss::cutBeamReference(beam, 60, 3, load);
    const auto row = [&](const char* cutter, const std::string& resolution,
                         const ss::CutBeamRun& r) {
      const double error = (r.tip - ref.tip) / ref.tip;
      std::fprintf(csv, "%s,%s,%d,%d,%s,%.6e,%.6e,%.5f,%.3f,%d\n", cutter, resolution.c_str(),
                   r.dofs, r.size, load_name, r.tip, ref.tip, error, r.step_ms, ref.dofs);
      std::printf(
          "T3(c)   %-7s %-10s %-12s %6d DOFs: tip %.4e m, reference %.4e m (%d DOFs), "
          "error %+.2f %%, %.2f ms/step\n",
          load_name, cutter, resolution.c_str(), r.dofs, r.tip, ref.tip, ref.dofs, 100 * error,
          r.step_ms);
    };
    for (const int k : {5, 10, 20}) {
      surgical_sim::tools::progress(
          "cutting_bench", std::string("T3(c) efg, ") + load_name + ", k = " + std::to_string(k));
      row("efg", "d=L/" + std::to_string(4 * k + 2), ss::efgCutBeam(beam, k, load));
    }
    for (auto [along, rings] : {std::pair{21, 2}, std::pair{31, 3}, std::pair{41, 4}}) {
      surgical_sim::tools::progress("cutting_bench", std::string("T3(c) tet cutter, ") + load_name +
                                                         ", " + std::to_string(along));
      row("tet4", std::to_string(along) + "x" + std::to_string(rings),
          ss::tetCutBeam(beam, along, rings, load));
    }
  }
  std::fclose(csv);
}

bool fuzz(const std::string& dir, int sweeps) {
  ss::CutFuzzSettings settings;
  settings.sweeps = sweeps;
  settings.cells_per_axis = 8;
  settings.seed = 6;
  surgical_sim::tools::progress("cutting_bench", "fuzz, " + std::to_string(sweeps) + " sweeps");
  const ss::CutFuzzReport r = ss::runCutFuzz(settings);
  FILE* csv = openCsv(dir, "cutting_fuzz.csv",
                      "sweeps,cells_per_axis,seed,failure,max_mass_error,min_rest_volume_m3,"
                      "cut_edges,pieces,pinched_edges,mean_update_ms,max_update_ms,finite");
  std::fprintf(csv, "%d,%d,%u,%s,%.3e,%.3e,%d,%d,%d,%.4f,%.4f,%d\n", r.sweeps,
               settings.cells_per_axis, settings.seed,
               r.failure.empty() ? "none" : r.failure.c_str(), r.max_mass_error, r.min_rest_volume,
               r.cut_edges, r.components, r.pinched_edges, r.mean_update_ms, r.max_update_ms,
               r.finite ? 1 : 0);
  std::fclose(csv);
  std::printf(
      "fuzz    %d sweeps: %s, max mass error %.1e, min volume %.2e m^3, %d pieces, "
      "finite %s\n",
      r.sweeps, r.failure.empty() ? "no failure" : r.failure.c_str(), r.max_mass_error,
      r.min_rest_volume, r.components, r.finite ? "yes" : "no");
  return r.failure.empty() && r.finite;
}

/// Means of the update phases and of the step over the sweeps added [ms].
struct EfgMeans {
  double positions = 0, volume = 0, surface = 0, remap = 0, total = 0, detect = 0, step = 0;
  int count = 0;
  double topology() const { return total - detect; }
  void add(const ss::EfgCutBody::Times& t, double step_ms) {
    positions += t.positions_ms;
    volume += t.volume_ms;
    surface += t.surface_ms;
    remap += t.remap_ms;
    total += t.update();
    detect += t.detect_ms;
    step += step_ms;
    ++count;
  }
  /// The sums divided by the count (left as they are without a sweep).
  EfgMeans mean() const {
    EfgMeans m = *this;
    const double n = std::max(count, 1);
    for (double* v : {&m.positions, &m.volume, &m.surface, &m.remap, &m.total, &m.detect, &m.step})
      *v /= n;
    return m;
  }
};

/// Means over records [from, to).
EfgMeans efgMeans(const std::vector<ss::EfgCutSweepRecord>& r, std::size_t from, std::size_t to) {
  EfgMeans m;
  for (std::size_t i = from; i < to; ++i) m.add(r[i].times, r[i].step_ms);
  return m.mean();
}

void writeEfgRecords(FILE* csv, const char* run, const std::vector<ss::EfgCutSweepRecord>& records,
                     const ss::EfgCutRunInfo& info, const std::string& solver) {
  for (const ss::EfgCutSweepRecord& r : records)
    std::fprintf(
        csv,
        "%s,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%.3e,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%s,"
        "%d,%.4f,%.4f,%.4f,%.4f\n",
        run, info.ips, info.surface_triangles, r.cut, r.sweep, r.severed_links, r.changed_ips,
        r.crossed_edges, r.ignored_crossings, r.remapped, r.triangles, r.dofs, r.pieces,
        r.finite ? 1 : 0, r.mass_error, r.times.positions_ms, r.times.volume_ms, r.times.surface_ms,
        r.times.remap_ms, r.times.update(), r.times.detect_ms, r.times.topology(), r.step_ms,
        solver.c_str(), r.linear_iterations, 1e3 * r.phases.forces, 1e3 * r.phases.assembly,
        1e3 * r.phases.factorization, 1e3 * r.phases.linear_solve);
}

constexpr const char* kEfgHeader =
    "run,ips,surface_triangles,cut,sweep,severed_links,changed_ips,crossed_edges,ignored_crossings,"
    "remapped,triangles,dofs,pieces,finite,mass_error,positions_ms,volume_ms,surface_ms,remap_ms,"
    "update_ms,detect_ms,topology_ms,step_ms,solver,linear_iterations,forces_ms,assembly_ms,"
    "factorization_ms,solve_ms";

/// (a) Cut update on ~20k IPs (d = 2.4 mm) with a 327,680-triangle surface, static tissue, 5
/// cuts through the top half each: a scalpel (2 cm blade, 30 sweeps of about 1.1 mm a cut: the
/// per-frame update) and a blade spanning the body (10 sweeps a cut).
void efgUpdateTimes(const std::string& dir) {
  FILE* csv = openCsv(dir, "efg_cut_update.csv", kEfgHeader);
  for (const bool scalpel : {true, false}) {
    const char* run = scalpel ? "update" : "update_span";
    surgical_sim::tools::progress("cutting_bench",
                                  std::string("EFG ") + run + ", ~20k IPs, 327,680 triangles");
    ss::EfgCutRunSettings s;
    s.surface_subdivisions = 7;
    s.spacing = 0.0024;
    s.front_width = 0.003;
    s.cuts = 5;
    s.sweeps_per_cut = scalpel ? 30 : 10;
    s.blade_length = scalpel ? 0.02 : 0.0;
    s.simulate = false;
    ss::EfgCutRunInfo info;
    const std::vector<ss::EfgCutSweepRecord> records = ss::runEfgProgressiveCuts(s, &info);
    writeEfgRecords(csv, run, records, info, "none");
    std::vector<ss::EfgCutSweepRecord> cutting;
    for (const ss::EfgCutSweepRecord& r : records)
      if (r.severed_links > 0 || r.crossed_edges > 0) cutting.push_back(r);
    const EfgMeans m = efgMeans(cutting, 0, cutting.size());
    double worst = 0;
    for (const ss::EfgCutSweepRecord& r : cutting) worst = std::max(worst, r.times.update());
    std::printf(
        "efg %-11s %d IPs, %d particles, %d triangles: %zu of %zu sweeps cut; mean cut update "
        "%.3f ms (volume %.3f, surface %.3f, remap %.3f) = detection %.3f + topology %.3f ms, "
        "worst %.2f ms; surface positions %.2f ms\n",
        run, info.ips, info.particles, info.surface_triangles, cutting.size(), records.size(),
        m.total, m.volume, m.surface, m.remap, m.detect, m.topology(), worst, m.positions);
    std::fflush(stdout);
  }
  std::fclose(csv);
}

/// Uncut steps of the progressive run before its first cut (2 s at dt = 0.01 s).
constexpr int kSettleSteps = 200;

/// `cuts` cuts of a 2 cm scalpel at ~10k IPs (d = 3 mm), 10 sweeps each, 30 % of the height deep.
ss::EfgCutRunSettings scalpelCuts(int cuts) {
  ss::EfgCutRunSettings s;
  s.spacing = 0.003;
  s.front_width = 0.004;
  s.cuts = cuts;
  s.sweeps_per_cut = 10;
  s.blade_length = 0.02;
  s.depth = 0.3;
  return s;
}

/// (b, c) `cuts` progressive cuts at ~10k IPs (d = 3 mm) with one implicit step per sweep: a 2 cm
/// scalpel descending 2.1 mm a sweep, 10 sweeps a cut, after kSettleSteps uncut steps (the liver
/// sags onto its clamp and its lobes swing for about a second: not the cutting's cost).
/// steps false: the body stays at rest (no settling, no step): the cut update alone.
void efgProgressive(const std::string& dir, int cuts, ss::SolverKind solver, bool steps) {
  surgical_sim::tools::progress(
      "cutting_bench", "EFG progressive cuts, ~10k IPs, " + std::to_string(cuts) + " cuts");
  ss::EfgCutRunSettings s = scalpelCuts(cuts);
  s.solver = solver;
  s.settle_steps = kSettleSteps;
  s.simulate = steps;
  ss::EfgCutRunInfo info;
  const std::vector<ss::EfgCutSweepRecord> records = ss::runEfgProgressiveCuts(s, &info);
  FILE* csv = openCsv(dir, "efg_cut_progressive.csv", kEfgHeader);
  writeEfgRecords(csv, "progressive", records, info, enumName(ss::kSolverNames, solver));
  std::fclose(csv);
  const std::size_t n = records.size(), tenth = std::max<std::size_t>(1, n / 10);
  const EfgMeans first = efgMeans(records, 0, tenth), last = efgMeans(records, n - tenth, n);
  double max_mass = 0;
  bool finite = true, same_dofs = true;
  for (const ss::EfgCutSweepRecord& r : records) {
    max_mass = std::max(max_mass, r.mass_error);
    finite = finite && r.finite;
    same_dofs = same_dofs && r.dofs == 3 * info.particles;
  }
  const EfgMeans all = efgMeans(records, 0, n);
  char step[160] = "no steps";
  if (steps)
    std::snprintf(step, sizeof step,
                  "step %.2f / %.2f ms; mean step %.2f ms (uncut, settled: %.2f ms)", first.step,
                  last.step, all.step, info.settled_step_ms);
  std::printf(
      "efg cuts   %d IPs, %d particles: %d cuts, %zu sweeps, %d pieces; first/last tenth: cut "
      "update %.2f / %.2f ms (topology %.2f / %.2f ms), %s; DOFs %s, max mass error %.1e, "
      "finite %s\n",
      info.ips, info.particles, cuts, n, records.empty() ? 0 : records.back().pieces, first.total,
      last.total, first.topology(), last.topology(), step, same_dofs ? "unchanged" : "CHANGED",
      max_mass, finite ? "yes" : "no");
}

bool efgFuzz(const std::string& dir, int sweeps) {
  surgical_sim::tools::progress("cutting_bench", "EFG fuzz, " + std::to_string(sweeps) + " sweeps");
  ss::EfgCutFuzzSettings settings;
  settings.sweeps = sweeps;
  settings.seed = 19;
  settings.passed = [](int done) {
    if (done % 50 == 0)
      surgical_sim::tools::progress("cutting_bench",
                                    "EFG fuzz, " + std::to_string(done) + " sweeps passed");
  };
  const ss::EfgCutFuzzReport r = ss::runEfgCutFuzz(settings);
  FILE* csv = openCsv(dir, "efg_cut_fuzz.csv",
                      "sweeps,seed,failure,max_mass_error,severed_links,crossed_edges,pieces,"
                      "triangles,planes_checked,sliver_vertices,mean_update_ms");
  std::fprintf(csv, "%d,%u,%s,%.3e,%d,%d,%d,%d,%lld,%d,%.4f\n", r.sweeps, settings.seed,
               r.failure.empty() ? "none" : r.failure.c_str(), r.max_mass_error, r.severed_links,
               r.crossed_edges, r.pieces, r.triangles, r.planes_checked, r.sliver_vertices,
               r.mean_update_ms);
  std::fclose(csv);
  std::printf(
      "efg fuzz   %d sweeps: %s, max mass error %.1e, %d links severed, %d surface edges cut, "
      "%d pieces, %lld vertex-plane sides checked (%d sliver vertices without an IP on their "
      "side), "
      "mean update %.2f ms\n",
      r.sweeps, r.failure.empty() ? "no failure" : r.failure.c_str(), r.max_mass_error,
      r.severed_links, r.crossed_edges, r.pieces, r.planes_checked, r.sliver_vertices,
      r.mean_update_ms);
  return r.failure.empty();
}

/// The node's path (TissueSimulation, as tissue_simulator runs it) on config/scenes/liver_efg.yaml
/// (20,480-triangle surface; its tool posed 20 cm above, touching nothing): 40 steps to settle,
/// 10 parallel scalpel cuts (a 6 cm blade along x descending 6 mm a step from 6 cm above the
/// organ's centre to its clamp, 12 steps each), then 20 steps. Per step: step, cut (both cutters,
/// surface and mapping adoption, model and contact update) and integration times.
void efgNode(const std::string& dir) {
  surgical_sim::tools::progress("cutting_bench", "EFG node path, liver_efg.yaml");
  ss::TissueSimulation sim(
      ss::loadRuntimeScene(surgical_sim::tools::configDir() + "/scenes/liver_efg.yaml"));
  Eigen::Isometry3d above = Eigen::Isometry3d::Identity();
  above.translation().z() = 0.2;
  for (int t = 0; t < sim.numTools(); ++t) sim.setToolPose(t, above);
  FILE* csv = openCsv(dir, "efg_cut_node.csv",
                      "step,phase,topology_changed,step_ms,cut_ms,integrate_ms,triangles,pieces,"
                      "status");
  const int triangles = static_cast<int>(sim.surface().triangles.cols());
  std::vector<double> settled, cutting, cut;
  int step = 0, not_ok = 0;
  const auto run = [&](const char* phase, const ss::BladeSweep* sweep) {
    if (sweep) sim.requestCut(*sweep);
    const ss::SimulationStepStats st = sim.step();
    not_ok += st.report.status != ss::StepStatus::Ok;
    if (std::string(phase) == "settle" && step >= 20) settled.push_back(1e3 * st.step_seconds);
    if (st.topology_changed) {
      cutting.push_back(1e3 * st.step_seconds);
      cut.push_back(1e3 * st.cut_seconds);
    }
    std::fprintf(csv, "%d,%s,%d,%.4f,%.4f,%.4f,%ld,%d,%s\n", step++, phase,
                 st.topology_changed ? 1 : 0, 1e3 * st.step_seconds, 1e3 * st.cut_seconds,
                 1e3 * st.integrate_seconds, static_cast<long>(sim.surface().triangles.cols()),
                 sim.numComponents(), ss::toString(st.report.status));
  };
  for (int k = 0; k < 40; ++k) run("settle", nullptr);
  for (int c = 0; c < 10; ++c) {
    const double y = -0.04 + 0.009 * c + 0.0003;  // off the particle grid planes
    for (int k = 0; k < 12; ++k) {
      ss::BladeSweep sweep;
      sweep.start.resize(3, 2);
      const double z0 = 0.06 - 0.006 * k;
      sweep.start << -0.03, 0.03, y, y, z0, z0;
      sweep.end = sweep.start;
      sweep.end.row(2).setConstant(z0 - 0.006);
      run("cut", &sweep);
    }
  }
  for (int k = 0; k < 20; ++k) run("after", nullptr);
  std::fclose(csv);
  std::printf(
      "efg node   liver_efg.yaml: settled step %.2f ms; %zu steps that cut: step %.2f ms, of "
      "which cut %.2f ms; %d -> %ld triangles, %d steps not ok\n",
      mean(settled, 0, settled.size()), cutting.size(), mean(cutting, 0, cutting.size()),
      mean(cut, 0, cut.size()), triangles, static_cast<long>(sim.surface().triangles.cols()),
      not_ok);
}

/// Probe cuts per body of the independence run (10 sweeps each).
constexpr int kProbeCuts = 20;

/// (d) Independence of the cut cost from earlier cuts: at ~10k IPs at rest, kProbeCuts probe cuts
/// (as in (b, c)) on a fresh body and, sweep by sweep, on a body that first took
/// `background_cuts` cuts in its other half.
void efgIndependence(const std::string& dir, int background_cuts) {
  surgical_sim::tools::progress(
      "cutting_bench",
      "EFG cut independence, ~10k IPs, " + std::to_string(background_cuts) + " background cuts");
  ss::EfgCutRunSettings s = scalpelCuts(kProbeCuts);
  s.simulate = false;
  ss::EfgCutIndependenceInfo info;
  const std::vector<ss::EfgProbeSweepRecord> records =
      ss::runEfgCutIndependence(s, background_cuts, &info);
  FILE* csv = openCsv(dir, "efg_cut_independence.csv",
                      "run,ips,surface_triangles,background_cuts,cut,sweep,body,severed_links,"
                      "crossed_edges,remapped,triangles,positions_ms,volume_ms,surface_ms,"
                      "remap_ms,update_ms,detect_ms,topology_ms");
  // Means over the sweeps that cut the fresh body, on each body [ms].
  std::array<EfgMeans, 2> sums;
  for (const ss::EfgProbeSweepRecord& r : records) {
    const bool cuts = r.body[0].severed_links > 0 || r.body[0].crossed_edges > 0;
    for (std::size_t k = 0; k < 2; ++k) {
      const ss::EfgProbeSweepRecord::Body& b = r.body[k];
      const auto& t = b.times;
      std::fprintf(csv, "probe,%d,%d,%d,%d,%d,%s,%d,%d,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                   info.run.ips, info.run.surface_triangles, background_cuts, r.cut, r.sweep,
                   k ? "after" : "fresh", b.severed_links, b.crossed_edges, b.remapped, b.triangles,
                   t.positions_ms, t.volume_ms, t.surface_ms, t.remap_ms, t.update(), t.detect_ms,
                   t.topology());
      if (cuts) sums[k].add(t, 0.0);
    }
  }
  std::fclose(csv);
  const EfgMeans fresh = sums[0].mean(), after = sums[1].mean();
  std::printf(
      "efg indep. %d IPs: %d probe cuts (%d sweeps cut) on a fresh body and on one after %d "
      "background cuts (%d triangles, was %d; %d pieces, %.2f ms a background sweep): mean cut "
      "update %.3f / %.3f ms (ratio %.3f; detection %.3f / %.3f, topology %.3f / %.3f); surface "
      "positions %.2f / %.2f ms\n",
      info.run.ips, kProbeCuts, fresh.count, background_cuts, info.background_triangles,
      info.run.surface_triangles, info.background_pieces, info.background_update_ms, fresh.total,
      after.total, after.total / fresh.total, fresh.detect, after.detect, fresh.topology(),
      after.topology(), fresh.positions, after.positions);
  std::fflush(stdout);
}

constexpr const char* kUsage =
    "usage: cutting_bench [--efg [--only PART] [--no-step]] [--out DIR] [--fuzz N] [--cuts N]\n"
    "                     [--background N] [--no-plot]\n"
    "P2 cutting benchmark: topology-update and step times, cut-surface error, T3(c) cut beams and\n"
    "a fuzz campaign of random blade sweeps; CSV files (and PNG plots) in DIR.\n"
    "  --efg       the meshless (EFG) cutters on the liver-like body: cut-update phase times,\n"
    "              progressive cuts with implicit steps, independence from earlier cuts, T3(c),\n"
    "              fuzz\n"
    "  --only PART with --efg: only update, progressive, independence, t3c, node or fuzz\n"
    "  --out DIR   output folder, created if missing (default ./report)\n"
    "  --fuzz N    random sweeps of the fuzz campaign, >= 1 (default 1000)\n"
    "  --cuts N    progressive cuts of --efg, >= 1 (default 1000)\n"
    "  --background N\n"
    "              cuts before the probes of the --efg independence run, >= 1 (default 100;\n"
    "              300 grow that half's surface to ~390k triangles: docs/benchmarks.md)\n"
    "  --solver S  linear solver of the progressive cuts' steps (default cholmod)\n"
    "  --no-step   with --efg: progressive cuts of the body at rest, the cut update alone\n"
    "  --no-plot   CSV only\n";

}  // namespace

int main(int argc, char** argv) {
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  std::string dir = "report";
  int sweeps = 1000, cuts = 1000, background = 100;
  bool plot = true, efg = false, steps = true;
  ss::SolverKind solver = ss::SolverKind::Cholmod;
  std::string only;  // --efg part to run alone, "" for all
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out" && i + 1 < argc) {
      dir = argv[++i];
    } else if ((arg == "--fuzz" || arg == "--cuts" || arg == "--background") && i + 1 < argc) {
      const std::string value = argv[++i];
      const std::optional<int> count = surgical_sim::tools::parseCount(value);
      if (!count) {
        std::cerr << "cutting_bench: " << arg << " '" << value
                  << "' is not a whole number from 1 to " << std::numeric_limits<int>::max()
                  << "\n";
        return 2;
      }
      (arg == "--fuzz" ? sweeps : arg == "--cuts" ? cuts : background) = *count;
    } else if (arg == "--solver" && i + 1 < argc) {
      const std::string name = argv[++i];
      const auto kind = ss::enumFromName(ss::kSolverNames, name);
      if (!kind) {
        std::cerr << "cutting_bench: --solver " << name << " is not one of "
                  << ss::enumNames(ss::kSolverNames) << "\n";
        return 2;
      }
      solver = *kind;
    } else if (arg == "--efg") {
      efg = true;
    } else if (arg == "--only" && i + 1 < argc) {
      only = argv[++i];
    } else if (arg == "--no-plot") {
      plot = false;
    } else if (arg == "--no-step") {
      steps = false;
    } else {
      std::cerr << "cutting_bench: unknown argument " << arg << "\n" << kUsage;
      return 2;
    }
  }
  if (!only.empty() &&
      (!efg || (only != "update" && only != "progressive" && only != "independence" &&
                only != "t3c" && only != "node" && only != "fuzz"))) {
    std::cerr << "cutting_bench: --only " << only
              << " needs --efg and one of update, progressive, independence, t3c, node, fuzz\n";
    return 2;
  }
  if (!steps && (!efg || (!only.empty() && only != "progressive"))) {
    std::cerr << "cutting_bench: --no-step needs --efg and the progressive cuts (no --only, or "
                 "--only progressive)\n";
    return 2;
  }
  // Before any work: a benchmark that runs for minutes must not fail only when it writes.
  std::error_code made;
  std::filesystem::create_directories(dir, made);
  if (made || !std::filesystem::is_directory(dir)) {
    std::cerr << "cutting_bench: cannot create the output folder " << dir
              << (made ? ": " + made.message() : std::string(": not a folder")) << "\n";
    return 2;
  }
  try {
    if (efg) {
      const auto runs = [&](const char* part) { return only.empty() || only == part; };
      if (runs("update")) efgUpdateTimes(dir);
      if (runs("progressive")) efgProgressive(dir, cuts, solver, steps);
      if (runs("independence")) efgIndependence(dir, background);
      if (runs("t3c")) t3c(dir);
      if (runs("node")) efgNode(dir);
      const bool ok = !runs("fuzz") || efgFuzz(dir, sweeps);
      if (plot) surgical_sim::tools::runPlotScript("cutting_bench", "plot_efg_cutting.py", {dir});
      return ok ? 0 : 1;
    }
    updateTimes(dir);
    stepTimes(dir);
    surfaceError(dir);
    t3c(dir);
    const bool ok = fuzz(dir, sweeps);
    if (plot) {
      surgical_sim::tools::runPlotScript("cutting_bench", "plot_cutting.py", {dir});
      surgical_sim::tools::runPlotScript("cutting_bench", "plot_efg_cutting.py", {dir});
    }
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "cutting_bench: " << e.what() << "\n";
    return 2;
  }
}
