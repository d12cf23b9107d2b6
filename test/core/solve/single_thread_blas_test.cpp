#include "surgical_sim/core/solve/single_thread_blas.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

namespace surgical_sim::core {
namespace {

// CHOLMOD links the OpenMP runtime; its num_threads clauses are capped only by the number of
// active parallel levels, which must be 0 afterwards (every parallel region runs one thread).
TEST(SingleThreadBlas, DisablesEveryOpenMpParallelLevel) {
  using GetLevels = int (*)();
  const auto get = reinterpret_cast<GetLevels>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  if (get == nullptr) GTEST_SKIP() << "no OpenMP runtime linked";
  useSingleThreadBlas();
  EXPECT_EQ(get(), 0);
  useSingleThreadBlas();  // idempotent
  EXPECT_EQ(get(), 0);
}

}  // namespace
}  // namespace surgical_sim::core
