#pragma once

#include <array>
#include <memory>
#include <string>

#include "surgical_sim/core/common/named_enum.h"
#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/solve/integrator_settings.h"
#include "surgical_sim/core/solve/linear_solver.h"

namespace surgical_sim::core {

/// The time integrators a scene can choose.
enum class IntegratorKind {
  SymplecticEuler,
  ImplicitEulerLinearized,
  ImplicitEulerNewton,
  QuasiStatic
};

/// Scene / CSV names.
inline constexpr std::array<EnumName<IntegratorKind>, 4> kIntegratorNames{{
    {IntegratorKind::SymplecticEuler, "symplectic_euler"},
    {IntegratorKind::ImplicitEulerLinearized, "implicit_euler_linearized"},
    {IntegratorKind::ImplicitEulerNewton, "implicit_euler_newton"},
    {IntegratorKind::QuasiStatic, "quasi_static"},
}};
inline const char* integratorName(IntegratorKind kind) { return enumName(kIntegratorNames, kind); }

/// Creates an integrator: SymplecticEuler (linear_solver unused, may be null),
/// ImplicitEulerLinearized, ImplicitEulerNewton, QuasiStatic (QuasiStaticNewton) (these take
/// ownership of linear_solver, which must not be null).
/// @throws std::invalid_argument naming the offending "integrator.*" setting
///         (validateIntegratorSettings), or "solver" for a missing solver.
std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const IntegratorSettings& settings,
                                           std::unique_ptr<LinearSolver> linear_solver);

}  // namespace surgical_sim::core
