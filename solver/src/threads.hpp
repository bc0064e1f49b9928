#pragma once
// OpenMP's thread queries, also in a build without OpenMP (one thread).

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sage::solver {

/// Threads a parallel region started here would get.
inline int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// Threads of the enclosing parallel region (1 outside one).
inline int team_size() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/// This thread's number in its team.
inline int thread_number() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

}  // namespace sage::solver
