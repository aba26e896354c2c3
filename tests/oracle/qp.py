r"""The fused cold path of a strictly convex QP: one kernel call from the caller's data to a
checked KKT point.

The QP (qpsolvers' form) ``min 1/2 x'Px + q'x  s.t.  G x <= h, A x = b, lb <= x <= ub``
with P positive definite is solved on its dual, an LCP in the inequality multipliers only:

1. ``P = L L'`` (Cholesky, one thread).  A pivot that is not clearly positive stops here
   with NOT_DEFINITE (unless step 7 applies): P is only semidefinite (or not even that),
   and the caller falls back to the KKT-MLCP path, which handles every convex QP.
2. The constraints are gathered as rows: equalities ``E x = f`` (A's rows, then a unit row
   per fixed variable, lb = ub) and inequalities ``C x <= d`` (G's rows, then ``x_j <=
   ub_j`` and ``-x_j <= -lb_j`` for every finite bound).  With ``u = L'x`` the QP reads
   ``min 1/2 |u + c|^2`` with ``c = L^-1 q``, subject to ``W_E' u = f`` and ``W_C' u <= d``,
   where ``W = L^-1 [E; C]'`` (forward substitutions, one per row).
3. The equalities are eliminated by a Householder QR ``W_E = Q [R; 0]``: with ``v = Q'u``
   the first p entries are fixed, ``v1 = R'^-1 f``, and the rest, v2, is free.  Writing
   ``F = Q'W_C`` (rows F1 and F2 of sizes p and n - p), the problem in v2 is
   ``min 1/2 |v2 + c2|^2  s.t.  F2'v2 <= d - F1'v1``.  A diagonal entry of R that is not
   clearly non-zero (dependent equalities, or more equalities than variables) stops with
   DEPENDENT_EQUALITIES: the MLCP path deals with those.
4. Its KKT conditions are the LCP ``w = M z + g >= 0, z >= 0, z'w = 0`` with
   ``M = F2'F2`` (positive semidefinite, of the size of the inequalities) and ``g = d -
   F1'v1 + F2'c2``, solved by ``cold.checked_once``: the same equilibration, pivoting rule,
   cycle recoveries and row-wise check as ``solve_lcp``, but no recovery runs after a first
   run whose point fails the check (the covering vector is passed, all ones): the QP then
   goes to the KKT-MLCP path at once.  M has rank at most n - p, and where m is much
   larger such a failure is a sign of a degenerate dual whose point would not pass the
   KKT check of step 6 either: on QPCBOEI1 (m = 971, n - p = 375) the first run stopped
   after 2 pivots, the recoveries then took 469 pivots on the dense 971 x 971 tableau
   (1.1 s, where the KKT-MLCP path takes 0.16 s) for a point that failed step 6.
5. The point and the multipliers come from the factors already at hand: ``v2 = -c2 - F2 z``,
   ``x = L'^-1 Q v``, and the equality multipliers ``y = -R^-1 (v1 + c1 + F1 z)``; a
   variable whose bound has a positive multiplier, or that is fixed (lb = ub), is set to
   that bound exactly.
6. The KKT conditions are checked once, row by row, on the caller's data with compensated
   (double-double) sums (:func:`kkt_check`), at the tolerance ``min(tol, STRICT_TOL)``:
   there is no refinement step, so an ill-conditioned problem whose point is only accurate
   to the tolerance is left to the KKT-MLCP path, which refines in double-double.

7. **Many more inequalities than variables** (``m >= GRAM_RATIO n``, the DUALC problems,
   m counting the bounds' rows): M = F2 F2' has rank at most ``r = n - p``, and forming it
   (``r m^2 / 2``) and pivoting on its m x m tableau (``m^2`` a pivot) is what the solve
   costs.  So the LCP is solved without forming it (``gram_lcp``): the unrevised method
   on its factored form (``unrevised.lemke`` with ``Fs``: a column ``F2 F2[e]'`` computed
   when z_e enters, the block H of at most r + 1 columns kept factored), with the rows of
   F2 scaled to unit norm (the symmetric equilibration of a Gram matrix; a row within
   rounding of the equalities' span is a constant, kept exactly zero) and the covering
   vector all ones in those units (z0 first meets the constraint farthest from the
   unconstrained minimum; invariant under the scaling of G's rows).  Same pivoting rule
   (``kernels.pivoting``).  The point is not read from the LCP's z (the normal equations
   ``M_SS z_S = -g_S`` square the condition): the final basis S names the active rows,
   whose equality-constrained QP is solved through the factors at hand and a QR of
   ``F2_S'`` (``active_solve``), then refined twice with its residuals on the caller's data
   summed in double-double (``active_residuals``), and checked by :func:`kkt_check` at the
   same tolerance as step 6.  A P that is positive semidefinite only to rounding (no
   Cholesky factor at step 1: DUALC2 and DUALC8, eigenvalues down to -1e-11 beside a
   largest of 6e5 and 7e6) is factored as ``P + delta I`` (``delta = PROXIMAL max P_jj``,
   ``proximal_cholesky``); the
   refinement (three steps) then runs with the caller's P in the residuals and the proximal
   factor in the solves, the proximal point iteration on the active rows: exact at once
   where the active rows pin x (a vertex, DUALC's case), converging by ``delta / (lambda +
   delta)`` a step along a direction of curvature lambda, and not converging where P is
   singular on a free direction, which the check then refuses.  Cost ``n^3/6 + m n^2``
   (substitutions and QR, as above) plus ``m (r + k)`` a pivot, k the size of H.  This path
   is an entry kernel of its own, :func:`solve_gram` (only a QP with that many rows
   compiles it; one entry for both paths cost the dense path's first call a quarter more
   compile); whatever it does not end solved and checked, ``solve_qp`` hands to
   :func:`solve` (steps 1-6) and then to the KKT-MLCP path, as before: an infeasible QP
   ends there with its certificate.

8. **A P that is not definite, with fewer rows.** :func:`solve` stops at step 1; the
   caller then calls :func:`solve_gram` with ``semidefinite`` set, which runs step 7 with
   the proximal factor whatever the number of rows, where the equalities can pin P's flat
   directions: when neither P's zero diagonal entries (each a direction of the null space
   of a semidefinite P) nor the proximal factor's pivots below ``FLAT max P_jj`` (the k-th
   leading block of ``P + delta I`` has a pivot of order delta exactly where the nullity of
   P's k-th leading block grows) outnumber the equality rows.  Then the reduced problem can
   be strictly convex and the proximal point iteration on the active rows converges by
   ``delta / (lambda + delta)`` a step, lambda its smallest curvature.  Elsewhere
   (linear-program-like problems, many variables without curvature and few equalities,
   where the proximal LCP is ill-conditioned and its runs failed the check on every
   Maros-Meszaros problem of that kind, at up to 2 s a problem) it returns NOT_APPLICABLE
   after the count of the diagonal or one Cholesky factor, and the caller takes the
   KKT-MLCP path (``solve_qp`` counts the zero diagonal entries itself first, so that a
   linear program neither calls nor compiles this entry).  On Maros-Meszaros: HS51-53, GENHS28, TAME, LOTSCHD, DPKLO1 and
   CVXQP1-3_S (0.01-1.3 ms instead of 0.9-13 ms); ZECEVIC2 and QSHARE2B would solve too but
   fail the count.

**Bounds only** (``solve_box``, an entry of its own; ``solve_qp`` calls it for plain data
below ``_qp.BOX_FIRST`` variables): the QP is the box LCP ``(P, q, lb, ub)``, solved by one
run of ``boxed.solve`` on n pairs (where steps 2-4 would make an LCP with a row per bound),
then checked by :func:`kkt_check` as in step 6.

No BLAS or LAPACK call is made: a factorization inside a kernel must not start a thread pool.
The O(n^3) loops are dot products and axpys over contiguous rows (vectorized).

Cost: ``n^3/6`` (Cholesky) ``+ n^2 (p + m) / 2`` (substitutions) ``+ 2 n p (p + m)`` (QR)
``+ (n - p) m^2 / 2`` (M) plus Lemke's pivots on an m x (m + 1) tableau; with step 7 the
last two terms are ``m (r + k)`` a pivot instead.
"""
import numpy as np

from . import boxed, cold, inline_kernel, kernel, pivoting, unrevised
from .linalg import (absmax, acc2, borrow, copy, dot, false_flags, nan_probe, no_matrix, pow2_rsqrt,
                     row_of, two_product, two_sum)

OK = 0
NOT_DEFINITE = 1  # a Cholesky pivot of P is not clearly positive
DEPENDENT_EQUALITIES = 2  # the equalities are (nearly) dependent, or more than n of them
NOT_SOLVED = 3  # the LCP ended otherwise than solved (infeasible QP, or a numerical failure)
CHECK_FAILED = 4  # the KKT check on the caller's data failed

BAD_INPUT = 5  # the data needs the front's validation (which raises, naming the entry)
NOT_APPLICABLE = 6  # solve_gram: fewer than GRAM_RATIO n inequalities

INFINITY = 1e20  # bounds at least this large in magnitude are infinite, as in qpsolvers
SYMMETRY_TOL = 1e-10  # relative, as the front's: a larger asymmetry of P is an error
DEFINITE_TOL = 1e-12  # a Cholesky pivot d_j must have d_j^2 > DEFINITE_TOL * max_k P_kk
RANK_TOL = 1e-10
STRICT_TOL = 1e-12  # the fused path answers only when its point passes at this tolerance  # |R_kk| must exceed RANK_TOL times the largest |W_E| column norm
EPS = np.finfo(np.float64).eps
GRAM_RATIO = 4  # the LCP is solved in factored form (step 7) when m >= GRAM_RATIO n
PROXIMAL = 1e-6  # delta of the proximal term, relative to max P_jj (step 7)
FLAT = 1e-3  # a proximal factor's pivot below FLAT max P_jj marks a flat direction of P (step 8)
REFINE = 2  # refinement steps of the point of step 7, P definite
REFINE_PROXIMAL = 3  # and with the proximal term


# ----------------------------------------------------------------------------- screening

@kernel
def screen(P, q, G, h, A, b, lb, ub):
    """``(ok, Ps, lo, up)``: whether the data is plainly valid (every entry of P, q, G, A, b
    finite, h finite or +inf (no constraint), no NaN in the bounds, lb < +inf, ub > -inf,
    lb <= ub, P symmetric to ``SYMMETRY_TOL`` of its largest entry), the symmetric part
    ``Ps = (P + P')/2``, and the bounds with entries beyond ``INFINITY`` made infinite.
    Data that is not plainly valid goes to the front's validation, which raises (naming the
    entry) or accepts it; this is only the fast way through for the common case.  So do
    shapes that do not match (P n x n, G m x n and h of length m, A p x n and b of length
    p, lb and ub of length n): the front leaves that comparison to this kernel."""
    n = q.shape[0]
    work = np.empty(n * (n + 2))  # one allocation: Ps, lo, up
    Ps = work[:n * n].reshape((n, n))
    lo = work[n * n:n * (n + 1)]
    up = work[n * (n + 1):]
    if not (P.shape[0] == n and P.shape[1] == n and G.shape[1] == n and h.shape[0] == G.shape[0]
            and A.shape[1] == n and b.shape[0] == A.shape[0] and lb.shape[0] == n
            and ub.shape[0] == n):
        return False, Ps, lo, up
    # P, G and A are C-contiguous: each is probed as one flat vector (a call per matrix, not
    # per row; the probe is 0 or NaN and the largest entry exact in any order)
    probe = nan_probe(q, n)
    Pf = P.reshape(n * n)
    probe += nan_probe(Pf, n * n)
    top = absmax(Pf, n * n)
    asym = 0.0
    B = 32  # in square tiles: P[j, i] is read down a column
    for i0 in range(0, n, B):
        for j0 in range(0, i0 + 1, B):
            for i in range(i0, min(i0 + B, n)):
                for j in range(j0, min(j0 + B, i + 1)):
                    a = P[i, j]
                    c = P[j, i]
                    asym = max(asym, abs(a - c))
                    Ps[i, j] = 0.5 * (a + c)
                    Ps[j, i] = Ps[i, j]
    m0 = G.shape[0]
    probe += nan_probe(G.reshape(m0 * n), m0 * n)
    for i in range(m0):
        if not (h[i] > -np.inf):  # NaN or -inf
            return False, Ps, lo, up
    p0 = A.shape[0]
    probe += nan_probe(A.reshape(p0 * n), p0 * n)
    probe += nan_probe(b, b.shape[0])
    if probe != 0.0 or asym > SYMMETRY_TOL * top:
        return False, Ps, lo, up
    for j in range(n):
        a = lb[j]
        c = ub[j]
        if not (a < np.inf and c > -np.inf and a <= c):  # also catches NaN
            return False, Ps, lo, up
        lo[j] = a if a > -INFINITY else -np.inf
        up[j] = c if c < INFINITY else np.inf
    return True, Ps, lo, up


# ----------------------------------------------------------------------------- factors

@kernel
def cholesky(P, L):
    """L (lower triangular, n x n) with ``L L' = P``, row by row; returns False when a
    pivot is not clearly positive (``d^2 <= DEFINITE_TOL max_k P_kk``) or not finite."""
    n = P.shape[0]
    top = 0.0
    for j in range(n):
        top = max(top, P[j, j])
    floor = DEFINITE_TOL * top
    if not top > 0.0:
        return False
    for i in range(n):
        Li = row_of(L, i)
        for j in range(i):
            Li[j] = (P[i, j] - dot(Li, row_of(L, j), j)) / L[j, j]
        d = P[i, i] - dot(Li, Li, i)
        if not d > floor:
            return False
        Li[i] = np.sqrt(d)
        for j in range(i + 1, n):
            Li[j] = 0.0
    return True


@kernel
def forward(L, r):
    """r := L^-1 r in place (L lower triangular, row-major: dot products over rows).  The
    leading zeros of r stay zero and are skipped (a bound's row e_j costs (n - j)^2 / 2)."""
    n = L.shape[0]
    s = 0
    while s < n and r[s] == 0.0:
        s += 1
    rs = borrow(r, s, n - s, np.float64)  # (borrowed: no view and its count per row)
    for j in range(s, n):
        Lj = row_of(L, j)
        r[j] = (r[j] - dot(Lj[s:], rs, j - s)) / Lj[j]


@kernel
def _dot4(a, r0, r1, r2, r3):
    """The four sums ``a' r_k`` in one pass over a, each in the fixed order of
    ``linalg.row_dot_and_size`` (eight running sums: lane ``j mod 8`` of the first
    ``8 floor(k / 8)`` terms, the rest into lane 0, combined ``((s0 + s1) + (s2 + s3)) +
    ((s4 + s5) + (s6 + s7))``; no fastmath, no fused multiply-add), so the same bits on
    every instruction set and in the C++ core (``qp::dot4``): ``linalg.dot(a, r_k, k)``
    four times over, with a read once.  (Before, this was compiled with fastmath
    ``reassoc`` and ``contract``: LLVM reordered the sums and fused the multiply-adds,
    by the host's vector width.)"""
    k = a.shape[0]
    s00 = s01 = s02 = s03 = s04 = s05 = s06 = s07 = 0.0
    s10 = s11 = s12 = s13 = s14 = s15 = s16 = s17 = 0.0
    s20 = s21 = s22 = s23 = s24 = s25 = s26 = s27 = 0.0
    s30 = s31 = s32 = s33 = s34 = s35 = s36 = s37 = 0.0
    j = 0
    while j + 8 <= k:
        a0 = a[j]
        a1 = a[j + 1]
        a2 = a[j + 2]
        a3 = a[j + 3]
        a4 = a[j + 4]
        a5 = a[j + 5]
        a6 = a[j + 6]
        a7 = a[j + 7]
        s00 += a0 * r0[j]
        s10 += a0 * r1[j]
        s20 += a0 * r2[j]
        s30 += a0 * r3[j]
        s01 += a1 * r0[j + 1]
        s11 += a1 * r1[j + 1]
        s21 += a1 * r2[j + 1]
        s31 += a1 * r3[j + 1]
        s02 += a2 * r0[j + 2]
        s12 += a2 * r1[j + 2]
        s22 += a2 * r2[j + 2]
        s32 += a2 * r3[j + 2]
        s03 += a3 * r0[j + 3]
        s13 += a3 * r1[j + 3]
        s23 += a3 * r2[j + 3]
        s33 += a3 * r3[j + 3]
        s04 += a4 * r0[j + 4]
        s14 += a4 * r1[j + 4]
        s24 += a4 * r2[j + 4]
        s34 += a4 * r3[j + 4]
        s05 += a5 * r0[j + 5]
        s15 += a5 * r1[j + 5]
        s25 += a5 * r2[j + 5]
        s35 += a5 * r3[j + 5]
        s06 += a6 * r0[j + 6]
        s16 += a6 * r1[j + 6]
        s26 += a6 * r2[j + 6]
        s36 += a6 * r3[j + 6]
        s07 += a7 * r0[j + 7]
        s17 += a7 * r1[j + 7]
        s27 += a7 * r2[j + 7]
        s37 += a7 * r3[j + 7]
        j += 8
    while j < k:
        at = a[j]
        s00 += at * r0[j]
        s10 += at * r1[j]
        s20 += at * r2[j]
        s30 += at * r3[j]
        j += 1
    return (((s00 + s01) + (s02 + s03)) + ((s04 + s05) + (s06 + s07)),
            ((s10 + s11) + (s12 + s13)) + ((s14 + s15) + (s16 + s17)),
            ((s20 + s21) + (s22 + s23)) + ((s24 + s25) + (s26 + s27)),
            ((s30 + s31) + (s32 + s33)) + ((s34 + s35) + (s36 + s37)))


@kernel
def forward_rows(L, R):
    """Every row r of R := L^-1 r, four rows at a time: each row of L is read once per four
    right-hand sides (the substitutions are bound by reading L).  Leading zeros common to
    the four are skipped, as in :func:`forward`."""
    n = L.shape[0]
    k = R.shape[0]
    i = 0
    while i + 4 <= k:
        r0 = row_of(R, i)
        r1 = row_of(R, i + 1)
        r2 = row_of(R, i + 2)
        r3 = row_of(R, i + 3)
        s = 0
        while s < n and r0[s] == 0.0 and r1[s] == 0.0 and r2[s] == 0.0 and r3[s] == 0.0:
            s += 1
        for j in range(s, n):
            Lj = row_of(L, j)
            d0, d1, d2, d3 = _dot4(Lj[s:j], r0[s:j], r1[s:j], r2[s:j], r3[s:j])
            inv = 1.0 / Lj[j]
            r0[j] = (r0[j] - d0) * inv
            r1[j] = (r1[j] - d1) * inv
            r2[j] = (r2[j] - d2) * inv
            r3[j] = (r3[j] - d3) * inv
        i += 4
    while i < k:
        forward(L, row_of(R, i))
        i += 1


@kernel
def backward_transposed(L, r):
    """r := L'^-1 r in place: column j of L' is row j of L, so each step is an axpy over a
    contiguous row."""
    n = L.shape[0]
    for j in range(n - 1, -1, -1):
        xj = r[j] / L[j, j]
        r[j] = xj
        Lj = row_of(L, j)
        for k in range(j):
            r[k] -= xj * Lj[k]


@kernel
def householder_apply(V, beta, k, x):
    """x := H_k x with ``H_k = I - beta_k v_k v_k'`` (v_k = V[k], zero before entry k)."""
    n = x.shape[0]
    v = borrow(V, k * V.shape[1] + k, V.shape[1] - k, np.float64)
    r = borrow(x, k, n - k, np.float64)
    s = beta[k] * dot(v, r, n - k)
    if s != 0.0:
        for t in range(n - k):  # over slices from 0: vectorized (see linalg._row_update)
            r[t] -= s * v[t]


@kernel
def qr_rows(WE, V, beta):
    """Householder QR of ``WE'`` (n x p, its columns the rows of WE): on return row k of
    WE holds column k of ``R`` in its first k + 1 entries (the rest is overwritten), V and
    beta the reflectors (``Q' = H_{p-1} ... H_0``).  Returns the smallest ``|R_kk|``
    relative to the largest row norm of WE (0 when p > n)."""
    p, n = WE.shape
    if p > n:
        return 0.0
    top = 0.0
    for k in range(p):
        top = max(top, np.sqrt(dot(row_of(WE, k), row_of(WE, k), n)))
    worst = np.inf
    for k in range(p):
        x = row_of(WE, k)
        for i in range(k):  # the earlier reflectors, in order
            householder_apply(V, beta, i, x)
        sigma = dot(x[k:], x[k:], n - k)
        norm = np.sqrt(sigma)
        v = row_of(V, k)
        v[:k] = 0.0
        v[k:] = x[k:]
        alpha = -norm if x[k] >= 0.0 else norm
        v[k] -= alpha
        vv = dot(v[k:], v[k:], n - k)
        beta[k] = 2.0 / vv if vv > 0.0 else 0.0
        x[k] = alpha
        for t in range(k + 1, n):
            x[t] = 0.0
        worst = min(worst, norm / top if top > 0.0 else 0.0)
    return worst if p else np.inf


# ----------------------------------------------------------------------------- compensated sums

@kernel
def dot2(x, y, c):
    """``(sum, size, norm)``: c + x'y summed in twice the working precision (Ogita, Rump and
    Oishi's Dot2), ``|c| + |x|'|y|`` and ``sum |x|``."""
    s = c
    err = 0.0
    size = abs(c)
    norm = 0.0
    for j in range(x.shape[0]):
        s, err = acc2(s, err, x[j], y[j])
        size += abs(x[j] * y[j])
        norm += abs(x[j])
    return s + err, size, norm


@kernel
def axpy2(s, err, size, a, x):
    """``s + err += a x`` compensated, elementwise, and ``size += |a x|``."""
    for j in range(s.shape[0]):
        p, e = two_product(a, x[j])
        t, f = two_sum(s[j], p)
        s[j] = t
        err[j] += e + f
        size[j] += abs(p)


@inline_kernel
def axpy2_rows(s, err, size, coef, rows):
    """``s + err += rows' coef`` compensated (:func:`axpy2`, row by row)."""
    for i in range(rows.shape[0]):
        axpy2(s, err, size, coef[i], rows[i])


@inline_kernel
def axpy2_matrix(s, err, size, coef, M):
    """:func:`axpy2_rows` indexing M in place (the same sums in the same order; no row views
    and no call per row, whose reference counting cost more than the sums at small n)."""
    n = s.shape[0]
    for i in range(M.shape[0]):
        a = coef[i]
        for j in range(n):
            p, e = two_product(a, M[i, j])
            t, f = two_sum(s[j], p)
            s[j] = t
            err[j] += e + f
            size[j] += abs(p)


@inline_kernel
def dot2_row(M, i, y, c):
    """:func:`dot2` of row i of M with y, indexing M in place."""
    s = c
    err = 0.0
    size = abs(c)
    norm = 0.0
    for j in range(y.shape[0]):
        s, err = acc2(s, err, M[i, j], y[j])
        size += abs(M[i, j] * y[j])
        norm += abs(M[i, j])
    return s + err, size, norm


@inline_kernel
def add_abs_rows(acc, a, M):
    """``acc[j] += a |M_ij|`` for every row i of M, in row order: a times the absolute
    column sums of M (the floor's weights in :func:`kkt_check`).  Nothing when a is 0."""
    if not a > 0.0:
        return
    n = acc.shape[0]
    for i in range(M.shape[0]):
        for j in range(n):
            acc[j] += a * abs(M[i, j])


@inline_kernel
def counts_as_zero(a, G, i, allow):
    """Whether multiplier a of row i of G counts as zero: removing it moves no stationarity
    row j by more than ``allow[j]``."""
    for j in range(allow.shape[0]):
        if not abs(a * G[i, j]) <= allow[j]:
            return False
    return True


# ----------------------------------------------------------------------------- the check

@kernel
def kkt_check(P, q, G, h, A, b, lb, ub, x, y, z, zb, tol, stats):
    """Whether ``(x, y, z, zb)`` is a KKT point of the QP, judged row by row on the caller's
    data with compensated sums, each row against its own size (as ``certify`` judges an
    LCP): with ``t = tol + 4 eps``,

    - stationarity ``|P_j x + q_j + A_j'y + G_j'z + zb_j| <= t s_j + f (|P_.j|_1 max|x| +
      |A_.j|_1 max|y| + |G_.j|_1 max|z| + max|zb|)`` (s_j the sum of the sizes of the terms);
    - equalities ``|A_i x - b_i| <= t s_i + f max|x| |A_i|_1``, inequalities ``G_i x - h_i <=
      t s_i + f max|x| |G_i|_1``, bounds ``lb_j - x_j <= t (|lb_j| + |x_j|) + f max|x|`` and
      ``x_j - ub_j <= t (...) + f max|x|``;
    - signs: ``z >= 0``, ``zb_j < 0`` only at a finite lb, ``> 0`` only at a finite ub;
    - complementarity: a non-zero multiplier's row is active to within its allowance, or
      the multiplier is small enough to count as zero (removing it moves no stationarity
      row by more than that row's allowance); the z_i of a row with h_i = +inf (no
      constraint) must count as zero, of either sign.

    f = ``4 (n + 2) eps`` is the rounding floor: a computed vector is accurate normwise, not
    entry by entry, so each of x, y, z, zb is exact only to about f times its own largest
    entry (an entry whose exact value is 0 comes out at that level), and each row is moved
    by those errors times the absolute column sums (stationarity) or row sums (the primal
    rows) of the data.  ``t s_j`` alone is the rounding of the row's own terms, which is
    the whole error of an exact point rounded entry by entry; without the floor a row whose
    terms are all at the rounding level (an exact 0 computed as 1e-15) gets an allowance
    of 1e-27 and fails whatever the solver does.

    ``stats`` gets qpsolvers' primal residual, dual residual, duality gap and the objective,
    each summed in double-double (:func:`dot2`, :func:`axpy2`, :func:`acc2`): their values on
    the point as given, not the rounding noise of evaluating them (the gap's terms can be
    1e8 times larger than the gap; summed in double, the gap's own rounding would then be
    1e-8 whatever the point).
    """
    n = q.shape[0]
    t = tol + 4.0 * EPS
    # stationarity: P x + q + A'y + G'z + zb, accumulated over rows (P is symmetric)
    work = np.empty(4 * n)  # one allocation: s, err, size, allow
    s = work[:n]
    err = work[n:2 * n]
    size = work[2 * n:3 * n]
    allow = work[3 * n:]
    for j in range(n):
        s[j] = q[j]
        err[j] = 0.0
        size[j] = abs(q[j])
    axpy2_matrix(s, err, size, x, P)
    # x'(P x + q) in double-double (gap_hi + gap_lo), for the gap and the objective
    gap_hi = 0.0
    gap_lo = 0.0
    for j in range(n):
        gap_hi, gap_lo = acc2(gap_hi, gap_lo, x[j], s[j])
        gap_lo += x[j] * err[j]
    xPq_hi = gap_hi
    xPq_lo = gap_lo
    axpy2_matrix(s, err, size, y, A)
    axpy2_matrix(s, err, size, z, G)
    # The rounding floor: each of x, y, z, zb is exact only to about f = 4 (n + 2) eps times
    # its own largest entry; allow[j] first holds what those errors move stationarity row j
    # by, divided by f (the primal rows: f max|x| sum_j |a_ij|).
    f = 4.0 * (n + 2) * EPS
    x_top = 0.0
    y_top = 0.0
    z_top = 0.0
    zb_top = 0.0
    for j in range(n):
        x_top = max(x_top, abs(x[j]))
    for i in range(A.shape[0]):
        y_top = max(y_top, abs(y[i]))
    for i in range(G.shape[0]):
        z_top = max(z_top, abs(z[i]))
    for j in range(n):
        zb_top = max(zb_top, abs(zb[j]))
    for j in range(n):
        allow[j] = zb_top
    add_abs_rows(allow, x_top, P)
    add_abs_rows(allow, y_top, A)
    add_abs_rows(allow, z_top, G)
    ok = True
    dual = 0.0
    for j in range(n):
        r, e = two_sum(s[j], zb[j])
        r += e + err[j]
        allow[j] = t * (size[j] + abs(zb[j])) + f * allow[j]
        dual = max(dual, abs(r))
        if not abs(r) <= allow[j]:
            ok = False
    floor = f * x_top
    primal = 0.0
    for i in range(A.shape[0]):
        r, sz, norm = dot2_row(A, i, x, -b[i])
        primal = max(primal, abs(r))
        gap_hi, gap_lo = acc2(gap_hi, gap_lo, b[i], y[i])
        if not abs(r) <= t * sz + floor * norm:
            ok = False
    for i in range(G.shape[0]):
        if not h[i] < np.inf:  # no constraint: its z_i must count as zero (either sign)
            if z[i] != 0.0 and not counts_as_zero(z[i], G, i, allow):
                ok = False
            continue
        r, sz, norm = dot2_row(G, i, x, -h[i])
        sz = t * sz + floor * norm
        primal = max(primal, r)
        gap_hi, gap_lo = acc2(gap_hi, gap_lo, h[i], z[i])
        zi = z[i]
        if not (r <= sz and zi >= 0.0):
            ok = False
        elif zi > 0.0 and -r > sz and not counts_as_zero(zi, G, i, allow):
            ok = False  # an inactive row with a multiplier that is not zero
    for j in range(n):
        zj = zb[j]
        lo = lb[j] > -np.inf
        up = ub[j] < np.inf
        s_lo = t * (abs(lb[j]) + abs(x[j])) + floor
        s_up = t * (abs(ub[j]) + abs(x[j])) + floor
        if lo:
            r = lb[j] - x[j]
            primal = max(primal, r)
            if zj < 0.0:
                gap_hi, gap_lo = acc2(gap_hi, gap_lo, lb[j], zj)
            if r > s_lo:
                ok = False
        if up:
            r = x[j] - ub[j]
            primal = max(primal, r)
            if zj > 0.0:
                gap_hi, gap_lo = acc2(gap_hi, gap_lo, ub[j], zj)
            if r > s_up:
                ok = False
        if lb[j] == ub[j]:
            active = True  # a fixed variable: its multiplier has either sign
        elif zj < 0.0:
            active = lo and x[j] - lb[j] <= s_lo
        elif zj > 0.0:
            active = up and ub[j] - x[j] <= s_up
        else:
            active = True
        if not active and abs(zj) > allow[j]:
            ok = False
        if not (x[j] == x[j]):
            ok = False
    # obj = (x'(P x + q) + q'x) / 2
    obj_hi = xPq_hi
    obj_lo = xPq_lo
    for j in range(n):
        obj_hi, obj_lo = acc2(obj_hi, obj_lo, q[j], x[j])
    stats[0] = primal
    stats[1] = dual
    stats[2] = abs(gap_hi + gap_lo)
    stats[3] = 0.5 * (obj_hi + obj_lo)
    return ok


# ----------------------------------------------------------------------------- the solve

@kernel
def rows_of(G, h, A, b, lb, ub):
    """``(E, f, ekind, C, d, ckind)``: the equalities ``E x = f`` (A's rows, then a unit row
    per fixed variable) and the inequalities ``C x <= d`` (G's rows, then ``x_j <= ub_j``
    for each finite upper bound, then ``-x_j <= -lb_j`` for each finite lower bound) as
    dense rows; a row of G with h_i = +inf is no constraint and left out.  ``ekind[k]`` is -1
    for a row of A and j for fixed x_j; ``ckind[k]`` is ``-1 - i`` for row i of G, j for an
    upper bound of x_j and n + j for a lower bound."""
    n = lb.shape[0]
    p0 = A.shape[0]
    m0 = G.shape[0]
    n_fix = 0
    n_up = 0
    n_lo = 0
    for j in range(n):
        if lb[j] == ub[j]:
            n_fix += 1
        else:
            if ub[j] < np.inf:
                n_up += 1
            if lb[j] > -np.inf:
                n_lo += 1
    m_g = 0
    for i in range(m0):
        if h[i] < np.inf:
            m_g += 1
    m = m_g + n_up + n_lo
    p = p0 + n_fix
    # one allocation: [E | C | f | d | ekind ckind], the kinds int64 in float64 slots
    work = np.empty((p + m) * (n + 2))
    for t in range((p + m) * n):
        work[t] = 0.0
    E = work[:p * n].reshape((p, n))
    C = work[p * n:(p + m) * n].reshape((m, n))
    f = work[(p + m) * n:(p + m) * n + p]
    d = work[(p + m) * n + p:(p + m) * (n + 1)]
    kinds = work[(p + m) * (n + 1):].view(np.int64)
    for t in range(p + m):
        kinds[t] = -1
    ekind = kinds[:p]
    ckind = kinds[p:]
    for i in range(p0):
        Ei = row_of(E, i)
        Ai = row_of(A, i)
        for t in range(n):
            Ei[t] = Ai[t]
        f[i] = b[i]
    k = p0
    for j in range(n):
        if lb[j] == ub[j]:
            E[k, j] = 1.0
            f[k] = lb[j]
            ekind[k] = j
            k += 1
    k = 0
    for i in range(m0):
        if h[i] < np.inf:  # h_i = +inf: no constraint
            Ck = row_of(C, k)
            Gi = row_of(G, i)
            for t in range(n):
                Ck[t] = Gi[t]
            d[k] = h[i]
            ckind[k] = -1 - i
            k += 1
    for j in range(n):
        if lb[j] != ub[j] and ub[j] < np.inf:
            C[k, j] = 1.0
            d[k] = ub[j]
            ckind[k] = j
            k += 1
    for j in range(n):
        if lb[j] != ub[j] and lb[j] > -np.inf:
            C[k, j] = -1.0
            d[k] = -lb[j]
            ckind[k] = n + j
            k += 1
    return E, f, ekind, C, d, ckind


@kernel
def mlcp_basis(lb, ub, m_g, ckind, lcp_basic, out):
    """The final basis as ``solve_qp``'s KKT-MLCP numbers it (its ``WarmStart``): pairs
    ``(x'_j, z_i, z_ub_j)`` for the variables with a finite bound (not fixed), the rows of
    G and the boxed variables, in that order.  ``x'_j`` (the distance from the bound it is
    shifted by: lb when finite, else ub) is basic unless that bound's multiplier is; z_i and
    z_ub_j are basic with theirs.  Writes the sorted basic pairs in ``out``; returns their
    number and the number of pairs."""
    n = lb.shape[0]
    m = ckind.shape[0]
    flags = np.empty(m + 2 * n, dtype=np.bool_)  # one allocation: on, lo_on, up_on
    for t in range(m + 2 * n):
        flags[t] = False
    on = flags[:m]
    lo_on = flags[m:m + n]
    up_on = flags[m + n:]
    for i in range(lcp_basic.shape[0]):
        on[lcp_basic[i]] = True
    for i in range(m_g, m):
        j = ckind[i]
        if j < n:
            up_on[j] = on[i]
        else:
            lo_on[j - n] = on[i]
    k = 0
    pos = 0
    for j in range(n):
        lo = lb[j] > -np.inf
        up = ub[j] < np.inf
        if (lo or up) and lb[j] != ub[j]:
            if not (lo_on[j] if lo else up_on[j]):
                out[k] = pos
                k += 1
            pos += 1
    for i in range(m_g):
        if on[i]:
            out[k] = pos
            k += 1
        pos += 1
    for j in range(n):
        if lb[j] > -np.inf and ub[j] < np.inf and lb[j] != ub[j]:
            if up_on[j]:
                out[k] = pos
                k += 1
            pos += 1
    return k, pos


@kernel
def out_size(n, p, m):
    """The length of :func:`solve`'s output buffer: ``[x (n) | y (p) | z (m) | zb (n) |
    primal, dual, gap, obj]``."""
    return 2 * n + p + m + 4


@inline_kernel
def out_views(out, n, p0, m0):
    """The views ``(x, y, z, zb, stats)`` of the output buffer (see :func:`out_size`)."""
    return (out[:n], out[n:n + p0], out[n + p0:n + p0 + m0], out[n + p0 + m0:2 * n + p0 + m0],
            out[2 * n + p0 + m0:])


@kernel
def solve(P, q, G, h, A, b, lb, ub, method, max_pivots, pivot_tol, tie_tol, tol, out):
    """The fused cold path of the module docstring, on the caller's arrays (float64, of
    matching shapes; :func:`screen` decides whether their values are plainly valid).

    Writes in ``out`` (see :func:`out_size`) the QP's point and multipliers (qpsolvers'
signs: ``P x + q + A'y + G'z + zb = 0``) and ``(primal, dual, gap, obj)`` (qpsolvers'
    residuals, see :func:`kkt_check`), and after them (``out`` of length at least
    ``out_size(n, p, m) + m + 2n``, m the rows of G) the final basis as :func:`mlcp_basis`
    numbers it, int64 in the buffer's float64 slots (the caller reads them back through a
    view): one buffer, one allocation and one array to pass.  Returns ``(code, pivots, k, pairs)``: code OK,
    BAD_INPUT, NOT_DEFINITE, DEPENDENT_EQUALITIES, NOT_SOLVED or CHECK_FAILED; k the length
    of the basis, pairs the number of pairs it is a basis of.  ``max_pivots < 0`` means
    the default cap ``100 (m + 1)``, m the number of inequalities the LCP has.  Scalars and
    caller-made buffers only: boxing returned arrays costs more than a small solve."""
    k0 = out_size(q.shape[0], A.shape[0], G.shape[0])
    out[:k0] = 0.0
    ok, Ps, lb, ub = screen(P, q, G, h, A, b, lb, ub)
    if not ok:
        return BAD_INPUT, 0, 0, 0
    x, y, z, zb, stats = out_views(out, q.shape[0], A.shape[0], G.shape[0])
    return _solve(Ps, q, G, h, A, b, lb, ub, method, max_pivots, pivot_tol, tie_tol, tol,
                  x, y, z, zb, stats, out[k0:].view(np.int64))


@kernel
def solve_gram(P, q, G, h, A, b, lb, ub, max_pivots, pivot_tol, tie_tol, tol, out, basic,
               semidefinite):
    """Steps 7 and 8 of the module docstring alone, with :func:`solve`'s arguments (but the
    method: always the unrevised one) and outputs: NOT_APPLICABLE when the QP has fewer
    than ``GRAM_RATIO n`` inequalities (bounds counted), unless ``semidefinite`` (step 8:
    :func:`solve` found P not definite) and the equalities can pin P's flat directions;
    else as :func:`solve`.  An entry of its own, so that only a QP with many more
    inequalities than variables, or a P that is not definite, compiles it; what it does not
    solve with many rows the caller hands to :func:`solve`."""
    out[:] = 0.0
    ok, Ps, lb, ub = screen(P, q, G, h, A, b, lb, ub)
    if not ok:
        return BAD_INPUT, 0, 0, 0
    x, y, z, zb, stats = out_views(out, q.shape[0], A.shape[0], G.shape[0])
    return _solve_gram(Ps, q, G, h, A, b, lb, ub, max_pivots, pivot_tol, tie_tol, tol,
                       x, y, z, zb, stats, basic, semidefinite)


@kernel
def box_out_size(n):
    """The length of :func:`solve_box`'s output buffer: ``[boxed.solve's buffer (6n + 1:
    x, w, ...) | zb (n) | primal, dual, gap, obj]``."""
    return 7 * n + 5


@kernel
def box_basis(lo, up, final, k, m, out):
    """The final basis of a box LCP (``final[:k]`` the basic x's, ``final[k:m]`` those at
    their upper bounds, as ``boxed.solve`` writes them) as ``solve_qp``'s KKT-MLCP numbers
    its pairs (as :func:`mlcp_basis`): first one pair per variable with a finite bound that
    is not fixed, its shifted variable (x - lb, or ub - x when only ub is finite) basic
    when x is basic or sits at ub with lb finite; then one pair per boxed variable, its
    upper multiplier basic when x sits at ub.  Writes the basic pairs in ``out`` (length
    at least 2n), ascending; returns their number and the number of pairs."""
    n = lo.shape[0]
    flags = np.empty(2 * n, dtype=np.bool_)
    for j in range(2 * n):
        flags[j] = False
    for i in range(k):
        flags[final[i]] = True
    for i in range(k, m):
        flags[n + final[i]] = True
    cnt = 0
    pos = 0
    for j in range(n):
        lo_f = lo[j] > -np.inf
        up_f = up[j] < np.inf
        if (lo_f or up_f) and not (lo_f and up_f and lo[j] == up[j]):
            if flags[j] or (lo_f and flags[n + j]):
                out[cnt] = pos
                cnt += 1
            pos += 1
    for j in range(n):
        if lo[j] > -np.inf and up[j] < np.inf and lo[j] != up[j]:
            if flags[n + j]:
                out[cnt] = pos
                cnt += 1
            pos += 1
    return cnt, pos


@kernel
def solve_box(P, q, G, h, A, b, lb, ub, warm, max_pivots, pivot_tol, tie_tol, tol, out, final):
    """A QP whose only constraints are bounds, in one call, as ``solve_qp``'s box path
    (``lemke._qp._solve_box``) solves it: :func:`screen` (G, h, A, b empty), P definite
    (:func:`cholesky`), then one run of ``boxed.solve`` on the box LCP ``(Ps, q, lo, up)``
    (its KKT conditions: w = Ps x + q, z_box = -w), judged by its natural-map check
    (``boxed.box_check``), and then by the fused path's own check, :func:`kkt_check` at
    ``min(tol, STRICT_TOL)`` on the caller's data (so an answer from here is held to what
    :func:`solve` holds its answers to).

    Writes in ``out`` (:func:`box_out_size`) boxed.solve's buffer (x in its first n
    entries), zb and ``(primal, dual, gap, obj)``, and in ``final`` (length 3n) boxed.solve's
    final basis (its first n entries), then the basis as :func:`box_basis` numbers it.
    Returns ``(code, pivots, k, pairs)``: code OK, BAD_INPUT, NOT_DEFINITE, NOT_SOLVED (the
    run did not end solved and checked: the front's other paths, with their recoveries,
    decide) or CHECK_FAILED; ``final[n:n + k]`` the basic pairs of ``pairs``.  ``max_pivots`` as
    ``solve_blcp``'s (the front passes its default, ``100 (n + 1)``)."""
    n = q.shape[0]
    ok, Ps, lo, up = screen(P, q, G, h, A, b, lb, ub)
    if not ok:
        return BAD_INPUT, 0, 0, 0
    L = np.empty((n, n))
    if not cholesky(Ps, L):
        return NOT_DEFINITE, 0, 0, 0
    buf = out[:6 * n + 1]
    code, pivots, z0, solved, residual, k, m = boxed.solve(
        Ps, q, lo, up, warm, np.int64(0), max_pivots, pivot_tol, tie_tol, tol, buf, final[:n])
    if not (code == pivoting.SOLVED and solved):
        return NOT_SOLVED, pivots, 0, 0
    x = buf[:n]
    w = buf[n:2 * n]
    zb = out[6 * n + 1:7 * n + 1]
    for j in range(n):
        zb[j] = -w[j]
    if not kkt_check(Ps, q, G, h, A, b, lo, up, x, b, h, zb, min(tol, STRICT_TOL),
                     out[7 * n + 1:]):
        return CHECK_FAILED, pivots, 0, 0
    cnt, pairs = box_basis(lo, up, final, k, m, final[n:])
    return OK, pivots, cnt, pairs


@inline_kernel
def factors(q, G, h, A, b, lb, ub, L):
    """Steps 2 and 3 and the LCP's right-hand side, given ``L`` (P = L L'): ``(code, E, f,
    ekind, C, d, ckind, m_g, V, beta, c, v, g)`` with code OK or DEPENDENT_EQUALITIES, the
    rows of :func:`rows_of` turned into R (E) and F = Q'W (C), the reflectors, c = Q'L^-1 q,
    v1 in ``v[:p]`` and ``g = d - F1 v1 + F2 c2``."""
    n = q.shape[0]
    E, f, ekind, C, d, ckind = rows_of(G, h, A, b, lb, ub)
    p = E.shape[0]
    m = C.shape[0]
    m_g = 0
    while m_g < m and ckind[m_g] < 0:
        m_g += 1
    pv = min(p, n)
    # one allocation: V, beta, c, v, g, and up_row below (int64 in float64 slots)
    work = np.empty(pv * (n + 1) + 3 * n + m)
    V = work[:pv * n].reshape((pv, n))
    beta = work[pv * n:pv * (n + 1)]
    o = pv * (n + 1)
    c = work[o:o + n]
    v = work[o + n:o + 2 * n]
    g = work[o + 2 * n:o + 2 * n + m]
    for t in range(n):
        c[t] = q[t]
    if p > n:
        return DEPENDENT_EQUALITIES, E, f, ekind, C, d, ckind, m_g, V, beta, c, v, g
    # W' = rows L^-1 e_i, L^-1 c_i
    forward_rows(L, E)
    # The rows of G and of the upper bounds; a lower bound's row -e_j is then minus the
    # row of x_j's upper bound when it has one.
    m_u = m_g
    while m_u < m and ckind[m_u] < n:
        m_u += 1
    forward_rows(L, C[:m_u])
    up_row = work[o + 2 * n + m:].view(np.int64)
    for j in range(n):
        up_row[j] = -1
    for i in range(m_g, m_u):
        up_row[ckind[i]] = i
    for i in range(m_u, m):
        j = ckind[i] - n
        if up_row[j] >= 0:
            Ci = row_of(C, i)
            Cu = row_of(C, up_row[j])
            for t in range(n):
                Ci[t] = -Cu[t]
        else:
            forward(L, row_of(C, i))
    forward(L, c)
    if qr_rows(E, V, beta) <= RANK_TOL:
        return DEPENDENT_EQUALITIES, E, f, ekind, C, d, ckind, m_g, V, beta, c, v, g
    for k in range(p):
        householder_apply(V, beta, k, c)
        for i in range(m):
            householder_apply(V, beta, k, row_of(C, i))
    # v1 = R'^-1 f, R[k, j] = E[j, k] (j >= k): R' is lower triangular with rows E[k, :k+1]
    for k in range(p):
        v[k] = (f[k] - dot(row_of(E, k), v, k)) / E[k, k]
    # the LCP on the inequality multipliers: M = F2 F2', g = d - F1 v1 + F2 c2
    r = n - p
    c2 = c[p:]
    for i in range(m):
        Fi = row_of(C, i)
        g[i] = d[i] - dot(Fi, v, p) + dot(Fi[p:], c2, r)
    return OK, E, f, ekind, C, d, ckind, m_g, V, beta, c, v, g


@inline_kernel
def _solve(P, q, G, h, A, b, lb, ub, method, max_pivots, pivot_tol, tie_tol, tol,
           x, y, z, zb, stats, basic):
    """:func:`solve` on screened data (P symmetric, bounds beyond INFINITY infinite); the
    outputs are written in place.  Returns ``(code, pivots, k, pairs)``, k the length of
    the basis written in ``basic``."""
    n = q.shape[0]
    L = np.empty((n, n))
    if not cholesky(P, L):
        return NOT_DEFINITE, 0, 0, 0
    code, E, f, ekind, C, d, ckind, m_g, V, beta, c, v, g = factors(q, G, h, A, b, lb, ub, L)
    if code != OK:
        return code, 0, 0, 0
    p = E.shape[0]
    m = C.shape[0]
    r = n - p
    # one allocation per kind for the rest: [M | zz | ones | yy | LCP buffer], the LCP's basis
    work = np.empty(m * (m + 2) + p + cold.buffer_size(m))
    M = work[:m * m].reshape((m, m))
    zz = work[m * m:m * (m + 1)]
    ones = work[m * (m + 1):m * (m + 2)]
    yy = work[m * (m + 2):m * (m + 2) + p]
    buf = work[m * (m + 2) + p:]
    # the LCP's basis in the head of basic: mlcp_basis reads it whole before it writes there
    lcp_basic = basic[:m]
    for i in range(m):
        zz[i] = 0.0
        ones[i] = 1.0
    for i in range(m):
        F2i = row_of(C, i)[p:]
        for j in range(i + 1):
            M[i, j] = dot(F2i, row_of(C, j)[p:], r)
            M[j, i] = M[i, j]
    pivots = 0
    k_basic = 0
    if m > 0:
        cap = max_pivots if max_pivots >= 0 else 100 * (m + 1)
        # The covering vector all ones, as solve_lcp's default, but given: cold.checked then
        # makes no recovery runs after a first run whose point fails its check (see the
        # module docstring, step 4); cold.checked_once is that, without their code.
        code, pivots, k_basic, lcp_ok, residual, recoveries = cold.checked_once(
            method, M, g, ones, cap, pivot_tol, tie_tol, tol, buf, lcp_basic)
        if not (code == pivoting.SOLVED or code == cold.TRIVIAL) or not lcp_ok:
            return NOT_SOLVED, pivots, 0, 0
        for i in range(m):
            zz[i] = max(buf[i], 0.0)
    k_basic, pairs = mlcp_basis(lb, ub, m_g, ckind, lcp_basic[:k_basic], basic)
    # v2 = -c2 - F2' z;  x = L'^-1 Q v
    for t in range(p, n):
        v[t] = -c[t]
    for i in range(m):
        zi = zz[i]
        if zi != 0.0:
            Ci = row_of(C, i)
            for t in range(p, n):
                v[t] -= zi * Ci[t]
    point(L, E, V, beta, C, c, v, zz, x, yy)
    caller_form(x, y, z, zb, yy, zz, ekind, f, ckind, d, m_g, np.True_)
    # No refinement step here: the point is kept only when it is accurate far beyond the
    # tolerance; otherwise the KKT-MLCP path, which refines in double-double, answers.
    if not kkt_check(P, q, G, h, A, b, lb, ub, x, y, z, zb, min(tol, STRICT_TOL), stats):
        return CHECK_FAILED, pivots, k_basic, pairs
    return OK, pivots, k_basic, pairs


@kernel
def _solve_gram(P, q, G, h, A, b, lb, ub, max_pivots, pivot_tol, tie_tol, tol,
                x, y, z, zb, stats, basic, semidefinite):
    """:func:`solve_gram` on screened data (as :func:`_solve`)."""
    n = q.shape[0]
    few = inequalities(h, lb, ub) < GRAM_RATIO * n
    if few and not semidefinite:
        return NOT_APPLICABLE, 0, 0, 0
    L = np.empty((n, n))
    definite = False if semidefinite else cholesky(P, L)
    if not definite:
        # step 8: with few rows, only where the equalities can pin P's flat directions
        # (a zero P_jj is one, for a semidefinite P; the proximal factor counts them all)
        if few and zero_diagonal(P) > equalities(A, lb, ub):
            return NOT_APPLICABLE, 0, 0, 0
        if not proximal_cholesky(P, L):
            return NOT_DEFINITE, 0, 0, 0
        if few and flat_directions(P, L) > equalities(A, lb, ub):
            return NOT_APPLICABLE, 0, 0, 0
    code, E, f, ekind, C, d, ckind, m_g, V, beta, c, v, g = factors(q, G, h, A, b, lb, ub, L)
    if code != OK:
        return code, 0, 0, 0
    return _gram(P, q, G, h, A, b, lb, ub, L, E, f, ekind, C, d, ckind, m_g, V, beta, g,
                 max_pivots, pivot_tol, tie_tol, tol, x, y, z, zb, stats, basic,
                 np.int64(REFINE if definite else REFINE_PROXIMAL))


@kernel
def flat_directions(P, L):
    """The pivots of the proximal factor L (``L L' = P + delta I``) below ``FLAT max P_jj``:
    for a positive semidefinite P, the dimension of its null space (the k-th leading block
    of P + delta I has a pivot of order delta exactly where the nullity of P's k-th
    leading block grows), plus the directions of curvature below that."""
    top = 0.0
    for j in range(P.shape[0]):
        top = max(top, P[j, j])
    flat = 0
    for j in range(P.shape[0]):
        if L[j, j] * L[j, j] < FLAT * top:
            flat += 1
    return flat


@kernel
def zero_diagonal(P):
    """The number of zero entries of P's diagonal (for a positive semidefinite P, each is a
    direction of its null space, and they are independent)."""
    k = 0
    for j in range(P.shape[0]):
        if P[j, j] == 0.0:
            k += 1
    return k


@kernel
def equalities(A, lb, ub):
    """The number of equality rows :func:`rows_of` makes: A's rows and the fixed variables."""
    p = A.shape[0]
    for j in range(lb.shape[0]):
        if lb[j] == ub[j]:
            p += 1
    return p


@kernel
def inequalities(h, lb, ub):
    """The number of inequality rows :func:`rows_of` makes: the rows of G with a finite h,
    and the finite bounds of the variables that are not fixed."""
    m = 0
    for i in range(h.shape[0]):
        if h[i] < np.inf:
            m += 1
    for j in range(lb.shape[0]):
        if lb[j] != ub[j]:
            m += (ub[j] < np.inf) + (lb[j] > -np.inf)
    return m


@inline_kernel
def point(L, E, V, beta, C, c, v, zz, x, yy):
    """x and the equality multipliers yy from v (``v1``, ``v2`` filled), c = Q'L^-1 q and the
    inequality multipliers zz: ``yy = -R^-1 (v1 + c1 + F1 zz)`` and ``x = L'^-1 Q v`` (v is
    overwritten)."""
    p = E.shape[0]
    m = C.shape[0]
    # y = -R^-1 (v1 + c1 + F1 z): back substitution with R (R[k, j] = E[j, k]), the
    # right-hand side in yy (entry k is read before it is overwritten, the later ones after)
    for k in range(p):
        acc = v[k] + c[k]
        for i in range(m):
            acc += C[i, k] * zz[i]
        yy[k] = acc
    for k in range(p - 1, -1, -1):
        acc = yy[k]
        for j in range(k + 1, p):
            acc -= E[j, k] * yy[j]
        yy[k] = acc / E[k, k]
    for k in range(p):
        yy[k] = -yy[k]
    for k in range(p - 1, -1, -1):
        householder_apply(V, beta, k, v)
    backward_transposed(L, v)
    copy(x, v)


@inline_kernel
def caller_form(x, y, z, zb, yy, zz, ekind, f, ckind, d, m_g, snap):
    """The multipliers in qpsolvers' form (y of A's rows, z of G's, zb of the bounds) from
    those of the rows (yy of the equalities, zz of the inequalities); with ``snap``, x set
    exactly to each bound whose multiplier is positive and to each fixed variable's value
    (it came out of the substitutions within their rounding of it)."""
    n = x.shape[0]
    p = ekind.shape[0]
    m = ckind.shape[0]
    p0 = y.shape[0]
    if snap:
        for i in range(m_g, m):
            if zz[i] > 0.0:
                j = ckind[i]
                x[j if j < n else j - n] = d[i] if j < n else -d[i]
        for k in range(p0, p):  # a fixed variable is its bound, exactly
            x[ekind[k]] = f[k]
    z[:] = 0.0
    zb[:] = 0.0
    for i in range(p0):
        y[i] = yy[i]
    for k in range(p0, p):
        zb[ekind[k]] = yy[k]
    for i in range(m_g):
        z[-1 - ckind[i]] = zz[i]
    for i in range(m_g, m):
        j = ckind[i]
        if j < n:
            zb[j] += zz[i]
        else:
            zb[j - n] -= zz[i]


# ----------------------------------------------------------------------------- m >> n

@kernel
def proximal_cholesky(P, L):
    """L with ``L L' = P + delta I``, ``delta = PROXIMAL max_j P_jj``: the factor of the
    proximal term of the module docstring (step 7) for a P that is only semidefinite to
    rounding.  False when P has no positive diagonal entry or the factor does not exist."""
    n = P.shape[0]
    top = 0.0
    for j in range(n):
        top = max(top, P[j, j])
    if not top > 0.0:
        return False
    Pd = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            Pd[i, j] = P[i, j]
        Pd[i, i] += PROXIMAL * top
    return cholesky(Pd, L)


@inline_kernel
def gram_lcp(C, g, p, max_pivots, pivot_tol, tie_tol, flags):
    """Lemke's method on the LCP ``w = F2 F2' z + g`` (F2 the columns p.. of C's rows)
    without forming M: the unrevised method on its factored form (``unrevised.lemke`` with
    ``Fs``), each row of F2 scaled by the power of two nearest to 1 / its norm (M's
    diagonal then near 1: the symmetric equilibration of a Gram matrix), the covering vector
    all ones in those units.  ``flags`` gets the basic z's.  Returns ``(status, pivots)``
    (SOLVED with no pivot when g >= 0)."""
    m = g.shape[0]
    r = C.shape[1] - p
    for i in range(m):
        flags[i] = False
    g_min = 0.0
    for i in range(m):
        g_min = min(g_min, g[i])
    if g_min >= 0.0:
        return pivoting.SOLVED, 0
    work = np.empty(m * (r + 4) + 2)
    Fs = work[:m * r].reshape((m, r))
    dcol = work[m * r:m * (r + 1)].reshape((m, 1))
    gs = work[m * (r + 1):m * (r + 2)]
    out = work[m * (r + 2):]
    for i in range(m):
        Fi = row_of(C, i)
        norm2 = dot(Fi[p:], Fi[p:], r)
        # A row within rounding of the equalities' span (its part in v2 below RANK_TOL of
        # the whole, as qr_rows judges the equalities) is a constant, w_i = g_i: kept
        # exactly zero, not scaled up to a unit row of rounding noise.
        keep = norm2 > RANK_TOL * RANK_TOL * (norm2 + dot(Fi, Fi, p))
        s = pow2_rsqrt(norm2) if keep else 1.0
        Fsi = Fs[i]
        for t in range(r):
            Fsi[t] = s * Fi[p + t] if keep else 0.0
        gs[i] = s * g[i]
        dcol[i, 0] = 1.0
    cap = max_pivots if max_pivots >= 0 else 100 * (m + 1)
    return unrevised.lemke(dcol, Fs, gs, false_flags(m), no_matrix(), cap, pivot_tol, tie_tol,
                           out[:m + 1], out[m + 1:], flags)


@kernel
def active_solve(L, E, V, beta, C, S, K2, V2, beta2, rd, rpE, rpS, x, yy, zz):
    """The KKT point of the equality-constrained QP whose constraints are the equalities and
    the inequalities ``S`` (k of them) held as equalities, through the factors at hand:
    ``(x, yy, zz)`` with ``P x + rd + E'yy + C_S'zz_S = 0``, ``E x = rpE`` and ``C_S x = rpS``
    (P = L L').  K2 holds the QR of ``F2_S'`` (``qr_rows`` of the rows S of F2), V2 and
    beta2 its reflectors.  In v = Q'L'x: v1 as in :func:`_solve`, and v2 the projection of
    -c2 on ``F2_S v2 = rpS - F1_S v1`` by that QR, not the normal equations of the LCP's
    ``M_SS z_S = -g_S`` (whose condition is the square).  zz is written at S only."""
    n = x.shape[0]
    p = E.shape[0]
    k = S.shape[0]
    cc = rd.copy()
    forward(L, cc)
    for j in range(p):
        householder_apply(V, beta, j, cc)
    v = np.empty(n)
    for j in range(p):
        v[j] = (rpE[j] - dot(row_of(E, j), v, j)) / E[j, j]
    c2 = cc[p:]
    for j in range(k):
        householder_apply(V2, beta2, j, c2)
    w = v[p:]
    for j in range(k):  # w1 = R2'^-1 (rpS - F1_S v1), R2[t, j] = K2[j, t]
        w[j] = (rpS[j] - dot(row_of(C, S[j]), v, p) - dot(row_of(K2, j), w, j)) / K2[j, j]
    zS = np.empty(k)
    for j in range(k - 1, -1, -1):  # z_S = -R2^-1 (w1 + (Q2'c2)_1)
        acc = -(w[j] + c2[j])
        for t in range(j + 1, k):
            acc -= K2[t, j] * zS[t]
        zS[j] = acc / K2[j, j]
    for t in range(k, w.shape[0]):
        w[t] = -c2[t]
    for j in range(k - 1, -1, -1):
        householder_apply(V2, beta2, j, w)
    for i in range(C.shape[0]):
        zz[i] = 0.0
    for j in range(k):
        zz[S[j]] = zS[j]
    point(L, E, V, beta, C, cc, v, zz, x, yy)


@kernel
def active_residuals(P, q, G, h, A, b, lb, ub, x, y, z, zb, ekind, f, ckind, S, rd, rpE, rpS):
    """The residuals of the active set's KKT system at ``(x, y, z, zb)`` (qpsolvers' form)
    on the caller's data, each summed in double-double (:func:`axpy2`, :func:`dot2`):
    ``rd = P x + q + A'y + G'z + zb``, ``rpE = f - E x`` (A's rows, then the fixed
    variables) and ``rpS = d_S - C_S x`` (the inequalities S)."""
    n = x.shape[0]
    p0 = A.shape[0]
    s = q.copy()
    err = np.zeros(n)
    size = np.empty(n)
    axpy2_rows(s, err, size, x, P)
    axpy2_rows(s, err, size, y, A)
    for j in range(S.shape[0]):
        i = ckind[S[j]]
        if i < 0:
            axpy2(s, err, size, z[-1 - i], G[-1 - i])
    for j in range(n):
        t, e = two_sum(s[j], zb[j])
        rd[j] = t + (e + err[j])
    for k in range(ekind.shape[0]):
        if k < p0:
            rpE[k] = -dot2(A[k], x, -b[k])[0]
        else:
            rpE[k] = f[k] - x[ekind[k]]
    for j in range(S.shape[0]):
        i = ckind[S[j]]
        if i < 0:
            rpS[j] = -dot2(G[-1 - i], x, -h[-1 - i])[0]
        elif i < n:
            rpS[j] = ub[i] - x[i]
        else:
            rpS[j] = x[i - n] - lb[i - n]


@inline_kernel
def _gram(P, q, G, h, A, b, lb, ub, L, E, f, ekind, C, d, ckind, m_g, V, beta, g, max_pivots,
          pivot_tol, tie_tol, tol, x, y, z, zb, stats, basic, steps):
    """The path for m >> n (module docstring, step 7): the LCP by :func:`gram_lcp`, the
    point of its final basis by :func:`active_solve`, refined ``steps`` times on the
    caller's data (:func:`active_residuals`), checked by :func:`kkt_check`.  Returns
    ``(code, pivots, k, pairs)`` as :func:`_solve`."""
    n = x.shape[0]
    p = E.shape[0]
    m = C.shape[0]
    r = n - p
    flags = np.empty(m, dtype=np.bool_)
    status, pivots = gram_lcp(C, g, p, max_pivots, pivot_tol, tie_tol, flags)
    if status != pivoting.SOLVED:
        return NOT_SOLVED, pivots, 0, 0
    k = 0
    for i in range(m):
        if flags[i]:
            k += 1
    if k > r:
        return NOT_SOLVED, pivots, 0, 0
    S = np.empty(k, dtype=np.int64)
    k = 0
    for i in range(m):
        if flags[i]:
            S[k] = i
            k += 1
    K2 = np.empty((k, r))
    for j in range(k):
        Fi = row_of(C, S[j])[p:]
        K2j = row_of(K2, j)
        for t in range(r):
            K2j[t] = Fi[t]
    V2 = np.empty((k, r))
    beta2 = np.empty(k)
    if qr_rows(K2, V2, beta2) <= RANK_TOL:
        return NOT_SOLVED, pivots, 0, 0
    rd = q.copy()
    rpE = f.copy()
    rpS = np.empty(k)
    for j in range(k):
        rpS[j] = d[S[j]]
    xi = np.empty(n)
    yy = np.empty(p)
    zz = np.empty(m)
    active_solve(L, E, V, beta, C, S, K2, V2, beta2, rd, rpE, rpS, xi, yy, zz)
    dx = np.empty(n)
    dy = np.empty(p)
    dz = np.empty(m)
    for step in range(steps):
        copy(x, xi)
        caller_form(x, y, z, zb, yy, zz, ekind, f, ckind, d, m_g, np.False_)
        active_residuals(P, q, G, h, A, b, lb, ub, x, y, z, zb, ekind, f, ckind, S, rd, rpE, rpS)
        active_solve(L, E, V, beta, C, S, K2, V2, beta2, rd, rpE, rpS, dx, dy, dz)
        for t in range(n):
            xi[t] += dx[t]
        for t in range(p):
            yy[t] += dy[t]
        for j in range(k):
            zz[S[j]] += dz[S[j]]
    for j in range(k):
        zz[S[j]] = max(zz[S[j]], 0.0)
    copy(x, xi)
    caller_form(x, y, z, zb, yy, zz, ekind, f, ckind, d, m_g, np.True_)
    k_basic, pairs = mlcp_basis(lb, ub, m_g, ckind, S, basic)
    if not kkt_check(P, q, G, h, A, b, lb, ub, x, y, z, zb, min(tol, STRICT_TOL), stats):
        return CHECK_FAILED, pivots, k_basic, pairs
    return OK, pivots, k_basic, pairs
