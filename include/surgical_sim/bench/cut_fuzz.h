#pragma once

#include <Eigen/Core>
#include <string>

namespace surgical_sim::bench {

/// Random blade sweeps over the organ blob (makeOrganBlob), the P2 fuzz campaign.
struct CutFuzzSettings {
  int sweeps = 0;                                ///< number of sweeps, >= 1
  int cells_per_axis = 0;                        ///< organ resolution, >= 1
  unsigned seed = 0;                             ///< std::mt19937 seed
  Eigen::Vector3d semi_axes{0.075, 0.05, 0.03};  ///< organ semi-axes [m]
  int simulate_steps = 5;  ///< implicit Euler steps of the cut organ under gravity at the end
};

/// Outcome of runCutFuzz().
struct CutFuzzReport {
  int sweeps = 0;                ///< sweeps run (stops at the first failure)
  std::string failure;           ///< "" or "sweep i: <problem>"
  double max_mass_error = 0.0;   ///< max |total mass - initial| / initial over all sweeps [-]
  double min_rest_volume = 0.0;  ///< smallest element rest volume seen [m^3]
  int cut_edges = 0;             ///< tissue edges cut in total
  int components = 0;            ///< pieces at the end
  int pinched_edges = 0;         ///< crack-front edges at the end
  double mean_update_ms = 0.0;   ///< mean detection + topology update per sweep [ms]
  double max_update_ms = 0.0;    ///< max detection + topology update per sweep [ms]
  bool finite = true;            ///< masses and the final simulation stayed finite
};

/// Each sweep moves a random 3-point blade polyline inside the organ's box by a random
/// translation while the tissue moves by a random rigid shift of up to 5 mm; after every sweep
/// the masses must be finite, positive and sum to the initial mass (relative 1e-12), every rest
/// volume positive and cutMeshProblem() empty. Then the cut organ (corotational, E = 5 kPa,
/// nu = 0.45) is simulated for simulate_steps implicit Euler steps of 0.01 s under gravity.
/// @throws std::invalid_argument for sweeps or cells_per_axis < 1.
CutFuzzReport runCutFuzz(const CutFuzzSettings& settings);

}  // namespace surgical_sim::bench
