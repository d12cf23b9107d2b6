#pragma once

#include <array>

#include "surgical_sim/core/common/named_enum.h"

namespace surgical_sim::core {

/// Per-integration-point rotation of the co-rotated EFG elasticity.
enum class EfgRotation {
  Polar,          ///< rotation of the deformation gradient F at the point (signed polar)
  ShapeMatching,  ///< rotation that best matches the neighbour particles (kernel-weighted)
};

/// Scene / CSV names: polar, shape_matching.
inline constexpr std::array<EnumName<EfgRotation>, 2> kEfgRotationNames{{
    {EfgRotation::Polar, "polar"},
    {EfgRotation::ShapeMatching, "shape_matching"},
}};

/// Discretisation of the meshless EFG tissue model (EfgModel). Validate with validate().
struct EfgOptions {
  /// Integration cell side d [m], finite and > 0 (required: no default). DOF particles lie on
  /// the grid of side 2 d.
  double spacing = 0.0;
  /// Particles per integration point [-], range [8, 16], default 8 (the enclosing DOF cell's
  /// corners; more adds the nearest other grid particles).
  int neighbours = 8;
  /// Kernel support h as a multiple of the distance from the integration point to its farthest
  /// neighbour [-], range [1.1, 10], default 3.
  double kernel_support = 3.0;
  /// Volume samples per axis of an integration cell [-] (samples^3 points), range [1, 8],
  /// default 4.
  int volume_samples = 4;
  /// Integration point of a cell: the centroid of its inside volume samples (true) or the cell
  /// centre (false, as in Magnoux's thesis); default true. The centroid integrates linear
  /// functions exactly over the cell's inside part, which removes the stiffening of cells cut by
  /// the surface.
  bool ip_at_centroid = true;
  /// Rotation of the co-rotated elasticity, default Polar.
  EfgRotation rotation = EfgRotation::Polar;
  /// Weight c [-] of the non-affine (zero-energy mode) stabilisation, range [0, 1], default
  /// 0.01: each IP adds the energy c mu V_e sum_a |d_a|^2 / sum_a |X_a - X_e|^2, where d_a is
  /// the distance of particle a from the affine map the IP predicts (x_e + F_e (X_a - X_e)).
  /// Affine motions are unaffected; particles seen by too few IPs no longer swing freely.
  double stabilization = 0.01;

  static constexpr int kMinNeighbours = 8;
  static constexpr int kMaxNeighbours = 16;
  static constexpr int kMaxVolumeSamples = 8;

  /// @throws std::invalid_argument naming "efg.spacing", "efg.neighbours", "efg.kernel_support",
  ///         "efg.volume_samples" or "efg.stabilization" with its unit and range.
  void validate() const;
};

}  // namespace surgical_sim::core
