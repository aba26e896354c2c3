/* lemke.h -- the C API of lemke's core: linear complementarity problems by Lemke's method.
 *
 * Given M (n x n, row-major) and q (n), find z >= 0 with w = M z + q >= 0 and z'w = 0.
 *
 * Every function returns a status code and never throws, aborts or reads outside the
 * arrays it is given (given the sizes it is told). Outputs go into caller-provided memory;
 * inputs are never written. A result is LEMKE_SOLVED only when the point passed the row-wise
 * check on the caller's M and q (the rule of lemke/_certify.py).
 *
 * Thread safety: the functions keep their work arrays per thread; any number of threads may
 * solve at once. Results are bit-identical across threads, runs and instruction sets.
 */
#ifndef LEMKE_H
#define LEMKE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes: the values of lemke.Status (Python), plus negative codes for bad input. A
 * function returns one of these and nothing else (the core's internal codes are each mapped
 * to one of them). */
enum lemke_status {
    LEMKE_SOLVED = 0,            /* z solves the LCP and passed the check */
    LEMKE_MAX_PIVOTS = 1,        /* the pivot limit was reached */
    LEMKE_RAY_TERMINATION = 2,   /* the method ended on a secondary ray that passed the ray
                                    check (no solution when M is copositive-plus) */
    LEMKE_NUMERICAL_FAILURE = 3, /* the answer failed the check */
    LEMKE_CYCLING = 6,           /* a basis repeated */
    LEMKE_TIME_LIMIT = 7,        /* stopped at options.time_limit (z: the unchecked point) */
    LEMKE_INTERRUPTED = 8,       /* stopped by lemke_interrupt() (z: the unchecked point) */
    LEMKE_NOT_FINITE = -1,       /* M or q holds a NaN or an infinity */
    LEMKE_INVALID_ARGUMENT = -3, /* a null pointer, n < 0, a bad basis index, bad options */
    LEMKE_OUT_OF_MEMORY = -4
};

typedef struct lemke_options {
    int64_t max_pivots; /* < 0: the default, 100 (n + 1) */
    double pivot_tol;   /* ratio-test threshold, relative (default 1e-11) */
    double tie_tol;     /* tie threshold, relative (default 1e-11) */
    double tol;         /* acceptance tolerance, relative (default 1e-9) */
    double time_limit;  /* seconds of wall-clock time for the call; < 0 or INFINITY: none (the
                           default, -1); kept to within some tens of microseconds */
} lemke_options;

typedef struct lemke_info {
    int status;       /* an enum lemke_status */
    int64_t pivots;   /* pivots made */
    double residual;  /* max_i |min(z_i, w_i)| on the caller's data */
    int warm;         /* 1 when the warm basis itself solved the problem (0 pivots) */
} lemke_info;

/* The defaults, as lemke.Options() in Python. */
void lemke_default_options(lemke_options* options);

/* Solve LCP(M, q) by the tableau method, cold (warm_basis == NULL or n_warm == 0) or warm
 * from a basis: warm_basis[0..n_warm) are the indices of the z's that were basic (the
 * basis_out of an earlier solve). options may be NULL (defaults). The same solve as
 * lemke.solve_lcp in Python, with the same bits: the old basis's point, a restart from it
 * (n >= 100), the cold run with its recoveries (cycles, failed checks, the ladder of
 * covering vectors and the unrevised method), rays checked.
 *
 * Out (each may be NULL when not wanted): z (n), w (n), basis_out (n: the basic z's of the
 * final basis, ascending; *n_basis_out says how many), info.
 * Returns info->status. */
int lemke_lcp_solve(int64_t n, const double* M, const double* q, const lemke_options* options,
                    const int64_t* warm_basis, int64_t n_warm, double* z, double* w,
                    int64_t* basis_out, int64_t* n_basis_out, lemke_info* info);

/* Solve the box LCP (lemke.solve_blcp): find z with lo <= z <= hi and w = M z + q such that
 * w_i >= 0 where z_i = lo_i, w_i <= 0 where z_i = hi_i and w_i = 0 in between. M is n x n,
 * row-major; lo may hold -INFINITY and hi +INFINITY; lo_i = hi_i fixes z_i. (ODE's and
 * DART's dSolveLCP pose A x = b + w: pass M = A and q = -b.)
 *
 * findex (NULL: none) is the friction index of ODE, Bullet and DART, as solve_blcp takes it:
 * findex[i] = -1 for an ordinary row; f = findex[i] >= 0 makes row i a friction row of the
 * contact whose normal impulse is z_f, with lo[i] = -hi[i] (hi[i] = mu_i >= 0, finite),
 * lo[f] >= 0, f not i and not itself a friction row; the bounds in force are
 * lo[i] z_f <= z_i <= hi[i] z_f at the answer, solved exactly (Stewart and Trinkle's rows,
 * an extended box LCP of size n + 2 n_friction).
 *
 * The runs are those of solve_blcp's one-call path, bit for bit (a cold run, then the other
 * covering vectors and exact ties, each checked; with a friction index the answer judged on
 * the caller's data); where they end without a checked answer, the final basis's point is
 * recomputed and checked, and Lemke restarts once from that basis (Python's general path
 * may take other steps there). options may be NULL; max_pivots < 0 means 100 (N + 1), N the
 * size solved.
 *
 * Out (each may be NULL): z (n), w (n; w = M z + q at z), info (warm is always 0).
 * Returns info->status: LEMKE_SOLVED only when z passed the check on the caller's data
 * (with a friction index, on the bounds in force at z); LEMKE_RAY_TERMINATION on a ray
 * that passed the ray check (for a monotone M: no solution); LEMKE_NOT_FINITE when M or q
 * holds a NaN or an infinity or lo or hi a NaN; LEMKE_INVALID_ARGUMENT for a null pointer,
 * n < 0, bad options, lo_i > hi_i, lo_i = +inf, hi_i = -inf, or a friction index (or a
 * friction row's bounds) refused as above. */
int lemke_blcp_solve(int64_t n, const double* M, const double* q, const double* lo,
                     const double* hi, const int64_t* findex, const lemke_options* options,
                     double* z, double* w, lemke_info* info);

/* lemke_blcp_solve, warm: state (n int8, in and out; NULL: cold, as lemke_blcp_solve) holds
 * each row's state in the basis to start from, as lemke.BoxWarmStart.row_states() gives it:
 * an ordinary row 0 (z_i at lo), 1 (at hi) or 2 (basic); a friction row (findex[i] >= 0)
 * 3 + 9 s(beta+) + 3 s(beta-) + s(lambda), each s in 0-2 (3 for a row starting cold). On
 * return it holds the final basis's states, to pass to the next step's solve (for rows that
 * come and go, carry them by contact as BoxWarmStart.take / relabel do: a new row cold,
 * 0 or 3). The runs are solve_blcp's from a warm start, bit for bit (the old basis's point
 * first: 0 pivots and info->warm = 1 when it still solves the problem); where they end
 * undecided, lemke_blcp_solve's cold runs. A state out of range for its row is
 * LEMKE_INVALID_ARGUMENT. */
int lemke_blcp_solve_warm(int64_t n, const double* M, const double* q, const double* lo,
                          const double* hi, const int64_t* findex, const lemke_options* options,
                          int8_t* state, double* z, double* w, lemke_info* info);

/* Stops every solve running in this process, in any thread, within some tens of
 * microseconds: each returns LEMKE_INTERRUPTED (solves started afterwards are not
 * affected). Async-signal-safe: a SIGINT handler of the program may call it. The library
 * installs no signal handler of its own. */
void lemke_interrupt(void);

/* A short English name of a status code ("SOLVED", ...). Never NULL. */
const char* lemke_status_name(int status);

#ifdef __cplusplus
}
#endif

#endif /* LEMKE_H */
