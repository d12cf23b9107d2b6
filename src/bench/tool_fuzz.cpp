#include "surgical_sim/bench/tool_fuzz.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/common/tool_pose_check.h"
#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/mesh/surface_closure.h"

namespace surgical_sim::bench {
namespace {

/// Axis-aligned box [m].
struct Box {
  Eigen::Vector3d lo, hi;
};

/// One tool's motion: the current commanded pose and the segment it is in.
struct ToolMotion {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  ///< tip position [m], S
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_target = Eigen::Quaterniond::Identity();
  double speed = 0.0;          ///< [m/s]
  double angular_speed = 0.0;  ///< [rad/s]
  int hold_steps = 0;          ///< steps left standing still (hold or teleported away)
  bool teleported = false;     ///< away by a teleport jump; jumps back when hold_steps ends
  Eigen::Vector3d p_before_teleport = Eigen::Vector3d::Zero();
  bool jaws_closed = false;
};

class MotionGenerator {
 public:
  MotionGenerator(const ToolFuzzSettings& settings, const Box& tissue, std::mt19937& rng)
      : settings_(settings), tissue_(tissue), rng_(rng) {}

  Eigen::Vector3d uniformIn(const Box& b) {
    return {uniform(b.lo.x(), b.hi.x()), uniform(b.lo.y(), b.hi.y()), uniform(b.lo.z(), b.hi.z())};
  }

  Eigen::Quaterniond randomOrientation() {
    std::normal_distribution<double> n(0.0, 1.0);
    Eigen::Vector4d v(n(rng_), n(rng_), n(rng_), n(rng_));
    while (v.norm() < 1e-6) v = Eigen::Vector4d(n(rng_), n(rng_), n(rng_), n(rng_));
    v.normalize();
    return Eigen::Quaterniond(v[0], v[1], v[2], v[3]);
  }

  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }

  /// Starting pose: above the tissue, within reach; returns true if the first segment is a
  /// teleport.
  bool start(ToolMotion& m) {
    m.p = uniformIn({Eigen::Vector3d(tissue_.lo.x(), tissue_.lo.y(), tissue_.hi.z()),
                     tissue_.hi + Eigen::Vector3d::Constant(settings_.reach)});
    m.q = randomOrientation();
    m.jaws_closed = false;
    return newSegment(m);
  }

  /// Advances the tool by one step of dt [s]; returns true if it teleported this step.
  bool advance(ToolMotion& m, double dt) {
    if (m.hold_steps > 0) {
      if (--m.hold_steps == 0 && m.teleported) {
        m.p = m.p_before_teleport;  // jump back
        m.teleported = false;
        newSegment(m);
      }
      return false;
    }
    const Eigen::Vector3d d = m.target - m.p;
    const double step = m.speed * dt;
    const double angle = m.q.angularDistance(m.q_target);
    m.q = angle > 0.0 ? m.q.slerp(std::min(1.0, m.angular_speed * dt / angle), m.q_target)
                      : m.q_target;
    if (d.norm() > step) {
      m.p += d * (step / d.norm());
      return false;
    }
    m.p = m.target;
    return newSegment(m);
  }

 private:
  /// Draws the next segment; returns true if it is a teleport (applied at once).
  bool newSegment(ToolMotion& m) {
    const Box reach{tissue_.lo - Eigen::Vector3d::Constant(settings_.reach),
                    tissue_.hi + Eigen::Vector3d::Constant(settings_.reach)};
    // Speeds biased low (median max_speed / 8) so contacts also build up slowly.
    m.speed = settings_.max_speed * std::max(0.005, std::pow(uniform(0.0, 1.0), 3.0));
    m.angular_speed = uniform(0.0, 2.0 * M_PI);
    m.q_target = randomOrientation();
    const double kind = uniform(0.0, 1.0);
    if (kind < 0.3) {  // wander near the tissue
      m.target = uniformIn(reach);
    } else if (kind < 0.55) {  // press into the body
      m.target = uniformIn(tissue_);
    } else if (kind < 0.75) {  // dive through the body, below its lowest point
      m.target = uniformIn({Eigen::Vector3d(tissue_.lo.x(), tissue_.lo.y(), reach.lo.z()),
                            Eigen::Vector3d(tissue_.hi.x(), tissue_.hi.y(), tissue_.lo.z())});
    } else if (kind < 0.9) {  // hold still
      m.target = m.p;
      m.hold_steps = 1 + static_cast<int>(uniform(0.0, 50.0));
    } else {  // teleport away, hold a while, jump back
      Eigen::Vector3d dir = randomOrientation().vec();
      if (dir.norm() < 1e-6) dir = Eigen::Vector3d::UnitZ();
      m.p_before_teleport = m.p;
      m.p += settings_.teleport_distance * dir.normalized();
      m.target = m.p;
      m.teleported = true;
      m.hold_steps = 1 + static_cast<int>(uniform(0.0, 20.0));
      return true;
    }
    return false;
  }

  const ToolFuzzSettings& settings_;
  Box tissue_;
  std::mt19937& rng_;
};

/// A malformed pose of one of five kinds: NaN position, Inf position, zero quaternion, tiny
/// quaternion, far beyond max_distance [m].
void malformedPose(MotionGenerator& gen, double max_distance, Eigen::Vector3d& p,
                   Eigen::Vector4d& q_wxyz) {
  p = Eigen::Vector3d(gen.uniform(-0.1, 0.1), gen.uniform(-0.1, 0.1), gen.uniform(-0.1, 0.1));
  const Eigen::Quaterniond q = gen.randomOrientation();
  q_wxyz = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
  const int kind = static_cast<int>(gen.uniform(0.0, 5.0));
  const auto axis = static_cast<Eigen::Index>(gen.uniform(0.0, 3.0));
  switch (kind) {
    case 0:
      p[axis] = std::numeric_limits<double>::quiet_NaN();
      break;
    case 1:
      p[axis] = std::numeric_limits<double>::infinity();
      break;
    case 2:
      q_wxyz.setZero();
      break;
    case 3:
      q_wxyz *= 1e-3;
      break;
    default:
      p = p.normalized() * max_distance * gen.uniform(1.01, 1e6);
      break;
  }
}

void validate(const ToolFuzzSettings& s) {
  if (s.steps < 1)
    throw std::invalid_argument("ToolFuzzSettings.steps = " + std::to_string(s.steps) +
                                " must be >= 1");
  requirePositive("ToolFuzzSettings.reach", s.reach, "m");
  requirePositive("ToolFuzzSettings.max_speed", s.max_speed, "m/s");
  requireNonNegative("ToolFuzzSettings.teleport_distance", s.teleport_distance, "m");
  requireInRange("ToolFuzzSettings.bad_pose_rate", s.bad_pose_rate, 0.0, 1.0, "-");
  requireInRange("ToolFuzzSettings.grasp_toggle_rate", s.grasp_toggle_rate, 0.0, 1.0, "-");
  requireInRange("ToolFuzzSettings.cut_rate", s.cut_rate, 0.0, 1.0, "-");
  requirePositive("ToolFuzzSettings.max_tool_distance", s.max_tool_distance, "m");
}

/// Bounding box of the rest tissue [m].
Box restBox(const TissueSimulation& sim) {
  const Eigen::Matrix3Xd& rest = sim.mesh().nodes;
  return {rest.rowwise().minCoeff(), rest.rowwise().maxCoeff()};
}
Box restBox(const MultiBodySimulation& sim) {
  Box box{Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
          Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};
  for (int b = 0; b < sim.numBodies(); ++b) {
    const Eigen::Matrix3Xd& rest = sim.bodyMesh(b).nodes;
    box.lo = box.lo.cwiseMin(rest.rowwise().minCoeff());
    box.hi = box.hi.cwiseMax(rest.rowwise().maxCoeff());
  }
  return box;
}

/// A random blade through the region of tip p [m]: 2 to 6 cm long, from 1 cm above p down by 1
/// to 7 cm, drifting up to 1 cm sideways.
BladeSweep randomBlade(MotionGenerator& gen, const Eigen::Vector3d& p) {
  const Eigen::Vector3d half =
      gen.uniform(0.01, 0.03) *
      Eigen::Vector3d(gen.uniform(-1.0, 1.0), gen.uniform(-1.0, 1.0), gen.uniform(-0.3, 0.3))
          .normalized();
  BladeSweep sweep;
  sweep.start.resize(3, 2);
  sweep.start << p - half, p + half;
  sweep.start.row(2).array() += 0.01;
  const Eigen::Vector3d motion(gen.uniform(-0.01, 0.01), gen.uniform(-0.01, 0.01),
                               -gen.uniform(0.01, 0.07));
  sweep.end = sweep.start.colwise() + motion;
  return sweep;
}

/// Whether the state's positions and velocities are finite.
bool finiteState(const TissueSimulation& sim) {
  return sim.state().x.allFinite() && sim.state().v.allFinite();
}
bool finiteState(const MultiBodySimulation& sim) {
  const CoupledState& state = sim.state();
  auto all = [](const std::vector<Eigen::VectorXd>& vectors) {
    return std::all_of(vectors.begin(), vectors.end(),
                       [](const Eigen::VectorXd& v) { return v.allFinite(); });
  };
  bool finite =
      all(state.organ_positions) && all(state.organ_velocities) && all(state.layer_velocities);
  for (const RigidNodeConfiguration& q : state.layer_configurations)
    for (int j = 0; j < q.numNodes(); ++j)
      finite = finite && q.p_TN[j].allFinite() && q.q_TN[j].coeffs().allFinite();
  return finite;
}

template <typename Simulation>
ToolFuzzOutcome runSequence(Simulation& sim, const ToolFuzzSettings& settings, std::mt19937& rng) {
  validate(settings);
  constexpr bool kCuts = std::is_same_v<Simulation, TissueSimulation>;
  if (!kCuts && settings.cut_rate > 0.0)
    throw std::invalid_argument("ToolFuzzSettings.cut_rate = " + std::to_string(settings.cut_rate) +
                                ": a multi-body scene takes no blade sweeps");
  sim.reset();
  MotionGenerator gen(settings, restBox(sim), rng);
  const auto n_tools = static_cast<std::size_t>(sim.numTools());
  std::vector<ToolMotion> motion(n_tools);
  ToolFuzzOutcome out;
  out.sequences = 1;
  for (ToolMotion& m : motion)
    if (gen.start(m)) ++out.teleports;
  double previous_energy = std::numeric_limits<double>::quiet_NaN();
  double mass = 0.0;  // at the start [kg]
  if constexpr (kCuts) mass = sim.model().lumpedMass().sum();
  for (int k = 0; k < settings.steps; ++k) {
    for (std::size_t i = 0; i < n_tools; ++i) {
      const int tool = static_cast<int>(i);
      ToolMotion& m = motion[i];
      if (gen.chance(settings.bad_pose_rate)) {
        Eigen::Vector3d p;
        Eigen::Vector4d q;
        malformedPose(gen, settings.max_tool_distance, p, q);
        if (isUsableToolPose(p, q, settings.max_tool_distance))
          ++out.bad_poses_accepted;
        else
          ++out.rejected_poses;
      }
      if (gen.advance(m, sim.timeStep())) ++out.teleports;
      const Eigen::Vector4d q_wxyz(m.q.w(), m.q.x(), m.q.y(), m.q.z());
      if (isUsableToolPose(m.p, q_wxyz, settings.max_tool_distance)) {
        Eigen::Isometry3d X_ST = Eigen::Isometry3d::Identity();
        X_ST.linear() = m.q.normalized().toRotationMatrix();
        X_ST.translation() = m.p;
        sim.setToolPose(tool, X_ST);
        ++out.accepted_poses;
      } else {
        ++out.rejected_poses;
      }
      const ToolSpec& spec = sim.scene().tools[i];
      if (spec.grasp && gen.chance(settings.grasp_toggle_rate)) {
        m.jaws_closed = !m.jaws_closed;
        sim.setGrasp(tool, m.jaws_closed);
        ++out.grasp_toggles;
      }
    }

    if constexpr (kCuts) {
      if (settings.cut_rate > 0.0 && n_tools > 0 && gen.chance(settings.cut_rate)) {
        sim.requestCut(randomBlade(gen, motion[0].p));
        ++out.cuts.sweeps;
      }
    }

    Stopwatch watch;
    const SimulationStepStats stats = sim.step();
    out.wall_seconds += watch.seconds();
    ++out.steps;
    const std::string status = toString(stats.report.status);
    ++out.status_steps[status];
    const double energy = stats.report.energy;
    bool finite = finiteState(sim) && std::isfinite(energy);
    bool over = false;
    bool limited_ok = false;
    bool contact = false;
    for (std::size_t i = 0; i < n_tools; ++i) {
      const ContactLinearization c = sim.toolContact(static_cast<int>(i));
      contact = contact || c.in_contact;
      const double f = c.f0_S.norm();
      if (!std::isfinite(f)) {
        finite = false;
        continue;
      }
      out.max_force = std::max(out.max_force, f);
      if (i >= settings.force_bounds.size() || !settings.force_bounds[i]) continue;
      const double bound = *settings.force_bounds[i];
      over = over || f > bound * (1.0 + 1e-6);
      limited_ok = limited_ok || (f >= bound * (1.0 - 1e-6) && status == "ok");
    }
    out.non_finite_steps += finite ? 0 : 1;
    out.contact_steps += contact ? 1 : 0;
    out.over_bound_steps += over ? 1 : 0;
    out.limited_but_ok_steps += limited_ok ? 1 : 0;
    if (std::isfinite(energy)) {
      out.max_abs_energy = std::max(out.max_abs_energy, std::abs(energy));
      if (std::isfinite(previous_energy))
        out.max_energy_rise = std::max(out.max_energy_rise, energy - previous_energy);
    }
    previous_energy = energy;
    if constexpr (kCuts) {
      out.cuts.changed_steps += stats.topology_changed ? 1 : 0;
      out.cuts.refused_steps += sim.cutError().empty() ? 0 : 1;
      out.cuts.max_mass_error =
          std::max(out.cuts.max_mass_error, std::abs(sim.model().lumpedMass().sum() - mass) / mass);
    }
  }
  if constexpr (kCuts) {
    out.cuts.open_surfaces = checkSurfaceClosure(sim.surface().triangles).open_edges > 0 ? 1 : 0;
  }
  return out;
}

}  // namespace

void ToolFuzzOutcome::merge(const ToolFuzzOutcome& o) {
  sequences += o.sequences;
  steps += o.steps;
  non_finite_steps += o.non_finite_steps;
  contact_steps += o.contact_steps;
  max_force = std::max(max_force, o.max_force);
  for (const auto& [status, n] : o.status_steps) status_steps[status] += n;
  over_bound_steps += o.over_bound_steps;
  limited_but_ok_steps += o.limited_but_ok_steps;
  accepted_poses += o.accepted_poses;
  rejected_poses += o.rejected_poses;
  bad_poses_accepted += o.bad_poses_accepted;
  grasp_toggles += o.grasp_toggles;
  teleports += o.teleports;
  max_abs_energy = std::max(max_abs_energy, o.max_abs_energy);
  max_energy_rise = std::max(max_energy_rise, o.max_energy_rise);
  wall_seconds += o.wall_seconds;
  cuts.merge(o.cuts);
}

void ToolFuzzOutcome::Cuts::merge(const Cuts& o) {
  sweeps += o.sweeps;
  changed_steps += o.changed_steps;
  refused_steps += o.refused_steps;
  max_mass_error = std::max(max_mass_error, o.max_mass_error);
  open_surfaces += o.open_surfaces;
}

std::vector<std::optional<double>> sceneForceBounds(const SceneBase& scene) {
  std::vector<std::optional<double>> bounds;
  for (const ToolSpec& tool : scene.tools) bounds.push_back(tool.max_force);
  return bounds;
}

ToolFuzzOutcome runToolFuzzSequence(TissueSimulation& sim, const ToolFuzzSettings& settings,
                                    std::mt19937& rng) {
  return runSequence(sim, settings, rng);
}

ToolFuzzOutcome runToolFuzzSequence(MultiBodySimulation& sim, const ToolFuzzSettings& settings,
                                    std::mt19937& rng) {
  return runSequence(sim, settings, rng);
}

}  // namespace surgical_sim::bench
