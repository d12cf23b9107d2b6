#pragma once

namespace surgical_sim::core {

/// Restricts the BLAS behind CHOLMOD's supernodal factorization (OpenBLAS, when it is the system
/// BLAS) and OpenMP to one thread. On a shared 2-core machine, the default thread pools spin and
/// yield against each other and against the simulator's own threads (measured: a 12k-DOF
/// linearized implicit step took 470 ms with the default pools and 250 ms with one thread).
/// OpenMP is limited process-wide (no active parallel level): CHOLMOD's supernodal numeric phase
/// asks for teams of its own size, which the per-thread thread count does not cap (measured: 4
/// more threads, and a cutting step at 6.6k DOF took 39 ms with them and 32 ms without).
/// Looks the controls up at run time, so it is a no-op with a BLAS that has none. Idempotent.
void useSingleThreadBlas();

}  // namespace surgical_sim::core
