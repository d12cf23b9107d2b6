#pragma once
// What this machine can do, measured: memory bandwidth (a STREAM-like triad), double-precision
// matrix-multiply throughput (a blocked kernel of our own and the system BLAS dgemm), both on 1
// or more threads, and the peak resident memory of the process. The benches divide each phase's
// achieved GFLOP/s and GB/s by these limits (docs/benchmarks.md).

#include <cstddef>
#include <optional>
#include <vector>

namespace surgical_sim::bench {

/// One throughput measurement: the best of its repetitions.
struct ProbeResult {
  double rate = 0.0;     ///< GB/s (triad) or GFLOP/s (dgemm), best repetition
  double seconds = 0.0;  ///< wall time of that repetition [s]
  /// Largest |computed - exact| entry of the kernel's output after the repetitions [-]: the
  /// probe checks its own arithmetic.
  double max_error = 0.0;
};

/// a = b + s c over `n` doubles per array (b = 1, c = 2, s = 3, so a = 7), split into `threads`
/// contiguous ranges, each on its own std::thread; `repeats` >= 1 passes. Bandwidth counts the
/// STREAM bytes, 24 per element (read b, c; write a; write-allocate traffic not counted), so it
/// is comparable with STREAM's triad. For a bandwidth figure choose n so that 24 n bytes is many
/// times the last-level cache.
/// @throws std::invalid_argument if n, threads or repeats < 1
ProbeResult triadBandwidth(std::size_t n, int threads, int repeats);

/// C = A B for n x n column-major matrices with a cache-blocked kernel of our own (compiled for
/// AVX2 + FMA, chosen at run time when the CPU has them, else for the baseline ISA), the rows of C
/// split over `threads` std::threads; 2 n^3 flops per product. A = 1 / (i + j + 1) (Hilbert),
/// B = I + 1: the exact C = A + A 1 1^T checks the result.
/// @throws std::invalid_argument if n, threads or repeats < 1
ProbeResult blockedDgemm(int n, int threads, int repeats);

/// The same product through the system BLAS dgemm_ (the library CHOLMOD was loaded with, found
/// with dlsym) with its thread count set to `threads` (OpenBLAS), restored to 1 afterwards.
/// nullopt when no dgemm_ is loaded.
/// @throws std::invalid_argument if n, threads or repeats < 1
std::optional<ProbeResult> blasDgemm(int n, int threads, int repeats);

/// Peak resident set size of this process so far (getrusage ru_maxrss) [bytes]; in a child
/// forked from a process it includes the parent's resident set at the fork.
double peakResidentBytes();

}  // namespace surgical_sim::bench
