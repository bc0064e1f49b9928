#pragma once
// SAGE_ALSO_AVX2 compiles a function twice, for the default x86-64 target
// and for AVX2, and picks one at run time (GCC's target_clones): four
// doubles per vector instruction instead of two. AVX2 alone has no fused
// multiply-adds, so both give the same bits. Elsewhere: the one default build.

#if defined(__x86_64__) && defined(__GNUC__)
#define SAGE_ALSO_AVX2 [[gnu::target_clones("avx2", "default")]]
#else
#define SAGE_ALSO_AVX2
#endif
