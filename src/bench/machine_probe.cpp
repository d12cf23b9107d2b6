#include "surgical_sim/bench/machine_probe.h"

#include <dlfcn.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>

#include "surgical_sim/core/common/stopwatch.h"

namespace surgical_sim::bench {
namespace {

/// Triad constants: a = b + s c = 1 + 3 * 2.
constexpr double kTriadB = 1.0, kTriadC = 2.0, kTriadScale = 3.0;
/// Blocked dgemm: a block of kRowBlock rows and kDepthBlock columns of A stays in L2 while the
/// columns of C pass; register tiles of C.
constexpr int kRowBlock = 128, kDepthBlock = 256, kTileRows = 8, kTileColumns = 4;

void requireAtLeastOne(const char* name, long long value) {
  if (value < 1)
    throw std::invalid_argument(std::string("machine probe: ") + name + " = " +
                                std::to_string(value) + ", must be >= 1");
}

/// Runs work(t) for t = 0 .. threads-1, t = 0 on the calling thread.
void onThreads(int threads, const std::function<void(int)>& work) {
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& th : pool) th.join();
}

/// [begin, end) of part t of `threads` equal parts of [0, n).
std::pair<std::size_t, std::size_t> part(std::size_t n, int threads, int t) {
  const auto k = static_cast<std::size_t>(threads);
  const auto i = static_cast<std::size_t>(t);
  return {n * i / k, n * (i + 1) / k};
}

/// C(:, j0:j1) += A B(:, j0:j1), column-major n x n: per block of depth and rows, tiles of
/// kTileRows x kTileColumns of C accumulate in registers. Compiled twice; the loader picks the
/// AVX2 + FMA clone on CPUs that have them.
__attribute__((target_clones("arch=haswell", "default"))) void blockedProduct(
    int n, const double* A, const double* B, double* C, int j0, int j1) {
  const auto at = [n](int i, int j) {
    return static_cast<std::ptrdiff_t>(i) + static_cast<std::ptrdiff_t>(j) * n;
  };
  for (int k0 = 0; k0 < n; k0 += kDepthBlock) {
    const int k1 = std::min(n, k0 + kDepthBlock);
    for (int i0 = 0; i0 < n; i0 += kRowBlock) {
      const int i1 = std::min(n, i0 + kRowBlock);
      for (int j = j0; j < j1; j += kTileColumns) {
        const int columns = std::min(kTileColumns, j1 - j);
        for (int i = i0; i < i1; i += kTileRows) {
          if (columns == kTileColumns && i + kTileRows <= i1) {
            double tile[kTileColumns][kTileRows];
            for (int c = 0; c < kTileColumns; ++c)
              for (int r = 0; r < kTileRows; ++r) tile[c][r] = C[at(i + r, j + c)];
            for (int k = k0; k < k1; ++k) {
              const double* a = A + at(i, k);
              for (int c = 0; c < kTileColumns; ++c) {
                const double b = B[at(k, j + c)];
                for (int r = 0; r < kTileRows; ++r) tile[c][r] += a[r] * b;
              }
            }
            for (int c = 0; c < kTileColumns; ++c)
              for (int r = 0; r < kTileRows; ++r) C[at(i + r, j + c)] = tile[c][r];
          } else {  // ragged edge of the block
            for (int c = 0; c < columns; ++c)
              for (int k = k0; k < k1; ++k)
                for (int r = i; r < std::min(i1, i + kTileRows); ++r)
                  C[at(r, j + c)] += A[at(r, k)] * B[at(k, j + c)];
          }
        }
      }
    }
  }
}

/// The dgemm test problem (see blockedDgemm) and its check.
struct ProductProblem {
  explicit ProductProblem(int n_in) : n(n_in), A(size()), B(size(), 1.0), C(size(), 0.0) {
    for (int j = 0; j < n; ++j) {
      B[index(j, j)] += 1.0;
      for (int i = 0; i < n; ++i) A[index(i, j)] = 1.0 / (i + j + 1.0);
    }
  }
  std::size_t size() const { return static_cast<std::size_t>(n) * static_cast<std::size_t>(n); }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * static_cast<std::size_t>(n);
  }
  /// Largest |C - (A + A 1 1^T)|.
  double maxError() const {
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
      double row_sum = 0.0;
      for (int j = 0; j < n; ++j) row_sum += A[index(i, j)];
      for (int j = 0; j < n; ++j)
        worst = std::max(worst, std::abs(C[index(i, j)] - (A[index(i, j)] + row_sum)));
    }
    return worst;
  }
  int n;
  std::vector<double> A, B, C;
};

/// Best of `repeats` timed runs of product(problem) (C zeroed before each), 2 n^3 flops each.
ProbeResult bestProduct(int n, int repeats, const std::function<void(ProductProblem&)>& product) {
  ProductProblem p(n);
  ProbeResult best;
  for (int r = 0; r < repeats; ++r) {
    std::fill(p.C.begin(), p.C.end(), 0.0);
    const core::Stopwatch watch;
    product(p);
    const double s = watch.seconds();
    if (best.seconds == 0.0 || s < best.seconds) best.seconds = s;
  }
  best.rate = 2.0 * std::pow(static_cast<double>(n), 3) / best.seconds / 1e9;
  best.max_error = p.maxError();
  return best;
}

}  // namespace

ProbeResult triadBandwidth(std::size_t n, int threads, int repeats) {
  requireAtLeastOne("n", static_cast<long long>(n));
  requireAtLeastOne("threads", threads);
  requireAtLeastOne("repeats", repeats);
  std::vector<double> a(n), b(n), c(n);
  // First touch on the thread that streams the range later.
  onThreads(threads, [&](int t) {
    const auto [begin, end] = part(n, threads, t);
    for (std::size_t i = begin; i < end; ++i) {
      a[i] = 0.0;
      b[i] = kTriadB;
      c[i] = kTriadC;
    }
  });
  ProbeResult best;
  for (int r = 0; r < repeats; ++r) {
    const core::Stopwatch watch;
    onThreads(threads, [&](int t) {
      const auto [begin, end] = part(n, threads, t);
      double* __restrict out = a.data();
      const double* __restrict x = b.data();
      const double* __restrict y = c.data();
      for (std::size_t i = begin; i < end; ++i) out[i] = x[i] + kTriadScale * y[i];
    });
    const double s = watch.seconds();
    if (best.seconds == 0.0 || s < best.seconds) best.seconds = s;
  }
  best.rate = 24.0 * static_cast<double>(n) / best.seconds / 1e9;
  const double exact = kTriadB + kTriadScale * kTriadC;
  for (const double v : a) best.max_error = std::max(best.max_error, std::abs(v - exact));
  return best;
}

ProbeResult blockedDgemm(int n, int threads, int repeats) {
  requireAtLeastOne("n", n);
  requireAtLeastOne("threads", threads);
  requireAtLeastOne("repeats", repeats);
  return bestProduct(n, repeats, [&](ProductProblem& p) {
    onThreads(threads, [&](int t) {
      const auto [j0, j1] = part(static_cast<std::size_t>(n), threads, t);
      blockedProduct(n, p.A.data(), p.B.data(), p.C.data(), static_cast<int>(j0),
                     static_cast<int>(j1));
    });
  });
}

std::optional<ProbeResult> blasDgemm(int n, int threads, int repeats) {
  requireAtLeastOne("n", n);
  requireAtLeastOne("threads", threads);
  requireAtLeastOne("repeats", repeats);
  using Dgemm = void (*)(const char*, const char*, const int*, const int*, const int*,
                         const double*, const double*, const int*, const double*, const int*,
                         const double*, double*, const int*);
  using SetThreads = void (*)(int);
  const auto dgemm = reinterpret_cast<Dgemm>(dlsym(RTLD_DEFAULT, "dgemm_"));
  if (dgemm == nullptr) return std::nullopt;
  const auto set_threads =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set_threads != nullptr) set_threads(threads);
  const double one = 1.0, zero = 0.0;
  const ProbeResult result = bestProduct(n, repeats, [&](ProductProblem& p) {
    dgemm("N", "N", &n, &n, &n, &one, p.A.data(), &n, p.B.data(), &n, &zero, p.C.data(), &n);
  });
  if (set_threads != nullptr) set_threads(1);
  return result;
}

double peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return 1024.0 * static_cast<double>(usage.ru_maxrss);  // Linux: kilobytes
}

}  // namespace surgical_sim::bench
