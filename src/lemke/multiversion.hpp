// Hot loops compiled once per instruction set and chosen at load time (GCC/clang
// target_clones on ELF platforms with ifunc support). The loops have no reduction that the
// compiler may reorder (-ffp-contract=off, no fast-math), so every variant gives the same
// bits; only the vector width differs.
#pragma once
// AddressSanitizer builds have no clones: GCC says so by __SANITIZE_ADDRESS__, clang by
// __has_feature(address_sanitizer).
#if defined(__SANITIZE_ADDRESS__)
#define LEMKE_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LEMKE_ASAN 1
#endif
#endif
// clang before 19 has no clones (the baseline code only, the same bits): its target_clones
// is unsafe here. clang 14 calls the resolver itself, not the function it picks, from a
// translation unit that only declares a cloned function (wrong answers), and clang 14-16
// silently compile a cloned function once, for the baseline, when a declaration without
// the attribute (this project's headers) comes before it and a call after it.
#if defined(__clang__) && __clang_major__ < 19
#define LEMKE_NO_TARGET_CLONES 1
#endif
#if defined(__GNUC__) && defined(__x86_64__) && defined(__linux__) && !defined(LEMKE_NO_CLONES) \
    && !defined(LEMKE_ASAN) && !defined(LEMKE_NO_TARGET_CLONES)
#if defined(__clang__)
// The same three variants, "default" named first: clang (14 and 19 at least) checks the
// calls in every clone with the features of the first one named, so with "avx512f" first
// the baseline and AVX2 clones' calls of simd.hpp's always-inlined helpers on 64-byte
// vectors are errors ("changes the ABI"). The order does not choose: the resolver tests
// AVX-512F, then AVX2, as GCC's does.
#define LEMKE_CLONES __attribute__((target_clones("default", "avx2", "avx512f")))
#else
#define LEMKE_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#endif
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
