#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/robot/continuum_robot_model.h"
#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/solve/integrator_settings.h"

namespace surgical_sim::core {

/// Settings of FullFePlant.
struct FullFePlantSettings {
  /// Young's modulus of the vertebra elements / section modulus [-], >= 1 (stiff, not rigid).
  double vertebra_stiffness_ratio = 1e3;
  /// Follower-load fixed-point passes per solve (loads recomputed from the deformed vertebrae)
  /// [-], >= 1.
  int follower_iterations = 10;
  /// Stop the passes when the tip moves less than this times the robot length [-], > 0.
  double follower_tolerance = 1e-7;
  IntegratorSettings newton;  ///< quasi-static Newton settings
};

/// @throws std::invalid_argument naming "full_fe_plant.<field>" with range.
void validateFullFePlantSettings(const FullFePlantSettings& settings);

/// Validation plant: the whole robot meshed with corotational Tet4 (makeTubeMesh over all gaps
/// with the section resolution; vertebrae as layers of thickness vertebra_thickness with a stiff
/// material), base face clamped, solved with the core's QuasiStaticNewton (CHOLMOD). Actuators are
/// exact FE terms: each pressure chamber is a ChamberPressureModel (the reduced model's cavity
/// surface embedded in the mesh, wall pressure p A n / 3 on its vertices as a follower load), each
/// cable a TendonModel (eyelets embedded in the vertebra elements; a frozen cable load would be a
/// buckling dead load). The tip force is spread over the tip vertebra's nodes as a statically
/// equivalent nodal force field at the fitted vertebra pose (centroid + Kabsch rotation),
/// converged by fixed-point passes.
class ChamberPressureModel;
class TendonModel;

class FullFePlant {
 public:
  /// @param model reduced model whose description and actuators are reused (not owned; must
  ///        outlive the plant).
  /// @throws std::invalid_argument if vertebra_thickness is 0 ("robot.<name>.vertebra_thickness
  ///         must be > 0 for the FE plant") or the settings are invalid.
  FullFePlant(const ContinuumRobotModel& model, const FullFePlantSettings& settings);
  ~FullFePlant();

  /// Quasi-static equilibrium under `actuation` ([Pa] chambers then [N] cables; + tip force,
  /// gravity if enabled), warm-started from the current state. Never throws.
  StepReport solve(const Eigen::VectorXd& actuation);
  /// Constant tip force [N], frame robot_base, spread over the tip vertebra.
  void setTipForce(const Eigen::Vector3d& f_B) { tip_force_ = f_B; }
  /// Tip position = fitted pose of the tip vertebra [m], frame robot_base.
  Eigen::Vector3d tipPosition() const;
  /// Back to the rest shape.
  void reset();
  int numNodes() const;
  /// Vertebra poses fitted to the current mesh (index 0 = base at rest).
  const std::vector<RigidNodePose>& vertebraPoses() const { return poses_; }

 private:
  void fitPoses();
  void buildLoads(const Eigen::VectorXd& actuation);

  const ContinuumRobotModel& model_;
  FullFePlantSettings settings_;
  std::unique_ptr<TissueModel> tissue_;
  std::vector<ChamberPressureModel*> chambers_;  ///< pressure terms inside tissue_ (owned by it)
  std::vector<TendonModel*> tendons_;            ///< cable terms inside tissue_ (owned by it)
  std::unique_ptr<Integrator> integrator_;
  DynamicsProblem problem_;
  SimulationState state_;
  Eigen::VectorXd gravity_force_;
  std::vector<std::vector<int>> vertebra_nodes_;  ///< per rigid node 0..n (0 unused)
  std::vector<RigidNodePose> poses_;
  Eigen::VectorXd wrench_;  ///< 6(n+1)
  Eigen::Vector3d tip_force_ = Eigen::Vector3d::Zero();
};

}  // namespace surgical_sim::core
