// machine_probe: what this machine can do, for the benches' fraction-of-limit columns: STREAM-like
// triad bandwidth and double matrix-multiply throughput (our blocked kernel and the system BLAS
// dgemm) on 1 and 2 threads. Usage: machine_probe [--csv FILE] [--quick]
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include "bench_cli.h"
#include "surgical_sim/bench/machine_probe.h"

namespace {

constexpr const char* kUsage =
    "usage: machine_probe [--csv FILE] [--quick]\n"
    "Measures the limits the benches compare their phases with, on 1 and 2 threads:\n"
    "  triad          a = b + s c over 3 arrays of 2^25 doubles (768 MB, far beyond the caches),\n"
    "                 GB/s counting 24 bytes per element (STREAM's convention), best of 5\n"
    "  blocked_dgemm  C = A B, n = 1000, our cache-blocked kernel (AVX2 + FMA when available),\n"
    "                 GFLOP/s (2 n^3 flops), best of 3\n"
    "  blas_dgemm     the same through the system BLAS dgemm_ (CHOLMOD's)\n"
    "One CSV row per probe and thread count on stdout: probe,threads,rate,unit,seconds,max_error.\n"
    "  --csv FILE  also write the rows to FILE\n"
    "  --quick     smaller problems (2^22 doubles, n = 256): a check, not a measurement\n";

int usage(const std::string& msg) {
  std::cerr << "machine_probe: " << msg << "\n" << kUsage;
  return 2;
}

std::string row(const std::string& probe, int threads, const char* unit,
                const surgical_sim::bench::ProbeResult& r) {
  std::ostringstream os;
  os << probe << "," << threads << "," << r.rate << "," << unit << "," << r.seconds << ","
     << r.max_error;
  return os.str();
}

}  // namespace

int main(int argc, char** argv) {
  namespace bench = surgical_sim::bench;
  if (surgical_sim::tools::wantsHelp(argc, argv)) {
    std::cout << kUsage;
    return 0;
  }
  std::string csv_path;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--csv" && i + 1 < argc) {
      csv_path = argv[++i];
    } else if (arg == "--quick") {
      quick = true;
    } else {
      return usage("unknown argument " + arg);
    }
  }
  std::ofstream csv;
  if (!surgical_sim::tools::openCsv("machine_probe", csv_path, csv)) return 1;
  const std::size_t triad_n = quick ? (std::size_t{1} << 22) : (std::size_t{1} << 25);
  const int gemm_n = quick ? 256 : 1000;
  const char* header = "probe,threads,rate,unit,seconds,max_error";
  std::cout << header << "\n";
  if (csv) csv << header << "\n";
  const auto emit = [&](const std::string& line) {
    std::cout << line << std::endl;
    if (csv) csv << line << "\n" << std::flush;
  };
  for (const int threads : {1, 2}) {
    surgical_sim::tools::progress("machine_probe", std::to_string(threads) + " thread(s)");
    emit(row("triad", threads, "GB/s", bench::triadBandwidth(triad_n, threads, 5)));
    emit(row("blocked_dgemm", threads, "GFLOP/s", bench::blockedDgemm(gemm_n, threads, 3)));
    if (const std::optional<bench::ProbeResult> blas = bench::blasDgemm(gemm_n, threads, 3)) {
      emit(row("blas_dgemm", threads, "GFLOP/s", *blas));
    } else if (threads == 1) {
      std::cerr << "machine_probe: no BLAS dgemm_ loaded; blas_dgemm skipped\n";
    }
  }
  return 0;
}
