#include "unrevised.hpp"

#include <algorithm>
#include <cstdint>

#include "multiversion.hpp"
#include "tableau.hpp"

namespace lemke {

void UnrevisedWork::layout(idx size, idx block_max, idx a_cols) {
    n = size;
    kmax = block_max;
    acols = a_cols;
    ld = (kmax + 7) / 8 * 8;
    nv = (n + 8) / 8 * 8;  // (n + 1: rv, rc, ratios, keys have a row for z0)
    f.resize(static_cast<std::size_t>(7 + (n + kmax) * ld + 16 * nv + n * acols + n +
                                      4 * kmax + 1));
    auto at = reinterpret_cast<std::uintptr_t>(f.data());
    off = static_cast<idx>((64 - at % 64) % 64 / sizeof(double));
    i.resize(static_cast<std::size_t>(5 * n + 2 + kmax));
    flags.resize(static_cast<std::size_t>(n + 1));
}

namespace {

constexpr idx REFACTOR_EVERY = 200;
constexpr double RESIDUAL_TOL = 1e-12;
constexpr idx CHECK_EVERY = 8;         // pivots between two checks of the values (drift)
constexpr double UPDATE_PIVOT = 1e-13;  // an update's pivot at or below this: refactor

// G[r, :k] += a[r] x[:k] for every r < k (but those with a[r] == 0 when skip_zero)
// (unrevised.add_rows). Compiled per instruction set: with the row products, the update of
// G is a pivot's O(k^2) part. Four rows at a time share x's loads (each entry's operation
// is its own: the same bits).
LEMKE_CLONES
void add_rows(Mat<double> G, idx k, const double* a, const double* x, bool skip_zero) {
    idx rows[4];
    int nr = 0;
    for (idx r = 0; r < k; ++r) {
        if (a[r] == 0.0 && skip_zero) continue;
        rows[nr++] = r;
        if (nr < 4) continue;
        nr = 0;
        double f0 = a[rows[0]], f1 = a[rows[1]], f2 = a[rows[2]], f3 = a[rows[3]];
        // (four distinct rows of G, none of them x: no store reaches a load of another)
        double *__restrict g0 = G.row(rows[0]), *__restrict g1 = G.row(rows[1]),
                           *__restrict g2 = G.row(rows[2]), *__restrict g3 = G.row(rows[3]);
        for (idx c = 0; c < k; ++c) {
            double v = x[c];
            g0[c] += f0 * v;
            g1[c] += f1 * v;
            g2[c] += f2 * v;
            g3[c] += f3 * v;
        }
    }
    for (int t = 0; t < nr; ++t) {
        double f = a[rows[t]];
        double* g = G.row(rows[t]);
        for (idx c = 0; c < k; ++c) g[c] += f * x[c];
    }
}

// add_rows, then out[r] = dot_lanes(G.row(r), y, ky) for every r < k (the rows add_rows
// skips too; G.cols >= ky): the next direction's G y (matvec's numbers, as matvec would take
// them after the update) while the rows are in cache, eight rows a pass (dot_lanes8).
LEMKE_CLONES
void add_rows_dot(Mat<double> G, idx k, const double* a, const double* __restrict x,
                  bool skip_zero, const double* y, idx ky, double* out) {
    idx r = 0;
    for (; r < k; r += 8) {
        idx end = r + 8 < k ? r + 8 : k;
        for (idx t = r; t < end; ++t) {
            double f = a[t];
            if (f != 0.0 || !skip_zero) {
                double* g = G.row(t);
                for (idx c = 0; c < k; ++c) g[c] += f * x[c];
            }
        }
        if (end == r + 8) {
            const double* rows[8];
            for (int l = 0; l < 8; ++l) rows[l] = G.row(r + l);
            dot_lanes8(rows, y, ky, out + r);
        } else if (end >= r + 4) {
            const double* rows[4] = {G.row(r), G.row(r + 1), G.row(r + 2), G.row(r + 3)};
            dot_lanes4(rows, y, ky, out + r);
            for (idx t = r + 4; t < end; ++t) out[t] = dot_lanes(G.row(t), y, ky);
        } else {
            for (idx t = r; t < end; ++t) out[t] = dot_lanes(G.row(t), y, ky);
        }
    }
}

// out[:k] = x[:k] G[:k, :k], row by row of G (unrevised._row_times): out[c] gets the terms
// x[p] G[p, c] of the rows with x[p] != 0 in increasing p, four rows a pass (the same sums
// in the same order, out read and written once a pass instead of once a row).
LEMKE_CLONES
void row_times(const double* x, Mat<const double> G, idx k, double* __restrict out) {
    for (idx c = 0; c < k; ++c) out[c] = 0.0;
    idx rows[4];
    int nr = 0;
    for (idx p = 0; p < k; ++p) {
        if (x[p] == 0.0) continue;
        rows[nr++] = p;
        if (nr < 4) continue;
        nr = 0;
        double x0 = x[rows[0]], x1 = x[rows[1]], x2 = x[rows[2]], x3 = x[rows[3]];
        const double *g0 = G.row(rows[0]), *g1 = G.row(rows[1]), *g2 = G.row(rows[2]),
                     *g3 = G.row(rows[3]);
        for (idx c = 0; c < k; ++c) {
            double o = out[c];
            o += x0 * g0[c];
            o += x1 * g1[c];
            o += x2 * g2[c];
            o += x3 * g3[c];
            out[c] = o;
        }
    }
    for (int t = 0; t < nr; ++t) {
        double xp = x[rows[t]];
        const double* g = G.row(rows[t]);
        for (idx c = 0; c < k; ++c) out[c] += xp * g[c];
    }
}

// dwv[i] = base[i] + AB[i, :k] dz for the rows with a basic w (apos[i] < 0; base nullptr:
// 0 +), each by dot's sum (inlined: a call per row cost as much as a short row), eight rows
// at a time, then four (dot_lanes8 / dot_lanes4: dz's loads shared, each row's sums its
// own; eight rows' pairwise sums in one hsum8). The rows are listed
// first, without a branch (n = 300: a solve 5 % faster than with a branch per row on apos;
// n = 100: within the noise).
LEMKE_CLONES
void basic_w_rows(Mat<const double> AB, const double* dz, idx k, const idx* apos,
                  const double* base, double* dwv) {
    constexpr idx CHUNK = 256;
    idx rows[CHUNK];
    const double* ptr[8];
    double d[8];
    idx n = AB.rows, i = 0;
    while (i < n) {
        idx nr = 0;
        for (; i < n && nr < CHUNK; ++i) {
            rows[nr] = i;
            nr += apos[i] < 0 ? 1 : 0;
        }
        idx t = 0;
        for (; t + 8 <= nr; t += 8) {
            for (int l = 0; l < 8; ++l) ptr[l] = AB.row(rows[t + l]);
            dot_lanes8(ptr, dz, k, d);
            for (int l = 0; l < 8; ++l) {
                idx r = rows[t + l];
                dwv[r] = base ? base[r] + d[l] : d[l];
            }
        }
        for (; t + 4 <= nr; t += 4) {
            for (int l = 0; l < 4; ++l) ptr[l] = AB.row(rows[t + l]);
            dot_lanes4(ptr, dz, k, d);
            for (int l = 0; l < 4; ++l) {
                idx r = rows[t + l];
                dwv[r] = base ? base[r] + d[l] : d[l];
            }
        }
        for (; t < nr; ++t) {
            idx r = rows[t];
            double dt = dot_lanes(AB.row(r), dz, k);
            dwv[r] = base ? base[r] + dt : dt;
        }
    }
}

// The pivot loop's steps are inlined into unrevised_lemke's instruction-set variants (a
// copy of their own would be compiled for the baseline instruction set only).
#if defined(__GNUC__)
#define LEMKE_STEP inline __attribute__((always_inline))
#else
#define LEMKE_STEP inline
#endif

// One run's state: views of the workspace and the sizes (one run's locals).
struct Run {
    idx n, kmax, k = 0;
    ColumnSource src;
    const double* q;
    const std::uint8_t* z_start;
    Mat<double> AB, G;
    double *zb, *wv, *dzb, *dw, *lz, *lw, *tmp, *tmp2, *row, *keys, *rv, *rc, *acol, *lcol,
        *coef, *ratios, *inv_work;
    double z0_max = 0.0;
    idx *alist, *blist, *apos, *bpos, *cand, *piv;

    Run(UnrevisedWork& w, const ColumnSource& s)
        : n(w.n), kmax(w.kmax), src(s), q(w.qs()), z_start(w.z_start()), AB(w.AB()), G(w.G()) {
        double** v[] = {&zb, &wv, &dzb, &dw, &lz, &lw, &tmp, &tmp2, &row, &keys, &rv, &rc,
                        &acol, &lcol, &coef, &ratios};
        for (idx j = 0; j < 16; ++j) *v[j] = w.vec(j);
        inv_work = w.inv_work();
        alist = w.alist();
        blist = w.blist();
        apos = w.apos();
        bpos = w.bpos();
        cand = w.cand();
        piv = w.piv();
    }

    // out = column e of A (e = n: the covering column). The one place that reads A: the
    // dense A, or with Fs, d (e = n) or the column Fs Fs[e]' of M (unrevised.fetch_column).
    LEMKE_STEP void fetch_column(idx e, double* out) const {
        if (src.Fs.rows == 0 && src.Ms.rows == 0) {
            for (idx i = 0; i < n; ++i) out[i] = src.A(i, e);
        } else if (e == n) {
            for (idx i = 0; i < n; ++i) out[i] = src.A(i, 0);
        } else if (src.Ms.rows > 0) {
            const double* me = src.Ms.row(e);
            for (idx i = 0; i < n; ++i) out[i] = me[i];
        } else {
            idx r = src.Fs.cols;
            const double* fe = src.Fs.row(e);
            for (idx i = 0; i < n; ++i) out[i] = dot(src.Fs.row(i), fe, r);
        }
    }

    LEMKE_STEP void set_column(idx j, const double* col) const {
        for (idx r = 0; r < n; ++r) AB(r, j) = col[r];
    }

    // G[:k, :k] = H^-1, H = AB[alist[:k], :k].
    bool invert() const {
        for (idx r = 0; r < k; ++r) {
            const double* s = AB.row(alist[r]);
            double* g = G.row(r);
            for (idx c = 0; c < k; ++c) g[c] = s[c];
        }
        return invert_in_place(G, k, inv_work, piv);
    }

    // wv = q + AB[:, :k] zb; the residual over alpha, row-wise relative (unrevised._all_w).
    LEMKE_STEP double all_w() const {
        double res = 0.0;
        for (idx i = 0; i < n; ++i) {
            double mz, size;
            dot_and_size_lanes(AB.row(i), zb, k, mz, size);
            double w = q[i] + mz;
            wv[i] = w;
            if (apos[i] >= 0) {
                size += std::fabs(q[i]);
                if (std::fabs(w) > res * size) res = std::fabs(w) / size;
            }
        }
        return res;
    }

    // zb = -G q_alpha, every wv; one refinement when the residual is above RESIDUAL_TOL.
    LEMKE_STEP double basic_point() const {
        for (idx r = 0; r < k; ++r) tmp[r] = -q[alist[r]];
        matvec(G, k, tmp, zb);  // (each row by dot's sums)
        double res = all_w();
        if (res > RESIDUAL_TOL) {
            for (idx r = 0; r < k; ++r) tmp[r] = wv[alist[r]];
            matvec(G, k, tmp, tmp2);
            for (idx c = 0; c < k; ++c) zb[c] -= tmp2[c];
            res = all_w();
        }
        return res;
    }

    LEMKE_STEP void advance(double t) const {
        for (idx p = 0; p < k; ++p) zb[p] += t * dzb[p];
        // (a select, not a branch: a non-basic w's dw is stale and never kept)
        for (idx i = 0; i < n; ++i) {
            double v = wv[i], moved = v + t * dw[i];
            wv[i] = apos[i] < 0 ? moved : v;
        }
    }

    LEMKE_STEP void place(double t, idx entering) const {
        if (entering >= n) zb[bpos[entering - n]] = t;
        else wv[entering] = t;
    }

    // How far the values are from the basis's, row by row relative (unrevised.drift).
    LEMKE_STEP double drift() const {
        double res = 0.0;
        for (idx i = 0; i < n; ++i) {
            double mz, size;
            dot_and_size_lanes(AB.row(i), zb, k, mz, size);
            size += std::fabs(q[i]);
            double w = q[i] + mz - (apos[i] < 0 ? wv[i] : 0.0);
            if (std::fabs(w) > res * size) res = std::fabs(w) / size;
        }
        return res;
    }

    // The change of every basic variable per unit of the non-basic `label`: dz (k, beta
    // order), dwv (n, at the basic w's). col: label's column of A when it is a z (or z0).
    LEMKE_STEP void direction(const double* col, idx label, double* dz, double* dwv) const {
        if (label < n) {  // a w leaves zero: H dz = e_p
            idx p = apos[label];
            for (idx r = 0; r < k; ++r) dz[r] = G(r, p);
            basic_w_rows(AB, dz, k, apos, nullptr, dwv);
        } else {  // a z (or z0) enters: H dz = -A[alpha, e]
            for (idx r = 0; r < k; ++r) tmp[r] = -col[alist[r]];
            matvec(G, k, tmp, dz);
            basic_w_rows(AB, dz, k, apos, col, dwv);
        }
    }

    // Row i of the ratio test is pair i's basic variable (row n: z0), its value in rv and
    // its change in rc; the one pair with neither basic gets 0 and 0 there, a row that never
    // blocks (rc = 0 is neither below the ratio test's threshold nor above 0 for first_row),
    // so the rows that can block are the basic variables in pair order. The basic w's first
    // (a select per row, a vector loop), then the basic z's written over their pairs from
    // beta's list (a z before its w, as the select per pair on which is basic had it): the
    // same values without that select's unpredictable branches (GCC made them branches).
    LEMKE_STEP void pairs() const {
        for (idx i = 0; i < n; ++i) {
            bool basic = apos[i] < 0;
            rv[i] = basic ? wv[i] : 0.0;
            rc[i] = basic ? dw[i] : 0.0;
        }
        rv[n] = 0.0;
        rc[n] = 0.0;
        for (idx p = 0; p < k; ++p) {
            idx b = blist[p];
            rv[b] = zb[p];
            rc[b] = dzb[p];
        }
    }

    // The basic variable of ratio-test row i.
    LEMKE_STEP idx label(idx i) const { return i == n ? 2 * n : bpos[i] >= 0 ? n + i : i; }

    // The leaving variable's row of the ratio test (pairs), -1 when nothing blocks.
    LEMKE_STEP idx ratio_test(double pivot_tol, double tie_tol) {
        idx m = n + 1;
        idx r_art = bpos[n] >= 0 ? n : -1;
        if (r_art >= 0) z0_max = pmax(z0_max, rv[r_art]);
        double cmax = absmax(rc, m);  // (the scalar pmax's answer: NaNs never win either)
        // the ratio test's vector passes pay from some 64 rows, as in tableau_lemke
        idx nc = blocking_rows(rv, rv, rc, m, -pivot_tol * cmax, tie_tol, cand, r_art, z0_max,
                               m >= 64 ? ratios : nullptr);
        if (nc <= 1) return nc == 1 ? cand[0] : -1;
        for (idx c = 0; c < nc; ++c)
            if (cand[c] == r_art) return cand[c];
        // Column j of the basis inverse relative to the starting basis: the unit vector of
        // its pair-j variable when that is basic, else minus its direction.
        for (idx j = 0; j < n; ++j) {
            bool zs = z_start[j] != 0;
            idx lab = zs ? n + j : j;
            bool basic = zs ? bpos[j] >= 0 : apos[j] < 0;
            if (!basic) {
                if (lab >= n) fetch_column(lab - n, lcol);
                direction(lcol, lab, lz, lw);
            }
            for (idx c = 0; c < nc; ++c) {
                idx cl = label(cand[c]);
                double b;
                if (basic) b = cl == lab ? 1.0 : 0.0;
                else b = -(cl >= n ? lz[bpos[cl - n]] : lw[cl]);
                keys[c] = lex_key(b, rc[cand[c]], pivot_tol);
            }
            nc = keep_lowest(cand, keys, nc, tie_tol);
            if (nc == 1) return cand[0];
        }
        return nc > 0 ? largest_pivot(cand, rc, nc) : -1;
    }

    // The index sets, AB and G for `entering` replacing `leaving` (one of four cases);
    // false when the update's pivot is too small to trust. Changes k where H grows or shrinks
    // after the update (the caller's k += 1 / k -= 1). When a w leaves, the next entering
    // variable is its z: its column goes to acol and its direction's G-part (matvec's
    // G tmp) to dzb, taken with the update of G's rows (add_rows_dot), and `ready` is set.
    LEMKE_STEP bool update_basis(idx entering, idx leaving, bool& ready) {
        if (entering >= n && leaving < n) {
            // z_e enters, w_i leaves: H gains row i and column e.
            idx e = entering - n, i = leaving;
            double s = dw[i];
            row_times(AB.row(i), G, k, row);
            for (idx p = 0; p < k; ++p) {
                coef[p] = -dzb[p] / s;
                G(p, k) = dzb[p] / s;
            }
            // z_i enters next: -A[alpha, i] over the new alpha (alpha, then i)
            fetch_column(i, lcol);
            for (idx r = 0; r < k; ++r) tmp[r] = -lcol[alist[r]];
            tmp[k] = -lcol[i];
            add_rows_dot(G, k, coef, row, false, tmp, k + 1, dzb);
            for (idx c = 0; c < k; ++c) G(k, c) = -row[c] / s;
            G(k, k) = 1.0 / s;
            dzb[k] = dot_lanes(G.row(k), tmp, k + 1);
            alist[k] = i;
            apos[i] = k;
            blist[k] = e;
            bpos[e] = k;
            set_column(k, acol);
            std::swap(acol, lcol);
            ready = true;
            return std::fabs(s) > UPDATE_PIVOT;
        }
        if (entering >= n) {
            // z_e replaces z_l as column p of H (Sherman-Morrison).
            idx e = entering - n, l = leaving - n;
            idx p = bpos[l];
            double pv = -dzb[p];
            for (idx c = 0; c < k; ++c) row[c] = G(p, c) / pv;
            for (idx r = 0; r < k; ++r) coef[r] = dzb[r] + (r == p ? 1.0 : 0.0);
            add_rows(G, k, coef, row, true);
            blist[p] = e;
            bpos[l] = -1;
            bpos[e] = p;
            set_column(p, acol);
            return std::fabs(pv) > UPDATE_PIVOT;
        }
        if (leaving < n) {
            // w_j enters, w_i leaves: row p of H becomes A[i, beta].
            idx j = entering, i = leaving;
            idx p = apos[j];
            row_times(AB.row(i), G, k, row);
            double pv = row[p];
            row[p] -= 1.0;
            for (idx r = 0; r < k; ++r) coef[r] = -(dzb[r] / pv);
            // z_i enters next: -A[alpha, i] over the new alpha (i in place p)
            fetch_column(i, lcol);
            for (idx r = 0; r < k; ++r) tmp[r] = -lcol[r == p ? i : alist[r]];
            add_rows_dot(G, k, coef, row, true, tmp, k, dzb);
            alist[p] = i;
            apos[j] = -1;
            apos[i] = p;
            std::swap(acol, lcol);
            ready = true;
            return std::fabs(pv) > UPDATE_PIVOT;
        }
        // w_j enters, z_l leaves: H loses row p and column m; the last row and column move
        // into the freed slots.
        idx j = entering, l = leaving - n;
        idx p = apos[j], m = bpos[l];
        double pv = G(m, p);
        for (idx r = 0; r < k; ++r) coef[r] = r != m ? -(G(r, p) / pv) : 0.0;
        for (idx c = 0; c < k; ++c) row[c] = G(m, c);
        add_rows(G, k, coef, row, true);
        idx last = k - 1;
        for (idx c = 0; c < k; ++c) G(m, c) = G(last, c);
        for (idx r = 0; r < last; ++r) G(r, p) = G(r, last);
        for (idx r = 0; r < n; ++r) AB(r, m) = AB(r, last);
        zb[m] = zb[last];
        idx bl = blist[last];
        blist[m] = bl;
        bpos[bl] = m;
        bpos[l] = -1;
        idx al = alist[last];
        alist[p] = al;
        apos[al] = p;
        apos[j] = -1;
        return std::fabs(pv) > UPDATE_PIVOT;
    }
};

}  // namespace

LEMKE_CLONES
Status unrevised_lemke(UnrevisedWork& w, const ColumnSource& src, idx max_pivots,
                       double pivot_tol, double tie_tol, double* x_out, double* ray_out,
                       std::uint8_t* z_basic_out, idx& pivots) {
    Run u(w, src);
    idx n = u.n;
    idx art = 2 * n;
    for (idx i = 0; i < n; ++i) u.apos[i] = -1;
    for (idx i = 0; i < n + 1; ++i) u.bpos[i] = -1;
    for (idx i = 0; i < n; ++i) {
        if (u.z_start[i]) {
            idx k = u.k;
            u.alist[k] = i;
            u.blist[k] = i;
            u.apos[i] = k;
            u.bpos[i] = k;
            u.fetch_column(i, u.acol);
            u.set_column(k, u.acol);
            u.k = k + 1;
        }
    }
    for (idx i = 0; i < n + 1; ++i) ray_out[i] = 0.0;
    for (idx i = 0; i < n + 1; ++i) x_out[i] = 0.0;

    Status status = MAX_PIVOTS;
    pivots = 0;
    if (u.k > 0 && !u.invert()) {  // (k == 0: an empty G0, nothing to invert)
        status = NUMERICAL_FAILURE;
        max_pivots = 0;
    }
    u.basic_point();
    idx since_refactor = 0, since_check = 0;
    idx entering = art;
    std::uint64_t h = 0;
    for (idx i = 0; i < n; ++i) h ^= label_key(u.bpos[i] >= 0 ? n + i : i);
    Detector detector;
    Poll poll;
    bool ready = false;
    std::int64_t work = n * (n + 1);
    while (pivots < max_pivots) {
        if (int stop = poll.tick(work); stop >= 0) {
            status = static_cast<Status>(stop);
            break;
        }
        if (ready) {  // (update_basis took G's part; entering is a z)
            basic_w_rows(u.AB, u.dzb, u.k, u.apos, u.acol, u.dw);
        } else {
            if (entering >= n) u.fetch_column(entering - n, u.acol);
            u.direction(u.acol, entering, u.dzb, u.dw);
        }
        ready = false;
        u.pairs();
        idx r, leaving;
        if (pivots == 0) {
            // z0 rises until every basic variable is >= 0.
            r = first_row(u.rv, u.rc, n + 1, tie_tol);
            if (r < 0) {
                status = NUMERICAL_FAILURE;
                break;
            }
            leaving = u.label(r);
        } else {
            r = u.ratio_test(pivot_tol, tie_tol);
            leaving = r >= 0 ? u.label(r) : -1;
            if (leaving < 0) {
                status = RAY_TERMINATION;
                if (entering >= n) ray_out[entering - n] = 1.0;
                for (idx p = 0; p < u.k; ++p) ray_out[u.blist[p]] = u.dzb[p];
                break;
            }
        }
        double pv = leaving >= n ? u.dzb[u.bpos[leaving - n]] : u.dw[leaving];
        if (!(std::fabs(pv) < INF)) {  // a NaN or infinite pivot: give up
            status = NUMERICAL_FAILURE;
            break;
        }
        if (entering >= n && leaving < n && u.k >= u.kmax) {
            status = NUMERICAL_FAILURE;  // H would outgrow M's rank: rounding, not a pivot
            break;
        }
        double t = -u.rv[r] / u.rc[r];
        u.advance(t);
        bool ok = u.update_basis(entering, leaving, ready);
        if (entering >= n && leaving < n) u.k += 1;
        else if (entering < n && leaving >= n) u.k -= 1;
        u.place(t, entering);
        ++pivots;
        ++since_refactor;
        ++since_check;
        bool refresh = !ok || since_refactor >= REFACTOR_EVERY;
        if (!refresh && since_check >= CHECK_EVERY) {
            since_check = 0;
            refresh = u.drift() > RESIDUAL_TOL;
        }
        if (refresh) {
            if (int stop = poll.now(); stop >= 0) {  // (a refactorization is O(k^3))
                status = static_cast<Status>(stop);
                break;
            }
            since_refactor = 0;
            since_check = 0;
            ready = false;  // (G is recomputed)
            if (u.k > 0 && !u.invert()) {
                status = NUMERICAL_FAILURE;
                break;
            }
            u.basic_point();
        }
        int stop = after_pivot(leaving, entering, art, h, detector);
        if (stop >= 0) {
            status = static_cast<Status>(stop);
            break;
        }
        entering = leaving < n ? leaving + n : leaving - n;
    }
    if (status != NUMERICAL_FAILURE) u.basic_point();  // the point from the basis inverse
    for (idx p = 0; p < u.k; ++p) x_out[u.blist[p]] = u.zb[p];
    for (idx i = 0; i < n; ++i) z_basic_out[i] = u.bpos[i] >= 0 ? 1 : 0;
    return status;
}

Status unrevised_solve(Mat<const double> M, const double* q, const double* d, const double* R,
                       const double* C, const std::uint8_t* z_start, idx max_pivots,
                       double pivot_tol, double tie_tol, double* x_out, double* ray_out,
                       std::uint8_t* z_basic_out, idx& pivots) {
    thread_local UnrevisedWork w;
    idx n = M.rows;
    w.layout(n, n, n + 1);
    Mat<double> A = w.A();
    double d_scale = scaled_into(M, q, d, R, C, A, w.qs());
    std::uint8_t* zs = w.z_start();
    for (idx i = 0; i < n; ++i) zs[i] = z_start && z_start[i] ? 1 : 0;
    ColumnSource src{A, Mat<const double>(), Mat<const double>()};
    Status status = unrevised_lemke(w, src, max_pivots, pivot_tol, tie_tol, x_out, ray_out,
                                    z_basic_out, pivots);
    unscale(x_out, ray_out, C, 1.0 / d_scale, status == SOLVED, n);
    return status;
}

namespace {

// unrevised_lemke with A = d alone (n x 1), M's columns from Fs (M = Fs Fs') or Ms (M
// symmetric, in place), from the basis z_start (nullptr: all w basic), H at most kmax wide.
Status column_source_run(Mat<const double> Fs, Mat<const double> Ms, idx n, const double* d,
                         const double* q, const std::uint8_t* z_start, idx kmax,
                         idx max_pivots, double pivot_tol, double tie_tol, double* x_out,
                         double* ray_out, std::uint8_t* z_basic_out, idx& pivots) {
    thread_local UnrevisedWork w;
    w.layout(n, kmax, 1);
    Mat<double> A = w.A();
    double* qs = w.qs();
    std::uint8_t* zs = w.z_start();
    for (idx i = 0; i < n; ++i) {
        A(i, 0) = d[i];
        qs[i] = q[i];
        zs[i] = z_start && z_start[i] ? 1 : 0;
    }
    ColumnSource src{A, Fs, Ms};
    return unrevised_lemke(w, src, max_pivots, pivot_tol, tie_tol, x_out, ray_out, z_basic_out,
                           pivots);
}

}  // namespace

Status unrevised_factored(Mat<const double> Fs, const double* d, const double* q,
                          idx max_pivots, double pivot_tol, double tie_tol, double* x_out,
                          double* ray_out, std::uint8_t* z_basic_out, idx& pivots) {
    idx n = Fs.rows;
    return column_source_run(Fs, Mat<const double>(), n, d, q, nullptr,
                             std::min<idx>(n, Fs.cols + 1), max_pivots, pivot_tol, tie_tol,
                             x_out, ray_out, z_basic_out, pivots);
}

Status unrevised_symmetric(Mat<const double> M, const double* d, const double* q,
                           const std::uint8_t* z_start, idx kmax, idx max_pivots,
                           double pivot_tol, double tie_tol, double* x_out, double* ray_out,
                           std::uint8_t* z_basic_out, idx& pivots) {
    idx n = M.rows;
    return column_source_run(Mat<const double>(), M, n, d, q, z_start, std::min(n, kmax),
                             max_pivots, pivot_tol, tie_tol, x_out, ray_out, z_basic_out,
                             pivots);
}

}  // namespace lemke
