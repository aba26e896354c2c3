#include "linalg.hpp"

#include "budget.hpp"

#include <vector>

#include "multiversion.hpp"

namespace lemke {

LEMKE_CLONES
void row_dot_and_size(const double* row, const double* y, idx k, double& dot_out,
                      double& size_out) {
    dot_and_size_lanes(row, y, k, dot_out, size_out);
}

LEMKE_CLONES
double dot(const double* x, const double* y, idx k) { return dot_lanes(x, y, k); }

LEMKE_CLONES
bool finite_absmax(Mat<const double> M, double& m_max) {
    idx n = M.rows;
    bool finite = true;
    m_max = 0.0;
    for (idx i = 0; i < n; ++i) {
        const double* r = M.row(i);
        finite &= all_finite(r, n);
        m_max = pmax(m_max, absmax(r, n));
    }
    return finite;
}

double pow2_scale(double x) {
    if (!(x > 0.0 && x < INF)) return 1.0;
    std::int64_t b = float_bits(x);
    std::int64_t biased = b >> 52;
    if (biased == 0 || biased >= 2045) {
        int e;
        double m = std::frexp(x, &e);
        return m < 0.7071067811865476 ? std::ldexp(1.0, 1 - e) : std::ldexp(1.0, -e);
    }
    const std::int64_t sqrt2_fraction = 0x6A09E667F3BCDLL;
    std::int64_t out = (b & 0xFFFFFFFFFFFFFLL) < sqrt2_fraction ? 2046 - biased : 2045 - biased;
    return bits_float(out << 52);
}

double pow2_rsqrt(double x) {
    if (!(x > 0.0 && x < INF)) return 1.0;
    std::int64_t biased = float_bits(x) >> 52;
    if (biased == 0) return pow2_scale(std::sqrt(x));
    return bits_float((1023 - ((biased - 1022) >> 1)) << 52);
}

namespace {

constexpr int EQUILIBRATE_SWEEPS = 16;

// K rows of sweep (rows[k], scaled by r[k]): each row's largest entry into out[k], every
// column's into cmax; with FINITE, each row's sum of 0 * M[i, j] into z[k] (all_finite's
// test); with UNIT (R and C all 1, the first sweep) the entries' sizes are |M[i, j]| itself
// (|M[i, j]| 1 1, the same number). A maximum of terms >= +0 that are not NaN is exact in
// any order: eight lanes, then four, then one by one, and cmax takes the K rows' terms at
// once (two rows: half the loads and stores of cmax, whose chain from row to row through
// memory bound the sweep at n = 24).
template <bool UNIT, bool FINITE, int K>
LEMKE_ALWAYS_INLINE void sweep_row(const double* const* rows, const double* r, const double* C,
                                   idx n, double* cmax, double* z, double* out) {
    double rm[K][8], zs[K][8];
    for (int k = 0; k < K; ++k)
        for (int l = 0; l < 8; ++l) rm[k][l] = zs[k][l] = 0.0;
    idx j = 0;
#ifdef LEMKE_SIMD
    {
        simd::v8d vr[K], rr[K], vz[K];
        for (int k = 0; k < K; ++k) {
            vr[k] = simd::splat8(0.0);
            rr[k] = simd::splat8(r[k]);
            vz[k] = simd::splat8(0.0);
        }
        for (; j + 8 <= n; j += 8) {
            simd::v8d top = simd::load8(cmax + j);
            for (int k = 0; k < K; ++k) {
                simd::v8d x = simd::load8(rows[k] + j);
                if (FINITE) vz[k] += simd::splat8(0.0) * x;
                simd::v8d a = UNIT ? simd::abs8(x) : (simd::abs8(x) * rr[k]) * simd::load8(C + j);
                vr[k] = simd::max8(vr[k], a);
                top = simd::max8(top, a);
            }
            simd::store8(cmax + j, top);
        }
        for (int k = 0; k < K; ++k)
            for (int l = 0; l < 8; ++l) {
                rm[k][l] = vr[k][l];
                zs[k][l] = vz[k][l];
            }
    }
#else
    for (; j + 8 <= n; j += 8) {
        for (int k = 0; k < K; ++k)
            for (int l = 0; l < 8; ++l) {
                if (FINITE) zs[k][l] += 0.0 * rows[k][j + l];
                double a = UNIT ? std::fabs(rows[k][j + l]) : std::fabs(rows[k][j + l]) * r[k] * C[j + l];
                rm[k][l] = pmax(rm[k][l], a);
                cmax[j + l] = pmax(cmax[j + l], a);
            }
    }
#endif
    if (j + 4 <= n) {
        for (int k = 0; k < K; ++k)
            for (int l = 0; l < 4; ++l) {
                if (FINITE) zs[k][l] += 0.0 * rows[k][j + l];
                double a = UNIT ? std::fabs(rows[k][j + l]) : std::fabs(rows[k][j + l]) * r[k] * C[j + l];
                rm[k][l] = pmax(rm[k][l], a);
                cmax[j + l] = pmax(cmax[j + l], a);
            }
        j += 4;
    }
    for (; j < n; ++j) {
        for (int k = 0; k < K; ++k) {
            if (FINITE) zs[k][0] += 0.0 * rows[k][j];
            double a = UNIT ? std::fabs(rows[k][j]) : std::fabs(rows[k][j]) * r[k] * C[j];
            rm[k][0] = pmax(rm[k][0], a);
            cmax[j] = pmax(cmax[j], a);
        }
    }
    for (int k = 0; k < K; ++k) {
        const double* q = zs[k];
        const double* m = rm[k];
        if (FINITE) z[k] = ((q[0] + q[1]) + (q[2] + q[3])) + ((q[4] + q[5]) + (q[6] + q[7]));
        out[k] = pmax(pmax(pmax(m[0], m[1]), pmax(m[2], m[3])),
                      pmax(pmax(m[4], m[5]), pmax(m[6], m[7])));
    }
}

#ifdef LEMKE_SIMD
// The largest lane of each of a, b, c, d into out[0..3], by shuffles on whole vectors (as
// simd::hsum4 takes sums; a maximum of terms >= +0 that are not NaN is exact in any order).
LEMKE_ALWAYS_INLINE void hmax4(simd::v8d a, simd::v8d b, simd::v8d c, simd::v8d d,
                               double* out) {
    using simd::max8;
    simd::v8d ab = max8(LEMKE_SHUFFLE8(a, b, 0, 8, 2, 10, 4, 12, 6, 14),
                        LEMKE_SHUFFLE8(a, b, 1, 9, 3, 11, 5, 13, 7, 15));
    simd::v8d cd = max8(LEMKE_SHUFFLE8(c, d, 0, 8, 2, 10, 4, 12, 6, 14),
                        LEMKE_SHUFFLE8(c, d, 1, 9, 3, 11, 5, 13, 7, 15));
    simd::v8d h = max8(LEMKE_SHUFFLE8(ab, cd, 0, 1, 8, 9, 4, 5, 12, 13),
                       LEMKE_SHUFFLE8(ab, cd, 2, 3, 10, 11, 6, 7, 14, 15));
    simd::v8d m = max8(h, LEMKE_SHUFFLE8(h, h, 4, 5, 6, 7, 0, 1, 2, 3));
    for (int l = 0; l < 4; ++l) out[l] = m[l];
}

// sweep_row on four rows, their maxima kept in vectors to the end and taken by hmax4 (one
// row at a time, each row's eight lanes went to scalars: most of a sweep at n = 24), the
// FINITE sums of the four rows in one vector (every term is +-0 or NaN, so any sum of them
// is 0 exactly when each row's is): `all` cleared when it is not 0.
template <bool UNIT, bool FINITE>
LEMKE_ALWAYS_INLINE void sweep_row4(const double* const* rows, const double* r, const double* C,
                                    idx n, double* cmax, bool& all, double* out) {
    simd::v8d vr[4], rr[4], vz = simd::splat8(0.0);
    for (int k = 0; k < 4; ++k) {
        vr[k] = simd::splat8(0.0);
        rr[k] = simd::splat8(r[k]);
    }
    idx j = 0;
    for (; j + 8 <= n; j += 8) {
        simd::v8d top = simd::load8(cmax + j);
        for (int k = 0; k < 4; ++k) {
            simd::v8d x = simd::load8(rows[k] + j);
            if (FINITE) vz += simd::splat8(0.0) * x;
            simd::v8d a = UNIT ? simd::abs8(x) : (simd::abs8(x) * rr[k]) * simd::load8(C + j);
            vr[k] = simd::max8(vr[k], a);
            top = simd::max8(top, a);
        }
        simd::store8(cmax + j, top);
    }
    double tm[4] = {0.0, 0.0, 0.0, 0.0}, zt = 0.0;
    for (; j < n; ++j) {
        double top = cmax[j];
        for (int k = 0; k < 4; ++k) {
            if (FINITE) zt += 0.0 * rows[k][j];
            double a = UNIT ? std::fabs(rows[k][j]) : std::fabs(rows[k][j]) * r[k] * C[j];
            tm[k] = pmax(tm[k], a);
            top = pmax(top, a);
        }
        cmax[j] = top;
    }
    hmax4(vr[0], vr[1], vr[2], vr[3], out);
    for (int k = 0; k < 4; ++k) out[k] = pmax(out[k], tm[k]);
    if (FINITE) {
        for (int l = 0; l < 8; ++l) zt += vz[l];
        all &= zt == 0.0;
    }
}
#endif

template <bool UNIT, bool FINITE>
LEMKE_ALWAYS_INLINE double sweep_rows(Mat<const double> M, const double* q, const double* R, const double* C,
                         double cq, double* rmax, double* cmax, double* mrow, bool& all) {
    idx n = M.rows;
    double qmax = 0.0;
    idx i = 0;
#ifdef LEMKE_SIMD
    for (; i + 4 <= n; i += 4) {
        const double* rows[4] = {M.row(i), M.row(i + 1), M.row(i + 2), M.row(i + 3)};
        double m[4];
        sweep_row4<UNIT, FINITE>(rows, R + i, C, n, cmax, all, m);
        for (idx k = i; k < i + 4; ++k) {
            mrow[k] = m[k - i];
            double a = std::fabs(q[k]) * R[k] * cq;
            rmax[k] = pmax(m[k - i], a);
            qmax = pmax(qmax, a);
        }
    }
#endif
    for (; i < n; i += 2) {
        const double* rows[2] = {M.row(i), i + 1 < n ? M.row(i + 1) : nullptr};
        double z[2] = {0.0, 0.0}, m[2];
        if (i + 1 < n)
            sweep_row<UNIT, FINITE, 2>(rows, R + i, C, n, cmax, z, m);
        else
            sweep_row<UNIT, FINITE, 1>(rows, R + i, C, n, cmax, z, m);
        for (idx k = i; k < i + 2 && k < n; ++k) {
            if (FINITE) all &= z[k - i] == 0.0;
            mrow[k] = m[k - i];
            double a = std::fabs(q[k]) * R[k] * cq;
            rmax[k] = pmax(m[k - i], a);
            qmax = pmax(qmax, a);
        }
    }
    return qmax;
}

// One sweep: the largest entry of each row (q's times cq included) and column of
// diag(R) M diag(C) into rmax, cmax, the rows' largest entries of M's part alone into mrow;
// returns q's largest. Every term is >= +0 and not NaN (M is finite, the scales positive and
// finite, or the sweeps stop), and a maximum of such terms is exact in any order: eight
// running maxima per row, so the loop is a vector loop. With `finite`, also whether every
// entry of M is finite (the sums of 0 * M[i, j], all_finite's test, in the same pass).
// `unit`: R and C are all 1 (the first sweep).
LEMKE_CLONES
double sweep(Mat<const double> M, const double* q, const double* R, const double* C, double cq,
             double* rmax, double* cmax, double* mrow, bool* finite, bool unit) {
    idx n = M.rows;
    for (idx j = 0; j < n; ++j) cmax[j] = 0.0;
    bool all = true;
    double qmax;
    if (finite)
        qmax = unit ? sweep_rows<true, true>(M, q, R, C, cq, rmax, cmax, mrow, all)
                    : sweep_rows<false, true>(M, q, R, C, cq, rmax, cmax, mrow, all);
    else
        qmax = unit ? sweep_rows<true, false>(M, q, R, C, cq, rmax, cmax, mrow, all)
                    : sweep_rows<false, false>(M, q, R, C, cq, rmax, cmax, mrow, all);
    if (finite) *finite = all;
    return qmax;
}

// A sweep after one that left R and C as they were: M's part of each row's maximum (mrow)
// and every column's are the same numbers, so only q's terms are new (the same rmax and
// qmax as sweep's).
double sweep_q(const double* q, const double* R, double cq, idx n, double* rmax,
               const double* mrow) {
    double qmax = 0.0;
    for (idx i = 0; i < n; ++i) {
        double a = std::fabs(q[i]) * R[i] * cq;
        rmax[i] = pmax(mrow[i], a);
        qmax = pmax(qmax, a);
    }
    return qmax;
}

// Whether every x[i] (i < k) that is not zero lies in [0.5, 2] (balanced), and each x[i]
// replaced by pow2_rsqrt(x[i]): by exponent arithmetic without a branch when every x[i] is
// zero or a positive normal float, else one by one. The tests read the bits as integers
// (for a float of sign 0 that is not NaN, the order of its bits is the order of the
// numbers): integer compares, which the compiler makes vector loops (its float compares
// on vectors of masks it had made one by one). `same`: whether every new x[i] is 1.
LEMKE_CLONES
bool rsqrt_all(double* x, idx k, bool& same) {
    const std::uint64_t TINY = 0x0010000000000000ULL, INF_BITS = 0x7FF0000000000000ULL;
    const std::uint64_t HALF = 0x3FE0000000000000ULL, TWO = 0x4000000000000000ULL;
    std::uint64_t slow = 0, off = 0;
    for (idx i = 0; i < k; ++i) {
        std::uint64_t b;
        std::memcpy(&b, x + i, 8);
        std::uint64_t mag = b & 0x7FFFFFFFFFFFFFFFULL;
        // fast: a == 0 (either sign) or TINY <= a < INF (a positive normal float)
        slow |= static_cast<std::uint64_t>(mag != 0 && b - TINY >= INF_BITS - TINY);
        // a > 0 and a < 0.5 or a > 2, a not NaN (sign 0, 0 < bits <= INF's)
        off |= static_cast<std::uint64_t>(b - 1 < INF_BITS && b - HALF > TWO - HALF);
    }
    bool balanced = off == 0;
    if (slow != 0) {
        same = true;
        for (idx i = 0; i < k; ++i) {
            x[i] = pow2_rsqrt(x[i]);
            same &= x[i] == 1.0;
        }
        return balanced;
    }
    // pow2_rsqrt of a positive normal float: 2^-((e - 1022) >> 1) for the biased exponent e
    const std::uint64_t ONE = 0x3FF0000000000000ULL;
    std::uint64_t other = 0;
    for (idx i = 0; i < k; ++i) {
        std::uint64_t b;
        std::memcpy(&b, x + i, 8);
        std::uint64_t mag = b & 0x7FFFFFFFFFFFFFFFULL;
        std::int64_t e = static_cast<std::int64_t>(mag >> 52);
        std::uint64_t v = static_cast<std::uint64_t>(1023 - ((e - 1022) >> 1)) << 52;
        v = mag == 0 ? ONE : v;
        other |= static_cast<std::uint64_t>(v != ONE);
        std::memcpy(x + i, &v, 8);
    }
    same = other == 0;
    return balanced;
}

}  // namespace

namespace {

// What the full sweeps of an equilibrate_finite_kept call found of a matrix (n x n,
// finite): for the t-th full sweep of that call its R and C and what it found of M alone,
// the rows' maxima of M's part (mrow) and the columns' (cmax). A full sweep's mrow and
// cmax depend on M, R and C only (q enters rmax and qmax alone), so a later call on the
// same M whose t-th full sweep starts from the same R and C finds the same numbers: it
// takes them from here and computes q's terms (sweep_q: rmax and qmax, the same
// operations as sweep's).
struct SweepMemo {
    std::vector<double> M, rec;  // rec: per full sweep t, [R | C | mrow | cmax] (4n)
    idx n = -1;
    int count = 0;  // records valid for M
};

}  // namespace

// A kept matrix (equilibrate_finite_kept): its sweeps' memo, and the last basis block of it
// that solve_gathered_kept factored (its rows, factors and eliminate's pivots; k = -1:
// none). The block is dropped whenever another matrix takes the slot.
struct KeptMatrix {
    SweepMemo memo;
    std::vector<double> factors;
    std::vector<idx> piv, index;
    idx k = -1;
    std::uint64_t seen = 0;  // the large slot: the hash of the last matrix not copied in
};

namespace {

// The table's slots: 2^KEPT_SLOT_BITS for matrices of up to KEPT_HASHED_MAX rows, chosen by
// a hash of their bits, and one for the larger ones (a slot grows to what its largest
// matrix needed: about 33 kB at KEPT_HASHED_MAX rows; at SWEEP_MEMO_MAX 2 MB for M's copy,
// up to 2 MB for a block's factors and 16 kB a sweep's record).
constexpr int KEPT_SLOT_BITS = 6;
constexpr idx KEPT_HASHED_MAX = 32;
// Above this many rows the large slot copies a matrix in only on its second call in a row
// (memo_matches); up to it at once (a simulation step that solves one M a few times, as
// bench_small's pile does, gains from the second call on).
constexpr idx KEPT_COPY_AT_ONCE_MAX = 256;
constexpr std::size_t KEPT_SLOTS = std::size_t{1} << KEPT_SLOT_BITS;

// A hash of M's bits (n x n).
std::uint64_t matrix_hash(Mat<const double> M) {
    idx n = M.rows;
    std::uint64_t sum = 0, all = 0;
    for (idx i = 0; i < n; ++i) {
        const double* r = M.row(i);
        for (idx j = 0; j < n; ++j) {
            std::uint64_t b;
            std::memcpy(&b, r + j, 8);
            sum += b;
            all ^= b;
        }
    }
    return (sum ^ ((all << 17) | (all >> 47)) ^ static_cast<std::uint64_t>(n)) *
           0x9E3779B97F4A7C15ULL;
}

// The slot of this thread's table for M.
KeptMatrix& kept_slot(Mat<const double> M) {
    thread_local std::vector<KeptMatrix> table;
    if (table.empty()) table.resize(KEPT_SLOTS + 1);
    if (M.rows > KEPT_HASHED_MAX) return table[KEPT_SLOTS];
    return table[static_cast<std::size_t>(matrix_hash(M) >> (64 - KEPT_SLOT_BITS))];
}

// Whether `kept` holds M (n x n) after this call. When it held another matrix, its records
// and block are dropped and M is copied in; above KEPT_COPY_AT_ONCE_MAX rows only when M
// has the hash of the last matrix left out (M seen twice in a row: a warm start's M that
// stays), else M is left out too (nothing kept: a matrix that moves every call pays a read
// of M for the hash, not a copy of it; a hash that matches by chance costs only a copy).
bool memo_matches(KeptMatrix& kept, Mat<const double> M) {
    SweepMemo& memo = kept.memo;
    idx n = M.rows;
    std::size_t row_bytes = static_cast<std::size_t>(n) * sizeof(double);
    idx i = 0;
    if (memo.n == n)
        while (i < n && std::memcmp(memo.M.data() + i * n, M.row(i), row_bytes) == 0) ++i;
    if (memo.n == n && i == n) return true;
    memo.count = 0;
    kept.k = -1;
    if (n > KEPT_COPY_AT_ONCE_MAX) {
        std::uint64_t h = matrix_hash(M);
        bool again = memo.n == -1 && kept.seen == h;
        kept.seen = h;
        if (!again) {
            memo.n = -1;
            return false;
        }
        i = 0;
    }
    if (memo.n != n) {
        memo.M.resize(static_cast<std::size_t>(n * n));
        memo.n = n;
        i = 0;
    }
    for (; i < n; ++i) std::memcpy(memo.M.data() + i * n, M.row(i), row_bytes);
    return true;
}

// One full sweep (sweep's outputs), the t-th of this call: from `memo` when it holds the
// t-th sweep from these R and C, else sweep itself, recorded in `memo` (when not null).
double full_sweep(Mat<const double> M, const double* q, const double* R, const double* C,
                  double cq, double* rmax, double* cmax, double* mrow, bool* finite, bool unit,
                  SweepMemo* memo, int t) {
    idx n = M.rows;
    std::size_t bytes = static_cast<std::size_t>(n) * sizeof(double);
    double* rec = memo && t < memo->count ? memo->rec.data() + 4 * n * t : nullptr;
    if (rec && std::memcmp(rec, R, bytes) == 0 &&
        std::memcmp(rec + n, C, bytes) == 0) {
        std::memcpy(mrow, rec + 2 * n, bytes);
        std::memcpy(cmax, rec + 3 * n, bytes);
        if (finite) *finite = true;  // (the records are of a finite M)
        return sweep_q(q, R, cq, n, rmax, mrow);
    }
    double qmax = sweep(M, q, R, C, cq, rmax, cmax, mrow, finite, unit);
    if (memo) {
        if (finite && !*finite) {
            memo->n = -1;  // (not finite: nothing kept)
            return qmax;
        }
        if (memo->rec.size() < static_cast<std::size_t>(4 * n * (t + 1)))
            memo->rec.resize(static_cast<std::size_t>(4 * n * (t + 1)));
        rec = memo->rec.data() + 4 * n * t;
        if (n > 0) {  // (n = 0: rec is null, and memcpy's pointers may not be, even for 0 bytes)
            std::memcpy(rec, R, bytes);
            std::memcpy(rec + n, C, bytes);
            std::memcpy(rec + 2 * n, mrow, bytes);
            std::memcpy(rec + 3 * n, cmax, bytes);
        }
        memo->count = t + 1;
    }
    return qmax;
}

// equilibrate's sweeps; with `finite`, the first sweep (run even past a deadline) also
// tells whether M is finite, and the scales are left alone when it is not. `memo`: the
// full sweeps taken from and recorded in it (full_sweep; the same numbers). Compiled per
// instruction set for its own loops: the baseline build of absmax(q) on eight-lane vectors
// went through the stack (two scalar stores, then a 16-byte load, per lane pair and per
// pass), half of this function's time at n = 24.
LEMKE_CLONES
void sweeps(Mat<const double> M, const double* q, double* R, double* C, double* work,
            bool* finite, SweepMemo* memo = nullptr) {
    idx n = M.rows;
    thread_local std::vector<double> rows;
    rows.resize(static_cast<std::size_t>(n));
    double* mrow = rows.data();
    for (idx i = 0; i < n; ++i) { R[i] = 1.0; C[i] = 1.0; }
    double cq = pow2_scale(absmax(q, n));
    double* rmax = work;
    double* cmax = work + n;
    double qmax = 0.0;
    int t = 0;  // full sweeps made
    if (finite) {
        qmax = full_sweep(M, q, R, C, cq, rmax, cmax, mrow, finite, true, memo, t++);
        if (!*finite) return;
    }
    bool same = false;  // the last sweep left R and C as they were
    for (int sweep_no = 0; sweep_no < EQUILIBRATE_SWEEPS; ++sweep_no) {
        // past the thread's deadline the scales are left as they are: the run that needs
        // them stops at its first look (budget.hpp)
        if (n >= 64 && deadline_passed() >= 0) break;
        bool balanced;
        if (same) {
            // cmax's factors are all 1 (and balanced) from the last sweep: the rows alone
            // (so `same` stays true when the rows' factors are all 1 too)
            qmax = sweep_q(q, R, cq, n, rmax, mrow);
            balanced = !(qmax > 0.0 && (qmax < 0.5 || qmax > 2.0));
            balanced &= rsqrt_all(work, n, same);
        } else {
            if (sweep_no > 0 || !finite)
                qmax = full_sweep(M, q, R, C, cq, rmax, cmax, mrow, nullptr, sweep_no == 0,
                                  memo, t++);
            balanced = !(qmax > 0.0 && (qmax < 0.5 || qmax > 2.0));
            balanced &= rsqrt_all(work, 2 * n, same);
        }
        if (balanced) break;
        for (idx i = 0; i < n; ++i) {
            R[i] = R[i] * rmax[i];
            C[i] = C[i] * cmax[i];
        }
        cq *= pow2_rsqrt(qmax);
    }
}

}  // namespace

void equilibrate(Mat<const double> M, const double* q, double* R, double* C, double* work) {
    sweeps(M, q, R, C, work, nullptr);
}

bool equilibrate_finite(Mat<const double> M, const double* q, double* R, double* C,
                        double* work) {
    if (!all_finite(q, M.rows)) return false;
    bool finite = true;
    sweeps(M, q, R, C, work, &finite);
    return finite;
}

bool equilibrate_finite_kept(Mat<const double> M, const double* q, double* R, double* C,
                             double* work, KeptMatrix*& kept) {
    kept = nullptr;
    if (M.rows > SWEEP_MEMO_MAX) return equilibrate_finite(M, q, R, C, work);
    if (!all_finite(q, M.rows)) return false;
    KeptMatrix& slot = kept_slot(M);
    bool finite = true;
    if (!memo_matches(slot, M)) {  // (M left out of the kept table: the plain sweeps)
        sweeps(M, q, R, C, work, &finite);
        return finite;
    }
    sweeps(M, q, R, C, work, &finite, &slot.memo);
    if (finite) kept = &slot;
    return finite;
}

LEMKE_CLONES
double scaled_into(Mat<const double> M, const double* q, const double* d, const double* R,
                   const double* C, Mat<double> A, double* qs) {
    idx n = M.rows;
    double d_scale = 0.0;
    for (idx i = 0; i < n; ++i) d_scale = pmax(d_scale, std::fabs(d[i]) * R[i]);
    double inv_d = 1.0 / d_scale;
    for (idx i = 0; i < n; ++i) {
        double r = R[i];
        const double* mrow = M.row(i);
        double* arow = A.row(i);
        for (idx j = 0; j < n; ++j) arow[j] = (mrow[j] * r) * C[j];
        arow[n] = (d[i] * r) * inv_d;
        qs[i] = q[i] * r;
    }
    return d_scale;
}

namespace {

// The row r in j..k-1 with the largest |A[r, j] - A[r, j - 1] shift| (shift 0: |A[r, j]|),
// -1 when that is 0 or NaN.
idx pivot_row(Mat<double> A, idx j, idx k, double shift) {
    idx p = -1;
    double best = 0.0;
    for (idx r = j; r < k; ++r) {
        double a = shift != 0.0 ? std::fabs(A(r, j) - A(r, j - 1) * shift) : std::fabs(A(r, j));
        if (a > best) {
            best = a;
            p = r;
        } else if (a != a) {
            return -1;
        }
    }
    return p;
}

void swap_rows(Mat<double> A, idx i, idx j, idx k) {
    if (i == j) return;
    for (idx c = 0; c < k; ++c) {
        double t = A(i, c);
        A(i, c) = A(j, c);
        A(j, c) = t;
    }
}

LEMKE_CLONES  // clang: a declaration before a cloned function's first use must say so too
bool eliminate(Mat<double> A, double* y, double* x, idx k, idx* piv, bool sparse = true);

}  // namespace

// The block M[index, index] gathered into a (k x k), then eliminate's solve (the dense
// updates: no pivots kept).
bool solve_gathered(Mat<const double> M, const idx* index, double* a, double* y, double* x,
                    idx k) {
    Mat<double> A(a, k, k);
    for (idx r = 0; r < k; ++r) {
        const double* mrow = M.row(index[r]);
        for (idx c = 0; c < k; ++c) A(r, c) = mrow[index[c]];
    }
    return solve_in_place(A, y, x, k);
}

bool solve_in_place(Mat<double> A, double* y, double* x, idx k, idx* piv) {
    for (idx i = 0; i < k; ++i) x[i] = 0.0;
    return eliminate(A, y, x, k, piv, false);
}

void residual2(Mat<const double> E, const double* x, idx k, const double* e, double* y) {
    for (idx r = 0; r < E.rows; ++r) {
        const double* er = E.row(r);
        double s = e[r], err = 0.0;
        for (idx c = 0; c < k; ++c) {
            double a = er[c];
            if (a != 0.0) acc2(s, err, a, x[c]);  // a zero adds nothing
        }
        y[r] = s + err;
    }
}

namespace {

// The columns c in lo..k-1 where x[c] or u[c] is not zero, into list; their count, or -1
// when they are a quarter of the range or more (linalg._nonzero_columns).
idx nonzero_columns(const double* x, const double* u, idx lo, idx k, idx* list) {
    idx m = 0;
    for (idx c = lo; c < k; ++c)
        if (x[c] != 0.0 || u[c] != 0.0) list[m++] = c;
    return 4 * m < k - lo ? m : -1;
}

// x = U^-1 y with U the upper triangle of A (linalg._back_substitute); whether x is finite.
// (Inlined: a cloned caller, eliminate, tail-called the baseline copy with its vector
// registers' upper halves dirty, which GCC 12 did not clear with a vzeroupper.)
LEMKE_ALWAYS_INLINE bool back_substitute(Mat<const double> A, const double* y, double* x, idx k) {
    for (idx r = k - 1; r >= 0; --r) {
        const double* ar = A.row(r);
        double acc = y[r];
        for (idx c = r + 1; c < k; ++c) acc -= ar[c] * x[c];
        x[r] = acc / ar[r];
    }
    return all_finite(x, k);
}

// linalg._eliminate: A x = y in place (x starts at 0), two pivots per pass. piv: nullptr,
// or 2k entries: the first k get each step's pivot row (for lu_solve), the second k list
// the pivot rows' non-zero columns, whose updates alone are made when they are under a
// quarter of the row (unless `sparse` is false: then every update is made, as with no piv,
// the same operations as that call's).
LEMKE_CLONES
bool eliminate(Mat<double> A, double* y, double* x, idx k, idx* piv, bool sparse) {
    bool finite = all_finite(y, k);
    for (idx r = 0; r < k; ++r) finite &= all_finite(A.row(r), k);
    if (!finite) return false;
    idx j = 0;
    while (j < k) {
        idx p = pivot_row(A, j, k, 0.0);
        if (p < 0) return false;
        if (piv) piv[j] = p;
        swap_rows(A, j, p, k);
        double t = y[j]; y[j] = y[p]; y[p] = t;
        double inv = 1.0 / A(j, j);
        if (j + 1 == k) break;
        for (idx r = j + 1; r < k; ++r) A(r, j) *= inv;
        double h = A(j, j + 1);
        p = pivot_row(A, j + 1, k, h);
        if (p < 0) return false;
        if (piv) piv[j + 1] = p;
        swap_rows(A, j + 1, p, k);
        t = y[j + 1]; y[j + 1] = y[p]; y[p] = t;
        double l1 = A(j + 1, j);
        for (idx c = j + 1; c < k; ++c) A(j + 1, c) -= l1 * A(j, c);
        y[j + 1] -= l1 * y[j];
        double inv1 = 1.0 / A(j + 1, j + 1);
        idx m = -1;
        const double* aj = A.row(j);
        const double* aj1 = A.row(j + 1);
        if (piv && sparse) m = nonzero_columns(aj, aj1, j + 2, k, piv + k);
        for (idx r = j + 2; r < k; ++r) {
            double f = A(r, j);
            double g = (A(r, j + 1) - f * h) * inv1;
            A(r, j + 1) = g;
            if (f != 0.0 || g != 0.0) {
                if (m >= 0) {
                    double* ar = A.row(r);
                    for (idx s = 0; s < m; ++s) {
                        idx c = piv[k + s];
                        ar[c] = (ar[c] - f * aj[c]) - g * aj1[c];
                    }
                }
                y[r] = (y[r] - f * y[j]) - g * y[j + 1];
            }
        }
        if (m < 0) {
            for (idx r = j + 2; r < k; ++r) {
                double f = A(r, j), g = A(r, j + 1);
                if (f != 0.0 || g != 0.0) {
                    double* ar = A.row(r);
                    for (idx c = j + 2; c < k; ++c) ar[c] = (ar[c] - f * aj[c]) - g * aj1[c];
                }
            }
        }
        j += 2;
    }
    return back_substitute(A, y, x, k);
}

// The work of solve and refined_solve, one per thread: A (k x k), y, d, and the pivots.
struct SolveWork {
    std::vector<double> f;
    std::vector<idx> piv;
    void layout(idx k) {
        f.resize(static_cast<std::size_t>(k * (k + 2)));
        piv.resize(static_cast<std::size_t>(2 * k));
    }
};

thread_local SolveWork solve_work;

}  // namespace

// Solve again with the factors eliminate left in A and piv (linalg._lu_solve): y is
// overwritten; each row of y gets the operations it got there.
bool lu_solve(Mat<const double> A, const idx* piv, double* y, double* x, idx k) {
    for (idx j = 0; j < k; ++j) {
        idx p = piv[j];
        double t = y[j]; y[j] = y[p]; y[p] = t;
    }
    for (idx j = 0; j + 1 < k; j += 2) {
        y[j + 1] -= A(j + 1, j) * y[j];
        for (idx r = j + 2; r < k; ++r) {
            double f = A(r, j), g = A(r, j + 1);
            if (f != 0.0 || g != 0.0) y[r] = (y[r] - f * y[j]) - g * y[j + 1];
        }
    }
    return back_substitute(A, y, x, k);
}

// A' x = y with the factors eliminate left in A and piv (P A = L U: L unit lower, its
// multipliers below A's diagonal, U on and above it, P the row exchanges piv[0..k) in
// order): U' v = y, L' u = v, x = P' u (the exchanges undone in reverse order). y is
// overwritten. Each sum by columns of U' and L', i.e. rows of A (axpy updates: no order of
// terms for a vector unit to change).
bool lu_solve_transpose(Mat<const double> A, const idx* piv, double* y, double* x, idx k) {
    for (idx c = 0; c < k; ++c) {  // U' v = y, forward: v_c, then row c of U
        const double* ac = A.row(c);
        double v = y[c] / ac[c];
        y[c] = v;
        for (idx r = c + 1; r < k; ++r) y[r] -= ac[r] * v;
    }
    for (idx c = k - 1; c > 0; --c) {  // L' u = v, backward: u_c, then row c of L
        const double* ac = A.row(c);
        double u = y[c];
        for (idx r = 0; r < c; ++r) y[r] -= ac[r] * u;
    }
    for (idx j = k - 1; j >= 0; --j) {
        idx p = piv[j];
        double t = y[j]; y[j] = y[p]; y[p] = t;
    }
    for (idx i = 0; i < k; ++i) x[i] = y[i];
    return all_finite(x, k);
}


bool solve(Mat<const double> H, const double* b, double* x, idx k) {
    for (idx i = 0; i < k; ++i) x[i] = 0.0;
    if (H.rows != k || H.cols != k) return false;
    SolveWork& w = solve_work;
    w.layout(k);
    Mat<double> A(w.f.data(), k, k);
    double* y = w.f.data() + k * k;
    for (idx r = 0; r < k; ++r) {
        const double* hr = H.row(r);
        for (idx c = 0; c < k; ++c) A(r, c) = hr[c];
        y[r] = b[r];
    }
    return eliminate(A, y, x, k, nullptr);
}

bool solve_gathered_kept(Mat<const double> M, const idx* index, double* a, double* y,
                         double* x, idx k, KeptMatrix* kept) {
    if (kept == nullptr || k > KEPT_BLOCK_MAX) return solve_gathered(M, index, a, y, x, k);
    if (kept->k == k &&
        std::memcmp(kept->index.data(), index, static_cast<std::size_t>(k) * sizeof(idx)) == 0) {
        // the same block of the same matrix: eliminate would make the same factors and
        // pivots (they depend on the block alone) and, on y, lu_solve's operations
        for (idx i = 0; i < k; ++i) x[i] = 0.0;
        if (!all_finite(y, k)) return false;
        return lu_solve(Mat<const double>(kept->factors.data(), k, k), kept->piv.data(), y, x, k);
    }
    Mat<double> A(a, k, k);
    for (idx r = 0; r < k; ++r) {
        const double* mrow = M.row(index[r]);
        for (idx c = 0; c < k; ++c) A(r, c) = mrow[index[c]];
    }
    for (idx i = 0; i < k; ++i) x[i] = 0.0;
    kept->k = -1;
    kept->piv.resize(static_cast<std::size_t>(2 * k));
    if (!eliminate(A, y, x, k, kept->piv.data(), false)) return false;
    kept->factors.assign(a, a + k * k);
    kept->index.assign(index, index + k);
    kept->k = k;
    return true;
}

bool kept_factors(const KeptMatrix* kept, const idx* index, idx k, const double*& factors,
                  const idx*& piv) {
    if (kept == nullptr || kept->k != k ||
        std::memcmp(kept->index.data(), index, static_cast<std::size_t>(k) * sizeof(idx)) != 0)
        return false;
    factors = kept->factors.data();
    piv = kept->piv.data();
    return true;
}

bool refined_solve(Mat<const double> K, const double* rhs, idx steps, double* x, double* lo) {
    idx k = K.rows;
    if (K.cols < k) return false;
    SolveWork& w = solve_work;
    w.layout(k);
    return refined_solve(K, rhs, steps, x, lo, w.f.data(), w.piv.data());
}

bool refined_solve(Mat<const double> K, const double* rhs, idx steps, double* x, double* lo,
                   double* work, idx* piv) {
    idx k = K.rows, j = K.cols - K.rows;
    if (j < 0 || !all_finite(x + k, j)) return false;
    Mat<double> A(work, k, k);
    double* y = work + k * k;
    double* d = y + k;
    for (idx i = 0; i < k; ++i) d[i] = 0.0;
    for (idx r = 0; r < k; ++r) {
        const double* kr = K.row(r);
        for (idx c = 0; c < k; ++c) A(r, c) = kr[c];
        y[r] = rhs[r];
    }
    if (j > 0) {  // y = rhs - K[:, k:] x[k:] (residual2 of the given columns and -x[k:])
        for (idx r = 0; r < k; ++r) {
            const double* kr = K.row(r) + k;
            double s = rhs[r], err = 0.0;
            for (idx c = 0; c < j; ++c) {
                double a = kr[c];
                if (a != 0.0) acc2(s, err, a, -x[k + c]);
            }
            y[r] = s + err;
        }
    }
    double* xs = x;
    for (idx i = 0; i < k; ++i) xs[i] = 0.0;
    if (!eliminate(A, y, xs, k, piv)) return false;
    for (idx i = 0; i < k; ++i) lo[i] = 0.0;
    for (idx step = 0; step < steps; ++step) {
        for (idx r = 0; r < k; ++r) {  // rhs - K (x + lo), in double-double
            const double* kr = K.row(r);
            double s = rhs[r], err = 0.0;
            for (idx c = 0; c < k + j; ++c) {
                double a = kr[c];
                if (a != 0.0) {
                    acc2(s, err, -a, x[c]);
                    if (c < k) err -= a * lo[c];
                }
            }
            y[r] = s + err;
        }
        if (!lu_solve(A, piv, y, d, k)) return false;
        for (idx r = 0; r < k; ++r) {  // (xs, lo) += d
            double t, e;
            two_sum(xs[r], d[r], t, e);
            e += lo[r];
            xs[r] = t + e;
            lo[r] = e - (xs[r] - t);
        }
    }
    return all_finite(xs, k);
}

bool invert_in_place(Mat<double> G, idx k) {
    if (k < 0) return false;
    SolveWork& w = solve_work;
    w.f.resize(static_cast<std::size_t>(4 * k));
    w.piv.resize(static_cast<std::size_t>(k));
    return invert_in_place(G, k, w.f.data(), w.piv.data());
}

void principal_block(Mat<const double> M, const idx* index, idx k, double* out) {
    for (idx r = 0; r < k; ++r) {
        const double* row = M.row(index[r]);
        for (idx c = 0; c < k; ++c) out[r * k + c] = row[index[c]];
    }
}

LEMKE_CLONES
void matvec(Mat<const double> G, idx k, const double* x, double* out) {
    idx r = 0;
    for (; r + 4 <= k; r += 4) {
        const double* rows[4] = {G.row(r), G.row(r + 1), G.row(r + 2), G.row(r + 3)};
        dot_lanes4(rows, x, k, out + r);
    }
    for (; r < k; ++r) out[r] = dot_lanes(G.row(r), x, k);
}

namespace {

// y[lo:k] -= f x[lo:k] (linalg._row_update): no reduction, so it vectorizes without
// reordering anything.
LEMKE_CLONES
void row_update(double* y, double f, const double* x, idx lo, idx k) {
    for (idx c = lo; c < k; ++c) y[c] -= f * x[c];
}

// Every row r of G[:k, :k] but j and j + 1 with f = fg[r], g = fg[k + r] not both zero:
// G[r, c] = (G[r, c] - f G[j, c]) - g G[j + 1, c], the pivot rows read from their copy in S
// (2k doubles) (linalg._update_all_pair).
LEMKE_CLONES
void update_all_pair(Mat<double> G, const double* fg, idx j, idx k, double* S) {
    const double* gj = G.row(j);
    const double* gj1 = G.row(j + 1);
    for (idx c = 0; c < k; ++c) {
        S[c] = gj[c];
        S[k + c] = gj1[c];
    }
    const double* s1 = S + k;
    for (idx r = 0; r < k; ++r) {
        if (r == j || r == j + 1) continue;
        double f = fg[r], g = fg[k + r];
        if (f != 0.0 || g != 0.0) {
            double* gr = G.row(r);
            for (idx c = 0; c < k; ++c) gr[c] = (gr[c] - f * S[c]) - g * s1[c];
        }
    }
}

bool block_finite(Mat<const double> G, idx k) {
    bool finite = true;
    for (idx r = 0; r < k; ++r) finite &= all_finite(G.row(r), k);
    return finite;
}

}  // namespace

bool invert_in_place(Mat<double> G, idx k, double* work, idx* piv) {
    if (k < 0 || k > G.rows || k > G.cols) return false;
    if (!block_finite(G, k)) return false;
    double* fg = work;     // a pass's multipliers f (k) and g (k)
    double* S = work + 2 * k;  // its pivot rows
    idx j = 0;
    while (j < k) {
        // Pivot j: the largest entry of column j (up to date) in rows j..k-1.
        idx p = pivot_row(G, j, k, 0.0);
        if (p < 0) return false;
        piv[j] = p;
        swap_rows(G, j, p, k);
        double* rowj = G.row(j);
        double d = 1.0 / rowj[j];
        rowj[j] = 1.0;
        for (idx c = 0; c < k; ++c) rowj[c] *= d;
        if (j + 1 == k) {  // the last pivot alone
            for (idx r = 0; r < j; ++r) {
                double* rowr = G.row(r);
                double f = rowr[j];
                if (f != 0.0) {
                    rowr[j] = 0.0;
                    row_update(rowr, f, rowj, 0, k);
                }
            }
            break;
        }
        // Pivot j + 1 from column j + 1 as pivot j will leave it: G[r, j + 1] - G[r, j] h.
        double h = rowj[j + 1];
        p = pivot_row(G, j + 1, k, h);
        if (p < 0) return false;
        piv[j + 1] = p;
        swap_rows(G, j + 1, p, k);
        double* row1 = G.row(j + 1);
        double f1 = row1[j];
        row1[j] = 0.0;
        row_update(row1, f1, rowj, 0, k);
        double d1 = 1.0 / row1[j + 1];
        row1[j + 1] = 1.0;
        for (idx c = 0; c < k; ++c) row1[c] *= d1;
        // Every other row: both eliminations in one pass (multipliers first).
        for (idx r = 0; r < k; ++r) {
            if (r == j || r == j + 1) continue;
            double f = G(r, j);
            fg[r] = f;
            fg[k + r] = G(r, j + 1) - f * h;
        }
        update_all_pair(G, fg, j, k, S);
        for (idx r = 0; r < k; ++r) {
            if (r == j || r == j + 1) continue;
            double f = fg[r], g = fg[k + r];
            if (f != 0.0 || g != 0.0) {
                G(r, j) = -f * rowj[j] - g * row1[j];
                G(r, j + 1) = -g * row1[j + 1];
            }
        }
        // Row j last (the pass above read it as pivot j left it).
        rowj[j + 1] = 0.0;
        row_update(rowj, h, row1, 0, k);
        j += 2;
    }
    // The rows were swapped on the way: swap the inverse's columns back, in reverse order.
    for (idx jj = k - 1; jj >= 0; --jj) {
        idx p = piv[jj];
        if (p != jj) {
            for (idx r = 0; r < k; ++r) {
                double t = G(r, jj);
                G(r, jj) = G(r, p);
                G(r, p) = t;
            }
        }
    }
    return block_finite(G, k);
}

}  // namespace lemke
