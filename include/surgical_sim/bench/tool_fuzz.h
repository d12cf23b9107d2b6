#pragma once

#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/scene/tissue_simulation.h"

namespace surgical_sim::bench {

using namespace core;  // the bench builds on the core's types

/// Hostile tool motion for the S1 robustness campaign (runToolFuzzSequence). Poses are tool-tip
/// poses X_ST in the tissue frame S.
struct ToolFuzzSettings {
  int steps = 1000;  ///< simulation steps per sequence, >= 1
  /// Motion targets lie within this distance of the tissue's rest bounding box [m], > 0.
  double reach = 0.1;
  double max_speed = 2.0;          ///< largest tool-tip speed of a motion segment [m/s], > 0
  double teleport_distance = 1.0;  ///< length of a teleport jump (and back) [m], >= 0
  /// Probability per step and tool of also sending a malformed pose (NaN, Inf, zero or tiny
  /// quaternion, far away) that isUsableToolPose() must reject [-], [0, 1].
  double bad_pose_rate = 0.02;
  /// Probability per step and tool of toggling the jaws, for tools with a grasp [-], [0, 1].
  double grasp_toggle_rate = 0.01;
  /// Probability per step of also sweeping a random blade (2 to 6 cm long, descending 1 to 7 cm
  /// from 1 cm above the first tool's tip, often through where it presses) [-], [0, 1];
  /// single-body scenes only (a multi-body scene rejects blades: nonzero is an error there).
  double cut_rate = 0.0;
  /// The pose check's distance bound, as the nodes' ~max_tool_distance [m], > 0.
  double max_tool_distance = 5.0;
  /// Per tool: bound on |force of the tissue on the tool| [N]; a missing entry or nullopt means
  /// no bound (the force is only reported). See sceneForceBounds().
  std::vector<std::optional<double>> force_bounds;
};

/// Counts of one sequence (or, merged, of many).
struct ToolFuzzOutcome {
  int sequences = 0;
  int steps = 0;
  /// Steps after which the state, the energy or a tool force was NaN/Inf.
  int non_finite_steps = 0;
  int contact_steps = 0;   ///< steps after which at least one tool was in contact
  double max_force = 0.0;  ///< max over steps and tools of |force of the tissue on the tool| [N]
  std::map<std::string, int> status_steps;  ///< steps per status name (toString(StepStatus))
  int over_bound_steps = 0;                 ///< steps where a tool's force exceeded its bound
  /// Steps where a tool's force reached its bound (within 1e-6 relative) while the step's status
  /// was "ok": a limited contact that did not say so.
  int limited_but_ok_steps = 0;
  int accepted_poses = 0;        ///< poses that passed the check and were set
  int rejected_poses = 0;        ///< malformed poses the check rejected (never set)
  int bad_poses_accepted = 0;    ///< malformed poses the check let through (a check bug)
  int grasp_toggles = 0;         ///< jaw open/close commands sent
  int teleports = 0;             ///< teleport jumps (each followed by a jump back)
  double max_abs_energy = 0.0;   ///< max |StepReport::energy| [J]
  double max_energy_rise = 0.0;  ///< max increase of StepReport::energy over one step [J]
  double wall_seconds = 0.0;     ///< wall time of the steps [s]
  /// What the blades of ToolFuzzSettings::cut_rate did.
  struct Cuts {
    int sweeps = 0;         ///< blade sweeps requested
    int changed_steps = 0;  ///< steps whose cuts changed the tissue's topology
    int refused_steps = 0;  ///< steps whose cut was rejected or refused (cutError())
    /// Largest |total lumped mass - at the start| / at the start after a step [-].
    double max_mass_error = 0.0;
    /// Sequences whose surface ended with an open edge, a hole (checked after the last step; the
    /// tet cutter's crack fronts, where two lips meet, are pinched edges by design).
    int open_surfaces = 0;
    void merge(const Cuts& other);
  } cuts;

  /// Adds another outcome's counts (maxima are maxima).
  void merge(const ToolFuzzOutcome& other);
};

/// Per tool of the scene: its force bound ToolSpec::max_force [N].
std::vector<std::optional<double>> sceneForceBounds(const SceneBase& scene);

/// Resets `sim` and runs one sequence of settings.steps steps. Each tool follows random motion
/// segments drawn from `rng`, at speeds up to settings.max_speed (biased low) with random
/// orientations: toward targets within settings.reach of the tissue's rest bounding box, into
/// the body, through the body to below its lowest point (through any fixed underside), holds,
/// and teleports settings.teleport_distance away and back; jaws toggle for tools with a grasp;
/// blades sweep through the first tool's tip region at settings.cut_rate.
/// Every pose goes through isUsableToolPose(); only accepted poses reach setToolPose(). Never
/// throws from the step path.
/// @throws std::invalid_argument naming the setting when a setting is out of range.
ToolFuzzOutcome runToolFuzzSequence(TissueSimulation& sim, const ToolFuzzSettings& settings,
                                    std::mt19937& rng);
/// The same on a multi-body scene: the motion targets are taken around the bounding box of all
/// bodies at rest; the state checked is every organ node and rigid node.
ToolFuzzOutcome runToolFuzzSequence(MultiBodySimulation& sim, const ToolFuzzSettings& settings,
                                    std::mt19937& rng);

}  // namespace surgical_sim::bench
