#include "surgical_sim/core/solve/single_thread_blas.h"

#include <dlfcn.h>

#include <initializer_list>

namespace surgical_sim::core {

void useSingleThreadBlas() {
  using SetThreads = void (*)(int);
  for (const char* symbol : {"openblas_set_num_threads", "omp_set_num_threads"}) {
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, symbol))) set(1);
  }
  // CHOLMOD's supernodal numeric phase asks for its own team size (num_threads clauses), which
  // omp_set_num_threads does not cap; no active parallel level makes every region one thread.
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) {
    set(0);
  }
}

}  // namespace surgical_sim::core
