// Small dense kernels: Python's max/min semantics, the fixed-order dot product, the finite
// check, Ruiz equilibration by powers of two, the scaled system, and a pivoted LU solve.
// Every sum is in a fixed order with no fused multiply-add (-ffp-contract=off), so the
// results are the same bits on every instruction set (those the goldens record).
#pragma once
#include <cmath>
#include <cstring>
#include <limits>

#include "multiversion.hpp"
#include "simd.hpp"
#include "span.hpp"

namespace lemke {

constexpr double INF = std::numeric_limits<double>::infinity();
constexpr double EPS = 2.220446049250313e-16;

// Python's max(a, b) and min(a, b): the first argument unless the second compares
// greater (smaller); NaN and signed zeros come out as they do there.
inline double pmax(double a, double b) { return b > a ? b : a; }
inline double pmin(double a, double b) { return b < a ? b : a; }

inline std::int64_t float_bits(double x) { std::int64_t b; std::memcpy(&b, &x, 8); return b; }
inline double bits_float(std::int64_t b) { double x; std::memcpy(&x, &b, 8); return x; }

// (sum M[i, j] y[j], sum |M[i, j] y[j]|) over j < k in the fixed order: eight running sums
// (lane j mod 8 of the first 8 floor(k / 8) terms, the rest into lane 0), added pairwise.
void row_dot_and_size(const double* row, const double* y, idx k, double& dot, double& size);
double dot(const double* x, const double* y, idx k);

// row_dot_and_size's body, for loops compiled per instruction set that take it row by row:
// always inlined (a copy of its own would be compiled for the baseline instruction set,
// where a vector of 8 doubles is four registers, and called once per row through the
// clones' dispatch, which costs as much as a short row).
//
// Below 8 terms (here and in dot_lanes, dot_lanes4, dot_lanes8, dot_and_size_lanes2) only
// lane 0 takes terms: the other lanes stay +0, and lane 0, a sum that starts at +0, is never
// -0 (nor is a sum of |terms|), so the pairwise sums leave it as it is and the answer is
// lane 0's plain running sum: the same bits, without the lanes' set-up and pairwise sums
// (the unrevised method's short rows at small n).
LEMKE_ALWAYS_INLINE void dot_and_size_lanes(const double* row, const double* y, idx k,
                                            double& dot_out, double& size_out) {
    if (k < 8) {
        double a = 0.0, s = 0.0;
        for (idx j = 0; j < k; ++j) {
            double t = row[j] * y[j];
            a += t;
            s += std::fabs(t);
        }
        dot_out = a;
        size_out = s;
        return;
    }
    double a[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    idx j = 0;
#ifdef LEMKE_SIMD
    {
        simd::v8d va = simd::splat8(0.0), vs = simd::splat8(0.0);
        for (; j + 8 <= k; j += 8) {
            simd::v8d t = simd::load8(row + j) * simd::load8(y + j);
            va += t;
            vs += simd::abs8(t);
        }
        for (int l = 0; l < 8; ++l) {
            a[l] = va[l];
            s[l] = vs[l];
        }
    }
#else
    for (; j + 8 <= k; j += 8) {
        for (int l = 0; l < 8; ++l) {
            double t = row[j + l] * y[j + l];
            a[l] += t;
            s[l] += std::fabs(t);
        }
    }
#endif
    for (; j < k; ++j) {
        double t = row[j] * y[j];
        a[0] += t;
        s[0] += std::fabs(t);
    }
    dot_out = ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
    size_out = ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

// dot_and_size_lanes of two rows with one y: out = {dot 0, dot 1, size 0, size 1}, each
// row's sums in that function's order (the same bits), y's loads shared and the four
// pairwise sums taken by shuffles at once (simd::hsum4) rather than lane by lane per row.
LEMKE_ALWAYS_INLINE void dot_and_size_lanes2(const double* r0, const double* r1, const double* y,
                                             idx k, double* out) {
    if (k < 8) {  // (lane 0 alone: see dot_and_size_lanes)
        dot_and_size_lanes(r0, y, k, out[0], out[2]);
        dot_and_size_lanes(r1, y, k, out[1], out[3]);
        return;
    }
#ifdef LEMKE_SIMD
    simd::v8d a0 = simd::splat8(0.0), a1 = a0, s0 = a0, s1 = a0;
    idx j = 0;
    for (; j + 8 <= k; j += 8) {
        simd::v8d v = simd::load8(y + j);
        simd::v8d t0 = simd::load8(r0 + j) * v, t1 = simd::load8(r1 + j) * v;
        a0 += t0;
        s0 += simd::abs8(t0);
        a1 += t1;
        s1 += simd::abs8(t1);
    }
    if (j < k) {
        double b0 = a0[0], b1 = a1[0], c0 = s0[0], c1 = s1[0];
        for (; j < k; ++j) {
            double t0 = r0[j] * y[j], t1 = r1[j] * y[j];
            b0 += t0;
            c0 += std::fabs(t0);
            b1 += t1;
            c1 += std::fabs(t1);
        }
        a0[0] = b0;
        a1[0] = b1;
        s0[0] = c0;
        s1[0] = c1;
    }
    simd::hsum4(a0, a1, s0, s1, out);
#else
    dot_and_size_lanes(r0, y, k, out[0], out[2]);
    dot_and_size_lanes(r1, y, k, out[1], out[3]);
#endif
}

// dot's body, inlined by loops compiled per instruction set that take many short dot
// products (a call per row through the clones' dispatch costs as much as a short row).
inline double dot_lanes(const double* x, const double* y, idx k) {
    if (k < 8) {  // (lane 0 alone: see dot_and_size_lanes)
        double s = 0.0;
        for (idx j = 0; j < k; ++j) s += x[j] * y[j];
        return s;
    }
    double a[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    idx j = 0;
    // (plain lanes: GCC vectorizes them; written on vector types, this loop made the QP
    // 1.5x slower at n = 300, where dot runs on many short rows)
    for (; j + 8 <= k; j += 8)
        for (int l = 0; l < 8; ++l) a[l] += x[j + l] * y[j + l];
    for (; j < k; ++j) a[0] += x[j] * y[j];
    return ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
}

// dot_lanes of four rows with one y: out[t] = dot_lanes(x[t], y, k), each row's sums in
// dot's order (the same bits), y's loads shared by the four rows. On vector types: left to
// the vectorizer, the four rows' lanes came out interleaved by permutes (slower than four
// calls of dot_lanes).
LEMKE_ALWAYS_INLINE void dot_lanes4(const double* const* x, const double* y, idx k, double* out) {
    const double *x0 = x[0], *x1 = x[1], *x2 = x[2], *x3 = x[3];
    idx j = 0;
#ifdef LEMKE_SIMD
    simd::v8d s0 = simd::splat8(0.0), s1 = s0, s2 = s0, s3 = s0;
    for (; j + 8 <= k; j += 8) {
        simd::v8d v = simd::load8(y + j);
        s0 += simd::load8(x0 + j) * v;
        s1 += simd::load8(x1 + j) * v;
        s2 += simd::load8(x2 + j) * v;
        s3 += simd::load8(x3 + j) * v;
    }
    double a0 = s0[0], a1 = s1[0], a2 = s2[0], a3 = s3[0];
    for (; j < k; ++j) {
        double v = y[j];
        a0 += x0[j] * v;
        a1 += x1[j] * v;
        a2 += x2[j] * v;
        a3 += x3[j] * v;
    }
    if (k < 8) {  // (lane 0 alone: see dot_and_size_lanes)
        out[0] = a0;
        out[1] = a1;
        out[2] = a2;
        out[3] = a3;
        return;
    }
    s0[0] = a0;
    s1[0] = a1;
    s2[0] = a2;
    s3[0] = a3;
    simd::hsum4(s0, s1, s2, s3, out);
#else
    double a[4][8];
    for (int t = 0; t < 4; ++t)
        for (int l = 0; l < 8; ++l) a[t][l] = 0.0;
    for (; j + 8 <= k; j += 8)
        for (int l = 0; l < 8; ++l) {
            double v = y[j + l];
            a[0][l] += x0[j + l] * v;
            a[1][l] += x1[j + l] * v;
            a[2][l] += x2[j + l] * v;
            a[3][l] += x3[j + l] * v;
        }
    for (; j < k; ++j) {
        double v = y[j];
        a[0][0] += x0[j] * v;
        a[1][0] += x1[j] * v;
        a[2][0] += x2[j] * v;
        a[3][0] += x3[j] * v;
    }
    for (int t = 0; t < 4; ++t) {
        const double* b = a[t];
        out[t] = ((b[0] + b[1]) + (b[2] + b[3])) + ((b[4] + b[5]) + (b[6] + b[7]));
    }
#endif
}

// dot_lanes of eight rows with one y: out[t] = dot_lanes(x[t], y, k), each row's sums in
// dot's order (the same bits), y's loads shared and the eight rows' pairwise sums taken by
// one hsum8 (for short rows, the sums cost as much as the products).
LEMKE_ALWAYS_INLINE void dot_lanes8(const double* const* x, const double* y, idx k, double* out) {
    if (k < 8) {  // (lane 0 alone: see dot_and_size_lanes; four rows at a time)
        dot_lanes4(x, y, k, out);
        dot_lanes4(x + 4, y, k, out + 4);
        return;
    }
#ifdef LEMKE_SIMD
    simd::v8d s[8];
    for (int t = 0; t < 8; ++t) s[t] = simd::splat8(0.0);
    idx j = 0;
    for (; j + 8 <= k; j += 8) {
        simd::v8d v = simd::load8(y + j);
        for (int t = 0; t < 8; ++t) s[t] += simd::load8(x[t] + j) * v;
    }
    if (j < k) {
        double a[8];
        for (int t = 0; t < 8; ++t) a[t] = s[t][0];
        for (; j < k; ++j) {
            double v = y[j];
            for (int t = 0; t < 8; ++t) a[t] += x[t][j] * v;
        }
        for (int t = 0; t < 8; ++t) s[t][0] = a[t];
    }
    simd::hsum8(s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], out);
#else
    dot_lanes4(x, y, k, out);
    dot_lanes4(x + 4, y, k, out + 4);
#endif
}

// Whether every x[j] is finite: sum 0 * x[j] is 0 then and NaN otherwise, in any order, so
// eight running sums (a vector loop without reordering permission).
inline bool all_finite(const double* x, idx k) {
    double a[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    idx j = 0;
    for (; j + 8 <= k; j += 8)
        for (int l = 0; l < 8; ++l) a[l] += 0.0 * x[j + l];
    for (; j < k; ++j) a[0] += 0.0 * x[j];
    return ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7])) == 0.0;
}

// max_j |x[j]| (0 for k = 0). A maximum of terms that are not NaN is exact in any order, so
// eight running maxima; with a NaN the result is meaningless (callers check finiteness).
inline double absmax(const double* x, idx k) {
    double m[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    idx j = 0;
#ifdef LEMKE_SIMD
    simd::v8d v = simd::splat8(0.0);
    for (; j + 8 <= k; j += 8) v = simd::max8(v, simd::abs8(simd::load8(x + j)));
    for (int l = 0; l < 8; ++l) m[l] = v[l];
#else
    for (; j + 8 <= k; j += 8)
        for (int l = 0; l < 8; ++l) m[l] = pmax(m[l], std::fabs(x[j + l]));
#endif
    for (; j < k; ++j) m[0] = pmax(m[0], std::fabs(x[j]));
    return pmax(pmax(pmax(m[0], m[1]), pmax(m[2], m[3])), pmax(pmax(m[4], m[5]), pmax(m[6], m[7])));
}

// (finite, max |M|) of a square matrix. max|M| is meaningless when M is not finite.
bool finite_absmax(Mat<const double> M, double& m_max);

// The power of two nearest to 1 / x (x > 0), 1 for x = 0 or x not finite.
double pow2_scale(double x);
// pow2_scale(sqrt(x)) read off the exponent.
double pow2_rsqrt(double x);

// Row and column scales R, C (powers of two) of the LCP (M, q): Ruiz's iteration with q as
// one more column, at most 16 sweeps (linalg.equilibrate). `work`: 2n doubles.
void equilibrate(Mat<const double> M, const double* q, double* R, double* C, double* work);
// Whether M and q are finite (all_finite's test, M's in the first sweep) and, when they
// are, equilibrate(M, q) into R, C (the same scales).
bool equilibrate_finite(Mat<const double> M, const double* q, double* R, double* C,
                        double* work);

// A matrix kept by equilibrate_finite_kept (linalg.cpp), with what was computed of it.
struct KeptMatrix;

// equilibrate_finite, the same verdict and scales, keeping what the sweeps found of M alone
// (each full sweep's row and column maxima of M's part, with the R and C it started from)
// for matrices of up to SWEEP_MEMO_MAX rows, in a table per thread (64 slots chosen by a
// hash of M's bits for up to 32 rows, one slot for larger ones): a later call on the same
// M (bit for bit) takes a sweep that starts from the same R and C from there and computes
// only q's terms. A warm start's old basis (one M, q moved; or islands, each its own M)
// pays a hash and a comparison of M instead of the sweeps over it. Above 256 rows the
// slot takes a matrix in only on its second call in a row (one that moves every call is
// not copied). `kept`: M's entry when the result is true and M is kept (for
// solve_gathered_kept), else nullptr.
constexpr idx SWEEP_MEMO_MAX = 512;
bool equilibrate_finite_kept(Mat<const double> M, const double* q, double* R, double* C,
                             double* work, KeptMatrix*& kept);

// A = [R M C | R d / d_scale] (n x (n + 1)) and qs = R q; returns d_scale = max |R d|.
double scaled_into(Mat<const double> M, const double* q, const double* d, const double* R,
                   const double* C, Mat<double> A, double* qs);

// Solve M[idx, idx] x = y (k x k, gathered into A) by the pivoted elimination of
// linalg._eliminate (pivots taken in pairs, no refinement). A: k*k doubles of work; y is
// overwritten; x gets the solution. Returns whether the block is non-singular and x finite.
bool solve_gathered(Mat<const double> M, const idx* index, double* A, double* y, double* x, idx k);
// A x = y (k x k, A.ld = k) by the same elimination, A and y overwritten (solve_gathered's
// solve, of a block assembled by the caller). piv: nullptr, or 2k entries that get the
// pivots (the first k; the same operations, every update dense): A then holds the factors
// for lu_solve and lu_solve_transpose.
bool solve_in_place(Mat<double> A, double* y, double* x, idx k, idx* piv = nullptr);

// Solve again with the factors the elimination left in A (k x k) and its pivots piv
// (linalg._lu_solve): A x = y, each entry of y getting the operations it got there (the
// same bits as a fresh elimination with this y); or, lu_solve_transpose, A' x = y (U' v = y,
// L' u = v, x = P' u; no fresh elimination to match). y is overwritten; whether x is finite.
bool lu_solve(Mat<const double> A, const idx* piv, double* y, double* x, idx k);
bool lu_solve_transpose(Mat<const double> A, const idx* piv, double* y, double* x, idx k);

// solve_gathered, the same bits, for a block of a kept matrix (`kept`: equilibrate_finite_kept's;
// nullptr: solve_gathered itself): the last block of it factored is kept (its rows, factors
// and pivots), and a block of the same rows (a warm start re-solving its basis with a new
// q) is solved with them (lu_solve: the operations eliminate makes on y), neither gathered
// nor factored again; blocks of up to KEPT_BLOCK_MAX rows.
constexpr idx KEPT_BLOCK_MAX = 512;
bool solve_gathered_kept(Mat<const double> M, const idx* index, double* A, double* y, double* x,
                         idx k, KeptMatrix* kept);
// The factors and pivots `kept` holds for the block of rows index[:k] (what
// solve_gathered_kept last factored or reused there), for lu_solve and lu_solve_transpose;
// false when it holds another block (or none). Valid until the thread's next kept solve.
bool kept_factors(const KeptMatrix* kept, const idx* index, idx k, const double*& factors,
                  const idx*& piv);

// --- Double-double sums and the refined solve (linalg.two_product, two_sum, acc2,
// residual2, solve, refined_solve, principal_block). std::fma only here, explicitly: a b + c
// rounded once on every instruction set.

// (p, e) with p = fl(a b) and a b = p + e exactly (unless a b over- or underflows).
inline void two_product(double a, double b, double& p, double& e) {
    p = a * b;
    e = std::fma(a, b, -p);
}

// (s, e) with s = fl(a + b) and a + b = s + e exactly (Knuth).
inline void two_sum(double a, double b, double& s, double& e) {
    s = a + b;
    double z = s - a;
    e = (a - (s - z)) + (b - z);
}

// (hi, lo) += a b in double-double (Ogita, Rump and Oishi's Dot2, one term).
inline void acc2(double& hi, double& lo, double a, double b) {
    double p, e, s, f;
    two_product(a, b, p, e);
    two_sum(hi, p, s, f);
    hi = s;
    lo = lo + (e + f);
}

// y[r] = E[r, :k] x + e[r] for every row r of E, each row summed in double-double (zeros
// of E skipped) and then rounded (linalg.residual2). E.cols >= k.
void residual2(Mat<const double> E, const double* x, idx k, const double* e, double* y);

// H x = b for the k x k H by the elimination of linalg.solve (two pivots per pass, no
// refinement): x gets the solution (zeros first; what the elimination left when it fails).
// Returns ok: H and b finite, no exactly zero or NaN pivot, x finite.
bool solve(Mat<const double> H, const double* b, double* x, idx k);

// linalg.refined_solve: K is k x (k + j), x has k + j entries (the last j given, finite),
// lo k. One LU of K[:, :k] (the sparse row updates where the pivot rows are mostly zero),
// then `steps` steps of refinement with residuals in double-double and x carried in
// double-double (x[:k] + lo). Returns ok (x[:k] is garbage when not).
bool refined_solve(Mat<const double> K, const double* rhs, idx steps, double* x, double* lo);
// The same in the caller's work: k (k + 2) doubles (the factors of K[:, :k] in the first
// k * k, row-major, for lu_solve and lu_solve_transpose), piv 2k (the pivots).
bool refined_solve(Mat<const double> K, const double* rhs, idx steps, double* x, double* lo,
                   double* work, idx* piv);

// invert_in_place with its work arrays from this thread's workspace.
bool invert_in_place(Mat<double> G, idx k);

// out (k x k, row-major) = M[index][:, index] (linalg.principal_block).
void principal_block(Mat<const double> M, const idx* index, idx k, double* out);

// out[:k] = G[:k, :k] x[:k], each row by `dot`'s sums (linalg.matvec; four rows at a time,
// dot_lanes4).
void matvec(Mat<const double> G, idx k, const double* x, double* out);

// Replace G[:k, :k] by its inverse (linalg.invert_in_place, the same operations in the same
// order): Gauss-Jordan elimination with partial pivoting, two pivots per pass over the rows,
// the inverse's columns swapped back at the end. G may be larger than k x k. work: 4k
// doubles (a pass's multipliers, its pivot rows), piv: k. False when the block is not
// finite, a pivot is exactly zero or NaN, or the inverse is not finite (G then holds what
// the elimination left).
bool invert_in_place(Mat<double> G, idx k, double* work, idx* piv);

}  // namespace lemke
