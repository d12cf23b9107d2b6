#include "surgical_sim/core/haptics/local_contact_model.h"

#include <algorithm>
#include <cmath>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validateLocalContactSettings(const LocalContactSettings& settings) {
  requirePositive("haptics.contact.max_age", settings.max_age, "s");
  requireNonNegative("haptics.contact.fade_time", settings.fade_time, "s");
}

LocalContactModel::LocalContactModel(const LocalContactSettings& settings) : settings_(settings) {
  validateLocalContactSettings(settings_);
}

void LocalContactModel::update(const LocalContactSample& sample) noexcept {
  sample_ = sample;
  has_model_ = true;
  sample_finite_ = std::isfinite(sample.stamp) && sample.p0_W.allFinite() &&
                   sample.f0_W.allFinite() && sample.K_W.allFinite();
}

void LocalContactModel::clear() noexcept { has_model_ = false; }

ContactEvaluation LocalContactModel::evaluate(const Eigen::Vector3d& p_WT,
                                              double now) const noexcept {
  ContactEvaluation out;
  if (!has_model_) return out;
  if (!sample_finite_ || !p_WT.allFinite() || !std::isfinite(now)) {
    out.status = ContactStatus::NonFinite;
    return out;
  }
  out.age = std::max(0.0, now - sample_.stamp);
  out.weight = 1.0;
  out.status = ContactStatus::Fresh;
  if (out.age > settings_.max_age) {
    out.status = ContactStatus::Stale;
    if (settings_.stale_policy == StalePolicy::Fade) {
      const double excess = out.age - settings_.max_age;
      out.weight = settings_.fade_time > 0.0
                       ? std::clamp(1.0 - excess / settings_.fade_time, 0.0, 1.0)
                       : 0.0;
    }
  }
  out.stiffness_W = out.weight * sample_.K_W;
  out.force_W = out.weight * (sample_.f0_W + sample_.K_W * (p_WT - sample_.p0_W));
  // Tissue pushes, it never pulls: an expansion pointing against f0 means the tool has left the
  // surface the model linearized, and extrapolating K past it would render adhesion.
  if (out.force_W.dot(sample_.f0_W) < 0.0) {
    out.force_W.setZero();
    out.stiffness_W.setZero();
    out.separated = true;
  }
  if (!out.force_W.allFinite()) {
    out.force_W.setZero();
    out.stiffness_W.setZero();
    out.weight = 0.0;
    out.status = ContactStatus::NonFinite;
  }
  return out;
}

}  // namespace surgical_sim::core
