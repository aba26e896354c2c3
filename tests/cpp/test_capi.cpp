// The C API's test (run by ctest, and by tests/test_capi.py under the sanitizers): known
// answers, random problems checked by an independent complementarity check, warm starts,
// and every kind of bad argument. With an argument, a file of problems written by
// tests/test_capi.py ("n", then M row-major, then q, per problem): each is solved and one
// line "status pivots checked z..." printed per problem, so the test can compare them with Python's.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <random>
#include <thread>
#include <vector>

#include "lemke.h"

static int failures = 0;
#define EXPECT(cond)                                                        \
    do {                                                                    \
        if (!(cond)) {                                                      \
            std::fprintf(stderr, "%s:%d: failed: %s\n", __FILE__, __LINE__, #cond); \
            ++failures;                                                     \
        }                                                                   \
    } while (0)

// z >= 0, w = M z + q >= 0, z'w = 0 to a tolerance relative to the data: computed here,
// not by the library.
static bool complementary(int64_t n, const double* M, const double* q, const double* z) {
    double scale = 1.0;
    for (int64_t i = 0; i < n * n; ++i) scale = std::fmax(scale, std::fabs(M[i]));
    for (int64_t i = 0; i < n; ++i) scale = std::fmax(scale, std::fabs(q[i]));
    double zmax = 1.0;
    for (int64_t i = 0; i < n; ++i) zmax = std::fmax(zmax, std::fabs(z[i]));
    double tol = 1e-8 * scale * zmax;
    for (int64_t i = 0; i < n; ++i) {
        long double w = q[i];
        for (int64_t j = 0; j < n; ++j) w += (long double)M[i * n + j] * z[j];
        if (z[i] < 0.0 || w < -tol) return false;
        if (std::fabs((double)(w * z[i])) > tol * zmax) return false;
    }
    return true;
}

static void known_answer() {
    const double M[9] = {0, -1, 2, 2, 0, -2, -1, 1, 0};
    const double q[3] = {-3, 6, -1};
    double z[3], w[3];
    int64_t basis[3], k = -1;
    lemke_info info;
    int s = lemke_lcp_solve(3, M, q, nullptr, nullptr, 0, z, w, basis, &k, &info);
    EXPECT(s == LEMKE_SOLVED && info.status == s);
    EXPECT(z[0] == 0.0 && z[1] == 1.0 && z[2] == 3.0);
    EXPECT(w[0] == 2.0 && w[1] == 0.0 && w[2] == 0.0);
    EXPECT(info.pivots == 5 && k == 2 && basis[0] == 1 && basis[1] == 2);
    // The article's degenerate example: M = [[4, -4], [-4, 4]], q = [2, -2]: z = (0, 0.5).
    const double M2[4] = {4, -4, -4, 4};
    const double q2[2] = {2, -2};
    s = lemke_lcp_solve(2, M2, q2, nullptr, nullptr, 0, z, w, nullptr, nullptr, &info);
    EXPECT(s == LEMKE_SOLVED && z[0] == 0.0 && std::fabs(z[1] - 0.5) < 1e-15);
    // q >= 0: z = 0 with no pivot; n = 0.
    const double q3[2] = {1, 0};
    s = lemke_lcp_solve(2, M2, q3, nullptr, nullptr, 0, z, w, basis, &k, &info);
    EXPECT(s == LEMKE_SOLVED && z[0] == 0.0 && z[1] == 0.0 && info.pivots == 0 && k == 0);
    s = lemke_lcp_solve(0, nullptr, nullptr, nullptr, nullptr, 0, nullptr, nullptr, nullptr,
                        nullptr, &info);
    EXPECT(s == LEMKE_SOLVED);
    // An infeasible LCP (M = 0, q < 0): a ray, never a success.
    const double Z[1] = {0.0};
    const double qn[1] = {-1.0};
    s = lemke_lcp_solve(1, Z, qn, nullptr, nullptr, 0, z, w, nullptr, nullptr, &info);
    EXPECT(s == LEMKE_RAY_TERMINATION);
}

static void random_problems() {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    int solved = 0;
    for (int t = 0; t < 300; ++t) {
        int64_t n = 1 + t % 40;
        std::vector<double> A(n * n), M(n * n), q(n), z(n), w(n), z2(n);
        for (auto& a : A) a = g(rng);
        for (int64_t i = 0; i < n; ++i)  // M = A A' + 0.01 I: positive definite, always solvable
            for (int64_t j = 0; j < n; ++j) {
                double s = 0.0;
                for (int64_t l = 0; l < n; ++l) s += A[i * n + l] * A[j * n + l];
                M[i * n + j] = s + (i == j ? 0.01 : 0.0);
            }
        for (auto& v : q) v = g(rng);
        std::vector<int64_t> basis(n);
        int64_t k = 0;
        lemke_info info;
        int s = lemke_lcp_solve(n, M.data(), q.data(), nullptr, nullptr, 0, z.data(), w.data(),
                                basis.data(), &k, &info);
        EXPECT(s == LEMKE_SOLVED);
        if (s != LEMKE_SOLVED) continue;
        EXPECT(complementary(n, M.data(), q.data(), z.data()));
        ++solved;
        // The same problem warm from its own basis: zero pivots (an empty basis, q >= 0: cold
        // and trivial, so not counted as warm).
        s = lemke_lcp_solve(n, M.data(), q.data(), nullptr, basis.data(), k, z2.data(), nullptr,
                            nullptr, nullptr, &info);
        EXPECT(s == LEMKE_SOLVED && info.pivots == 0 && info.warm == (k > 0 ? 1 : 0));
        // A moved q, warm: solved and checked whatever the old basis does.
        for (auto& v : q) v += 0.05 * g(rng);
        s = lemke_lcp_solve(n, M.data(), q.data(), nullptr, basis.data(), k, z2.data(), nullptr,
                            nullptr, nullptr, &info);
        EXPECT(s == LEMKE_SOLVED && complementary(n, M.data(), q.data(), z2.data()));
    }
    EXPECT(solved == 300);
}

static void bad_arguments() {
    const double M[4] = {2, 1, 1, 2};
    const double q[2] = {-1, -1};
    double z[2];
    lemke_info info;
    EXPECT(lemke_lcp_solve(-1, M, q, nullptr, nullptr, 0, z, nullptr, nullptr, nullptr, &info) ==
           LEMKE_INVALID_ARGUMENT);
    EXPECT(info.status == LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_lcp_solve(2, nullptr, q, nullptr, nullptr, 0, z, nullptr, nullptr, nullptr,
                           nullptr) == LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_lcp_solve(2, M, nullptr, nullptr, nullptr, 0, z, nullptr, nullptr, nullptr,
                           nullptr) == LEMKE_INVALID_ARGUMENT);
    const int64_t out_of_range[1] = {2};
    EXPECT(lemke_lcp_solve(2, M, q, nullptr, out_of_range, 1, z, nullptr, nullptr, nullptr,
                           nullptr) == LEMKE_INVALID_ARGUMENT);
    const int64_t twice[2] = {1, 1};
    EXPECT(lemke_lcp_solve(2, M, q, nullptr, twice, 2, z, nullptr, nullptr, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_lcp_solve(2, M, q, nullptr, nullptr, 1, z, nullptr, nullptr, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_lcp_solve(2, M, q, nullptr, twice, 3, z, nullptr, nullptr, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    lemke_options o;
    lemke_default_options(&o);
    o.tol = std::nan("");
    EXPECT(lemke_lcp_solve(2, M, q, &o, nullptr, 0, z, nullptr, nullptr, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    const double Mn[4] = {2, std::nan(""), 1, 2};
    EXPECT(lemke_lcp_solve(2, Mn, q, nullptr, nullptr, 0, z, nullptr, nullptr, nullptr, nullptr) ==
           LEMKE_NOT_FINITE);
    const double qi[2] = {-1, -INFINITY};
    EXPECT(lemke_lcp_solve(2, M, qi, nullptr, nullptr, 0, z, nullptr, nullptr, nullptr, nullptr) ==
           LEMKE_NOT_FINITE);
    lemke_default_options(&o);
    o.max_pivots = 1;  // a cap reached: reported, never a success
    EXPECT(lemke_lcp_solve(2, M, q, &o, nullptr, 0, z, nullptr, nullptr, nullptr, &info) ==
           LEMKE_MAX_PIVOTS);
    EXPECT(std::string_view(lemke_status_name(LEMKE_CYCLING)) == "CYCLING");
    EXPECT(std::string_view(lemke_status_name(12345)) == "UNKNOWN");
}

// A box LCP's answer checked here, not by the library: lo <= z <= hi (with a friction index,
// the bounds in force lo_i z_f, hi_i z_f) and w = M z + q (long double) with w_i <= tol off
// the lower bound, w_i >= -tol off the upper one, tol relative to the data and z.
static bool box_solution(int64_t n, const double* M, const double* q, const double* lo,
                         const double* hi, const int64_t* findex, const double* z) {
    double scale = 1.0, zmax = 1.0;
    for (int64_t i = 0; i < n * n; ++i) scale = std::fmax(scale, std::fabs(M[i]));
    for (int64_t i = 0; i < n; ++i) scale = std::fmax(scale, std::fabs(q[i]));
    for (int64_t i = 0; i < n; ++i) zmax = std::fmax(zmax, std::fabs(z[i]));
    double tol = 1e-8 * scale * zmax;
    for (int64_t i = 0; i < n; ++i) {
        double l = lo[i], h = hi[i];
        if (findex && findex[i] >= 0) {
            l = lo[i] * z[findex[i]];
            h = hi[i] * z[findex[i]];
        }
        if (!std::isfinite(z[i]) || z[i] < l - tol || z[i] > h + tol) return false;
        long double w = q[i];
        for (int64_t j = 0; j < n; ++j) w += (long double)M[i * n + j] * z[j];
        if (l == h) continue;
        bool at_lo = z[i] <= l + tol, at_hi = z[i] >= h - tol;
        if (!at_lo && w > tol) return false;
        if (!at_hi && w < -tol) return false;
    }
    return true;
}

static void box_known_answers() {
    // solve_blcp's docstring example: z = (2, -1).
    const double M[4] = {2, 1, 1, 2};
    const double q[2] = {-5, 1};
    const double lo[2] = {0, -1}, hi[2] = {2, 1};
    double z[2], w[2];
    lemke_info info;
    int s = lemke_blcp_solve(2, M, q, lo, hi, nullptr, nullptr, z, w, &info);
    EXPECT(s == LEMKE_SOLVED && info.status == s && z[0] == 2.0 && z[1] == -1.0);
    EXPECT(w[0] == -2.0 && w[1] == 1.0 && info.warm == 0);
    // An LCP is the box LCP with lo = 0, hi = +inf: the same answer as lemke_lcp_solve.
    const double Ml[9] = {0, -1, 2, 2, 0, -2, -1, 1, 0};
    const double ql[3] = {-3, 6, -1};
    const double zero[3] = {0, 0, 0}, inf[3] = {INFINITY, INFINITY, INFINITY};
    double zl[3], zb[3];
    lemke_lcp_solve(3, Ml, ql, nullptr, nullptr, 0, zl, nullptr, nullptr, nullptr, nullptr);
    s = lemke_blcp_solve(3, Ml, ql, zero, inf, nullptr, nullptr, zb, nullptr, &info);
    EXPECT(s == LEMKE_SOLVED && zb[0] == zl[0] && zb[1] == zl[1] && zb[2] == zl[2]);
    // Free and fixed variables.
    const double Mf[9] = {2, 1, 0, 1, 2, 1, 0, 1, 2};
    const double qf[3] = {-1, 3, -2};
    const double lof[3] = {-INFINITY, 0.5, 0.0}, hif[3] = {INFINITY, 0.5, INFINITY};
    double zf[3], wf[3];
    s = lemke_blcp_solve(3, Mf, qf, lof, hif, nullptr, nullptr, zf, wf, &info);
    EXPECT(s == LEMKE_SOLVED && zf[1] == 0.5 && std::fabs(wf[0]) < 1e-12);
    EXPECT(box_solution(3, Mf, qf, lof, hif, nullptr, zf));
    // No solution (M = 0, w = q has the wrong sign at both bounds of z_0 >= 0): a checked ray.
    const double Z[4] = {0, 0, 0, 0};
    const double qn[2] = {-1, 1};
    const double lo0[2] = {0, 0}, hiinf[2] = {INFINITY, INFINITY};
    s = lemke_blcp_solve(2, Z, qn, lo0, hiinf, nullptr, nullptr, z, nullptr, &info);
    EXPECT(s == LEMKE_RAY_TERMINATION);
    // Friction (a normal row and its friction row, mu = 0.5): sticking and sliding.
    const int64_t findex[2] = {-1, 0};
    const double Mc[4] = {2.0, 0.5, 0.5, 1.0};
    const double loc[2] = {0.0, -0.5}, hic[2] = {INFINITY, 0.5};
    const double stick[2] = {-1.0, -0.2}, slide[2] = {-1.0, -2.0};
    s = lemke_blcp_solve(2, Mc, stick, loc, hic, findex, nullptr, z, w, &info);
    EXPECT(s == LEMKE_SOLVED && box_solution(2, Mc, stick, loc, hic, findex, z));
    EXPECT(std::fabs(w[1]) < 1e-12 && std::fabs(z[1]) < 0.5 * z[0]);
    s = lemke_blcp_solve(2, Mc, slide, loc, hic, findex, nullptr, z, w, &info);
    EXPECT(s == LEMKE_SOLVED && box_solution(2, Mc, slide, loc, hic, findex, z));
    EXPECT(std::fabs(z[1] - 0.5 * z[0]) < 1e-12 && w[1] < 0.0);
    // n = 0.
    s = lemke_blcp_solve(0, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
                         nullptr, &info);
    EXPECT(s == LEMKE_SOLVED);
}

// lemke_blcp_solve_warm: a step solved cold from cold row states, then the next step (q
// moved a little) warm from the states it returned: the old basis still solves it (0
// pivots, info.warm); a step whose basis no longer fits still solves; contacts with
// friction (2 contacts: normal rows 0 and 2, friction rows 1 and 3); bad states refused.
static void box_warm() {
    const double M[16] = {2.0, 0.5, 0.1, 0.0, 0.5, 1.0, 0.0, 0.1,
                          0.1, 0.0, 2.0, 0.5, 0.0, 0.1, 0.5, 1.0};
    const double lo[4] = {0.0, -0.5, 0.0, -0.5}, hi[4] = {INFINITY, 0.5, INFINITY, 0.5};
    const int64_t fi[4] = {-1, 0, -1, 2};
    const double q1[4] = {-1.0, 0.3, -1.0, -0.2};
    const double q2[4] = {-1.0 - 1e-9, 0.3, -1.0, -0.2 + 1e-9};
    const double q3[4] = {-1.0, -2.0, 0.5, -0.2};  // another contact state: sliding, lifted
    double z[4], w[4];
    lemke_info info;
    int8_t state[4] = {0, 3, 0, 3};  // cold
    EXPECT(lemke_blcp_solve_warm(4, M, q1, lo, hi, fi, nullptr, state, z, w, &info) ==
           LEMKE_SOLVED);
    EXPECT(box_solution(4, M, q1, lo, hi, fi, z) && info.warm == 0);
    EXPECT(state[0] >= 0 && state[0] <= 2 && state[1] >= 3 && state[1] < 30);
    EXPECT(lemke_blcp_solve_warm(4, M, q2, lo, hi, fi, nullptr, state, z, w, &info) ==
           LEMKE_SOLVED);
    EXPECT(box_solution(4, M, q2, lo, hi, fi, z) && info.warm == 1 && info.pivots == 0);
    EXPECT(lemke_blcp_solve_warm(4, M, q3, lo, hi, fi, nullptr, state, z, w, &info) ==
           LEMKE_SOLVED);
    EXPECT(box_solution(4, M, q3, lo, hi, fi, z) && info.warm == 0);
    // the same as a cold solve's answer where the cold solve decides (NULL state: cold)
    double zc[4];
    EXPECT(lemke_blcp_solve_warm(4, M, q3, lo, hi, fi, nullptr, nullptr, zc, nullptr, &info) ==
           LEMKE_SOLVED);
    EXPECT(box_solution(4, M, q3, lo, hi, fi, zc));
    // without friction: random box problems, warm from their own states after q moves
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g;
    for (int t = 0; t < 200; ++t) {
        int64_t n = 1 + static_cast<int64_t>(rng() % 12);
        std::vector<double> A(n * n), B(n * n, 0.0), q(n), l(n), h(n), zz(n);
        for (auto& v : A) v = g(rng);
        for (int64_t i = 0; i < n; ++i)
            for (int64_t j = 0; j < n; ++j) {
                for (int64_t k = 0; k < n; ++k) B[i * n + j] += A[i * n + k] * A[j * n + k];
                if (i == j) B[i * n + j] += 0.1;
            }
        for (int64_t i = 0; i < n; ++i) {
            q[i] = g(rng);
            l[i] = rng() % 3 == 0 ? -INFINITY : -std::fabs(g(rng));
            h[i] = rng() % 3 == 0 ? INFINITY : std::fabs(g(rng));
        }
        std::vector<int8_t> s(n, 0);
        int r1 = lemke_blcp_solve_warm(n, B.data(), q.data(), l.data(), h.data(), nullptr,
                                       nullptr, s.data(), zz.data(), nullptr, &info);
        EXPECT(r1 == LEMKE_SOLVED && box_solution(n, B.data(), q.data(), l.data(), h.data(),
                                                  nullptr, zz.data()));
        for (auto& v : q) v += 1e-10 * g(rng);
        int r2 = lemke_blcp_solve_warm(n, B.data(), q.data(), l.data(), h.data(), nullptr,
                                       nullptr, s.data(), zz.data(), nullptr, &info);
        EXPECT(r2 == LEMKE_SOLVED && box_solution(n, B.data(), q.data(), l.data(), h.data(),
                                                  nullptr, zz.data()));
        for (auto& v : q) v = g(rng);  // another step: the old basis rarely fits
        int r3 = lemke_blcp_solve_warm(n, B.data(), q.data(), l.data(), h.data(), nullptr,
                                       nullptr, s.data(), zz.data(), nullptr, &info);
        EXPECT(r3 == LEMKE_SOLVED && box_solution(n, B.data(), q.data(), l.data(), h.data(),
                                                  nullptr, zz.data()));
    }
    int8_t bad[4] = {0, 2, 0, 3};  // a friction row with an ordinary row's state
    EXPECT(lemke_blcp_solve_warm(4, M, q1, lo, hi, fi, nullptr, bad, z, w, &info) ==
           LEMKE_INVALID_ARGUMENT);
    int8_t bad2[4] = {7, 3, 0, 3};  // an ordinary row's state out of range
    EXPECT(lemke_blcp_solve_warm(4, M, q1, lo, hi, fi, nullptr, bad2, z, w, &info) ==
           LEMKE_INVALID_ARGUMENT);
    int8_t bad3[2] = {3, 0};  // a friction state without a friction index
    EXPECT(lemke_blcp_solve_warm(2, M, q1, lo, hi, nullptr, nullptr, bad3, z, w, &info) ==
           LEMKE_INVALID_ARGUMENT);
}

static void box_random_problems() {
    std::mt19937_64 rng(11);
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int solved = 0;
    for (int t = 0; t < 200; ++t) {
        int64_t n = 1 + t % 30;
        bool friction = t % 3 == 0 && n >= 2;
        std::vector<double> A(n * n), M(n * n), q(n), lo(n), hi(n), z(n), w(n);
        std::vector<int64_t> findex(n, -1);
        for (auto& a : A) a = g(rng);
        for (int64_t i = 0; i < n; ++i)  // positive definite: always solvable
            for (int64_t j = 0; j < n; ++j) {
                double s = 0.0;
                for (int64_t l = 0; l < n; ++l) s += A[i * n + l] * A[j * n + l];
                M[i * n + j] = s + (i == j ? 0.01 : 0.0);
            }
        for (int64_t i = 0; i < n; ++i) {
            q[i] = 3 * g(rng);
            lo[i] = -2 * u(rng);
            hi[i] = 2 * u(rng);
            if (t % 4 == 1 && u(rng) < 0.3) lo[i] = -INFINITY;  // one-sided, free
            if (t % 4 == 1 && u(rng) < 0.3) hi[i] = INFINITY;
            if (u(rng) < 0.1) hi[i] = lo[i] = std::isfinite(lo[i]) ? lo[i] : 0.25;  // fixed
        }
        if (friction)  // pairs (normal 2c, friction 2c + 1)
            for (int64_t c = 0; 2 * c + 1 < n; ++c) {
                lo[2 * c] = 0.0;
                hi[2 * c] = INFINITY;
                double mu = u(rng);
                lo[2 * c + 1] = -mu;
                hi[2 * c + 1] = mu;
                findex[2 * c + 1] = 2 * c;
            }
        lemke_info info;
        int s = lemke_blcp_solve(n, M.data(), q.data(), lo.data(), hi.data(),
                                 friction ? findex.data() : nullptr, nullptr, z.data(), w.data(),
                                 &info);
        EXPECT(s == LEMKE_SOLVED);
        if (s != LEMKE_SOLVED) continue;
        EXPECT(box_solution(n, M.data(), q.data(), lo.data(), hi.data(),
                            friction ? findex.data() : nullptr, z.data()));
        ++solved;
    }
    EXPECT(solved == 200);
}

static void box_bad_arguments() {
    const double M[4] = {2, 1, 1, 2};
    const double q[2] = {-1, -1};
    const double lo[2] = {0, 0}, hi[2] = {1, 1};
    double z[2];
    lemke_info info;
    EXPECT(lemke_blcp_solve(-1, M, q, lo, hi, nullptr, nullptr, z, nullptr, &info) ==
           LEMKE_INVALID_ARGUMENT && info.status == LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_blcp_solve(2, M, q, nullptr, hi, nullptr, nullptr, z, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_blcp_solve(2, M, q, lo, nullptr, nullptr, nullptr, z, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    const double bad_lo[2] = {2, 0};  // lo > hi
    EXPECT(lemke_blcp_solve(2, M, q, bad_lo, hi, nullptr, nullptr, z, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    const double inf_lo[2] = {INFINITY, 0}, inf_hi[2] = {INFINITY, 1};
    EXPECT(lemke_blcp_solve(2, M, q, inf_lo, inf_hi, nullptr, nullptr, z, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    const double nan_lo[2] = {std::nan(""), 0};
    EXPECT(lemke_blcp_solve(2, M, q, nan_lo, hi, nullptr, nullptr, z, nullptr, nullptr) ==
           LEMKE_NOT_FINITE);
    const double qi[2] = {-1, INFINITY};
    EXPECT(lemke_blcp_solve(2, M, qi, lo, hi, nullptr, nullptr, z, nullptr, nullptr) ==
           LEMKE_NOT_FINITE);
    const double flo[2] = {0, -1}, fhi[2] = {INFINITY, 1};
    const int64_t self[2] = {-1, 1}, out[2] = {-1, 2}, chain[2] = {1, 0}, neg[2] = {-1, -2};
    for (const int64_t* f : {self, out, chain, neg})
        EXPECT(lemke_blcp_solve(2, M, q, flo, fhi, f, nullptr, z, nullptr, nullptr) ==
               LEMKE_INVALID_ARGUMENT);
    const int64_t ok[2] = {-1, 0};
    const double asym_lo[2] = {0, -2};  // a friction row needs lo = -hi
    EXPECT(lemke_blcp_solve(2, M, q, asym_lo, fhi, ok, nullptr, z, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
    EXPECT(lemke_blcp_solve(2, M, q, flo, fhi, ok, nullptr, z, nullptr, nullptr) == LEMKE_SOLVED);
    lemke_options o;
    lemke_default_options(&o);
    o.tie_tol = -1.0;
    EXPECT(lemke_blcp_solve(2, M, q, lo, hi, nullptr, &o, z, nullptr, nullptr) ==
           LEMKE_INVALID_ARGUMENT);
}

// Budgets: Murty's problem at n = 26 takes 2^26 pivots (seconds): a time limit ends it with
// TIME_LIMIT after some pivots (none with a zero budget), lemke_interrupt() from another
// thread with INTERRUPTED; neither sticks to the next solve.
static void budgets() {
    const int64_t n = 26;
    std::vector<double> M(n * n, 0.0), q(n), lo(n, 0.0), hi(n, INFINITY), z(n);
    for (int64_t i = 0; i < n; ++i) {
        M[i * n + i] = 1.0;
        for (int64_t j = i + 1; j < n; ++j) M[i * n + j] = 2.0;
        q[i] = -(std::ldexp(1.0, n + 1) - std::ldexp(1.0, i + 1));
    }
    lemke_options o;
    lemke_default_options(&o);
    o.max_pivots = int64_t(1) << 40;
    lemke_info info;
    // 0.25 s, not less: the deadline is on the wall clock from the call, and on a busy
    // machine a process can wait longer than 10 ms before its first pivot (seen at load 14:
    // TIME_LIMIT with no pivot made)
    o.time_limit = 0.25;
    EXPECT(lemke_lcp_solve(n, M.data(), q.data(), &o, nullptr, 0, z.data(), nullptr, nullptr,
                           nullptr, &info) == LEMKE_TIME_LIMIT);
    EXPECT(info.status == LEMKE_TIME_LIMIT && info.pivots > 0);
    EXPECT(lemke_blcp_solve(n, M.data(), q.data(), lo.data(), hi.data(), nullptr, &o, z.data(),
                            nullptr, &info) == LEMKE_TIME_LIMIT);
    EXPECT(info.pivots > 0);
    o.time_limit = 0.0;
    EXPECT(lemke_lcp_solve(n, M.data(), q.data(), &o, nullptr, 0, z.data(), nullptr, nullptr,
                           nullptr, &info) == LEMKE_TIME_LIMIT);
    EXPECT(info.pivots == 0);
    o.time_limit = std::nan("");
    EXPECT(lemke_lcp_solve(n, M.data(), q.data(), &o, nullptr, 0, z.data(), nullptr, nullptr,
                           nullptr, &info) == LEMKE_INVALID_ARGUMENT);
    o.time_limit = -1.0;
    std::thread stopper([] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        lemke_interrupt();
    });
    int s = lemke_lcp_solve(n, M.data(), q.data(), &o, nullptr, 0, z.data(), nullptr, nullptr,
                            nullptr, &info);
    stopper.join();
    EXPECT(s == LEMKE_INTERRUPTED && info.pivots > 0);
    EXPECT(std::string_view(lemke_status_name(LEMKE_INTERRUPTED)) == "INTERRUPTED");
    o.max_pivots = -1;  // the next solve is not interrupted: n = 4 solves
    int64_t small = 4;
    std::vector<double> M4(small * small, 0.0), q4(small);
    for (int64_t i = 0; i < small; ++i) {
        M4[i * small + i] = 1.0;
        for (int64_t j = i + 1; j < small; ++j) M4[i * small + j] = 2.0;
        q4[i] = -(std::ldexp(1.0, small + 1) - std::ldexp(1.0, i + 1));
    }
    EXPECT(lemke_lcp_solve(small, M4.data(), q4.data(), &o, nullptr, 0, z.data(), nullptr,
                           nullptr, nullptr, &info) == LEMKE_SOLVED);
    EXPECT(complementary(small, M4.data(), q4.data(), z.data()));
}

// Solve every box LCP of a table file written by tests/test_capi.py ("n f", M, q, lo, hi,
// and with f = 1 findex); print "status pivots checked" and z as hexadecimal floats.
static int box_table(const char* path, bool warm) {
    std::FILE* f = std::fopen(path, "r");
    if (!f) {
        std::fprintf(stderr, "cannot open %s\n", path);
        return 2;
    }
    long long n;
    int has_findex;
    while (std::fscanf(f, "%lld %d", &n, &has_findex) == 2) {
        std::vector<double> M(n * n), q(n), lo(n), hi(n), z(n), w(n);
        std::vector<int64_t> findex(n, -1);
        for (auto* a : {&M, &q, &lo, &hi})
            for (auto& v : *a) if (std::fscanf(f, "%lf", &v) != 1) return 2;
        if (has_findex)
            for (auto& v : findex) {
                long long x;
                if (std::fscanf(f, "%lld", &x) != 1) return 2;
                v = x;
            }
        const int64_t* fi = has_findex ? findex.data() : nullptr;
        std::vector<int8_t> state(n + 1);
        if (warm)  // then the row states to start from (lemke_blcp_solve_warm)
            for (int64_t i = 0; i < n; ++i) {
                int x;
                if (std::fscanf(f, "%d", &x) != 1) return 2;
                state[i] = static_cast<int8_t>(x);
            }
        lemke_info info;
        int s = warm ? lemke_blcp_solve_warm(n, M.data(), q.data(), lo.data(), hi.data(), fi,
                                             nullptr, state.data(), z.data(), w.data(), &info)
                     : lemke_blcp_solve(n, M.data(), q.data(), lo.data(), hi.data(), fi, nullptr,
                                        z.data(), w.data(), &info);
        bool checked = s != LEMKE_SOLVED || box_solution(n, M.data(), q.data(), lo.data(),
                                                         hi.data(), fi, z.data());
        std::printf("%d %lld %d", s, (long long)info.pivots, checked ? 1 : 0);
        for (auto v : z) std::printf(" %a", v);
        std::printf("\n");
    }
    std::fclose(f);
    return 0;
}

// Solve every problem of a table file; print "status pivots" per problem.
static int table(const char* path) {
    std::FILE* f = std::fopen(path, "r");
    if (!f) {
        std::fprintf(stderr, "cannot open %s\n", path);
        return 2;
    }
    long long n;
    while (std::fscanf(f, "%lld", &n) == 1) {
        std::vector<double> M(n * n), q(n), z(n), w(n);
        for (auto& v : M) if (std::fscanf(f, "%lf", &v) != 1) return 2;
        for (auto& v : q) if (std::fscanf(f, "%lf", &v) != 1) return 2;
        lemke_info info;
        int s = lemke_lcp_solve(n, M.data(), q.data(), nullptr, nullptr, 0, z.data(), w.data(),
                                nullptr, nullptr, &info);
        bool checked = s != LEMKE_SOLVED || complementary(n, M.data(), q.data(), z.data());
        std::printf("%d %lld %d", s, (long long)info.pivots, checked ? 1 : 0);
        for (long long i = 0; i < n; ++i) std::printf(" %.17g", z[i]);
        std::printf("\n");
    }
    std::fclose(f);
    return 0;
}

int main(int argc, char** argv) {
    if (argc > 2 && std::string_view(argv[1]) == "--blcp") return box_table(argv[2], false);
    if (argc > 2 && std::string_view(argv[1]) == "--blcp-warm") return box_table(argv[2], true);
    if (argc > 1 && std::string_view(argv[1]) != "-") return table(argv[1]);
    known_answer();
    random_problems();
    bad_arguments();
    box_known_answers();
    box_random_problems();
    box_bad_arguments();
    box_warm();
    budgets();
    if (failures) {
        std::fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    std::printf("C API: all checks passed\n");
    return 0;
}
