#pragma once
// SAGE_VECTOR_CLONES compiles a function three times, for the default
// x86-64 target, for AVX2 and for AVX-512, and picks one at run time (GCC's
// target_clones): two, four or eight doubles per vector instruction. The
// build never contracts a * b + c into a fused multiply-add
// (-ffp-contract=off in CMakeLists.txt), so all three give the same bits.
// Elsewhere, and with clang (the fuzz build), whose target_clones takes no
// function templates: the one default build.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SAGE_VECTOR_CLONES [[gnu::target_clones("avx512f", "avx2", "default")]]
#else
#define SAGE_VECTOR_CLONES
#endif
