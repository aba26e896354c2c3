// Islands of box LCPs in one call (solve_blcp_many): per island what solve_blcp's one-call
// paths run (lemke/_blcp.py: the cold fast path's one boxed::solve, else _one_call: front,
// the run from the warm start, the checked point, the cold run and its ladder, the
// friction check), the same calls in the same order, so the same bits. An island those
// paths do not settle (a checked ray, a failed ladder, a friction answer that fails the
// check) is left to the Python front's general path (stage -1), data the kernels refuse
// too (stage -2: the front says which entry).
#pragma once
#include <cstdint>

#include "boxed.hpp"

namespace lemke {
namespace boxed {

// Row states (BoxWarmStart.row_states): an ordinary row 0 at lo, 1 at hi, 2 basic; a
// friction row 3 + 9 s(beta+) + 3 s(beta-) + s(lambda).
constexpr int FRICTION_STATE = 3;

// The row states of a final basis (final[:k] basic, final[k:m] at hi, of the problem of
// n + 2 nf rows that solve_blcp solves with nf friction rows) into states (n);
// scratch: n + 2 nf.
void row_states(const idx* final, idx k, idx m, idx n, idx nf, const idx* findex,
                std::int8_t* scratch, std::int8_t* states);

// Islands lo..hi-1, laid end to end: island b has n = qoff[b + 1] - qoff[b] rows, M the
// n x n row-major block at Ms + mstart[b], q, lo, hi, findex (when fflag[b]) and the warm
// row states (when wflag[b]) at offset qoff[b]; its output buffer bufs + buff[b] (solve_blcp's
// one-call layout), its final basis and friction rows ints + ioff[b], its final row states
// state_out + qoff[b]. Row b of out_i gets (code, pivots, k, m, recoveries, stage, N), out_f[b]
// the residual; stage 0: the warm start's own point (its states copied), 1: solved and
// checked by runs, -1: the general path must decide, -2: the data are refused.
void batch(const double* Ms, const idx* mstart, const double* qs, const double* los,
           const double* his, const idx* qoff, const idx* findex, const std::uint8_t* fflag,
           const std::int8_t* state, const std::uint8_t* wflag, idx lo, idx hi,
           const idx* max_pivots, double pivot_tol, double tie_tol, double tol, double* bufs,
           const idx* buff, idx* ints, const idx* ioff, std::int8_t* state_out, idx* out_i,
           double* out_f);

}  // namespace boxed
}  // namespace lemke
