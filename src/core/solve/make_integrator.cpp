#include "surgical_sim/core/solve/make_integrator.h"

#include <stdexcept>

#include "surgical_sim/core/solve/implicit_euler_linearized.h"
#include "surgical_sim/core/solve/implicit_euler_newton.h"
#include "surgical_sim/core/solve/quasi_static_newton.h"
#include "surgical_sim/core/solve/symplectic_euler.h"

namespace surgical_sim::core {

std::unique_ptr<Integrator> makeIntegrator(const std::string& name,
                                           const IntegratorSettings& settings,
                                           std::unique_ptr<LinearSolver> linear_solver) {
  validateIntegratorSettings(settings);
  if (name == "symplectic_euler") {
    return std::make_unique<SymplecticEuler>(settings.blow_up_energy_ratio);
  }
  if (name == "implicit_euler_linearized") {
    return std::make_unique<ImplicitEulerLinearized>(std::move(linear_solver),
                                                     settings.max_line_search_halvings);
  }
  if (name == "implicit_euler_newton") {
    return std::make_unique<ImplicitEulerNewton>(settings, std::move(linear_solver));
  }
  if (name == "quasi_static") {
    return std::make_unique<QuasiStaticNewton>(settings, std::move(linear_solver));
  }
  throw std::invalid_argument("integrator.type = \"" + name +
                              "\" is unknown: must be one of symplectic_euler, "
                              "implicit_euler_linearized, implicit_euler_newton, quasi_static");
}

}  // namespace surgical_sim::core
