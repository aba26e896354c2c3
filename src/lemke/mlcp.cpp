#include "mlcp.hpp"

#include <cfloat>
#include <cmath>
#include <vector>

#include "linalg.hpp"
#include "multiversion.hpp"

namespace lemke {

namespace {

// The MLCP kernels' workspace, one per thread: the pivot row and its non-zero columns
// (N + 1 each), the free columns and slack rows of a round (N each), where each non-basic
// label sits (2N); equilibrate's row and column maxima (N each).
struct MlcpWork {
    std::vector<double> f;
    std::vector<idx> i;
    idx N = -1;
    void layout(idx size) {
        N = size;
        f.resize(static_cast<std::size_t>(2 * (N + 1)));
        i.resize(static_cast<std::size_t>((N + 1) + N + N + 2 * N));
    }
    double* prow() { return f.data(); }
    double* colmax() { return f.data() + N + 1; }
    idx* nz() { return i.data(); }
    idx* fcols() { return nz() + N + 1; }
    idx* srows() { return fcols() + N; }
    idx* col_of() { return srows() + N; }
};

thread_local MlcpWork mlcp_work;

// Exchange the basic variable of row r with the non-basic one of column c:
// where the pivot row has few non-zeros only those columns of the other rows are updated.
// c = -1 is read from the end, as a Python index (T's last column, col_label's last entry):
// reduce can pass it when no free column is left in the row (the bits the tests record).
// Per instruction set (the row updates are elementwise: the same bits in every variant).
LEMKE_CLONES
void exchange(Mat<double> T, idx r, idx c, idx* row_label, idx* col_label, double* prow,
              idx* nz) {
    idx rows = T.rows, cols = T.cols;
    idx cT = c < 0 ? c + cols : c;
    idx cL = c < 0 ? c + rows : c;
    double* tr = T.row(r);
    double inv = 1.0 / tr[cT];
    idx m = 0;
    for (idx k = 0; k < cols; ++k) {  // (prow[c] is not set to inv: the rows' entries c are overwritten)
        double v = -tr[k] * inv;
        prow[k] = v;
        tr[k] = v;
        if (v != 0.0 && k != c) nz[m++] = k;
    }
    tr[cT] = inv;
    bool sparse = 4 * m < cols;
    for (idx i = 0; i < rows; ++i) {
        if (i == r) continue;
        double* ti = T.row(i);
        double f = ti[cT];
        if (f == 0.0) continue;
        if (sparse) {
            for (idx t = 0; t < m; ++t) {
                idx k = nz[t];
                ti[k] += f * prow[k];
            }
        } else {
            for (idx k = 0; k < cols; ++k) ti[k] += f * prow[k];
        }
        ti[cT] = f * inv;
    }
    idx tmp = row_label[r];
    row_label[r] = col_label[cL];
    col_label[cL] = tmp;
}

// Remove entry t of the ascending list of slack rows (the order kept).
void drop_slack(idx* slack, idx& ns, idx t) {
    for (idx u = t + 1; u < ns; ++u) slack[u - 1] = slack[u];
    --ns;
}

// Row r in the ascending list of slack rows iff its basic variable is a slack (label < n),
// after an exchange there.
void sync_slack(idx r, const idx* row_label, idx n, idx* slack, idx& ns) {
    idx t = 0;
    while (t < ns && slack[t] < r) ++t;
    bool listed = t < ns && slack[t] == r;
    if (row_label[r] < n) {
        if (listed) return;
        for (idx u = ns; u > t; --u) slack[u] = slack[u - 1];
        slack[t] = r;
        ++ns;
    } else if (listed) {
        drop_slack(slack, ns, t);
    }
}

// The free variable of column c enters in place of the slack of an equation, the one with
// the largest entry in that column, if that entry exceeds rank_tol (kmlcp.enter_free).
// slack (ns of them, ascending): the rows whose basic variable is a slack (row_label < n),
// the only rows looked at (the first largest in row order, as a scan of every row), and the
// row that takes the free variable leaves the list.
void enter_free(Mat<double> T, idx c, double rank_tol, idx* row_label, idx* col_label,
                double* prow, idx* nz, idx* slack, idx& ns) {
    double best = 0.0;
    idx t_best = -1;
    for (idx t = 0; t < ns; ++t) {
        double v = std::fabs(T(slack[t], c));
        if (v > best) {
            best = v;
            t_best = t;
        }
    }
    if (t_best >= 0 && best > rank_tol) {
        exchange(T, slack[t_best], c, row_label, col_label, prow, nz);
        drop_slack(slack, ns, t_best);
    }
}

// colmax[c]: the largest |T(r, c)| over the slack rows r (every column, the constant's
// included); a max, so its order does not matter.
LEMKE_CLONES
void slack_column_max(Mat<double> T, const idx* slack, idx ns, double* colmax) {
    idx cols = T.cols;
    for (idx c = 0; c < cols; ++c) colmax[c] = 0.0;
    for (idx t = 0; t < ns; ++t) {
        const double* tr = T.row(slack[t]);
        for (idx c = 0; c < cols; ++c) colmax[c] = pmax(colmax[c], std::fabs(tr[c]));
    }
}

// max_t |ti[cols[t]]| (0 for k = 0), eight running maxima as linalg's absmax (a max of
// terms that are not NaN is exact in any order; a NaN is passed over by every pmax alike).
LEMKE_CLONES
double gathered_absmax(const double* ti, const idx* cols, idx k) {
    double m[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    idx t = 0;
    for (; t + 8 <= k; t += 8)
        for (int l = 0; l < 8; ++l) m[l] = pmax(m[l], std::fabs(ti[cols[t + l]]));
    for (; t < k; ++t) m[0] = pmax(m[0], std::fabs(ti[cols[t]]));
    return pmax(pmax(pmax(m[0], m[1]), pmax(m[2], m[3])), pmax(pmax(m[4], m[5]), pmax(m[6], m[7])));
}

}  // namespace

namespace {

// One sweep's row and column maxima of |E| r s over the non-zeros of E alone (their
// columns and |E_ij| by rows, nz_start: N + 1 offsets), for r and s finite and positive:
// then every v = |E_ij| r_i s_j is +0 or more and not NaN, a zero E_ij gives +0, and the
// maxima start at +0 instead of -inf: the dense sweep's maxima, bit for bit.
LEMKE_CLONES
void sparse_maxima(idx N, const idx* nz_start, const idx* nz_col, const double* nz_abs,
                   const double* r, const double* s, double* rows, double* cols) {
    for (idx i = 0; i < N; ++i) {
        rows[i] = 0.0;
        cols[i] = 0.0;
    }
    for (idx i = 0; i < N; ++i) {
        double ri = r[i], best = 0.0;
        for (idx t = nz_start[i]; t < nz_start[i + 1]; ++t) {
            idx j = nz_col[t];
            double v = nz_abs[t] * ri * s[j];
            if (v > best) best = v;
            if (v > cols[j]) cols[j] = v;
        }
        rows[i] = best;
    }
}

bool finite_positive(const double* a, idx N) {
    for (idx i = 0; i < N; ++i)
        if (!(a[i] > 0.0 && a[i] <= DBL_MAX)) return false;
    return true;
}

}  // namespace

LEMKE_CLONES
void mlcp_equilibrate(Mat<const double> E, idx n, idx iterations, double* r, double* s) {
    idx N = E.rows;
    thread_local std::vector<double> work;
    thread_local std::vector<idx> nz_idx;
    work.resize(static_cast<std::size_t>(2 * N));
    double* rows = work.data();
    double* cols = rows + N;
    // E's non-zeros by rows, when they are under a third of it (the KKT systems of LP-like
    // QPs: a few per cent): each sweep then reads them alone.
    idx nnz = 0;
    for (idx i = 0; i < N; ++i) {
        const double* ei = E.row(i);
        for (idx j = 0; j < N; ++j) nnz += ei[j] != 0.0;
    }
    bool sparse = N > 0 && 3 * nnz < N * N;
    if (sparse) {
        work.resize(static_cast<std::size_t>(2 * N + nnz));
        rows = work.data();
        cols = rows + N;
        nz_idx.resize(static_cast<std::size_t>(N + 1 + nnz));
        idx* nz_start = nz_idx.data();
        idx* nz_col = nz_start + N + 1;
        double* nz_abs = cols + N;
        idx t = 0;
        for (idx i = 0; i < N; ++i) {
            nz_start[i] = t;
            const double* ei = E.row(i);
            for (idx j = 0; j < N; ++j) {
                if (ei[j] != 0.0) {
                    nz_col[t] = j;
                    nz_abs[t++] = std::fabs(ei[j]);
                }
            }
        }
        nz_start[N] = t;
    }
    for (idx it = 0; it < iterations; ++it) {
        if (sparse && finite_positive(r, N) && finite_positive(s, N)) {
            const idx* nz_start = nz_idx.data();
            sparse_maxima(N, nz_start, nz_start + N + 1, cols + N, r, s, rows, cols);
        } else {
            for (idx i = 0; i < N; ++i) {
                rows[i] = -INF;
                cols[i] = -INF;
            }
            for (idx i = 0; i < N; ++i) {
                const double* ei = E.row(i);
                double ri = r[i];
                for (idx j = 0; j < N; ++j) {
                    double v = std::fabs(ei[j]) * ri * s[j];
                    if (v > rows[i] || v != v) rows[i] = v;
                    if (v > cols[j] || v != v) cols[j] = v;
                }
            }
        }
        bool done = true;
        for (idx i = 0; i < N; ++i) {
            if (rows[i] == 0.0) rows[i] = 1.0;
            if (cols[i] == 0.0) cols[i] = 1.0;
            if (!(std::fabs(rows[i] - 1.0) < 0.1 && std::fabs(cols[i] - 1.0) < 0.1)) done = false;
        }
        for (idx i = 0; i < n; ++i) {
            r[i] /= std::sqrt(rows[i]);
            s[i] /= std::sqrt(cols[i]);
        }
        for (idx i = n; i < N; ++i) {
            double a = rows[i], b = cols[i];
            double f = 1.0 / std::sqrt(a >= b || a != a ? a : b);
            r[i] *= f;
            s[i] *= f;
        }
        if (done) break;
    }
}

LEMKE_CLONES
void mlcp_scale(Mat<const double> E, const double* e, const double* r, const double* s,
                Mat<double> T) {
    idx N = E.rows;
    for (idx i = 0; i < N; ++i) {
        const double* ei = E.row(i);
        double* ti = T.row(i);
        double ri = r[i];
        for (idx j = 0; j < N; ++j) ti[j] = ei[j] * (ri * s[j]);
        ti[N] = e[i] * ri;
    }
}

ReduceResult mlcp_reduce(Mat<double> T, idx n, double rank_tol, double e_size, idx* row_label,
                         idx* col_label) {
    idx N = T.rows;
    MlcpWork& w = mlcp_work;
    w.layout(N);
    double* prow = w.prow();
    idx* nz = w.nz();
    for (idx i = 0; i < N; ++i) {
        row_label[i] = i;
        col_label[i] = N + i;
    }
    auto is_free = [N, n](idx label) { return N <= label && label < N + n; };
    // The rows whose basic variable is a slack, ascending (rows 0 .. n-1 at first): each
    // exchange below puts a free or pair variable in one of them, none puts a slack back.
    idx* srows = w.srows();
    idx ns = n;
    for (idx r = 0; r < n; ++r) srows[r] = r;
    // 1. u_c enters in place of the slack of an equation (column by column, largest pivot).
    for (idx c = 0; c < n; ++c) enter_free(T, c, rank_tol, row_label, col_label, prow, nz, srows, ns);

    // 2. Swap a pair k to make room: 2 x 2 exchanges while slacks and free columns remain.
    idx* fcols = w.fcols();
    idx* col_of = w.col_of();
    auto col = [&T](idx j) { return j < 0 ? j + T.cols : j; };  // a negative index counts from the end
    while (true) {
        idx nf = 0;
        for (idx l = 0; l < 2 * N; ++l) col_of[l] = -1;
        for (idx c = 0; c < N; ++c) {
            idx lc = col_label[c];
            col_of[lc] = c;
            if (is_free(lc)) fcols[nf++] = c;
        }
        // Rows of pair variables: for each, its largest entry over the free columns.
        // A row is passed over at once where the scan of its partner's column (below)
        // would not move best: no slack row's entry there exceeds rank_tol, or the largest
        // times rmax does not exceed best (v <= vmax gives v rmax <= vmax rmax, rounded
        // too): the same choice, without reading that column row by row for every row.
        double* colmax = w.colmax();
        slack_column_max(T, srows, ns, colmax);
        double best = 0.0;
        idx r_best = -1, k_col = -1, k_row = -1;
        for (idx i = 0; i < N; ++i) {
            idx li = row_label[i];
            if (li < n || is_free(li)) continue;  // a slack or a free variable
            // This row's pair partner is non-basic in some column j.
            idx j = col_of[li >= N ? li - N : li + N];
            idx jT = col(j);
            double vmax = colmax[jT];
            if (!(vmax > rank_tol)) continue;
            const double* ti = T.row(i);
            double rmax = gathered_absmax(ti, fcols, nf);
            if (rmax <= rank_tol) continue;
            if (!(vmax * rmax > best)) continue;
            for (idx t = 0; t < ns; ++t) {
                idx r = srows[t];
                double v = std::fabs(T(r, jT));
                if (v > rank_tol && v * rmax > best) {
                    best = v * rmax;
                    r_best = r;
                    k_col = j;
                    k_row = i;
                }
            }
        }
        if (r_best < 0) break;
        exchange(T, r_best, k_col, row_label, col_label, prow, nz);
        sync_slack(r_best, row_label, n, srows, ns);
        idx c_best = -1;
        double cbest = 0.0;
        const double* tk = T.row(k_row);
        for (idx c = 0; c < N; ++c) {
            if (is_free(col_label[c]) && std::fabs(tk[c]) > cbest) {
                cbest = std::fabs(tk[c]);
                c_best = c;
            }
        }
        exchange(T, k_row, c_best, row_label, col_label, prow, nz);
        sync_slack(k_row, row_label, n, srows, ns);
        // The 1-step pivot may now succeed in a column that failed before.
        for (idx c = 0; c < N; ++c)
            if (is_free(col_label[c]))
                enter_free(T, c, rank_tol, row_label, col_label, prow, nz, srows, ns);
    }

    // 3. What remains must be redundant: zero rows (slacks) and zero columns (free variables).
    for (idx r = 0; r < N; ++r) {
        if (row_label[r] >= n) continue;
        const double* tr = T.row(r);
        for (idx c = 0; c < N; ++c)
            if (col_label[c] >= n && std::fabs(tr[c]) > rank_tol) return {MLCP_SINGULAR, r};
        if (std::fabs(tr[N]) > rank_tol * e_size) return {MLCP_INCONSISTENT, r};
    }
    for (idx c = 0; c < N; ++c) {
        if (!is_free(col_label[c])) continue;
        for (idx r = 0; r < N; ++r) {
            idx lr = row_label[r];
            if (lr >= n && !is_free(lr) && std::fabs(T(r, c)) > rank_tol) return {MLCP_SINGULAR, r};
        }
    }
    return {MLCP_OK, -1};
}

}  // namespace lemke
