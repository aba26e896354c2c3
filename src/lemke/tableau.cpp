#include "tableau.hpp"

#include <cstdint>
#include <utility>

#include "multiversion.hpp"

namespace lemke {

void TableauWork::layout(idx size) {
    n = size;
    block = block_size(n);
    idx lanes = n < 48 ? 4 : 8;
    ld = (n + lanes) / lanes * lanes;
    nv = (n + 7) / 8 * 8;
    f.resize(static_cast<std::size_t>(7 + n * ld + 7 * nv + ld + nv * block + block * ld));
    auto at = reinterpret_cast<std::uintptr_t>(f.data());
    off = static_cast<idx>((64 - at % 64) % 64 / sizeof(double));
    i.resize(static_cast<std::size_t>(6 * n + 2));
    flags.resize(static_cast<std::size_t>(2 * n + 1));
}

// The pivot on row r and column s (entering column in col), applied at once; the same
// operations in the same order whatever the block, so the same bits. Compiled
// per instruction set (multiversion.hpp): the row updates are the solve's hot loop.
namespace {

// t[j] += f * v[j] for j < m (eight lanes at a time, then one by one).
LEMKE_ALWAYS_INLINE void axpy(double* t, double f, const double* v, idx m) {
    idx j = 0;
#ifdef LEMKE_SIMD
    simd::v8d vf = simd::splat8(f);
    for (; j + 8 <= m; j += 8) simd::store8(t + j, simd::load8(t + j) + vf * simd::load8(v + j));
    if (j + 4 <= m) {
        simd::v4d wf = simd::splat4(f);
        simd::store4(t + j, simd::load4(t + j) + wf * simd::load4(v + j));
        j += 4;
    }
#endif
    for (; j < m; ++j) t[j] += f * v[j];
}

// t[j] += f * v[j] over a row's m columns (axpy): the row updates' operation on a row.
struct RowAxpy {
    const double* v;
    idx m;
    LEMKE_ALWAYS_INLINE void operator()(double* t, double f) const { axpy(t, f, v, m); }
};

// The same on rows of exactly 4 Q doubles (T.ld <= 32: the small tableaux, whose pivots are
// applied at once): the pivot row's vectors held in registers for all the rows and each
// row's update unrolled (no loop over the row, no load of the pivot row per row; n = 24:
// a cold solve 3.45 -> 2.98 us with the splat8 fix). Each entry gets the same operation,
// t + f v, so the same bits as RowAxpy.
template <int Q>
struct RowAxpyFixed {
#ifdef LEMKE_SIMD
    static constexpr int H = Q / 2;  // whole eight-lane vectors, then four lanes when Q is odd
    simd::v8d pv[H > 0 ? H : 1];
    simd::v4d p4;
    LEMKE_ALWAYS_INLINE explicit RowAxpyFixed(const double* v) {
        for (int k = 0; k < H; ++k) pv[k] = simd::load8(v + 8 * k);
        p4 = Q % 2 == 1 ? simd::load4(v + 8 * H) : simd::splat4(0.0);
    }
    LEMKE_ALWAYS_INLINE void operator()(double* t, double f) const {
        simd::v8d vf = simd::splat8(f);
        for (int k = 0; k < H; ++k) simd::store8(t + 8 * k, simd::load8(t + 8 * k) + vf * pv[k]);
        if (Q % 2 == 1) {
            simd::v4d wf = simd::splat4(f);
            simd::store4(t + 8 * H, simd::load4(t + 8 * H) + wf * p4);
        }
    }
#else
    RowAxpy a;
    explicit RowAxpyFixed(const double* v) : a{v, 4 * Q} {}
    void operator()(double* t, double f) const { a(t, f); }
#endif
};

// The rows count of T from ti (stride ld) updated by the pivot row (row(t, f): t += f
// prow), their factors in col and their rhs, magb, col_next entries at the same offsets; a
// template per kept vector, so that the loop carries no test and few values (with more,
// GCC kept some on the stack, and a load from the stack each row waited on the row's
// stores whenever its address matched one of theirs modulo 4096, which depended on where
// the stack lay: the same solve took 2.9 or 4.9 us from one process to the next at n = 24).
template <bool RHS, bool MAGB, bool NEXT, class Row>
LEMKE_ALWAYS_INLINE void update_rows(double* ti, idx ld, idx count, const double* col, double* rhs,
                        double* magb, double* col_next, const double* prow, idx s, idx s_next,
                        double inv, double rr, double mr, const Row& row) {
    double pn = NEXT ? prow[s_next] : 0.0;
    for (idx c = 0; c < count; ++c, ti += ld) {
        double f = col[c];
        // col_next: the entry s_next after the update, computed before the row's vector
        // loop by that loop's operation (t + f v) rather than read back after its stores
        double next = NEXT ? ti[s_next] : 0.0;
        if (f != 0.0) {
            if (NEXT) next = next + f * pn;
            if (RHS) rhs[c] += f * rr;
            if (MAGB) magb[c] += std::fabs(f) * mr;
            row(ti, f);
            ti[s] = f * inv + f * 0.0;
        } else {
            ti[s] = f * inv;
        }
        if (NEXT) col_next[c] = next;
    }
}

template <bool RHS, bool MAGB, bool NEXT, class Row>
LEMKE_ALWAYS_INLINE void update_all(const Mat<double>& T, idx r, const double* col, double* rhs, double* magb,
                       double* col_next, const double* prow, idx s, idx s_next, double inv,
                       double rr, double mr, const Row& row) {
    update_rows<RHS, MAGB, NEXT>(T.row(0), T.ld, r, col, rhs, magb, col_next, prow, s,
                                 s_next, inv, rr, mr, row);
    idx r1 = r + 1;
    update_rows<RHS, MAGB, NEXT>(T.row(0) + r1 * T.ld, T.ld, T.rows - r1, col + r1,
                                 RHS ? rhs + r1 : rhs, MAGB ? magb + r1 : magb,
                                 NEXT ? col_next + r1 : col_next, prow, s, s_next, inv, rr, mr,
                                 row);
    if (NEXT) col_next[r] = prow[s_next];  // (row r is prow but for column s)
}

// update_all over T.ld columns: the fixed widths (RowAxpyFixed) where T.ld <= 32 is a
// multiple of 4 and magb is not kept, else RowAxpy.
template <bool RHS, bool MAGB, bool NEXT>
LEMKE_ALWAYS_INLINE void update_any(const Mat<double>& T, idx r, const double* col, double* rhs,
                                    double* magb, double* col_next, const double* prow, idx s,
                                    idx s_next, double inv, double rr, double mr) {
#define LEMKE_UPDATE(ROW) update_all<RHS, MAGB, NEXT>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr, ROW)
    if (!MAGB && T.ld <= 32 && T.ld % 4 == 0) {
        switch (T.ld / 4) {
            case 1: LEMKE_UPDATE(RowAxpyFixed<1>(prow)); return;
            case 2: LEMKE_UPDATE(RowAxpyFixed<2>(prow)); return;
            case 3: LEMKE_UPDATE(RowAxpyFixed<3>(prow)); return;
            case 4: LEMKE_UPDATE(RowAxpyFixed<4>(prow)); return;
            case 5: LEMKE_UPDATE(RowAxpyFixed<5>(prow)); return;
            case 6: LEMKE_UPDATE(RowAxpyFixed<6>(prow)); return;
            case 7: LEMKE_UPDATE(RowAxpyFixed<7>(prow)); return;
            default: LEMKE_UPDATE(RowAxpyFixed<8>(prow)); return;
        }
    }
    LEMKE_UPDATE((RowAxpy{prow, T.ld}));
#undef LEMKE_UPDATE
}

// The pivot row's rhs and magb entries (pivot_now and pivot_delayed alike; either may be
// nullptr: not kept): rr, mr get their new values (0 when not kept).
LEMKE_ALWAYS_INLINE void pivot_row_values(double* rhs, double* magb, idx r, double inv, double& rr,
                                          double& mr) {
    if (rhs) {
        rhs[r] = -rhs[r] * inv;
        rr = rhs[r];
    }
    if (magb) {
        magb[r] *= std::fabs(inv);
        mr = magb[r];
    }
}

// The rows' rhs and col_next entries of a pivot on row r (T's rows not yet updated): for
// every row c whose factor f = col[c] is not 0, rhs[c] + f rr and T[c, s_next] + f pn, else
// rhs[c] and T[c, s_next] (update_rows's operations on them), eight rows at a time and
// stored as whole vectors; rhs[r] and col_next[r] are set after (row r is the pivot row).
// Done before the row updates rather than row by row among them: the scalar stores of
// those entries, read next by the ratio test's and the column's vector loads, made those
// loads wait for every store of the row updates (a vector load cannot take its bytes from
// several smaller stores). Either pointer may be nullptr (not kept).
LEMKE_ALWAYS_INLINE void side_entries(const Mat<double>& T, const double* col, double* rhs,
                                      double* col_next, idx s_next, double pn, double rr) {
    idx n = T.rows, c = 0;
#ifdef LEMKE_SIMD
    simd::v8d vr = simd::splat8(rr), vp = simd::splat8(pn), zero = simd::splat8(0.0);
    for (; c + 8 <= n; c += 8) {
        simd::v8d f = simd::load8(col + c);
        auto kept = f != zero;
        if (rhs) {
            simd::v8d h = simd::load8(rhs + c);
            simd::store8(rhs + c, kept ? h + f * vr : h);
        }
        if (col_next) {
            const double* tc = T.row(c) + s_next;
            simd::v8d t;
            for (int l = 0; l < 8; ++l) t[l] = tc[l * T.ld];
            simd::store8(col_next + c, kept ? t + f * vp : t);
        }
    }
#endif
    for (; c < n; ++c) {
        double f = col[c];
        if (rhs && f != 0.0) rhs[c] += f * rr;
        if (col_next) {
            double t = T(c, s_next);
            col_next[c] = f != 0.0 ? t + f * pn : t;
        }
    }
}

}  // namespace

LEMKE_CLONES
void pivot_now(const Mat<double>& T, double* rhs, double* magb, idx r, idx s, const double* col,
               double* prow, idx s_next, double* col_next) {
    idx m = T.ld;
    double inv = 1.0 / col[r];
    double* tr = T.row(r);
    for (idx j = 0; j < m; ++j) {
        double v = -tr[j] * inv;
        prow[j] = v;
        tr[j] = v;
    }
    tr[s] = inv;
    double rr = 0.0, mr = 0.0;
    pivot_row_values(rhs, magb, r, inv, rr, mr);
    bool next = s_next >= 0;
    if (!magb && m <= 32 && m % 4 == 0 && T.rows >= 16) {
        // the small tableaux of 16 rows or more (rows of at most 32 doubles, magb not
        // kept), whose ratio test is a vector pass (tableau_lemke): rhs and col_next in
        // their own vector pass, then the rows alone (the same operations on each entry;
        // below 16 rows no faster: n = 12 1.03 -> 1.06 us)
        side_entries(T, col, rhs, next ? col_next : nullptr, s_next, next ? prow[s_next] : 0.0, rr);
        if (rhs) rhs[r] = rr;
        if (next) col_next[r] = prow[s_next];
        update_any<false, false, false>(T, r, col, nullptr, nullptr, nullptr, prow, s, -1, inv, 0.0, 0.0);
        return;
    }
    if (rhs && magb) {
        if (next) update_any<true, true, true>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr);
        else update_any<true, true, false>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr);
    } else if (rhs) {
        if (next) update_any<true, false, true>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr);
        else update_any<true, false, false>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr);
    } else {
        if (next) update_any<false, false, true>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr);
        else update_any<false, false, false>(T, r, col, rhs, magb, col_next, prow, s, s_next, inv, rr, mr);
    }
}

namespace {

// t[j] = ((t[j] + a[0] v[0][j]) + a[1] v[1][j]) + ... for j < m: K terms in one pass.
template <int K>
inline void add_terms(double* t, const double* a, const double* const* v, idx m) {
    idx j = 0;
#ifdef LEMKE_SIMD
    simd::v8d va[K];
    for (int c = 0; c < K; ++c) va[c] = simd::splat8(a[c]);
    for (; j + 8 <= m; j += 8) {
        simd::v8d x = simd::load8(t + j);
        for (int c = 0; c < K; ++c) x = x + va[c] * simd::load8(v[c] + j);
        simd::store8(t + j, x);
    }
#endif
    for (; j < m; ++j) {
        double x = t[j];
        for (int c = 0; c < K; ++c) x = x + a[c] * v[c][j];
        t[j] = x;
    }
}

}  // namespace

// Column s of the current tableau into col: entry() for every row, a pending pivot at a
// time over all rows (each entry's terms in pivot order; a zero factor's term is -0.0, which
// leaves any number as it is, as entry() skips it), so the rows' sums run side by side.
LEMKE_CLONES
void pending_column(Mat<double> T, const Pending& P, idx s, double* col) {
    idx n = T.rows;
    for (idx i = 0; i < n; ++i) col[i] = T(i, s);
    for (idx p = 0; p < P.k; ++p) {
        double vp = P.v(p)[s];
        const double* u = P.U + p * n;
        for (idx i = 0; i < n; ++i) {
            double f = u[i];
            double t = f * vp;
            col[i] = col[i] + (f != 0.0 ? t : -0.0);
        }
    }
}

// Apply the k pending pivots, row by row (tableau.flush: each entry gets the row's terms in
// pivot order, ((t + a0 v0) + a1 v1) + ..., the terms with a zero factor skipped, as an
// immediate update skips them): up to eight terms in one pass over the row. Wide rows go in
// strips of 256 columns, so that the pending rows' strips stay in the first-level cache
// while every row of T passes (each entry gets the same terms in the same order).
LEMKE_CLONES
void flush(Mat<double> T, Pending& P) {
    idx n = T.rows, m = P.m;
    idx strip = m > 512 ? 256 : m;
    for (idx j0 = 0; j0 < m; j0 += strip) {
        idx w = m - j0 < strip ? m - j0 : strip;
        for (idx i = 0; i < n; ++i) {
            double a[8];
            const double* v[8];
            double* ti = T.row(i) + j0;
            idx na = 0;
            for (idx p = 0; p < P.k; ++p) {
                double f = P.u(i, p);
                if (f != 0.0) {
                    a[na] = f;
                    v[na++] = P.v(p) + j0;
                }
                if (na == 8 || (p + 1 == P.k && na > 0)) {
                    switch (na) {
                        case 1: add_terms<1>(ti, a, v, w); break;
                        case 2: add_terms<2>(ti, a, v, w); break;
                        case 3: add_terms<3>(ti, a, v, w); break;
                        case 4: add_terms<4>(ti, a, v, w); break;
                        case 5: add_terms<5>(ti, a, v, w); break;
                        case 6: add_terms<6>(ti, a, v, w); break;
                        case 7: add_terms<7>(ti, a, v, w); break;
                        default: add_terms<8>(ti, a, v, w); break;
                    }
                    na = 0;
                }
            }
        }
    }
    P.k = 0;
}

// The pivot on row r and column s with P.k pivots pending (tableau.pivot): the pivot row
// and column made exact in T, the rank-one update kept pending; flushed when b are.
LEMKE_CLONES
void pivot_delayed(Mat<double> T, double* rhs, double* magb, idx r, idx s,
                   const double* col, double* prow, Pending& P) {
    idx n = T.rows, m = P.m, k = P.k, b = P.b;
    double inv = 1.0 / col[r];
    double* tr = T.row(r);
    for (idx j = 0; j < m; ++j) prow[j] = tr[j];
    for (idx p = 0; p < k; ++p) {
        double f = P.u(r, p);
        if (f != 0.0) {
            const double* v = P.v(p);
            for (idx j = 0; j < m; ++j) prow[j] += f * v[j];
        }
    }
    for (idx j = 0; j < m; ++j) prow[j] = -prow[j] * inv;
    prow[s] = inv;
    for (idx j = 0; j < m; ++j) tr[j] = prow[j];
    double rr = 0.0, mr = 0.0;
    pivot_row_values(rhs, magb, r, inv, rr, mr);
    for (idx p = 0; p < k; ++p) {
        P.U[p * n + r] = 0.0;
        P.V[p * m + s] = 0.0;
    }
    for (idx i = 0; i < n; ++i) {
        double f = col[i];
        P.U[k * n + i] = f;
        if (i != r) {
            T(i, s) = f * inv;
            if (f != 0.0) {
                if (rhs) rhs[i] += f * rr;
                if (magb) magb[i] += std::fabs(f) * mr;
            }
        }
    }
    P.U[k * n + r] = 0.0;
    double* vk = P.V + k * m;
    for (idx j = 0; j < m; ++j) vk[j] = prow[j];
    vk[s] = 0.0;
    P.k = k + 1;
    if (P.k == b) flush(T, P);
}

namespace {

// mags = the size |B^-1| |q| of the rows under the running bound that may be rounding.
// careful_sizes and lex_ties are inlined into tableau_lemke's clones (their one caller): GCC 12
// called them as baseline functions from the avx2 clone with a ymm register's upper half dirty
// and no vzeroupper, so the clone returned dirty after a careful run or a tie
// (benchmarks/scan_vzeroupper.py).
LEMKE_ALWAYS_INLINE void careful_sizes(Mat<double> T, const Pending& P, const double* col,
                                       const double* rhs, const idx* pos,
                                       const std::uint8_t* is_basic, const idx* start_basis,
                                       const double* q0, const double* magb, double* mags) {
    idx n = T.rows;
    for (idx i = 0; i < n; ++i) {
        double v = rhs[i];
        mags[i] = v;
        if (col[i] < 0.0 && v > 0.0 && v <= VALUE_ROUNDING * magb[i]) {
            double size = 0.0;
            for (idx j = 0; j < n; ++j) {
                idx lab = start_basis[j];
                double b = is_basic[lab] ? (pos[lab] == i ? 1.0 : 0.0) : entry(T, P, i, pos[lab]);
                size += std::fabs(b) * std::fabs(q0[j]);
            }
            mags[i] = size;
        }
    }
}

LEMKE_ALWAYS_INLINE idx lex_ties(Mat<double> T, const Pending& P, const double* col, const idx* basis,
                                 const idx* pos, const std::uint8_t* is_basic, const idx* start_basis,
                                 idx artificial, double pivot_tol, double tie_tol, idx* cand,
                                 double* keys, idx nc) {
    idx n = T.rows;
    for (idx c = 0; c < nc; ++c)
        if (basis[cand[c]] == artificial) return cand[c];
    for (idx j = 0; j < n; ++j) {
        idx lab = start_basis[j];
        for (idx c = 0; c < nc; ++c) {
            idx i = cand[c];
            double b = is_basic[lab] ? (pos[lab] == i ? 1.0 : 0.0) : -entry(T, P, i, pos[lab]);
            keys[c] = lex_key(b, col[i], pivot_tol);
        }
        nc = keep_lowest(cand, keys, nc, tie_tol);
        if (nc == 1) return cand[0];
    }
    return nc > 0 ? largest_pivot(cand, col, nc) : -1;
}

}  // namespace

// Compiled per instruction set too: the column copy, its maximum and the ratio test run
// every pivot (a baseline SSE2 build of them was about a tenth of a solve at n = 48).
LEMKE_CLONES
Status tableau_lemke(TableauWork& w, idx max_pivots, double pivot_tol, double tie_tol,
                     double* x_out, double* ray_out, std::uint8_t* z_basic_out, bool careful,
                     idx& pivots) {
    idx n = w.n;
    idx artificial = 2 * n;
    Mat<double> T = w.T();
    double *rhs = w.rhs(), *col = w.col(), *col_next = w.col2(), *q0 = w.q0(), *mags = w.mags();
    // the rows' running bounds |B^-1| |q| serve only the careful run's sizes (careful_sizes)
    double* magb = careful ? w.magb() : nullptr;
    double *prow = w.prow(), *keys = w.keys();
    idx *basis = w.basis(), *nonbasic = w.nonbasic(), *pos = w.pos();
    idx *start_basis = w.start_basis(), *cand = w.cand();
    std::uint8_t* is_basic = w.flags.data();
    Pending P{w.U(), w.V(), w.block, w.ld, 0, n};
    for (idx i = 0; i < 2 * n + 1; ++i) is_basic[i] = 0;
    for (idx i = 0; i < n; ++i) {
        start_basis[i] = basis[i];
        pos[basis[i]] = i;
        is_basic[basis[i]] = 1;
    }
    for (idx j = 0; j < n + 1; ++j) pos[nonbasic[j]] = j;
    for (idx j = 0; j < n + 1; ++j) ray_out[j] = 0.0;

    // the ratios in one vector pass from 16 rows (blocking_rows_vector: then the one-pass
    // rule on them below 64 rows, with a branch only on the rows within the running bound,
    // and two more vector passes from 64; n = 24: 1 % of a cold solve)
    double* ratios = n >= 16 ? keys : nullptr;
    Status status = MAX_PIVOTS;
    pivots = 0;
    idx s = pos[artificial];
    for (idx i = 0; i < n; ++i) col[i] = T(i, s);
    idx r = first_row(rhs, col, n, tie_tol);
    if (r < 0) {
        max_pivots = 0;
        status = NUMERICAL_FAILURE;
    }
    std::uint64_t h = 0;
    for (idx i = 0; i < n; ++i) h ^= label_key(basis[i]);
    Detector detector;
    double z0_max = 0.0;
    if (careful) {
        for (idx i = 0; i < n; ++i) {
            q0[i] = rhs[i];
            magb[i] = std::fabs(rhs[i]);
        }
    }
    Poll poll;
    std::int64_t work = n * (n + 1);
    while (pivots < max_pivots) {
        if (int stop = poll.tick(work); stop >= 0) {
            status = static_cast<Status>(stop);
            break;
        }
        idx leaving = basis[r];
        idx entering = nonbasic[s];
        if (!(std::fabs(col[r]) < INF)) {
            status = NUMERICAL_FAILURE;
            break;
        }
        // the complement of the leaving variable enters next: a column now (its label is
        // nonbasic and neither `leaving` nor `entering`), read during the pivot's row updates
        idx s_next = leaving == artificial ? -1 : pos[leaving < n ? leaving + n : leaving - n];
        if (P.b == 1) {
            pivot_now(T, rhs, magb, r, s, col, prow, s_next, col_next);
        } else {
            pivot_delayed(T, rhs, magb, r, s, col, prow, P);
            s_next = -1;
        }
        ++pivots;
        swap_labels(basis, nonbasic, pos, is_basic, r, s);
        int stop = after_pivot(leaving, entering, artificial, h, detector);
        if (stop >= 0) {
            status = static_cast<Status>(stop);
            break;
        }
        s = pos[leaving < n ? leaving + n : leaving - n];  // the complement enters
        if (s == s_next) {
            std::swap(col, col_next);
        } else if (P.k == 0) {
            for (idx i = 0; i < n; ++i) col[i] = T(i, s);
        } else {
            pending_column(T, P, s, col);
        }
        // max |col| (a running maximum: no NaN ever enters it, so eight lanes give the same
        // number as one)
        double cmax = absmax(col, n);
        if (is_basic[artificial]) z0_max = pmax(z0_max, rhs[pos[artificial]]);
        idx art = is_basic[artificial] ? pos[artificial] : -1;
        idx nc;
        if (careful) {
            careful_sizes(T, P, col, rhs, pos, is_basic, start_basis, q0, magb, mags);
            nc = blocking_rows(rhs, mags, col, n, -pivot_tol * cmax, tie_tol, cand, art, z0_max,
                               ratios);
        } else {
            nc = blocking_rows(rhs, rhs, col, n, -pivot_tol * cmax, tie_tol, cand, art, z0_max,
                               ratios);
        }
        if (nc <= 1) {
            r = nc == 1 ? cand[0] : -1;
        } else {
            r = lex_ties(T, P, col, basis, pos, is_basic, start_basis, artificial, pivot_tol,
                         tie_tol, cand, keys, nc);
        }
        if (r < 0) {
            status = RAY_TERMINATION;
            entering = nonbasic[s];
            for (idx i = 0; i < n; ++i) {
                idx lab = basis[i];
                if (lab >= n) ray_out[lab - n] = col[i];
            }
            if (entering >= n) ray_out[entering - n] = 1.0;
            break;
        }
    }
    for (idx j = 0; j < n + 1; ++j) x_out[j] = 0.0;
    for (idx j = 0; j < n; ++j) z_basic_out[j] = 0;
    for (idx i = 0; i < n; ++i) {
        idx lab = basis[i];
        if (lab >= n) {
            x_out[lab - n] = rhs[i];
            if (lab < artificial) z_basic_out[lab - n] = 1;
        }
    }
    return status;
}

Status tableau_solve(Mat<const double> M, const double* q, const double* d, const double* R,
                     const double* C, idx max_pivots, double pivot_tol, double tie_tol,
                     double* x_out, double* ray_out, std::uint8_t* z_basic_out, bool careful,
                     idx& pivots) {
    thread_local TableauWork w;
    idx n = M.rows;
    w.layout(n);
    double d_scale = scaled_into(M, q, d, R, C, w.T(), w.rhs());
    idx* basis = w.basis();
    idx* nonbasic = w.nonbasic();
    for (idx i = 0; i < n; ++i) {
        basis[i] = i;
        nonbasic[i] = n + i;
    }
    nonbasic[n] = 2 * n;
    Status status = tableau_lemke(w, max_pivots, pivot_tol, tie_tol, x_out, ray_out,
                                  z_basic_out, careful, pivots);
    unscale(x_out, ray_out, C, 1.0 / d_scale, status == SOLVED, n);
    return status;
}

void unscale(double* x_out, double* ray_out, const double* C, double z0_factor, bool solved,
             idx n) {
    for (idx i = 0; i < n; ++i) {
        x_out[i] *= C[i];
        ray_out[i] *= C[i];
    }
    x_out[n] *= z0_factor;
    ray_out[n] *= z0_factor;
    if (solved)
        for (idx i = 0; i < n + 1; ++i) x_out[i] = pmax(x_out[i], 0.0);
}

}  // namespace lemke
