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

/* Status codes: the values of lemke.Status (Python), plus negative codes for bad input. */
enum lemke_status {
    LEMKE_SOLVED = 0,            /* z solves the LCP and passed the check */
    LEMKE_MAX_PIVOTS = 1,        /* the pivot limit was reached */
    LEMKE_RAY_TERMINATION = 2,   /* the method ended on a secondary ray that passed the ray
                                    check (no solution when M is copositive-plus) */
    LEMKE_NUMERICAL_FAILURE = 3, /* the answer failed the check */
    LEMKE_CYCLING = 6,           /* a basis repeated */
    LEMKE_NOT_FINITE = -1,       /* M or q holds a NaN or an infinity */
    LEMKE_INVALID_ARGUMENT = -3, /* a null pointer, n < 0, a bad basis index, bad options */
    LEMKE_OUT_OF_MEMORY = -4
};

typedef struct lemke_options {
    int64_t max_pivots; /* < 0: the default, 100 (n + 1) */
    double pivot_tol;   /* ratio-test threshold, relative (default 1e-11) */
    double tie_tol;     /* tie threshold, relative (default 1e-11) */
    double tol;         /* acceptance tolerance, relative (default 1e-9) */
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

/* A short English name of a status code ("SOLVED", ...). Never NULL. */
const char* lemke_status_name(int status);

#ifdef __cplusplus
}
#endif

#endif /* LEMKE_H */
