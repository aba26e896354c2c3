#include "lcp.hpp"

#include <algorithm>
#include <vector>

#include "certify.hpp"
#include "tableau.hpp"

namespace lemke {

namespace {

struct Views {
    double *x, *ray, *w, *cov, *R, *C;
    Views(double* buf, idx n) {
        BufferLayout L{n};
        x = buf + L.z();
        ray = buf + L.ray();
        w = buf + L.w();
        cov = buf + L.covering();
        R = buf + L.row_scale();
        C = buf + L.col_scale();
    }
};

// The finite check, the scales and the covering vector. Returns NOT_FINITE, TRIVIAL (z = 0
// and w = q written) or 0. `scaled`: the check and the scales are done already.
int prologue(Mat<const double> M, const double* q, const double* d, const Views& v, bool scaled,
             std::vector<double>& work) {
    idx n = M.rows;
    if (!scaled) {
        double m_max;
        bool finite = finite_absmax(M, m_max);
        finite &= all_finite(q, n);
        if (!finite) return NOT_FINITE;
        work.resize(static_cast<std::size_t>(2 * n));
        equilibrate(M, q, v.R, v.C, work.data());
    }
    double q_min = 0.0;
    for (idx i = 0; i < n; ++i) {
        q_min = pmin(q_min, q[i]);
        v.cov[i] = d ? d[i] : 1.0;
    }
    if (q_min >= 0.0) {
        for (idx i = 0; i < n + 1; ++i) v.x[i] = v.ray[i] = 0.0;
        for (idx i = 0; i < n; ++i) v.w[i] = q[i];
        return TRIVIAL;
    }
    return 0;
}

// z of the complementary basis with z_i basic for i in beta[:k]: z_beta = -M_bb^-1 q_beta,
// clipped at 0. work: at least k (k + 2) doubles.
bool basis_point(Mat<const double> M, const double* q, const idx* beta, idx k, double* z,
                 double* work) {
    idx n = M.rows;
    for (idx i = 0; i < n; ++i) z[i] = 0.0;
    if (k == 0) return true;
    double* A = work;
    double* y = work + k * k;
    double* zb = work + k * (k + 1);
    for (idx i = 0; i < k; ++i) y[i] = -q[beta[i]];
    if (!solve_gathered(M, beta, A, y, zb, k)) return false;
    for (idx i = 0; i < k; ++i) z[beta[i]] = pmax(zb[i], 0.0);
    return true;
}

// The first stage of a warm start. Returns 0 (the old basis solves it), 1 (its point fails),
// 2 (its block is singular), -1 (not finite).
int old_basis(Mat<const double> M, const double* q, const double* d, const idx* beta, idx k,
              double tol, const Views& v, idx* basic, double& residual,
              std::vector<double>& work) {
    idx n = M.rows;
    residual = 0.0;
    double m_max;
    if (!finite_absmax(M, m_max) || !all_finite(q, n)) return -1;
    work.resize(static_cast<std::size_t>(std::max(k * (k + 2), 2 * n)));
    equilibrate(M, q, v.R, v.C, work.data());
    v.x[n] = 0.0;
    if (!basis_point(M, q, beta, k, v.x, work.data())) return 2;
    if (!check_rows(M, q, v.x, tol, v.w, v.R, work.data(), true, residual)) {
        residual = 0.0;
        return 1;
    }
    for (idx i = 0; i < n; ++i) v.cov[i] = d ? d[i] : 1.0;
    for (idx i = 0; i < n + 1; ++i) v.ray[i] = 0.0;
    for (idx i = 0; i < k; ++i) basic[i] = beta[i];
    return 0;
}

}  // namespace

RunResult first_run(Mat<const double> M, const double* q, const double* d, const idx* beta,
                    idx k, idx max_pivots, double pivot_tol, double tie_tol, double tol,
                    double* buf, idx* basic) {
    thread_local std::vector<double> work;
    thread_local std::vector<std::uint8_t> z_basic;
    RunResult out;
    idx n = M.rows;
    Views v(buf, n);
    if (k > 0) {
        double residual;
        int found = old_basis(M, q, d, beta, k, tol, v, basic, residual, work);
        if (found == 0) {
            out.code = SOLVED;
            out.k = k;
            out.ok = true;
            out.residual = residual;
            out.stage = 0;
            return out;
        }
        if (found < 0) {
            out.code = NOT_FINITE;
            return out;
        }
        if (found == 1 && n >= RESTART_FROM) {
            out.stage = -2;
            return out;
        }
    }
    int code = prologue(M, q, d, v, k > 0, work);
    if (code < 0) {
        out.code = code;
        out.ok = code == TRIVIAL;
        return out;
    }
    z_basic.resize(static_cast<std::size_t>(n));
    idx pivots = 0;
    Status st = tableau_solve(M, q, v.cov, v.R, v.C, max_pivots, pivot_tol, tie_tol, v.x, v.ray,
                              z_basic.data(), false, pivots);
    code = st;
    bool ok = false;
    double residual = 0.0;
    if (code != CYCLING) {
        work.resize(static_cast<std::size_t>(2 * n));
        ok = check_rows(M, q, v.x, tol, v.w, v.R, work.data(), false, residual);
        if (ok) code = SOLVED;
    }
    out.code = code;
    out.pivots = pivots;
    out.residual = residual;
    if (code == CYCLING || (!ok && (code == RAY_TERMINATION || (d == nullptr && pivots < max_pivots)))) {
        for (idx i = 0; i < n; ++i) basic[i] = z_basic[i];
        out.stage = -1;
        return out;
    }
    idx kk = 0;
    for (idx i = 0; i < n; ++i)
        if (z_basic[i]) basic[kk++] = i;
    out.k = kk;
    out.ok = ok;
    return out;
}

}  // namespace lemke
