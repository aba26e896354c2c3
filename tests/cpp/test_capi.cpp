// The C API's test (run by ctest, and by tests/test_capi.py under the sanitizers): known
// answers, random problems checked by an independent complementarity check, warm starts,
// and every kind of bad argument. With an argument, a file of problems written by
// tests/test_capi.py ("n", then M row-major, then q, per problem): each is solved and one
// line "status pivots checked z..." printed per problem, so the test can compare them with Python's.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <random>
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
    if (argc > 1 && std::string_view(argv[1]) != "-") return table(argv[1]);
    known_answer();
    random_problems();
    bad_arguments();
    if (failures) {
        std::fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    std::printf("C API: all checks passed\n");
    return 0;
}
