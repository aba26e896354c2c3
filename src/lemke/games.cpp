#include "games.hpp"

#include <algorithm>
#include <cstdint>

#include "ladder.hpp"
#include "multiversion.hpp"
#include "simd.hpp"

namespace lemke {
namespace games {

void GamesWork::reserve(idx nf, idx ni, idx nz) {
    if (static_cast<idx>(f.size()) < nf) f.resize(static_cast<std::size_t>(nf));
    if (static_cast<idx>(i.size()) < ni) i.resize(static_cast<std::size_t>(ni));
    if (static_cast<idx>(z.size()) < nz) z.resize(static_cast<std::size_t>(nz));
}

// --- the condensed tableau: shared by both methods ------------------------------------------

// games.payoff_range: the least and the largest payoff and whether every payoff is finite
// (sum of v * 0, NaN when one is not). Eight lanes: the minimum and the maximum of a set do
// not depend on the order they are taken in (up to the sign of a zero, which nothing after
// reads: every use is v - lo, hi - lo or |lo|, the same bits for either zero), nor does
// the sum of zeros (NaN when any term is).
LEMKE_CLONES
Range payoff_range(Mat<const double> A) {
    idx m = A.rows, n = A.cols;
    if (A.ld == n) {  // one run of m n payoffs: no short rows' scalar tails
        n *= m;
        m = m > 0 ? 1 : 0;
    }
    double lo = INF, hi = -INF, z = 0.0;
#ifdef LEMKE_SIMD
    using namespace simd;
    v8d lo8 = splat8(INF), hi8 = splat8(-INF), z8 = splat8(0.0), zero = splat8(0.0);
#endif
    for (idx i = 0; i < m; ++i) {
        const double* a = A.row(i);
        idx j = 0;
#ifdef LEMKE_SIMD
        for (; j + 8 <= n; j += 8) {
            v8d v = load8(a + j);
            lo8 = v < lo8 ? v : lo8;
            hi8 = max8(hi8, v);
            z8 = z8 + v * zero;
        }
#endif
        for (; j < n; ++j) {
            double v = a[j];
            lo = pmin(lo, v);
            hi = pmax(hi, v);
            z += v * 0.0;
        }
    }
#ifdef LEMKE_SIMD
    for (int q = 0; q < 8; ++q) {
        lo = pmin(lo, lo8[q]);
        hi = pmax(hi, hi8[q]);
        z += z8[q];
    }
#endif
    return {lo, hi, z == 0.0};
}

namespace {

double positive_scale(double lo, double hi) { return hi > lo ? pow2_scale(hi - lo) : 0.0; }

// One condensed tableau and its labels (basic[i] = rhs[i] + sum_j T[i, j] nonbasic[j]);
// magb: running bounds on the values' sizes; start: the labels basic at the start, row by
// row (the lexicographic keys are relative to them); wlab, wcol: see row_size.
struct Tab {
    Mat<double> T;
    double* rhs;
    double* magb;
    idx* basis;
    idx* nonbasic;
    idx* pos;
    std::uint8_t* inb;
    const idx* start;
    double* wlab;
    double* wcol;
};

// The scratch that a pivot uses (col: the entering column; prow: the pivot row).
struct Scratch {
    double* col;
    double* prow;
    idx* cand;
    double* keys;
    double* scratch;
    double* mags;
};

// The row updates of games.exchange: t_i += f_i prow, t_i[s] = f_i inv, rhs_i += f_i rr for
// every row i but r whose factor f_i = col[i] is not zero. W + H > 0: the rows' first W x 8
// + H x 4 doubles, which hold the columns (prow zero past them), taken W vectors of eight
// and H of four, with the pivot row held in registers (each entry gets the scalar loop's
// t + f p, the padding f * 0, which nothing reads).
template <int W, int H>
LEMKE_ALWAYS_INLINE void update_rows(Mat<double> T, double* rhs, idx r, idx s, const double* col,
                                     const double* prow, double inv, double rr) {
    idx n = T.rows, k = T.cols;
#ifdef LEMKE_SIMD
    using namespace simd;
    v8d p[W > 0 ? W : 1];
    for (int q = 0; q < W; ++q) p[q] = load8(prow + 8 * q);
    v4d ph = H > 0 ? load4(prow + 8 * W) : v4d{};
#endif
    for (idx i = 0; i < n; ++i) {
        if (i == r) continue;
        double f = col[i];
        if (f != 0.0) {
            rhs[i] += f * rr;
            double* ti = T.row(i);
#ifdef LEMKE_SIMD
            if (W + H > 0) {
                for (int q = 0; q < W; ++q) store8(ti + 8 * q, load8(ti + 8 * q) + f * p[q]);
                if (H > 0) store4(ti + 8 * W, load4(ti + 8 * W) + f * ph);
            } else
#endif
                for (idx j = 0; j < k; ++j) ti[j] += f * prow[j];
            ti[s] = f * inv;
        }
    }
}

// update_rows for rows `width` fours wide (F: the first width tried; 0: the scalar loop).
constexpr int MAX_FOURS = 32;  // rows up to 128 columns held in registers
template <int F>
LEMKE_ALWAYS_INLINE void update_rows_in(idx width, Mat<double> T, double* rhs, idx r, idx s,
                                        const double* col, const double* prow, double inv,
                                        double rr) {
    if (width == F)
        update_rows<F / 2, F % 2>(T, rhs, r, s, col, prow, inv, rr);
    else if constexpr (F < MAX_FOURS)
        update_rows_in<F + 1>(width, T, rhs, r, s, col, prow, inv, rr);
    else
        update_rows<0, 0>(T, rhs, r, s, col, prow, inv, rr);
}

// games.exchange: the pivot on row r and column s (entering column in col). Rows whose
// entry is zero are left alone, their entry s included (it keeps its sign of zero). With
// `wlab` and `wcol`, magb[r] is first set to row r's size (row_size, summed in the same
// order in the loop that reads the row for the pivot), as games.step does before its pivot.
// The bounds magb are updated after the tableau (other arrays, the same operations), so
// that the rows' updates need not wait for the size's chain of additions. prow holds
// T.ld doubles.
LEMKE_CLONES
void exchange(Mat<double> T, double* rhs, double* magb, idx r, idx s, const double* col,
              double* prow, const idx* basis = nullptr, const double* wlab = nullptr,
              const double* wcol = nullptr) {
    idx n = T.rows, k = T.cols;
    double inv = 1.0 / col[r];
    double* tr = T.row(r);
    if (wlab != nullptr) {
        double size = wlab[basis[r]];
        for (idx j = 0; j < k; ++j) {
            double t = tr[j];
            size += std::fabs(t) * wcol[j];
            double v = -t * inv;
            prow[j] = v;
            tr[j] = v;
        }
        magb[r] = size;
    } else {
        for (idx j = 0; j < k; ++j) {
            double v = -tr[j] * inv;
            prow[j] = v;
            tr[j] = v;
        }
    }
    tr[s] = inv;
    double rr = -rhs[r] * inv;
    rhs[r] = rr;
    // The rows' vectors: W of eight and H (0 or 1) of four cover the k columns (width
    // 8 W + 4 H, within the rows' padding to a multiple of 8); none (W = H = 0: the scalar
    // loop) when the rows are not so padded or too wide.
    idx width = T.ld % 8 == 0 && k <= 4 * MAX_FOURS ? (k + 3) / 4 : 0;  // in fours
    if (width > 0)
        for (idx j = k; j < T.ld; ++j) prow[j] = 0.0;
    update_rows_in<1>(width, T, rhs, r, s, col, prow, inv, rr);
    magb[r] *= std::fabs(inv);
    double mr = magb[r];
    for (idx i = 0; i < n; ++i) {
        double f = col[i];
        if (i != r && f != 0.0) magb[i] += std::fabs(f) * mr;
    }
}

// games.binv: entry i of the basis inverse's column for the label lab basic at the start.
inline double binv(Mat<double> T, const idx* pos, const std::uint8_t* is_basic, idx lab, idx i) {
    if (is_basic[lab]) return pos[lab] == i ? 1.0 : 0.0;
    return -T(i, pos[lab]);
}

// games.row_size: |B^-1| |q0| of row i, read off the tableau row.
double row_size(Mat<double> T, idx i, const idx* basis, const double* wlab, const double* wcol) {
    double size = wlab[basis[i]];
    const double* t = T.row(i);
    for (idx c = 0; c < T.cols; ++c) size += std::fabs(t[c]) * wcol[c];
    return size;
}

void column_weights(const idx* nonbasic, idx k, const double* wlab, double* wcol) {
    for (idx c = 0; c < k; ++c) wcol[c] = wlab[nonbasic[c]];
}

// games.lex_break.
idx lex_break(Mat<double> T, const double* c, const idx* pos, const std::uint8_t* is_basic,
              const idx* start_basis, idx art, double pivot_tol, double tie_tol, idx* cand,
              double* keys, idx nc) {
    if (nc <= 1) return nc == 1 ? cand[0] : -1;
    for (idx t = 0; t < nc; ++t)
        if (cand[t] == art) return art;
    for (idx j = 0; j < T.rows; ++j) {
        idx lab = start_basis[j];
        for (idx t = 0; t < nc; ++t) {
            idx i = cand[t];
            keys[t] = lex_key(binv(T, pos, is_basic, lab, i), c[i], pivot_tol);
        }
        nc = keep_lowest(cand, keys, nc, tie_tol);
        if (nc == 1) return cand[0];
    }
    return nc > 0 ? largest_pivot(cand, c, nc) : -1;
}

// games.leaving_row.
idx leaving_row(Tab& t, const double* col, bool has_free, const std::uint8_t* free, idx art,
                double z0_max, double pivot_tol, double tie_tol, Scratch& w) {
    idx n = t.T.rows;
    const double* c = col;
    if (has_free) {
        for (idx i = 0; i < n; ++i) w.scratch[i] = free[t.basis[i]] ? 0.0 : col[i];
        c = w.scratch;
    }
    bool exact_sizes = false;
    for (idx i = 0; i < n; ++i) {
        double v = t.rhs[i];
        if (c[i] < 0.0 && v > 0.0 && v <= VALUE_ROUNDING * t.magb[i]) {
            if (!exact_sizes) {
                exact_sizes = true;
                for (idx j = 0; j < n; ++j) w.mags[j] = t.rhs[j];
            }
            double size = row_size(t.T, i, t.basis, t.wlab, t.wcol);
            w.mags[i] = size;
            t.magb[i] = size;
        }
    }
    double cmax = 0.0;  // pivoting.min_ratio
    for (idx i = 0; i < n; ++i) cmax = pmax(cmax, std::fabs(c[i]));
    idx nc = blocking_rows(t.rhs, exact_sizes ? w.mags : t.rhs, c, n, -pivot_tol * cmax, tie_tol,
                           w.cand, art, z0_max);
    return lex_break(t.T, c, t.pos, t.inb, t.start, art, pivot_tol, tie_tol, w.cand, w.keys, nc);
}

// pivoting.blocking_rows(vals, vals, col, n, thr, tie_tol, cand, -1, 0.0), the same rows in
// the same order, for the common case (no artificial row, every value's size its own): the
// ratios first, in a loop without branches (ratio[i], NaN where row i does not block), then
// the scan, whose branch is almost never taken once the minimum is found (the ratio test
// with a branch on each entry's sign cost a third of a pivot at n = 100, mispredicted).
LEMKE_CLONES
void plain_ratios(const double* vals, const double* col, idx n, double thr, double* ratio) {
    for (idx i = 0; i < n; ++i) {
        double c = col[i];
        double v = vals[i];
        double t = (v > VALUE_ROUNDING * v ? v : 0.0) / -c;  // row_value(vals, vals, i, -1, 0)
        ratio[i] = c < thr ? t : NAN;
    }
}

idx plain_blocking_rows(const double* vals, const double* col, idx n, double thr, double tie_tol,
                        idx* cand, double* ratio) {
    plain_ratios(vals, col, n, thr, ratio);
    return blocking_rows_scan(ratio, n, tie_tol, cand);  // (NaN ratios do not block)
}

// games.step: one pivot, the label `entering` enters; returns the label that left, -1 when
// nothing blocks, -2 when the pivot entry is not finite.
idx step(Tab& t, idx entering, bool has_free, const std::uint8_t* free, idx art, double z0_max,
         double pivot_tol, double tie_tol, Scratch& w) {
    idx s = t.pos[entering];
    idx rows = t.T.rows;
    double* col = w.col;
    bool sized = false;
    const double* T = t.T.p;
    idx ld = t.T.ld;
    // cmax: the largest |entry| (pivoting.min_ratio's), taken in four running maxima (the
    // maximum does not depend on the order; pmax skips a NaN either way), so that the
    // column's loads need not wait for one chain of comparisons.
    double c0 = 0.0, c1 = 0.0;
    const double* rhs = t.rhs;
    const double* magb = t.magb;
    auto blocks_small = [&](double v, idx i) {
        double b = rhs[i];
        return (v < 0.0) & (b > 0.0) & (b <= VALUE_ROUNDING * magb[i]);
    };
    idx i = 0;
    for (; i + 2 <= rows; i += 2) {
        double v0 = T[i * ld + s], v1 = T[(i + 1) * ld + s];
        col[i] = v0;
        col[i + 1] = v1;
        c0 = pmax(c0, std::fabs(v0));
        c1 = pmax(c1, std::fabs(v1));
        sized |= blocks_small(v0, i) | blocks_small(v1, i + 1);
    }
    if (i < rows) {
        double v = T[i * ld + s];
        col[i] = v;
        c0 = pmax(c0, std::fabs(v));
        sized |= blocks_small(v, i);
    }
    double cmax = pmax(c0, c1);
    idx r;
    if (has_free || art >= 0 || sized) {
        r = leaving_row(t, col, has_free, free, art, z0_max, pivot_tol, tie_tol, w);
    } else {
        idx nc = plain_blocking_rows(t.rhs, col, rows, -pivot_tol * cmax, tie_tol, w.cand,
                                     w.mags);
        r = nc == 1 ? w.cand[0]
                    : lex_break(t.T, col, t.pos, t.inb, t.start, art, pivot_tol, tie_tol, w.cand,
                                w.keys, nc);
    }
    idx leaving = -1;
    if (r >= 0 && !(std::fabs(col[r]) < INF)) {
        leaving = -2;
    } else if (r >= 0) {
        exchange(t.T, t.rhs, t.magb, r, s, col, w.prow, t.basis, t.wlab, t.wcol);  // row_size too
        leaving = swap_labels(t.basis, t.nonbasic, t.pos, t.inb, r, s);
        t.wcol[s] = t.wlab[leaving];
    }
    return leaving;
}

// games.place: pivot until the labels target[:count] are the basic ones. want: L flags.
bool place(Tab& t, const idx* target, idx count, idx n_labels, double* col, double* prow,
           std::uint8_t* want) {
    idx n = t.T.rows;
    bool done = true;
    for (idx q = 0; q < count; ++q) done &= t.inb[target[q]] != 0;
    if (done) return true;
    for (idx l = 0; l < n_labels; ++l) want[l] = 0;
    for (idx q = 0; q < count; ++q) want[target[q]] = 1;
    for (idx q = 0; q < count; ++q) {
        idx lab = target[q];
        if (t.inb[lab]) continue;
        idx s = t.pos[lab];
        idx best = -1;
        double big = 0.0;
        for (idx i = 0; i < n; ++i) {
            if (!want[t.basis[i]] && std::fabs(t.T(i, s)) > big) {
                big = std::fabs(t.T(i, s));
                best = i;
            }
        }
        if (best < 0 || big < 1e-12) return false;
        for (idx i = 0; i < n; ++i) col[i] = t.T(i, s);
        exchange(t.T, t.rhs, t.magb, best, s, col, prow);
        swap_labels(t.basis, t.nonbasic, t.pos, t.inb, best, s);
    }
    return true;
}

// games.normalize: v / sum(v), negative rounding clamped to 0; false when nothing is left.
bool normalize(double* v, idx len) {
    double t = 0.0;
    for (idx i = 0; i < len; ++i) {
        v[i] = pmax(v[i], 0.0);
        t += v[i];
    }
    if (!(t > 0.0) || !(t < INF)) return false;
    for (idx i = 0; i < len; ++i) v[i] /= t;
    return true;
}

// int(x) of a float64 as x86's cvttsd2si gives it (INT64_MIN when out of range or NaN).
idx float_to_int(double x) {
    if (x >= -9223372036854775808.0 && x < 9223372036854775808.0) return static_cast<idx>(x);
    return INT64_MIN;
}

// --- Lemke-Howson ---------------------------------------------------------------------------

// The work arrays of one Lemke-Howson solve (F, I, Z, U), laid out here
// and only here.
struct LHViews {
    Tab P, Q;
    Scratch w;
    idx *slackP, *slackQ;
    std::uint8_t* want;
    double* acc;   // verdict's scratch (n)
    idx* index;    // verdict's scratch (max(m, n))
};

// Each tableau row and the pivot row start on a 64-byte boundary (rows padded to a multiple
// of 8 doubles): the updates' vector loads then never straddle two cache lines.
constexpr idx ALIGN = 8;  // doubles
inline idx padded(idx k) { return (k + ALIGN - 1) / ALIGN * ALIGN; }

LHViews lh_layout(GamesWork& g, idx m, idx n) {
    idx L = m + n, big = std::max(m, n);
    idx ldP = padded(m), ldQ = padded(n);  // P is n x m, Q m x n
    g.reserve(ALIGN + n * ldP + m * ldQ + padded(big) + 4 * L + 2 * L + 4 * big + n,
              6 * L + 2 * big, 3 * L);
    LHViews v;
    double* f = g.f.data();
    idx* i = g.i.data();
    std::uint8_t* z = g.z.data();
    f += (ALIGN - reinterpret_cast<std::uintptr_t>(f) / sizeof(double) % ALIGN) % ALIGN;
    v.P.T = Mat<double>(f, n, m);
    v.P.T.ld = ldP;
    f += n * ldP;
    v.Q.T = Mat<double>(f, m, n);
    v.Q.T.ld = ldQ;
    f += m * ldQ;
    v.w.prow = f; f += padded(big);
    v.P.rhs = f; v.P.magb = f + n; f += 2 * n;
    v.Q.rhs = f; v.Q.magb = f + m; f += 2 * m;
    v.P.wlab = f; v.Q.wlab = f + L; f += 2 * L;
    v.P.wcol = f; v.Q.wcol = f + m; f += L;
    v.w.col = f; v.w.scratch = f + big; v.w.keys = f + 2 * big; v.w.mags = f + 3 * big;
    f += 4 * big;
    v.acc = f;
    v.P.basis = i; v.P.nonbasic = i + n; i += L;
    v.Q.basis = i; v.Q.nonbasic = i + m; i += L;
    v.P.pos = i; v.Q.pos = i + L; i += 2 * L;
    v.slackP = i; v.slackQ = i + n; i += L;
    v.w.cand = i; i += big;
    v.index = i;
    v.P.start = v.slackP;
    v.Q.start = v.slackQ;
    v.P.inb = z; v.Q.inb = z + L; v.want = z + 2 * L;
    return v;
}

// The entries of a tableau at the artificial equilibrium: T[r, c] = -(1 + (P[c, r] - lo) f)
// with P[c, r] = src[r * rs + c * cs] (rs = 1: the payoffs transposed), the rows' padding 0.
LEMKE_CLONES
void setup_entries(Mat<double> T, const double* src, idx rs, idx cs, double lo, double f) {
    for (idx r = 0; r < T.rows; ++r) {
        double* tr = T.row(r);
        const double* p = src + r * rs;
        if (cs == 1) {
            for (idx c = 0; c < T.cols; ++c) tr[c] = -(1.0 + (p[c] - lo) * f);
        } else {
            for (idx c = 0; c < T.cols; ++c) tr[c] = -(1.0 + (p[c * cs] - lo) * f);
        }
        for (idx c = T.cols; c < T.ld; ++c) tr[c] = 0.0;  // the padding: read, never used
    }
}

// games.tableau_setup: one tableau at the artificial equilibrium from the payoffs src (see
// setup_entries).
void tableau_setup(const double* src, idx rs, idx cs, double lo, double f, Tab& t, idx first) {
    idx rows = t.T.rows, cols = t.T.cols, L = rows + cols;
    setup_entries(t.T, src, rs, cs, lo, f);
    for (idx r = 0; r < rows; ++r) {
        t.rhs[r] = 1.0;
        idx lab = first + r < L ? first + r : first + r - L;  // (first + r) % L
        t.basis[r] = lab;
        t.pos[lab] = r;
        t.inb[lab] = 1;
    }
    for (idx c = 0; c < cols; ++c) {
        idx lab = first + rows + c < L ? first + rows + c : first + rows + c - L;
        t.nonbasic[c] = lab;
        t.pos[lab] = c;
        t.inb[lab] = 0;
    }
}

// games.lh_path: one path dropping label k from the basis whose basic labels are startP
// (n) and startQ (m).
int lh_path(Mat<const double> A, Mat<const double> B, const double* scale, idx k,
            const idx* startP, const idx* startQ, bool perturb, idx max_pivots,
            double pivot_tol, double tie_tol, double* x, double* y, idx* basisP, idx* basisQ,
            idx* state, LHViews& v, idx& pivots) {
    idx m = A.rows, n = A.cols, L = m + n;
    Tab& P = v.P;
    Tab& Q = v.Q;
    tableau_setup(B.p, 1, B.ld, scale[2], scale[3], P, m);     // P[r, c] from B[c, r]
    tableau_setup(A.p, A.ld, 1, scale[0], scale[1], Q, 0);     // Q[r, c] from A[r, c]
    for (idx j = 0; j < n; ++j) v.slackP[j] = P.basis[j];
    for (idx i = 0; i < m; ++i) v.slackQ[i] = Q.basis[i];
    if (perturb) {
        for (idx j = 0; j < n; ++j)
            P.rhs[j] *= 1.0 + PERTURBATION * unit_random(label_key(m + j));
        for (idx i = 0; i < m; ++i) Q.rhs[i] *= 1.0 + PERTURBATION * unit_random(label_key(i));
    }
    for (idx j = 0; j < n; ++j) P.magb[j] = std::fabs(P.rhs[j]);
    for (idx i = 0; i < m; ++i) Q.magb[i] = std::fabs(Q.rhs[i]);
    for (idx l = 0; l < L; ++l) P.wlab[l] = Q.wlab[l] = 0.0;
    for (idx j = 0; j < n; ++j) P.wlab[m + j] = std::fabs(P.rhs[j]);
    for (idx i = 0; i < m; ++i) Q.wlab[i] = std::fabs(Q.rhs[i]);
    int status = MAX_PIVOTS;
    pivots = 0;
    if (!(place(P, startP, n, L, v.w.col, v.w.prow, v.want) &&
          place(Q, startQ, m, L, v.w.col, v.w.prow, v.want))) {
        status = NUMERICAL_FAILURE;
        max_pivots = 0;
    }
    column_weights(P.nonbasic, m, P.wlab, P.wcol);
    column_weights(Q.nonbasic, n, Q.wlab, Q.wcol);
    std::uint64_t h = 0, hq = 0;
    for (idx j = 0; j < n; ++j) h ^= label_key(P.basis[j]);
    for (idx i = 0; i < m; ++i) hq ^= label_key(Q.basis[i] + L);
    h ^= hq;
    Detector detector;
    idx* hist = state + 3;
    idx entering = k;
    idx side = P.inb[k] ? 1 : 0;  // the tableau where label k is non-basic
    Poll poll;
    std::int64_t work = (m + 1) * (n + 1) * 2;
    while (pivots < max_pivots) {
        if (int stop = poll.tick(work); stop >= 0) {
            status = stop;
            break;
        }
        idx leaving = step(side == 0 ? P : Q, entering, false, nullptr, -1, 0.0, pivot_tol,
                           tie_tol, v.w);
        if (leaving < 0) {
            status = NUMERICAL_FAILURE;  // P and Q are bounded: a ray is rounding
            break;
        }
        hist[pivots & (HISTORY - 1)] = leaving;
        pivots += 1;
        idx shift = side == 0 ? 0 : L;
        int stop = after_pivot(leaving + shift, entering + shift, k + shift, h, detector);
        entering = leaving;
        side = 1 - side;
        if (stop >= 0) {
            status = stop;
            break;
        }
    }
    state[0] = entering;
    state[1] = side;
    state[2] = pivots;
    for (idx i = 0; i < m; ++i) x[i] = 0.0;
    for (idx j = 0; j < n; ++j) y[j] = 0.0;
    for (idx j = 0; j < n; ++j)
        if (P.basis[j] < m) x[P.basis[j]] = P.rhs[j];
    for (idx i = 0; i < m; ++i)
        if (Q.basis[i] >= m) y[Q.basis[i] - m] = Q.rhs[i];
    for (idx j = 0; j < n; ++j) basisP[j] = P.basis[j];
    for (idx i = 0; i < m; ++i) basisQ[i] = Q.basis[i];
    return status;
}

}  // namespace

LHResult lemke_howson(Mat<const double> A, Mat<const double> B, idx k, const idx* start,
                      const double* params, double* buf) {
    idx m = A.rows, n = A.cols;
    Range ra = payoff_range(A), rb = payoff_range(B);
    if (!(ra.finite && rb.finite)) return {NOT_FINITE, 0, 0};
    idx max_pivots = float_to_int(params[0]);
    double pivot_tol = params[1], tie_tol = params[2], tol = params[3];
    LHLayout at{m, n};
    double* x = buf + at.x();
    double* y = buf + at.y();
    double* out = buf + at.regret();
    const idx* startP = start;
    const idx* startQ = start + n;
    idx* basisP = reinterpret_cast<idx*>(buf + at.labels());
    idx* basisQ = basisP + n;
    idx* state = reinterpret_cast<idx*>(buf + at.state());
    double scale[4] = {ra.lo, positive_scale(ra.lo, ra.hi), rb.lo, positive_scale(rb.lo, rb.hi)};
    thread_local GamesWork work;
    LHViews v = lh_layout(work, m, n);
    idx pivots = 0, restarts = 0;
    int status = NUMERICAL_FAILURE;
    // The ladder (ladder.hpp): the path, again with exact ties, then the third path (its
    // perturbation); each path after the first is a restart.
    auto path = [&](double tt, bool perturb) {
        idx p = 0;
        status = lh_path(A, B, scale, k, startP, startQ, perturb, max_pivots - pivots,
                         pivot_tol, tt, x, y, basisP, basisQ, state, v, p);
        pivots += p;
    };
    ladder::climb(
        [&] {
            return status == SOLVED || status == MAX_PIVOTS || is_stop(status) ||
                   pivots >= max_pivots;
        },
        ladder::rung("the path", ladder::Always{}, [&] { path(tie_tol, false); }),
        ladder::rung("exact ties", [&] { return !(tie_tol == 0.0); }, [&] {
            restarts += 1;
            path(0.0, false);
        }),  // (skipped when the first path had exact ties already)
        ladder::rung("perturbed", ladder::Always{}, [&] {
            restarts += 1;
            path(0.0, true);
        }));
    bool good = normalize(x, m) && normalize(y, n);
    if (!good) {
        out[0] = INF;
        return {status == SOLVED ? static_cast<int>(NUMERICAL_FAILURE) : status, pivots, restarts};
    }
    bool ok = verdict(A, B, x, y, allowance(ra.lo, ra.hi, m, n, tol),
                      allowance(rb.lo, rb.hi, m, n, tol), out, v.acc, v.index);
    if (status == SOLVED && !ok) status = UNCHECKED;
    return {status, pivots, restarts};
}

// --- the tracing procedure ------------------------------------------------------------------

namespace {

// The work arrays of one tracing run, laid out here and only here: the system (N = m + n + 2
// rows, m + n + 3 columns, 2 (m + n) + 5 labels), the positive payoffs and the scratch.
struct TraceViews {
    Tab t;
    Scratch w;
    double *Ap, *Bp, *acc;
    idx *start, *index;
    std::uint8_t* free;
};

TraceViews trace_layout(GamesWork& g, idx m, idx n) {
    idx L = m + n, N = L + 2, K = L + 3, labels = 2 * L + 5, big = std::max(m, n);
    g.reserve(N * K + 3 * N + labels + K + N + K + 2 * N + 2 * m * n + n,
              N + K + labels + 2 * N + big, 2 * labels);
    TraceViews v;
    double* f = g.f.data();
    idx* i = g.i.data();
    std::uint8_t* z = g.z.data();
    v.t.T = Mat<double>(f, N, K); f += N * K;
    v.t.rhs = f; v.t.magb = f + N; v.w.mags = f + 2 * N; f += 3 * N;
    v.t.wlab = f; f += labels;
    v.t.wcol = f; f += K;
    v.w.col = f; f += N;
    v.w.prow = f; f += K;
    v.w.keys = f; v.w.scratch = f + N; f += 2 * N;
    v.Ap = f; v.Bp = f + m * n; f += 2 * m * n;
    v.acc = f;
    v.t.basis = i; i += N;
    v.t.nonbasic = i; i += K;
    v.t.pos = i; i += labels;
    v.start = i; v.t.start = i; i += N;
    v.w.cand = i; i += N;
    v.index = i;
    v.t.inb = z; v.free = z + labels;
    return v;
}

// games.positive_payoffs into out (m x n).
void positive_payoffs(Mat<const double> A, double* out) {
    Range r = payoff_range(A);
    double f = positive_scale(r.lo, r.hi);
    for (idx i = 0; i < A.rows; ++i)
        for (idx j = 0; j < A.cols; ++j) out[i * A.cols + j] = 1.0 + (A(i, j) - r.lo) * f;
}

}  // namespace

TraceResult trace(Mat<const double> A, Mat<const double> B, const double* p, const double* q,
                  idx max_pivots, double pivot_tol, double tie_tol, double tol, double* x,
                  double* y, idx* basis_out, double* out) {
    idx m = A.rows, n = A.cols, L = m + n, N = L + 2, K = L + 3, labels = 2 * L + 5;
    idx U = 2 * L, V = 2 * L + 1, Z0 = 2 * L + 2, E1 = 2 * L + 3, E2 = 2 * L + 4;
    thread_local GamesWork work;
    TraceViews v = trace_layout(work, m, n);
    Tab& t = v.t;
    Mat<double> T = t.T;
    double* rhs = t.rhs;
    positive_payoffs(A, v.Ap);
    positive_payoffs(B, v.Bp);
    for (idx e = 0; e < N * K; ++e) T.p[e] = 0.0;
    for (idx r = 0; r < N; ++r) rhs[r] = 0.0;
    for (idx i = 0; i < m; ++i) {
        double aq = 0.0;
        for (idx j = 0; j < n; ++j) {
            T(i, m + j) = -v.Ap[i * n + j];
            aq += v.Ap[i * n + j] * q[j];
        }
        T(i, L) = 1.0;
        T(i, L + 2) = -aq;
    }
    for (idx j = 0; j < n; ++j) {
        double bp = 0.0;
        for (idx i = 0; i < m; ++i) {
            T(m + j, i) = -v.Bp[i * n + j];
            bp += v.Bp[i * n + j] * p[i];
        }
        T(m + j, L + 1) = 1.0;
        T(m + j, L + 2) = -bp;
    }
    for (idx i = 0; i < m; ++i) T(L, i) = -1.0;
    for (idx j = 0; j < n; ++j) T(L + 1, m + j) = -1.0;
    T(L, L + 2) = -1.0;
    T(L + 1, L + 2) = -1.0;
    rhs[L] = 1.0;
    rhs[L + 1] = 1.0;
    idx *basis = t.basis, *nonbasic = t.nonbasic, *pos = t.pos;
    std::uint8_t* inb = t.inb;
    for (idx l = 0; l < labels; ++l) inb[l] = 0;
    for (idx r = 0; r < L; ++r) basis[r] = L + r;
    basis[L] = E1;
    basis[L + 1] = E2;
    for (idx c = 0; c < L; ++c) nonbasic[c] = c;
    nonbasic[L] = U;
    nonbasic[L + 1] = V;
    nonbasic[L + 2] = Z0;
    for (idx r = 0; r < N; ++r) {
        pos[basis[r]] = r;
        inb[basis[r]] = 1;
    }
    for (idx c = 0; c < K; ++c) pos[nonbasic[c]] = c;
    // The best responses to the prior (the first on ties).
    idx istar = 0;
    double best = -INF;
    for (idx i = 0; i < m; ++i) {
        if (-T(i, L + 2) > best) {
            best = -T(i, L + 2);
            istar = i;
        }
    }
    idx jstar = 0;
    best = -INF;
    for (idx j = 0; j < n; ++j) {
        if (-T(m + j, L + 2) > best) {
            best = -T(m + j, L + 2);
            jstar = j;
        }
    }
    double* col = v.w.col;
    double* prow = v.w.prow;
    double* magb = t.magb;
    for (idx r = 0; r < N; ++r) magb[r] = std::fabs(rhs[r]);
    const idx target[4] = {U, V, Z0, m + jstar};
    const idx rows[4] = {istar, m + jstar, L, L + 1};
    for (int s4 = 0; s4 < 4; ++s4) {
        idx s = pos[target[s4]];
        for (idx i = 0; i < N; ++i) col[i] = T(i, s);
        exchange(T, rhs, magb, rows[s4], s, col, prow);
        swap_labels(basis, nonbasic, pos, inb, rows[s4], s);
    }
    for (idx r = 0; r < N; ++r) v.start[r] = basis[r];  // the keys are relative to it
    for (idx r = 0; r < N; ++r) magb[r] = std::fabs(rhs[r]);
    double* wlab = t.wlab;
    for (idx l = 0; l < labels; ++l) wlab[l] = 0.0;
    for (idx r = 0; r < N; ++r) wlab[basis[r]] = std::fabs(rhs[r]);
    column_weights(nonbasic, K, wlab, t.wcol);
    std::uint8_t* free = v.free;
    for (idx l = 0; l < labels; ++l) free[l] = 0;
    free[U] = 1;
    free[V] = 1;
    std::uint64_t h = 0;
    for (idx r = 0; r < N; ++r) h ^= label_key(basis[r]);
    Detector detector;
    int status = MAX_PIVOTS;
    idx pivots = 0;
    idx entering = istar;
    double z0_max = 1.0;
    Poll poll;
    std::int64_t pivot_work = N * K;
    while (pivots < max_pivots) {
        if (int stop = poll.tick(pivot_work); stop >= 0) {
            status = stop;
            break;
        }
        idx art = inb[Z0] ? pos[Z0] : -1;
        idx leaving = step(t, entering, true, free, art, z0_max, pivot_tol, tie_tol, v.w);
        if (leaving < 0) {
            status = leaving == -1 ? RAY_TERMINATION : NUMERICAL_FAILURE;
            break;
        }
        pivots += 1;
        int stop = after_pivot(leaving, entering, Z0, h, detector);
        if (stop >= 0) {
            status = stop;
            break;
        }
        entering = leaving < L ? leaving + L : leaving - L;  // the complement
    }
    for (idx i = 0; i < m; ++i) x[i] = 0.0;
    for (idx j = 0; j < n; ++j) y[j] = 0.0;
    for (idx r = 0; r < N; ++r) {
        idx lab = basis[r];
        if (lab < m)
            x[lab] = rhs[r];
        else if (lab < L)
            y[lab - m] = rhs[r];
    }
    for (idx r = 0; r < N; ++r) basis_out[r] = basis[r];
    if (!(normalize(x, m) && normalize(y, n))) {
        out[0] = INF;
        return {status == SOLVED ? static_cast<int>(NUMERICAL_FAILURE) : status, pivots};
    }
    Range ra = payoff_range(A), rb = payoff_range(B);
    bool ok = verdict(A, B, x, y, allowance(ra.lo, ra.hi, m, n, tol),
                      allowance(rb.lo, rb.hi, m, n, tol), out, v.acc, v.index);
    if (ok) return {SOLVED, pivots};
    return {status == SOLVED ? UNCHECKED : status, pivots};
}

}  // namespace games
}  // namespace lemke
