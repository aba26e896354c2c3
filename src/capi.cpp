// The C API (include/lemke.h) over the driver: argument checks, one solve, the final
// basis's point when the run's own point fails, outputs copied to the caller's memory.
// No exception crosses it.
#include "lemke.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <vector>

#include "capi_status.hpp"
#include "lemke/boxed.hpp"
#include "lemke/boxed_batch.hpp"
#include "lemke/certify.hpp"
#include "lemke/lcp.hpp"

using lemke::idx;

extern "C" void lemke_default_options(lemke_options* o) {
    if (!o) return;
    o->max_pivots = -1;
    o->pivot_tol = 1e-11;
    o->tie_tol = 1e-11;
    o->tol = 1e-9;
    o->time_limit = -1.0;
}

extern "C" void lemke_interrupt(void) { lemke::interrupt_all(); }

extern "C" const char* lemke_status_name(int status) {
    switch (status) {
        case LEMKE_SOLVED: return "SOLVED";
        case LEMKE_MAX_PIVOTS: return "MAX_PIVOTS";
        case LEMKE_RAY_TERMINATION: return "RAY_TERMINATION";
        case LEMKE_NUMERICAL_FAILURE: return "NUMERICAL_FAILURE";
        case LEMKE_CYCLING: return "CYCLING";
        case LEMKE_TIME_LIMIT: return "TIME_LIMIT";
        case LEMKE_INTERRUPTED: return "INTERRUPTED";
        case LEMKE_NOT_FINITE: return "NOT_FINITE";
        case LEMKE_INVALID_ARGUMENT: return "INVALID_ARGUMENT";
        case LEMKE_OUT_OF_MEMORY: return "OUT_OF_MEMORY";
        default: return "UNKNOWN";
    }
}

namespace {

bool valid_tolerance(double t) { return t >= 0.0 && t < 1.0; }  // NaN fails
bool valid_options(const lemke_options& o) {
    return valid_tolerance(o.pivot_tol) && valid_tolerance(o.tie_tol) &&
           valid_tolerance(o.tol) && !std::isnan(o.time_limit);
}

int solve(idx n, const double* M, const double* q, const lemke_options* options,
          const int64_t* warm, idx n_warm, double* z, double* w, int64_t* basis_out,
          int64_t* n_basis_out, lemke_info* info) {
    lemke_options o;
    lemke_default_options(&o);
    if (options) o = *options;
    if (n < 0 || (n > 0 && (!M || !q)) || n_warm < 0 || n_warm > n || (n_warm > 0 && !warm) ||
        !valid_options(o) || n > (idx(1) << 26))
        return LEMKE_INVALID_ARGUMENT;
    lemke::DeadlineScope budget(o.time_limit);
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
    int status = lemke::c_status(r.code);  // (TRIVIAL: SOLVED)
    if (status == LEMKE_NOT_FINITE) return status;
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

// A checked answer off a bound by less than the check's allowance (a run's point is not
// clamped when the run itself did not end solved; the fuzz found z = 0 for lo = 1e-300, and
// a denormal past hi): onto the bound, as the Python front's answer is.
void onto_bounds(double* z, const double* lo, const double* hi, idx n) {
    for (idx i = 0; i < n; ++i) z[i] = std::min(std::max(z[i], lo[i]), hi[i]);
}

// The box LCP (lemke_blcp_solve): _blcp._one_call's runs (cold), then the final basis's
// point and one restart from that basis.
int blcp(idx n, const double* M, const double* q, const double* lo, const double* hi,
         const int64_t* findex, const lemke_options* options, double* z, double* w,
         lemke_info* info, std::int8_t* state_out = nullptr) {
    namespace bx = lemke::boxed;
    lemke_options o;
    lemke_default_options(&o);
    if (options) o = *options;
    if (n < 0 || (n > 0 && (!M || !q || !lo || !hi)) || !valid_options(o) || n > (idx(1) << 26))
        return LEMKE_INVALID_ARGUMENT;
    lemke::DeadlineScope budget(o.time_limit);
    bool friction = findex && n > 0;
    idx nf = 0;
    if (friction)
        for (idx i = 0; i < n; ++i) nf += findex[i] >= 0;
    bx::FrontLayout FL{n, nf, friction};
    idx N = FL.N();
    std::vector<std::uint8_t> warm(static_cast<std::size_t>(2 * N), 0);
    std::vector<double> buf(static_cast<std::size_t>(FL.length()));
    std::vector<idx> ints(static_cast<std::size_t>(FL.ints_length()));
    std::vector<double> work(static_cast<std::size_t>(FL.work_length()));
    lemke::Mat<const double> A(M, n, n);
    double tol = o.tol;
    idx buf_len = static_cast<idx>(buf.size()), ints_len = static_cast<idx>(ints.size());
    idx work_len = static_cast<idx>(work.size());
    double residual = 0.0;
    auto front = [&](int phase) {
        return bx::front(phase, A, q, lo, hi, friction ? findex : nullptr, friction ? n : 0,
                         warm.data(), 2 * N, false, tol, buf.data(), buf_len, ints.data(),
                         ints_len, work.data(), work_len, residual);
    };
    int code = front(bx::PREPARE);
    if (code != bx::NEED_RUN) return lemke::c_status(code);  // NOT_FINITE, BAD_BOUNDS, BAD_FINDEX
    // The problem solved: the extended one with friction rows, else the caller's.
    lemke::Mat<const double> Ae = A;
    const double *qa = q, *la = lo, *ha = hi;
    if (nf > 0) {
        Ae = lemke::Mat<const double>(work.data() + FL.work_M(), N, N);
        qa = work.data() + FL.work_q();
        la = work.data() + FL.work_lo();
        ha = work.data() + FL.work_hi();
    }
    idx* final = ints.data() + FL.final();
    double* ext = buf.data();
    bx::BoxLayout L = FL.run();
    idx limit = o.max_pivots < 0 ? 100 * (N + 1) : o.max_pivots;
    double pt = o.pivot_tol, tt = o.tie_tol;
    idx pivots = 0;
    bx::SolveResult r = bx::solve(Ae, qa, la, ha, warm.data(), 0, limit, pt, tt, tol, ext, final);
    pivots += std::max<idx>(r.pivots, 0);
    bool done = r.code == 0 && r.ok;
    bool ray = false;
    int stop = lemke::is_stop(r.code) ? r.code : 0;  // stopped by its budget: no more runs
    if (!done && !stop) {
        if (r.code == lemke::RAY_TERMINATION &&
            bx::is_ray(Ae, qa, la, ha, ext + L.covering(), ext + L.z(), r.z0, ext + L.ray(), tol)) {
            ray = true;
        } else {
            const double ties[2] = {tt, 0.0};
            for (int mode = 1; mode <= 2; ++mode) {
                idx left = limit - pivots;
                if (left <= 0) break;
                r = bx::solve(Ae, qa, la, ha, warm.data(), mode, left, pt, ties[mode - 1], tol,
                              ext, final);
                pivots += std::max<idx>(r.pivots, 0);
                if (r.code == 0 && r.ok) {
                    done = true;
                    break;
                }
                if (lemke::is_stop(r.code)) {
                    stop = r.code;
                    break;
                }
            }
        }
    }
    residual = r.residual;
    std::vector<std::uint8_t> zb(static_cast<std::size_t>(N)), zh(static_cast<std::size_t>(N));
    std::vector<double> zp(static_cast<std::size_t>(N)), wp(static_cast<std::size_t>(N));
    // The point of the final basis from the data, checked (the runs' point failed).
    auto basis_point = [&](const bx::SolveResult& run) {
        for (idx i = 0; i < N; ++i) zb[i] = zh[i] = 0;
        for (idx i = 0; i < run.k; ++i) zb[final[i]] = 1;
        for (idx i = run.k; i < run.m; ++i) zh[final[i]] = 1;
        return bx::basis_point(Ae, qa, la, ha, zb.data(), zh.data(), false, zp.data());
    };
    if (!done && basis_point(r) &&
        bx::box_check(Ae, qa, la, ha, zp.data(), tol, wp.data(), ext + L.row_scale(), 0, residual)) {
        for (idx i = 0; i < N; ++i) {
            ext[L.z() + i] = zp[i];
            ext[L.w() + i] = wp[i];
        }
        done = true;
        ray = false;
    }
    if (!done && !ray && !stop) {  // one restart from the final basis (its flags in zb, zh)
        std::vector<double> kept(buf.begin(), buf.begin() + L.length());
        std::vector<idx> kept_final(ints.begin(), ints.begin() + N);
        std::vector<std::uint8_t> from(static_cast<std::size_t>(2 * N), 0);
        for (idx i = 0; i < N; ++i) {
            from[i] = zb[i];
            from[N + i] = zh[i] && !zb[i];
        }
        bx::SolveResult again = bx::solve(Ae, qa, la, ha, from.data(), 1 | bx::PARTIAL, limit, pt, tt, tol,
                                          ext, final);
        pivots += std::max<idx>(again.pivots, 0);
        if (again.code == 0 && again.ok) {
            r = again;
            residual = r.residual;
            done = true;
        } else {
            std::copy(kept.begin(), kept.end(), buf.begin());
            std::copy(kept_final.begin(), kept_final.end(), ints.begin());
        }
    }
    if (friction) {
        // The answer mapped back and judged on the caller's data; when it fails, the point
        // of the final basis from the extended data, judged again.
        double res = residual;
        bool mapped = front(bx::SOLVED_RUN) == 0;
        if (done && !mapped && basis_point(r)) {
            for (idx i = 0; i < N; ++i) ext[L.z() + i] = zp[i];
            mapped = front(bx::SOLVED_RUN) == 0;
        }
        if (done && !mapped) done = false;
        if (!done) residual = res;
    }
    int status = done ? LEMKE_SOLVED
                 : ray ? LEMKE_RAY_TERMINATION
                 : stop ? stop
                 : (r.code == LEMKE_MAX_PIVOTS || r.code == LEMKE_CYCLING) ? r.code
                                                                            : LEMKE_NUMERICAL_FAILURE;
    const double* zo = buf.data() + (friction ? FL.z() : L.z());
    const double* wo = buf.data() + (friction ? FL.w() : L.w());
    if (z) for (idx i = 0; i < n; ++i) z[i] = zo[i];
    if (z && status == LEMKE_SOLVED && !friction) onto_bounds(z, lo, hi, n);
    if (w) for (idx i = 0; i < n; ++i) w[i] = wo[i];
    if (state_out && n > 0) {  // the final basis's row states (lemke_blcp_solve_warm)
        std::vector<std::int8_t> scratch(static_cast<std::size_t>(N));
        bx::row_states(final, r.k, r.m, n, nf, friction ? findex : nullptr, scratch.data(),
                       state_out);
    }
    if (info) {
        info->status = status;
        info->pivots = pivots;
        info->residual = residual;
        info->warm = 0;
    }
    return status;
}

// A row state's code as lemke_blcp_solve_warm takes it: 0-2 for an ordinary row, 3-29 for
// a friction row (BoxWarmStart.row_states).
bool valid_state(std::int8_t s, bool friction_row) {
    return friction_row ? (s >= lemke::boxed::FRICTION_STATE && s < lemke::boxed::FRICTION_STATE + 27)
                        : (s >= 0 && s <= 2);
}

// lemke_blcp_solve_warm: solve_blcp's one-call runs from the row states (boxed::batch on one
// island: the same calls, the same bits); what they leave undecided, the cold runs of blcp.
int blcp_warm(idx n, const double* M, const double* q, const double* lo, const double* hi,
              const int64_t* findex, const lemke_options* options, std::int8_t* state,
              double* z, double* w, lemke_info* info) {
    namespace bx = lemke::boxed;
    if (state == nullptr) return blcp(n, M, q, lo, hi, findex, options, z, w, info);
    lemke_options o;
    lemke_default_options(&o);
    if (options) o = *options;
    if (n < 0 || (n > 0 && (!M || !q || !lo || !hi)) || !valid_options(o) || n > (idx(1) << 26))
        return LEMKE_INVALID_ARGUMENT;
    bool friction = findex && n > 0;
    idx nf = 0;
    for (idx i = 0; i < n; ++i) {
        bool fr = friction && findex[i] >= 0;
        nf += fr;
        if (!valid_state(state[i], fr)) return LEMKE_INVALID_ARGUMENT;
    }
    lemke::DeadlineScope budget(o.time_limit);
    bx::FrontLayout FL{n, nf, friction};
    idx N = FL.N();
    idx buf_len = FL.length(), ints_len = FL.ints_length();
    std::vector<double> buf(static_cast<std::size_t>(buf_len));
    std::vector<idx> ints(static_cast<std::size_t>(ints_len + 1));
    std::vector<std::int8_t> state_out(static_cast<std::size_t>(n + 1));
    std::vector<idx> no_findex(static_cast<std::size_t>(n + 1), -1);
    const idx mstart[1] = {0}, qoff[2] = {0, n}, buff[2] = {0, buf_len}, ioff[2] = {0, ints_len};
    const idx limit[1] = {o.max_pivots < 0 ? 100 * (N + 1) : o.max_pivots};
    const std::uint8_t fflag[1] = {static_cast<std::uint8_t>(friction)}, wflag[1] = {1};
    idx out_i[7];
    double out_f[1];
    bx::batch(M, mstart, q, lo, hi, qoff, friction ? findex : no_findex.data(), fflag, state,
              wflag, 0, 1, limit, o.pivot_tol, o.tie_tol, o.tol, buf.data(), buff, ints.data(),
              ioff, state_out.data(), out_i, out_f);
    idx stage = out_i[5];
    if (stage < 0)  // undecided (a ray to judge, a failed ladder) or refused data: the cold way
        return blcp(n, M, q, lo, hi, findex, options, z, w, info, state);
    const double* zo = buf.data() + FL.answer();
    const double* wo = buf.data() + FL.answer() + n;  // (w follows z in either layout)
    if (z) for (idx i = 0; i < n; ++i) z[i] = zo[i];
    if (z && !friction) onto_bounds(z, lo, hi, n);
    if (w) for (idx i = 0; i < n; ++i) w[i] = wo[i];
    std::copy(state_out.begin(), state_out.begin() + n, state);
    if (info) {
        info->status = LEMKE_SOLVED;
        info->pivots = out_i[1];
        info->residual = out_f[0];
        info->warm = stage == 0;
    }
    return LEMKE_SOLVED;
}

}  // namespace

namespace {

// An entry point's body with no exception across the C API: info reset first, the status
// the body returns (or OUT_OF_MEMORY / INVALID_ARGUMENT for an exception) written to info.
template <class Body>
int guarded(lemke_info* info, Body body) {
    if (info) {
        info->status = LEMKE_INVALID_ARGUMENT;
        info->pivots = 0;
        info->residual = 0.0;
        info->warm = 0;
    }
    int s;
    try {
        s = body();
    } catch (const std::bad_alloc&) {
        s = LEMKE_OUT_OF_MEMORY;
    } catch (...) {
        s = LEMKE_INVALID_ARGUMENT;
    }
    if (info) info->status = s;
    return s;
}

}  // namespace

extern "C" int lemke_blcp_solve_warm(int64_t n, const double* M, const double* q,
                                     const double* lo, const double* hi, const int64_t* findex,
                                     const lemke_options* options, int8_t* state, double* z,
                                     double* w, lemke_info* info) {
    return guarded(info, [&] {
        return blcp_warm(n, M, q, lo, hi, findex, options, state, z, w, info);
    });
}

extern "C" int lemke_blcp_solve(int64_t n, const double* M, const double* q, const double* lo,
                                const double* hi, const int64_t* findex,
                                const lemke_options* options, double* z, double* w,
                                lemke_info* info) {
    return guarded(info, [&] { return blcp(n, M, q, lo, hi, findex, options, z, w, info); });
}

extern "C" int lemke_lcp_solve(int64_t n, const double* M, const double* q,
                               const lemke_options* options, const int64_t* warm_basis,
                               int64_t n_warm, double* z, double* w, int64_t* basis_out,
                               int64_t* n_basis_out, lemke_info* info) {
    return guarded(info, [&] {
        return solve(n, M, q, options, warm_basis, n_warm, z, w, basis_out, n_basis_out, info);
    });
}
