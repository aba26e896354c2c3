// The C API (include/lemke.h) over the driver: argument checks, one solve, the final
// basis's point when the run's own point fails, outputs copied to the caller's memory.
// No exception crosses it.
#include "lemke.h"

#include <algorithm>
#include <new>
#include <vector>

#include "lemke/certify.hpp"
#include "lemke/lcp.hpp"

using lemke::idx;

extern "C" void lemke_default_options(lemke_options* o) {
    if (!o) return;
    o->max_pivots = -1;
    o->pivot_tol = 1e-11;
    o->tie_tol = 1e-11;
    o->tol = 1e-9;
}

extern "C" const char* lemke_status_name(int status) {
    switch (status) {
        case LEMKE_SOLVED: return "SOLVED";
        case LEMKE_MAX_PIVOTS: return "MAX_PIVOTS";
        case LEMKE_RAY_TERMINATION: return "RAY_TERMINATION";
        case LEMKE_NUMERICAL_FAILURE: return "NUMERICAL_FAILURE";
        case LEMKE_CYCLING: return "CYCLING";
        case LEMKE_NOT_FINITE: return "NOT_FINITE";
        case LEMKE_INVALID_ARGUMENT: return "INVALID_ARGUMENT";
        case LEMKE_OUT_OF_MEMORY: return "OUT_OF_MEMORY";
        default: return "UNKNOWN";
    }
}

namespace {

bool valid_tolerance(double t) { return t >= 0.0 && t < 1.0; }  // NaN fails

int solve(idx n, const double* M, const double* q, const lemke_options* options,
          const int64_t* warm, idx n_warm, double* z, double* w, int64_t* basis_out,
          int64_t* n_basis_out, lemke_info* info) {
    lemke_options o;
    lemke_default_options(&o);
    if (options) o = *options;
    if (n < 0 || (n > 0 && (!M || !q)) || n_warm < 0 || n_warm > n || (n_warm > 0 && !warm) ||
        !valid_tolerance(o.pivot_tol) || !valid_tolerance(o.tie_tol) || !valid_tolerance(o.tol) ||
        n > (idx(1) << 26))
        return LEMKE_INVALID_ARGUMENT;
    std::vector<std::uint8_t> seen(static_cast<std::size_t>(n), 0);
    for (idx i = 0; i < n_warm; ++i) {
        if (warm[i] < 0 || warm[i] >= n || seen[warm[i]]) return LEMKE_INVALID_ARGUMENT;
        seen[warm[i]] = 1;
    }
    std::vector<idx> beta(warm, warm + n_warm);
    idx max_pivots = o.max_pivots < 0 ? 100 * (n + 1) : o.max_pivots;
    lemke::BufferLayout L{n};
    std::vector<double> buf(static_cast<std::size_t>(L.length()));
    std::vector<idx> basic(static_cast<std::size_t>(n) + 1);
    lemke::Mat<const double> A(M, n, n);
    // The whole solve of solve_lcp by the tableau: the warm basis's point, a restart from it
    // at n >= RESTART_FROM, the cold run with its recoveries, every answer checked.
    lemke::RunResult r = lemke::solve(lemke::TABLEAU, A, q, nullptr, beta.data(), n_warm,
                                      max_pivots, o.pivot_tol, o.tie_tol, o.tol, buf.data(),
                                      basic.data());
    if (r.code == lemke::NOT_FINITE) return LEMKE_NOT_FINITE;
    int status = r.code == lemke::TRIVIAL ? LEMKE_SOLVED : r.code;
    double* x = buf.data() + L.z();
    double* wv = buf.data() + L.w();
    idx k = r.k;
    if (status == LEMKE_SOLVED && !r.ok) {
        // Solved on a point that fails the check: the point of the final basis, one LU
        // solve on the caller's data (what the Python front does), checked again.
        std::vector<double> work(static_cast<std::size_t>(std::max(k * (k + 2), 2 * n)));
        std::vector<double> zb(static_cast<std::size_t>(n));
        std::vector<double> y(static_cast<std::size_t>(k)), xb(static_cast<std::size_t>(k));
        for (idx i = 0; i < k; ++i) y[i] = -q[basic[i]];
        bool ok = lemke::solve_gathered(A, basic.data(), work.data(), y.data(), xb.data(), k);
        double residual = 0.0;
        if (ok) {
            for (idx i = 0; i < n; ++i) zb[i] = 0.0;
            for (idx i = 0; i < k; ++i) zb[basic[i]] = lemke::pmax(xb[i], 0.0);
            ok = lemke::check_rows(A, q, zb.data(), o.tol, wv, buf.data() + L.row_scale(),
                                   work.data(), false, residual);
        }
        if (ok) {
            for (idx i = 0; i < n; ++i) x[i] = zb[i];
            r.residual = residual;
        } else {
            status = LEMKE_NUMERICAL_FAILURE;
        }
    } else if (status == LEMKE_RAY_TERMINATION && !r.ok) {
        status = LEMKE_NUMERICAL_FAILURE;  // a ray that failed the ray check proves nothing
    }
    if (z) for (idx i = 0; i < n; ++i) z[i] = x[i];
    if (w) for (idx i = 0; i < n; ++i) w[i] = wv[i];
    if (basis_out) for (idx i = 0; i < k; ++i) basis_out[i] = basic[i];
    if (n_basis_out) *n_basis_out = k;
    if (info) {
        info->status = status;
        info->pivots = r.pivots;
        info->residual = r.residual;
        info->warm = r.stage == 0;
    }
    return status;
}

}  // namespace

extern "C" int lemke_lcp_solve(int64_t n, const double* M, const double* q,
                               const lemke_options* options, const int64_t* warm_basis,
                               int64_t n_warm, double* z, double* w, int64_t* basis_out,
                               int64_t* n_basis_out, lemke_info* info) {
    if (info) {
        info->status = LEMKE_INVALID_ARGUMENT;
        info->pivots = 0;
        info->residual = 0.0;
        info->warm = 0;
    }
    try {
        int s = solve(n, M, q, options, warm_basis, n_warm, z, w, basis_out, n_basis_out, info);
        if (info) info->status = s;
        return s;
    } catch (const std::bad_alloc&) {
        if (info) info->status = LEMKE_OUT_OF_MEMORY;
        return LEMKE_OUT_OF_MEMORY;
    } catch (...) {
        if (info) info->status = LEMKE_INVALID_ARGUMENT;
        return LEMKE_INVALID_ARGUMENT;
    }
}
