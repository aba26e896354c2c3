"""Lemke's method without a tableau: the "unrevised" method of Dai & Drumwright.

Only the index sets are kept.  With A = [M | d] (d: the artificial variable z0's column),
let alpha be the indices of the non-basic w's and beta those of the basic z's (z0 is index
n).  They have the same size k, and the basic point solves the k x k system

    H z_beta = -q_alpha,        H = A[alpha, beta],

with every basic w_i = q_i + A[i, beta] z_beta.  The change of the basic variables per unit
of a driving variable comes from the same block, so each pivot needs only products with
G = H^-1 and with AB = A[:, beta] (kept as a contiguous copy, one column changed a pivot).
G is updated from pivot to pivot in O(k^2), one of four cases: the block gains a row and a
column, loses them, or has one row or one column replaced.  The basic values move along the
driving column by the entering variable's new value (:func:`advance`, :func:`place`: the
tableau's update of its right-hand side, O(n) a pivot); every ``CHECK_EVERY`` pivots they
are checked against the block row by row (:func:`drift`, relative to each row's terms,
RESIDUAL_TOL).  G is refactored (``linalg.invert_in_place``, on the calling thread) and the
values recomputed from it (:func:`basic_point`) when they drifted, when an update's pivot
is tiny, and every ``REFACTOR_EVERY`` pivots; the final point is recomputed from G.
Recomputing the point at every pivot (as this kernel first did) cost O(n k) a pivot, a
third of the method's time at n = 100 to 300.

**M in factored form.**  With ``Fs`` not empty (n x r), M is ``Fs Fs'`` and is never
formed: A is the covering column d alone (n x 1), a column of M is computed when a z enters
(``Fs Fs[e]'``, n r multiply-adds, :func:`fetch_column`), and the block H, of rank at most
r + 1, is kept in arrays of at most r + 1 columns.  A pivot then costs O(n (r + k)), not
O(n^2): ``kernels.qp`` solves the multiplier LCP of a QP with many more inequalities than
variables this way.

Labels are those of the tableau kernel: 0..n-1 for w, n..2n-1 for z, 2n for z0.  The rule is
:mod:`lemke.kernels.pivoting`'s, applied to the basic variables in pair order (pair j's basic
variable, z0 last), with the basis inverse taken relative to the starting basis (whose row j
holds the basic variable of pair j).
"""
import numpy as np

from . import inline_kernel, kernel, pivoting
from .linalg import (borrow, dot, invert_in_place, matvec, no_matrix, row_dot_and_size, row_of,
                     scaled_system)
from .pivoting import MAX_PIVOTS, NUMERICAL_FAILURE, RAY_TERMINATION, SOLVED
from .tableau import unscale

REFACTOR_EVERY = 200
RESIDUAL_TOL = 1e-12
CHECK_EVERY = 8  # pivots between two checks of the values against the basis (drift)


@kernel
def invert(AB, alist, k, G):
    """G[:k, :k] = inverse of H = AB[alist[:k], :k], by ``linalg.invert_in_place`` (one
    thread, no LAPACK).  False when H is singular or the inverse is not finite."""
    for r in range(k):
        src = AB[alist[r]]
        for c in range(k):  # a loop, not a slice assignment: see copy_column
            G[r, c] = src[c]
    return invert_in_place(G, k)


@inline_kernel
def set_column(dst, j, col):
    """dst[:, j] = col, as a loop (see :func:`copy_column`)."""
    for r in range(dst.shape[0]):
        dst[r, j] = col[r]


@inline_kernel
def copy_column(dst, j, src, i):
    """dst[:, j] = src[:, i], as a loop: each slice assignment between arrays makes numba
    compile an implementation of its own, with the formatting of its error messages (about
    a second each)."""
    for r in range(dst.shape[0]):
        dst[r, j] = src[r, i]


@kernel
def _all_w(AB, q, apos, zb, k, wv):
    """wv = q + AB[:, :k] z_beta; returns the residual of H z_beta + q_alpha (zero in exact
    arithmetic), row by row relative to the size of the row's terms: max over i in alpha of
    |w_i| / (|q_i| + |AB[i]| |z_beta|)."""
    res = 0.0
    for i in range(q.shape[0]):
        mz, size = row_dot_and_size(AB, i, zb, k)
        w = q[i] + mz
        wv[i] = w
        if apos[i] >= 0:
            size += abs(q[i])
            if abs(w) > res * size:
                res = abs(w) / size
    return res


@kernel
def basic_point(AB, q, alist, k, G, apos, zb, wv, tmp, tmp2):
    """z_beta = -G q_alpha and every w_i = q_i + AB[i] z_beta (the values of the basic w's).
    Refines z_beta once when the row-wise residual of H z_beta + q_alpha (see ``_all_w``)
    is above RESIDUAL_TOL, and returns that residual.  ``zmag`` and ``wmag`` receive the
    sizes of the terms that formed each value (|G| |q_alpha| and |q| + |AB| |z_beta|)."""
    for r in range(k):
        tmp[r] = -q[alist[r]]
    for r in range(k):
        zb[r] = dot(row_of(G, r), tmp, k)
    res = _all_w(AB, q, apos, zb, k, wv)
    if res > RESIDUAL_TOL:
        for r in range(k):
            tmp[r] = wv[alist[r]]
        matvec(G, k, tmp, tmp2)
        for c in range(k):
            zb[c] -= tmp2[c]
        res = _all_w(AB, q, apos, zb, k, wv)
    return res


@inline_kernel
def advance(t, k, n, apos, zb, dzb, wv, dw):
    """Move every basic value by t times its change per unit of the entering variable
    (the tableau's update of its right-hand side): zb += t dzb, and wv += t dw at the basic
    w's."""
    for p in range(k):
        zb[p] += t * dzb[p]
    for i in range(n):
        if apos[i] < 0:
            wv[i] += t * dw[i]


@inline_kernel
def place(t, entering, n, bpos, zb, wv):
    """The entering variable's value t, at its place after :func:`update_basis`."""
    if entering >= n:
        zb[bpos[entering - n]] = t
    else:
        wv[entering] = t


@kernel
def drift(AB, q, apos, zb, k, wv):
    """How far the values (updated in place) are from those of the basis, row by row
    relative to the size of the row's terms: max over i of |q_i + AB[i] z_beta - w_i| /
    (|q_i| + |AB[i]| |z_beta|), with w_i = 0 for the non-basic w's (i in alpha)."""
    res = 0.0
    for i in range(q.shape[0]):
        mz, size = row_dot_and_size(AB, i, zb, k)
        size += abs(q[i])
        w = q[i] + mz - (wv[i] if apos[i] < 0 else 0.0)
        if abs(w) > res * size:
            res = abs(w) / size
    return res


@kernel
def direction(acol, AB, label, n, alist, k, G, apos, dzb, dw, tmp):
    """The change of every basic variable per unit increase of the non-basic ``label``:
    dzb (k, the basic z's in beta order) and dw (n, read at the basic w's).  For a z label
    (or z0), ``acol`` is its column of A (:func:`fetch_column`)."""
    if label < n:  # a w leaves zero: H dz_beta = e_p
        p = apos[label]
        for r in range(k):
            dzb[r] = G[r, p]
        for i in range(n):
            if apos[i] < 0:
                dw[i] = dot(row_of(AB, i), dzb, k)
    else:  # a z (or z0) enters: H dz_beta = -A[alpha, e]
        for r in range(k):
            tmp[r] = -acol[alist[r]]
        matvec(G, k, tmp, dzb)
        for i in range(n):
            if apos[i] < 0:
                dw[i] = acol[i] + dot(row_of(AB, i), dzb, k)


@kernel
def fetch_column(A, Fs, e, acol):
    """acol = column e of [M | d]: read from A = [M | d] when Fs is empty; else M = Fs Fs'
    and A is d alone (n x 1), so column e < n is ``Fs Fs[e]'`` (computed, n r multiply-adds)
    and column n is d."""
    n = acol.shape[0]
    if Fs.shape[0] == 0:
        for i in range(n):
            acol[i] = A[i, e]
    elif e == n:
        for i in range(n):
            acol[i] = A[i, 0]
    else:
        r = Fs.shape[1]
        Fe = row_of(Fs, e)  # (borrowed rows: no view and its reference count per row)
        for i in range(n):
            acol[i] = dot(row_of(Fs, i), Fe, r)


@kernel
def lemke(A, Fs, q, z_start, G0, max_pivots, pivot_tol, tie_tol, x_out, ray_out, z_basic_out):
    """Lemke's method from the complementary basis with z_i basic where z_start[i].

    ``A`` = [M | d] (n x (n + 1)) and q, in the scaled units of tableau.solve, with Fs
    empty; or M = Fs Fs' given by Fs (n x r) and A = d (n x 1), see the module docstring
    (the block H then has at most r + 1 columns: a pivot that would give it more stops
    with NUMERICAL_FAILURE).  The
    artificial variable's column must be positive in the coordinates of that basis.  ``G0``
    is the inverse of the starting block A[z_start, z_start] when the caller has it, else
    an empty array.  Returns ``(status, pivots)``; x_out gets z and z0, ray_out the ray on
    RAY_TERMINATION and z_basic_out the final set of basic z's.
    """
    n = q.shape[0]
    kmax = n if Fs.shape[0] == 0 else min(n, Fs.shape[1] + 1)  # H's largest size
    # Three allocations for the whole run (each one costs about as much as a small pivot):
    # the int, float and key work arrays, carved by lemke_in.
    return lemke_in(A, Fs, q, z_start, G0, max_pivots, pivot_tol, tie_tol, x_out, ray_out,
                    z_basic_out, np.empty(7 * n + 1, dtype=np.int64),
                    np.empty(n * kmax + kmax * kmax + 15 * n + 1),
                    np.empty(2 * n + 4, dtype=np.uint64))


@kernel
def lemke_in(A, Fs, q, z_start, G0, max_pivots, pivot_tol, tie_tol, x_out, ray_out,
             z_basic_out, I, F, H):
    """:func:`lemke` with its work arrays given (``I`` 7n + 1 int64, ``F`` n kmax + kmax^2 +
    15n + 1 floats, ``H`` 2n + 4 uint64).  Every array, the arguments included, is borrowed
    (``linalg.borrow``): the kernels called every pivot (``direction``, ``fetch_column``,
    ``ratio_test``, ``update_basis`` ...) then count no references to what they are handed
    (with views, 22 % of a solve at n = 48 went to reference counts)."""
    n = q.shape[0]
    art = 2 * n
    kmax = n if Fs.shape[0] == 0 else min(n, Fs.shape[1] + 1)  # H's largest size
    A = borrow(A, 0, (A.shape[0], A.shape[1]), np.float64)
    Fs = borrow(Fs, 0, (Fs.shape[0], Fs.shape[1]), np.float64)
    q = borrow(q, 0, n, np.float64)
    z_start = borrow(z_start, 0, z_start.shape[0], np.bool_)
    x_out = borrow(x_out, 0, x_out.shape[0], np.float64)
    ray_out = borrow(ray_out, 0, ray_out.shape[0], np.float64)
    alist = borrow(I, 0, n, np.int64)  # H's rows: the non-basic w's
    blist = borrow(I, n, n, np.int64)  # H's columns: the basic z's (n stands for z0)
    apos, bpos = borrow(I, 2 * n, n, np.int64), borrow(I, 3 * n, n + 1, np.int64)
    apos[:] = -1
    bpos[:] = -1
    o = n * kmax + kmax * kmax
    AB = borrow(F, 0, (n, kmax), np.float64)  # AB[:, c] = A[:, blist[c]]
    G = borrow(F, n * kmax, (kmax, kmax), np.float64)
    zb = borrow(F, o, n, np.float64)
    wv = borrow(F, o + 1 * n, n, np.float64)
    dzb = borrow(F, o + 2 * n, n, np.float64)
    dw = borrow(F, o + 3 * n, n, np.float64)
    lz = borrow(F, o + 4 * n, n, np.float64)
    lw = borrow(F, o + 5 * n, n, np.float64)
    tmp = borrow(F, o + 6 * n, n, np.float64)
    tmp2 = borrow(F, o + 7 * n, n, np.float64)
    row = borrow(F, o + 8 * n, n, np.float64)
    keys = borrow(F, o + 9 * n, n, np.float64)
    rv = borrow(F, o + 10 * n, n, np.float64)  # the basic variables' values (pair order, z0 last)
    rc = borrow(F, o + 11 * n, n, np.float64)  # and their changes per unit of the entering variable
    acol = borrow(F, o + 12 * n, n, np.float64)  # the entering variable's column of A
    lcol = borrow(F, o + 13 * n, n, np.float64)  # and another one's, for the lexicographic keys
    coef = borrow(F, o + 14 * n, n, np.float64)  # update_basis's multipliers
    z0_max = borrow(F, o + 15 * n, 1, np.float64)  # the largest value z0 has had (ratio_test keeps it)
    z0_max[0] = 0.0
    cand = borrow(I, 4 * n + 1, n, np.int64)  # tied candidates, as positions in rlab
    rlab = borrow(I, 5 * n + 1, n, np.int64)  # the basic variables in pair order, z0 last
    # the labels' keys and the cycle detector
    hkeys, detector = borrow(H, 0, 2 * n + 1, np.uint64), borrow(H, 2 * n + 1, 3, np.uint64)
    pivoting.fill_label_keys(hkeys)
    detector[:] = 0
    k = np.int64(0)  # not a literal 0: see kernels/__init__.py
    for i in range(n):
        if z_start[i]:
            alist[k] = i
            blist[k] = i
            apos[i] = k
            bpos[i] = k
            fetch_column(A, Fs, i, acol)
            set_column(AB, k, acol)
            k += 1
    ray_out[:] = 0.0
    x_out[:] = 0.0

    status = MAX_PIVOTS
    pivots = 0
    if G0.shape[0] == k:
        for r in range(k):
            for c in range(k):
                G[r, c] = G0[r, c]
    elif not invert(AB, alist, k, G):
        status = NUMERICAL_FAILURE
        max_pivots = 0
    basic_point(AB, q, alist, k, G, apos, zb, wv, tmp, tmp2)
    since_refactor = 0
    since_check = 0
    entering = art
    h = np.uint64(0)
    for i in range(n):
        h ^= hkeys[n + i] if bpos[i] >= 0 else hkeys[i]
    while pivots < max_pivots:
        if entering >= n:
            fetch_column(A, Fs, entering - n, acol)
        direction(acol, AB, entering, n, alist, k, G, apos, dzb, dw, tmp)
        m = gather(n, apos, bpos, zb, wv, dzb, dw, rlab, rv, rc)
        if pivots == 0:
            # z0 rises until every basic variable is >= 0 (pivoting.first_row).
            r = pivoting.first_row(rv, rc, m, tie_tol)
            if r < 0:
                status = NUMERICAL_FAILURE
                break
            leaving = rlab[r]
        else:
            r = ratio_test(A, Fs, AB, n, alist, k, G, apos, bpos, dzb, dw, z_start,
                           pivot_tol, tie_tol, rlab, rv, rc, m, cand, keys, lz, lw, tmp,
                           lcol, z0_max)
            leaving = rlab[r] if r >= 0 else np.int64(-1)
            if leaving < 0:
                status = RAY_TERMINATION
                if entering >= n:
                    ray_out[entering - n] = 1.0
                for p in range(k):
                    ray_out[blist[p]] = dzb[p]
                break
        piv = dzb[bpos[leaving - n]] if leaving >= n else dw[leaving]
        if not abs(piv) < np.inf:  # a NaN or infinite pivot: give up
            status = NUMERICAL_FAILURE
            break
        if entering >= n and leaving < n and k >= kmax:
            status = NUMERICAL_FAILURE  # H would outgrow M's rank: rounding, not a pivot
            break
        # The values move along the direction by the entering variable's new value t
        # (updated in place, as the tableau updates its right-hand side).
        t = -rv[r] / rc[r]
        advance(t, k, n, apos, zb, dzb, wv, dw)
        ok = update_basis(acol, AB, n, entering, leaving, alist, blist, apos, bpos, k, G, dzb, dw,
                          row, zb, coef)
        if entering >= n and leaving < n:
            k += 1  # the block gained a row and a column
        elif entering < n and leaving >= n:
            k -= 1  # the block lost a row and a column
        place(t, entering, n, bpos, zb, wv)
        pivots += 1
        since_refactor += 1
        since_check += 1
        refresh = not ok or since_refactor >= REFACTOR_EVERY
        if not refresh and since_check >= CHECK_EVERY:
            since_check = 0
            refresh = drift(AB, q, apos, zb, k, wv) > RESIDUAL_TOL
        if refresh:
            # a tiny update pivot, the periodic refactorization, or values that drifted:
            # refactor, and recompute the values from the inverse
            since_refactor = 0
            since_check = 0
            if k > 0 and not invert(AB, alist, k, G):
                status = NUMERICAL_FAILURE
                break
            basic_point(AB, q, alist, k, G, apos, zb, wv, tmp, tmp2)
        h, stop = pivoting.after_pivot(leaving, entering, art, h, hkeys, detector)
        if stop >= 0:
            status = stop
            break
        entering = leaving + n if leaving < n else leaving - n
    if status != NUMERICAL_FAILURE:
        # the point from the basis inverse, not the values updated in place
        basic_point(AB, q, alist, k, G, apos, zb, wv, tmp, tmp2)
    for p in range(k):
        x_out[blist[p]] = zb[p]
    for i in range(n):
        z_basic_out[i] = bpos[i] >= 0
    return status, pivots


@inline_kernel
def solve(M, q, d, R, C, z_start, G0, max_pivots, pivot_tol, tie_tol, x_out, ray_out,
          z_basic_out):
    """Lemke's method from the basis ``z_start`` on (M, q) with covering vector d, on the
    equilibrated system of ``linalg.scaled_system`` (R, C: the row and column scales;
    ``G0``: the inverse of the starting block in those units, or an empty array).  Outputs
    as ``lemke``, in the caller's units."""
    A, qs, d_scale = scaled_system(M, q, d, R, C)
    status, pivots = lemke(A, no_matrix(), qs, z_start, G0, max_pivots, pivot_tol, tie_tol,
                           x_out, ray_out, z_basic_out)
    unscale(x_out, ray_out, C, 1.0 / d_scale, status == SOLVED)
    return status, pivots


@kernel
def gather(n, apos, bpos, zb, wv, dzb, dw, rlab, rv, rc):
    """The basic variables in pair order (z0 last): labels, values and changes per unit of
    the entering variable.  Returns how many (n: z0 and one variable of every pair but the
    entering one's)."""
    m = 0
    for i in range(n + 1):
        if bpos[i] >= 0:
            rlab[m] = n + i
            rv[m] = zb[bpos[i]]
            rc[m] = dzb[bpos[i]]
            m += 1
        elif i < n and apos[i] < 0:
            rlab[m] = i
            rv[m] = wv[i]
            rc[m] = dw[i]
            m += 1
    return m


@inline_kernel
def ratio_test(A, Fs, AB, n, alist, k, G, apos, bpos, dzb, dw, z_start, pivot_tol, tie_tol,
               rlab, rv, rc, m, cand, keys, lz, lw, tmp, lcol, z0_max):
    """The leaving variable's position in (rlab, rv, rc), the basic variables gathered by
    :func:`gather`, or -1 when nothing blocks: pivoting's rule over them, with the values
    as their own sizes (as in the tableau's first run: only negative values count as
    zero)."""
    art = 2 * n
    r_art = m - 1 if m > 0 and rlab[m - 1] == art else np.int64(-1)  # see kernels/__init__.py
    if r_art >= 0:
        z0_max[0] = max(z0_max[0], rv[r_art])
    nc = pivoting.min_ratio(rv, rv, rc, m, pivot_tol, tie_tol, cand, r_art, z0_max[0])
    if nc <= 1:
        return cand[0] if nc == 1 else -1
    for c in range(nc):
        if rlab[cand[c]] == art:
            return cand[c]
    # Column j of the basis inverse relative to the starting basis is the unit vector of
    # its pair-j variable when that is basic, else minus its direction.
    for j in range(n):
        lab = n + j if z_start[j] else j
        basic = bpos[j] >= 0 if z_start[j] else apos[j] < 0
        if not basic:
            if lab >= n:
                fetch_column(A, Fs, lab - n, lcol)
            direction(lcol, AB, lab, n, alist, k, G, apos, lz, lw, tmp)
        for c in range(nc):
            cl = rlab[cand[c]]
            if basic:
                b = 1.0 if cl == lab else 0.0
            else:
                b = -(lz[bpos[cl - n]] if cl >= n else lw[cl])
            keys[c] = pivoting.lex_key(b, rc[cand[c]], pivot_tol)
        nc = pivoting.keep_lowest(cand, keys, nc, tie_tol)
        if nc == 1:
            return cand[0]
    return pivoting.largest_pivot(cand, rc, nc) if nc > 0 else -1


@inline_kernel
def update_basis(acol, AB, n, entering, leaving, alist, blist, apos, bpos, k, G, dzb, dw, row, zb,
                 coef):
    """Update the index sets, AB and G = H^-1 for ``entering`` replacing ``leaving``
    (``acol``: the entering variable's column of A, when it is a z; ``row`` and ``coef``:
    scratch of n floats).  Returns False when the update's pivot is too small to trust
    (then refactor)."""
    if entering >= n and leaving < n:
        # z_e enters, w_i leaves: H gains row i and column e.  With u = G A[alpha, e]
        # (= -dzb), r = A[i, beta] G and the Schur complement s = dw[i]:
        # G' = [[G + u r / s, -u / s], [-r / s, 1 / s]].
        e = entering - n
        i = leaving
        s = dw[i]
        _row_times(row_of(AB, i), G, k, row)
        for p in range(k):
            coef[p] = -dzb[p] / s
            G[p, k] = dzb[p] / s
        add_rows(G, k, coef, row, np.False_)
        for c in range(k):
            G[k, c] = -row[c] / s
        G[k, k] = 1.0 / s
        alist[k] = i
        apos[i] = k
        blist[k] = e
        bpos[e] = k
        set_column(AB, k, acol)
        return abs(s) > 1e-13
    if entering >= n:
        # z_e replaces z_l as column p of H (Sherman-Morrison): with u = G A[alpha, e],
        # G' = G - (u - e_p) G[p, :] / u[p].
        e = entering - n
        l = leaving - n
        p = bpos[l]
        piv = -dzb[p]
        for c in range(k):
            row[c] = G[p, c] / piv
        for r in range(k):
            coef[r] = dzb[r] + (1.0 if r == p else 0.0)  # -f, f = -dzb[r] - [r == p]
        add_rows(G, k, coef, row, np.True_)
        blist[p] = e
        bpos[l] = -1
        bpos[e] = p
        set_column(AB, p, acol)
        return abs(piv) > 1e-13
    if leaving < n:
        # w_j enters, w_i leaves: row p of H becomes A[i, beta].  With r = A[i, beta] G:
        # G' = G - G[:, p] (r - e_p) / r[p].
        j = entering
        i = leaving
        p = apos[j]
        _row_times(row_of(AB, i), G, k, row)
        piv = row[p]
        row[p] -= 1.0
        for r in range(k):
            coef[r] = -(dzb[r] / piv)  # dzb = G[:, p]
        add_rows(G, k, coef, row, np.True_)
        alist[p] = i
        apos[j] = -1
        apos[i] = p
        return abs(piv) > 1e-13
    # w_j enters, z_l leaves: H loses row p (w_j) and column m (z_l):
    # G' = G[-m, -p] - G[-m, p] G[m, -p] / G[m, p]; then the last row and column of G
    # (and of the index lists) move into the freed slots.
    j = entering
    l = leaving - n
    p = apos[j]
    m = bpos[l]
    piv = G[m, p]
    for r in range(k):
        coef[r] = -(G[r, p] / piv) if r != m else 0.0
    for c in range(k):
        row[c] = G[m, c]
    add_rows(G, k, coef, row, np.True_)
    last = k - 1
    for c in range(k):
        G[m, c] = G[last, c]
    for r in range(last):
        G[r, p] = G[r, last]
    copy_column(AB, m, AB, last)
    zb[m] = zb[last]
    bl = blist[last]
    blist[m] = bl
    bpos[bl] = m
    bpos[l] = -1
    al = alist[last]
    alist[p] = al
    apos[al] = p
    apos[j] = -1
    return abs(piv) > 1e-13


@kernel
def add_rows(G, k, a, x, skip_zero):
    """G[r, :k] += a[r] x[:k] for every r < k (but those with a[r] == 0 when skip_zero):
    ``linalg.axpy`` on each row, the same operations, in one call.  A row view and a call
    per row cost two atomic reference count operations each, and x, not a row of G, lets
    LLVM's overlap check (hoisted out of the row loop) pass, so that the rows' loops run
    in vector registers."""
    for r in range(k):
        f = a[r]
        if f != 0.0 or not skip_zero:
            for c in range(k):
                G[r, c] += f * x[c]


@kernel
def _row_times(x, G, k, out):
    """out[:k] = x[:k] G[:k, :k] (row-major friendly)."""
    for c in range(k):
        out[c] = 0.0
    for p in range(k):  # linalg.axpy of each row of G, without a view per row (add_rows)
        xp = x[p]
        if xp != 0.0:
            for c in range(k):
                out[c] += xp * G[p, c]
