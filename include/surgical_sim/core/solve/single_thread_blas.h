#pragma once

namespace surgical_sim::core {

/// Restricts the BLAS behind CHOLMOD's supernodal factorization (OpenBLAS, when it is the system
/// BLAS) and OpenMP to one thread: on a shared 2-core machine the default thread pools spin and
/// yield against each other and against the simulator's own threads (docs/models.md).
/// OpenMP is limited process-wide (no active parallel level): CHOLMOD's supernodal numeric phase
/// asks for teams of its own size, which the per-thread thread count does not cap.
/// Looks the controls up at run time, so it is a no-op with a BLAS that has none. Idempotent.
void useSingleThreadBlas();

}  // namespace surgical_sim::core
