// A seeded random driver for the C API (run under AddressSanitizer and UBSan by
// tests/test_capi.py): random, degenerate, non-finite and mis-sized input for a given
// number of rounds. Passes when nothing crashes, leaks or reads out of bounds (the
// sanitizers), every status is one of the documented codes, and a SOLVED answer is
// non-negative. Each round's arrays are allocated at exactly the size the call is told, so
// a read past them is caught.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <utility>
#include <random>
#include <vector>

#include "lemke.h"

int main(int argc, char** argv) {
    long rounds = argc > 1 ? std::atol(argv[1]) : 10000;
    std::mt19937_64 rng(argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 12345);
    auto pick = [&](int k) { return static_cast<int>(rng() % static_cast<unsigned>(k)); };
    const double specials[] = {0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 1e300, -1e300, 5e-324,
                               std::numeric_limits<double>::infinity(),
                               -std::numeric_limits<double>::infinity(),
                               std::numeric_limits<double>::quiet_NaN(), 2.0, -2.0, 0.5};
    long bad = 0;
    for (long r = 0; r < rounds; ++r) {
        int64_t n = pick(4) == 0 ? pick(3) : 1 + pick(24);
        auto M = std::make_unique<double[]>(static_cast<std::size_t>(n * n + 1));
        auto q = std::make_unique<double[]>(static_cast<std::size_t>(n + 1));
        int style = pick(5);
        for (int64_t i = 0; i < n * n; ++i) {
            if (style == 0) M[i] = specials[pick(15)];
            else if (style == 1) M[i] = pick(3) - 1;            // degenerate integers
            else if (style == 2) M[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;  // identity
            else M[i] = std::ldexp(static_cast<double>(pick(2001) - 1000), pick(40) - 20);
        }
        for (int64_t i = 0; i < n; ++i)
            q[i] = style == 0 ? specials[pick(15)] : static_cast<double>(pick(21) - 10);
        auto z = std::make_unique<double[]>(static_cast<std::size_t>(n + 1));
        auto w = std::make_unique<double[]>(static_cast<std::size_t>(n + 1));
        auto basis = std::make_unique<int64_t[]>(static_cast<std::size_t>(n + 1));
        int64_t k = 0;
        int64_t nw = n > 0 ? pick(static_cast<int>(n) + 1) : 0;
        auto warm = std::make_unique<int64_t[]>(static_cast<std::size_t>(nw + 1));
        for (int64_t i = 0; i < nw; ++i) warm[i] = pick(4) == 0 ? pick(static_cast<int>(n) + 3) - 1 : i;
        lemke_options o;
        lemke_default_options(&o);
        if (pick(8) == 0) o.max_pivots = pick(5);
        if (pick(16) == 0) o.tol = specials[pick(15)];
        if (pick(16) == 0) o.time_limit = pick(2) ? specials[pick(15)] : 0.0;
        int64_t told = pick(32) == 0 ? n - 1 : n;  // sometimes a smaller n than the data
        lemke_info info;
        int s = lemke_lcp_solve(told, M.get(), q.get(), pick(4) ? &o : nullptr,
                                pick(2) ? warm.get() : nullptr, nw, z.get(), w.get(),
                                basis.get(), &k, &info);
        bool known = s == LEMKE_SOLVED || s == LEMKE_MAX_PIVOTS || s == LEMKE_RAY_TERMINATION ||
                     s == LEMKE_NUMERICAL_FAILURE || s == LEMKE_CYCLING || s == LEMKE_TIME_LIMIT ||
                     s == LEMKE_NOT_FINITE || s == LEMKE_INVALID_ARGUMENT;
        if (!known || info.status != s) { ++bad; std::fprintf(stderr, "round %ld: status %d\n", r, s); }
        if (s == LEMKE_SOLVED)
            for (int64_t i = 0; i < told; ++i)
                if (!(z[i] >= 0.0)) { ++bad; std::fprintf(stderr, "round %ld: z[%lld] < 0\n", r, (long long)i); break; }
        // The box LCP on the same data: bounds from the specials (ordered or not), sometimes
        // a friction index (valid pairs, or arbitrary entries).
        auto lo = std::make_unique<double[]>(static_cast<std::size_t>(n + 1));
        auto hi = std::make_unique<double[]>(static_cast<std::size_t>(n + 1));
        auto findex = std::make_unique<int64_t[]>(static_cast<std::size_t>(n + 1));
        int bstyle = pick(4);
        for (int64_t i = 0; i < n; ++i) {
            double a = specials[pick(15)], b = specials[pick(15)];
            if (bstyle > 0 && a > b) std::swap(a, b);
            if (bstyle == 2 && !(a == a)) a = -1.0;
            if (bstyle == 2 && !(b == b)) b = 1.0;
            lo[i] = a;
            hi[i] = b;
            findex[i] = -1;
        }
        if (pick(3) == 0) {
            for (int64_t i = 1; i < n; i += 2) {
                if (pick(2)) {
                    findex[i] = i - 1;
                    lo[i - 1] = 0.0;
                    hi[i] = std::fabs(hi[i]);
                    lo[i] = -hi[i];
                }
                if (pick(16) == 0) findex[i] = pick(static_cast<int>(n) + 3) - 2;
            }
        }
        bool with_findex = pick(2) == 0;
        s = lemke_blcp_solve(told, M.get(), q.get(), lo.get(), hi.get(),
                             with_findex ? findex.get() : nullptr, pick(4) ? &o : nullptr,
                             z.get(), w.get(), &info);
        known = s == LEMKE_SOLVED || s == LEMKE_MAX_PIVOTS || s == LEMKE_RAY_TERMINATION ||
                s == LEMKE_NUMERICAL_FAILURE || s == LEMKE_CYCLING || s == LEMKE_TIME_LIMIT || s == LEMKE_NOT_FINITE ||
                s == LEMKE_INVALID_ARGUMENT;
        if (!known || info.status != s) { ++bad; std::fprintf(stderr, "round %ld: box status %d\n", r, s); }
        auto within = [&](const char* what) {
            for (int64_t i = 0; i < told; ++i) {
                double l = lo[i], h = hi[i];
                if (with_findex && findex[i] >= 0) {
                    l = -std::fabs(hi[i] * z[findex[i]]);
                    h = std::fabs(hi[i] * z[findex[i]]);
                }
                if (!(z[i] >= l && z[i] <= h)) {
                    ++bad;
                    std::fprintf(stderr, "round %ld: %s z[%lld] out of its bounds\n", r, what, (long long)i);
                    break;
                }
            }
        };
        if (s == LEMKE_SOLVED) within("box");
        // The warm entry on the same data from row states made from the round number (the
        // stream of pick() left as it was): valid codes for the row's kind, or sometimes
        // not (every 7th round one out of range).
        std::vector<int8_t> state(static_cast<std::size_t>(told + 1));
        for (int64_t i = 0; i < told; ++i) {
            bool fr = with_findex && findex[i] >= 0;
            state[i] = static_cast<int8_t>(fr ? 3 + (r * 7 + i * 13) % 27 : (r + i) % 3);
        }
        if (r % 7 == 0 && told > 0) state[0] = static_cast<int8_t>(31);
        s = lemke_blcp_solve_warm(told, M.get(), q.get(), lo.get(), hi.get(),
                                  with_findex ? findex.get() : nullptr, r % 4 ? &o : nullptr,
                                  r % 5 == 0 ? nullptr : state.data(), z.get(), w.get(), &info);
        known = s == LEMKE_SOLVED || s == LEMKE_MAX_PIVOTS || s == LEMKE_RAY_TERMINATION ||
                s == LEMKE_NUMERICAL_FAILURE || s == LEMKE_CYCLING || s == LEMKE_TIME_LIMIT ||
                s == LEMKE_NOT_FINITE || s == LEMKE_INVALID_ARGUMENT;
        if (!known || info.status != s) { ++bad; std::fprintf(stderr, "round %ld: warm box status %d\n", r, s); }
        if (s == LEMKE_SOLVED) within("warm box");
    }
    std::printf("fuzz: %ld rounds, %ld bad\n", rounds, bad);
    return bad ? 1 : 0;
}
