// Benchmark R1 / R2 (BENCHMARKS.md): inverse control of continuum robots. No ROS.
//
// Usage: robot_bench [config/continuum_robot.yaml] [output_dir (default report)] [R1|R2|all]
// Writes <output_dir>/robot_bench.csv (one row per control step), robot_cases.csv (one row per
// tracking case: model and FE-plant tip error mean/max, solve time per control step mean/max),
// robot_summary.csv (effector error vs solve time as the iteration caps vary) and
// robot_bench.png (scripts/plot_robot.py).
//
// Plane choice: the backbone is +x of robot_base, so the tip moves across the y-z plane; the
// paths lie in the plane x = x_tip_rest + dx (dx = +10 mm for the pressure trunk, which always
// extends when pressurized; -1.5 mm for the cable robot, which shortens when cables are pulled:
// bending it 10 mm aside shortens it by about 0.5 mm, the rest comes from cable compression).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "package_dirs.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/robot/compliance_cache.h"
#include "surgical_sim/core/robot/continuum_robot_loader.h"
#include "surgical_sim/core/robot/full_fe_plant.h"
#include "surgical_sim/core/robot/inverse_controller.h"

namespace ss = surgical_sim::core;

namespace {

/// CPU time of the calling thread [ms]: the solve cost without the waiting a shared (loaded)
/// machine adds to the wall-clock time.
double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * t.tv_sec + 1e-6 * t.tv_nsec;
}

/// Circle of radius r [m] in the plane x = center.x, sampled every speed*dt along the arc.
std::vector<Eigen::Vector3d> circlePath(const Eigen::Vector3d& center, double r, double speed,
                                        double dt) {
  const int n = static_cast<int>(std::ceil(2.0 * M_PI * r / (speed * dt)));
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i <= n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    out.push_back(center + Eigen::Vector3d(0.0, r * std::cos(a), r * std::sin(a)));
  }
  return out;
}

/// Square of side a [m] centred on center in its y-z plane.
std::vector<Eigen::Vector3d> squarePath(const Eigen::Vector3d& center, double a, double speed,
                                        double dt) {
  const double h = 0.5 * a;
  const Eigen::Vector2d corners[5] = {{h, h}, {-h, h}, {-h, -h}, {h, -h}, {h, h}};
  const int per_side = static_cast<int>(std::ceil(a / (speed * dt)));
  std::vector<Eigen::Vector3d> out;
  for (int s = 0; s < 4; ++s)
    for (int i = 0; i < per_side + (s == 3 ? 1 : 0); ++i) {
      const Eigen::Vector2d q = corners[s] + (corners[s + 1] - corners[s]) * i / per_side;
      out.push_back(center + Eigen::Vector3d(0.0, q.x(), q.y()));
    }
  return out;
}

struct Robot {
  ss::ContinuumRobotDescription description;
  std::unique_ptr<ss::ContinuumRobotModel> model;
  std::unique_ptr<ss::FullFePlant> plant;
};

Robot makeRobot(const std::string& config, const std::string& name) {
  surgical_sim::tools::progress("robot_bench",
                                name + ": condensing sections, building the FE plant");
  Robot r;
  r.description = ss::loadContinuumRobot(config, name);
  const ss::SectionCompliances c =
      ss::computeSectionCompliances(r.description, ss::ComplianceCache::defaultDirectory());
  std::fprintf(stderr, "%s: %d sections condensed in %.2f s (%d cache hits)\n", name.c_str(),
               r.description.num_vertebrae, c.seconds, c.cache_hits);
  r.model = std::make_unique<ss::ContinuumRobotModel>(r.description, c);
  ss::FullFePlantSettings ps;
  ps.newton.max_iterations = 30;
  ps.follower_tolerance = 1e-5;
  r.plant = std::make_unique<ss::FullFePlant>(*r.model, ps);
  std::fprintf(stderr, "%s: FE plant with %d nodes\n", name.c_str(), r.plant->numNodes());
  return r;
}

struct RunStats {
  double error_sum = 0.0, error_max = 0.0, ms_sum = 0.0, ms_max = 0.0, cpu_ms_sum = 0.0;
  double plant_sum = 0.0, plant_max = 0.0;
  int steps = 0, plant_steps = 0;
};

/// Follows `path`; evaluates the FE plant every plant_stride steps (0: never). Rows go to csv.
RunStats follow(Robot& robot, const std::string& case_name, const std::string& path_name,
                const std::vector<Eigen::Vector3d>& path, double tolerance, int max_iterations,
                const ss::ModelSolveSettings& model_settings, int plant_stride, FILE* csv) {
  surgical_sim::tools::progress(
      "robot_bench", case_name + " " + robot.description.name + " " + path_name + ", " +
                         std::to_string(path.size()) + " targets, " +
                         std::to_string(max_iterations) + " QP / " +
                         std::to_string(model_settings.max_iterations) + " Newton iterations" +
                         (plant_stride > 0 ? ", FE plant" : ""));
  ss::InverseControllerSettings cs;
  cs.model = model_settings;
  ss::InverseController controller(*robot.model, cs);
  robot.plant->reset();
  ss::InverseResult result;
  result.actuation = controller.actuation();
  RunStats st;
  for (size_t i = 0; i < path.size(); ++i) {
    const ss::Stopwatch clock;
    const double cpu0 = threadCpuMs();
    controller.solveTarget(path[i], tolerance, max_iterations, result);
    const double ms = clock.milliseconds(), cpu_ms = threadCpuMs() - cpu0;
    double plant_error = NAN;
    if (plant_stride > 0 && (i % plant_stride == 0 || i + 1 == path.size())) {
      robot.plant->solve(result.actuation);
      plant_error = (robot.plant->tipPosition() - path[i]).norm();
      st.plant_sum += plant_error;
      st.plant_max = std::max(st.plant_max, plant_error);
      ++st.plant_steps;
    }
    if (i > 0) {  // the first step moves from rest onto the path; not a tracking step
      st.error_sum += result.effector_error;
      st.error_max = std::max(st.error_max, result.effector_error);
      st.ms_sum += ms;
      st.cpu_ms_sum += cpu_ms;
      st.ms_max = std::max(st.ms_max, ms);
      ++st.steps;
    }
    if (csv)
      std::fprintf(csv, "%s,%s,%s,%zu,%.6f,%.6f,%.6f,%.6e,%.6e,%.3f,%.3f,%d,%s\n",
                   case_name.c_str(), robot.description.name.c_str(), path_name.c_str(), i,
                   path[i].x(), path[i].y(), path[i].z(), result.effector_error, plant_error, ms,
                   cpu_ms, result.qp_iterations, ss::toString(result.status));
  }
  return st;
}

/// The benchmark proper (main() reports its exceptions).
int runBench(int argc, char** argv) {
  const std::string config =
      argc > 1 ? argv[1] : surgical_sim::tools::configDir() + "/continuum_robot.yaml";
  const std::string out_dir = argc > 2 ? argv[2] : "report";
  const std::string cases_to_run = argc > 3 ? argv[3] : "all";
  if (cases_to_run != "all" && cases_to_run != "R1" && cases_to_run != "R2") {
    std::fprintf(stderr, "third argument must be R1, R2 or all, got '%s'\n", cases_to_run.c_str());
    return 2;
  }
  std::system(("mkdir -p '" + out_dir + "'").c_str());
  FILE* csv = std::fopen((out_dir + "/robot_bench.csv").c_str(), "w");
  FILE* summary = std::fopen((out_dir + "/robot_summary.csv").c_str(), "w");
  FILE* cases = std::fopen((out_dir + "/robot_cases.csv").c_str(), "w");
  if (!csv || !summary || !cases) {
    std::fprintf(stderr, "cannot write to %s\n", out_dir.c_str());
    return 1;
  }
  std::fprintf(csv,
               "case,robot,path,step,target_x,target_y,target_z,model_error_m,plant_error_m,"
               "solve_ms,solve_cpu_ms,qp_iterations,status\n");
  std::fprintf(summary,
               "case,robot,path,max_iterations,newton_iterations,mean_error_m,max_error_m,"
               "mean_solve_ms,max_solve_ms,mean_solve_cpu_ms\n");
  std::fprintf(
      cases,
      "case,robot,path,steps,model_mean_error_m,model_max_error_m,plant_samples,"
      "plant_mean_error_m,plant_max_error_m,mean_solve_ms,max_solve_ms,mean_solve_cpu_ms\n");
  const double dt = 0.1;  // control period [s] (10 Hz)
  const double tol = 1e-4;
  const ss::ModelSolveSettings full_newton;
  // (QP iterations, Newton iterations) caps of the error-vs-solve-time sweep.
  const int caps[][2] = {{1, 100}, {2, 100}, {3, 100}, {10, 100}, {1, 2}, {3, 3}};

  const auto report = [cases](const char* case_name, const char* robot, const char* path,
                              const RunStats& s) {
    const double model_mean = s.error_sum / std::max(1, s.steps);
    const double plant_mean = s.plant_sum / std::max(1, s.plant_steps);
    const double ms_mean = s.ms_sum / std::max(1, s.steps);
    const double cpu_mean = s.cpu_ms_sum / std::max(1, s.steps);
    std::printf(
        "%s %-6s %-7s steps %4d  model err mean %.3e max %.3e m  plant err mean %.3e max %.3e m"
        " (%d samples)  solve mean %.2f max %.2f ms (CPU %.2f ms)\n",
        case_name, robot, path, s.steps, model_mean, s.error_max, plant_mean, s.plant_max,
        s.plant_steps, ms_mean, s.ms_max, cpu_mean);
    std::fprintf(cases, "%s,%s,%s,%d,%.6e,%.6e,%d,%.6e,%.6e,%.4f,%.4f,%.4f\n", case_name, robot,
                 path, s.steps, model_mean, s.error_max, s.plant_steps, plant_mean, s.plant_max,
                 ms_mean, s.ms_max, cpu_mean);
  };
  // Effector error vs solve time as the (QP, Newton) iteration caps vary, no plant.
  const auto sweep = [&](Robot& robot, const char* case_name, const char* path_name,
                         const std::vector<Eigen::Vector3d>& path) {
    for (const auto& cap : caps) {
      ss::ModelSolveSettings ms;
      ms.max_iterations = cap[1];
      const RunStats s = follow(robot, case_name, path_name, path, tol, cap[0], ms, 0, nullptr);
      std::fprintf(summary, "%s,%s,%s,%d,%d,%.6e,%.6e,%.3f,%.3f,%.3f\n", case_name,
                   robot.description.name.c_str(), path_name, cap[0], cap[1], s.error_sum / s.steps,
                   s.error_max, s.ms_sum / s.steps, s.ms_max, s.cpu_ms_sum / s.steps);
    }
  };
  // Follows the circle and the square path with the full-Newton model, checking against the FE
  // plant every `*_stride` steps.
  const auto followBoth = [&](Robot& robot, const char* case_name, const char* robot_name,
                              const std::vector<Eigen::Vector3d>& circle,
                              const std::vector<Eigen::Vector3d>& square, int circle_stride,
                              int square_stride) {
    report(case_name, robot_name, "circle",
           follow(robot, case_name, "circle", circle, tol, 10, full_newton, circle_stride, csv));
    report(case_name, robot_name, "square",
           follow(robot, case_name, "square", square, tol, 10, full_newton, square_stride, csv));
  };
  // ---- R1: trunk ------------------------------------------------------------------------------
  if (cases_to_run != "R2") {
    Robot trunk = makeRobot(config, "trunk");
    const Eigen::Vector3d c1 = trunk.model->restNodes().back().p_BN + Eigen::Vector3d(0.01, 0, 0);
    const auto circle = circlePath(c1, 0.060, 0.025, dt);
    const auto square = squarePath(c1, 0.080, 0.031, dt);
    followBoth(trunk, "R1", "trunk", circle, square, 75, 52);
    std::vector<Eigen::Vector3d> coarse;
    for (size_t i = 0; i < circle.size(); i += 3) coarse.push_back(circle[i]);
    sweep(trunk, "R1", "circle_coarse", coarse);
  }

  // ---- R2: cable robot ------------------------------------------------------------------------
  if (cases_to_run != "R1") {
    Robot cable = makeRobot(config, "cable");
    const Eigen::Vector3d tip0 = cable.model->restNodes().back().p_BN;
    const Eigen::Vector3d c2 = tip0 + Eigen::Vector3d(-0.0015, 0, 0);
    // The 150 mm cable robot bends only ~10-15 mm aside with its 3 N cables (less between two
    // cables), so R1's 60 mm circle is out of reach: the paths are scaled to its workspace
    // (circle R = 10 mm at 1 cm/s, square of side 14 mm at 1.2 cm/s).
    const auto cable_circle = circlePath(c2, 0.010, 0.01, dt);
    const auto cable_square = squarePath(c2, 0.014, 0.012, dt);
    followBoth(cable, "R2", "cable", cable_circle, cable_square, 8, 8);
    sweep(cable, "R2", "circle", cable_circle);
    // Unreachable (beyond the tip along the axis: cables can only shorten the robot) and binding
    // bounds (lateral target beyond what 3 N can bend).
    const std::vector<Eigen::Vector3d> special = {tip0, tip0 + Eigen::Vector3d(0.03, 0.0, 0.0),
                                                  tip0 + Eigen::Vector3d(-0.03, 0.09, 0.0)};
    const std::vector<std::string> names = {"rest", "unreachable_axial", "bounds_bind_lateral"};
    for (size_t i = 0; i < special.size(); ++i) {
      surgical_sim::tools::progress("robot_bench", "R2 cable " + names[i]);
      ss::InverseController controller(*cable.model, ss::InverseControllerSettings{});
      const ss::Stopwatch clock;
      const double cpu0 = threadCpuMs();
      const ss::InverseResult r = controller.solveTarget(special[i], tol, 30);
      const double ms = clock.milliseconds(), cpu_ms = threadCpuMs() - cpu0;
      cable.plant->reset();
      cable.plant->solve(r.actuation);
      const double plant_error = (cable.plant->tipPosition() - special[i]).norm();
      std::fprintf(csv, "R2,cable,%s,0,%.6f,%.6f,%.6f,%.6e,%.6e,%.3f,%.3f,%d,%s\n",
                   names[i].c_str(), special[i].x(), special[i].y(), special[i].z(),
                   r.effector_error, plant_error, ms, cpu_ms, r.qp_iterations,
                   ss::toString(r.status));
      std::printf("R2 %-22s status %-12s model err %.3e m plant err %.3e m  %.2f ms  tensions",
                  names[i].c_str(), ss::toString(r.status), r.effector_error, plant_error, ms);
      for (int a = 0; a < r.actuation.size(); ++a) std::printf(" %.3f", r.actuation[a]);
      std::printf(" N\n");
    }
  }
  std::fclose(csv);
  std::fclose(summary);
  std::fclose(cases);
  surgical_sim::tools::runPlotScript("robot_bench", "plot_robot.py", {out_dir});
  return 0;
}

constexpr const char* kUsage =
    "usage: robot_bench [robot.yaml [out_dir [R1|R2|all]]]\n"
    "R1/R2 continuum-robot benchmarks: inverse-control error and time against the full FE plant;\n"
    "CSV files and plots in out_dir. Progress on stderr.\n"
    "  robot.yaml  robot descriptions (default: the package's config/continuum_robot.yaml)\n"
    "  out_dir     output folder (default ./report)\n"
    "  R1|R2|all   cases to run (default all)\n";

}  // namespace

int main(int argc, char** argv) {
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (argc > 1 && argv[1][0] == '-') {
    std::fprintf(stderr, "robot_bench: unknown option %s\n%s", argv[1], kUsage);
    return 2;
  }
  try {
    return runBench(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robot_bench: %s\n", e.what());
    return 1;
  }
}
