#include "surgical_sim/bench/machine_probe.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace surgical_sim::bench {
namespace {

TEST(MachineProbe, TriadComputesBPlusScaledCOnEveryThreadCount) {
  for (const int threads : {1, 2, 3}) {
    // An odd size: the last thread's range is not a multiple of the others'.
    const ProbeResult r = triadBandwidth(100003, threads, 2);
    EXPECT_EQ(r.max_error, 0.0) << threads << " threads";  // 1 + 3 * 2 is exact
    EXPECT_GT(r.rate, 0.0);
    EXPECT_GT(r.seconds, 0.0);
  }
}

TEST(MachineProbe, BlockedProductMatchesTheClosedFormOnRaggedBlocks) {
  // 71 and 300: neither a multiple of the 4-column, 64-row or 256-deep blocks.
  for (const int n : {71, 300})
    for (const int threads : {1, 2}) {
      const ProbeResult r = blockedDgemm(n, threads, 1);
      // Entries of C are at most 1 + ln(2n); summation error ~ n eps.
      EXPECT_LT(r.max_error, 1e-12) << "n " << n << ", " << threads << " threads";
      EXPECT_GT(r.rate, 0.0);
    }
}

TEST(MachineProbe, SystemBlasProductMatchesTheClosedFormWhenLoaded) {
  const std::optional<ProbeResult> r = blasDgemm(97, 2, 1);
  if (!r) GTEST_SKIP() << "no dgemm_ loaded in this process";
  EXPECT_LT(r->max_error, 1e-12);
  EXPECT_GT(r->rate, 0.0);
}

TEST(MachineProbe, RejectsEmptyProblemsNamingTheParameter) {
  try {
    triadBandwidth(0, 1, 1);
    FAIL() << "n = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("n = 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(blockedDgemm(8, 0, 1), std::invalid_argument);
  EXPECT_THROW(blasDgemm(8, 1, 0), std::invalid_argument);
}

TEST(MachineProbe, PeakResidentMemoryCoversWhatTheProcessTouched) {
  const double before = peakResidentBytes();
  EXPECT_GT(before, 1e6);  // a gtest process with its libraries: megabytes
  constexpr std::size_t kBytes = std::size_t{256} << 20;
  std::vector<char> block(kBytes, 1);  // touched: resident
  const double after = peakResidentBytes();
  EXPECT_GE(after, static_cast<double>(kBytes));
  EXPECT_GE(after, before);
  EXPECT_LT(after, 1e12);
  EXPECT_EQ(block[kBytes / 2], 1);
}

}  // namespace
}  // namespace surgical_sim::bench
