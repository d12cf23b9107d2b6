// trocar_bench: headless H1 benchmark of the active-trocar haptic loop (no ROS).
// Usage: trocar_bench [--seconds S] [--rt-priority P] [--csv FILE] [--plot FILE]
//  1. runs HapticLoop at 1 kHz (the trocar of urdf/active_trocar.urdf) for S seconds (default 3)
//  with a moving operator and a 60 Hz
//     contact model, prints period mean / p99 / max deviation / missed ticks;
//  2. the stiff wall (5 kN/m) with and without the passivity controller: energy summary;
//  3. rendered-force error vs tissue update rate (30..500 Hz) for a stiffening contact, zero-order
//     hold of f0 vs local linear model f0 + K dx: one CSV row per case (stdout and --csv), plot
//     with scripts/plot_haptics.py (--plot, needs --csv).
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>

#include "bench_cli.h"
#include "package_dirs.h"
#include "surgical_sim/bench/contact_rate_study.h"
#include "surgical_sim/bench/stiff_wall_simulation.h"
#include "surgical_sim/core/common/text_file.h"
#include "surgical_sim/core/haptics/haptic_loop.h"
#include "surgical_sim/core/haptics/trocar_urdf.h"

namespace {

using namespace surgical_sim::bench;

constexpr const char* kUsage =
    "usage: trocar_bench [--seconds S] [--rt-priority P] [--csv FILE] [--plot FILE]\n"
    "H1 benchmark of the active-trocar haptic loop (no ROS): loop timing, stiff wall with and\n"
    "without passivity control, rendered-force error against the tissue update rate.\n"
    "  --seconds S      loop timing duration [s], (0, 3600], default 3\n"
    "  --rt-priority P  SCHED_FIFO priority of the loop, [0, 99], default 0 (none)\n"
    "  --csv FILE       rendered-force error rows\n"
    "  --plot FILE      their plot (PNG; needs --csv)\n";

int usage(const std::string& msg) {
  std::cerr << "trocar_bench: " << msg << "\n" << kUsage;
  return 2;
}

void runLoopTiming(double seconds, int rt_priority) {
  HapticRendererConfig config;
  const TrocarUrdf trocar =
      readTrocarUrdf(readTextFile(surgical_sim::tools::packageDir() + "/urdf/active_trocar.urdf"),
                     TrocarUrdfNames::forTrocar("trocar"));
  config.chain = trocar.chain;
  config.device = makeTrocarDeviceConfig(trocar, chendebPrototypeMotors());
  config.coupling.stiffness = 3000.0;
  config.coupling.damping = 2.0;
  HapticLoop loop(config, 1 << 16, rt_priority);
  const TrocarKinematics kinematics(config.chain);
  StiffeningTissue tissue;  // surface 0.14 m below the fulcrum, normal toward it
  tissue.normal_W = -Eigen::Vector3d::UnitZ();
  tissue.surface_point_W = Eigen::Vector3d(0.0, 0.0, 0.14);

  TrocarJointVector q;
  q << 0.1, -0.05, 0.0, 0.13, 0.2;
  loop.setJointCommand(q);
  loop.start();
  const auto t0 = std::chrono::steady_clock::now();
  int step = 0;
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < seconds) {
    const double t = 0.005 * step;
    // Operator motion at 200 Hz; tissue contact model at 60 Hz (every third command).
    q[kTrocarInsertion] = 0.135 + 0.01 * std::sin(2.0 * M_PI * 1.0 * t);
    q[kTrocarPitch] = 0.1 + 0.05 * std::sin(2.0 * M_PI * 0.5 * t);
    loop.setJointCommand(q);
    if (step % 3 == 0) {
      LocalContactSample sample;
      sample.stamp = loop.now();
      sample.p0_W = kinematics.toolTipPose(q).translation();
      sample.f0_W = tissue.force(sample.p0_W);
      sample.K_W = tissue.stiffness(sample.p0_W);
      loop.setContactModel(sample);
    }
    ++step;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  loop.stop();
  const LoopStatistics s = loop.statistics();
  const HapticOutput out = loop.latestOutput();
  std::cout << "H1 loop timing (" << seconds << " s at " << 1.0 / s.nominal_period << " Hz): ticks "
            << s.ticks << ", period mean " << 1e6 * s.period_mean << " us, p99 "
            << 1e6 * s.period_p99 << " us, max deviation " << 1e6 * s.max_deviation
            << " us, missed ticks " << s.missed_ticks << " (ring of " << s.samples
            << " periods, SCHED_FIFO " << (loop.realtimeGranted() ? "on" : "off") << ")\n"
            << "  last output: insertion effort " << out.effort[kTrocarInsertion]
            << " N, pitch effort " << out.effort[kTrocarPitch] << " N m, contact age "
            << 1e3 * out.contact_age << " ms\n";
}

void runStiffWall() {
  for (const bool passivity : {false, true}) {
    StiffWallSettings settings;
    settings.passivity = passivity;
    const StiffWallResult r = simulateStiffWall(settings);
    double min_observed = 0.0;
    for (const StiffWallSample& sample : r.history)
      min_observed = std::min(min_observed, sample.observer_energy);
    std::cout << "H1 stiff wall k = " << settings.wall_stiffness << " N/m, "
              << (passivity ? "with" : "without") << " passivity control: energy initial "
              << 1e3 * r.initial_energy << " mJ, max " << 1e3 * r.max_energy
              << " mJ, max over last third " << 1e3 * r.late_max_energy << " mJ, min E_obs "
              << 1e3 * min_observed << " mJ, dissipated " << 1e3 * r.dissipated_energy
              << " mJ, max penetration " << 1e3 * r.max_penetration << " mm\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  std::string csv_path, plot_path;
  double seconds = 3.0;
  int rt_priority = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--csv" || arg == "--plot" || arg == "--seconds" || arg == "--rt-priority") &&
        i + 1 < argc) {
      const std::string value = argv[++i];
      if (arg == "--csv") csv_path = value;
      if (arg == "--plot") plot_path = value;
      if (arg == "--seconds") {
        std::istringstream in(value);
        if (!(in >> seconds) || !(seconds > 0.0) || seconds > 3600.0)
          return usage("--seconds must be in (0, 3600]");
      }
      if (arg == "--rt-priority") {
        std::istringstream in(value);
        if (!(in >> rt_priority) || rt_priority < 0 || rt_priority > 99)
          return usage("--rt-priority must be in [0, 99]");
      }
    } else {
      return usage("unknown argument " + arg);
    }
  }
  if (!plot_path.empty() && csv_path.empty()) return usage("--plot needs --csv");
  std::ofstream csv;
  if (!surgical_sim::tools::openCsv("trocar_bench", csv_path, csv)) return 1;

  surgical_sim::tools::progress("trocar_bench", "loop timing, " + std::to_string(seconds) + " s");
  runLoopTiming(seconds, rt_priority);
  surgical_sim::tools::progress("trocar_bench", "stiff wall without and with passivity control");
  runStiffWall();

  const std::string header =
      "case,model,update_rate_hz,loop_rate_hz,ms_per_update,force_error_rel,status";
  std::cout << header << "\n";
  if (csv) csv << header << "\n";
  for (const double rate : {30.0, 60.0, 120.0, 250.0, 500.0}) {
    for (const bool linear : {false, true}) {
      surgical_sim::tools::progress("trocar_bench",
                                    std::string("contact rate study, ") +
                                        (linear ? "local_linear" : "zero_order_hold") + " at " +
                                        std::to_string(rate) + " Hz");
      ContactRateStudySettings settings;
      settings.update_rate_hz = rate;
      settings.linear_model = linear;
      std::ostringstream row;
      row << "stiffening_contact," << (linear ? "local_linear" : "zero_order_hold") << "," << rate
          << "," << settings.loop_rate_hz << "," << 1e3 / rate << ",";
      const ContactRateStudyResult r = runContactRateStudy(settings);
      row << r.force_error_rel << "," << (std::isfinite(r.force_error_rel) ? "ok" : "non_finite");
      std::cout << row.str() << "\n";
      if (csv) csv << row.str() << "\n";
    }
  }
  if (!plot_path.empty()) {
    csv.close();
    if (!surgical_sim::tools::runPlotScript("trocar_bench", "plot_haptics.py",
                                            {csv_path, plot_path})) {
      return 1;
    }
  }
  return 0;
}
