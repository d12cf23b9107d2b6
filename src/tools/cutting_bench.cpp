// P2 cutting benchmark (BENCHMARKS.md). Usage:
//   cutting_bench [--out DIR] [--fuzz N] [--no-plot]
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
//   cutting_t3c.csv     T3(c) tip deflection of hexagonal beams cut at mid-length through half the
//                       width, against a fine reference modelling the cut as duplicated nodes
//   cutting_fuzz.csv    the fuzz campaign (N random sweeps over the organ, default 1000)
//   cutting_*.png       plots (scripts/plot_cutting.py) unless --no-plot
// Prints a summary. Exit code 1 if the fuzz campaign fails.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "package_dirs.h"
#include "surgical_sim/bench/beam_tip_deflection.h"
#include "surgical_sim/bench/cut_fuzz.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"
#include "surgical_sim/core/tissue/model_factory.h"

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

/// T3(c): hexagonal beam (side a, length 10 a) under a transverse body force, cut at mid-length
/// from the top down to the axis. Reference: a fine mesh with a node layer at mid-length whose
/// nodes above the axis are duplicated for the elements beyond it.
void t3c(const std::string& dir) {
  const double a = 0.01, L = 0.1;
  const ss::Material material = ss::Material::create(1e6, 0.3, 1000.0);
  const Eigen::Vector3d load(0, 0, -9.81);
  ss::TetMesh ref = ss::makeHexagonalBeam(a, L, 40, 4, ss::ElementType::Tet4);
  const double w_ref_uncut =
      ss::beamTipDeflection(*ss::makeTissueModel(ss::ModelKind::Corotational, ref, material), load);
  std::vector<int> duplicate(static_cast<std::size_t>(ref.numNodes()), -1);
  for (int e = 0; e < ref.numElements(); ++e) {
    double cx = 0;
    for (int i = 0; i < 4; ++i) cx += ref.nodes(0, ref.elements(i, e)) / 4;
    if (cx < 0.5 * L) continue;
    for (int i = 0; i < 4; ++i) {
      const int v = ref.elements(i, e);
      if (std::abs(ref.nodes(0, v) - 0.5 * L) > 1e-9 * L || ref.nodes(2, v) < 1e-9 * a) continue;
      int& d = duplicate[static_cast<std::size_t>(v)];
      if (d < 0) {
        d = ref.numNodes();
        ref.nodes.conservativeResize(3, d + 1);
        ref.nodes.col(d) = ref.nodes.col(v);
      }
      ref.elements(i, e) = d;
    }
  }
  const double w_ref =
      ss::beamTipDeflection(*ss::makeTissueModel(ss::ModelKind::Corotational, ref, material), load);
  const double A = 1.5 * std::sqrt(3.0) * a * a, I = 5.0 * std::sqrt(3.0) / 16.0 * a * a * a * a;
  const double w_closed = 1000.0 * 9.81 * A * std::pow(L, 4) / (8.0 * material.young_modulus * I);
  FILE* csv = openCsv(dir, "cutting_t3c.csv",
                      "elements,cells_along,rings,w_uncut_m,w_cut_m,w_ref_cut_m,error_cut_rel,"
                      "w_ref_uncut_m,w_closed_form_uncut_m,cut_update_ms");
  for (auto [along, rings] : {std::pair{11, 1}, std::pair{21, 2}, std::pair{31, 3}}) {
    surgical_sim::tools::progress("cutting_bench", "T3(c) cut beam, " + std::to_string(along) +
                                                       " cells along, " + std::to_string(rings) +
                                                       " rings");
    const ss::TetMesh beam = ss::makeHexagonalBeam(a, L, along, rings, ss::ElementType::Tet4);
    ss::TetCutter cutter(beam, material.density);
    const double w_uncut = ss::beamTipDeflection(
        *ss::makeCutTissueModel(ss::ModelKind::Corotational, cutter, material), load);
    const Eigen::VectorXd x = restVector(beam);
    ss::BladeSweep sweep;
    sweep.start.resize(3, 2);
    sweep.end.resize(3, 2);
    sweep.start << 0.5 * L, 0.5 * L, -2 * a, 2 * a, 2 * a, 2 * a;
    sweep.end << 0.5 * L, 0.5 * L, -2 * a, 2 * a, 1e-6 * a, 1e-6 * a;
    const ss::CutUpdate u = cutter.cut(sweep, x, x);
    const double w_cut = ss::beamTipDeflection(
        *ss::makeCutTissueModel(ss::ModelKind::Corotational, cutter, material), load);
    std::fprintf(csv, "%d,%d,%d,%.6e,%.6e,%.6e,%.4f,%.6e,%.6e,%.4f\n", beam.numElements(), along,
                 rings, w_uncut, w_cut, w_ref, (w_cut - w_ref) / w_ref, w_ref_uncut, w_closed,
                 1e3 * (u.detect_seconds + u.update_seconds));
    std::printf(
        "T3(c)   %6d elements: tip %.3e m uncut, %.3e m cut, reference %.3e m (error %+.1f %%)\n",
        beam.numElements(), w_uncut, w_cut, w_ref, 100 * (w_cut - w_ref) / w_ref);
  }
  std::printf("T3(c)   reference %d elements: uncut %.3e m (closed form %.3e m), cut %.3e m\n",
              ref.numElements(), w_ref_uncut, w_closed, w_ref);
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

constexpr const char* kUsage =
    "usage: cutting_bench [--out DIR] [--fuzz N] [--no-plot]\n"
    "P2 cutting benchmark: topology-update and step times, cut-surface error, T3(c) cut beams and\n"
    "a fuzz campaign of random blade sweeps; CSV files (and PNG plots) in DIR.\n"
    "  --out DIR   output folder (default ./report)\n"
    "  --fuzz N    random sweeps of the fuzz campaign, >= 1 (default 1000)\n"
    "  --no-plot   CSV only\n";

}  // namespace

int main(int argc, char** argv) {
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  std::string dir = "report";
  int sweeps = 1000;
  bool plot = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out" && i + 1 < argc) {
      dir = argv[++i];
    } else if (arg == "--fuzz" && i + 1 < argc) {
      sweeps = std::atoi(argv[++i]);
    } else if (arg == "--no-plot") {
      plot = false;
    } else {
      std::cerr << "cutting_bench: unknown argument " << arg << "\n" << kUsage;
      return 2;
    }
  }
  if (sweeps < 1) {
    std::cerr << "cutting_bench: --fuzz must be >= 1\n";
    return 2;
  }
  try {
    updateTimes(dir);
    stepTimes(dir);
    surfaceError(dir);
    t3c(dir);
    const bool ok = fuzz(dir, sweeps);
    if (plot) {
      surgical_sim::tools::runPlotScript("cutting_bench", "plot_cutting.py", {dir});
    }
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "cutting_bench: " << e.what() << "\n";
    return 2;
  }
}
