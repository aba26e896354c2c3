// The LCP driver: a cold or warm solve's first stages in one call (first_run; the stages are
// stated below). The output buffer is laid out as in python/lemke/_layout.py's BUFFER: [z | z0 | ray (n + 1) | w | covering | row scales |
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

enum Method : int { TABLEAU = 0, UNREVISED = 1 };

// What solve_lcp runs first (tableau method), cold (k == 0) or warm from the basic z's
// beta[:k]. d: the covering vector (nullptr: all ones). buf: BufferLayout(n).length()
// doubles; basic: n int64 (the basic z's, or on stage -1 the final flags). `keep`: a warm
// start's old basis is equilibrated and solved through the thread's kept matrices
// (equilibrate_finite_kept, solve_gathered_kept: the same bits, M's sweeps and the block's
// factors reused when M repeats); false for the batch's islands, each its own M, where
// keeping costs more than it saves.
RunResult first_run(Mat<const double> M, const double* q, const double* d, const idx* beta,
                    idx k, idx max_pivots, double pivot_tol, double tie_tol, double tol,
                    double* buf, idx* basic, bool keep = true);

// What solve_lcp runs for one problem, and every batch per problem (cold.solve_one): a warm
// start's stages from beta[:k] when k > 0, then, unless they solved it, the cold solve with
// its recoveries (cycles; failed checks: the final basis's point, a restart from it at
// n >= RESTART_FROM, the ladder of covering vectors and the other method) and the checks.
// k = -1: go on after first_run's stage -1 (its code beta[0] after beta[1] pivots, its
// flags in `basic`); k < -1: restart from the warm basis beta[:-2 - k] whose point
// first_run tried (stage -2).
// stop_at_ray: the rule for the recovery runs of the cold solve (checked): with it set, a
// first recovery run that ends on a ray ends the recoveries, the solve ending on that ray
// (checked here or not).  The MLCP ladder (lemke/_mlcp.py) passes it, through solve_lcp's
// private `_ray_stop` and _core.solve_one, for a step that has another after it, which
// checks the ray on the caller's data and goes on to the next step when it fails there: on
// QSCORPIO and QBEACONF the later recovery runs (the same M) took 620 and 230 pivots more,
// ending on rays that failed there too, and the next step (M_clean) solved in 243 and 51.
// Off everywhere else (solve_lcp, the batches, the C API).
RunResult solve_one(Method method, Mat<const double> M, const double* q, const double* d,
                    const idx* beta, idx k, idx max_pivots, double pivot_tol, double tie_tol,
                    double tol, double* buf, idx* basic, bool keep = true,
                    bool stop_at_ray = false);

// The first run and, when it does not settle the solve, solve_one from where it stopped: the
// path of solve_lcp for one problem (and of a batch's problem), by either method. A first
// run that ended on a ray whose point failed the check gets the ray check here, as
// solve_one would give it.
RunResult solve(Method method, Mat<const double> M, const double* q, const double* d,
                const idx* beta, idx k, idx max_pivots, double pivot_tol, double tie_tol,
                double tol, double* buf, idx* basic, bool keep = true);

// checked_once: checked() with the covering vector d given (so no recovery runs after a
// failed check) and a ray not judged (ok false): the prologue, one run of `method` with the
// recoveries from a cycle, the check. For qp.cpp's multiplier LCP. buf:
// BufferLayout(n).length() doubles; basic: n int64 (the basic z's, k of them).
RunResult checked_once(Method method, Mat<const double> M, const double* q, const double* d,
                       idx max_pivots, double pivot_tol, double tie_tol, double tol, double* buf,
                       idx* basic);

// solve() on problems lo..hi-1 laid end to end (cold.batch's layout): problem b has
// n = qoff[b + 1] - qoff[b], q = qs + qoff[b], M the n x n row-major block at Ms + mstart[b],
// warm start beta[boff[b]..boff[b + 1]), buffer bufs + buff[b], basic z's basics + qoff[b],
// pivot cap max_pivots[b]. Row b of out_i gets (code, pivots, k, recoveries, stage), of
// out_f (ok, residual).
void batch(Method method, const double* Ms, const idx* mstart, const double* qs, const idx* qoff,
           const idx* beta, const idx* boff, idx lo, idx hi, const idx* max_pivots,
           double pivot_tol, double tie_tol, double tol, double* bufs, const idx* buff,
           idx* basics, idx* out_i, double* out_f);

}  // namespace lemke
