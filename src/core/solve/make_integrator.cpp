#include "surgical_sim/core/solve/make_integrator.h"

#include <stdexcept>

#include "surgical_sim/core/solve/implicit_euler_linearized.h"
#include "surgical_sim/core/solve/implicit_euler_newton.h"
#include "surgical_sim/core/solve/quasi_static_newton.h"
#include "surgical_sim/core/solve/symplectic_euler.h"

namespace surgical_sim::core {

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const IntegratorSettings& settings,
                                           std::unique_ptr<LinearSolver> linear_solver) {
  validateIntegratorSettings(settings);
  switch (kind) {
    case IntegratorKind::SymplecticEuler:
      return std::make_unique<SymplecticEuler>(settings.blow_up_energy_ratio);
    case IntegratorKind::ImplicitEulerLinearized:
      return std::make_unique<ImplicitEulerLinearized>(std::move(linear_solver),
                                                       settings.max_line_search_halvings);
    case IntegratorKind::ImplicitEulerNewton:
      return std::make_unique<ImplicitEulerNewton>(settings, std::move(linear_solver));
    case IntegratorKind::QuasiStatic:
      return std::make_unique<QuasiStaticNewton>(settings, std::move(linear_solver));
  }
  throw std::invalid_argument("makeIntegrator: invalid IntegratorKind");
}

}  // namespace surgical_sim::core
