// Beltrami core: loops compiled for several processor generations.
#pragma once

/// Kernels marked CLONES are compiled three times, for AVX-512 (x86-64-v4),
/// for AVX2/FMA (x86-64-v3) and for any x86-64, and the processor picks at
/// run time: the build stays portable.  Their loops should be branch-free
/// so that they vectorize.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define CLONES
#endif

/// Asks for the cache line at p (software prefetch) in a way the compiler
/// keeps: GCC drops __builtin_prefetch from loops it vectorizes (and, seen
/// in the remesher's relaxation, from other inlined loops too); an empty
/// statement that takes the address keeps it.  Check with
/// `objdump -d ... | grep prefetch` after changing a loop that uses it.
inline void PrefetchKept(const void* p)
{
  __builtin_prefetch(p);
#if defined(__GNUC__)
  asm volatile("" : : "r"(p));
#endif
}
