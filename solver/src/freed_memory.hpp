#pragma once
// Gives freed heap pages back to the system between the solver's phases.
// glibc keeps the pages of freed blocks (in each thread's arena, and below
// its mmap threshold, which rises as large blocks are freed), so the
// temporaries of one phase (the assembly's columns, the Galerkin
// products' pieces) would otherwise stay resident under the next phase's
// arrays and add to the peak: 70-110 MB each on the bracket at degree 3
// (elasticity, 50,000 unknowns).

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace sage::solver {

inline void release_freed_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

}  // namespace sage::solver
