#include "surgical_sim/bench/contact_rate_study.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/haptics/local_contact_model.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

Eigen::Vector3d StiffeningTissue::force(const Eigen::Vector3d& p_W) const {
  const double d = -(p_W - surface_point_W).dot(normal_W);
  if (d <= 0.0) return Eigen::Vector3d::Zero();
  return (k1 * d + k3 * d * d * d) * normal_W;
}

Eigen::Matrix3d StiffeningTissue::stiffness(const Eigen::Vector3d& p_W) const {
  const double d = -(p_W - surface_point_W).dot(normal_W);
  if (d <= 0.0) return Eigen::Matrix3d::Zero();
  return -(k1 + 3.0 * k3 * d * d) * normal_W * normal_W.transpose();
}

void validateContactRateStudySettings(const ContactRateStudySettings& s) {
  requireNonNegative("contact_rate_study.tissue.k1", s.tissue.k1, "N/m");
  requireNonNegative("contact_rate_study.tissue.k3", s.tissue.k3, "N/m^3");
  if (!s.tissue.normal_W.allFinite() || std::abs(s.tissue.normal_W.norm() - 1.0) > 1e-9)
    throw std::invalid_argument(
        "contact_rate_study.tissue.normal_W is out of range: must be a finite unit vector");
  if (!s.tissue.surface_point_W.allFinite())
    throw std::invalid_argument(
        "contact_rate_study.tissue.surface_point_W is out of range: must be finite [m]");
  requirePositive("contact_rate_study.update_rate_hz", s.update_rate_hz, "Hz");
  requireInRange("contact_rate_study.loop_rate_hz", s.loop_rate_hz, s.update_rate_hz, 1e5, "Hz");
  requireNonNegative("contact_rate_study.latency_updates", s.latency_updates, "");
  requireFinite("contact_rate_study.mean_depth", s.mean_depth, "m");
  requireNonNegative("contact_rate_study.amplitude", s.amplitude, "m");
  requirePositive("contact_rate_study.frequency", s.frequency, "Hz");
  requirePositive("contact_rate_study.duration", s.duration, "s");
}

ContactRateStudyResult runContactRateStudy(const ContactRateStudySettings& s) {
  validateContactRateStudySettings(s);
  const auto toolTip = [&s](double t) -> Eigen::Vector3d {
    const double depth = s.mean_depth + s.amplitude * std::sin(2.0 * M_PI * s.frequency * t);
    return s.tissue.surface_point_W - depth * s.tissue.normal_W;
  };
  LocalContactSettings contact_settings;
  contact_settings.max_age = 0.5;
  contact_settings.stale_policy = StalePolicy::Hold;
  LocalContactModel model(contact_settings);

  ContactRateStudyResult result;
  const double update_period = 1.0 / s.update_rate_hz;
  const double latency = s.latency_updates * update_period;
  const int ticks = static_cast<int>(std::floor(s.duration * s.loop_rate_hz));
  int next_update = 0;
  double sum_error_sq = 0.0, sum_true_sq = 0.0;
  for (int n = 0; n < ticks; ++n) {
    const double t = n / s.loop_rate_hz;
    // Publish every model that has become visible by t (built at t_k, visible at t_k + latency).
    while (next_update * update_period + latency <= t + 1e-12) {
      const double t_k = next_update * update_period;
      LocalContactSample sample;
      sample.stamp = t_k;
      sample.p0_W = toolTip(t_k);
      sample.f0_W = s.tissue.force(sample.p0_W);
      sample.K_W = s.linear_model ? s.tissue.stiffness(sample.p0_W) : Eigen::Matrix3d::Zero();
      model.update(sample);
      ++next_update;
      ++result.updates;
    }
    const Eigen::Vector3d p = toolTip(t);
    const ContactEvaluation eval = model.evaluate(p, t);
    if (eval.status == ContactStatus::NoModel) continue;  // start-up, before the first model
    ++result.ticks;
    if (eval.status == ContactStatus::Stale) ++result.stale_ticks;
    const Eigen::Vector3d f_true = s.tissue.force(p);
    const double error = (eval.force_W - f_true).norm();
    sum_error_sq += error * error;
    sum_true_sq += f_true.squaredNorm();
    result.max_error = std::max(result.max_error, error);
  }
  result.rms_true_force = std::sqrt(sum_true_sq / std::max(1, result.ticks));
  result.force_error_rel = sum_true_sq > 0.0 ? std::sqrt(sum_error_sq / sum_true_sq) : 0.0;
  return result;
}

}  // namespace surgical_sim::bench
