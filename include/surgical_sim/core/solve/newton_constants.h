#pragma once

namespace surgical_sim::core {

/// Residual norms below this fraction of their round-off scale (the norms of the residual's terms)
/// cannot be reduced further: the Newton solve counts as converged.
constexpr double kNewtonResidualRoundOff = 1e-13;
/// A Newton iteration reducing the residual norm by less than this factor counts as stalled; the
/// next one tries the exact tangent (the projected one converges only linearly under compression).
constexpr double kNewtonStallRatio = 0.5;

}  // namespace surgical_sim::core
