// Compile-only probe: the core must not include the bench library. Building this file with the
// core's include paths must FAIL; the tests "core_rejects_bench" (ctest) and rostest target
// core_boundary check that it does.
#include "surgical_sim/bench/tissue_case.h"
