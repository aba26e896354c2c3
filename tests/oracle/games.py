"""Bimatrix games: the Lemke-Howson method and the van den Elzen-Talman tracing procedure,
both on condensed tableaux with the shared pivoting rule of :mod:`lemke.kernels.pivoting`.

**Convention.**  ``A`` and ``B`` (both m x n) are the payoffs of the row player and of the
column player.  The labels are ``0..m-1`` for the row player's actions and ``m..m+n-1`` for
the column player's.

**Lemke-Howson.**  With payoffs made positive (``A' = 1 + (A - min A) f``, f a power of two
near 1 / (max A - min A), so integer payoffs stay exact; a positive affine change of a
player's payoffs changes no equilibrium) the two best-response polytopes are

    P = {x >= 0 : B'^T x <= 1}   (n rows, slack s_j with label m + j; x_i has label i)
    Q = {y >= 0 : A' y <= 1}     (m rows, slack r_i with label i; y_j has label m + j)

held as two condensed tableaux in the form of :mod:`lemke.kernels.tableau`,
``basic[i] = rhs[i] + sum_j T[i, j] nonbasic[j]``, with the slacks basic at the start (the
artificial equilibrium x = y = 0).  A label is *present* in a tableau when its variable is
non-basic there.  Dropping label k makes its variable enter in the tableau where it is
non-basic; the variable that leaves has a label l that is now present in both tableaux, so
the variable with label l enters in the other tableau, and so on until the label that leaves
is k: then every label is present once, and (x / sum x, y / sum y) is an equilibrium.

The leaving row is chosen by the shared rule (``pivoting.min_ratio``, then the lexicographic
keys of the basis inverse relative to the slack basis, read off the tableau as in
``tableau.ratio_test``), so the paths are those of the lexicographically perturbed game: in
exact arithmetic no basis repeats and every path ends.  The basis (both tableaux together)
is fingerprinted for Brent's cycle detector; a run that detects a repeated basis stops with
``CYCLING``, and :func:`lemke_howson` restarts it with exact ties, then with a slightly
perturbed right-hand side (whose final basis the front re-solves with the true one).

**The tracing procedure** (van den Elzen & Talman 1991; von Stengel, van den Elzen & Talman
2002): from a prior (p, q), with z0 going from 1 to 0, x and y (of mass 1 - z0 each) are best
responses to y + z0 q and x + z0 p.  This is Lemke's method on

    a = u 1 - A' y - (A' q) z0 >= 0  _|_  x >= 0
    b = v 1 - B'^T x - (B'^T p) z0 >= 0  _|_  y >= 0
    1^T x + z0 = 1,  1^T y + z0 = 1,     u, v free,

started at z0 = 1 from the best responses i*, j* to the prior (see :func:`trace`).

Every kernel checks its answer on the caller's payoffs (the largest regret of either player,
:func:`regrets`) before it reports ``SOLVED``.
"""
import math

import numpy as np

from . import kernel, pivoting
from .linalg import borrow, pow2_scale
from .pivoting import CYCLING, MAX_PIVOTS, NUMERICAL_FAILURE, RAY_TERMINATION, SOLVED

PERTURBATION = 1e-7  # relative perturbation of the right-hand side in the last restart
NOT_FINITE = -1  # a payoff is NaN or infinite: the front says which
UNCHECKED = 7  # a path ended with every label present, at a point that fails the check
ROUNDING_SLACK = 64.0  # regret allowance for rounding, in units of eps * (n + m) * max|payoff|


# --- the condensed tableau: shared by both methods -------------------------------------------

@kernel
def payoff_range(A):
    """``(lo, hi, finite)``: the smallest and the largest payoff and whether all are finite,
    in one pass.  Four independent running minima, maxima and sums of ``v * 0`` (0, or NaN
    for an infinite or NaN payoff): one chain of comparisons waits a few cycles on each
    element (the order cannot change lo and hi, except for the sign of a zero, which no
    use of them sees)."""
    lo0 = lo1 = lo2 = lo3 = np.inf
    hi0 = hi1 = hi2 = hi3 = -np.inf
    z0 = z1 = z2 = z3 = 0.0
    m, n = A.shape
    for i in range(m):
        j = 0
        while j + 4 <= n:
            v0, v1, v2, v3 = A[i, j], A[i, j + 1], A[i, j + 2], A[i, j + 3]
            lo0, lo1, lo2, lo3 = min(lo0, v0), min(lo1, v1), min(lo2, v2), min(lo3, v3)
            hi0, hi1, hi2, hi3 = max(hi0, v0), max(hi1, v1), max(hi2, v2), max(hi3, v3)
            z0, z1, z2, z3 = z0 + v0 * 0.0, z1 + v1 * 0.0, z2 + v2 * 0.0, z3 + v3 * 0.0
            j += 4
        while j < n:
            v = A[i, j]
            lo0 = min(lo0, v)
            hi0 = max(hi0, v)
            z0 += v * 0.0
            j += 1
    finite = (z0 + z1) + (z2 + z3) == 0.0
    return min(min(lo0, lo1), min(lo2, lo3)), max(max(hi0, hi1), max(hi2, hi3)), finite


@kernel
def positive_scale(lo, hi):
    """The factor f of :func:`positive_payoffs`."""
    return pow2_scale(hi - lo) if hi > lo else 0.0


@kernel
def positive_payoffs(A):
    """``1 + (A - min A) f`` with f the power of two nearest 1 / (max A - min A) (1 when all
    payoffs are equal): entries in [1, 2.5), exact for integer payoffs."""
    lo, hi, _ = payoff_range(A)
    f = positive_scale(lo, hi)
    out = np.empty_like(A)
    for i in range(A.shape[0]):
        for j in range(A.shape[1]):
            out[i, j] = 1.0 + (A[i, j] - lo) * f
    return out


@kernel
def exchange(T, rhs, magb, r, s, col, prow):
    """Pivot: the non-basic variable of column s (its current column in ``col``) replaces the
    basic variable of row r.  ``magb`` is a running upper bound on the size |B^-1| |q| of the
    terms behind each value (see :func:`leaving_row`).  ``prow``: scratch of length
    T.shape[1]."""
    n, k = T.shape
    inv = 1.0 / col[r]
    for j in range(k):  # (prow[s] is not set to inv: the rows' entries s are overwritten)
        v = -T[r, j] * inv
        prow[j] = v
        T[r, j] = v
    T[r, s] = inv
    rr = -rhs[r] * inv
    rhs[r] = rr
    magb[r] *= abs(inv)
    mr = magb[r]
    for i in range(n):
        f = col[i]
        if i != r and f != 0.0:
            rhs[i] += f * rr
            magb[i] += abs(f) * mr
            for j in range(k):  # indexed directly: a row view per row costs refcounting
                T[i, j] += f * prow[j]
            T[i, s] = f * inv


@kernel
def binv(T, pos, is_basic, lab, i):
    """Entry i of the basis inverse's column for the label ``lab`` basic at the start: the
    unit vector of its row while basic, minus its tableau column when not."""
    if is_basic[lab]:
        return 1.0 if pos[lab] == i else 0.0
    return -T[i, pos[lab]]


@kernel
def row_size(T, i, basis, wlab, wcol):
    """The size |B^-1| |q0| of the terms behind row i's value: ``wlab[lab]`` is |q0| of the
    row where label ``lab`` was basic at the start (0 for the other labels) and ``wcol`` the
    same per non-basic column, so the row of B^-1 is read off the tableau row in one
    contiguous pass."""
    size = wlab[basis[i]]
    for c in range(T.shape[1]):
        size += abs(T[i, c]) * wcol[c]
    return size


@kernel
def column_weights(nonbasic, wlab, wcol):
    """``wcol[c] = wlab[nonbasic[c]]`` (see :func:`row_size`)."""
    for c in range(nonbasic.shape[0]):
        wcol[c] = wlab[nonbasic[c]]


@kernel
def leaving_row(T, rhs, col, basis, pos, is_basic, start_basis, has_free, free, art, z0_max,
                pivot_tol, tie_tol, cand, keys, scratch, wlab, wcol, magb, mags):
    """The row that blocks the entering column (current entries ``col``) by the shared rule:
    ``pivoting.min_ratio`` (the artificial variable's row ``art`` first on a tie), then the
    lexicographic keys of the basis inverse relative to ``start_basis`` (the labels basic at
    the start, row by row).  With ``has_free``, rows whose basic variable is ``free`` never
    block.  -1 when
    nothing blocks.

    A value counts as zero when it is rounding of an exact zero: below
    ``pivoting.VALUE_ROUNDING`` times the size |B^-1| |q0| of its terms (:func:`row_size`).
    That size is computed only for the blocking rows whose value is below that fraction of
    the running bound ``magb`` (which it then replaces); the others pass their value as
    their size."""
    n = T.shape[0]
    c = col
    if has_free:  # free rows never block: their entries count as 0
        for i in range(n):
            scratch[i] = 0.0 if free[basis[i]] else col[i]
        c = scratch
    exact_sizes = False  # mags holds the sizes (else the values stand for their sizes)
    for i in range(n):
        v = rhs[i]
        if c[i] < 0.0 and v > 0.0 and v <= pivoting.VALUE_ROUNDING * magb[i]:
            if not exact_sizes:
                exact_sizes = True
                for j in range(n):
                    mags[j] = rhs[j]
            size = row_size(T, i, basis, wlab, wcol)
            mags[i] = size
            magb[i] = size  # the bound of this row is exact again
    nc = pivoting.min_ratio(rhs, mags if exact_sizes else rhs, c, n, pivot_tol, tie_tol, cand,
                            art, z0_max)
    return lex_break(T, c, pos, is_basic, start_basis, art, pivot_tol, tie_tol, cand, keys, nc)


@kernel
def lex_break(T, c, pos, is_basic, start_basis, art, pivot_tol, tie_tol, cand, keys, nc):
    """The row among the ``nc`` candidates tied at the minimum ratio (``cand``): the
    artificial variable's row ``art`` if tied, else the lexicographic minimum of the basis
    inverse's rows relative to ``start_basis``; -1 when nothing blocks."""
    if nc <= 1:
        return cand[0] if nc == 1 else -1
    for t in range(nc):
        if cand[t] == art:
            return art
    # Column j of the basis inverse is the current column of the variable basic in row j at
    # the start: the unit vector of its row while basic, minus its tableau column when not.
    for j in range(T.shape[0]):
        lab = start_basis[j]
        for t in range(nc):
            i = cand[t]
            keys[t] = pivoting.lex_key(binv(T, pos, is_basic, lab, i), c[i], pivot_tol)
        nc = pivoting.keep_lowest(cand, keys, nc, tie_tol)
        if nc == 1:
            return cand[0]
    return pivoting.largest_pivot(cand, c, nc) if nc > 0 else -1


@kernel
def place(T, rhs, magb, basis, nonbasic, pos, is_basic, target, col, prow):
    """Pivot until the labels ``target`` (one per row, any order) are the basic ones: each
    missing label enters in the row, among those whose basic label is not wanted, with the
    largest entry.  Returns False if the target basis is singular."""
    n = T.shape[0]
    done = True
    for lab in target:
        done &= is_basic[lab]
    if done:
        return True
    want = np.zeros(is_basic.shape[0], dtype=np.bool_)
    for lab in target:
        want[lab] = True
    for lab in target:
        if is_basic[lab]:
            continue
        s = pos[lab]
        best = np.int64(-1)  # not a literal: see kernels/__init__.py
        big = 0.0
        for i in range(n):
            if not want[basis[i]] and abs(T[i, s]) > big:
                big = abs(T[i, s])
                best = i
        if best < 0 or big < 1e-12:
            return False
        for i in range(n):
            col[i] = T[i, s]
        swap(T, rhs, magb, basis, nonbasic, pos, is_basic, best, s, col, prow)
    return True


@kernel
def swap(T, rhs, magb, basis, nonbasic, pos, is_basic, r, s, col, prow):
    """:func:`exchange` and the bookkeeping of the labels; returns the label that left."""
    exchange(T, rhs, magb, r, s, col, prow)
    return pivoting.swap_labels(basis, nonbasic, pos, is_basic, r, s)


# --- the check on the caller's payoffs --------------------------------------------------------

@kernel
def support(v, idx):
    """The indices of v's non-zero entries, in order, in ``idx``; returns how many."""
    k = 0
    for i in range(v.shape[0]):
        if v[i] != 0.0:
            idx[k] = i
            k += 1
    return k


@kernel
def regrets(A, B, x, y, acc, idx):
    """``(row regret, column regret, row payoff, column payoff)`` of the profile (x, y):
    max_i (A y)_i - x'A y and max_j (B'x)_j - x'B y, on the caller's payoffs.  Only the
    support of the opponent's strategy is summed over, in increasing order, so each
    (A y)_i is the sum over all j bit for bit (a zero term leaves a sum unchanged: the
    payoffs are finite); ``(B'x)_j`` is accumulated row by row of B in ``acc`` (n), which
    reads B contiguously.  ``idx``: scratch of length max(m, n)."""
    m, n = A.shape
    k = support(y, idx)
    best_a = -np.inf
    pay_a = 0.0
    for i in range(m):
        t = 0.0
        for q in range(k):
            j = idx[q]
            t += A[i, j] * y[j]
        best_a = max(best_a, t)
        pay_a += x[i] * t
    acc[:n] = 0.0
    k = support(x, idx)
    for q in range(k):
        i = idx[q]
        xi = x[i]
        for j in range(n):
            acc[j] += B[i, j] * xi
    best_b = -np.inf
    pay_b = 0.0
    for j in range(n):
        best_b = max(best_b, acc[j])
        pay_b += y[j] * acc[j]
    return best_a - pay_a, best_b - pay_b, pay_a, pay_b


@kernel
def allowance(lo, hi, m, n, tol):
    """The regret accepted for payoffs in [lo, hi] (m x n): tol times their range plus
    rounding."""
    big = max(abs(lo), abs(hi))
    return tol * (hi - lo) + ROUNDING_SLACK * 2.2e-16 * (m + n) * big


@kernel
def check(A, B, x, y, tol, out):
    """Is (x, y) an equilibrium of (A, B)?  x, y must be probability vectors (checked here
    too); ``out`` gets (regret, row payoff, column payoff).  Returns the verdict."""
    m, n = A.shape
    loA, hiA, _ = payoff_range(A)
    loB, hiB, _ = payoff_range(B)
    return verdict(A, B, x, y, allowance(loA, hiA, m, n, tol), allowance(loB, hiB, m, n, tol),
                   out, np.empty(n), np.empty(max(m, n), dtype=np.int64))


@kernel
def verdict(A, B, x, y, allow_a, allow_b, out, acc, idx):
    """:func:`check` given the allowances; ``acc``, ``idx``: scratch (see :func:`regrets`)."""
    ok = True
    sx = 0.0
    for v in x:
        ok &= v >= 0.0
        sx += v
    sy = 0.0
    for v in y:
        ok &= v >= 0.0
        sy += v
    ok &= abs(sx - 1.0) <= 1e-12 * x.shape[0] and abs(sy - 1.0) <= 1e-12 * y.shape[0]
    ra, rb, pa, pb = regrets(A, B, x, y, acc, idx)
    out[0] = max(ra, rb)
    out[1] = pa
    out[2] = pb
    return ok and ra <= allow_a and rb <= allow_b


@kernel
def normalize(v):
    """v / sum(v) with negative rounding clamped to 0; False when nothing is left."""
    t = 0.0
    for i in range(v.shape[0]):
        v[i] = max(v[i], 0.0)
        t += v[i]
    if not t > 0.0 or not t < np.inf:
        return False
    for i in range(v.shape[0]):
        v[i] /= t
    return True


# --- Lemke-Howson -----------------------------------------------------------------------------

@kernel
def step(T, rhs, magb, basis, nonbasic, pos, inb, start, wlab, wcol, entering, has_free,
         free, art, z0_max, pivot_tol, tie_tol, col, prow, cand, keys, scratch, mags):
    """One pivot in one tableau: the variable with label ``entering`` enters, the row of
    :func:`leaving_row` leaves.  Returns the label that left, -1 when nothing blocks (a
    ray) or -2 when the pivot entry is not finite.

    The common case takes a shortcut to the same row: while the column is read, its
    largest entry and whether any blocking row's value needs its exact size (see
    :func:`leaving_row`) are found; with no free rows, no artificial variable and no such
    value, :func:`leaving_row` would pass the values as their own sizes to the shared rule,
    which is then called directly (``pivoting.blocking_rows``, one pass over the rows)."""
    s = pos[entering]
    rows = T.shape[0]
    cmax = 0.0
    sized = False  # some blocking row's value may be rounding of a zero
    for i in range(rows):
        v = T[i, s]
        col[i] = v
        cmax = max(cmax, abs(v))
        b = rhs[i]  # (no branch on the sign of v: it would be mispredicted half the time)
        sized |= (v < 0.0) & (b > 0.0) & (b <= pivoting.VALUE_ROUNDING * magb[i])
    if has_free or art >= 0 or sized:
        r = leaving_row(T, rhs, col, basis, pos, inb, start, has_free, free, art, z0_max,
                        pivot_tol, tie_tol, cand, keys, scratch, wlab, wcol, magb, mags)
    else:
        nc = pivoting.blocking_rows(rhs, rhs, col, rows, -pivot_tol * cmax, tie_tol, cand, art,
                                    z0_max)
        r = cand[0] if nc == 1 else lex_break(T, col, pos, inb, start, art, pivot_tol, tie_tol,
                                              cand, keys, nc)
    leaving = -1
    if r >= 0 and not abs(col[r]) < np.inf:
        leaving = -2
    elif r >= 0:
        magb[r] = row_size(T, r, basis, wlab, wcol)  # a loose bound would spread to all rows
        exchange(T, rhs, magb, r, s, col, prow)
        leaving = pivoting.swap_labels(basis, nonbasic, pos, inb, r, s)
        wcol[s] = wlab[leaving]
    return leaving


@kernel
def tableau_setup(P, lo, f, T, rhs, basis, nonbasic, pos, is_basic, first):
    """One tableau at the artificial equilibrium, in place: ``T[r, c] = -(1 + (P[c, r] - lo)
    f)`` (the positive payoffs of :func:`positive_payoffs`, transposed: rows are P's columns),
    ``rhs = 1``; the slacks (labels ``first``, ``first + 1``, ... modulo m + n) basic row by
    row, the other labels non-basic column by column."""
    rows, cols = T.shape
    L = rows + cols
    for r in range(rows):
        for c in range(cols):
            T[r, c] = -(1.0 + (P[c, r] - lo) * f)
        rhs[r] = 1.0
        lab = (first + r) % L
        basis[r] = lab
        pos[lab] = r
        is_basic[lab] = True
    for c in range(cols):
        lab = (first + rows + c) % L
        nonbasic[c] = lab
        pos[lab] = c
        is_basic[lab] = False


HISTORY = 64  # the leaving labels of the last HISTORY pivots of a path are kept (a power of 2)
STATE = 3 + HISTORY  # the path's state after the labels in ibuf (see lemke_howson)


@kernel
def lh_path(A, B, scale, k, startP, startQ, perturb, max_pivots, pivot_tol, tie_tol, x, y,
            basisP, basisQ, state, F, I, Z, U):
    """One Lemke-Howson path on the positive payoffs of (A, B) (``scale`` = lo and f of A,
    then of B, see :func:`positive_payoffs`), dropping label k, from the basis whose basic
    labels are ``startP`` (n) and ``startQ`` (m) (the slack labels: the artificial
    equilibrium).  ``perturb``: multiply the right-hand sides by fixed pseudo-random factors
    1 + PERTURBATION [0, 1).  F, I, Z, U: work space (float, int, bool, uint64; see
    :func:`lemke_howson`), so that a solve allocates four arrays.

    Returns ``(status, pivots)``; x, y get the final (unnormalized) strategies, ``basisP``,
    ``basisQ`` the final basic labels row by row, ``state`` (STATE) where the path stands:
    the label that enters next and its side (0: P, 1: Q; after the last pivot, the label
    that left and the other side), the pivots of this run, then the labels that left in
    its last HISTORY pivots (pivot t's at ``3 + t % HISTORY``).
    """
    m, n = A.shape
    L = m + n
    big = max(m, n)
    # The work arrays borrowed from F, I, Z, U (linalg.borrow: step, called every pivot with
    # a dozen of them, then counts no references; with views that was a sixth of a solve)
    f8, i8 = np.float64, np.int64
    o = 0
    TP = borrow(F, o, (n, m), f8)
    o += n * m
    TQ = borrow(F, o, (m, n), f8)
    o += m * n
    rP, mbP = borrow(F, o, n, f8), borrow(F, o + n, n, f8)
    rQ, mbQ = borrow(F, o + 2 * n, m, f8), borrow(F, o + 2 * n + m, m, f8)
    o += 2 * L
    wlabP, wlabQ = borrow(F, o, L, f8), borrow(F, o + L, L, f8)
    wcolP, wcolQ = borrow(F, o + 2 * L, m, f8), borrow(F, o + 2 * L + m, n, f8)
    o += 3 * L
    col, prow, scratch = borrow(F, o, big, f8), borrow(F, o + big, big, f8), borrow(F, o + 2 * big, big, f8)
    keys_, mags = borrow(F, o + 3 * big, big, f8), borrow(F, o + 4 * big, big, f8)
    bP, nP, bQ, nQ = borrow(I, 0, n, i8), borrow(I, n, m, i8), borrow(I, L, m, i8), borrow(I, L + m, n, i8)
    posP, posQ = borrow(I, 2 * L, L, i8), borrow(I, 3 * L, L, i8)
    slackP, slackQ = borrow(I, 4 * L, n, i8), borrow(I, 4 * L + n, m, i8)
    cand = borrow(I, 5 * L, big, i8)
    inP, inQ, free = borrow(Z, 0, L, np.bool_), borrow(Z, L, L, np.bool_), borrow(Z, 2 * L, L, np.bool_)
    hkeys, detector = borrow(U, 0, 2 * L, np.uint64), borrow(U, 2 * L, 3, np.uint64)
    tableau_setup(B, scale[2], scale[3], TP, rP, bP, nP, posP, inP, m)
    tableau_setup(A.T, scale[0], scale[1], TQ, rQ, bQ, nQ, posQ, inQ, np.int64(0))
    slackP[:] = bP
    slackQ[:] = bQ
    if perturb:
        pivoting.fill_label_keys(hkeys[:L])
        for j in range(n):
            rP[j] *= 1.0 + PERTURBATION * pivoting.unit_random(hkeys, m + j)
        for i in range(m):
            rQ[i] *= 1.0 + PERTURBATION * pivoting.unit_random(hkeys, i)
    for j in range(n):  # bounds on the size of each value (leaving_row)
        mbP[j] = abs(rP[j])
    for i in range(m):
        mbQ[i] = abs(rQ[i])
    wlabP[:] = 0.0
    wlabQ[:] = 0.0
    for j in range(n):
        wlabP[m + j] = abs(rP[j])
    for i in range(m):
        wlabQ[i] = abs(rQ[i])
    free[:] = False
    status = MAX_PIVOTS
    pivots = 0
    if not (place(TP, rP, mbP, bP, nP, posP, inP, startP, col, prow)
            and place(TQ, rQ, mbQ, bQ, nQ, posQ, inQ, startQ, col, prow)):
        status = NUMERICAL_FAILURE
        max_pivots = 0
    column_weights(nP, wlabP, wcolP)
    column_weights(nQ, wlabQ, wcolQ)
    pivoting.fill_label_keys(hkeys)
    h = pivoting.fingerprint(hkeys, bP, n) ^ pivoting.fingerprint(hkeys, bQ + L, m)
    detector[:] = 0
    hist = state[3:]
    entering = k
    side = 0 if not inP[k] else 1  # the tableau where label k is present (non-basic)
    while pivots < max_pivots:
        # Two calls rather than one call on arrays chosen by side: numba reference-counts
        # every array variable that is reassigned, which costs more than a small pivot.
        if side == 0:
            leaving = step(TP, rP, mbP, bP, nP, posP, inP, slackP, wlabP, wcolP, entering,
                           np.False_, free, np.int64(-1), 0.0, pivot_tol, tie_tol, col, prow,
                           cand, keys_, scratch, mags)
        else:
            leaving = step(TQ, rQ, mbQ, bQ, nQ, posQ, inQ, slackQ, wlabQ, wcolQ, entering,
                           np.False_, free, np.int64(-1), 0.0, pivot_tol, tie_tol, col, prow,
                           cand, keys_, scratch, mags)
        if leaving < 0:
            status = NUMERICAL_FAILURE  # P and Q are bounded: a ray is rounding
            break
        hist[pivots & (HISTORY - 1)] = leaving
        pivots += 1
        shift = 0 if side == 0 else L
        h, stop = pivoting.after_pivot(leaving + shift, entering + shift, k + shift, h, hkeys, detector)
        entering = leaving
        side = 1 - side
        if stop >= 0:
            status = stop
            break
    state[0] = entering
    state[1] = side
    state[2] = pivots
    x[:] = 0.0
    y[:] = 0.0
    for j in range(n):
        if bP[j] < m:
            x[bP[j]] = rP[j]
    for i in range(m):
        if bQ[i] >= m:
            y[bQ[i] - m] = rQ[i]
    basisP[:] = bP
    basisQ[:] = bQ
    return status, pivots


@kernel
def lemke_howson(A, B, k, start, params, buf):
    """Lemke-Howson dropping label k, checked on the caller's (A, B); one kernel call per
    solve, its arguments packed (numba's dispatch costs per argument):

    - ``start`` (n + m): the basic labels to start from, those of P then those of Q (the
      slack labels ``m..m+n-1, 0..m-1``: the artificial equilibrium);
    - ``params``: ``(max_pivots, pivot_tol, tie_tol, tol)``;
    - ``buf`` (2 (m + n) + 3 + STATE, one array: numpy allocates once) receives ``[x | y |
      regret, row payoff, column payoff]``, then, as int64 (``buf[m + n + 3:].view``), the
      final basic labels of P then Q, then the state of the last run (see
      :func:`lh_path`: the exact continuation of the front starts from it).

    A path that cycles or breaks down is restarted with exact ties, then with a perturbed
    right-hand side.  Returns ``(status, pivots, restarts)``: ``SOLVED`` (checked),
    ``UNCHECKED`` (the path ended, every label present, but the point fails the check: the
    front re-solves that basis), ``NOT_FINITE`` (nothing done), or the status of the last
    run."""
    m, n = A.shape
    loA, hiA, okA = payoff_range(A)
    loB, hiB, okB = payoff_range(B)
    if not (okA and okB):
        return NOT_FINITE, 0, 0
    L = m + n
    big = max(m, n)
    max_pivots = int(params[0])
    pivot_tol, tie_tol, tol = params[1], params[2], params[3]
    x = buf[:m]
    y = buf[m:L]
    out = buf[L : L + 3]
    ibuf = buf[L + 3 :].view(np.int64)
    startP, startQ = start[:n], start[n:]
    basisP, basisQ, state = ibuf[:n], ibuf[n:L], ibuf[L : L + STATE]
    scale = np.array([loA, positive_scale(loA, hiA), loB, positive_scale(loB, hiB)])
    F = np.empty(2 * m * n + 5 * L + 5 * big)
    I = np.empty(5 * L + big, dtype=np.int64)
    Z = np.empty(3 * L, dtype=np.bool_)
    U = np.empty(2 * L + 3, dtype=np.uint64)
    pivots = 0
    restarts = 0
    status = NUMERICAL_FAILURE
    for attempt in range(3):
        if attempt == 1 and tie_tol == 0.0:
            continue  # the first run had exact ties already
        if attempt > 0:
            restarts += 1
        tt = tie_tol if attempt == 0 else 0.0
        status, p = lh_path(A, B, scale, k, startP, startQ, attempt == 2, max_pivots - pivots,
                            pivot_tol, tt, x, y, basisP, basisQ, state, F, I, Z, U)
        pivots += p
        if status == SOLVED or status == MAX_PIVOTS or pivots >= max_pivots:
            break
    good = normalize(x) and normalize(y)
    if not good:
        out[0] = np.inf
        return (NUMERICAL_FAILURE if status == SOLVED else status), pivots, restarts
    ok = verdict(A, B, x, y, allowance(loA, hiA, m, n, tol), allowance(loB, hiB, m, n, tol),
                 out, F[:n], I[:big])
    if status == SOLVED and not ok:
        status = UNCHECKED
    return status, pivots, restarts


# --- the tracing procedure --------------------------------------------------------------------

@kernel
def trace(A, B, p, q, max_pivots, pivot_tol, tie_tol, tol, x, y, basis_out, out):
    """The van den Elzen-Talman tracing procedure from the prior (p, q), as Lemke's method on
    the system of the module docstring.  Returns ``(status, pivots)``; x, y get the
    strategies, ``basis_out`` (m + n + 2) the final basic labels, ``out`` as in
    :func:`lemke_howson`.

    Variables (labels): x_i -> i, y_j -> m + j, a_i -> L + i, b_j -> L + m + j (L = m + n),
    u -> 2L, v -> 2L + 1, z0 -> 2L + 2, and the slacks of the two equations 2L + 3, 2L + 4
    (they start basic, leave in the setup pivots and, having no complement, never return).
    Rows: a (m), b (n), then the two equations.
    """
    m, n = A.shape
    L = m + n
    N = L + 2
    U, V, Z0, E1, E2 = 2 * L, 2 * L + 1, 2 * L + 2, 2 * L + 3, 2 * L + 4
    Ap = positive_payoffs(A)
    Bp = positive_payoffs(B)
    # Non-basic columns at the start: x (m), y (n), u, v, z0.
    T = np.zeros((N, L + 3))
    rhs = np.zeros(N)
    for i in range(m):
        aq = 0.0
        for j in range(n):
            T[i, m + j] = -Ap[i, j]
            aq += Ap[i, j] * q[j]
        T[i, L] = 1.0
        T[i, L + 2] = -aq
    for j in range(n):
        bp = 0.0
        for i in range(m):
            T[m + j, i] = -Bp[i, j]
            bp += Bp[i, j] * p[i]
        T[m + j, L + 1] = 1.0
        T[m + j, L + 2] = -bp
    for i in range(m):
        T[L, i] = -1.0
    for j in range(n):
        T[L + 1, m + j] = -1.0
    T[L, L + 2] = -1.0
    T[L + 1, L + 2] = -1.0
    rhs[L] = 1.0
    rhs[L + 1] = 1.0
    labels = 2 * L + 5
    basis = np.empty(N, dtype=np.int64)
    nonbasic = np.empty(L + 3, dtype=np.int64)
    pos = np.empty(labels, dtype=np.int64)
    inb = np.zeros(labels, dtype=np.bool_)
    for r in range(L):
        basis[r] = L + r
    basis[L] = E1
    basis[L + 1] = E2
    for c in range(L):
        nonbasic[c] = c
    nonbasic[L] = U
    nonbasic[L + 1] = V
    nonbasic[L + 2] = Z0
    for r in range(N):
        pos[basis[r]] = r
        inb[basis[r]] = True
    for c in range(L + 3):
        pos[nonbasic[c]] = c
    # The best responses to the prior (the first on ties): their slacks are 0 at z0 = 1.
    istar = 0
    best = -np.inf
    for i in range(m):
        if -T[i, L + 2] > best:
            best = -T[i, L + 2]
            istar = i
    jstar = 0
    best = -np.inf
    for j in range(n):
        if -T[m + j, L + 2] > best:
            best = -T[m + j, L + 2]
            jstar = j
    col = np.empty(N)
    prow = np.empty(L + 3)
    magb = np.abs(rhs)
    # Setup: u for a_i*, v for b_j*, z0 for the first equation's slack, y_j* (at 0) for the
    # second's; the path then starts with x_i* entering.
    target = np.array([U, V, Z0, m + jstar])
    rows = np.array([istar, m + jstar, L, L + 1])
    for t in range(4):
        s = pos[target[t]]
        for i in range(N):
            col[i] = T[i, s]
        swap(T, rhs, magb, basis, nonbasic, pos, inb, rows[t], s, col, prow)
    start = basis.copy()
    # The system is relative to this basis from here on.
    magb[:] = np.abs(rhs)
    mags = np.empty(N)
    wlab = np.zeros(labels)
    for r in range(N):
        wlab[basis[r]] = abs(rhs[r])
    wcol = np.empty(L + 3)
    column_weights(nonbasic, wlab, wcol)
    free = np.zeros(labels, dtype=np.bool_)
    free[U] = True
    free[V] = True
    cand = np.empty(N, dtype=np.int64)
    keys = np.empty(N)
    scratch = np.empty(N)
    hkeys = pivoting.label_keys(labels)
    h = pivoting.fingerprint(hkeys, basis, N)
    detector = pivoting.new_detector()
    status = MAX_PIVOTS
    pivots = 0
    entering = istar
    z0_max = 1.0
    while pivots < max_pivots:
        art = pos[Z0] if inb[Z0] else np.int64(-1)  # not a literal: kernels/__init__.py
        leaving = step(T, rhs, magb, basis, nonbasic, pos, inb, start, wlab, wcol, entering,
                       np.True_, free, art, z0_max, pivot_tol, tie_tol, col, prow, cand, keys,
                       scratch, mags)
        if leaving < 0:
            status = RAY_TERMINATION if leaving == -1 else NUMERICAL_FAILURE
            break
        pivots += 1
        h, stop = pivoting.after_pivot(leaving, entering, Z0, h, hkeys, detector)
        if stop >= 0:
            status = stop
            break
        entering = leaving + L if leaving < L else leaving - L  # the complement
    x[:] = 0.0
    y[:] = 0.0
    for r in range(N):
        lab = basis[r]
        if lab < m:
            x[lab] = rhs[r]
        elif lab < L:
            y[lab - m] = rhs[r]
    basis_out[:] = basis
    if not (normalize(x) and normalize(y)):
        out[0] = np.inf
        return (NUMERICAL_FAILURE if status == SOLVED else status), pivots
    ok = check(A, B, x, y, tol, out)
    if ok:
        return SOLVED, pivots
    return (UNCHECKED if status == SOLVED else status), pivots
