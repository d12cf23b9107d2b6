#include "surgical_sim/core/haptics/haptic_renderer.h"

#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {

void validateHapticRendererConfig(const HapticRendererConfig& config) {
  validateTrocarChain(config.chain);
  validateTrocarDeviceConfig(config.device);
  validateLocalContactSettings(config.contact);
  validateVirtualCouplingSettings(config.coupling);
  validatePassivityControllerSettings(config.passivity);
  requireInRange("haptics.rate_hz", config.rate_hz, 100.0, 20000.0, "Hz");
  const Eigen::Matrix3d R = config.X_WF.linear();
  if (!config.X_WF.matrix().allFinite() ||
      !(R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-9) || R.determinant() < 0.0) {
    throw std::invalid_argument(
        "haptics.X_WF is out of range: must be a finite rigid transform (rotation orthonormal, "
        "det +1)");
  }
}

HapticRenderer::HapticRenderer(const HapticRendererConfig& config)
    : config_((validateHapticRendererConfig(config), config)),
      kinematics_(config_.chain),
      device_(config_.device),
      contact_(config_.contact),
      coupling_(config_.coupling),
      passivity_(config_.passivity),
      dt_(1.0 / config_.rate_hz) {}

void HapticRenderer::setContactSample(const LocalContactSample& sample) noexcept {
  contact_.update(sample);
}

void HapticRenderer::reset() noexcept {
  has_previous_ = false;
  passivity_.reset();
  output_ = HapticOutput();
}

const HapticOutput& HapticRenderer::update(const TrocarJointVector& q_command,
                                           double now) noexcept {
  HapticOutput& out = output_;
  out.tick += 1;
  out.time = now;

  // Sensing: limits, encoder quantization, forward kinematics.
  TrocarJointVector q = q_command;
  out.joints_clamped = device_.clampToLimits(q);
  out.q_measured = device_.quantize(q);
  const Eigen::Isometry3d X_FT = kinematics_.toolTipPose(out.q_measured);
  out.X_WT = config_.X_WF * X_FT;
  const Eigen::Vector3d p_WT = out.X_WT.translation();
  if (!has_previous_) {
    p_WT_previous_ = p_WT;
    coupling_.reset(p_WT);
    has_previous_ = true;
  }
  out.v_WT = (p_WT - p_WT_previous_) / dt_;
  p_WT_previous_ = p_WT;

  // Environment at the proxy, coupled to the device tip.
  const Eigen::Vector3d p_WP = coupling_.proxyPosition();
  const ContactEvaluation contact = contact_.evaluate(p_WP, now);
  out.contact_status = contact.status;
  out.contact_age = contact.age;
  out.f_contact_W = contact.force_W;
  Eigen::Vector3d f_W =
      coupling_.step(p_WT, out.v_WT, contact.force_W, contact.stiffness_W, p_WP, dt_);
  out.p_WP = coupling_.proxyPosition();

  // Passivity, then effort mapping and saturation.
  f_W = passivity_.step(f_W, out.v_WT, dt_);
  out.passivity_damping = passivity_.damping();
  SpatialVector w_F = SpatialVector::Zero();
  w_F.head<3>() = config_.X_WF.linear().transpose() * f_W;
  out.effort = TrocarDevice::jointEfforts(kinematics_.jacobian(out.q_measured), w_F);
  out.saturation = device_.saturate(out.effort);
  out.f_rendered_W = out.saturation.non_finite ? Eigen::Vector3d::Zero()
                                               : Eigen::Vector3d(out.saturation.scale * f_W);
  passivity_.setHeldForce(out.f_rendered_W);
  out.observer_energy = passivity_.observedEnergy();
  out.motor_torque = device_.motorTorques(out.effort);
  return out;
}

}  // namespace surgical_sim::core
