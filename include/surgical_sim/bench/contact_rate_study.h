#pragma once

#include <Eigen/Core>

namespace surgical_sim::bench {

/// Synthetic stiffening tissue for the H1 force-error study: a half-space with outward unit
/// normal n through surface_point s; penetration d = -(p - s) . n [m]; force on the tool
///   f(p) = (k1 d + k3 d^3) n  for d > 0, zero otherwise [N],
/// stiffness df/dp = -(k1 + 3 k3 d^2) n n^T [N/m] (3x3), world frame.
struct StiffeningTissue {
  double k1 = 200.0;                                          ///< linear stiffness [N/m], >= 0
  double k3 = 2e6;                                            ///< cubic stiffening [N/m^3], >= 0
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();        ///< outward normal n [-], unit
  Eigen::Vector3d surface_point_W = Eigen::Vector3d::Zero();  ///< point s on the surface [m]

  /// Force on the tool at p_W [N].
  Eigen::Vector3d force(const Eigen::Vector3d& p_W) const;
  /// Stiffness df/dp at p_W [N/m], 3x3.
  Eigen::Matrix3d stiffness(const Eigen::Vector3d& p_W) const;
};

/// One case of the force-error-vs-tissue-update-rate study.
struct ContactRateStudySettings {
  StiffeningTissue tissue;
  double update_rate_hz = 60.0;  ///< tissue (contact-model) update rate R [Hz], > 0
  double loop_rate_hz = 1000.0;  ///< haptic loop rate L [Hz], >= update_rate_hz
  /// Each model is built from the tool position at t_k = k / R and becomes visible to the loop
  /// latency_updates / R later (1: the tissue step takes one update period) [-], >= 0.
  double latency_updates = 1.0;
  /// true: render f0 + K (p - p0) (local linear model); false: zero-order hold of f0.
  bool linear_model = true;
  double mean_depth = 0.005;  ///< mean penetration of the sinusoidal tool motion [m]
  double amplitude = 0.005;   ///< amplitude of the motion along -n [m], >= 0
  double frequency = 2.0;     ///< motion frequency [Hz], > 0
  double duration = 5.0;      ///< simulated time [s], > 0
};

/// @throws std::invalid_argument naming "contact_rate_study.<field>".
void validateContactRateStudySettings(const ContactRateStudySettings& settings);

/// Result of one case.
struct ContactRateStudyResult {
  double force_error_rel = 0.0;  ///< RMS |f_rendered - f_true| / RMS |f_true| over the ticks [-]
  double rms_true_force = 0.0;   ///< RMS |f_true| [N]
  double max_error = 0.0;        ///< max |f_rendered - f_true| [N]
  int ticks = 0;                 ///< haptic ticks evaluated (those with a model)
  int updates = 0;               ///< contact models published
  int stale_ticks = 0;           ///< ticks whose model was flagged stale
};

/// Runs one case deterministically through LocalContactModel (Hold policy, max_age 0.5 s).
/// Ticks before the first model becomes visible (start-up) are not scored.
/// The tool tip moves as p(t) = s - (mean_depth + amplitude sin(2 pi frequency t)) n.
/// @throws std::invalid_argument if the settings are invalid.
ContactRateStudyResult runContactRateStudy(const ContactRateStudySettings& settings);

}  // namespace surgical_sim::bench
