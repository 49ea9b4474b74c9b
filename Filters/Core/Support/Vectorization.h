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
