#include "boxed.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "basis.hpp"
#include "certify.hpp"
#include "multiversion.hpp"
#include "reductions.hpp"
#include "tableau.hpp"

namespace lemke {
namespace boxed {

void BoxedWork::layout(idx size) {
    n = size;
    idx lanes = n < 48 ? 4 : 8;  // TableauWork's rule (tableau.cpp)
    ld = (n + lanes) / lanes * lanes;
    block = block_size(n);
    off = 0;
    // grown, never shrunk: a resize down then up again (islands of varying sizes on one
    // thread) zero-filled the regrown part on every call, which no field reads (solve
    // writes each field before reading it; the flags are zeroed there)
    auto grow = [](auto& v, idx len) {
        if (static_cast<idx>(v.size()) < len) v.resize(static_cast<std::size_t>(len));
    };
    grow(f, f_length() + 7);
    auto at = reinterpret_cast<std::uintptr_t>(f.data());
    off = static_cast<idx>((64 - at % 64) % 64 / sizeof(double));
    grow(i, i_length());
    grow(flags, flags_length());
}

double* BoxedWork::check_area(idx len) {
    if (static_cast<idx>(chk.size()) < len + 1) chk.resize(static_cast<std::size_t>(len + 1));
    return chk.data();
}

idx* BoxedWork::check_indices(idx len) {
    if (static_cast<idx>(chk_i.size()) < len + 1) chk_i.resize(static_cast<std::size_t>(len + 1));
    return chk_i.data();
}

std::uint8_t* BoxedWork::check_flags(idx len) {
    if (static_cast<idx>(chk_f.size()) < len + 1) chk_f.resize(static_cast<std::size_t>(len + 1));
    return chk_f.data();
}

namespace {

BoxedWork& work() {
    thread_local BoxedWork w;
    return w;
}

// Whether z_i starts as a free variable (both bounds FAR away or infinite).
inline bool far_both(const double* lo, const double* hi, idx i) {
    return lo[i] <= -FAR && hi[i] >= FAR;
}

// Where z_i starts (boxed.start_point, row i), into z[i]; at_hi[i] updated.
inline void start_point(const double* lo, const double* hi, std::uint8_t* at_hi, const double* q,
                        bool guess, idx i, double* z) {
    if (far_both(lo, hi, i) && (guess || (lo[i] == -INF && hi[i] == INF))) {
        z[i] = 0.0;
        at_hi[i] = 0;
        return;
    }
    if (guess && lo[i] > -INF && hi[i] < INF) {
        if (lo[i] <= -FAR) {
            at_hi[i] = 1;
        } else if (hi[i] >= FAR) {
            at_hi[i] = 0;
        } else {
            at_hi[i] = q[i] < 0.0;
        }
    }
    if (at_hi[i] && hi[i] < INF) {
        z[i] = hi[i];
    } else if (lo[i] > -INF) {
        z[i] = lo[i];
    } else if (hi[i] < INF) {
        z[i] = hi[i];
    } else {
        z[i] = 0.0;
    }
}

bool trivial_start(const double* lo, const double* hi, const std::uint8_t* at_hi,
                   const double* w, idx n) {
    for (idx i = 0; i < n; ++i) {
        if (lo[i] == hi[i]) continue;
        if (far_both(lo, hi, i)) return false;
        if ((w[i] < 0.0 && !at_hi[i]) || (w[i] > 0.0 && at_hi[i])) return false;
    }
    return true;
}

// The bounds of variable `lab` while basic (scaled units), boxed.bounds_of.
inline void bounds_of(idx lab, idx n, const double* lo, const double* hi,
                      const std::uint8_t* at_hi, double& lb, double& ub) {
    if (lab >= 2 * n) {
        lb = 0.0;
        ub = INF;
        return;
    }
    if (lab >= n) {
        lb = lo[lab - n];
        ub = hi[lab - n];
        return;
    }
    if (lo[lab] == hi[lab]) {
        lb = -INF;
        ub = INF;
        return;
    }
    if (at_hi[lab]) {
        lb = -INF;
        ub = 0.0;
        return;
    }
    lb = 0.0;
    ub = INF;
}

inline void step_values(double* x, const idx* basis, const double* col, idx n, idx e,
                        double delta) {
    for (idx i = 0; i < n; ++i) x[basis[i]] += col[i] * delta;
    x[e] += delta;
}

// The run's views of the workspace.
struct Run {
    idx n;
    Mat<double> T;
    double *x, *prow, *col;
    idx *basis, *nonbasic, *pos;
    std::uint8_t* is_basic;
    explicit Run(BoxedWork& w)
        : n(w.n), T(w.T()), x(w.x()), prow(w.prow()),
          col(w.col()), basis(w.basis()), nonbasic(w.nonbasic()), pos(w.pos()),
          is_basic(w.is_basic()) {}
};

// Make the wanted z's basic in exchange for their w's (boxed.exchange); returns the pivots.
idx exchange(Run& R, const std::uint8_t* want) {
    idx n = R.n;
    Mat<double> T = R.T;
    const std::uint8_t* is_basic = R.is_basic;
    const idx* pos = R.pos;
    double* col = R.col;
    idx done = 0;
    while (true) {
        double best = 0.0;
        idx br = -1, bs = -1;
        for (idx j = 0; j < n; ++j) {
            if (want[j] && !is_basic[n + j] && is_basic[j]) {
                double a = std::fabs(T(pos[j], pos[n + j]));
                if (a > best) {
                    best = a;
                    br = pos[j];
                    bs = pos[n + j];
                }
            }
        }
        if (best < EXCHANGE_TOL) {
            for (idx i = 0; i < n; ++i) {
                if (want[i] && is_basic[i]) {
                    for (idx j = 0; j < n; ++j) {
                        if (want[j] && !is_basic[n + j]) {
                            double a = std::fabs(T(pos[i], pos[n + j]));
                            if (a > best) {
                                best = a;
                                br = pos[i];
                                bs = pos[n + j];
                            }
                        }
                    }
                }
            }
        }
        if (br < 0 || best < EXCHANGE_TOL) return done;
        for (idx i = 0; i < n; ++i) col[i] = T(i, bs);
        idx e = R.nonbasic[bs];
        idx leaving = R.basis[br];
        step_values(R.x, R.basis, col, n, e, -R.x[leaving] / col[br]);
        R.x[leaving] = 0.0;
        pivot_now(T, nullptr, nullptr, br, bs, col, R.prow);
        swap_labels(R.basis, R.nonbasic, R.pos, R.is_basic, br, bs);
        ++done;
    }
}

// Row i's low flag (i < n) as boxed.ratio_rows defines it: the entering column c = sigma
// col[i] is negative (the basic variable falls to its lower bound) or the bound it moves
// towards is infinite. Taken for the few rows that need it (the blocking rows), not stored
// for every row.
LEMKE_ALWAYS_INLINE bool row_low(const double* col, double sigma, const double* rlo,
                                 const double* rhi, idx i) {
    double c = sigma * col[i];
    bool neg = c < 0.0;
    double bnd = neg ? rlo[i] : rhi[i];
    return neg || !(std::fabs(bnd) < INF);
}

// The rows of the ratio test (boxed.ratio_rows): returns the artificial variable's row
// (-1 when not basic), cmax the largest |cc|, kept as the rows go in eight running maxima
// (a maximum of numbers that no NaN ever changes, as pmax runs it, is the same in any order;
// it was a loop of its own). The low flags: row_low, for the rows that need them, and
// low[n] here. Eight rows at a time on vectors, branch-free selects (both gaps computed,
// each lane the scalar row's operations); the flags stored per row had made it a scalar
// loop with a branch on each row's sign (GCC leaves the plain form scalar too). Inlined
// into each of lemke_run's clones (LEMKE_CLONES).
LEMKE_ALWAYS_INLINE idx ratio_rows(const double* xb, const idx* pos,
                                   const std::uint8_t* is_basic, const double* col,
                                   double sigma, idx e, idx n, const double* lo,
                                   const double* hi, const double* rlo, const double* rhi,
                                   double* gaps, double* cc, std::uint8_t* low, double& cmax) {
    idx art_lab = 2 * n;
    idx art = is_basic[art_lab] ? pos[art_lab] : -1;
    double tops[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    idx i = 0;
#ifdef LEMKE_SIMD
    {
        simd::v8d vsig = simd::splat8(sigma), vinf = simd::splat8(INF);
        simd::v8d zero = simd::splat8(0.0), vtop = zero;
        for (; i + 8 <= n; i += 8) {
            simd::v8d c = vsig * simd::load8(col + i);
            simd::v8d v = simd::load8(xb + i);
            simd::v8d rl = simd::load8(rlo + i), rh = simd::load8(rhi + i);
            simd::v8l neg = c < zero;
            simd::v8d bnd = neg ? rl : rh;
            simd::v8l fin = simd::abs8(bnd) < vinf;
            simd::v8d a = simd::abs8(c);
            simd::v8d g = neg ? (v - rl) : (rh - v);
            simd::store8(gaps + i, fin ? g : vinf);
            simd::store8(cc + i, fin ? -a : a);
            vtop = simd::max8(vtop, a);
        }
        for (int l = 0; l < 8; ++l) tops[l] = vtop[l];
    }
#endif
    for (; i < n; ++i) {
        double c = sigma * col[i];
        double v = xb[i];
        double rl = rlo[i], rh = rhi[i];
        bool neg = c < 0.0;
        double bnd = neg ? rl : rh;
        bool fin = std::fabs(bnd) < INF;
        double a = std::fabs(c);
        double g = neg ? (v - rl) : (rh - v);
        gaps[i] = fin ? g : INF;
        cc[i] = fin ? -a : a;
        tops[0] = pmax(tops[0], a);
    }
    double top = 0.0;
    for (int l = 0; l < 8; ++l) top = pmax(top, tops[l]);
    if (art >= 0) gaps[art] = xb[art];
    gaps[n] = INF;
    cc[n] = 0.0;
    low[n] = 0;
    if (e >= n && e < 2 * n) {
        double lb = lo[e - n], ub = hi[e - n];
        if (lb > -INF && ub < INF) {
            gaps[n] = ub - lb;
            cc[n] = -1.0;
            low[n] = sigma < 0.0;
        }
    }
    cmax = pmax(top, std::fabs(cc[n]));
    return art;
}

// The blocking row among nc > 1 tied rows (boxed.ratio_ties); -1 when none is left.
idx ratio_ties(Mat<double> T, const Pending& P, const idx* pos, const std::uint8_t* is_basic,
               const idx* start_basis, const double* s0, idx n, double pivot_tol,
               double tie_tol, const double* cc, const std::uint8_t* low, idx* cand,
               double* keys, idx nc, idx art) {
    for (idx c = 0; c < nc; ++c)
        if (cand[c] == art) return art;
    for (idx j = 0; j < n; ++j) {
        idx lab = start_basis[j];
        for (idx c = 0; c < nc; ++c) {
            idx i = cand[c];
            double b;
            if (i == n) {
                b = 0.0;
            } else if (is_basic[lab]) {
                b = pos[lab] == i ? 1.0 : 0.0;
            } else {
                b = -entry(T, P, i, pos[lab]);
            }
            double sg = low[i] ? 1.0 : -1.0;
            keys[c] = lex_key(sg * s0[j] * b, cc[i], pivot_tol);
        }
        nc = keep_lowest(cand, keys, nc, tie_tol);
        if (nc == 1) return cand[0];
    }
    return nc > 0 ? largest_pivot(cand, cc, nc) : -1;
}

// Bounded-variable Lemke (boxed.lemke) from a complementary basis with z0's column in
// T[:, n], z0 non-basic; lo, hi, at_hi the scaled bounds and flags; ray (2n + 1). Compiled
// per instruction set, as tableau_lemke: the column copy and the ratio test run every pivot.
LEMKE_CLONES
Status lemke_run(BoxedWork& w, Run& R, const double* lo, const double* hi, std::uint8_t* at_hi,
                 const double* s0, idx max_pivots, double pivot_tol, double tie_tol,
                 double* ray, idx& pivots_out) {
    idx n = R.n;
    Mat<double> T = R.T;
    double* x = R.x;
    double* col = R.col;
    double* col_next = w.col2();  // the next entering column, read during pivot_now
    idx *basis = R.basis, *pos = R.pos;
    std::uint8_t* is_basic = R.is_basic;
    idx art_lab = 2 * n;
    idx* start_basis = w.start_basis();
    idx* cand = w.cand();
    double *keys = w.keys(), *gaps = w.gaps(), *cc = w.cc(), *rlo = w.rlo(), *rhi = w.rhi();
    std::uint8_t* low = w.low();
    // pivots kept pending from n = 32 (block_size), as tableau_lemke keeps them: each pivot
    // makes its row and column exact in T and leaves the rank-one update pending, flushed
    // eight at a time; the columns and ratio_ties's entries read through the pending terms.
    // The run returns with up to seven pending (solve reads no T after it; the next run
    // lays T out afresh)
    Pending P{w.U(), w.V(), w.block, w.ld, 0, n};
    // keys 0..2n the labels, 2n + 1 + i z_i at hi (pivoting.label_key)
    std::uint64_t h = 0;
    Detector detector;
    pivots_out = 0;  // (ray: zeroed by solve)
    // the ratios in one vector pass from 16 rows (blocking_rows_vector, as the tableau's;
    // n = 48: 2 % of a cold solve); keys (n + 1) hold them, free until ratio_ties writes them
    double* ratios = n >= 16 ? keys : nullptr;
    // First pivot: z0 rises until every basic variable is within its bounds. One pass over
    // the rows: the start basis, each row's bounds, the fingerprint (an exclusive or, in any
    // order), z0's column and what each row needs of it.
    idx s = pos[art_lab];
    double* need = gaps;
    double* sc = cc;
    for (idx i = 0; i < n; ++i) {
        idx b = basis[i];
        start_basis[i] = b;
        bounds_of(b, n, lo, hi, at_hi, rlo[i], rhi[i]);
        h ^= label_key(b);
        if (at_hi[i] && !is_basic[n + i]) h ^= label_key(2 * n + 1 + i);
        double c = T(i, s);
        col[i] = c;
        if (c > 0.0) {
            need[i] = x[b] - rlo[i];
            sc[i] = c;
        } else if (c < 0.0) {
            need[i] = rhi[i] - x[b];
            sc[i] = -c;
        } else {
            need[i] = 0.0;
            sc[i] = 0.0;
        }
    }
    idx r = first_row(need, sc, n, tie_tol);
    if (r < 0) return NUMERICAL_FAILURE;
    double t = -need[r] / sc[r];
    // the basic variables' values by row from here (xb[i] is x[basis[i]]; x keeps the
    // non-basic ones, and the basic ones only once the run ends), so that the ratio test and
    // the steps run over contiguous rows; the same operations on the same numbers: this
    // first step is step_values's
    double* xb = w.xb();
    for (idx i = 0; i < n; ++i) xb[i] = x[basis[i]] + col[i] * t;
    x[art_lab] += t;
    bool low_r = col[r] > 0.0;
    idx pivots = 0;
    double sigma = 1.0;
    idx e = art_lab;
    double z0_max = 0.0;
    Status status = MAX_PIVOTS;
    Poll poll;
    idx s_next = -1;
    std::int64_t work = n * (n + 1);
    while (pivots < max_pivots) {
        if (int stop = poll.tick(work); stop >= 0) {
            status = static_cast<Status>(stop);
            break;
        }
        if (r == n) {  // bound flip of the entering z: no basis change
            idx j = e - n;
            at_hi[j] = !at_hi[j];
            x[e] = at_hi[j] ? hi[j] : lo[j];
            h ^= label_key(2 * n + 1 + j);
            ++pivots;
            e = j;
            sigma = at_hi[j] ? -1.0 : 1.0;
        } else {
            idx leaving = basis[r];
            if (!(std::fabs(col[r]) < INF) || col[r] == 0.0) {
                status = NUMERICAL_FAILURE;
                break;
            }
            double lb, ub;
            bounds_of(leaving, n, lo, hi, at_hi, lb, ub);
            x[leaving] = low_r ? lb : ub;
            xb[r] = x[e];  // the entering variable's value, basic in row r
            // the complement of the leaving variable enters next (below; none when z0
            // leaves): its column, non-basic and not s, is read during the row updates
            if (P.b == 1) {
                idx e_next = leaving < n ? leaving + n : leaving - n;
                s_next = leaving == art_lab || is_basic[e_next] || pos[e_next] == s
                             ? -1
                             : pos[e_next];
                pivot_now(T, nullptr, nullptr, r, s, col, R.prow, s_next, col_next);
            } else {
                pivot_delayed(T, nullptr, nullptr, r, s, col, R.prow, P);
            }
            swap_labels(basis, R.nonbasic, pos, is_basic, r, s);
            bounds_of(e, n, lo, hi, at_hi, rlo[r], rhi[r]);
            ++pivots;
            h ^= label_key(leaving) ^ label_key(e);
            if (e >= n && e < 2 * n && at_hi[e - n]) h ^= label_key(2 * n + 1 + e - n);
            if (leaving == art_lab) {
                x[art_lab] = 0.0;
                status = SOLVED;
                break;
            }
            if (leaving >= n) {  // a z left at a bound: its w enters, on that bound's side
                idx j = leaving - n;
                at_hi[j] = !low_r;
                if (at_hi[j]) h ^= label_key(2 * n + 1 + j);
                e = j;
                sigma = low_r ? 1.0 : -1.0;
            } else {  // a w reached 0: its z leaves the bound it sits at
                e = n + leaving;
                sigma = at_hi[leaving] ? -1.0 : 1.0;
            }
        }
        if (detector.repeats(h)) {
            status = CYCLING;
            break;
        }
        if (s_next >= 0 && pos[e] == s_next) {
            std::swap(col, col_next);  // the column pivot_now read: the same values
        } else if (P.k == 0) {
            for (idx i = 0; i < n; ++i) col[i] = T(i, pos[e]);
        } else {
            pending_column(T, P, pos[e], col);  // the current column: T and the pending terms
        }
        s = pos[e];
        s_next = -1;
        if (is_basic[art_lab]) z0_max = pmax(z0_max, xb[pos[art_lab]]);
        double cmax;
        idx art = ratio_rows(xb, pos, is_basic, col, sigma, e, n, lo, hi, rlo, rhi, gaps,
                             cc, low, cmax);
        idx nc = blocking_rows(gaps, gaps, cc, n + 1, -pivot_tol * cmax, tie_tol, cand, art,
                               z0_max, ratios);
        if (nc <= 1) {
            r = nc == 1 ? cand[0] : -1;
        } else {
            for (idx c = 0; c < nc; ++c)
                if (cand[c] < n) low[cand[c]] = row_low(col, sigma, rlo, rhi, cand[c]);
            r = ratio_ties(T, P, pos, is_basic, start_basis, s0, n, pivot_tol, tie_tol, cc, low,
                           cand, keys, nc, art);
        }
        if (r < 0) {
            status = RAY_TERMINATION;
            for (idx i = 0; i < n; ++i) ray[basis[i]] = sigma * col[i];
            ray[e] = sigma;
            break;
        }
        low_r = r < n ? row_low(col, sigma, rlo, rhi, r) : low[n] != 0;
        double g = gaps[r];
        double step = (cc[r] < 0.0 && g > 0.0 && g < INF) ? g / -cc[r] : 0.0;
        double delta = sigma * step;
        for (idx i = 0; i < n; ++i) xb[i] += col[i] * delta;  // step_values, by row
        x[e] += delta;
    }
    for (idx i = 0; i < n; ++i) x[basis[i]] = xb[i];
    pivots_out = pivots;
    return status;
}

// T's rows: R M C, zeros in z0's column and the padding (to T.ld); compiled per instruction
// set (the n^2 products of every cold box solve).
LEMKE_CLONES
void scaled_rows(Mat<const double> M, const double* R, const double* C, Mat<double> T) {
    idx n = M.rows;
    for (idx i = 0; i < n; ++i) {
        double r = R[i];
        const double* mrow = M.row(i);
        double* trow = T.row(i);
        for (idx j = 0; j < n; ++j) trow[j] = (mrow[j] * r) * C[j];
        for (idx j = n; j < T.ld; ++j) trow[j] = 0.0;
    }
}

// qs = q + M z (the start point's w), two rows at a time (pair_rows: row_dot_and_size's
// bits); compiled per instruction set.
LEMKE_CLONES
void shifted_q(Mat<const double> M, const double* q, const double* z, double* qs) {
    idx n = M.rows;
    double mz[2], size[2];
    for (idx i = 0; i < n; i += 2) {
        pair_rows(M, z, i, mz, size);
        qs[i] = q[i] + mz[0];
        if (i + 1 < n) qs[i + 1] = q[i + 1] + mz[1];
    }
}

}  // namespace

BoxedWork& thread_work() { return work(); }

// Compiled per instruction set: all_finite's eight running sums on vectors (every box solve
// reads M once here).
LEMKE_CLONES
int prologue(Mat<const double> M, const double* q, const double* lo, const double* hi) {
    idx n = M.rows;
    bool finite = all_finite(q, n);  // (M's largest entry is not needed here: not computed)
    if (M.ld == n && n < 32) {
        // its rows end to end in one pass (below 32 rows: all_finite's eight sums are one
        // chain of n^2 / 8 additions, which row by row calls overlap)
        finite = finite && all_finite(M.p, n * n);
    } else {
        for (idx i = 0; i < n && finite; ++i) finite = all_finite(M.row(i), n);
    }
    if (!finite) return NOT_FINITE;
    for (idx i = 0; i < n; ++i) {
        if (!(lo[i] <= hi[i])) return (lo[i] != lo[i] || hi[i] != hi[i]) ? NOT_FINITE : BAD_BOUNDS;
        if (lo[i] == INF || hi[i] == -INF) return BAD_BOUNDS;
    }
    return 0;
}

bool basis_point(Mat<const double> M, const double* q, const double* lo, const double* hi,
                 const std::uint8_t* zb, const std::uint8_t* zh, bool warm_rule, double* z,
                 KeptMatrix* kept) {
    // (the seam's BoxBasis, basis.hpp; the work as before: n * n + 3 n doubles, n indices)
    idx n = M.rows;
    BoxedWork& W = work();
    double* area = W.check_area(n * n + 3 * n);
    idx* index = W.check_indices(n);
    return BoxBasis(M, q, lo, hi, index, area, nullptr, kept).point(zb, zh, warm_rule, z);
}

namespace {
// friction_point with the thread's work given (front looks it up once for this and the
// check after it): the seam's FrictionBasis (basis.hpp) on the work as before (n * n + 3 n
// doubles, 3 n indices, n flags)
bool friction_point_in(Mat<const double> M, const double* q, const double* lo,
                       const double* hi, const idx* F, idx nf, const std::uint8_t* zb,
                       const std::uint8_t* zh, double* z, BoxedWork& W) {
    idx n = M.rows;
    double* area = W.check_area(FrictionBasis::work_size(n));
    idx* ints = W.check_indices(FrictionBasis::index_size(n));
    std::uint8_t* kind = W.check_flags(n);
    return FrictionBasis(M, q, lo, hi, F, nf, area, ints, kind).point(zb, zh, z);
}
}  // namespace

bool friction_point(Mat<const double> M, const double* q, const double* lo, const double* hi,
                    const idx* F, idx nf, const std::uint8_t* zb, const std::uint8_t* zh,
                    double* z) {
    return friction_point_in(M, q, lo, hi, F, nf, zb, zh, z, work());
}

namespace {

// extend's F (the friction rows, then their normal rows) and its right-hand side and
// bounds (qx, lox, hix); the rows of Mx are ext_row's.
// extend's F: the friction rows in order, then their normal rows.
void friction_order(const idx* findex, idx n, idx nf, idx* F) {
    idx c = 0;
    for (idx i = 0; i < n; ++i) {
        if (findex[i] >= 0) {
            F[c] = i;
            F[nf + c] = findex[i];
            ++c;
        }
    }
}

void extend_vectors(const double* q, const double* lo, const double* hi, const idx* findex,
                    idx n, idx nf, double* qx, double* lox, double* hix, idx* F) {
    friction_order(findex, n, nf, F);
    for (idx i = 0; i < n; ++i) {
        qx[i] = q[i];
        lox[i] = lo[i];
        hix[i] = hi[i];
    }
    for (idx cc = 0; cc < nf; ++cc) {
        idx i = F[cc];
        idx lam = n + nf + cc;
        qx[n + cc] = -q[i];
        qx[lam] = 0.0;
        lox[n + cc] = 0.0;
        lox[lam] = 0.0;
        hix[n + cc] = INF;
        hix[lam] = INF;
        lox[i] = 0.0;
        hix[i] = INF;
    }
}

// Row r of the extended matrix Mx (N = n + 2 nf entries) into out: the caller's row r
// (r < n: M's row with each friction column doubled, -, and 1 at λ for a friction row),
// β-'s row (-the friction row, its friction columns +, 1 at λ), λ's row (mu at the
// normal, -1 at β+ and β-). `fric`: the rank of each row among the friction rows, -1.
void ext_row(Mat<const double> M, const double* hi, const idx* F, const idx* fric, idx nf,
             idx r, double* out) {
    idx n = M.rows;
    idx N = n + 2 * nf;
    for (idx j = 0; j < N; ++j) out[j] = 0.0;
    if (r < n) {
        const double* row = M.row(r);
        for (idx j = 0; j < n; ++j) out[j] = row[j];
        for (idx cc = 0; cc < nf; ++cc) out[n + cc] = -row[F[cc]];
        if (fric[r] >= 0) out[n + nf + fric[r]] = 1.0;
    } else if (r < n + nf) {
        idx cc = r - n;
        const double* row = M.row(F[cc]);
        for (idx j = 0; j < n; ++j) out[j] = -row[j];
        for (idx d = 0; d < nf; ++d) out[n + d] = row[F[d]];
        out[n + nf + cc] = 1.0;
    } else {
        idx cc = r - n - nf;
        idx i = F[cc];
        out[F[nf + cc]] = hi[i];
        out[i] = -1.0;
        out[n + cc] = -1.0;
    }
}

// extend with only the rows of Mx that `need` flags (the others left as they were).
void extend_rows(Mat<const double> M, const double* q, const double* lo, const double* hi,
                 const idx* findex, idx nf, double* work_out, idx* F, const std::uint8_t* need) {
    idx n = M.rows;
    FrontLayout L{n, nf, true};
    idx N = L.N();
    double* Mx = work_out + L.work_M();
    extend_vectors(q, lo, hi, findex, n, nf, work_out + L.work_q(), work_out + L.work_lo(),
                   work_out + L.work_hi(), F);
    idx* fric = work().check_indices(n);
    for (idx i = 0; i < n; ++i) fric[i] = -1;
    for (idx cc = 0; cc < nf; ++cc) fric[F[cc]] = cc;
    for (idx r = 0; r < N; ++r)
        if (need == nullptr || need[r]) ext_row(M, hi, F, fric, nf, r, Mx + r * N);
}

}  // namespace

void extend(Mat<const double> M, const double* q, const double* lo, const double* hi,
            const idx* findex, idx nf, double* work_out, idx* F) {
    reductions::FrictionBox{M, q, lo, hi, findex, nf}.apply(work_out, F);
}

SolveResult solve(Mat<const double> M, const double* q, const double* lo, const double* hi,
                  const std::uint8_t* warm, int cov_mode, idx max_pivots, double pivot_tol,
                  double tie_tol, double tol, double* buf, idx* final, bool checked) {
    idx n = M.rows;
    BoxLayout L{n};
    double *z = buf + L.z(), *w = buf + L.w(), *d = buf + L.covering();
    double *Rs = buf + L.row_scale(), *Cs = buf + L.col_scale(), *ray = buf + L.ray();
    const std::uint8_t* warm_basic = warm;
    const std::uint8_t* warm_hi = warm + n;
    SolveResult out;
    // (`checked`: extend's problem, made of data front's prologue passed: M's entries,
    // their negations, +-1 and the finite mu; q's negated; bounds 0, INF or the caller's)
    int code = checked ? 0 : prologue(M, q, lo, hi);
    if (code < 0) {
        out.code = code;
        return out;
    }
    BoxedWork& W = work();
    W.layout(n);
    std::fill(W.flags.begin(), W.flags.begin() + W.flags_length(), std::uint8_t(0));
    std::uint8_t *z_basic = W.z_basic(), *z_hi = W.z_hi(), *is_basic = W.is_basic();
    std::uint8_t* want = W.want();
    double *qs = W.qs(), *los = W.los(), *his = W.his(), *s0 = W.s0(), *z0s = W.z0s();
    double *x = W.x(), *ray_lab = W.ray_lab();
    Mat<double> T = W.T();
    bool cold = true;
    for (idx i = 0; i < n; ++i) {
        z_hi[i] = warm_hi[i];
        cold = cold && !(warm_hi[i] || warm_basic[i]);
    }
    // the set-up's loops over the rows, each row's steps in one pass where no row reads
    // another's (the same operations; at n = 12 the set-up's many short loops were a sixth
    // of a solve)
    bool shift = false;  // (nonzero(z0s, n))
    for (idx i = 0; i < n; ++i) {
        start_point(lo, hi, z_hi, q, cold, i, z0s);
        z_hi[i] = ((z_hi[i] && hi[i] < INF) || (lo[i] == -INF && hi[i] < INF)) &&
                  !(cold && far_both(lo, hi, i));
        qs[i] = q[i];
        shift = shift || z0s[i] != 0.0;
    }
    if (shift) shifted_q(M, q, z0s, qs);
    if (cold && trivial_start(lo, hi, z_hi, qs, n)) {
        for (idx i = 0; i < n; ++i) {  // every w has its sign already: the start solves it
            z[i] = z0s[i];
            d[i] = 0.0;
            z_basic[i] = 0;
        }
        for (idx i = 0; i < n + 1; ++i) ray[i] = 0.0;
        equilibrate(M, qs, Rs, Cs, W.eq_work());
        double residual;
        bool ok = box_check(M, q, lo, hi, z, tol, w, Rs, 0, residual);
        idx k = 0;
        for (idx i = 0; i < n; ++i)
            if (z_hi[i]) final[k++] = i;
        out.code = ok ? SOLVED : NUMERICAL_FAILURE;
        out.pivots = 0;
        out.z0 = 0.0;
        out.ok = ok;
        out.residual = residual;
        out.k = 0;
        out.m = k;
        return out;
    }
    equilibrate(M, qs, Rs, Cs, W.eq_work());
    // The tableau [R M C | cov] and the values (scaled): w = R (M z + q), z' = z / C; the
    // complementary basis of the w's; the z's wanted basic; rmax; d and ray_lab zeroed.
    scaled_rows(M, Rs, Cs, T);
    idx *basis = W.basis(), *nonbasic = W.nonbasic(), *pos = W.pos();
    bool any_want = false;
    double rmax = 0.0;
    for (idx i = 0; i < n; ++i) {
        double r = Rs[i];
        x[i] = qs[i] * r;
        double c = Cs[i], rc;  // C's entries are powers of two (equilibrate): no division
        if (pow2_reciprocal(c, rc)) {
            x[n + i] = z0s[i] * rc;
            los[i] = lo[i] * rc;
            his[i] = hi[i] * rc;
        } else {
            x[n + i] = z0s[i] / c;
            los[i] = lo[i] / c;
            his[i] = hi[i] / c;
        }
        basis[i] = i;
        nonbasic[i] = n + i;
        pos[i] = i;
        pos[n + i] = i;
        is_basic[i] = 1;
        std::uint8_t wi = warm_basic[i];
        if (far_both(lo, hi, i) && (cold || (lo[i] == -INF && hi[i] == INF))) {
            wi = 1;
        } else if (lo[i] == hi[i]) {
            wi = 0;
        }
        want[i] = wi;
        any_want = any_want || wi;
        rmax = pmax(rmax, r);
        d[i] = 0.0;
        ray_lab[i] = 0.0;
        ray_lab[n + i] = 0.0;
    }
    x[2 * n] = 0.0;
    ray_lab[2 * n] = 0.0;
    nonbasic[n] = 2 * n;
    pos[2 * n] = n;
    Run run(W);
    // (with no z wanted basic, exchange and the check below find nothing to do)
    idx pivots = any_want ? exchange(run, want) : 0;
    bool singular = false;
    bool partial = (cov_mode & PARTIAL) != 0;
    int mode = cov_mode & ~PARTIAL;
    for (idx i = 0; i < n && any_want; ++i) {
        if (want[i] && !is_basic[n + i]) {
            if (far_both(lo, hi, i) && (cold || (lo[i] == -INF && hi[i] == INF))) {
                z_hi[i] = 0;  // a free z left non-basic: it rests at 0 as if at a lower bound
            } else if (!partial) {
                singular = true;
            }  // (PARTIAL: it stays non-basic at the bound of its start, and Lemke goes on)
        }
    }
    if (singular) {
        // The warm basis cannot be made basic: report the start point, nothing else.
        for (idx i = 0; i < n + 1; ++i) ray[i] = 0.0;
        for (idx i = 0; i < n; ++i) d[i] = 0.0;
        for (idx i = 0; i < n; ++i) z[i] = z0s[i];
        double residual;
        bool ok = box_check(M, q, lo, hi, z, tol, w, Rs, 0, residual);
        out.code = ok ? SOLVED : SINGULAR;
        out.pivots = 0;
        out.z0 = 0.0;
        out.ok = ok;
        out.residual = residual;
        out.k = 0;
        out.m = 0;
        return out;
    }
    // The covering column, set in the current basis (each row's s0 and d too).
    bool infeasible = false;
    for (idx i = 0; i < n; ++i) {
        idx b = basis[i];
        double lb, ub;
        bounds_of(b, n, los, his, z_hi, lb, ub);
        double v = x[b];
        double mag;
        if (b < n) {
            mag = mode == 0 ? div_exact(Rs[b], rmax) : 1.0;  // (powers of two)
        } else {
            mag = 1.0;
        }
        if (mode == 2) mag *= 1.0 + unit_random(label_key(i));
        double sgn = 0.0;
        if (v < lb) {
            sgn = 1.0;
        } else if (v > ub) {
            sgn = -1.0;
        } else if (b < n && lb == 0.0) {
            sgn = 1.0;
        } else if (b < n && ub == 0.0) {
            sgn = -1.0;
        }
        if (v < lb || v > ub) infeasible = true;
        T(i, n) = sgn * mag;
        s0[i] = sgn < 0.0 ? -1.0 : 1.0;
        if (b < n) d[b] = div_exact(T(i, n), Rs[b]);
    }
    code = SOLVED;
    double z0 = 0.0;
    if (infeasible) {
        idx p = 0;
        code = lemke_run(W, run, los, his, z_hi, s0, max_pivots - pivots, pivot_tol, tie_tol,
                         ray_lab, p);
        pivots += p;
        z0 = x[2 * n];
    }
    // Back to the caller's units; the final basis: the basic z's, then the non-basic z's at hi.
    idx k = 0;
    for (idx i = 0; i < n; ++i) {
        z[i] = pmin(pmax(x[n + i] * Cs[i], lo[i]), hi[i]);
        ray[i] = ray_lab[n + i] * Cs[i];
        z_basic[i] = is_basic[n + i];
        if (z_basic[i]) {
            z_hi[i] = 0;
            final[k++] = i;
        }
    }
    ray[n] = ray_lab[2 * n];
    if (code != SOLVED)
        for (idx i = 0; i < n; ++i) z[i] = x[n + i] * Cs[i];  // where it stopped, unclamped
    double residual;
    bool ok = box_check(M, q, lo, hi, z, tol, w, Rs, 0, residual);
    if (ok) code = SOLVED;
    idx m = k;
    for (idx i = 0; i < n; ++i)
        if (z_hi[i]) final[m++] = i;
    out.code = code;
    out.pivots = pivots;
    out.z0 = z0;
    out.ok = ok;
    out.residual = residual;
    out.k = k;
    out.m = m;
    return out;
}

namespace {

// Whether every friction row's normal impulse z_f lies in its box (so that the friction
// rows' bounds in force are those of the z returned).
bool normals_inside(const double* z, const double* lo, const double* hi, const idx* F, idx nf) {
    bool inside = true;
    for (idx c = 0; c < nf; ++c) {
        idx f = F[nf + c];
        inside = inside && z[f] >= lo[f] && z[f] <= hi[f];
    }
    return inside;
}

}  // namespace

int front(int phase, Mat<const double> M, const double* q, const double* lo, const double* hi,
          const idx* findex, idx findex_len, const std::uint8_t* warm, idx warm_len,
          bool has_warm, double tol, double* buf, idx buf_len, idx* ints, idx ints_len,
          double* work_in, idx work_len, double& residual) {
    idx n = M.rows;
    bool friction = findex_len > 0;
    idx nf = 0;
    residual = INF;
    if (phase == PREPARE) {
        int code = prologue(M, q, lo, hi);
        if (code < 0) return code;
        // In one pass: the friction index (-1, or the row of a normal whose own entry is
        // -1), the friction rows' bounds (-mu, mu; the normal's lo >= 0), their count
        for (idx i = 0; i < findex_len; ++i) {
            idx f = findex[i];
            if (f == -1) continue;
            if (f < 0 || f >= findex_len || f == i || findex[f] != -1) return BAD_FINDEX;
            if (!(hi[i] >= 0.0 && hi[i] < INF && lo[i] == -hi[i] && lo[f] >= 0.0))
                return BAD_FINDEX;
            ++nf;
        }
    } else {
        for (idx i = 0; i < findex_len; ++i) nf += findex[i] >= 0;
    }
    FrontLayout FL{n, nf, friction};
    idx N = FL.N();
    if (buf_len != FL.length() || ints_len != FL.ints_length() ||
        work_len != FL.work_length() || warm_len != 2 * N)
        return BAD_FINDEX;  // (the front sizes them: never)
    idx* F = ints + FL.friction_rows();
    if (phase != PREPARE) {
        // F was written by PREPARE; refuse what it could not have written.
        for (idx c = 0; c < 2 * nf; ++c)
            if (F[c] < 0 || F[c] >= n) return BAD_FINDEX;
    }
    double* z = buf + FL.run().z();
    // (the friction index's reduction: the extended problem and its map back)
    reductions::FrictionBox red{M, q, lo, hi, findex, nf};
    if (phase == PREPARE) {
        Mat<const double> A = M;
        const double *qa = q, *la = lo, *ha = hi;
        // With a warm start, only the rows of Mx that its point reads (the basic ones, and
        // the free z's) are made first; the whole of it when more is needed (the extended
        // check, a run).
        bool part = false;
        if (nf > 0 && has_warm) {
            // The basis's point on the caller's rows first (friction_point: a block of the
            // LCP's size, no extended matrix), judged by the check that decides 'solved' (on
            // the caller's rows, the coupled bounds at this point); when it passes with the
            // normals in their boxes, that is the answer (0 pivots). Otherwise the extended
            // problem's point decides as before (below).
            red.rows(F);
            BoxedWork& W = work();
            if (friction_point_in(M, q, lo, hi, F, nf, warm, warm + N, buf + FL.z(), W) &&
                normals_inside(buf + FL.z(), lo, hi, F, nf) &&
                coupled_check(M, q, lo, hi, F, nf, N, tol, buf, residual, W)) {
                double* d = buf + FL.run().covering();
                for (idx i = 0; i < N; ++i) d[i] = 0.0;
                return SOLVED;
            }
        }
        if (nf > 0) {
            std::uint8_t* need = nullptr;
            if (has_warm) {
                need = work().check_flags(N);
                for (idx r = 0; r < N; ++r)
                    need[r] = warm[r] || (r < n && findex[r] < 0 && lo[r] == -INF && hi[r] == INF);
                part = true;
            }
            red.apply(work_in, F, need);
            A = Mat<const double>(work_in + FL.work_M(), N, N);
            qa = work_in + FL.work_q();
            la = work_in + FL.work_lo();
            ha = work_in + FL.work_hi();
        }
        BoxLayout L = FL.run();
        double *w = buf + L.w(), *d = buf + L.covering(), *R = buf + L.row_scale();
        double* C = buf + L.col_scale();
        // No friction, warm: the check's scales first (into `scales`: R and C are written
        // only when the point is made, as before), through the kept matrices (M's sweeps'
        // records when M repeats bit for bit), and the basis's block by solve_gathered_kept
        // (the last block of M factored, when its rows repeat): the same scales and point.
        KeptMatrix* kept = nullptr;
        thread_local std::vector<double> scales;
        if (nf == 0 && has_warm) {
            scales.resize(static_cast<std::size_t>(2 * n));
            check_scales_kept(A, qa, la, ha, scales.data(), scales.data() + n, kept);
        }
        if (!has_warm || !basis_point(A, qa, la, ha, warm, warm + N, true, z, kept)) {
            if (part) red.apply(work_in, F);
            residual = INF;
            return NEED_RUN;
        }
        if (nf > 0) {
            // The check that decides 'solved' (on the caller's rows, the coupled bounds at
            // this point) first: when it passes and the point's normals lie in their boxes
            // (so that the friction rows' bounds in force are those of the z returned), the
            // extended problem's own check (a second equilibration, of N rows) is not made.
            // Otherwise that check decides first, as before: failed, a run from the basis
            // (NEED_RUN); passed, the caller's check's verdict (SOLVED, or UNDECIDED: the
            // general path).
            bool ok = red.check(F, z, tol, buf, residual);
            bool inside = normals_inside(z, lo, hi, F, nf);
            if (!(ok && inside)) {
                double ext_residual;
                red.apply(work_in, F);  // (every row, for the check)
                check_scales(A, qa, la, ha, R, C);
                if (!box_check(A, qa, la, ha, z, tol, w, R, 0, ext_residual)) {
                    residual = INF;
                    return NEED_RUN;
                }
            }
            for (idx i = 0; i < N; ++i) d[i] = 0.0;
            if (!ok) {
                residual = INF;
                return UNDECIDED;
            }
            return SOLVED;
        }
        std::copy(scales.begin(), scales.begin() + n, R);
        std::copy(scales.begin() + n, scales.begin() + 2 * n, C);
        bool ok = box_check(A, qa, la, ha, z, tol, w, R, 0, residual);
        if (!ok) {
            residual = INF;
            return NEED_RUN;
        }
        for (idx i = 0; i < N; ++i) d[i] = 0.0;
    }
    if (friction) {
        bool ok = red.check(F, z, tol, buf, residual);
        if (!ok) {
            residual = INF;
            return UNDECIDED;
        }
    }
    return SOLVED;
}

}  // namespace boxed

// ----------------------------------------------------------------------------- reductions.hpp's FrictionBox

namespace reductions {

void FrictionBox::rows(idx* F) const { boxed::friction_order(findex, n(), nf, F); }

void FrictionBox::apply(double* work, idx* F, const std::uint8_t* need) const {
    boxed::extend_rows(M, q, lo, hi, findex, nf, work, F, need);
}

void FrictionBox::recover(const idx* F, const double* zx, double* z) const {
    idx k = n();
    for (idx i = 0; i < k; ++i) z[i] = zx[i];
    for (idx c = 0; c < nf; ++c) z[F[c]] = zx[F[c]] - zx[k + c];
}

bool FrictionBox::check(const idx* F, const double* zx, double tol, double* buf,
                        double& residual) const {
    return boxed::friction_check(M, q, lo, hi, F, nf, zx, N(), tol, buf, residual);
}

}  // namespace reductions
}  // namespace lemke
