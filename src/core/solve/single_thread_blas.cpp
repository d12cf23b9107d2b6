#include "surgical_sim/core/solve/single_thread_blas.h"

#include <dlfcn.h>

#include <initializer_list>

namespace surgical_sim::core {

void useSingleThreadBlas() {
  using SetThreads = void (*)(int);
  for (const char* symbol : {"openblas_set_num_threads", "omp_set_num_threads"}) {
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, symbol))) set(1);
  }
}

}  // namespace surgical_sim::core
