#pragma once

#include <string>
#include <vector>

#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {

/// Geometry convention of every continuum robot (frame robot_base, "B"): the backbone axis is +x
/// of robot_base; rigid node k (k = 0 is the clamped base vertebra, k = 1..n the moving vertebrae,
/// n = num_vertebrae) rests at p_BN = (k * vertebra_spacing, 0, 0) with identity orientation.
/// Gap k (k = 0..n-1) is the soft inter-vertebra section between rigid nodes k and k+1: a tube
/// from x_k + vertebra_thickness/2 to x_{k+1} - vertebra_thickness/2. Angles around the axis are
/// measured from +y towards +z.

/// Tetrahedral resolution of one inter-vertebra section.
struct RobotMeshResolution {
  int radial_layers = 0;             ///< element layers from inner to outer radius [-], [1, 16]
  int circumferential_segments = 0;  ///< element columns around the axis [-], [6, 128]
  int axial_layers = 0;              ///< element layers along one section [-], [1, 32]
};

/// A pneumatic chamber running through gaps first_gap..last_gap: in each gap a closed cylindrical
/// cavity (caps on the two vertebra faces) of the given radius, parallel to the axis.
struct PressureChamberDescription {
  std::string name;
  int first_gap = -1;          ///< first gap [-], [0, n-1]
  int last_gap = -1;           ///< last gap [-], [first_gap, n-1]
  double angle = 0.0;          ///< angular position of the chamber axis [rad], finite
  double radial_offset = 0.0;  ///< distance of the chamber axis from the backbone [m], > 0
  double radius = 0.0;         ///< chamber radius [m], in (0, radial_offset)
  double pressure_min = 0.0;   ///< lower gauge pressure bound [Pa], finite
  double pressure_max = 0.0;   ///< upper gauge pressure bound [Pa], > pressure_min
};

/// A cable fixed at the base vertebra, threaded through one eyelet per vertebra and terminated at
/// vertebra last_vertebra. Pulling it (tension >= 0) shortens its routing polyline.
struct CableDescription {
  std::string name;
  int last_vertebra = -1;      ///< terminating vertebra [-], [1, n]
  double angle = 0.0;          ///< angular position of the eyelets [rad], finite
  double radial_offset = 0.0;  ///< eyelet distance from the backbone [m], > 0
  double tension_max = 0.0;    ///< upper tension bound [N], > 0 (the lower bound is 0)
};

/// Validated description of a continuum robot (see validateContinuumRobotDescription).
struct ContinuumRobotDescription {
  std::string name;
  int num_vertebrae = 0;  ///< moving vertebrae n (rigid nodes besides the base) [-], [1, 200]
  double vertebra_spacing = 0.0;    ///< distance between consecutive rigid nodes [m], > 0
  double vertebra_thickness = 0.0;  ///< rigid vertebra thickness [m], [0, vertebra_spacing)
  double outer_radius_base = 0.0;   ///< outer radius at rigid node 0 [m], > inner_radius
  double outer_radius_tip = 0.0;    ///< outer radius at rigid node n [m], > inner_radius
  double inner_radius = 0.0;        ///< radius of the central bore [m], > 0
  Material material;                ///< inter-vertebra material (validated by Material::create)
  double vertebra_mass = 0.0;       ///< mass of one rigid vertebra [kg], >= 0
  bool gravity_enabled = false;     ///< apply g = 9.81 m/s^2 along -z of robot_base
  RobotMeshResolution mesh;
  std::vector<PressureChamberDescription> chambers;
  std::vector<CableDescription> cables;

  /// Number of actuators: chambers first, then cables.
  int numActuators() const { return static_cast<int>(chambers.size() + cables.size()); }
  /// Outer radius at axial position x [m] (linear taper from rigid node 0 to rigid node n).
  double outerRadiusAt(double x) const;
  /// Length from rigid node 0 to rigid node n [m].
  double length() const { return num_vertebrae * vertebra_spacing; }
};

/// @throws std::invalid_argument naming the parameter with prefix "robot.<name>.", its unit and
///         range, e.g. "robot.trunk.vertebra_spacing = -1 m is out of range: must be finite and
///         > 0", or "robot.trunk.chambers[2].last_gap = 20 is out of range ...".
void validateContinuumRobotDescription(const ContinuumRobotDescription& description);

}  // namespace surgical_sim::core
