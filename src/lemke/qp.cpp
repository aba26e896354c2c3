#include "qp.hpp"

#include "multiversion.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "boxed.hpp"
#include "lcp.hpp"
#include "multiversion.hpp"
#include "pivoting.hpp"
#include "reductions.hpp"
#include "unrevised.hpp"

namespace lemke {
namespace qp {

// clang: a declaration before a cloned function's first use must say so too (not qp.hpp's:
// a cloned declaration makes GCC call the clones by name from other files, and GCC's are
// local symbols)
LEMKE_CLONES void forward_rows_from(Mat<const double> L, Mat<double> R, const idx* lstart);
LEMKE_CLONES bool cholesky_shifted(Mat<const double> P, double shift, Mat<double> L);

namespace {

// The QP kernels' workspace, one per thread, laid out in one place (QPWork::layout) for a
// QP with p equality rows and m inequality rows (qp.rows_of) of n variables, r = n - p:
// (screen's Ps, lo, up come first, in a block of their own: the bounds decide p and m.)
//   f:  L (n x n), E (p x n),
//       C (m x n), f (p), d (m), V (pv x n, pv = min(p, n)), beta (pv), c, v (n), g (m);
//       the fused path's LCP: M (m x m, only when dense), zz, ones (m), yy (p),
//       buf (6m + 2: cold's buffer); the factored path (gram_lcp keeps its own: it is
//       bound alone too): K2, V2 (kr x r, kr = min(m, r)), beta2 (kr), rd (n), rpE (p),
//       rpS (kr), xi, dx (n), dy (p), dz, zg (m), cc, va (n), zS (kr); the sums' s, err,
//       size (n) and kkt_check's 4n.
//   i:  ekind (p), ckind (m), up_row (n), S (m), lcp basic (m).
//   b:  mlcp_basis's flags (m + 2n), gram's flags (m).
// An allocator whose resize leaves new doubles unset (every part of f is written before it
// is read: what a larger earlier layout left there is as good as zeros), so that a layout
// that grows does not first clear it (a first solve at n = 100 spent ~5% there).
template <class T>
struct Unset : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = Unset<U>;
    };
    Unset() = default;
    template <class U>
    Unset(const Unset<U>&) {}
    template <class U>
    void construct(U* p) { ::new (static_cast<void*>(p)) U; }
    template <class U, class... A>
    void construct(U* p, A&&... a) { ::new (static_cast<void*>(p)) U(std::forward<A>(a)...); }
};

// The bits of an array (the factor cache's P, A and G), kept compact for same_matrices'
// test, which runs on every call: the runs of entries that are not all +0 (literal runs; a
// gap of fewer than GAP +0 entries between two of them is kept in the run) with their bits
// in order, the rest +0 by construction. same() reads each entry of the caller's array once
// and only the literal runs' bits besides: on the MPC loop's P, A and G (2-17 % nonzero)
// 58 KB of the caller's and 4 KB of the key's, where a full copy read as much again (the
// hit test was ~115 KB a call, mostly out of cache after the caller's other work). Exact:
// an entry's bits against the bits it had (a zero that changes sign or value, a NaN's
// payload, all miss), as a memcmp against a full copy.
struct BitKey {
    static constexpr idx GAP = 8;
    std::vector<idx> run;  // literal runs [run[2k], run[2k + 1]), in order
    std::vector<std::uint64_t, Unset<std::uint64_t>> bits;  // their entries' bits, in order
    idx len = -1;  // (-1: empty)

    void build(const double* a, idx n);
    bool same(const double* a, idx n) const;
};

struct QPWork {
    std::vector<double, Unset<double>> f;
    std::vector<idx> i;
    std::vector<std::uint8_t> b;
    idx n = 0, p = 0, m = 0, r = 0, pv = 0, kr = 0;
    Mat<double> L, E, C, V, M, K2, V2;
    double *fv, *d, *beta, *c, *v, *g, *zz, *ones, *yy, *buf, *beta2, *rd, *rpE, *rpS, *xi, *dx, *dy, *dz, *zg, *cc, *va, *zS, *s, *err, *size, *kkt;
    idx *ekind, *ckind, *up_row, *S, *lcp_basic;
    std::uint8_t *bflags, *gflags;
    std::vector<idx> lstart;  // L's profile (factors': profile), for forward and forward_rows
    std::vector<idx> elast;  // (factors') the last nonzero row of E's columns k < p below k
    std::vector<idx> estart;  // (factors') the first nonzero of E's rows left of the diagonal
    // The factor cache (solve's, see same_factors): what the dense layout's L, E, V, beta, C,
    // the kinds, up_row and M were computed from. Any layout() call drops it.
    bool cached = false;
    idx key_p0 = 0, key_m0 = 0, m_g = 0;
    BitKey keyP, keyA, keyG;  // the caller's P, A, G (compact: BitKey)
    std::vector<double> keyPs;  // screen's Ps of P
    std::vector<std::uint8_t> keyPat;
    // With the cache (sparse_ready): the nonzeros of keyPs, A and G by rows, and whether C is
    // finite (point's sums then skip the rows with zz = 0: see point).
    SparseRows spP, spA, spG;
    bool c_finite = false, sparse_built = false;  // (sparse_ready's)
    // (sparse_ready's, from keyPat: right_hand_sides' sources of f and d past b, in order)
    std::vector<idx> fixed_j, h_i, up_j, lo_j;

    void layout(idx n_, idx p_, idx m_, bool dense) {
        cached = false;
        c_finite = false;
        sparse_built = false;
        spP.on = spA.on = spG.on = false;
        n = n_;
        p = p_;
        m = m_;
        r = std::max<idx>(n - p, 0);
        pv = std::min(p, n);
        kr = std::min(m, r);
        idx total = n * n + p * n + m * n + p + m + pv * n + pv + 2 * n + m +
                    (dense ? m * m : 0) + 2 * m + p + 6 * m + 2 + 2 * kr * r + kr + n + p + kr + 2 * n + p + 2 * m + 2 * n + kr + 3 * n +
                    4 * n + 1;
        f.resize(static_cast<std::size_t>(total));
        i.resize(static_cast<std::size_t>(p + 3 * m + n + 1));
        b.resize(static_cast<std::size_t>(2 * m + 2 * n + 1));
        Carver cv(f.data());
        auto mat = [&](idx rows, idx cols) { return Mat<double>(cv.take(rows * cols).data(), rows, cols); };
        auto vec = [&](idx len) { return cv.take(len).data(); };
        L = mat(n, n);
        E = mat(p, n);
        C = mat(m, n);
        fv = vec(p);
        d = vec(m);
        V = mat(pv, n);
        beta = vec(pv);
        c = vec(n);
        v = vec(n);
        g = vec(m);
        M = mat(dense ? m : 0, dense ? m : 0);
        zz = vec(m);
        ones = vec(m);
        yy = vec(p);
        buf = vec(6 * m + 2);
        K2 = mat(kr, r);
        V2 = mat(kr, r);
        beta2 = vec(kr);
        rd = vec(n);
        rpE = vec(p);
        rpS = vec(kr);
        xi = vec(n);
        dx = vec(n);
        dy = vec(p);
        dz = vec(m);
        zg = vec(m);
        cc = vec(n);
        va = vec(n);
        zS = vec(kr);
        s = vec(n);
        err = vec(n);
        size = vec(n);
        kkt = vec(4 * n);
        idx* ip = i.data();
        ekind = ip;
        ckind = ip + p;
        up_row = ckind + m;
        S = up_row + n;
        lcp_basic = S + m;
        bflags = b.data();
        gflags = bflags + m + 2 * n;
    }
};

QPWork& work() {
    thread_local QPWork w;
    return w;
}

// ----------------------------------------------------------------------------- factors

// r := L^-1 r, each sum from r's first nonzero (s) in dot's order from there; with L's
// profile (lstart: row j's first nonzero), the whole blocks of eight (counted from s) left of
// row j's start skipped while r's entries are finite (forward_rows says why the bits stay).
void forward(Mat<const double> L, double* r, const idx* lstart = nullptr) {
    idx n = L.rows;
    idx s = 0;
    while (s < n && r[s] == 0.0) ++s;
    bool skip = lstart != nullptr;
    for (idx j = s; j < n; ++j) {
        const double* Lj = L.row(j);
        idx b = s;
        if (skip && lstart[j] > s) b = s + ((lstart[j] - s) & ~static_cast<idx>(7));
        r[j] = (r[j] - dot(Lj + b, r + b, j - b)) / Lj[j];
        if (skip && !std::isfinite(r[j])) skip = false;
    }
}

// L's profile: start[j] is row j's first nonzero left of the diagonal (j where none).
void profile(Mat<const double> L, idx* start) {
    for (idx j = 0; j < L.rows; ++j) {
        const double* Lj = L.row(j);
        idx s = 0;
        while (s < j && Lj[s] == 0.0) ++s;
        start[j] = s;
    }
}

// The screened copy of P and the bounds (screened), one per thread for solve and solve_gram:
// the front's step 8 after solve's NOT_DEFINITE writes the pages solve's screen touched.
std::vector<double>& screen_scratch() {
    thread_local std::vector<double> scr;
    return scr;
}

// The data whose screen screen_scratch holds, when solve left it there on NOT_DEFINITE
// (its Cholesky failed: nothing after screen wrote the buffer), for solve_gram's
// reuse_screen (the front's step 8 right after that solve, on the same arrays).
struct ScreenOf {
    bool valid = false;
    Data dt{};
};

ScreenOf& screen_of() {
    thread_local ScreenOf s;
    return s;
}

bool same_mat(Mat<const double> a, Mat<const double> b) {
    return a.p == b.p && a.rows == b.rows && a.cols == b.cols && a.ld == b.ld;
}

bool same_arrays(const Data& a, const Data& b) {
    return same_mat(a.P, b.P) && same_mat(a.G, b.G) && same_mat(a.A, b.A) && a.q == b.q &&
           a.h == b.h && a.b == b.b && a.lb == b.lb && a.ub == b.ub;
}

// r := L^-T r; with L's profile (lstart), row j's update starts at its first nonzero while
// the x_j so far are finite and r held no -0 at the start. Each update skipped subtracts
// x_j 0 = +-0, which changes no entry but a -0 one (-0 - -0 = +0), and there is none: an
// entry becomes -0 only from -0 (+0 - +-0 = +0, an exact cancellation gives +0). So the
// same bits as the whole rows (point's solve: L is diagonal on the MPC loop, 14 KB read
// for 60 entries).
void backward_transposed(Mat<const double> L, double* r, const idx* lstart = nullptr) {
    idx n = L.rows;
    bool skip = lstart != nullptr;
    for (idx k = 0; k < n && skip; ++k)
        if (r[k] == 0.0 && std::signbit(r[k])) skip = false;
    for (idx j = n - 1; j >= 0; --j) {
        double xj = r[j] / L(j, j);
        r[j] = xj;
        if (skip && !std::isfinite(xj)) skip = false;
        const double* Lj = L.row(j);
        for (idx k = skip ? lstart[j] : 0; k < j; ++k) r[k] -= xj * Lj[k];
    }
}

// x := H_k x (x of V.cols entries) for k = 0, ..., p - 1 (or p - 1, ..., 0 when down):
// s = beta_k dot(v_k, x[k:]) (dot_lanes, dot's body), then x[k:] -= s v_k unless s is 0.
// Cloned, so that the updates run on the widest vectors (elementwise: the same bits on
// every instruction set); the right-hand sides and point take p reflectors a call.
LEMKE_CLONES
void householder_seq(Mat<const double> V, const double* beta, idx p, bool down, double* x) {
    idx n = V.cols;
    for (idx i = 0; i < p; ++i) {
        idx k = down ? p - 1 - i : i;
        const double* v = V.row(k) + k;
        double* r = x + k;
        double s = beta[k] * dot_lanes(v, r, n - k);
        if (s != 0.0)
            for (idx t = 0; t < n - k; ++t) r[t] -= s * v[t];
    }
}

// qp::dot4's body, inlined by the cloned loops that call it (below).
LEMKE_ALWAYS_INLINE void dot4_lanes(const double* a, const double* r0, const double* r1, const double* r2,
                                    const double* r3, idx len, double* out) {
#ifdef LEMKE_SIMD
    // (dot_lanes4 with a as its y: a product's bits do not depend on its operands' order, and
    // its pairwise sums are dot's, taken by shuffles (simd::hsum4); the four rows' sums taken
    // lane by lane from the stack were a third of forward_rows' time at n = 100)
    const double* r[4] = {r0, r1, r2, r3};
    dot_lanes4(r, a, len, out);
#else
    out[0] = dot_lanes(a, r0, len);
    out[1] = dot_lanes(a, r1, len);
    out[2] = dot_lanes(a, r2, len);
    out[3] = dot_lanes(a, r3, len);
#endif
}

#ifdef LEMKE_SIMD
// dot_lanes4 or dot_lanes8 of Q rows with one y.
template <int Q>
LEMKE_ALWAYS_INLINE void dot_lanes_q(const double* const* x, const double* y, idx k, double* out) {
    if constexpr (Q == 8) dot_lanes8(x, y, k, out);
    else dot_lanes4(x, y, k, out);
}

// The reflectors k0..k1-1 applied to Q rows r[q] (each row householder_seq's operations
// exactly, reflector by reflector), one pass over the rows per reflector: the update of
// reflector k (r_t -= s v_t, elementwise) and the sums of reflector k + 1 (dot's lanes from
// column k + 1, the tail into lane 0, dot's pairwise sums) in the same loop, so each row is
// loaded and stored once a reflector, not loaded again for the next one's sums.  Where a
// row's s is 0 (householder_seq leaves it as it is then: not even r - 0 v) the update and
// the sums go one after the other, as before.
template <int Q>
LEMKE_ALWAYS_INLINE void reflect_rows(Mat<const double> V, const double* beta, idx k0, idx k1,
                                      double* const* r) {
    idx n = V.cols;
    if (k0 >= k1) return;
    double d[Q];
    const double* x[Q];
    for (int q = 0; q < Q; ++q) x[q] = r[q] + k0;
    dot_lanes_q<Q>(x, V.row(k0) + k0, n - k0, d);
    for (idx k = k0; k < k1; ++k) {
        const double* v = V.row(k) + k;
        double s[Q];
        bool fused = k + 1 < k1;
        for (int q = 0; q < Q; ++q) {
            s[q] = beta[k] * d[q];
            if (s[q] == 0.0) fused = false;
        }
        if (!fused) {
            for (int q = 0; q < Q; ++q) {
                double* rq = r[q] + k;
                if (s[q] != 0.0)
                    for (idx t = 0; t < n - k; ++t) rq[t] -= s[q] * v[t];
            }
            if (k + 1 < k1) {
                for (int q = 0; q < Q; ++q) x[q] = r[q] + k + 1;
                dot_lanes_q<Q>(x, V.row(k + 1) + k + 1, n - k - 1, d);
            }
            continue;
        }
        for (int q = 0; q < Q; ++q) r[q][k] -= s[q] * v[0];
        const double* vk = v + 1;                  // reflector k from column k + 1
        const double* w = V.row(k + 1) + k + 1;    // reflector k + 1
        idx len = n - k - 1;
        simd::v8d acc[Q], sv[Q];
        for (int q = 0; q < Q; ++q) {
            acc[q] = simd::splat8(0.0);
            sv[q] = simd::splat8(s[q]);
        }
        idx j = 0;
        for (; j + 8 <= len; j += 8) {
            simd::v8d a = simd::load8(vk + j), b = simd::load8(w + j);
            for (int q = 0; q < Q; ++q) {
                double* p = r[q] + k + 1 + j;
                simd::v8d y = simd::load8(p) - sv[q] * a;
                simd::store8(p, y);
                acc[q] += y * b;
            }
        }
        double a0[Q];
        for (int q = 0; q < Q; ++q) a0[q] = acc[q][0];
        for (; j < len; ++j) {
            for (int q = 0; q < Q; ++q) {
                double* p = r[q] + k + 1 + j;
                double y = *p - s[q] * vk[j];
                *p = y;
                a0[q] += y * w[j];
            }
        }
        if (len < 8) {  // (lane 0 alone: see dot_and_size_lanes)
            for (int q = 0; q < Q; ++q) d[q] = a0[q];
            continue;
        }
        for (int q = 0; q < Q; ++q) acc[q][0] = a0[q];
        if constexpr (Q == 8) simd::hsum8(acc[0], acc[1], acc[2], acc[3], acc[4], acc[5], acc[6], acc[7], d);
        else simd::hsum4(acc[0], acc[1], acc[2], acc[3], d);
    }
}
#endif

// The reflectors k0..k1-1 (householder_seq's, in that order) applied to every row of X:
// eight rows at a time, then four (reflect_rows: each reflector's sums in one pass, the rows
// in cache through all the reflectors), the rest one by one. Each row gets householder_seq's
// operations exactly.
LEMKE_CLONES
void householder_range(Mat<const double> V, const double* beta, idx k0, idx k1, Mat<double> X) {
    idx n = V.cols;
    idx i = 0;
#ifdef LEMKE_SIMD
    for (; i + 8 <= X.rows; i += 8) {
        double* r[8];
        for (int q = 0; q < 8; ++q) r[q] = X.row(i + q);
        reflect_rows<8>(V, beta, k0, k1, r);
    }
    for (; i + 4 <= X.rows; i += 4) {
        double* r[4] = {X.row(i), X.row(i + 1), X.row(i + 2), X.row(i + 3)};
        reflect_rows<4>(V, beta, k0, k1, r);
    }
#endif
    for (; i < X.rows; ++i) {
        double* x = X.row(i);
        for (idx k = k0; k < k1; ++k) {
            const double* v = V.row(k) + k;
            double* rr = x + k;
            double s = beta[k] * dot_lanes(v, rr, n - k);
            if (s != 0.0)
                for (idx t = 0; t < n - k; ++t) rr[t] -= s * v[t];
        }
    }
}

// The reflectors 0..p-1 applied to every row of X (householder_range).
void householder_rows(Mat<const double> V, const double* beta, idx p, Mat<double> X) {
    householder_range(V, beta, 0, p, X);
}

// The multiplier matrix M = F2 F2' (F2 = C[:, p:]): M[i, j] = M[j, i] = dot(F2i, F2j) for
// j <= i, rows [i0, i1) (solve's loop, in blocks between its deadline checks).
LEMKE_CLONES
void gram_rows(Mat<const double> C, idx p, idx i0, idx i1, Mat<double> M) {
    idx r = C.cols - p;
    for (idx i = i0; i < i1; ++i) {
        const double* F2i = C.row(i) + p;
        double* Mi = M.row(i);
        idx j = 0;
        for (; j + 4 <= i + 1; j += 4)
            dot4_lanes(F2i, C.row(j) + p, C.row(j + 1) + p, C.row(j + 2) + p, C.row(j + 3) + p, r,
                       Mi + j);
        for (; j <= i; ++j) Mi[j] = dot_lanes(F2i, C.row(j) + p, r);
        for (idx j = 0; j < i; ++j) M(j, i) = Mi[j];
    }
}

// screen's symmetric part: Ps = (P + P')/2 (each entry 0.5 (P_ij + P_ji), the same bits as
// 0.5 (P_ji + P_ij)); returns max |P_ij - P_ji| (a maximum, exact in any order; NaN entries
// are screen's to refuse). By 8 x 8 tiles of the lower triangle, each with its mirror tile
// transposed in registers (the maximum was one chain of dependent comparisons, and the
// mirror's entries strided loads); the edges that are no whole tile one entry at a time.
LEMKE_CLONES
double symmetrize(Mat<const double> P, Mat<double> Ps) {
    idx n = P.rows;
    double asym = 0.0;
    idx nt = n - n % 8;
#ifdef LEMKE_SIMD
    using simd::v8d;
    v8d am = simd::splat8(0.0);
    // the 8 x 8 transpose of rows c[0..7], in three rounds of two-vector shuffles
    auto transpose = [](v8d* c) {
        v8d t[8];
        for (int k = 0; k < 8; k += 2) {
            t[k] = LEMKE_SHUFFLE8(c[k], c[k + 1], 0, 8, 2, 10, 4, 12, 6, 14);
            t[k + 1] = LEMKE_SHUFFLE8(c[k], c[k + 1], 1, 9, 3, 11, 5, 13, 7, 15);
        }
        for (int k = 0; k < 8; k += 4)
            for (int h = 0; h < 2; ++h) {
                c[k + h] = LEMKE_SHUFFLE8(t[k + h], t[k + h + 2], 0, 1, 8, 9, 4, 5, 12, 13);
                c[k + h + 2] = LEMKE_SHUFFLE8(t[k + h], t[k + h + 2], 2, 3, 10, 11, 6, 7, 14, 15);
            }
        for (int h = 0; h < 4; ++h) {
            t[h] = LEMKE_SHUFFLE8(c[h], c[h + 4], 0, 1, 2, 3, 8, 9, 10, 11);
            t[h + 4] = LEMKE_SHUFFLE8(c[h], c[h + 4], 4, 5, 6, 7, 12, 13, 14, 15);
        }
        for (int k = 0; k < 8; ++k) c[k] = t[k];
    };
    for (idx i0 = 0; i0 < nt; i0 += 8)
        for (idx j0 = 0; j0 <= i0; j0 += 8) {
            v8d a[8], c[8];
            for (int k = 0; k < 8; ++k) {
                a[k] = simd::load8(P.row(i0 + k) + j0);  // P[i0 + k, j0 + l]
                c[k] = simd::load8(P.row(j0 + k) + i0);  // P[j0 + k, i0 + l]
            }
            transpose(c);  // c[k][l] = P[j0 + l, i0 + k]
            for (int k = 0; k < 8; ++k) {
                am = simd::max8(am, simd::abs8(a[k] - c[k]));
                a[k] = simd::splat8(0.5) * (a[k] + c[k]);  // Ps[i0 + k, j0 + l]
                simd::store8(Ps.row(i0 + k) + j0, a[k]);
            }
            transpose(a);  // a[k][l] = Ps[i0 + l, j0 + k]
            for (int k = 0; k < 8; ++k) simd::store8(Ps.row(j0 + k) + i0, a[k]);
        }
    for (int l = 0; l < 8; ++l) asym = pmax(asym, am[l]);
#else
    nt = 0;
#endif
    // the rest: rows i >= nt against every column j <= i
    for (idx i = nt; i < n; ++i)
        for (idx j = 0; j <= i; ++j) {
            double a = P(i, j), c = P(j, i);
            asym = pmax(asym, std::fabs(a - c));
            Ps(i, j) = 0.5 * (a + c);
            Ps(j, i) = Ps(i, j);
        }
    return asym;
}

// ----------------------------------------------------------------------------- compensated sums

}  // namespace

// (dot2 and axpy2_matrix: one variant per instruction set, so that the avx512f one runs
// std::fma as an instruction, not a call into libm: fma is rounded once either way, the same bits)
LEMKE_CLONES
Dot2 dot2(const double* x, const double* y, idx n, double c) {
    double s = c, err = 0.0, size = std::fabs(c), norm = 0.0;
    for (idx j = 0; j < n; ++j) {
        acc2(s, err, x[j], y[j]);
        size += std::fabs(x[j] * y[j]);
        norm += std::fabs(x[j]);
    }
    return {s + err, size, norm};
}

namespace {

// One term a x of axpy2 into (s, err, size).
inline void axpy2_term(double& s, double& err, double& size, double a, double x) {
    double p, e, t, f;
    two_product(a, x, p, e);
    two_sum(s, p, t, f);
    s = t;
    err += e + f;
    size += std::fabs(p);
}

inline void axpy2(double* s, double* err, double* size, idx n, double a, const double* x) {
    for (idx j = 0; j < n; ++j) axpy2_term(s[j], err[j], size[j], a, x[j]);
}

}  // namespace

// axpy2 of every row of M with coefficient coef[i] (qp.axpy2_matrix, axpy2_rows).
LEMKE_CLONES
void axpy2_matrix(double* s, double* err, double* size, idx n, const double* coef,
                  Mat<const double> M) {
    for (idx i = 0; i < M.rows; ++i) axpy2(s, err, size, n, coef[i], M.row(i));
}

namespace {

// ----------------------------------------------------------------------------- rows

struct Rows {
    Mat<double> E, C;
    double *f, *d;
    idx *ekind, *ckind;
    idx p, m, m_g;
};

// The counts of qp.rows_of: (p, m).
void row_counts(const Data& dt, const double* lb, const double* ub, idx& p, idx& m) {
    idx n = dt.n();
    idx n_fix = 0, n_up = 0, n_lo = 0;
    for (idx j = 0; j < n; ++j) {
        if (lb[j] == ub[j]) {
            ++n_fix;
        } else {
            if (ub[j] < INF) ++n_up;
            if (lb[j] > -INF) ++n_lo;
        }
    }
    idx m_g = 0;
    for (idx i = 0; i < dt.m0(); ++i)
        if (dt.h[i] < INF) ++m_g;
    m = m_g + n_up + n_lo;
    p = dt.p0() + n_fix;
}

Rows rows_of(const Data& dt, const double* lb, const double* ub, QPWork& w) {
    idx n = dt.n();
    Rows R{w.E, w.C, w.fv, w.d, w.ekind, w.ckind, w.p, w.m, 0};
    for (idx t = 0; t < w.p * n; ++t) R.E.p[t] = 0.0;
    for (idx t = 0; t < w.m * n; ++t) R.C.p[t] = 0.0;
    for (idx t = 0; t < w.p; ++t) R.ekind[t] = -1;
    for (idx t = 0; t < w.m; ++t) R.ckind[t] = -1;
    idx p0 = dt.p0();
    for (idx i = 0; i < p0; ++i) {
        double* Ei = R.E.row(i);
        const double* Ai = dt.A.row(i);
        for (idx t = 0; t < n; ++t) Ei[t] = Ai[t];
        R.f[i] = dt.b[i];
    }
    idx k = p0;
    for (idx j = 0; j < n; ++j) {
        if (lb[j] == ub[j]) {
            R.E(k, j) = 1.0;
            R.f[k] = lb[j];
            R.ekind[k] = j;
            ++k;
        }
    }
    k = 0;
    for (idx i = 0; i < dt.m0(); ++i) {
        if (dt.h[i] < INF) {
            double* Ck = R.C.row(k);
            const double* Gi = dt.G.row(i);
            for (idx t = 0; t < n; ++t) Ck[t] = Gi[t];
            R.d[k] = dt.h[i];
            R.ckind[k] = -1 - i;
            ++k;
        }
    }
    for (idx j = 0; j < n; ++j) {
        if (lb[j] != ub[j] && ub[j] < INF) {
            R.C(k, j) = 1.0;
            R.d[k] = ub[j];
            R.ckind[k] = j;
            ++k;
        }
    }
    for (idx j = 0; j < n; ++j) {
        if (lb[j] != ub[j] && lb[j] > -INF) {
            R.C(k, j) = -1.0;
            R.d[k] = -lb[j];
            R.ckind[k] = n + j;
            ++k;
        }
    }
    return R;
}

// qp.mlcp_basis: the basis as solve_qp's KKT-MLCP numbers it, into out; (k, pairs).
void mlcp_basis(const double* lb, const double* ub, idx n, idx m_g, const idx* ckind, idx m,
                const idx* lcp_basic, idx kb, idx* out, std::uint8_t* flags, idx& k_out,
                idx& pairs) {
    for (idx t = 0; t < m + 2 * n; ++t) flags[t] = 0;
    std::uint8_t* on = flags;
    std::uint8_t* lo_on = flags + m;
    std::uint8_t* up_on = flags + m + n;
    for (idx i = 0; i < kb; ++i) on[lcp_basic[i]] = 1;
    for (idx i = m_g; i < m; ++i) {
        idx j = ckind[i];
        if (j < n) up_on[j] = on[i];
        else lo_on[j - n] = on[i];
    }
    idx k = 0, pos = 0;
    for (idx j = 0; j < n; ++j) {
        bool lo = lb[j] > -INF, up = ub[j] < INF;
        if ((lo || up) && lb[j] != ub[j]) {
            if (!(lo ? lo_on[j] : up_on[j])) out[k++] = pos;
            ++pos;
        }
    }
    for (idx i = 0; i < m_g; ++i) {
        if (on[i]) out[k++] = pos;
        ++pos;
    }
    for (idx j = 0; j < n; ++j) {
        if (lb[j] > -INF && ub[j] < INF && lb[j] != ub[j]) {
            if (up_on[j]) out[k++] = pos;
            ++pos;
        }
    }
    k_out = k;
    pairs = pos;
}

// The end of qp.factors: v1 (the equalities' particular point, from f) and g, the multiplier
// LCP's right-hand side, from d, v1 and c (in w.c, through L and the QR).
// out[i] = dot(C_i[col0:col0 + len], x, len) for every row i of C, four rows at a time
// (dot_lanes4: x's loads shared, each row's sums in dot's order, so dot's bits).
LEMKE_CLONES
void rows_dot(Mat<const double> C, idx col0, idx len, const double* x, double* out) {
    idx i = 0;
    for (; i + 4 <= C.rows; i += 4) {
        const double* rows[4] = {C.row(i) + col0, C.row(i + 1) + col0, C.row(i + 2) + col0,
                                 C.row(i + 3) + col0};
        dot_lanes4(rows, x, len, out + i);
    }
    for (; i < C.rows; ++i) out[i] = dot_lanes(C.row(i) + col0, x, len);
}

void lcp_rhs(const Rows& R, QPWork& w, idx n) {
    idx p = R.p, m = R.m;
    double* v = w.v;
    // (row k's whole blocks of eight left of its first nonzero, w.estart[k], skipped while
    // the v's are finite: their terms are +-0, forward's rule, the same bits)
    bool finite = true;
    for (idx k = 0; k < p; ++k) {
        idx b = finite ? w.estart[k] & ~static_cast<idx>(7) : 0;
        v[k] = (R.f[k] - dot(R.E.row(k) + b, v + b, k - b)) / R.E(k, k);
        finite = finite && std::isfinite(v[k]);
    }
    idx r = n - p;
    const double* c2 = w.c + p;
    // g_i = d_i - dot(F_i, v1, p) + dot(F_i[p:], c2, r), the two dots by rows_dot
    thread_local std::vector<double> t;
    t.resize(static_cast<std::size_t>(m));
    Mat<const double> C(R.C.p, m, R.C.cols, R.C.ld);
    rows_dot(C, 0, p, v, t.data());
    rows_dot(C, p, r, c2, w.g);
    for (idx i = 0; i < m; ++i) w.g[i] = R.d[i] - t[i] + w.g[i];
}

// qp.factors: steps 2 and 3 and g, given L (in w.L). Returns OK or DEPENDENT_EQUALITIES.
int factors(const Data& dt, const double* lb, const double* ub, QPWork& w, Rows& R) {
    idx n = dt.n();
    R = rows_of(dt, lb, ub, w);
    idx p = R.p, m = R.m;
    idx m_g = 0;
    while (m_g < m && R.ckind[m_g] < 0) ++m_g;
    R.m_g = m_g;
    double* c = w.c;
    for (idx t = 0; t < n; ++t) c[t] = dt.q[t];
    if (p > n) return DEPENDENT_EQUALITIES;
    Mat<const double> L = w.L;
    w.lstart.resize(static_cast<std::size_t>(n + 1));
    const idx* lstart = w.lstart.data();
    profile(L, w.lstart.data());
    forward_rows_from(L, R.E, lstart);
    idx m_u = m_g;
    while (m_u < m && R.ckind[m_u] < n) ++m_u;
    // in blocks of 32 rows (forward_rows takes rows by fours: the same bits), the thread's
    // deadline looked at between them
    for (idx i0 = 0; i0 < m_u; i0 += 32) {
        if (deadline_passed() >= 0) return TIME_LIMIT;
        forward_rows_from(L, Mat<double>(R.C.row(i0), std::min<idx>(32, m_u - i0), n), lstart);
    }
    idx* up_row = w.up_row;
    for (idx j = 0; j < n; ++j) up_row[j] = -1;
    for (idx i = m_g; i < m_u; ++i) up_row[R.ckind[i]] = i;
    for (idx i = m_u; i < m; ++i) {
        if ((i & 31) == 31 && deadline_passed() >= 0) return TIME_LIMIT;
        idx j = R.ckind[i] - n;
        if (up_row[j] >= 0) {
            double* Ci = R.C.row(i);
            const double* Cu = R.C.row(up_row[j]);
            for (idx t = 0; t < n; ++t) Ci[t] = -Cu[t];
        } else {
            forward(L, R.C.row(i), lstart);
        }
    }
    forward(L, c, lstart);
    if (qr_rows(R.E, w.V, w.beta) <= RANK_TOL) return DEPENDENT_EQUALITIES;
    w.estart.resize(static_cast<std::size_t>(p));
    for (idx k = 0; k < p; ++k) {  // (lcp_rhs's: row k's first nonzero left of the diagonal)
        const double* Ek = R.E.row(k);
        idx e = 0;
        while (e < k && Ek[e] == 0.0) ++e;
        w.estart[k] = e;
    }
    w.elast.resize(static_cast<std::size_t>(p));
    for (idx k = 0; k < p; ++k) {  // (point's: E's last nonzero below the diagonal)
        idx e = k;
        for (idx j = k + 1; j < p; ++j)
            if (R.E(j, k) != 0.0) e = j;
        w.elast[k] = e;
    }
    householder_seq(w.V, w.beta, p, false, c);
    // (C's rows in blocks of 32, the thread's deadline looked at between them)
    for (idx i0 = 0; i0 < m && p > 0; i0 += 32) {
        if (deadline_passed() >= 0) return TIME_LIMIT;
        householder_rows(w.V, w.beta, p, Mat<double>(R.C.row(i0), std::min<idx>(32, m - i0), n));
    }
    lcp_rhs(R, w, n);
    return OK;
}

// qp.point: x and yy from v (v1, v2 filled), c and zz (v is overwritten).
// With w.c_finite (solve's cache: C finite), yy's sums over the rows of C take only the
// rows with zz_i != 0 (NaN included), in the same order: a row with zz_i = 0 adds C_ik zz_i
// = +-0, which leaves a nonzero sum as it is and a zero one zero, so every sum that ends
// nonzero has the same bits; one that ends zero (its sign might differ) is summed again
// whole.
void point(Mat<const double> L, const Rows& R, const QPWork& w, const double* c, double* v,
           const double* zz, double* x, double* yy) {
    idx p = R.p, m = R.m, n = L.rows;
    thread_local std::vector<idx> on;
    on.clear();
    if (w.c_finite && w.cached)
        for (idx i = 0; i < m; ++i)
            if (zz[i] != 0.0) on.push_back(i);
    bool skip = w.c_finite && w.cached;
    for (idx k = 0; k < p; ++k) {
        double acc = v[k] + c[k];
        if (skip) {
            for (idx i : on) acc += R.C(i, k) * zz[i];
        }
        if (!skip || acc == 0.0) {
            acc = v[k] + c[k];
            for (idx i = 0; i < m; ++i) acc += R.C(i, k) * zz[i];
        }
        yy[k] = acc;
    }
    // (column k's terms below its last nonzero, w.elast[k], are +-0 while the yy's are
    // finite: they change no sum but a zero one, which is summed again whole; on the MPC
    // loop E is banded, 200 of its 780 terms nonzero, and this chain of subtractions is
    // serial)
    bool finite = true;  // yy[j] for j > k
    for (idx k = p - 1; k >= 0; --k) {
        double acc = yy[k];
        idx end = finite ? w.elast[k] + 1 : p;
        for (idx j = k + 1; j < end; ++j) acc -= R.E(j, k) * yy[j];
        if (end < p && acc == 0.0) {
            acc = yy[k];
            for (idx j = k + 1; j < p; ++j) acc -= R.E(j, k) * yy[j];
        }
        yy[k] = acc / R.E(k, k);
        finite = finite && std::isfinite(yy[k]);
    }
    for (idx k = 0; k < p; ++k) yy[k] = -yy[k];
    householder_seq(w.V, w.beta, p, true, v);
    backward_transposed(L, v, w.lstart.data());
    for (idx t = 0; t < n; ++t) x[t] = v[t];
}

// ----------------------------------------------------------------------------- the factor cache

// The structure the factors depend on besides P, A and G: which rows of G count (h finite)
// and each variable's kind of bounds (screened: fixed, upper, lower, both, none).
void structure(const Data& dt, const double* lo, const double* up, std::vector<std::uint8_t>& pat) {
    idx n = dt.n(), m0 = dt.m0();
    pat.resize(static_cast<std::size_t>(m0 + n));
    for (idx i = 0; i < m0; ++i) pat[i] = dt.h[i] < INF ? 1 : 0;
    for (idx j = 0; j < n; ++j)
        pat[m0 + j] = lo[j] == up[j] ? 4 : static_cast<std::uint8_t>((up[j] < INF ? 1 : 0) | (lo[j] > -INF ? 2 : 0));
}

LEMKE_ALWAYS_INLINE std::uint64_t bits_of(const double* a, idx t) {
    std::uint64_t u;
    std::memcpy(&u, a + t, sizeof u);
    return u;
}

// x's bits copied into dst, and how many of them are +0 (BitKey::build's test for a matrix
// without one: a single run, copied in the same pass). Cloned: the copy and count vectorized.
LEMKE_CLONES
idx copy_bits(const double* x, idx n, std::uint64_t* dst) {
    idx z = 0;
    for (idx t = 0; t < n; ++t) {
        std::uint64_t u = bits_of(x, t);
        dst[t] = u;
        z += u == 0 ? 1 : 0;
    }
    return z;
}

void BitKey::build(const double* a, idx n) {
    len = n;
    run.clear();
    bits.clear();
    // (tried when the first 64 entries hold no +0, which a sparse matrix's rarely do)
    bool dense = n > 0;
    for (idx t = 0; t < std::min<idx>(n, 64) && dense; ++t) dense = bits_of(a, t) != 0;
    if (dense) {
        bits.resize(static_cast<std::size_t>(n));
        if (copy_bits(a, n, bits.data()) == 0) {  // (dense: one run)
            run.push_back(0);
            run.push_back(n);
            return;
        }
        bits.clear();
    }
    // (whole blocks of eight +0's, or of eight entries that are not, skipped at once)
    auto zeros8 = [a](idx t) {
        std::uint64_t o = 0;
        for (idx j = 0; j < 8; ++j) o |= bits_of(a, t + j);
        return o == 0;
    };
    auto full8 = [a](idx t) {
        bool all = true;
        for (idx j = 0; j < 8; ++j) all &= bits_of(a, t + j) != 0;
        return all;
    };
    idx t = 0;
    while (t < n) {
        while (t + 8 <= n && zeros8(t)) t += 8;
        while (t < n && bits_of(a, t) == 0) ++t;
        if (t == n) break;
        idx s = t, e;  // e: past the run's last entry that is not +0
        for (;;) {
            while (t + 8 <= n && full8(t)) t += 8;
            while (t < n && bits_of(a, t) != 0) ++t;
            e = t;
            while (t < n && t - e < GAP && bits_of(a, t) == 0) ++t;
            if (t == n || t - e == GAP) break;
        }
        run.push_back(s);
        run.push_back(e);
        std::size_t at = bits.size();
        bits.resize(at + static_cast<std::size_t>(e - s));
        std::memcpy(bits.data() + at, a + s, static_cast<std::size_t>(e - s) * sizeof(double));
        t = e;
    }
}

// BitKey::same's loops: the OR of the gaps' bits and of the runs' differences, which is 0
// exactly when every entry has its key's bits (cloned: the ORs vectorized).
LEMKE_CLONES
bool key_same(const idx* run, idx runs, const std::uint64_t* bits, const double* a, idx n) {
    std::uint64_t acc = 0;
    idx t = 0;
    for (idx k = 0; k < runs; ++k) {
        idx s = run[2 * k], e = run[2 * k + 1];
        for (; t < s; ++t) acc |= bits_of(a, t);
        for (; t < e; ++t) acc |= bits_of(a, t) ^ *bits++;
        if (acc != 0) return false;
    }
    for (; t < n; ++t) acc |= bits_of(a, t);
    return acc == 0;
}

bool BitKey::same(const double* a, idx n) const {
    return len == n && key_same(run.data(), static_cast<idx>(run.size() / 2), bits.data(), a, n);
}

// Whether w holds the factors of this QP's matrices: solve's dense layout at these sizes,
// computed from P, A, G of the same bits and the same structure (compared here in full,
// never trusted by identity: a caller may have changed an array in place). The factors are
// then exactly what cholesky, factors and the Gram product would compute again.
bool same_matrices(const Data& dt, const QPWork& w) {
    idx n = dt.n();
    return w.cached && w.n == n && w.key_p0 == dt.p0() && w.key_m0 == dt.m0() &&
           w.keyP.same(dt.P.p, n * n) && w.keyA.same(dt.A.p, dt.p0() * n) &&
           w.keyG.same(dt.G.p, dt.m0() * n);
}

bool same_structure(const Data& dt, const double* lo, const double* up, const QPWork& w, idx p,
                    idx m, std::vector<std::uint8_t>& pat) {
    if (w.p != p || w.m != m) return false;
    structure(dt, lo, up, pat);
    return pat == w.keyPat;
}

// screen's last step: lb <= ub (neither a wrong-way infinity), the bounds beyond 1e20 infinite.
bool screen_bounds(const Data& dt, double* lo, double* up) {
    for (idx j = 0; j < dt.n(); ++j) {
        double a = dt.lb[j], c = dt.ub[j];
        if (!(a < INF && c > -INF && a <= c)) return false;
        lo[j] = a > -INFINITY_BOUND ? a : -INF;
        up[j] = c < INFINITY_BOUND ? c : INF;
    }
    return true;
}

// screen's verdict and bounds for data whose P, A, G have the bits of data that screen
// passed (same_matrices): the checks of the other arrays only, in screen's terms.
bool screen_vectors(const Data& dt, double* lo, double* up) {
    idx n = dt.n();
    if (!all_finite(dt.q, n) || !all_finite(dt.b, dt.p0())) return false;
    for (idx i = 0; i < dt.m0(); ++i)
        if (!(dt.h[i] > -INF)) return false;
    return screen_bounds(dt, lo, up);
}

// (scr: the buffer that holds ds.P when it is screen's, taken over instead of copied; ds's
// pointers stay valid, in w.keyPs now)
void remember(const Data& dt, const Data& ds, const double* lo, const double* up, QPWork& w,
              idx m_g, std::vector<double>& scr) {
    idx n = dt.n();
    w.keyP.build(dt.P.p, n * n);
    if (ds.P.p == scr.data())
        std::swap(w.keyPs, scr);
    else
        w.keyPs.assign(ds.P.p, ds.P.p + n * n);
    w.keyA.build(dt.A.p, dt.p0() * n);
    w.keyG.build(dt.G.p, dt.m0() * n);
    structure(dt, lo, up, w.keyPat);
    w.key_p0 = dt.p0();
    w.key_m0 = dt.m0();
    w.m_g = m_g;
    w.spP.on = w.spA.on = w.spG.on = false;  // (built at the first hit: sparse_ready)
    w.c_finite = false;
    w.sparse_built = false;
    w.cached = true;
}

// The cache's SparseRows, c_finite and right_hand_sides' row sources (from keyPat), made at
// the first solve that reuses its factors (dt:
// that solve's data, whose P, A, G are the cache's: same_matrices), not by remember: a first
// solve of new matrices would pay a scan of Ps, A, G and C for sums that only the solves
// reusing them save (the sums have the same bits either way).
void sparse_ready(const Data& dt, QPWork& w) {
    if (w.sparse_built) return;
    idx n = dt.n();
    w.spP.build(w.keyPs.data(), n, n);
    w.spA.build(dt.A.p, dt.p0(), n);
    w.spG.build(dt.G.p, dt.m0(), n);
    w.c_finite = all_finite(w.C.p, w.m * w.n);
    idx m0 = dt.m0();
    const std::uint8_t* pat = w.keyPat.data();
    w.fixed_j.clear();
    w.h_i.clear();
    w.up_j.clear();
    w.lo_j.clear();
    for (idx i = 0; i < m0; ++i)
        if (pat[i] == 1) w.h_i.push_back(i);
    for (idx j = 0; j < n; ++j) {
        std::uint8_t kind = pat[m0 + j];
        if (kind == 4) w.fixed_j.push_back(j);
        if (kind != 4 && (kind & 1)) w.up_j.push_back(j);
        if (kind != 4 && (kind & 2)) w.lo_j.push_back(j);
    }
    w.sparse_built = true;
}

// factors' right-hand sides on cached factors: f and d (rows_of's values), c, v and g, by
// the same operations in the same order as factors (so the same bits).
Rows right_hand_sides(const Data& dt, const double* lb, const double* ub, QPWork& w) {
    idx n = dt.n();
    Rows R{w.E, w.C, w.fv, w.d, w.ekind, w.ckind, w.p, w.m, w.m_g};
    idx p0 = dt.p0();
    // (rows_of's values in rows_of's order, from the cache's structure: the same kinds, so
    // the same rows, without a branch on each bound)
    for (idx i = 0; i < p0; ++i) R.f[i] = dt.b[i];
    idx k = p0;
    for (idx j : w.fixed_j) R.f[k++] = lb[j];
    k = 0;
    for (idx i : w.h_i) R.d[k++] = dt.h[i];
    for (idx j : w.up_j) R.d[k++] = ub[j];
    for (idx j : w.lo_j) R.d[k++] = -lb[j];
    idx p = R.p;
    double* c = w.c;
    for (idx t = 0; t < n; ++t) c[t] = dt.q[t];
    forward(w.L, c, w.lstart.data());  // (factors' L profile: its sums, its bits)
    householder_seq(w.V, w.beta, p, false, c);
    lcp_rhs(R, w, n);
    return R;
}

// A warm start (the KKT-MLCP's basic pairs, mlcp_basis's numbering) as the multiplier LCP's
// basic z's (the active rows of C), sorted, into beta; false when it has another number of
// pairs than this QP (`pairs` gets this QP's).
bool warm_rows(const double* lb, const double* ub, idx n, const Rows& R, const idx* warm, idx kw,
               idx warm_pairs, std::vector<idx>& beta, idx& pairs) {
    idx m = R.m, m_g = R.m_g;
    idx ns = 0, nb = 0;
    for (idx j = 0; j < n; ++j) {
        bool lo = lb[j] > -INF, up = ub[j] < INF;
        if ((lo || up) && lb[j] != ub[j]) {
            ++ns;
            if (lo && up) ++nb;
        }
    }
    pairs = ns + m_g + nb;
    if (warm_pairs != pairs) return false;
    thread_local std::vector<idx> rows;
    thread_local std::vector<std::uint8_t> on;
    rows.assign(static_cast<std::size_t>(2 * n), -1);  // ub row of j, then lb row of j
    on.assign(static_cast<std::size_t>(pairs + m + 1), 0);
    for (idx i = m_g; i < m; ++i) rows[R.ckind[i]] = i;
    for (idx t = 0; t < kw; ++t) on[warm[t]] = 1;
    std::uint8_t* act = on.data() + pairs;
    idx pos = 0;
    for (idx j = 0; j < n; ++j) {
        bool lo = lb[j] > -INF, up = ub[j] < INF;
        if ((lo || up) && lb[j] != ub[j]) {
            if (!on[pos]) act[lo ? rows[n + j] : rows[j]] = 1;
            ++pos;
        }
    }
    for (idx i = 0; i < m_g; ++i)
        if (on[pos++]) act[i] = 1;
    for (idx j = 0; j < n; ++j)
        if (lb[j] > -INF && ub[j] < INF && lb[j] != ub[j])
            if (on[pos++]) act[rows[j]] = 1;
    beta.clear();
    for (idx i = 0; i < m; ++i)
        if (act[i]) beta.push_back(i);
    return true;
}

// qpsolvers' initvals: the multiplier LCP's rows active at the primal guess x0 (sorted, into
// beta): a row of G tight or violated to ACTIVE_TOL relative to its terms,
// G_i x0 - h_i >= -ACTIVE_TOL (|h_i| + sum |G_ij x0_j|), a bound x0 is at or beyond,
// x0_j - lb_j <= ACTIVE_TOL (|lb_j| + |x0_j|) (ub alike); of a variable within that of both
// bounds, the nearer one (lb on a tie). _qp._initvals_start is the same rule in numpy.
void guess_rows(const Data& ds, const double* lb, const double* ub, const Rows& R,
                const double* x0, std::vector<idx>& beta) {
    idx n = ds.n(), m = R.m;
    beta.clear();
    for (idx i = 0; i < m; ++i) {
        idx kind = R.ckind[i];
        bool on;
        if (kind < 0) {
            const double* Gi = ds.G.row(-1 - kind);
            double hi = ds.h[-1 - kind];
            double acc = -hi, scale = std::fabs(hi);
            for (idx j = 0; j < n; ++j) {
                double t = Gi[j] * x0[j];
                acc += t;
                scale += std::fabs(t);
            }
            on = acc >= -ACTIVE_TOL * scale;
        } else {
            idx j = kind < n ? kind : kind - n;
            double xj = x0[j], ax = std::fabs(xj);
            double d_up = ub[j] < INF ? ub[j] - xj : INF;
            double d_lo = lb[j] > -INF ? xj - lb[j] : INF;
            bool at_up = ub[j] < INF && d_up <= ACTIVE_TOL * (std::fabs(ub[j]) + ax);
            bool at_lo = lb[j] > -INF && d_lo <= ACTIVE_TOL * (std::fabs(lb[j]) + ax);
            if (at_up && at_lo) {
                at_lo = d_lo <= d_up;
                at_up = !at_lo;
            }
            on = kind < n ? at_up : at_lo;
        }
        if (on) beta.push_back(i);
    }
}

struct Outs {
    double *x, *y, *z, *zb, *stats;
};

// qp.caller_form.
void caller_form(const Outs& o, idx n, idx p0, idx m0, const double* yy, const double* zz,
                 const Rows& R, bool snap) {
    idx p = R.p, m = R.m, m_g = R.m_g;
    if (snap) {
        for (idx i = m_g; i < m; ++i) {
            if (zz[i] > 0.0) {
                idx j = R.ckind[i];
                o.x[j < n ? j : j - n] = j < n ? R.d[i] : -R.d[i];
            }
        }
        for (idx k = p0; k < p; ++k) o.x[R.ekind[k]] = R.f[k];
    }
    for (idx i = 0; i < m0; ++i) o.z[i] = 0.0;
    for (idx j = 0; j < n; ++j) o.zb[j] = 0.0;
    for (idx i = 0; i < p0; ++i) o.y[i] = yy[i];
    for (idx k = p0; k < p; ++k) o.zb[R.ekind[k]] = yy[k];
    for (idx i = 0; i < m_g; ++i) o.z[-1 - R.ckind[i]] = zz[i];
    for (idx i = m_g; i < m; ++i) {
        idx j = R.ckind[i];
        if (j < n) o.zb[j] += zz[i];
        else o.zb[j - n] -= zz[i];
    }
}

Outs out_views(double* out, idx n, idx p0, idx m0) {
    OutLayout L{n, p0, m0};
    return {out + L.x(), out + L.y(), out + L.z(), out + L.zb(), out + L.stats()};
}

// The factor of P + PROXIMAL max_j P_jj I (cholesky_shifted: the shifted diagonal read in
// place, not from a copy of P).
bool proximal_cholesky(Mat<const double> P, Mat<double> L) {
    idx n = P.rows;
    double top = 0.0;
    for (idx j = 0; j < n; ++j) top = pmax(top, P(j, j));
    if (!(top > 0.0)) return false;
    return cholesky_shifted(P, PROXIMAL * top, L);
}

// qp.active_solve. S (k), K2/V2/beta2 the QR of F2_S'; zz written at S (and zeroed).
void active_solve(Mat<const double> L, const Rows& R, QPWork& w, const idx* S, idx k,
                  Mat<const double> K2, Mat<const double> V2, const double* beta2,
                  const double* rd, const double* rpE, const double* rpS, double* x, double* yy,
                  double* zz) {
    idx n = L.rows, p = R.p;
    double* cc = w.cc;
    for (idx t = 0; t < n; ++t) cc[t] = rd[t];
    forward(L, cc, w.lstart.data());
    householder_seq(w.V, w.beta, p, false, cc);
    double* v = w.va;
    for (idx j = 0; j < p; ++j) v[j] = (rpE[j] - dot(R.E.row(j), v, j)) / R.E(j, j);
    double* c2 = cc + p;
    householder_seq(V2, beta2, k, false, c2);
    double* wv = v + p;
    idx wl = n - p;
    for (idx j = 0; j < k; ++j)
        wv[j] = (rpS[j] - dot(R.C.row(S[j]), v, p) - dot(K2.row(j), wv, j)) / K2(j, j);
    double* zS = w.zS;
    for (idx j = k - 1; j >= 0; --j) {
        double acc = -(wv[j] + c2[j]);
        for (idx t = j + 1; t < k; ++t) acc -= K2(t, j) * zS[t];
        zS[j] = acc / K2(j, j);
    }
    for (idx t = k; t < wl; ++t) wv[t] = -c2[t];
    householder_seq(V2, beta2, k, true, wv);
    for (idx i = 0; i < R.m; ++i) zz[i] = 0.0;
    for (idx j = 0; j < k; ++j) zz[S[j]] = zS[j];
    point(L, R, w, cc, v, zz, x, yy);
}

void axpy2_P(double* s, double* err, double* size, const double* x, const Data& dt,
             const QPWork& w);
// kkt_rows (the acceptance module, certify.cpp) on solve's cache: QPWork's nonzeros of P, A
// and G (sw null: the dense sums).
inline bool kkt_rows(const Data& dt, const QPWork* sw, const double* x, const double* y,
                     const double* z, const double* zb, double tol, double* stats) {
    if (sw == nullptr) return qp::kkt_rows(dt, nullptr, nullptr, nullptr, x, y, z, zb, tol, stats);
    return qp::kkt_rows(dt, &sw->spP, &sw->spA, &sw->spG, x, y, z, zb, tol, stats);
}

// qp.active_residuals (P the screened Ps, lb/ub the screened bounds).
void active_residuals(const Data& dt, const double* lb, const double* ub, const Outs& o,
                      const Rows& R, const idx* S, idx k, QPWork& w, double* rd, double* rpE,
                      double* rpS) {
    idx n = dt.n(), p0 = dt.p0();
    double *s = w.s, *err = w.err, *size = w.size;
    for (idx j = 0; j < n; ++j) {
        s[j] = dt.q[j];
        err[j] = 0.0;
        size[j] = 0.0;
    }
    axpy2_P(s, err, size, o.x, dt, w);
    axpy2_matrix(s, err, size, n, o.y, dt.A);
    for (idx j = 0; j < k; ++j) {
        idx i = R.ckind[S[j]];
        if (i < 0) axpy2(s, err, size, n, o.z[-1 - i], dt.G.row(-1 - i));
    }
    for (idx j = 0; j < n; ++j) {
        double t, e;
        two_sum(s[j], o.zb[j], t, e);
        rd[j] = t + (e + err[j]);
    }
    for (idx kk = 0; kk < R.p; ++kk) {
        if (kk < p0) rpE[kk] = -dot2(dt.A.row(kk), o.x, n, -dt.b[kk]).sum;
        else rpE[kk] = R.f[kk] - o.x[R.ekind[kk]];
    }
    for (idx j = 0; j < k; ++j) {
        idx i = R.ckind[S[j]];
        if (i < 0) rpS[j] = -dot2(dt.G.row(-1 - i), o.x, n, -dt.h[-1 - i]).sum;
        else if (i < n) rpS[j] = ub[i] - o.x[i];
        else rpS[j] = o.x[i - n] - lb[i - n];
    }
}

// The QP kind's basis system (the seam, issue 31 item 2: basis.hpp's members apply, point,
// recover, solve, solve_transpose, check). Here, not in basis.hpp: it is a view on this
// file's QPWork and Rows (the engine's own factors and caches, which point's skipped terms
// need to keep their bits), not a block built from the caller's data. A basis is an active
// set S of the multiplier LCP's rows (rows_of's C: G's rows with h finite, then the upper
// bounds, then the lower ones); its KKT system, in the caller's variables,
//     K (x, yy, z_S) = (-rd, rpE, rpS),   K = [[P, E', C_S'], [E, 0, 0], [C_S, 0, 0]]
// (E: A's rows, then the fixed variables' unit rows), is solved through the factors, not as
// a block: L (P's Cholesky factor, w.L; P + shift I on the proximal path), the QR of E
// (w.V, w.beta, R.E) and the QR of F2_S' (apply: K2, V2, w.beta2). dt: the screened data
// (P its Ps, lb and ub the screened bounds), as every user has it.
struct QpBasis {
    const Data& dt;
    const double *lb, *ub;
    QPWork& w;
    const Rows& R;
    const idx* S = nullptr;  // the set (apply: in w.S)
    idx k = 0;
    Mat<double> K2, V2;  // F2_S (k x r) and its QR (qr_rows)

    QpBasis(const Data& dt_, const double* lb_, const double* ub_, QPWork& w_, const Rows& R_)
        : dt(dt_), lb(lb_), ub(ub_), w(w_), R(R_) {}

    // S = the rows whose flag is set (m flags: the LCP's basic z's), F2_S into K2 and its QR.
    // False (nothing to solve) when S has more rows than free directions (k > n - p) or
    // the QR's rank test refuses F2_S' (qr_rows <= RANK_TOL).
    bool apply(const std::uint8_t* flags) {
        idx m = R.m, p = R.p, r = dt.n() - p;
        k = 0;
        for (idx i = 0; i < m; ++i)
            if (flags[i]) ++k;
        if (k > r) return false;
        idx* s = w.S;
        k = 0;
        for (idx i = 0; i < m; ++i)
            if (flags[i]) s[k++] = i;
        S = s;
        K2 = Mat<double>(w.K2.p, k, r);
        V2 = Mat<double>(w.V2.p, k, r);
        for (idx j = 0; j < k; ++j) {
            const double* Fi = R.C.row(S[j]) + p;
            double* K2j = K2.row(j);
            for (idx t = 0; t < r; ++t) K2j[t] = Fi[t];
        }
        return qr_rows(K2, V2, w.beta2) > RANK_TOL;
    }

    // K (x, yy, z_S) = (-rd, rpE, rpS) after apply (active_solve: x n entries, yy p, zz m
    // written at S, zero elsewhere). rd, rpE, rpS are read only.
    void solve(const double* rd, const double* rpE, const double* rpS, double* x, double* yy,
               double* zz) const {
        active_solve(w.L, R, w, S, k, K2, V2, w.beta2, rd, rpE, rpS, x, yy, zz);
    }
    // K' u = rhs: K is symmetric (P symmetric, the off-diagonal blocks each other's
    // transposes), so solve itself (tests/test_basis_seam.py checks both against numpy).
    void solve_transpose(const double* rd, const double* rpE, const double* rpS, double* x,
                         double* yy, double* zz) const {
        solve(rd, rpE, rpS, x, yy, zz);
    }

    // The point of the set after apply: solve on (q, f, d_S), then `steps` refinements (the
    // residuals on dt in double-double, active_residuals, solved and added), z_S clipped at
    // 0, recover into o. The iterate in (w.xi, w.yy, w.zg); o's x, y, z, zb the residuals'
    // scratch. w.spP is built (P's nonzeros by rows, for the residuals' and check's sums);
    // the caller turns it off after check.
    void point(idx steps, const Outs& o) {
        idx n = dt.n(), p = R.p;
        double *rd = w.rd, *rpE = w.rpE, *rpS = w.rpS;
        for (idx t = 0; t < n; ++t) rd[t] = dt.q[t];
        for (idx t = 0; t < p; ++t) rpE[t] = R.f[t];
        for (idx j = 0; j < k; ++j) rpS[j] = R.d[S[j]];
        double *xi = w.xi, *yy = w.yy, *zz = w.zg, *dx = w.dx, *dy = w.dy, *dz = w.dz;
        solve(rd, rpE, rpS, xi, yy, zz);
        idx p0 = dt.p0(), m0 = dt.m0();
        // P's nonzeros by rows (kept where at most a quarter): the refinement's sums over P and
        // the check's take them alone, with the same bits (axpy2_P, kkt_rows).  (layout() made
        // w's SparseRows off and the cache empty: they are the point's own here.)
        w.spP.build(dt.P.p, n, n);
        for (idx step = 0; step < steps; ++step) {
            for (idx t = 0; t < n; ++t) o.x[t] = xi[t];
            caller_form(o, n, p0, m0, yy, zz, R, false);
            active_residuals(dt, lb, ub, o, R, S, k, w, rd, rpE, rpS);
            solve(rd, rpE, rpS, dx, dy, dz);
            for (idx t = 0; t < n; ++t) xi[t] += dx[t];
            for (idx t = 0; t < p; ++t) yy[t] += dy[t];
            for (idx j = 0; j < k; ++j) zz[S[j]] += dz[S[j]];
        }
        for (idx j = 0; j < k; ++j) zz[S[j]] = pmax(zz[S[j]], 0.0);
        recover(xi, yy, zz, o);
    }

    // The point of given multipliers zz (m entries, >= 0: the multiplier LCP's answer; no
    // apply, no refinement): v2 = -(c2 + sum_i zz_i F2_i) over the rows `rows` in their
    // order (nullptr: all m in order; a row with zz_i = 0 adds nothing), then x and yy
    // (point: L, the QR of E) into o.x and w.yy, recover.
    void point_given(const double* zz, const idx* rows, idx count, const Outs& o) {
        idx n = dt.n(), p = R.p;
        double* v = w.v;
        for (idx t = p; t < n; ++t) v[t] = -w.c[t];
        for (idx j = 0; j < count; ++j) {
            idx i = rows != nullptr ? rows[j] : j;
            double zi = zz[i];
            if (zi != 0.0) {
                const double* Ci = R.C.row(i);
                for (idx t = p; t < n; ++t) v[t] -= zi * Ci[t];
            }
        }
        qp::point(w.L, R, w, w.c, v, zz, o.x, w.yy);
        recover(o.x, w.yy, zz, o);
    }

    // The map back to the caller's form: x into o.x, (yy, zz) into o's y, z, zb, the
    // active bounds' and fixed variables' x snapped to their bounds (caller_form).
    void recover(const double* x, const double* yy, const double* zz, const Outs& o) const {
        idx n = dt.n();
        if (x != o.x)
            for (idx t = 0; t < n; ++t) o.x[t] = x[t];
        caller_form(o, n, dt.p0(), dt.m0(), yy, zz, R, true);
    }

    // The set `set` (kb rows of C) as the KKT-MLCP numbers its basis (mlcp_basis) into
    // basic; res.k, res.pairs.
    void numbering(const idx* set, idx kb, idx* basic, Result& res) const {
        mlcp_basis(lb, ub, dt.n(), R.m_g, R.ckind, R.m, set, kb, basic, w.bflags, res.k,
                   res.pairs);
    }

    // The KKT check of o on dt at min(tol, STRICT_TOL) (kkt_rows with w's sparse rows);
    // o.stats gets (primal, dual, gap, obj).
    bool check(const Outs& o, double tol) const {
        return kkt_rows(dt, &w, o.x, o.y, o.z, o.zb, pmin(tol, STRICT_TOL), o.stats);
    }
};

// qp._gram: the factored LCP, the active set's point refined `steps` times, the check (the
// set's basis system, QpBasis).
Result gram(const Data& dt, const double* lb, const double* ub, QPWork& w, Rows& R,
            idx max_pivots, double pivot_tol, double tie_tol, double tol, const Outs& o,
            idx* basic, idx steps) {
    Result res;
    idx p = R.p;
    std::uint8_t* flags = w.gflags;
    idx pivots = 0;
    int status = gram_lcp(R.C, w.g, p, max_pivots, pivot_tol, tie_tol, flags, pivots);
    res.pivots = pivots;
    if (status != SOLVED) {
        res.code = is_stop(status) ? status : NOT_SOLVED;
        return res;
    }
    QpBasis basis(dt, lb, ub, w, R);
    if (!basis.apply(flags)) {
        res.code = NOT_SOLVED;
        return res;
    }
    basis.point(steps, o);
    basis.numbering(basis.S, basis.k, basic, res);
    bool passed = basis.check(o, tol);
    w.spP.on = false;
    if (!passed) {
        res.code = CHECK_FAILED;
        return res;
    }
    res.code = OK;
    return res;
}

}  // namespace

// axpy2_matrix over M's nonzeros only (sp), rows with coef[i] = 0 skipped: each term it
// skips is an exact +-0 (kkt_rows says why that keeps the bits).
LEMKE_CLONES
void axpy2_sparse(double* s, double* err, double* size, const double* coef, Mat<const double> M,
                  const SparseRows& sp) {
    for (idx i = 0; i < M.rows; ++i) {
        double a = coef[i];
        if (a == 0.0) continue;
        for (idx t = sp.start[i]; t < sp.start[i + 1]; ++t) {
            idx j = sp.col[t];
            axpy2_term(s[j], err[j], size[j], a, sp.val[t]);
        }
    }
}

namespace {

// active_residuals' sums over P (s, err, size from q, 0, 0): axpy2_matrix, or with w.spP (gram's:
// P's nonzeros by rows, where at most a quarter) and x finite, axpy2_sparse.  A skipped
// term is an exact +-0: it changes no error term (they never hold -0) and no sum but one
// at -0 (-0 + +0 = +0), and a sum that differs so has only +-0 terms after it (the first
// nonzero one gives both the same bits): a sum ending at -0 is summed again whole, in
// order.  So the same bits as axpy2_matrix.
void axpy2_P(double* s, double* err, double* size, const double* x, const Data& dt,
             const QPWork& w) {
    idx n = dt.n();
    if (!(w.spP.on && all_finite(x, n))) {
        axpy2_matrix(s, err, size, n, x, dt.P);
        return;
    }
    axpy2_sparse(s, err, size, x, dt.P, w.spP);
    for (idx j = 0; j < n; ++j) {
        if (s[j] == 0.0 && std::signbit(s[j])) {
            s[j] = dt.q[j];
            err[j] = 0.0;
            size[j] = 0.0;
            for (idx i = 0; i < n; ++i) axpy2_term(s[j], err[j], size[j], x[i], dt.P(i, j));
        }
    }
}

// acc[i] += Mj[i] z, size[i] += |Mj[i] z| (i < m): one term of warm_point's sums per row.
LEMKE_CLONES
void add_row_terms(const double* Mj, double z, double* acc, double* size, idx m) {
    for (idx i = 0; i < m; ++i) {
        double t = Mj[i] * z;
        acc[i] += t;
        size[i] += std::fabs(t);
    }
}

// The warm start's own KKT point (solve's first stage from a warm start), with a few
// active-set updates: the multipliers of the active rows S from M_SS z_S = -g_S (the
// multiplier LCP's principal block, LU), a look at the LCP (z_S >= 0 and w = M z + g >= 0
// off S, each to tol relative to its terms); while that fails, at most ACTIVE_SET_STEPS
// times (and ACTIVE_SET_MORE times more while each moves a single row), while the number of
// rows that move does not grow and no set comes back, S loses its rows with z < 0 and gains
// those with w < 0 (a primal-dual active-set step: no pivoting rule, so no guarantee, only
// a cheap try). A set that passes gives the
// point, caller_form and the KKT check on the data as for a solved LCP: true (Result OK,
// pivots the number of rows that entered or left S, the basis written; or CHECK_FAILED when
// the point fails the KKT check); false (Result.pivots the updates tried) leaves zz zero and
// `nearest` the set tried (M_SS factored) with the fewest rows to move, where restart takes
// the LCP on from.
bool warm_point(const Data& ds, const double* lo, const double* up, QPWork& w, const Rows& R,
                const std::vector<idx>& beta, double tol, const Outs& o, idx* basic, Result& res,
                std::vector<idx>& nearest) {
    idx n = ds.n(), p = R.p, m = R.m;
    nearest.clear();
    idx fewest = m + 1;  // the rows nearest's set had to move
    thread_local std::vector<double> lu, ws;
    thread_local std::vector<idx> S, next, seen, starts, last_set;  // seen: the sets tried, sorted
    S.assign(beta.begin(), beta.end());
    seen.clear();
    starts.assign(1, 0);
    last_set.clear();
    double* zz = w.zz;  // (zero: solve zeroed it)
    std::uint8_t* in_s = w.bflags;  // (mlcp_basis rewrites them)
    for (idx i = 0; i < m; ++i) in_s[i] = 0;
    idx changes = 0, last = 0;
    bool ok = false;
    for (idx step = 0; step <= ACTIVE_SET_STEPS + ACTIVE_SET_MORE; ++step) {
        // beyond the first ACTIVE_SET_STEPS updates, only while the last one moved a single
        // row (close: a cheap step more; else the restart, without more tries)
        if (step > ACTIVE_SET_STEPS && last != 1) break;
        idx kb = static_cast<idx>(S.size());
        if (kb > n - p) break;  // more active rows than free directions: singular
        lu.resize(static_cast<std::size_t>(kb * (kb + 2)));
        double* blk = lu.data();
        double* y = blk + kb * kb;
        double* zS = y + kb;
        for (idx i = 0; i < kb; ++i) y[i] = -w.g[S[i]];
        if (kb > 0 && !solve_gathered(w.M, S.data(), blk, y, zS, kb)) break;
        // zz and in_s are zero but on the last step's set (solve zeroed zz; in_s below)
        for (idx r : last_set) {
            zz[r] = 0.0;
            in_s[r] = 0;
        }
        last_set.assign(S.begin(), S.end());
        double top = 0.0;
        for (idx i = 0; i < kb; ++i) top = pmax(top, std::fabs(zS[i]));
        next.clear();
        for (idx i = 0; i < kb; ++i) {
            in_s[S[i]] = 1;
            zz[S[i]] = pmax(zS[i], 0.0);
            if (zS[i] < -tol * top) in_s[S[i]] = 2;  // leaves
        }
        // w = g + M_S z_S and its terms' sizes, row S_j of M at a time (M is symmetric to
        // the bit: M(i, S_j) z_j is M(S_j, i) z_j, added in the same order j as row i's
        // own sum would add it, so the same bits; kb rows read whole instead of kb scattered
        // entries of each of the m rows)
        ws.resize(static_cast<std::size_t>(2 * m));
        double* acc = ws.data();
        double* size = acc + m;
        for (idx i = 0; i < m; ++i) {
            acc[i] = w.g[i];
            size[i] = std::fabs(w.g[i]);
        }
        for (idx j = 0; j < kb; ++j)
            add_row_terms(w.M.row(S[j]), zz[S[j]], acc, size, m);
        idx moved = 0;
        for (idx i = 0; i < m; ++i) {
            if (in_s[i] == 2) {
                ++moved;
                continue;
            }
            if (in_s[i] == 1) {
                next.push_back(i);
                continue;
            }
            if (acc[i] < -tol * size[i]) {  // enters
                next.push_back(i);
                ++moved;
            }
        }
        if (moved == 0) {
            ok = true;
            break;
        }
        if (moved < fewest) {
            fewest = moved;
            nearest.assign(S.begin(), S.end());
        }
        if (step > 0 && moved > last) break;  // moving away: the restart, without more tries
        // a set tried before: the steps repeat (each set gives the same next one), never
        // one that holds; the restart, without the rest of the tries
        seen.insert(seen.end(), S.begin(), S.end());
        std::sort(seen.end() - kb, seen.end());
        starts.push_back(static_cast<idx>(seen.size()));
        bool again = false;
        for (std::size_t t = 0; t + 1 < starts.size() && !again; ++t)
            again = std::equal(next.begin(), next.end(), seen.begin() + starts[t],
                               seen.begin() + starts[t + 1]);
        if (again) break;
        last = moved;
        changes += moved;
        S.swap(next);
    }
    idx kb = static_cast<idx>(S.size());
    QpBasis basis(ds, lo, up, w, R);
    if (ok) {
        // (the set's point from its z: the terms of S's rows in S's order, unrefined)
        basis.point_given(zz, S.data(), kb, o);
        if (!basis.check(o, tol)) {
            // the LCP is solved and its point fails the check: what the cold LCP would give
            // (x is unique, P definite), so the caller's fallback, not another LCP run
            res.code = CHECK_FAILED;
            res.pivots = changes;
            return true;
        }
    }
    res.pivots = changes;
    if (!ok) {
        for (idx i = 0; i < m; ++i) zz[i] = 0.0;
        return false;
    }
    basis.numbering(S.data(), kb, basic, res);
    res.code = OK;
    return true;
}

// A failed warm start taken on from where warm_point left it: Lemke's method from the
// complementary basis with z_S basic, S = nearest (warm_point factored M_SS), covering vector
// d = c e_N - M[:, S] 1 (lcp.cpp's restart's; c = max_i M_ii >= max |M|, M positive
// semidefinite), so that z0 lifts z_S = zbar_S + z0 1 and w_N = wbar_N + c z0 together: the
// pivots move the rows the updates could not, not the whole path from the all-w basis. By
// the unrevised method with M read in place (unrevised_symmetric, H at most r + 1 wide),
// capped at cap pivots. Returns its status (NOT_SOLVED when it does not run: S empty, c not
// positive), pivots in `pivots`; on SOLVED the basic z's into lcp_basic (k of them) and zz
// (clipped at 0) from M_SS z_S = -g_S on them (the method's own z when M_SS is singular).
int restart(const QPWork& w, const Rows& R, idx r, const std::vector<idx>& nearest, idx cap,
            double pivot_tol, double tie_tol, idx* lcp_basic, idx& k, idx& pivots) {
    idx m = R.m;
    pivots = 0;
    k = 0;
    if (nearest.empty()) return NOT_SOLVED;
    double c = 0.0;
    for (idx i = 0; i < m; ++i) c = pmax(c, w.M(i, i));
    if (!(c > 0.0 && c < INF)) return NOT_SOLVED;
    thread_local std::vector<double> buf;
    thread_local std::vector<std::uint8_t> flags;
    buf.resize(static_cast<std::size_t>(3 * m + 2));
    flags.assign(static_cast<std::size_t>(2 * m), 0);
    double* x = buf.data();
    double* ray = x + m + 1;
    double* d = ray + m + 1;
    std::uint8_t* start = flags.data();
    std::uint8_t* basic = start + m;
    for (idx i : nearest) start[i] = 1;
    for (idx i = 0; i < m; ++i) d[i] = start[i] ? 0.0 : c;
    for (idx j : nearest) {  // (M symmetric to the bit: column j is row j)
        const double* Mj = w.M.row(j);
        for (idx i = 0; i < m; ++i) d[i] -= Mj[i];
    }
    Status st = unrevised_symmetric(w.M, d, w.g, start, r + 1, cap, pivot_tol, tie_tol, x, ray,
                                    basic, pivots);
    if (st != SOLVED) return st;
    for (idx i = 0; i < m; ++i)
        if (basic[i]) lcp_basic[k++] = i;
    // z_S of the final basis S from M_SS z_S = -g_S (LU, as warm_point's sets): nearer the
    // KKT point than the method's own values, kept to RESIDUAL_TOL of their block
    thread_local std::vector<double> lu;
    lu.resize(static_cast<std::size_t>(k * (k + 2)));
    double* y = lu.data() + k * k;
    double* zS = y + k;
    for (idx i = 0; i < k; ++i) y[i] = -w.g[lcp_basic[i]];
    bool exact = k > 0 && solve_gathered(w.M, lcp_basic, lu.data(), y, zS, k);
    for (idx i = 0; i < m; ++i) w.zz[i] = exact ? 0.0 : pmax(x[i], 0.0);
    if (exact)
        for (idx i = 0; i < k; ++i) w.zz[lcp_basic[i]] = pmax(zS[i], 0.0);
    return SOLVED;
}

// ----------------------------------------------------------------------------- the multiplier LCP

// The fused path's reduction (reductions.hpp's third pair; declared here, its work being
// QPWork): a strictly convex QP on screened data (ds, lo, up), P's Cholesky factor in w.L,
// as the LCP (M, g) of its inequality multipliers, of R.m rows; `recover` maps the LCP's
// answer (w.zz, its basic z's) back to the caller's x, y, z, zb and basis, `check` judges
// them on the data (kkt_rows).
struct MultiplierLcp {
    const Data& ds;
    const double *lo, *up;
    QPWork& w;

    // factors (the rows, the substitutions through L, the QR of the equalities, g into w.g),
    // then with `dense` M = C2 C2' into w.M (gram_rows, 16 rows at a time, the thread's
    // deadline looked at between them; without, the LCP stays in factored form, C2 = R.C's
    // columns p..n, as gram solves it). OK, DEPENDENT_EQUALITIES or a stop.
    int apply(Rows& R, bool dense) {
        int code = factors(ds, lo, up, w, R);
        if (code != OK || !dense) return code;
        if ((code = deadline_passed()) >= 0) return code;  // (after the factorizations)
        for (idx i0 = 0; i0 < R.m; i0 += 16) {  // (a stop here leaves the cache empty: layout dropped it)
            if (i0 > 0 && (code = deadline_passed()) >= 0) return code;
            gram_rows(R.C, R.p, i0, std::min<idx>(i0 + 16, R.m), w.M);
        }
        return OK;
    }
    // apply on the factors kept from the same matrices (the cache): g alone, by factors'
    // operations (right_hand_sides); M is w.M as it was.
    Rows apply_vectors() { return right_hand_sides(ds, lo, up, w); }
    // The LCP's answer (w.zz, the basic z's lcp_basic[:k]) mapped back through the set's
    // basis system (QpBasis): the basis as mlcp_basis numbers it into basic (numbering;
    // res.k, res.pairs), the point of the given multipliers from the factors (point_given:
    // x, the equality multipliers; caller_form: qpsolvers' y, z, zb, x snapped to its
    // active bounds).
    void recover(const Rows& R, const idx* lcp_basic, idx k, const Outs& o, idx* basic,
                 Result& res) {
        QpBasis basis(ds, lo, up, w, R);
        // numbering reads the LCP's basis whole before it writes there (they may share `basic`)
        idx* lb_copy = w.lcp_basic;
        for (idx i = 0; i < k; ++i) lb_copy[i] = lcp_basic[i];
        basis.numbering(lb_copy, k, basic, res);
        // (the point of the LCP's z: every row's term in row order, unrefined)
        basis.point_given(w.zz, nullptr, R.m, o);
    }
    // The KKT check on the data at the fused path's tolerance, min(tol, STRICT_TOL)
    // (QpBasis::check).
    bool check(const Rows& R, const Outs& o, double tol) {
        return QpBasis(ds, lo, up, w, R).check(o, tol);
    }
};

// solve's end from the multiplier LCP's answer (w.zz, the basic z's lcp_basic[:k]): the
// basis as mlcp_basis numbers it into basic (res.k, res.pairs), the point, caller_form and
// the KKT check on the data (MultiplierLcp's recover and check); whether it passes.
bool finish(const Data& ds, const double* lo, const double* up, QPWork& w, const Rows& R,
            const idx* lcp_basic, idx k, double tol, const Outs& o, idx* basic, Result& res) {
    MultiplierLcp red{ds, lo, up, w};
    red.recover(R, lcp_basic, k, o, basic, res);
    return red.check(R, o, tol);
}

}  // namespace

// ----------------------------------------------------------------------------- public pieces

// qp._dot4: the four sums a' r_q in one pass over a, each in linalg's fixed order (dot,
// row_dot_and_size): eight running sums, lane j mod 8 of the first 8 floor(len / 8) terms,
// the rest into lane 0, combined ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7)); no
// fused multiply-add (-ffp-contract=off), so the same bits on every instruction set.
LEMKE_CLONES
void dot4(const double* a, const double* r0, const double* r1, const double* r2,
          const double* r3, idx len, double* out) {
    dot4_lanes(a, r0, r1, r2, r3, len, out);
}

// Each row of R (k x n) replaced by L^-1 times it, four rows at a time, each sum from the
// first column where one of the four rows is nonzero (s) in dot's order from there.  A
// row of L that starts with zeros (its first nonzero at lstart, L's profile, P's) skips
// the whole blocks of eight (counted from s) left of it while the rows' entries are
// finite: each term skipped is +-0, added to a lane still at +0, so the sums keep their
// bits (a diagonal L: O(n) per row instead of O(n^2)).
//
// Two such groups of four go through the columns together (Group: each its own s, lane
// offset and finite flag, so each row gets the operations it got alone): a group's column j
// waits on its column j - 1 (the dot's last term, the pairwise sums, the division), a
// chain of latencies that a second, independent group fills (forward_rows was a fifth of a
// first solve at n = 100).  Where both groups' dots start at the same lane block, one
// dot_lanes8 takes them (L's row loaded once; the same sums, the same bits).
struct Group {
    double* r[4];
    idx s;
    bool finite;  // the entries written so far (the only ones a skip passes over)
    void begin(Mat<double> R, idx i, idx n) {
        for (int q = 0; q < 4; ++q) r[q] = R.row(i + q);
        s = 0;
        while (s < n && r[0][s] == 0.0 && r[1][s] == 0.0 && r[2][s] == 0.0 && r[3][s] == 0.0) ++s;
        finite = true;
    }
    // the lane block column j's dot starts at (row j of L starting at lstart_j)
    idx from(idx /*j*/, idx lstart_j) const {
        if (finite && lstart_j > s) return s + ((lstart_j - s) & ~static_cast<idx>(7));
        return s;
    }
    // (track: whether the flag can matter, some row of L starting right of s; it cannot
    // for a dense L, which then skips the tests)
    LEMKE_ALWAYS_INLINE void finish(idx j, const double* d, double inv, bool track) {
        for (int q = 0; q < 4; ++q) r[q][j] = (r[q][j] - d[q]) * inv;
        if (track && !(std::isfinite(r[0][j]) && std::isfinite(r[1][j]) &&
                       std::isfinite(r[2][j]) && std::isfinite(r[3][j])))
            finite = false;
    }
};

LEMKE_CLONES
void forward_rows_from(Mat<const double> L, Mat<double> R, const idx* lstart) {
    idx n = L.rows, k = R.rows;
    idx i = 0;
    idx last = 0;  // the rightmost start of L's rows
    for (idx j = 0; j < n; ++j) last = std::max(last, lstart[j]);
    for (; i + 8 <= k; i += 8) {
        Group a, b;
        a.begin(R, i, n);
        b.begin(R, i + 4, n);
        bool ta = last > a.s, tb = last > b.s;
        for (idx j = std::min(a.s, b.s); j < n; ++j) {
            const double* Lj = L.row(j);
            double inv = 1.0 / Lj[j];
            bool on_a = j >= a.s, on_b = j >= b.s;
            idx ba = a.from(j, lstart[j]), bb = b.from(j, lstart[j]);
            double d[8];
            if (on_a && on_b && ba == bb) {
                const double* x[8] = {a.r[0] + ba, a.r[1] + ba, a.r[2] + ba, a.r[3] + ba,
                                      b.r[0] + ba, b.r[1] + ba, b.r[2] + ba, b.r[3] + ba};
                dot_lanes8(x, Lj + ba, j - ba, d);
            } else {
                if (on_a) dot4_lanes(Lj + ba, a.r[0] + ba, a.r[1] + ba, a.r[2] + ba, a.r[3] + ba, j - ba, d);
                if (on_b) dot4_lanes(Lj + bb, b.r[0] + bb, b.r[1] + bb, b.r[2] + bb, b.r[3] + bb, j - bb, d + 4);
            }
            if (on_a) a.finish(j, d, inv, ta);
            if (on_b) b.finish(j, d + 4, inv, tb);
        }
    }
    for (; i + 4 <= k; i += 4) {
        Group a;
        a.begin(R, i, n);
        for (idx j = a.s; j < n; ++j) {
            const double* Lj = L.row(j);
            idx ba = a.from(j, lstart[j]);
            double d[4];
            dot4_lanes(Lj + ba, a.r[0] + ba, a.r[1] + ba, a.r[2] + ba, a.r[3] + ba, j - ba, d);
            a.finish(j, d, 1.0 / Lj[j], last > a.s);
        }
    }
    for (; i < k; ++i) forward(L, R.row(i), lstart);
}

void forward_rows(Mat<const double> L, Mat<double> R) {
    thread_local std::vector<idx> lstart;
    lstart.resize(static_cast<std::size_t>(L.rows + 1));
    profile(L, lstart.data());
    forward_rows_from(L, R, lstart.data());
}

double qr_rows(Mat<double> WE, Mat<double> V, double* beta) {
    idx p = WE.rows, n = WE.cols;
    if (p > n) return 0.0;
    double top = 0.0;
    for (idx k = 0; k < p; ++k) top = pmax(top, std::sqrt(dot(WE.row(k), WE.row(k), n)));
    double worst = INF;
    // (right-looking: reflector k goes to the rows below as soon as it is made, several rows
    // at a time (householder_range), where row k took reflectors 0..k-1 one after the other,
    // each waiting on the last; each row gets them in the same order, the same bits)
    for (idx k = 0; k < p; ++k) {
        double* x = WE.row(k);
        double sigma = dot(x + k, x + k, n - k);
        double norm = std::sqrt(sigma);
        double* v = V.row(k);
        for (idx t = 0; t < k; ++t) v[t] = 0.0;
        for (idx t = k; t < n; ++t) v[t] = x[t];
        double alpha = x[k] >= 0.0 ? -norm : norm;
        v[k] -= alpha;
        double vv = dot(v + k, v + k, n - k);
        beta[k] = vv > 0.0 ? 2.0 / vv : 0.0;
        x[k] = alpha;
        for (idx t = k + 1; t < n; ++t) x[t] = 0.0;
        worst = pmin(worst, top > 0.0 ? norm / top : 0.0);
        if (k + 1 < p)
            householder_range(V, beta, k, k + 1, Mat<double>(WE.row(k + 1), p - k - 1, n, WE.ld));
    }
    return p ? worst : INF;
}

// all_finite(x, k) and absmax(x, k) (into top) in one pass over x: the same verdict and the
// same maximum (a sum of 0 x_j is 0 or NaN, a maximum exact, in any order; top meaningless
// when x is not finite, as absmax's).  screen read P twice before symmetrize's pass:
// 5 us of a first solve at n = 100, P coming from the outer caches.
LEMKE_ALWAYS_INLINE bool finite_top(const double* x, idx k, double& top) {
    idx j = 0;
    double a = 0.0, m = 0.0;
#ifdef LEMKE_SIMD
    simd::v8d va = simd::splat8(0.0), vm = va;
    for (; j + 8 <= k; j += 8) {
        simd::v8d v = simd::load8(x + j);
        va += simd::splat8(0.0) * v;
        vm = simd::max8(vm, simd::abs8(v));
    }
    for (int l = 0; l < 8; ++l) {
        a += va[l];
        m = pmax(m, vm[l]);
    }
#endif
    for (; j < k; ++j) {
        a += 0.0 * x[j];
        m = pmax(m, std::fabs(x[j]));
    }
    top = m;
    return a == 0.0;
}

// (cloned: absmax's and all_finite's eight-lane vectors, lowered to SSE2 by the default
// build, went through the stack: 30 us of a 200 us solve at n = 100)
LEMKE_CLONES
bool screen(const Data& dt, double* Ps_, double* lo, double* up) {
    idx n = dt.n();
    Mat<double> Ps(Ps_, n, n);
    bool finite = all_finite(dt.q, n);
    double top = 0.0;
    finite &= finite_top(dt.P.p, n * n, top);
    double asym = symmetrize(dt.P, Ps);
    idx m0 = dt.m0();
    finite &= all_finite(dt.G.p, m0 * n);
    for (idx i = 0; i < m0; ++i)
        if (!(dt.h[i] > -INF)) return false;
    idx p0 = dt.p0();
    finite &= all_finite(dt.A.p, p0 * n);
    finite &= all_finite(dt.b, p0);
    if (!finite || asym > SYMMETRY_TOL * top) return false;
    return screen_bounds(dt, lo, up);
}

// Row by row (L's row i from rows < i), each entry in dot's fixed order; the rows in panels
// of four, whose entries left of the panel are four independent chains (one row alone is a
// chain of dependent dots and divisions: latency-bound, 2-3x slower at n = 100). The panel
// is built aside and copied row by row, so that on failure L holds what the row-by-row
// loop wrote: the rows above the failing one, its entries left of the diagonal.
//
// Leading zeros (P's profile: row i's first nonzero left of the diagonal, start[i]): while
// every entry computed so far is finite, L's row i is exactly P(i, j) / L(j, j) = P(i, j)
// (+-0, L(j, j) > 0) left of start[i] (its dot there sums +-0 terms into lanes that start at +0, and stays +0), and
// a dot of two rows skips the whole blocks of eight (its lanes' blocks, counted from 0) left
// of the larger start: the terms it skips are +-0, added to lanes still at +0, so every
// lane, and the sum, keeps its bits.  A diagonal or banded P costs O(n) per row then, not
// O(n^2) (PRIMAL1-3: P diagonal but for one zero).  An entry that is not finite (an
// overflow) ends the skipping: the rest is summed whole, as before.
// (shifted: P's diagonal read as P(i, i) + shift, the entry a shifted copy would hold)
LEMKE_ALWAYS_INLINE bool cholesky_body(Mat<const double> P, Mat<double> L, bool shifted,
                                       double shift) {
    idx n = P.rows;
    auto diag = [&](idx i) { return shifted ? P(i, i) + shift : P(i, i); };
    double top = 0.0;
    for (idx j = 0; j < n; ++j) top = pmax(top, diag(j));
    double floor = DEFINITE_TOL * top;
    if (!(top > 0.0)) return false;
    thread_local std::vector<double> panel;
    thread_local std::vector<idx> start_v;
    panel.resize(static_cast<std::size_t>(4 * n));
    start_v.resize(static_cast<std::size_t>(n + 1));
    idx* start = start_v.data();
    bool track = false;  // whether some row starts with zeros (else the flag below cannot matter)
    for (idx i = 0; i < n; ++i) {
        const double* Pi = P.row(i);
        idx s = 0;
        while (s < i && Pi[s] == 0.0) ++s;
        start[i] = s;
        if (s > 0) track = true;
    }
    // every entry of L computed so far (skipping allowed); with no leading zeros anywhere
    // neither the skips nor the copies below ever apply, and the tests are left out
    bool finite = true;
    // the first lane block a dot of length len may start at, both rows' leading zeros
    // (from a and b) skipped: a multiple of 8, at most len
    auto from = [&](idx a, idx b, idx len) -> idx {
        if (!finite) return 0;
        idx s = std::max(a, b) & ~static_cast<idx>(7);
        return s < len ? s : len & ~static_cast<idx>(7);
    };
    double* R[4] = {panel.data(), panel.data() + n, panel.data() + 2 * n, panel.data() + 3 * n};
    for (idx i0 = 0; i0 < n; i0 += 4) {
        idx c = std::min<idx>(4, n - i0);
        // (the thread's deadline, every 32 rows: false then, and the callers ask
        // deadline_passed() before they read false as "not definite")
        if ((i0 & 31) == 28 && deadline_passed() >= 0) return false;
        if (c == 4) {
            const double *P0 = P.row(i0), *P1 = P.row(i0 + 1), *P2 = P.row(i0 + 2),
                         *P3 = P.row(i0 + 3);
            idx s4 = std::min(std::min(start[i0], start[i0 + 1]), std::min(start[i0 + 2], start[i0 + 3]));
            for (idx j = 0; j < i0; ++j) {
                const double* Lj = L.row(j);
                double ljj = Lj[j], d[4];
                if (finite && j < s4) {  // every row's dot is +0 here: (P - 0) / ljj = P (+-0)
                    R[0][j] = P0[j];
                    R[1][j] = P1[j];
                    R[2][j] = P2[j];
                    R[3][j] = P3[j];
                    continue;
                }
                idx b = from(s4, start[j], j);
                dot4_lanes(Lj + b, R[0] + b, R[1] + b, R[2] + b, R[3] + b, j - b, d);
                R[0][j] = (P0[j] - d[0]) / ljj;
                R[1][j] = (P1[j] - d[1]) / ljj;
                R[2][j] = (P2[j] - d[2]) / ljj;
                R[3][j] = (P3[j] - d[3]) / ljj;
                if (track && !(std::isfinite(R[0][j]) && std::isfinite(R[1][j]) &&
                               std::isfinite(R[2][j]) && std::isfinite(R[3][j])))
                    finite = false;
            }
        } else {
            for (idx j = 0; j < i0; ++j) {
                const double* Lj = L.row(j);
                for (idx q = 0; q < c; ++q) {
                    idx i = i0 + q;
                    if (finite && j < start[i]) {
                        R[q][j] = P(i, j);
                        continue;
                    }
                    idx b = from(start[i], start[j], j);
                    R[q][j] = (P(i, j) - dot_lanes(R[q] + b, Lj + b, j - b)) / Lj[j];
                    if (track && !std::isfinite(R[q][j])) finite = false;
                }
            }
        }
        for (idx q = 0; q < c; ++q) {
            idx i = i0 + q;
            double* Ri = R[q];
            for (idx j = i0; j < i; ++j) {
                if (finite && j < start[i]) {
                    Ri[j] = P(i, j);
                    continue;
                }
                idx b = from(start[i], start[j], j);
                Ri[j] = (P(i, j) - dot_lanes(Ri + b, R[j - i0] + b, j - b)) / R[j - i0][j];
                if (track && !std::isfinite(Ri[j])) finite = false;
            }
            idx b = from(start[i], 0, i);
            double d = diag(i) - dot_lanes(Ri + b, Ri + b, i - b);
            double* Li = L.row(i);
            for (idx j = 0; j < i; ++j) Li[j] = Ri[j];
            if (!(d > floor)) return false;
            Li[i] = Ri[i] = std::sqrt(d);
            if (track && !std::isfinite(Li[i])) finite = false;
            for (idx j = i + 1; j < n; ++j) Li[j] = 0.0;
        }
    }
    return true;
}

LEMKE_CLONES
bool cholesky(Mat<const double> P, Mat<double> L) { return cholesky_body(P, L, false, 0.0); }

LEMKE_CLONES
bool cholesky_shifted(Mat<const double> P, double shift, Mat<double> L) {
    return cholesky_body(P, L, true, shift);
}

idx zero_diagonal(Mat<const double> P) {
    idx k = 0;
    for (idx j = 0; j < P.rows; ++j)
        if (P(j, j) == 0.0) ++k;
    return k;
}

idx flat_directions(Mat<const double> P, Mat<const double> L) {
    double top = 0.0;
    for (idx j = 0; j < P.rows; ++j) top = pmax(top, P(j, j));
    idx flat = 0;
    for (idx j = 0; j < P.rows; ++j)
        if (L(j, j) * L(j, j) < FLAT * top) ++flat;
    return flat;
}

idx equalities(idx p0, const double* lb, const double* ub, idx n) {
    idx p = p0;
    for (idx j = 0; j < n; ++j)
        if (lb[j] == ub[j]) ++p;
    return p;
}

// Step 8 with few inequalities (fewer than GRAM_RATIO n) takes on as many flat directions of P
// (zero diagonal entries; then pivots of the proximal factor below FLAT) as there are
// equality rows (fixed variables counted), which pin them; one more where the rows of G
// outnumber the bounds' rows (PRIMAL1-3: one linear variable among hundreds, pinned at the
// optimum by the rows of G); and any number below SMALL_FLAT variables, where a try costs
// microseconds (ZECEVIC2, QAFIRO).  Beyond that the proximal point need not be the answer,
// and on the Maros-Meszaros LPs with a few quadratic terms the step mostly ended
// CHECK_FAILED or NOT_SOLVED after many pivots (QBEACONF, QSC205, QE226; with the bound
// rows outnumbering G's, PRIMALC1-8 took 3-15x the KKT-MLCP path's time), so it declines.
idx flat_allowed(idx p0, const double* h, idx m0, const double* lb, const double* ub, idx n) {
    idx eq = equalities(p0, lb, ub, n);
    if (n <= SMALL_FLAT) return n;
    idx rows = 0, bounds = 0;
    for (idx i = 0; i < m0; ++i)
        if (h[i] < INF) ++rows;
    for (idx j = 0; j < n; ++j)
        if (lb[j] != ub[j]) bounds += static_cast<idx>(ub[j] < INF) + static_cast<idx>(lb[j] > -INF);
    return rows > bounds ? eq + 1 : eq;
}

idx inequalities(const double* h, idx m0, const double* lb, const double* ub, idx n) {
    idx m = 0;
    for (idx i = 0; i < m0; ++i)
        if (h[i] < INF) ++m;
    for (idx j = 0; j < n; ++j)
        if (lb[j] != ub[j]) m += static_cast<idx>(ub[j] < INF) + static_cast<idx>(lb[j] > -INF);
    return m;
}

int gram_lcp(Mat<const double> C, const double* g, idx p, idx max_pivots, double pivot_tol,
             double tie_tol, std::uint8_t* flags, idx& pivots) {
    idx m = C.rows;
    idx r = C.cols - p;
    pivots = 0;
    for (idx i = 0; i < m; ++i) flags[i] = 0;
    double g_min = 0.0;
    for (idx i = 0; i < m; ++i) g_min = pmin(g_min, g[i]);
    if (g_min >= 0.0) return SOLVED;
    thread_local std::vector<double> work;
    work.resize(static_cast<std::size_t>(m * (r + 4) + 2));
    Mat<double> Fs(work.data(), m, r);
    double* dcol = work.data() + m * r;
    double* gs = dcol + m;
    double* lx = gs + m;
    double* lray = lx + m + 1;
    for (idx i = 0; i < m; ++i) {
        const double* Fi = C.row(i);
        double norm2 = dot(Fi + p, Fi + p, r);
        bool keep = norm2 > RANK_TOL * RANK_TOL * (norm2 + dot(Fi, Fi, p));
        double s = keep ? pow2_rsqrt(norm2) : 1.0;
        double* Fsi = Fs.row(i);
        for (idx t = 0; t < r; ++t) Fsi[t] = keep ? s * Fi[p + t] : 0.0;
        gs[i] = s * g[i];
        dcol[i] = 1.0;
    }
    idx cap = max_pivots >= 0 ? max_pivots : 100 * (m + 1);
    Status st = unrevised_factored(Fs, dcol, gs, cap, pivot_tol, tie_tol, lx, lray, flags, pivots);
    return st;
}

// screen into scr (Ps, then the bounds: n (n + 2) + 1 doubles) and ds = dt with the
// screened P and bounds; false when screen refuses the data.
static bool screened(const Data& dt, std::vector<double>& scr, Data& ds) {
    idx n = dt.n();
    scr.resize(static_cast<std::size_t>(n * (n + 2) + 1));
    double* Ps = scr.data();
    double* lo = Ps + n * n;
    double* up = lo + n;
    if (!screen(dt, Ps, lo, up)) return false;
    ds = dt;
    ds.P = Mat<const double>(Ps, n, n);
    ds.lb = lo;
    ds.ub = up;
    return true;
}

WarmEnds& warm_ends() {
    thread_local WarmEnds ends;
    return ends;
}

idx& cache_hits() {
    thread_local idx hits = 0;
    return hits;
}

Result solve(const Data& dt, int method, idx max_pivots, double pivot_tol, double tie_tol,
             double tol, double* out, idx* basic, const idx* warm, idx k_warm, idx warm_pairs,
             const double* x0) {
    Result res;
    idx n = dt.n(), p0 = dt.p0(), m0 = dt.m0();
    idx k0 = OutLayout{n, p0, m0}.basis();
    for (idx t = 0; t < k0; ++t) out[t] = 0.0;
    if ((res.code = deadline_passed()) >= 0) return res;
    res.code = OK;
    screen_of().valid = false;
    QPWork& w = work();
    // the sizes first (screen's bounds decide them): the workspace's layout, then screen
    std::vector<double>& scr = screen_scratch();
    thread_local std::vector<std::uint8_t> pat;
    Data ds;
    bool hit = same_matrices(dt, w);
    if (hit) {  // P passed screen before: its Ps is kept, the vectors are checked here
        ++cache_hits();
        scr.resize(static_cast<std::size_t>(2 * n + 1));
        if (!screen_vectors(dt, scr.data(), scr.data() + n)) {
            res.code = BAD_INPUT;
            return res;
        }
        ds = dt;
        ds.P = Mat<const double>(w.keyPs.data(), n, n);
        ds.lb = scr.data();
        ds.ub = scr.data() + n;
    } else if (!screened(dt, scr, ds)) {
        res.code = BAD_INPUT;
        return res;
    }
    const double* lo = ds.lb;
    const double* up = ds.ub;
    idx p, m;
    row_counts(dt, lo, up, p, m);
    Outs o = out_views(out, n, p0, m0);
    Rows R;
    if (hit && same_structure(dt, lo, up, w, p, m, pat)) {
        // the matrices of the last solve on this thread: its factors and M, new right-hand sides
        sparse_ready(dt, w);
        R = MultiplierLcp{ds, lo, up, w}.apply_vectors();
    } else {
        if (hit) {  // the same matrices, another structure: the full screen's Ps (the same bits)
            thread_local std::vector<double> ps;
            ps.assign(w.keyPs.begin(), w.keyPs.end());
            ds.P = Mat<const double>(ps.data(), n, n);
        }
        w.layout(n, p, m, true);
        if (!cholesky(ds.P, w.L)) {
            res.code = deadline_passed() >= 0 ? TIME_LIMIT : NOT_DEFINITE;
            if (res.code == NOT_DEFINITE && ds.P.p == scr.data()) screen_of() = {true, dt};
            return res;
        }
        // the multiplier LCP (M, g): factors, then M = C2 C2' (the deadline looked at between)
        int code = MultiplierLcp{ds, lo, up, w}.apply(R, true);
        if (code != OK) {
            res.code = code;
            return res;
        }
        if ((res.code = deadline_passed()) >= 0) return res;
        remember(dt, ds, lo, up, w, R.m_g, scr);
        if ((res.code = deadline_passed()) >= 0) return res;
        res.code = OK;
    }
    thread_local std::vector<idx> beta;
    beta.clear();
    if (warm != nullptr && !warm_rows(lo, up, n, R, warm, k_warm, warm_pairs, beta, res.pairs)) {
        res.code = BAD_WARM;
        return res;
    }
    if (x0 != nullptr) guess_rows(ds, lo, up, R, x0, beta);
    for (idx i = 0; i < m; ++i) {
        w.zz[i] = 0.0;
        w.ones[i] = 1.0;
    }
    idx pivots = 0, k_basic = 0;
    idx* lcp_basic = basic;
    idx cap = max_pivots >= 0 ? max_pivots : 100 * (m + 1);
    if ((warm != nullptr || x0 != nullptr) && m > 0) {
        thread_local std::vector<idx> nearest;
        WarmEnds& ends = warm_ends();
        if (warm_point(ds, lo, up, w, R, beta, tol, o, basic, res, nearest)) {
            ++ends.kept;
            return res;
        }
        // the old set failed: Lemke's method on from the nearest set tried (restart); the
        // cold LCP only when that does not end on a point that passes the KKT check
        idx rp = 0;
        int st = restart(w, R, n - p, nearest, cap, pivot_tol, tie_tol, lcp_basic, k_basic, rp);
        res.pivots += rp;
        if (is_stop(st)) {
            res.code = st;  // a stop ends the QP too
            return res;
        }
        if (st == SOLVED && finish(ds, lo, up, w, R, lcp_basic, k_basic, tol, o, basic, res)) {
            ++ends.restarted;
            res.code = OK;
            return res;
        }
        ++ends.cold;
        for (idx i = 0; i < m; ++i) w.zz[i] = 0.0;
    }
    if (m > 0) {
        Method mt = method == TABLEAU ? TABLEAU : UNREVISED;
        // cold (also after a warm start that neither warm_point nor restart could finish)
        RunResult rr = checked_once(mt, w.M, w.g, w.ones, cap, pivot_tol, tie_tol, tol, w.buf,
                                    lcp_basic);
        pivots = rr.pivots + res.pivots;
        k_basic = rr.k;
        if (!(rr.code == SOLVED || rr.code == TRIVIAL) || !rr.ok) {
            res.code = is_stop(rr.code) ? rr.code : NOT_SOLVED;  // a stop ends the QP too
            res.pivots = pivots;
            return res;
        }
        for (idx i = 0; i < m; ++i) w.zz[i] = pmax(w.buf[i], 0.0);
    }
    bool passed = finish(ds, lo, up, w, R, lcp_basic, k_basic, tol, o, basic, res);
    res.pivots = pivots;
    res.code = passed ? OK : CHECK_FAILED;
    return res;
}

Result solve_gram(const Data& dt, idx max_pivots, double pivot_tol, double tie_tol, double tol,
                  double* out, idx out_len, idx* basic, bool semidefinite, bool relaxed,
                  bool reuse_screen) {
    Result res;
    idx n = dt.n(), p0 = dt.p0(), m0 = dt.m0();
    for (idx t = 0; t < out_len; ++t) out[t] = 0.0;
    if ((res.code = deadline_passed()) >= 0) return res;
    res.code = OK;
    std::vector<double>& scr = screen_scratch();
    Data ds;
    ScreenOf& memo = screen_of();
    if (reuse_screen && memo.valid && same_arrays(memo.dt, dt)) {  // screened's, as solve left it
        ds = dt;
        ds.P = Mat<const double>(scr.data(), n, n);
        ds.lb = scr.data() + n * n;
        ds.ub = ds.lb + n;
    } else if (!screened(dt, scr, ds)) {
        memo.valid = false;
        res.code = BAD_INPUT;
        return res;
    }
    memo.valid = false;
    const double* lo = ds.lb;
    const double* up = ds.ub;
    Outs o = out_views(out, n, p0, m0);
    bool few = inequalities(dt.h, m0, lo, up, n) < GRAM_RATIO * n;
    if (few && !semidefinite) {
        res.code = NOT_APPLICABLE;
        return res;
    }
    idx p, m;
    row_counts(dt, lo, up, p, m);
    QPWork& w = work();
    w.layout(n, p, m, false);
    bool definite = semidefinite ? false : cholesky(ds.P, w.L);
    if (!definite && (res.code = deadline_passed()) >= 0) return res;
    res.code = OK;
    if (!definite) {
        idx allowed = !few ? n : relaxed ? flat_allowed(p0, dt.h, m0, lo, up, n) : equalities(p0, lo, up, n);
        if (few && zero_diagonal(ds.P) > allowed) {
            res.code = NOT_APPLICABLE;
            return res;
        }
        if (!proximal_cholesky(ds.P, w.L)) {
            res.code = NOT_DEFINITE;
            return res;
        }
        if (few && flat_directions(ds.P, w.L) > allowed) {
            res.code = NOT_APPLICABLE;
            return res;
        }
    }
    Rows R;
    int code = MultiplierLcp{ds, lo, up, w}.apply(R, false);  // (its LCP in factored form)
    if (code != OK) {
        res.code = code;
        return res;
    }
    return gram(ds, lo, up, w, R, max_pivots, pivot_tol, tie_tol, tol, o, basic,
                definite ? REFINE : REFINE_PROXIMAL);
}

void box_basis(const double* lo, const double* up, idx n, const idx* final, idx k, idx m,
               idx* out, idx& count, idx& pairs) {
    thread_local std::vector<std::uint8_t> work;
    work.resize(static_cast<std::size_t>(2 * n + 1));
    std::uint8_t* flags = work.data();
    for (idx j = 0; j < 2 * n; ++j) flags[j] = 0;
    for (idx i = 0; i < k; ++i) flags[final[i]] = 1;
    for (idx i = k; i < m; ++i) flags[n + final[i]] = 1;
    idx cnt = 0, pos = 0;
    for (idx j = 0; j < n; ++j) {
        bool lo_f = lo[j] > -INF, up_f = up[j] < INF;
        if ((lo_f || up_f) && !(lo_f && up_f && lo[j] == up[j])) {
            if (flags[j] || (lo_f && flags[n + j])) out[cnt++] = pos;
            ++pos;
        }
    }
    for (idx j = 0; j < n; ++j) {
        if (lo[j] > -INF && up[j] < INF && lo[j] != up[j]) {
            if (flags[n + j]) out[cnt++] = pos;
            ++pos;
        }
    }
    count = cnt;
    pairs = pos;
}

Result solve_box(const Data& dt, const std::uint8_t* warm, idx max_pivots, double pivot_tol,
                 double tie_tol, double tol, double* out, idx* final) {
    Result res;
    idx n = dt.n();
    thread_local std::vector<double> scr;
    scr.resize(static_cast<std::size_t>(n * (2 * n + 2) + 1));
    // the box LCP (reductions.hpp's BoxQp): screen's Ps, lo, up into scr, P's factor after them
    reductions::BoxQp red{dt};
    double* rw = scr.data();
    double* Lw = rw + reductions::BoxQp::work_length(n);
    if (!red.apply(rw)) {
        res.code = BAD_INPUT;
        return res;
    }
    Mat<const double> P = red.M(rw);
    if (!cholesky(P, Mat<double>(Lw, n, n))) {
        res.code = deadline_passed() >= 0 ? TIME_LIMIT : NOT_DEFINITE;
        return res;
    }
    double* buf = out;
    boxed::SolveResult r = boxed::solve(P, red.q(), red.lo(rw), red.up(rw), warm, 0, max_pivots,
                                        pivot_tol, tie_tol, tol, buf, final);
    res.pivots = r.pivots;
    if (!(r.code == SOLVED && r.ok)) {
        res.code = is_stop(r.code) ? r.code : NOT_SOLVED;
        return res;
    }
    const double* x = buf;  // (the run's z)
    const double* w = buf + n;
    BoxOutLayout L{n};  // (its zb after boxed's buffer)
    double* zb = out + L.zb();
    red.recover(w, zb);
    if (!red.check(rw, x, zb, pmin(tol, STRICT_TOL), out + L.stats())) {
        res.code = CHECK_FAILED;
        return res;
    }
    red.recover_basis(rw, final, r.k, r.m, final + n, res.k, res.pairs);
    res.code = OK;
    return res;
}

BasisSeam basis_seam(const Data& dt, const std::uint8_t* active, idx m_active, const double* z,
                     idx m_z, idx steps, double tol, double* out, const double* rhs, idx rhs_len,
                     bool transpose, double* sol) {
    BasisSeam a;
    idx n = dt.n(), p0 = dt.p0(), m0 = dt.m0();
    for (idx t = 0; t < OutLayout{n, p0, m0}.basis(); ++t) out[t] = 0.0;
    std::vector<double> scr;
    Data ds;
    if (!screened(dt, scr, ds)) {
        a.code = BAD_INPUT;
        return a;
    }
    const double* lo = ds.lb;
    const double* up = ds.ub;
    idx p, m;
    row_counts(dt, lo, up, p, m);
    a.p = p;
    a.m = m;
    if (m_active != m || (z != nullptr && m_z != m)) {
        a.code = 3;
        return a;
    }
    QPWork w;
    w.layout(n, p, m, false);
    if (!cholesky(ds.P, w.L)) {
        a.code = NOT_DEFINITE;
        return a;
    }
    Rows R;
    int code = factors(ds, lo, up, w, R);
    if (code != OK) {
        a.code = code;
        return a;
    }
    QpBasis basis(ds, lo, up, w, R);
    if (!basis.apply(active)) {
        a.code = 2;
        return a;
    }
    a.k = basis.k;
    if (rhs != nullptr && rhs_len != n + p + basis.k) {
        a.code = 3;
        return a;
    }
    Outs o = out_views(out, n, p0, m0);
    if (z != nullptr)
        basis.point_given(z, nullptr, m, o);
    else
        basis.point(steps, o);
    a.code = basis.check(o, tol) ? 0 : 1;
    w.spP.on = false;
    if (rhs != nullptr) {
        idx k = basis.k;
        std::vector<double> rd(static_cast<std::size_t>(n)), zz(static_cast<std::size_t>(m));
        for (idx t = 0; t < n; ++t) rd[t] = -rhs[t];
        const double *rpE = rhs + n, *rpS = rhs + n + p;
        double *x = sol, *yy = sol + n;
        if (transpose)
            basis.solve_transpose(rd.data(), rpE, rpS, x, yy, zz.data());
        else
            basis.solve(rd.data(), rpE, rpS, x, yy, zz.data());
        for (idx j = 0; j < k; ++j) sol[n + p + j] = zz[basis.S[j]];
        a.solved = all_finite(sol, n + p + k);
    }
    return a;
}

}  // namespace qp

// ----------------------------------------------------------------------------- reductions.hpp's
// ends of the multiplier LCP, for the tests

namespace reductions {

bool BoxQp::apply(double* work) const {
    idx k = n();
    return qp::screen(d, work, work + k * k, work + k * (k + 1));
}

namespace {

// screen, P's factor and MultiplierLcp's apply (dense) on this thread's work; the code.
int multiplier_prepare(const qp::Data& d, std::vector<double>& scr, qp::Data& ds, qp::Rows& R) {
    using namespace qp;
    if (!screened(d, scr, ds)) return BAD_INPUT;
    idx p, m;
    row_counts(d, ds.lb, ds.ub, p, m);
    QPWork& w = work();
    w.layout(d.n(), p, m, true);  // (drops the factor cache: solve factors afresh after this)
    if (!cholesky(ds.P, w.L)) return deadline_passed() >= 0 ? TIME_LIMIT : NOT_DEFINITE;
    return MultiplierLcp{ds, ds.lb, ds.ub, w}.apply(R, true);
}

}  // namespace

int multiplier_apply(const qp::Data& d, std::vector<double>& M, std::vector<double>& g,
                     idx& m) {
    thread_local std::vector<double> scr;
    qp::Data ds;
    qp::Rows R;
    m = 0;
    int code = multiplier_prepare(d, scr, ds, R);
    if (code != qp::OK) return code;
    qp::QPWork& w = qp::work();
    m = R.m;
    M.assign(w.M.p, w.M.p + m * m);
    g.assign(w.g, w.g + m);
    return qp::OK;
}

int multiplier_recover(const qp::Data& d, const double* zz, idx m_given, const idx* lcp_basic,
                       idx k, double tol, double* out, idx* basic, idx& count, idx& pairs,
                       bool& passed) {
    thread_local std::vector<double> scr;
    qp::Data ds;
    qp::Rows R;
    count = pairs = 0;
    passed = false;
    idx n = d.n(), p0 = d.p0(), m0 = d.m0();
    for (idx t = 0; t < qp::OutLayout{n, p0, m0}.basis(); ++t) out[t] = 0.0;
    int code = multiplier_prepare(d, scr, ds, R);
    if (code != qp::OK) return code;
    if (m_given != R.m || k < 0 || k > R.m) return qp::BAD_INPUT;
    for (idx i = 0; i < k; ++i)
        if (lcp_basic[i] < 0 || lcp_basic[i] >= R.m) return qp::BAD_INPUT;
    qp::QPWork& w = qp::work();
    for (idx i = 0; i < R.m; ++i) w.zz[i] = pmax(zz[i], 0.0);  // (solve's clip)
    qp::MultiplierLcp red{ds, ds.lb, ds.ub, w};
    qp::Result res;
    qp::Outs o = qp::out_views(out, n, p0, m0);
    red.recover(R, lcp_basic, k, o, basic, res);
    passed = red.check(R, o, tol);
    count = res.k;
    pairs = res.pairs;
    return qp::OK;
}

}  // namespace reductions
}  // namespace lemke
