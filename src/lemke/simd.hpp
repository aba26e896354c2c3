// Eight-lane vectors (GCC/clang vector extensions) for the loops that keep eight running
// sums or maxima: each lane gets exactly the operations of the scalar code, in the same
// order, so the bits do not depend on the vector width. The compiler leaves the scalar
// forms of these loops scalar when a lane's update is a compare-and-select (pmax) or when
// a store may alias a load; written on vectors they run in vector registers on every
// instruction set (a 64-byte vector is split into the widest registers there are).
#pragma once
#include <cstdint>

namespace lemke {
namespace simd {

#if defined(__GNUC__)
#define LEMKE_SIMD 1
// The helpers are always inlined: no vector crosses a call, so the ABI note about passing
// 64-byte vectors without AVX-512 does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double v8d __attribute__((vector_size(64)));
typedef std::int64_t v8l __attribute__((vector_size(64)));
typedef double v4d __attribute__((vector_size(32)));
typedef std::int64_t v4l __attribute__((vector_size(32)));

#define LEMKE_SIMD_INLINE inline __attribute__((always_inline))

LEMKE_SIMD_INLINE v8d load8(const double* p) {
    v8d v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
LEMKE_SIMD_INLINE void store8(double* p, v8d v) { __builtin_memcpy(p, &v, sizeof v); }
// The lanes of two vectors picked by constant indices (0-7: a's, 8-15: b's).
#if defined(__has_builtin)
#if __has_builtin(__builtin_shufflevector)
#define LEMKE_SHUFFLE8(a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)
#endif
#endif
#ifndef LEMKE_SHUFFLE8
#define LEMKE_SHUFFLE8(a, b, ...) __builtin_shuffle(a, b, ::lemke::simd::v8l{__VA_ARGS__})
#endif

// x in every lane, as __builtin_shufflevector's shuffle of lane 0: one broadcast in every
// clone. Two other forms cost in the AVX-512 clones of GCC 12: the vector of x's,
// v8d{x, x, ...}, became one masked broadcast per lane (ten instructions, each merging into
// the last: a chain of eight, once per row in pivot_now's row updates and per row and
// pending pivot in flush; 2026-11-29, issue 31), and __builtin_shuffle's shuffle of lane 0
// a permute with an index vector (flush 17-20 % slower at n = 100 and 300).
LEMKE_SIMD_INLINE v8d splat8(double x) {
    v8d v = {};
    v[0] = x;
    return LEMKE_SHUFFLE8(v, v, 0, 0, 0, 0, 0, 0, 0, 0);
}
LEMKE_SIMD_INLINE v4d load4(const double* p) {
    v4d v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}
LEMKE_SIMD_INLINE void store4(double* p, v4d v) { __builtin_memcpy(p, &v, sizeof v); }
LEMKE_SIMD_INLINE v4d splat4(double x) {
#if defined(__clang__)
    return __builtin_shufflevector(v4d{x}, v4d{x}, 0, 0, 0, 0);
#else
    return __builtin_shuffle(v4d{x}, v4l{0, 0, 0, 0});
#endif
}
// |x| lane by lane (the sign bit cleared, as std::fabs).
LEMKE_SIMD_INLINE v8d abs8(v8d x) {
    const std::int64_t m = 0x7FFFFFFFFFFFFFFFLL;
    return reinterpret_cast<v8d>(reinterpret_cast<v8l>(x) & v8l{m, m, m, m, m, m, m, m});
}
// pmax(a, b) lane by lane: b where b > a, else a (Python's max).
LEMKE_SIMD_INLINE v8d max8(v8d a, v8d b) { return b > a ? b : a; }

// out[0..3] = ((x[0] + x[1]) + (x[2] + x[3])) + ((x[4] + x[5]) + (x[6] + x[7])) for the
// lanes x of a, b, c, d: the eight running sums' pairwise order, the same additions, taken
// by shuffles on whole vectors instead of lane by lane.
LEMKE_SIMD_INLINE void hsum4(v8d a, v8d b, v8d c, v8d d, double* out) {
    v8d ab = LEMKE_SHUFFLE8(a, b, 0, 8, 2, 10, 4, 12, 6, 14) +
             LEMKE_SHUFFLE8(a, b, 1, 9, 3, 11, 5, 13, 7, 15);  // (a0+a1, b0+b1, a2+a3, ...)
    v8d cd = LEMKE_SHUFFLE8(c, d, 0, 8, 2, 10, 4, 12, 6, 14) +
             LEMKE_SHUFFLE8(c, d, 1, 9, 3, 11, 5, 13, 7, 15);
    v8d h = LEMKE_SHUFFLE8(ab, cd, 0, 1, 8, 9, 4, 5, 12, 13) +
            LEMKE_SHUFFLE8(ab, cd, 2, 3, 10, 11, 6, 7, 14, 15);  // halves: a, b, c, d
    v8d s = h + LEMKE_SHUFFLE8(h, h, 4, 5, 6, 7, 0, 1, 2, 3);
    for (int l = 0; l < 4; ++l) out[l] = s[l];
}

// out[0..7] = the same pairwise sums for the lanes of eight vectors a..h, in three levels of
// shuffles (pairs, quads, halves) that leave the eight sums in one vector, stored at once.
LEMKE_SIMD_INLINE void hsum8(v8d a, v8d b, v8d c, v8d d, v8d e, v8d f, v8d g, v8d h,
                             double* out) {
#define LEMKE_PAIRS(x, y) (LEMKE_SHUFFLE8(x, y, 0, 8, 2, 10, 4, 12, 6, 14) + \
                           LEMKE_SHUFFLE8(x, y, 1, 9, 3, 11, 5, 13, 7, 15))
#define LEMKE_QUADS(x, y) (LEMKE_SHUFFLE8(x, y, 0, 1, 8, 9, 4, 5, 12, 13) + \
                           LEMKE_SHUFFLE8(x, y, 2, 3, 10, 11, 6, 7, 14, 15))
    v8d abcd = LEMKE_QUADS(LEMKE_PAIRS(a, b), LEMKE_PAIRS(c, d));  // (a0123 .. d0123, a4567 ..)
    v8d efgh = LEMKE_QUADS(LEMKE_PAIRS(e, f), LEMKE_PAIRS(g, h));
#undef LEMKE_PAIRS
#undef LEMKE_QUADS
    store8(out, LEMKE_SHUFFLE8(abcd, efgh, 0, 1, 2, 3, 8, 9, 10, 11) +
                    LEMKE_SHUFFLE8(abcd, efgh, 4, 5, 6, 7, 12, 13, 14, 15));
}
#endif

}  // namespace simd
}  // namespace lemke
