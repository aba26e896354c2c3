"""Lemke's method for the box LCP, with bounded variables: n pairs, not 2n.

**The problem.**  Given M, q and bounds lo <= hi (lo may be -inf, hi +inf per entry), find
z with lo <= z <= hi and w = M z + q such that w_i >= 0 where z_i = lo_i, w_i <= 0 where
z_i = hi_i and w_i = 0 in between (z = mid(lo, hi, z - w): the natural map is zero).

**The method.**  Every pair (w_i, z_i) is in one of three states: z_i non-basic at lo_i
(w_i basic and >= 0), z_i non-basic at hi_i (w_i basic and <= 0), or z_i basic within
[lo_i, hi_i] (w_i non-basic at 0).  A fixed variable (lo_i = hi_i) has w_i basic and free of
sign; a free one (lo_i = -inf, hi_i = +inf) is made basic first (exchange pivots, as an
MLCP's free variables, see :func:`exchange`; one that a singular free block leaves
non-basic rests at 0 and enters when its w reaches 0).  The almost-complementary path is Lemke's
with bounded variables: the artificial variable z0 enters with covering entries of the sign
each row needs (+ where w_i must be >= 0, - where it must be <= 0), and then the complement
of the variable that left enters, moving away from the bound it sits at.  What blocks the
entering variable is a basic variable reaching a bound (a z_i at lo_i or hi_i, a w_i at 0,
z0 at 0), or the entering z_e itself reaching its other bound: then no basis changes, z_e
just moves to that bound (a *bound flip*) and w_e enters, on the other side of 0.  This is
Lemke's method on the 2n reformulation (x = z - lo, the slack hi - z and its multiplier)
with the rows of the slacks kept implicit: a basic z_i stands for both x_i and its slack,
a bound flip is the pivot that exchanges the slack with its multiplier, so each pivot works
on an n x (n + 1) tableau instead of a 2n x (2n + 1) one.

**The rule** is that of :mod:`lemke.kernels.pivoting`, on the distances to the bounds: for
each basic variable that moves towards a finite bound, its distance and its rate, the
signed column.  Lexicographic keys are the rows of the basis inverse in those same
coordinates (times the sign of the bound each row moves towards and of the side each
starting row was on); a bound flip has key 0 beyond its ratio (its slack's row of the basis
inverse has no entry in the starting columns).  The cycle detector fingerprints the basis
and the set of non-basic variables at their upper bounds.

**The start.**  Each z starts non-basic at a bound: a cold start puts a variable with two
finite bounds at hi_i when q_i < 0 and at lo_i otherwise (where the diagonal of M would push
it), a one-sided one at its finite bound; a bound beyond FAR = 1e20 counts as far away
(a variable starts at its other bound, or, with both far, as a free one: starting at a bound
of 1e300 would drown the data in M z); a warm start puts them where the previous final
basis had them.

**Equilibration.**  Ruiz's scaling of [M | q + M z_start] (z_start: every z at the bound it
starts on), powers of two; the bounds are scaled with the columns.

**The check.**  :func:`box_check` judges the answer on the caller's data, row by row, as
``certify.lcp_check_sized`` judges an LCP's: with ``r_i = |M_i.| |z| + |q_i|`` and
``t = tol + (n + 2) eps``, w_i may be off its sign by ``t r_i`` (plus the rounding floor of
q) and z_i may be off its bound by what moves no row beyond its allowance.  A kernel run
ends SOLVED only when the point passes it.

The output arrays (caller's units): z, w, the ray (n + 1: dz then dz0), the covering vector
d in the caller's coordinates (the augmented rows read w + d z0), the row and column scales,
which z end basic and which non-basic z sit at their upper bounds.
"""
import numpy as np

from . import inline_kernel, kernel, pivoting, tableau
from .certify import CERTIFIABLE, EPS, zero_size
from .linalg import (borrow, dot, equilibrate, finite_absmax, nan_probe, row_dot_and_size,
                     row_of, solve_principal)
from .pivoting import CYCLING, MAX_PIVOTS, NUMERICAL_FAILURE, RAY_TERMINATION, SOLVED

NOT_FINITE = -1  # M or q has a NaN or an infinity, or lo/hi a NaN: the front says where
BAD_BOUNDS = -3  # some lo_i > hi_i, or lo_i = +inf, or hi_i = -inf
SINGULAR = -4  # a warm start's basis cannot be made basic
BAD_FINDEX = -5  # a friction index the front refuses (see _validate.blcp): the front says where
UNDECIDED = -6  # front: the friction check failed; the front's general path decides
NEED_RUN = -7  # front: a run must decide
PARTIAL = 4  # solve's cov_mode flag: keep what a singular warm basis can make basic, go on
EXCHANGE_TOL = 1e-9  # an exchange pivot below this (equilibrated units) counts as singular


FAR = 1e20  # a bound this large counts as far away when choosing where to start


@kernel
def far_both(lo, hi, i):
    """Whether z_i starts as a free variable (made basic, from 0): both bounds infinite, or
    (a cold start) both at least FAR from 0 on either side of it."""
    return lo[i] <= -FAR and hi[i] >= FAR


@kernel
def start_point(lo, hi, at_hi, q, guess, n):
    """Where each z starts, non-basic: at hi_i when ``at_hi[i]`` (and hi_i finite), else at
    lo_i when finite, else at hi_i when finite, else 0 (a free variable, made basic).  With
    ``guess`` (a cold start): a variable with both bounds FAR away starts at 0, made basic
    as a free one; one with a single bound FAR away starts at the other; one with both
    bounds near starts at hi_i when q_i < 0 (it is pushed up there when M is diagonally
    dominant) and at lo_i otherwise; ``at_hi`` is set accordingly."""
    z = np.empty(n)
    for i in range(n):
        if far_both(lo, hi, i) and (guess or lo[i] == -np.inf and hi[i] == np.inf):
            z[i] = 0.0
            at_hi[i] = False
            continue
        if guess and lo[i] > -np.inf and hi[i] < np.inf:
            if lo[i] <= -FAR:
                at_hi[i] = True
            elif hi[i] >= FAR:
                at_hi[i] = False
            else:
                at_hi[i] = q[i] < 0.0
        if at_hi[i] and hi[i] < np.inf:
            z[i] = hi[i]
        elif lo[i] > -np.inf:
            z[i] = lo[i]
        elif hi[i] < np.inf:
            z[i] = hi[i]
        else:
            z[i] = 0.0
    return z


@kernel
def nonzero(x, n):
    """Whether x[:n] has a non-zero entry (a NaN counts)."""
    for i in range(n):
        if x[i] != 0.0:
            return True
    return False


@kernel
def trivial_start(lo, hi, at_hi, w, n):
    """Whether the start point (no free variable; w = M z_start + q) already solves it:
    every w_i has the sign its z_i's bound needs."""
    for i in range(n):
        if lo[i] == hi[i]:
            continue
        if far_both(lo, hi, i):
            return False
        if (w[i] < 0.0 and not at_hi[i]) or (w[i] > 0.0 and at_hi[i]):
            return False
    return True


@kernel
def bounds_of(lab, n, lo, hi, at_hi):
    """The bounds of variable ``lab`` while basic (scaled units): a z its box; a w, while its
    z is non-basic, [0, inf) at lo, (-inf, 0] at hi, free for a fixed z; z0 [0, inf).
    (Every entry read before the branches that return: so written, numba's pruning removes
    the reference counts of the three arrays, six atomic operations a call, two calls a
    pivot.)"""
    if lab >= 2 * n:
        return 0.0, np.inf
    if lab >= n:
        return lo[lab - n], hi[lab - n]
    lb = lo[lab]
    ub = hi[lab]
    up = at_hi[lab]
    if lb == ub:
        return -np.inf, np.inf
    if up:
        return -np.inf, 0.0
    return 0.0, np.inf


@kernel
def step_values(x, basis, col, n, e, delta):
    """Move the entering variable e by ``delta`` and every basic variable along ``col``."""
    for i in range(n):
        x[basis[i]] += col[i] * delta
    x[e] += delta


@kernel
def exchange(T, x, basis, nonbasic, pos, is_basic, want, n, scratch):
    """Make the z_j with ``want[j]`` basic, in exchange for their w's: Gauss-Jordan on that
    principal block, each pivot the largest diagonal entry left, or (when every diagonal
    entry is below EXCHANGE_TOL) the largest entry of the block.  Returns the number of
    pivots; when the block is singular some wanted z's stay non-basic."""
    col = scratch[3]
    done = 0
    while True:
        best = 0.0
        br = np.int64(-1)  # not literals: see kernels/__init__.py
        bs = np.int64(-1)
        for j in range(n):
            if want[j] and not is_basic[n + j] and is_basic[j]:
                a = abs(T[pos[j], pos[n + j]])
                if a > best:
                    best, br, bs = a, pos[j], pos[n + j]
        if best < EXCHANGE_TOL:
            for i in range(n):  # rows of w_i, i wanted; columns of z_j, j wanted
                if want[i] and is_basic[i]:
                    for j in range(n):
                        if want[j] and not is_basic[n + j]:
                            a = abs(T[pos[i], pos[n + j]])
                            if a > best:
                                best, br, bs = a, pos[i], pos[n + j]
        if br < 0 or best < EXCHANGE_TOL:
            return done  # the caller sees which wanted z's are still non-basic
        for i in range(n):
            col[i] = T[i, bs]
        e = nonbasic[bs]
        leaving = basis[br]
        step_values(x, basis, col, n, e, -x[leaving] / col[br])
        x[leaving] = 0.0
        tableau.pivot_now(T, scratch[0], scratch[1], br, bs, col, scratch[2])
        pivoting.swap_labels(basis, nonbasic, pos, is_basic, br, bs)
        done += 1


@kernel
def ratio_rows(x, basis, pos, is_basic, col, sigma, e, n, lo, hi, rlo, rhi, gaps, cc, low):
    """The rows of the ratio test for the entering variable e (moving in direction ``sigma``,
    its column in ``col``): ``gaps[i]`` the distance of row i's basic variable to the bound
    it moves towards, ``cc[i]`` its (negative) rate, ``low[i]`` whether it stops at its
    lower bound; row n the bound flip of e.  ``rlo``, ``rhi``: the bounds of each row's
    basic variable.  Returns the artificial variable's row (-1 when it is not basic) and the
    largest |cc|.  (The ratio test's first half, calling no kernel: numba then counts no
    references to its arrays; :func:`lemke` takes the blocking rows from
    ``pivoting.blocking_rows`` and its ties from :func:`ratio_ties`.)"""
    art_lab = 2 * n
    art = pos[art_lab] if is_basic[art_lab] else np.int64(-1)  # not a literal: kernels/__init__.py
    for i in range(n):  # written to compile to selects: this loop runs every pivot
        c = sigma * col[i]
        v = x[basis[i]]
        neg = c < 0.0
        bnd = rlo[i] if neg else rhi[i]
        fin = abs(bnd) < np.inf
        a = abs(c)
        # The distance to the bound it moves towards, and the (negative) rate; a row that
        # never blocks keeps a positive entry, which still counts in the pivot tolerance.
        gaps[i] = ((v - bnd) if neg else (bnd - v)) if fin else np.inf
        cc[i] = -a if fin else a
        low[i] = neg or not fin
    if art >= 0:
        gaps[art] = x[art_lab]  # z0's value, for the rule's "z0 zero to rounding"
    gaps[n] = np.inf
    cc[n] = 0.0
    low[n] = False
    if e >= n and e < 2 * n:
        lb = lo[e - n]
        ub = hi[e - n]
        if lb > -np.inf and ub < np.inf:
            gaps[n] = ub - lb
            cc[n] = -1.0
            low[n] = sigma < 0.0
    cmax = 0.0  # (pivoting.min_ratio's, over the n + 1 rates)
    for i in range(n + 1):
        cmax = max(cmax, abs(cc[i]))
    return art, cmax


@kernel
def ratio_ties(T, pos, is_basic, start_basis, s0, n, pivot_tol, tie_tol, cc, low, cand, keys, nc,
               art):
    """The blocking row among the ``nc`` > 1 rows tied at the minimum ratio (``cand``): z0's
    row when it is one of them, else the lexicographic rule on the rows of the starting
    basis's inverse (``pivoting.lex_key``), then the largest pivot; -1 when none is left."""
    for c in range(nc):
        if cand[c] == art:
            return art
    for j in range(n):
        lab = start_basis[j]
        for c in range(nc):
            i = cand[c]
            if i == n:
                b = 0.0
            elif is_basic[lab]:
                b = 1.0 if pos[lab] == i else 0.0
            else:
                b = -T[i, pos[lab]]
            sg = 1.0 if low[i] else -1.0
            keys[c] = pivoting.lex_key(sg * s0[j] * b, cc[i], pivot_tol)
        nc = pivoting.keep_lowest(cand, keys, nc, tie_tol)
        if nc == 1:
            return cand[0]
    return pivoting.largest_pivot(cand, cc, nc) if nc > 0 else -1


@kernel
def lemke(T, x, lo, hi, at_hi, basis, nonbasic, pos, is_basic, s0, max_pivots, pivot_tol,
          tie_tol, ray, scratch, F, I, low):
    """Bounded-variable Lemke from a complementary basis with z0's column in T[:, n] and
    z0 non-basic; everything in scaled units.  Returns ``(status, pivots)``; on a ray,
    ``ray`` (2n + 1, by label) gets the direction of every variable.  Work arrays (from
    :func:`solve_in`'s allocations): ``F`` 5n + 3 floats, ``I`` 5n + 5 int64, ``low`` n + 1
    bools."""
    n = T.shape[0]
    rhs_s, magb_s, prow_s, col = scratch
    art_lab = 2 * n
    # The work arrays borrowed from the caller's (linalg.borrow: no reference counts).
    start_basis, cand = borrow(I, 0, n, np.int64), borrow(I, n, n + 1, np.int64)
    start_basis[:] = basis
    keys, gaps = borrow(F, 0, n + 1, np.float64), borrow(F, n + 1, n + 1, np.float64)
    cc = borrow(F, 2 * n + 2, n + 1, np.float64)
    # the bounds of each row's basic variable
    rlo, rhi = borrow(F, 3 * n + 3, n, np.float64), borrow(F, 4 * n + 3, n, np.float64)
    for i in range(n):
        rlo[i], rhi[i] = bounds_of(basis[i], n, lo, hi, at_hi)
    # the labels' keys and the cycle detector: keys 0..2n the labels, 2n+1+i z_i at hi
    hkeys = borrow(I, 2 * n + 1, 3 * n + 1, np.uint64)
    detector = borrow(I, 5 * n + 2, 3, np.uint64)
    pivoting.fill_label_keys(hkeys)
    h = pivoting.fingerprint(hkeys, basis, n)
    for i in range(n):
        if at_hi[i] and not is_basic[n + i]:
            h ^= hkeys[2 * n + 1 + i]
    detector[:] = 0
    ray[:] = 0.0
    # First pivot: z0 rises until every basic variable is within its bounds.
    s = pos[art_lab]
    for i in range(n):
        col[i] = T[i, s]
    need = gaps  # scratch until the main loop
    sc = cc
    for i in range(n):
        b = basis[i]
        lb, ub = bounds_of(b, n, lo, hi, at_hi)
        if col[i] > 0.0:
            need[i] = x[b] - lb
            sc[i] = col[i]
        elif col[i] < 0.0:
            need[i] = ub - x[b]
            sc[i] = -col[i]
        else:
            need[i] = 0.0
            sc[i] = 0.0
    r = pivoting.first_row(need, sc, n, tie_tol)
    if r < 0:
        return NUMERICAL_FAILURE, 0
    t = -need[r] / sc[r]
    step_values(x, basis, col, n, art_lab, t)
    low_r = col[r] > 0.0
    pivots = 0
    sigma = 1.0
    e = art_lab
    z0_max = 0.0
    status = MAX_PIVOTS
    while pivots < max_pivots:
        if r == n:  # bound flip of the entering z: no basis change
            j = e - n
            at_hi[j] = not at_hi[j]
            x[e] = hi[j] if at_hi[j] else lo[j]
            h ^= hkeys[2 * n + 1 + j]
            pivots += 1
            e = j
            sigma = -1.0 if at_hi[j] else 1.0
        else:
            leaving = basis[r]
            if not abs(col[r]) < np.inf or col[r] == 0.0:
                status = NUMERICAL_FAILURE
                break
            lb, ub = bounds_of(leaving, n, lo, hi, at_hi)
            x[leaving] = lb if low_r else ub
            # (the pivot's two calls made here, not through a kernel of their own: a kernel
            # that hands its arrays on to another kernel counts references to them, nine
            # atomic pairs a pivot)
            tableau.pivot_now(T, rhs_s, magb_s, r, s, col, prow_s)
            pivoting.swap_labels(basis, nonbasic, pos, is_basic, r, s)
            rlo[r], rhi[r] = bounds_of(e, n, lo, hi, at_hi)
            pivots += 1
            h ^= hkeys[leaving] ^ hkeys[e]
            if e >= n and e < 2 * n and at_hi[e - n]:
                h ^= hkeys[2 * n + 1 + e - n]
            if leaving == art_lab:
                x[art_lab] = 0.0
                status = SOLVED
                break
            if leaving >= n:  # a z left at a bound: its w enters, on that bound's side
                j = leaving - n
                at_hi[j] = not low_r
                if at_hi[j]:
                    h ^= hkeys[2 * n + 1 + j]
                e = j
                sigma = 1.0 if low_r else -1.0
            else:  # a w reached 0: its z leaves the bound it sits at
                e = n + leaving
                sigma = -1.0 if at_hi[leaving] else 1.0
        if pivoting.repeats(detector, h):
            status = CYCLING
            break
        s = pos[e]
        for i in range(n):
            col[i] = T[i, s]
        if is_basic[art_lab]:
            z0_max = max(z0_max, x[art_lab])
        # The ratio test, its parts called from here (see ratio_rows)
        art, cmax = ratio_rows(x, basis, pos, is_basic, col, sigma, e, n, lo, hi, rlo, rhi,
                               gaps, cc, low)
        nc = pivoting.blocking_rows(gaps, gaps, cc, n + 1, -pivot_tol * cmax, tie_tol, cand, art,
                                    z0_max)
        if nc <= 1:
            r = cand[0] if nc == 1 else np.int64(-1)
        else:
            r = ratio_ties(T, pos, is_basic, start_basis, s0, n, pivot_tol, tie_tol, cc, low,
                           cand, keys, nc, art)
        if r < 0:
            status = RAY_TERMINATION
            for i in range(n):
                ray[basis[i]] = sigma * col[i]
            ray[e] = sigma
            break
        low_r = low[r]
        # The step: the blocking row's distance over its rate (0 for a distance that is
        # negative by rounding, or for z0 leaving as zero to rounding on a rising entry).
        g = gaps[r]
        step = g / -cc[r] if cc[r] < 0.0 and g > 0.0 and g < np.inf else 0.0
        step_values(x, basis, col, n, e, sigma * step)
    return status, pivots


@kernel
def box_check(M, q, lo, hi, z, tol, w, R, n_round=0):
    """Fill ``w = M z + q`` and judge z on the caller's data, row by row: returns
    ``(ok, residual)`` with residual ``max_i |z_i - mid(lo_i, hi_i, z_i - w_i)|``.

    With ``r_i = |M_i.| |z| + |q_i|``, ``t = tol + (n + 2) eps`` and the rounding floor f_i
    of q's largest row (as in ``certify.lcp_check_sized``), row i passes when z_i is in
    [lo_i, hi_i] and: w_i >= -(t r_i + f_i) unless z_i is at hi_i, w_i <= t r_i + f_i unless
    z_i is at lo_i, where "at a bound" means within the distance that moves no w_j beyond
    its allowance (``certify.zero_size``).  ``n_round`` (default n) is the size of the
    problem whose rounding is allowed for, in t and the floor: a friction-index answer comes
    from a larger problem than the caller's.  A fixed variable (lo_i = hi_i) passes with any
    w_i.  A point whose terms dwarf the data (the rounding of M z beyond CERTIFIABLE times
    the tolerance, in the row-equilibrated units) is refused, as in the LCP check; the data
    here are q + M p with p the point of the box nearest 0."""
    n = q.shape[0]
    nr = max(n, n_round)
    t = tol + (nr + 2) * EPS
    work = np.empty(3 * n)  # one allocation (it costs about as much as the check at small n)
    rows, floors, p = work[:n], work[n : 2 * n], work[2 * n :]
    p_zero = True  # the box holds 0 (the common case): no pass over M for the data
    for i in range(n):
        p[i] = min(max(0.0, lo[i]), hi[i])
        p_zero = p_zero and p[i] == 0.0
    q_top = 0.0
    for i in range(n):
        q_top = max(q_top, R[i] * abs(q[i]))
    big = 0.0
    data = 1.0
    z_zero = not nonzero(z, n)
    for i in range(n):
        mz, size = (0.0, 0.0) if z_zero else row_dot_and_size(M, i, z, n)
        w[i] = q[i] + mz
        rows[i] = size + abs(q[i])
        floors[i] = (nr + 2) * EPS * q_top / R[i]
        big = max(big, R[i] * size)
        psize = 0.0 if p_zero else row_dot_and_size(M, i, p, n)[1]
        data = max(data, R[i] * (abs(q[i]) + psize))
    ok = EPS * big <= CERTIFIABLE * t * data
    residual = 0.0
    for i in range(n):
        zi = z[i]
        wi = w[i]
        if not (zi == zi and wi == wi):
            ok = False
            residual = np.nan
            continue
        residual = max(residual, abs(zi - min(max(zi - wi, lo[i]), hi[i])))
        if lo[i] == hi[i]:
            if zi != lo[i]:
                ok = False
            continue
        s_w = t * rows[i] + floors[i]
        # How far z_i may be from a bound and still count as at it: only computed (O(n))
        # for a row that needs it.
        off = max(lo[i] - zi, zi - hi[i])
        if wi > s_w:
            off = max(off, zi - lo[i])
        if wi < -s_w:
            off = max(off, hi[i] - zi)
        if off > 0.0 and off > zero_size(M, rows, i, t, floors):
            ok = False
    return ok, residual


@kernel
def prologue(M, q, lo, hi):
    """0, NOT_FINITE (M or q not finite, or a NaN in lo or hi) or BAD_BOUNDS."""
    n = q.shape[0]
    finite, m_max = finite_absmax(M)
    if not (finite and nan_probe(q, n) == 0.0):
        return NOT_FINITE
    for i in range(n):
        if not (lo[i] <= hi[i]):
            return NOT_FINITE if (lo[i] != lo[i] or hi[i] != hi[i]) else BAD_BOUNDS
        if lo[i] == np.inf or hi[i] == -np.inf:
            return BAD_BOUNDS
    return 0


@kernel
def layout(n, buf):
    """The views ``(z, w, d, R, C, ray)`` of the output buffer (length 6n + 1), borrowed
    (``linalg.borrow``: valid while ``buf``, an argument of the caller, is)."""
    return (borrow(buf, 0, n, np.float64), borrow(buf, n, n, np.float64),
            borrow(buf, 2 * n, n, np.float64), borrow(buf, 3 * n, n, np.float64),
            borrow(buf, 4 * n, n, np.float64), borrow(buf, 5 * n, n + 1, np.float64))


@kernel
def solve(M, q, lo, hi, warm, cov_mode, max_pivots, pivot_tol, tie_tol, tol, buf, final):
    """One run, checked: validate the data, equilibrate, exchange pivots (the free z's and
    the warm basis ``warm[:n]``, with non-basic z's at hi where ``warm[n:]``), Lemke with
    covering vector ``cov_mode`` (0: ones in the caller's coordinates, 1: ones in the
    equilibrated ones, 2: fixed pseudo-random factors in [1, 2) there; with the flag
    ``PARTIAL`` added, a warm basis that the exchange pivots cannot make basic whole is kept
    in part instead of SINGULAR), and the check of the point on (M, q, lo, hi).

    Returns ``(code, pivots, z0, ok, residual, k, m)``.  code: a pivoting status, or
    NOT_FINITE, BAD_BOUNDS (nothing else done) or SINGULAR (the start point); the outputs (views of ``buf``, see
    :func:`layout`) are described in the module docstring; ``final[:k]`` lists the basic
    z's and ``final[k:m]`` the non-basic z's at their upper bounds.  A run that stops other than SOLVED at a point that passes the check is
    SOLVED (the check decides, as in ``kernels.cold``)."""
    n = q.shape[0]
    if warm.shape[0] < 2 * n or buf.shape[0] < 6 * n + 1 or final.shape[0] < n:
        return NOT_FINITE, 0, 0.0, False, np.inf, 0, 0  # (the front's arrays: never here)
    # Three allocations for the whole solve (each one costs about as much as a small pivot):
    # the flags, floats and indices of the run, each carved into its arrays by solve_in.
    return solve_in(M, q, lo, hi, warm, cov_mode, max_pivots, pivot_tol, tie_tol, tol, buf,
                    final, np.zeros(6 * n + 2, dtype=np.bool_),
                    np.empty(n * (n + 1) + 17 * n + 6), np.empty(9 * n + 7, dtype=np.int64))


@kernel
def solve_in(M, q, lo, hi, warm, cov_mode, max_pivots, pivot_tol, tie_tol, tol, buf, final,
             flags, F, I):
    """:func:`solve` with its work arrays given: ``flags`` (6n + 2 bools, all False), ``F``
    (n (n + 1) + 17n + 6 floats) and ``I`` (9n + 7 int64), the last n + 1, 5n + 3 and 5n +
    5 of them :func:`lemke`'s.  Every array of the run is
    borrowed from them and from ``buf`` and ``warm`` (``linalg.borrow``: numba counts no
    references to them; as views they took 124 atomic pairs a call, about 1 us at n =
    12)."""
    n = q.shape[0]
    z, w, d, R, C, ray = layout(n, buf)
    z_basic, z_hi = borrow(flags, 0, n, np.bool_), borrow(flags, n, n, np.bool_)
    is_basic, want = borrow(flags, 2 * n, 2 * n + 1, np.bool_), borrow(flags, 4 * n + 1, n, np.bool_)
    T = borrow(F, 0, (n, n + 1), np.float64)  # the tableau [R M C | cov]
    o = n * (n + 1)
    qs, los = borrow(F, o, n, np.float64), borrow(F, o + n, n, np.float64)
    his, s0 = borrow(F, o + 2 * n, n, np.float64), borrow(F, o + 3 * n, n, np.float64)
    x, ray_lab = borrow(F, o + 4 * n, 2 * n + 1, np.float64), borrow(F, o + 6 * n + 1, 2 * n + 1, np.float64)
    o += 8 * n + 2
    rhs_s, magb_s = borrow(F, o, n, np.float64), borrow(F, o + n, n, np.float64)  # the pivots' scratch
    prow_s, col_s = borrow(F, o + 2 * n, n + 1, np.float64), borrow(F, o + 3 * n + 1, n, np.float64)
    basis, nonbasic = borrow(I, 0, n, np.int64), borrow(I, n, n + 1, np.int64)
    pos = borrow(I, 2 * n + 1, 2 * n + 1, np.int64)
    warm_basic, warm_hi = borrow(warm, 0, n, np.bool_), borrow(warm, n, n, np.bool_)
    code = prologue(M, q, lo, hi)
    if code < 0:
        return code, 0, 0.0, False, np.inf, 0, 0
    z_hi[:] = warm_hi
    cold = np.True_  # not a literal: see kernels/__init__.py
    for i in range(n):
        cold = cold and not (warm_hi[i] or warm_basic[i])
    z0s = start_point(lo, hi, z_hi, q, cold, n)
    for i in range(n):
        z_hi[i] = ((z_hi[i] and hi[i] < np.inf or (lo[i] == -np.inf and hi[i] < np.inf))
                   and not (cold and far_both(lo, hi, i)))
    qs[:] = q
    if nonzero(z0s, n):
        for i in range(n):
            qs[i] = q[i] + row_dot_and_size(M, i, z0s, n)[0]
    if cold and trivial_start(lo, hi, z_hi, qs, n):
        for i in range(n):  # every w has its sign already: the start solves it
            z[i] = z0s[i]
            d[i] = 0.0
            z_basic[i] = False
        ray[:] = 0.0
        equilibrate(M, qs, R, C)
        ok, residual = box_check(M, q, lo, hi, z, tol, w, R)
        k = 0
        for i in range(n):
            if z_hi[i]:
                final[k] = i
                k += 1
        return SOLVED if ok else NUMERICAL_FAILURE, 0, 0.0, ok, residual, 0, k
    equilibrate(M, qs, R, C)
    # The tableau [R M C | cov] and the values (scaled): w = R (M z + q), z' = z / C.
    x[:] = 0.0
    for i in range(n):
        r = R[i]
        for j in range(n):
            T[i, j] = (M[i, j] * r) * C[j]
        T[i, n] = 0.0
        x[i] = qs[i] * r
        x[n + i] = z0s[i] / C[i]
        los[i] = lo[i] / C[i]
        his[i] = hi[i] / C[i]
    for i in range(n):
        basis[i] = i
        nonbasic[i] = n + i
        pos[i] = i
        pos[n + i] = i
        is_basic[i] = True
    nonbasic[n] = 2 * n
    pos[2 * n] = n
    rhs_s[:] = 0.0
    magb_s[:] = 0.0
    scratch = (rhs_s, magb_s, prow_s, col_s)
    want[:] = warm_basic
    for i in range(n):
        if far_both(lo, hi, i) and (cold or lo[i] == -np.inf and hi[i] == np.inf):
            want[i] = True
        elif lo[i] == hi[i]:
            want[i] = False
    pivots = exchange(T, x, basis, nonbasic, pos, is_basic, want, n, scratch)
    singular = False
    partial = (cov_mode & PARTIAL) != 0
    mode = cov_mode & 3
    for i in range(n):
        if want[i] and not is_basic[n + i]:
            if far_both(lo, hi, i) and (cold or lo[i] == -np.inf and hi[i] == np.inf):
                # A free z that the singular free block leaves non-basic: it rests at 0
                # as if at a lower bound there (its w held to >= 0, covered by z0), and
                # enters when that w reaches 0, free from then on; the check decides.
                # (Taking the side of w's current sign instead solved fewer of a fuzz
                # family: 2605 against 2616 of 3000.)
                z_hi[i] = False
            elif not partial:
                singular = True
            # (PARTIAL: it stays non-basic at the bound of its start, and Lemke goes on)
    if singular:
        # The warm basis cannot be made basic: report the start point (it may still pass
        # the check), nothing else; the front then solves cold.
        ray[:] = 0.0
        d[:] = 0.0
        for i in range(n):
            z[i] = z0s[i]
        ok, residual = box_check(M, q, lo, hi, z, tol, w, R)
        return SOLVED if ok else SINGULAR, 0, 0.0, ok, residual, 0, 0
    # The covering column, set in the current basis: each row needs z0 on the side its
    # variable must stay (w >= 0 at lo: +; w <= 0 at hi: -; a basic z outside its box: back
    # towards it; a basic z inside, a fixed variable's w: 0).
    keys = pivoting.label_keys(n if mode == 2 else 0)
    rmax = 0.0
    for i in range(n):
        rmax = max(rmax, R[i])
    s0[:] = 1.0
    infeasible = False
    for i in range(n):
        b = basis[i]
        lb, ub = bounds_of(b, n, los, his, z_hi)
        v = x[b]
        if b < n:
            mag = R[b] / rmax if mode == 0 else 1.0
        else:
            mag = 1.0
        if mode == 2:
            mag *= 1.0 + pivoting.unit_random(keys, i)
        sgn = 0.0
        if v < lb:
            sgn = 1.0
        elif v > ub:
            sgn = -1.0
        elif b < n and lb == 0.0:
            sgn = 1.0
        elif b < n and ub == 0.0:
            sgn = -1.0
        if v < lb or v > ub:
            infeasible = True
        T[i, n] = sgn * mag
        s0[i] = -1.0 if sgn < 0.0 else 1.0
    for i in range(n):  # the covering vector in the caller's rows (see the front)
        d[i] = 0.0
    for i in range(n):
        if basis[i] < n:
            d[basis[i]] = T[i, n] / R[basis[i]]
    code = SOLVED
    z0 = 0.0
    ray_lab[:] = 0.0
    if infeasible:
        code, p = lemke(T, x, los, his, z_hi, basis, nonbasic, pos, is_basic, s0,
                        max_pivots - pivots, pivot_tol, tie_tol, ray_lab, scratch,
                        borrow(F, n * (n + 1) + 12 * n + 3, 5 * n + 3, np.float64),
                        borrow(I, 4 * n + 2, 5 * n + 5, np.int64),
                        borrow(flags, 5 * n + 1, n + 1, np.bool_))
        pivots += p
        z0 = x[2 * n]
    # Back to the caller's units.
    for i in range(n):
        z[i] = min(max(x[n + i] * C[i], lo[i]), hi[i])
        ray[i] = ray_lab[n + i] * C[i]
        z_basic[i] = is_basic[n + i]
    ray[n] = ray_lab[2 * n]
    for i in range(n):
        if z_basic[i]:
            z_hi[i] = False
    if code != SOLVED:
        for i in range(n):  # where it stopped, unclamped
            z[i] = x[n + i] * C[i]
    ok, residual = box_check(M, q, lo, hi, z, tol, w, R)
    if ok:
        code = SOLVED
    k = 0  # the final basis: the basic z's, then the non-basic z's at hi
    for i in range(n):
        if z_basic[i]:
            final[k] = i
            k += 1
    m = k
    for i in range(n):
        if z_hi[i]:
            final[m] = i
            m += 1
    return code, pivots, z0, ok, residual, k, m


# --------------------------------------------------------------------------- one call


@kernel
def is_ray(M, q, lo, hi, d, z, z0, ray, tol):
    """Whether ``(z, z0) + t ray`` (t >= 0) stays a solution of the augmented box problem
    (w + d z0 in place of w) for every t: judged row by row, each against its own size, as
    the check of a point.  Rows of a moving z_i must have u_i = du_i = 0 and an infinite
    bound on the side it moves to; a resting z_i at its lower bound needs u_i, du_i >= 0, at
    its upper bound <= 0, in between = 0.  (``_blcp.is_box_ray`` is its front.)"""
    n = q.shape[0]
    if ray.shape[0] != n + 1 or d.shape[0] != n or z.shape[0] != n:
        return False
    if not (nan_probe(ray, n + 1) == 0.0 and abs(z0) < np.inf and z0 >= 0.0):
        return False
    g = (n + 3) * EPS
    t = tol + g
    dz = np.empty(n)
    top = 0.0
    for i in range(n):
        top = max(top, abs(ray[i]))
    for i in range(n):
        dz[i] = ray[i] if abs(ray[i]) > g * top else 0.0
    dz0 = ray[n] if abs(ray[n]) > g * max(top, 1.0) else 0.0
    if dz0 < 0.0 or (top == 0.0 and dz0 == 0.0):
        return False
    q_top = 0.0
    for i in range(n):
        q_top = max(q_top, abs(q[i]))
    m_top = finite_absmax(M)[1]
    for i in range(n):
        mz, size = row_dot_and_size(M, i, z, n)
        mdz, dsize = row_dot_and_size(M, i, dz, n)
        u = (mz + q[i]) + d[i] * z0
        du = mdz + d[i] * dz0
        su = t * ((size + abs(q[i])) + abs(d[i] * z0)) + g * q_top
        sdu = t * (dsize + abs(d[i] * dz0)) + g * top * m_top
        if lo[i] == hi[i]:
            if dz[i] != 0.0:
                return False
            continue
        at_lo = lo[i] > -np.inf and abs(z[i] - lo[i]) <= t * max(abs(lo[i]), 1.0) * 10
        at_hi = hi[i] < np.inf and abs(z[i] - hi[i]) <= t * max(abs(hi[i]), 1.0) * 10
        if dz[i] != 0.0:
            if (dz[i] > 0.0 and hi[i] < np.inf) or (dz[i] < 0.0 and lo[i] > -np.inf):
                return False
            if abs(u) > su or abs(du) > sdu:
                return False
        elif at_lo:
            if u < -su or du < -sdu:
                return False
        elif at_hi:
            if u > su or du > sdu:
                return False
        elif abs(u) > su or abs(du) > sdu:
            return False
    return True




@kernel
def basis_point(M, q, lo, hi, zb, zh, warm_rule, z):
    """Write into z the point of a basis: the z_i with ``zb[i]`` basic, from one solve with
    the principal block ``M[b, b] z_b = -(q_b + M[b, nb] z_nb)`` (``linalg.solve_principal``:
    single-threaded LU, no LAPACK), the others at a bound.  With ``warm_rule`` (a warm
    start's point): a non-basic z_i at hi_i where ``zh[i]`` and hi_i is finite, else at its
    finite bound (lo_i first), a free z_i (both bounds infinite) basic.  Without (a final
    basis's point recomputed): at hi_i where ``zh[i]``, else lo_i, 0 for an infinite bound,
    and the point clamped into the box afterwards.  Returns False (z garbage) when the
    block is singular or the point not finite."""
    n = q.shape[0]
    idx = np.empty(n, dtype=np.int64)
    rhs = np.empty(n)
    nb = 0
    for i in range(n):
        free = warm_rule and lo[i] == -np.inf and hi[i] == np.inf
        if warm_rule:
            if zh[i] and hi[i] < np.inf:
                v = hi[i]
            elif lo[i] > -np.inf:
                v = lo[i]
            elif hi[i] < np.inf:
                v = hi[i]
            else:
                v = 0.0
        else:
            v = hi[i] if zh[i] else lo[i]
            if not abs(v) < np.inf:
                v = 0.0
        if zb[i] or free:
            idx[nb] = i
            nb += 1
            v = 0.0  # no part in the right-hand side
        z[i] = v
    if nb > 0:
        for c in range(nb):
            r = idx[c]
            rhs[c] = -(q[r] + dot(row_of(M, r), z, n))
        ok, x = solve_principal(M, idx[:nb], rhs[:nb])
        if not ok:
            return False
        for c in range(nb):
            z[idx[c]] = x[c]
    if nan_probe(z, n) != 0.0:
        return False
    if not warm_rule:
        for i in range(n):
            z[i] = min(max(z[i], lo[i]), hi[i])
    return True


@kernel
def check_scales(M, q, lo, hi, R, C):
    """The scales :func:`box_check` judges a point with, when no run made them: those of
    ``equilibrate(M, q + M p)``, p the point of the box nearest 0 (as a cold run's start)."""
    n = q.shape[0]
    qs = np.empty(2 * n)
    p, qs = qs[n:], qs[:n]
    p_zero = True
    for i in range(n):
        p[i] = min(max(0.0, lo[i]), hi[i])
        p_zero = p_zero and p[i] == 0.0
    for i in range(n):
        qs[i] = q[i] if p_zero else q[i] + dot(row_of(M, i), p, n)
    equilibrate(M, qs, R, C)


@inline_kernel
def friction_rows(findex, n):
    """``nf`` (the number of friction rows), or BAD_FINDEX where ``_validate.blcp`` would
    refuse the index itself: an entry other than -1 outside [0, n), pointing at its own row
    or at another friction row."""
    nf = 0
    for i in range(n):
        f = findex[i]
        if f == -1:
            continue
        if f < 0 or f >= n or f == i or findex[f] != -1:
            return BAD_FINDEX
        nf += 1
    return nf


@kernel
def extend(M, q, lo, hi, findex, nf, work, F):
    """The box LCP that solves the friction index exactly (``_blcp``'s module docstring),
    built into ``work`` (length N N + 3 N, N = n + 2 nf): returns its views ``(Mx, qx, lox,
    hix)``; ``F`` (length 2 nf) gets the friction rows, then their normal rows.  Variables:
    the caller's z with beta+ in place of each friction z_i, then beta- and lambda per
    friction row."""
    n = q.shape[0]
    N = n + 2 * nf
    Mx = work[: N * N].reshape((N, N))
    qx, lox, hix = work[N * N : N * N + N], work[N * N + N : N * N + 2 * N], work[N * N + 2 * N :]
    c = 0
    for i in range(n):
        if findex[i] >= 0:
            F[c] = i
            F[nf + c] = findex[i]
            c += 1
    for r in range(N):
        for j in range(N):
            Mx[r, j] = 0.0
    for i in range(n):
        row = M[i]
        for j in range(n):
            Mx[i, j] = row[j]
        for c in range(nf):
            Mx[i, n + c] = -row[F[c]]
        qx[i] = q[i]
        lox[i] = lo[i]
        hix[i] = hi[i]
    for c in range(nf):
        i = F[c]
        lam = n + nf + c
        row = M[i]
        for j in range(n):
            Mx[n + c, j] = -row[j]
        for d in range(nf):
            Mx[n + c, n + d] = row[F[d]]
        Mx[i, lam] = 1.0
        Mx[n + c, lam] = 1.0
        Mx[lam, F[nf + c]] = hi[i]
        Mx[lam, i] = -1.0
        Mx[lam, n + c] = -1.0
        qx[n + c] = -q[i]
        qx[lam] = 0.0
        lox[n + c] = 0.0
        lox[lam] = 0.0
        hix[n + c] = np.inf
        hix[lam] = np.inf
        lox[i] = 0.0
        hix[i] = np.inf
    return Mx, qx, lox, hix


@inline_kernel
def friction_check(M, q, lo, hi, F, nf, zx, N, tol, out):
    """The friction index's answer from the extended one zx, judged on the caller's data:
    z_i = beta+_i - beta-_i on the friction rows, the coupled bounds -mu_i z_f, mu_i z_f at
    that z, z clamped into them and checked by :func:`box_check` (rounding allowed for at
    the extended size N), with the scales of :func:`check_scales`.  ``out`` (6n): z, w,
    lo and hi in force, R, C.  Returns ``(ok, residual)``."""
    n = q.shape[0]
    z, w, lo_in, hi_in = out[:n], out[n : 2 * n], out[2 * n : 3 * n], out[3 * n : 4 * n]
    R, C = out[4 * n : 5 * n], out[5 * n :]
    for i in range(n):
        z[i] = zx[i]
        lo_in[i] = lo[i]
        hi_in[i] = hi[i]
    for c in range(nf):
        z[F[c]] = zx[F[c]] - zx[n + c]
    for c in range(nf):
        i = F[c]
        mu = hi[i]
        lo_in[i] = -mu * z[F[nf + c]]
        hi_in[i] = mu * z[F[nf + c]]
    check_scales(M, q, lo, hi, R, C)
    for i in range(n):
        z[i] = min(max(z[i], min(lo_in[i], hi_in[i])), hi_in[i])
    return box_check(M, q, lo_in, hi_in, z, tol, w, R, N)


PREPARE = 0  # front's phases: validate, build, a warm start's own point
SOLVED_RUN = 1  # after a run that ended solved and checked


@kernel
def front(phase, M, q, lo, hi, findex, warm, has_warm, tol, buf, ints, work):
    """The kernel part of ``solve_blcp`` with a friction index and/or a warm start
    (``_blcp._one_call`` runs :func:`solve` between its phases).  ``findex`` of length n,
    or 0 for none; N = n + 2 nf the size of the problem solved (with a friction index, the
    extended one, :func:`extend`).  ``buf``: that problem's output (6 N + 1,
    :func:`layout`), then with a friction index (even one without friction rows) the
    caller's (6 n: z, w, lo and hi in force, R, C); ``ints``: the final basis (N, as
    :func:`solve` gives it), then the friction rows and their normal rows (2 nf);
    ``work`` (N N + 3 N with friction rows): the extended problem; ``warm`` (2 N): the
    warm start's basic z's, then its non-basic z's at hi.

    ``PREPARE``: validate the data (:func:`prologue`, :func:`friction_rows`, and the
    friction rows' bounds as ``_validate.blcp``: mu = hi_i finite and >= 0, lo_i = -mu,
    lo_f >= 0), build the extended problem; with a warm start, its basis's point
    (:func:`basis_point`, as ``_blcp._warm``) judged by :func:`box_check`.
    ``SOLVED_RUN``: the answer in ``buf``, solved and checked.  Then with a friction index,
    the answer mapped back and judged on the caller's data (:func:`friction_check`).

    Returns ``(code, residual)``: SOLVED (the answer and its residual in ``buf``),
    NEED_RUN (PREPARE without a warm start or with one whose point fails: a run must
    decide), UNDECIDED (the friction check failed: the front's general path decides), or
    NOT_FINITE, BAD_BOUNDS, BAD_FINDEX (the front says where)."""
    n = q.shape[0]
    friction = findex.shape[0] > 0
    nf = 0
    if phase == PREPARE:
        code = prologue(M, q, lo, hi)
        if code < 0:
            return code, np.inf
        nf = friction_rows(findex, findex.shape[0])
        if nf < 0:
            return BAD_FINDEX, np.inf
        for i in range(findex.shape[0]):
            f = findex[i]
            if f >= 0 and not (hi[i] >= 0.0 and hi[i] < np.inf and lo[i] == -hi[i] and lo[f] >= 0.0):
                return BAD_FINDEX, np.inf
    else:
        for i in range(findex.shape[0]):
            nf += findex[i] >= 0
    N = n + 2 * nf
    if (buf.shape[0] != 6 * N + 1 + (6 * n if friction else 0) or ints.shape[0] != N + 2 * nf
            or work.shape[0] != (N * N + 3 * N if nf > 0 else 0) or warm.shape[0] != 2 * N):
        return BAD_FINDEX, np.inf  # (the front sizes them: never)
    F = ints[N:]
    z = buf[:N]
    residual = np.inf
    if phase == PREPARE:
        A, qa, la, ha = M, q, lo, hi
        if nf > 0:
            A, qa, la, ha = extend(M, q, lo, hi, findex, nf, work, F)
        if not has_warm or not basis_point(A, qa, la, ha, warm[:N], warm[N:], np.True_, z):
            return NEED_RUN, np.inf
        _, w, d, R, C, _ = layout(N, buf[: 6 * N + 1])
        check_scales(A, qa, la, ha, R, C)
        ok, residual = box_check(A, qa, la, ha, z, tol, w, R)
        if not ok:
            return NEED_RUN, np.inf
        for i in range(N):
            d[i] = 0.0
    if friction:
        ok, residual = friction_check(M, q, lo, hi, F, nf, z, N, tol, buf[6 * N + 1 :])
        if not ok:
            return UNDECIDED, np.inf
    return SOLVED, residual
