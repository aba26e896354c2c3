#include "lcp.hpp"

#include <algorithm>
#include <vector>

#include "basis.hpp"
#include "certify.hpp"
#include "ladder.hpp"
#include "pivoting.hpp"
#include "tableau.hpp"
#include "unrevised.hpp"

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
        work.resize(static_cast<std::size_t>(2 * n));
        if (!equilibrate_finite(M, q, v.R, v.C, work.data())) return NOT_FINITE;
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
// clipped at 0 (the seam's LcpBasis::point, basis.hpp). work: at least k (k + 2) doubles.
// `kept`: by solve_gathered_kept (a warm start's old basis: the same bits, the last block's
// factors reused when it repeats), with M's entry `kept_m`.
bool basis_point(Mat<const double> M, const double* q, const idx* beta, idx k, double* z,
                 double* work, bool kept = false, KeptMatrix* kept_m = nullptr) {
    return LcpBasis(M, q, beta, k, work, nullptr, kept ? kept_m : nullptr).point(z);
}

// The first stage of a warm start. Returns 0 (the old basis solves it), 1 (its point fails),
// 2 (its block is singular), -1 (not finite). The finite test rides on the equilibration's
// first sweep (equilibrate_finite: the same test and the same scales as all_finite and
// equilibrate apart), so a basis that still fits costs one pass over M fewer; max |M|, which
// only a restart needs, is left to it. When M or q is not finite, the buffer's scales are
// put back as they were (as the separate finite test, made before any scale was written,
// left them).
int old_basis(Mat<const double> M, const double* q, const double* d, const idx* beta, idx k,
              double tol, const Views& v, idx* basic, double& residual,
              std::vector<double>& work, bool keep) {
    idx n = M.rows;
    residual = 0.0;
    work.resize(static_cast<std::size_t>(std::max(k * (k + 2), 4 * n)));
    double* kept = work.data() + 2 * n;  // (equilibrate's work is the first 2n)
    for (idx i = 0; i < n; ++i) {
        kept[i] = v.R[i];
        kept[n + i] = v.C[i];
    }
    KeptMatrix* kept_m = nullptr;
    if (!(keep ? equilibrate_finite_kept(M, q, v.R, v.C, work.data(), kept_m)
               : equilibrate_finite(M, q, v.R, v.C, work.data()))) {
        for (idx i = 0; i < n; ++i) {
            v.R[i] = kept[i];
            v.C[i] = kept[n + i];
        }
        return -1;
    }
    v.x[n] = 0.0;
    if (!basis_point(M, q, beta, k, v.x, work.data(), keep, kept_m)) return 2;
    if (!check_rows(M, q, v.x, tol, v.w, v.R, work.data(), true, residual)) {
        residual = 0.0;
        return 1;
    }
    for (idx i = 0; i < n; ++i) v.cov[i] = d ? d[i] : 1.0;
    for (idx i = 0; i < n + 1; ++i) v.ray[i] = 0.0;
    for (idx i = 0; i < k; ++i) basic[i] = beta[i];
    return 0;
}

// The result of a warm start's first stage when it decides the solve: found 0 (the old
// basis solves it, 0 pivots, stage 0) or -1 (not finite).
RunResult warm_verdict(int found, idx k, double residual) {
    RunResult out;
    if (found < 0) {
        out.code = NOT_FINITE;
        return out;
    }
    out.code = SOLVED;
    out.k = k;
    out.ok = true;
    out.residual = residual;
    out.stage = 0;
    return out;
}

}  // namespace

RunResult first_run(Mat<const double> M, const double* q, const double* d, const idx* beta,
                    idx k, idx max_pivots, double pivot_tol, double tie_tol, double tol,
                    double* buf, idx* basic, bool keep) {
    thread_local std::vector<double> work;
    thread_local std::vector<std::uint8_t> z_basic;
    RunResult out;
    idx n = M.rows;
    Views v(buf, n);
    if (k > 0) {
        double residual;
        int found = old_basis(M, q, d, beta, k, tol, v, basic, residual, work, keep);
        if (found <= 0) return warm_verdict(found, k, residual);
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
    if (!is_stop(code) &&
        (code == CYCLING || (!ok && (code == RAY_TERMINATION || (d == nullptr && pivots < max_pivots))))) {
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

namespace {

constexpr int RETRIES = 4;
constexpr double PERTURBATION = 1e-6;

// One run of the method from the all-w basis (cold.pivot_once).
Status pivot_once(Method method, Mat<const double> M, const double* q, double tie_tol,
                  idx max_pivots, double pivot_tol, const Views& v, std::uint8_t* z_basic,
                  bool careful, idx& pivots) {
    if (method == TABLEAU)
        return tableau_solve(M, q, v.cov, v.R, v.C, max_pivots, pivot_tol, tie_tol, v.x, v.ray,
                             z_basic, careful, pivots);
    return unrevised_solve(M, q, v.cov, v.R, v.C, nullptr, max_pivots, pivot_tol, tie_tol, v.x,
                           v.ray, z_basic, pivots);
}

struct Run {
    int code;
    idx pivots;
    idx recoveries;
    bool ok;
    double residual;
};

// pivot_once, then the recoveries from a cycle (exact ties; then a perturbed covering
// vector): a ladder (ladder.hpp) whose rungs go on while the run cycles; start 1 goes on after
// first_run's run (code after pivots). Then the check.
Run run_checked(Method method, Mat<const double> M, const double* q, idx max_pivots,
                double pivot_tol, double tie_tol, double tol, const Views& v,
                std::uint8_t* z_basic, bool careful, int start, int code, idx pivots,
                std::vector<double>& work) {
    idx n = M.rows;
    idx recoveries = start - 1;
    ladder::Cap cap{max_pivots, pivots};
    auto once = [&](double tt) {
        recoveries += 1;
        idx p = 0;
        code = pivot_once(method, M, q, tt, cap.left(), pivot_tol, v, z_basic, careful, p);
        cap.charge(p);
    };
    ladder::climb([] { return false; },
                  ladder::rung("the run", [&] { return start == 0; }, [&] { once(tie_tol); }),
                  ladder::rung("exact ties", [&] { return code == CYCLING && !(tie_tol <= 0.0); },
                               [&] { once(0.0); }),
                  ladder::rung("perturbed covering vector", [&] { return code == CYCLING; },
                               [&] {
                                   for (idx i = 0; i < n; ++i)
                                       v.cov[i] *= 1.0 + PERTURBATION * unit_random(label_key(i));
                                   once(0.0);
                               }));
    work.resize(static_cast<std::size_t>(2 * n));
    Run r;
    r.ok = check_rows(M, q, v.x, tol, v.w, v.R, work.data(), false, r.residual);
    r.code = r.ok ? SOLVED : code;
    r.pivots = cap.pivots;
    r.recoveries = recoveries;
    return r;
}

// The covering vector of recovery run `step` into cov; returns whether it uses exact tests.
bool retry_covering(int step, const double* q, const double* R, double* cov, idx n) {
    if (step == 1) {
        double top = 0.0;
        for (idx i = 0; i < n; ++i) top = pmax(top, R[i] * std::fabs(q[i]));
        for (idx i = 0; i < n; ++i)
            cov[i] = top > 0.0 ? pmax(R[i] * std::fabs(q[i]), 1e-3 * top) / R[i] : 1.0 / R[i];
        return true;
    }
    if (step == 2) {
        for (idx i = 0; i < n; ++i) cov[i] = (1.0 + unit_random(label_key(i))) / R[i];
        return false;
    }
    for (idx i = 0; i < n; ++i) cov[i] = 1.0 / R[i];
    return false;
}

// The point of the complementary basis with z_i basic where z_basic[i] into z (and w), and
// the verdict of its check (cold.basis_point_checked).
bool basis_point_checked(Mat<const double> M, const double* q, const std::uint8_t* z_basic,
                         double tol, const double* R, double* z, double* w, double& residual) {
    idx n = M.rows;
    std::vector<idx> beta(static_cast<std::size_t>(n));
    idx k = basic_indices(z_basic, n, beta.data());
    std::vector<double> work(static_cast<std::size_t>(std::max(LcpBasis::work_size(k), 2 * n)));
    residual = 0.0;
    LcpBasis basis(M, q, beta.data(), k, work.data());
    if (!basis.point(z)) return false;
    return basis.check(z, tol, R, w, work.data(), false, residual);
}

bool basis_checks(Mat<const double> M, const double* q, const std::uint8_t* z_basic, double tol,
                  const double* R) {
    idx n = M.rows;
    std::vector<double> zw(static_cast<std::size_t>(2 * n));
    double residual;
    return basis_point_checked(M, q, z_basic, tol, R, zw.data(), zw.data() + n, residual);
}

// Lemke's method restarted from the complementary basis z_start (beta[:k]) by the unrevised
// method with the covering vector c e_alpha - M[:, beta] 1 (cold.restart), its point checked.
idx restart(Mat<const double> M, const double* q, const std::uint8_t* z_start, const idx* beta,
            idx k, double m_max, idx max_pivots, double pivot_tol, double tie_tol, double tol,
            const Views& v, std::uint8_t* z_basic, bool& ok, double& residual, int& code) {
    idx n = M.rows;
    double m_scale = m_max > 0.0 ? m_max : 1.0;
    for (idx i = 0; i < n; ++i) {
        double acc = z_start[i] ? 0.0 : m_scale;
        const double* row = M.row(i);
        for (idx j = 0; j < k; ++j) acc -= row[beta[j]];
        v.cov[i] = acc;
    }
    idx pivots = 0;
    code = unrevised_solve(M, q, v.cov, v.R, v.C, z_start, max_pivots, pivot_tol, tie_tol, v.x,
                           v.ray, z_basic, pivots);
    ok = false;
    residual = 0.0;
    if (code == NUMERICAL_FAILURE && pivots == 0) return pivots;
    std::vector<double> work(static_cast<std::size_t>(2 * n));
    ok = check_rows(M, q, v.x, tol, v.w, v.R, work.data(), false, residual);
    return pivots;
}

// The cold solve with its recoveries. Returns code, pivots, k (basic z's into
// basic), ok, residual, recoveries in a RunResult (stage 2). stop_at_ray: solve_one's
// (lcp.hpp), a first recovery run's ray ends the recoveries.
RunResult checked(Method method, Mat<const double> M, const double* q, const double* d,
                  idx max_pivots, double pivot_tol, double tie_tol, double tol, double* buf,
                  idx* basic, int first_code, idx first_pivots, bool scaled,
                  bool stop_at_ray) {
    thread_local std::vector<double> work;
    thread_local std::vector<std::uint8_t> z_basic;  // (an allocation a call, ~2 % at n = 2)
    idx n = M.rows;
    RunResult out;
    Views v(buf, n);
    z_basic.assign(static_cast<std::size_t>(n), 0);
    int start = 0;
    if (first_code < 0) {
        int code = prologue(M, q, d, v, scaled, work);
        if (code < 0) {
            out.code = code;
            out.ok = code == TRIVIAL;
            return out;
        }
    } else {
        start = 1;
        for (idx i = 0; i < n; ++i) z_basic[i] = basic[i] != 0;
    }
    int code = MAX_PIVOTS;
    bool ok = false;
    double residual = 0.0;
    idx recoveries = 0;
    ladder::Cap cap{max_pivots, 0};
    Method other = method == TABLEAU ? UNREVISED : TABLEAU;
    BufferLayout L{n};
    std::vector<double> buf2;  // the recovery runs' own, allocated only when one runs
    std::vector<std::uint8_t> z_basic2;
    bool have_ray = false, ray_known = false, ray_ok = false;
    bool ended = false;  // a rung ended the climb (a checked ray, a stop, stop_at_ray)
    // A recovery run of the ladder: covering vector `step` (retry_covering), the last by the
    // other method, in its own buffer; taken when it does better than the answer so far.
    auto recovery = [&](int step) {
        if (step == 0) {
            buf2.assign(static_cast<std::size_t>(L.length()), 0.0);
            z_basic2.assign(static_cast<std::size_t>(n), 0);
        }
        std::copy(buf, buf + L.length(), buf2.data());
        Views rv(buf2.data(), n);
        bool exact = retry_covering(step, q, v.R, rv.cov, n);
        Method run_method = step == RETRIES - 1 ? other : method;
        Run r = run_checked(run_method, M, q, cap.left(), exact ? 0.0 : pivot_tol,
                            exact ? 0.0 : tie_tol, tol, rv, z_basic2.data(), true, 0, CYCLING, 0,
                            work);
        cap.pivots += r.pivots;
        recoveries += r.recoveries + 1;
        if (is_stop(r.code)) {  // stopped by its budget: the best answer so far stands
            if (!(code == SOLVED && ok)) code = r.code;
            ended = true;
            return;
        }
        bool take = r.code == SOLVED && (r.ok || code != SOLVED);
        if (!take && r.code == SOLVED && code == SOLVED && !ok &&
            !basis_checks(M, q, z_basic.data(), tol, v.R) &&
            basis_checks(M, q, z_basic2.data(), tol, v.R))
            take = true;  // both failed the check, only this one's basis gives a point
        if (!take && !have_ray && r.code == RAY_TERMINATION &&
            ray_check(M, q, rv.cov, rv.x, rv.x[n], rv.ray, tol, rv.R, rv.C)) {
            take = have_ray = true;
            ray_known = ray_ok = true;
        } else if (take) {
            have_ray = false;
        }
        if (take) {
            std::copy(buf2.begin(), buf2.end(), buf);
            z_basic = z_basic2;
            code = r.code;
            ok = r.ok;
            residual = r.residual;
        }
        if (step == 0 && r.code == RAY_TERMINATION && stop_at_ray) {
            if (!take) {  // (a ray that fails the check here: the answer all the same, unchecked)
                std::copy(buf2.begin(), buf2.end(), buf);
                z_basic = z_basic2;
                code = r.code;
                ok = false;
                residual = r.residual;
                ray_known = true;
                ray_ok = false;
            }
            ended = true;
        }
    };
    // The recovery runs apply without a covering vector given, while pivots are left.
    auto recovers = [&] { return d == nullptr && !cap.spent(); };
    // The final basis of a first run solved on a point that fails the check.
    auto missed = [&] { return code == SOLVED && !ok && d == nullptr; };
    ladder::climb(
        [&] { return (code == SOLVED && ok) || is_stop(code) || ended; },
        ladder::rung("the cold run", ladder::Always{}, [&] {
            Run r = run_checked(method, M, q, cap.left(), pivot_tol, tie_tol, tol, v,
                                z_basic.data(), false, start, first_code, first_pivots, work);
            cap.pivots += r.pivots;
            code = r.code;
            ok = r.ok;
            residual = r.residual;
            recoveries = r.recoveries;
        }),
        ladder::rung("the final basis's point", missed, [&] {
            std::vector<double> zw(static_cast<std::size_t>(2 * n));
            double rb;
            bool okb = basis_point_checked(M, q, z_basic.data(), tol, v.R, zw.data(),
                                           zw.data() + n, rb);
            if (okb) {
                for (idx i = 0; i < n; ++i) {
                    v.x[i] = zw[i];
                    v.w[i] = zw[n + i];
                }
                v.x[n] = 0.0;
                ok = okb;
                residual = rb;
            }
        }),
        ladder::rung("restart from the final basis",
                     [&] { return missed() && n >= RESTART_FROM && !cap.spent(); }, [&] {
            // Lemke's method restarted from that basis, kept only when it passes.
            buf2.assign(buf, buf + L.length());
            z_basic2.assign(static_cast<std::size_t>(n), 0);
            std::vector<idx> beta(static_cast<std::size_t>(n));
            idx kb = basic_indices(z_basic.data(), n, beta.data());
            double m_max;
            finite_absmax(M, m_max);
            bool ok3;
            double r3;
            int code3;
            Views v2(buf2.data(), n);
            idx p3 = restart(M, q, z_basic.data(), beta.data(), kb, m_max, cap.left(), pivot_tol,
                             tie_tol, tol, v2, z_basic2.data(), ok3, r3, code3);
            cap.pivots += p3;
            recoveries += 1;
            if (!ok3 && is_stop(code3)) {
                ok = false;
                code = code3;  // the point stays the first run's, unchecked
            }
            if (ok3) {
                std::copy(buf2.begin(), buf2.end(), buf);
                z_basic = z_basic2;
                ok = ok3;
                residual = r3;
            }
        }),
        ladder::rung("the ray checked", [&] { return recovers() && code == RAY_TERMINATION; },
                     [&] {
                         ray_known = true;
                         ray_ok = ray_check(M, q, v.cov, v.x, v.x[n], v.ray, tol, v.R, v.C);
                         ended = ray_ok;
                     }),
        ladder::rung("covering vector 1/R, careful", recovers, [&] { recovery(0); }),
        ladder::rung("covering vector |q|, exact", recovers, [&] { recovery(1); }),
        ladder::rung("random covering vector", recovers, [&] { recovery(2); }),
        ladder::rung("the other method", recovers, [&] { recovery(3); }));
    idx pivots = cap.pivots;
    if (code == RAY_TERMINATION)
        ok = ray_known ? ray_ok : ray_check(M, q, v.cov, v.x, v.x[n], v.ray, tol, v.R, v.C);
    out.code = code;
    out.pivots = pivots;
    out.k = basic_indices(z_basic.data(), n, basic);
    out.ok = ok;
    out.residual = residual;
    out.recoveries = recoveries;
    return out;
}

}  // namespace

RunResult checked_once(Method method, Mat<const double> M, const double* q, const double* d,
                       idx max_pivots, double pivot_tol, double tie_tol, double tol, double* buf,
                       idx* basic) {
    thread_local std::vector<double> work;
    thread_local std::vector<std::uint8_t> z_basic;
    idx n = M.rows;
    RunResult out;
    Views v(buf, n);
    int code = prologue(M, q, d, v, false, work);
    if (code < 0) {
        out.code = code;
        out.ok = code == TRIVIAL;
        return out;
    }
    z_basic.assign(static_cast<std::size_t>(n), 0);
    Run r = run_checked(method, M, q, max_pivots, pivot_tol, tie_tol, tol, v, z_basic.data(),
                        false, 0, CYCLING, 0, work);
    out.code = r.code;
    out.pivots = r.pivots;
    out.k = basic_indices(z_basic.data(), n, basic);
    out.ok = r.ok;
    out.residual = r.residual;
    out.recoveries = r.recoveries;
    return out;
}

RunResult solve_one(Method method, Mat<const double> M, const double* q, const double* d,
                    const idx* beta, idx k, idx max_pivots, double pivot_tol, double tie_tol,
                    double tol, double* buf, idx* basic, bool keep, bool stop_at_ray) {
    thread_local std::vector<double> work;
    idx n = M.rows;
    Views v(buf, n);
    idx pivots = 0;
    int first_code = -1;
    idx first_pivots = 0;
    bool scaled = false;
    if (k == -1) {
        first_code = static_cast<int>(beta[0]);
        first_pivots = beta[1];
    } else if (k != 0) {
        bool tried = k < 0;
        if (tried) k = -2 - k;
        // the warm start's stages (cold.warm_stages): a ladder whose rung that settles the
        // solve is its stage (0: the old basis's point; 1: the restart from it)
        int found = 1;  // (old_basis's verdict: tried already by first_run, its point failed)
        double residual = 0.0;
        RunResult out;
        bool restarted = false;  // the restart's answer stands (checked, or stopped unchecked)
        int stage = ladder::climb(
            [&] { return found <= 0 || restarted; },
            ladder::rung("the old basis's point", [&] { return !tried; }, [&] {
                found = old_basis(M, q, d, beta, k, tol, v, basic, residual, work, keep);
            }),
            ladder::rung("restart from the old basis",
                         [&] { return found == 1 && n >= RESTART_FROM; }, [&] {
                double m_max;
                finite_absmax(M, m_max);  // (M is finite: old_basis, or first_run's, tested it)
                std::vector<std::uint8_t> flags(static_cast<std::size_t>(2 * n), 0);
                std::uint8_t* z_start = flags.data();
                std::uint8_t* z_basic = flags.data() + n;
                for (idx i = 0; i < k; ++i) z_start[beta[i]] = 1;
                bool ok;
                int code;
                pivots = restart(M, q, z_start, beta, k, m_max, max_pivots, pivot_tol, tie_tol,
                                 tol, v, z_basic, ok, residual, code);
                restarted = ok || is_stop(code);
                if (restarted) {  // checked, or the restart's point, unchecked
                    out.code = ok ? static_cast<int>(SOLVED) : code;
                    out.pivots = pivots;
                    out.k = basic_indices(z_basic, n, basic);
                    out.ok = ok;
                    out.residual = ok ? residual : 0.0;
                }
            }));
        if (found <= 0) return warm_verdict(found, k, residual);
        if (restarted) {
            out.stage = stage;
            return out;
        }
        scaled = true;
    }
    RunResult out = checked(method, M, q, d, std::max<idx>(0, max_pivots - pivots), pivot_tol,
                            tie_tol, tol, buf, basic, first_code, first_pivots, scaled,
                            stop_at_ray);
    out.pivots += pivots;
    out.stage = 2;
    return out;
}

RunResult solve(Method method, Mat<const double> M, const double* q, const double* d,
                const idx* beta, idx k, idx max_pivots, double pivot_tol, double tie_tol,
                double tol, double* buf, idx* basic, bool keep) {
    if (method != TABLEAU)
        return solve_one(method, M, q, d, beta, k, max_pivots, pivot_tol, tie_tol, tol, buf, basic,
                         keep);
    RunResult r = first_run(M, q, d, beta, k, max_pivots, pivot_tol, tie_tol, tol, buf, basic,
                            keep);
    if (r.stage >= 0) return r;
    idx n = M.rows;
    if (r.stage == -1 && r.code == RAY_TERMINATION) {
        Views v(buf, n);
        if (ray_check(M, q, v.cov, v.x, v.x[n], v.ray, tol, v.R, v.C)) {
            idx kk = 0;  // the flags in basic to indices, in place (kk <= i)
            for (idx i = 0; i < n; ++i)
                if (basic[i] != 0) basic[kk++] = i;
            r.k = kk;
            r.ok = true;
            r.stage = 2;
            return r;
        }
    }
    if (r.stage == -1) {
        idx resume[2] = {r.code, r.pivots};
        return solve_one(method, M, q, d, resume, -1, max_pivots, pivot_tol, tie_tol, tol, buf,
                         basic);
    }
    return solve_one(method, M, q, d, beta, -2 - k, max_pivots, pivot_tol, tie_tol, tol, buf,
                     basic);
}

void batch(Method method, const double* Ms, const idx* mstart, const double* qs, const idx* qoff,
           const idx* beta, const idx* boff, idx lo, idx hi, const idx* max_pivots,
           double pivot_tol, double tie_tol, double tol, double* bufs, const idx* buff,
           idx* basics, idx* out_i, double* out_f) {
    std::uint64_t seen = interrupts_seen();
    for (idx b = lo; b < hi; ++b) {
        idx n = qoff[b + 1] - qoff[b];
        Mat<const double> M(Ms + mstart[b], n, n);
        RunResult r;
        if (interrupts_seen() != seen) {  // interrupted: the rest are not run (zeros)
            double* buf = bufs + buff[b];
            for (idx i = 0; i < BufferLayout{n}.length(); ++i) buf[i] = 0.0;
            for (idx i = 0; i < n; ++i) basics[qoff[b] + i] = 0;
            r.code = INTERRUPTED;
        } else
        r = solve(method, M, qs + qoff[b], nullptr, beta + boff[b], boff[b + 1] - boff[b],
                            max_pivots[b], pivot_tol, tie_tol, tol, bufs + buff[b], basics + qoff[b],
                            false);
        idx* oi = out_i + 5 * b;
        oi[0] = r.code;
        oi[1] = r.pivots;
        oi[2] = r.k;
        oi[3] = r.recoveries;
        oi[4] = r.stage;
        out_f[2 * b] = r.ok ? 1.0 : 0.0;
        out_f[2 * b + 1] = r.residual;
    }
}

}  // namespace lemke
