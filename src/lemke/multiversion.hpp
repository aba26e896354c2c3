// Hot loops compiled once per instruction set and chosen at load time (GCC/clang
// target_clones on ELF platforms with ifunc support). The loops have no reduction that the
// compiler may reorder (-ffp-contract=off, no fast-math), so every variant gives the same
// bits; only the vector width differs.
#pragma once
#if defined(__GNUC__) && defined(__x86_64__) && defined(__linux__) && !defined(LEMKE_NO_CLONES) \
    && !defined(__SANITIZE_ADDRESS__)
#define LEMKE_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define LEMKE_CLONES
#endif
// For the helpers that a cloned function calls in its loops: inlined into every clone (a
// helper GCC chose not to inline was compiled once, for the baseline instruction set).
#if defined(__GNUC__)
#define LEMKE_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define LEMKE_ALWAYS_INLINE inline
#endif
