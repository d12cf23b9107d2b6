#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Local linear contact model published by the tissue simulator (topic tissue/contact_model), all
/// in the world frame W: the force on the tool is f(p) = f0 + K (p - p0) near p0.
struct LocalContactSample {
  double stamp = 0.0;                              ///< time the model is valid at [s]
  Eigen::Vector3d p0_W = Eigen::Vector3d::Zero();  ///< linearization point (tool tip) [m], W
  Eigen::Vector3d f0_W = Eigen::Vector3d::Zero();  ///< force of the tissue on the tool [N], W
  Eigen::Matrix3d K_W = Eigen::Matrix3d::Zero();   ///< stiffness df/dp [N/m], W, 3x3
};

/// What LocalContactModel does with a model older than max_age.
enum class StalePolicy {
  Fade,  ///< scale the force linearly to zero over fade_time, then render zero
  Hold,  ///< keep rendering the last model unchanged (flagged stale)
};

/// Settings of LocalContactModel.
struct LocalContactSettings {
  double max_age = 0.1;     ///< a model older than this is stale [s], > 0
  double fade_time = 0.05;  ///< Fade: time to ramp from full force to zero [s], >= 0
  StalePolicy stale_policy = StalePolicy::Fade;
};

/// @throws std::invalid_argument naming "haptics.contact.max_age" or "haptics.contact.fade_time".
void validateLocalContactSettings(const LocalContactSettings& settings);

/// Status of one contact-model evaluation.
enum class ContactStatus {
  NoModel,    ///< no model received yet: zero force
  Fresh,      ///< age <= max_age
  Stale,      ///< age > max_age: faded or held according to the policy
  NonFinite,  ///< NaN/Inf in the model or the query point: zero force
};

/// Result of LocalContactModel::evaluate, in W.
struct ContactEvaluation {
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();      ///< rendered force f(p) [N]
  Eigen::Matrix3d stiffness_W = Eigen::Matrix3d::Zero();  ///< weight * K [N/m], 3x3
  double weight = 0.0;     ///< fade factor applied to the model [-], in [0, 1]
  double age = 0.0;        ///< now - stamp [s] (0 when there is no model)
  bool separated = false;  ///< the expansion pointed against f0: contact released, zero force
  ContactStatus status = ContactStatus::NoModel;
};

/// Evaluates the latest local linear contact model at the tool tip, f(p) = w (f0 + K (p - p0)),
/// with a staleness weight w: 1 while fresh, then (Fade) 1 - (age - max_age) / fade_time clamped
/// to [0, 1], or (Hold) 1. The contact is unilateral: where f(p) . f0 < 0 (the tool has moved
/// out past the point where the expansion changes sign) the force and stiffness are zero
/// (flagged `separated`). A model stamped in the future counts as age 0. Not thread-safe; the
/// haptic loop owns one. update() and evaluate() allocate nothing and never throw.
class LocalContactModel {
 public:
  /// @throws std::invalid_argument if the settings are invalid.
  explicit LocalContactModel(const LocalContactSettings& settings);

  /// Replaces the model by sample (any content is accepted; a non-finite one evaluates to zero).
  void update(const LocalContactSample& sample) noexcept;
  /// Forgets the model (evaluate() returns NoModel).
  void clear() noexcept;
  bool hasModel() const noexcept { return has_model_; }
  const LocalContactSample& sample() const noexcept { return sample_; }

  /// Force at the tool-tip position p_WT [m], W, at time now [s] (same clock as the stamps).
  ContactEvaluation evaluate(const Eigen::Vector3d& p_WT, double now) const noexcept;

 private:
  LocalContactSettings settings_;
  LocalContactSample sample_;
  bool has_model_ = false;
  bool sample_finite_ = true;
};

}  // namespace surgical_sim::core
