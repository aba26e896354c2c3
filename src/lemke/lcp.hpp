// The LCP driver: a cold or warm solve's first stages in one call (the port of
// lemke/kernels/cold.py's first_run, whose docstring states the stages). The output buffer
// is laid out as in cold.BUFFER: [z | z0 | ray (n + 1) | w | covering | row scales |
// column scales], 6n + 2 doubles (BufferLayout), with the n basic indices (int64) after it.
#pragma once
#include <cstdint>

#include "span.hpp"

namespace lemke {

constexpr int NOT_FINITE = -1;  // NaN or infinity in M or q, or sizes that do not match
constexpr int TRIVIAL = -2;     // q >= 0: z = 0
constexpr idx RESTART_FROM = 100;

// The one statement of the output buffer's layout (a test checks it against cold.fields).
struct BufferLayout {
    idx n;
    idx z() const { return 0; }
    idx z0() const { return n; }
    idx ray() const { return n + 1; }
    idx w() const { return 2 * n + 2; }
    idx covering() const { return 3 * n + 2; }
    idx row_scale() const { return 4 * n + 2; }
    idx col_scale() const { return 5 * n + 2; }
    idx length() const { return 6 * n + 2; }
};

struct RunResult {
    int code = 0;        // a Status, NOT_FINITE or TRIVIAL
    idx pivots = 0;
    idx k = 0;           // basic z's written (their indices in `basic`)
    bool ok = false;     // the check passed (the point; a ray is not judged here)
    double residual = 0.0;
    idx recoveries = 0;
    int stage = 2;       // 0 warm basis solved it; 2 cold; -1 go on in the full driver; -2 restart
};

// What solve_lcp runs first (tableau method), cold (k == 0) or warm from the basic z's
// beta[:k]. d: the covering vector (nullptr: all ones). buf: BufferLayout(n).length()
// doubles; basic: n int64 (the basic z's, or on stage -1 the final flags).
RunResult first_run(Mat<const double> M, const double* q, const double* d, const idx* beta,
                    idx k, idx max_pivots, double pivot_tol, double tie_tol, double tol,
                    double* buf, idx* basic);

}  // namespace lemke
