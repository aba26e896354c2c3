"""Lemke's complementary pivoting on a condensed tableau.

The tableau holds only the non-basic columns.  Row i says

    basic[i] = rhs[i] + sum_j T[i, j] * nonbasic[j]

for the n basic variables and the n + 1 non-basic ones (z0, the artificial variable, among
them).  A cold start is ``T = [M | d]``, ``rhs = q``, w basic and z, z0 non-basic: the
system ``w = M z + q + d z0``.  Storing n x (n + 1) numbers instead of the full
n x (2n + 2) tableau halves the memory each pivot sweeps.

Variables are labelled ``0..n-1`` for w, ``n..2n-1`` for z and ``2n`` for z0.  The columns
of the basis inverse, needed by the lexicographic rule, are read off the tableau: the
variable that was basic in row j at the start has the unit column e_row when basic and
``-T[:, col]`` when non-basic.

Updates are delayed: a pivot is a rank-one change of every row but the pivot row, and up to
``block_size(n)`` of them are kept pending (``U`` n x b, ``V`` b x (n + 1): the current
tableau is ``T + sum_k U[:, k] V[k]``, summed in pivot order) and then applied row by row,
each row read and written once for the whole block while it sits in the L1 cache.  The
pivot row and the pivot column are written into T at once (their pending terms zeroed), and
the column and row each pivot needs are formed from T and the pending terms with exactly the
operations, in the order, of an immediate update: the delay changes no bit of the result, it
only cuts the memory traffic, which bounds the speed of a tableau that does not fit in cache.
"""
import numpy as np

from . import inline_kernel, kernel, pivoting
from .linalg import axpy, borrow, copy, scaled_into
from .pivoting import MAX_PIVOTS, NUMERICAL_FAILURE, RAY_TERMINATION, SOLVED


@kernel
def block_size(n):
    """Pivots kept pending before they are applied: 1 (no delay) while the tableau fits in
    the cache anyway."""
    return 1 if n < 400 else 8


@inline_kernel
def entry(T, U, V, k, i, j):
    """The current T[i, j]: T[i, j] plus the k pending terms, in pivot order."""
    t = T[i, j]
    for p in range(k):
        f = U[i, p]
        if f != 0.0:
            t += f * V[p, j]
    return t


@inline_kernel
def current_column(T, U, V, k, s, col):
    """col = the current column s."""
    for i in range(T.shape[0]):
        col[i] = entry(T, U, V, k, i, s)


@inline_kernel
def pivot(T, rhs, magb, r, s, col, U, V, k, prow, act):
    """Exchange the basic variable of row r with the non-basic variable of column s (whose
    current values are in ``col``), with k pivots pending; returns the new number pending.

    ``prow`` is scratch of length n + 1 for the new pivot row, ``act`` for ``flush``.
    """
    n, m = T.shape
    inv = 1.0 / col[r]
    copy(prow, T[r])
    for p in range(k):
        f = U[r, p]
        if f != 0.0:
            axpy(prow, f, V[p])
    for j in range(m):
        prow[j] = -prow[j] * inv
    prow[s] = inv
    for j in range(m):  # loops, not row assignments, which compile error formatting
        T[r, j] = prow[j]
    rhs[r] = -rhs[r] * inv
    rr = rhs[r]
    magb[r] *= abs(inv)  # an upper bound on |B^-1| |q| per row (see careful_sizes)
    mr = magb[r]
    for p in range(k):  # row r and column s are now exact in T
        U[r, p] = 0.0
        V[p, s] = 0.0
    for i in range(n):
        f = col[i]
        U[i, k] = f
        if i != r:
            T[i, s] = f * inv
            if f != 0.0:  # an exact zero leaves row i unchanged: sparse columns cost nothing
                rhs[i] += f * rr
                magb[i] += abs(f) * mr
    U[r, k] = 0.0
    for j in range(m):
        V[k, j] = prow[j]
    V[k, s] = 0.0
    k += 1
    if k == U.shape[1]:
        flush(T, U, V, k, act)
        k = 0
    return k


@kernel
def pivot_now(T, rhs, magb, r, s, col, prow):
    """:func:`pivot` with nothing pending and the update applied at once (a block of 1): the
    same operations in the same order as pivot() followed by :func:`flush` (flush's update
    of row i, its entry s included, where V's row is 0), so the same bits.  ``prow``:
    scratch of length T.shape[1].  A kernel, not inlined: an inlined callee's array
    arguments cost an atomic reference count increment and decrement each, every pivot.

    Entry s of a row is written after the row's loop, never before: a scalar store that the
    loop's vector loads then overlap cannot be forwarded to them, and that stall was about
    40 % of a pivot at n = 24.  So prow[s] keeps the loop's -T[r, s] inv (V's row has 0
    there: the rows' updates in column s are overwritten, by the values they would have
    had: f inv + f * 0)."""
    n, m = T.shape
    inv = 1.0 / col[r]
    for j in range(m):
        v = -T[r, j] * inv
        prow[j] = v
        T[r, j] = v
    T[r, s] = inv
    rhs[r] = -rhs[r] * inv
    rr = rhs[r]
    magb[r] *= abs(inv)  # an upper bound on |B^-1| |q| per row (see careful_sizes)
    mr = magb[r]
    for i in range(n):
        if i != r:
            f = col[i]
            if f != 0.0:
                rhs[i] += f * rr
                magb[i] += abs(f) * mr
                for j in range(m):
                    T[i, j] += f * prow[j]
                T[i, s] = f * inv + f * 0.0
            else:
                T[i, s] = f * inv


@inline_kernel
def flush(T, U, V, k, act):
    """Apply the k pending pivots, row by row, four at a time (the terms of a row with a
    zero factor are skipped, as an immediate update would skip them).  ``act``: scratch of
    length >= k.  Indexes T and V directly: a row view per row costs more than the update
    itself at small n."""
    n, m = T.shape
    for i in range(n):
        na = 0
        for p in range(k):
            if U[i, p] != 0.0:
                act[na] = p
                na += 1
        c = 0
        while c + 4 <= na:
            p0, p1, p2, p3 = act[c], act[c + 1], act[c + 2], act[c + 3]
            a0, a1, a2, a3 = U[i, p0], U[i, p1], U[i, p2], U[i, p3]
            for j in range(m):
                T[i, j] = (((T[i, j] + a0 * V[p0, j]) + a1 * V[p1, j]) + a2 * V[p2, j]) + a3 * V[p3, j]
            c += 4
        while c < na:
            p = act[c]
            a = U[i, p]
            for j in range(m):
                T[i, j] += a * V[p, j]
            c += 1


@inline_kernel
def careful_sizes(T, U, V, k_pending, col, rhs, pos, is_basic, start_basis, q0, magb, mags):
    """``mags`` = the size of the terms behind each value, |B^-1| |q|, for the rule's test of
    "zero to rounding", in a careful run (the recovery runs of kernels.cold): magb bounds it
    from above (updated with every pivot), so only a row whose value is below
    VALUE_ROUNDING * magb can be rounding, and only for those rows is the exact size
    computed, from the row of B^-1 (O(n) each; the bound grows with the pivots, and on
    large problems that makes the first run up to 10x slower, so the first run passes the
    values themselves); the other rows get their values."""
    n = T.shape[0]
    for i in range(n):
        v = rhs[i]
        mags[i] = v
        if col[i] < 0.0 and v > 0.0 and v <= pivoting.VALUE_ROUNDING * magb[i]:
            size = 0.0
            for j in range(n):
                lab = start_basis[j]
                if is_basic[lab]:
                    b = 1.0 if pos[lab] == i else 0.0
                else:
                    b = entry(T, U, V, k_pending, i, pos[lab])
                size += abs(b) * abs(q0[j])
            mags[i] = size


@inline_kernel
def lex_ties(T, U, V, k_pending, col, basis, pos, is_basic, start_basis, artificial, pivot_tol,
             tie_tol, cand, keys, nc):
    """The row among the ``nc`` candidates tied at the minimum ratio (``cand``, nc >= 2):
    the artificial variable if it is one of them, else the lexicographic rule."""
    n = T.shape[0]
    for c in range(nc):
        if basis[cand[c]] == artificial:
            return cand[c]
    # Column j of B^-1 is the column of the variable basic in row j at the start: the unit
    # vector of its row while it is basic, minus its tableau column while it is not.
    for j in range(n):
        lab = start_basis[j]
        for c in range(nc):
            i = cand[c]
            if is_basic[lab]:
                b = 1.0 if pos[lab] == i else 0.0
            else:
                b = -entry(T, U, V, k_pending, i, pos[lab])
            keys[c] = pivoting.lex_key(b, col[i], pivot_tol)
        nc = pivoting.keep_lowest(cand, keys, nc, tie_tol)
        if nc == 1:
            return cand[0]
    return pivoting.largest_pivot(cand, col, nc) if nc > 0 else np.int64(-1)


@kernel
def work_sizes(n, block):
    """The lengths of the float and int64 work arrays of :func:`lemke`."""
    return 6 * n + 1 + block * (2 * n + 1), 4 * n + 1 + block + (2 * n + 1 + 7) // 8 + 2 * n + 4


@kernel
def lemke(T, rhs, basis, nonbasic, max_pivots, pivot_tol, tie_tol, x_out, ray_out, z_basic_out,
          block, careful, F, I):
    """Run Lemke's method from the tableau (T, rhs) with the artificial variable non-basic,
    keeping up to ``block`` pivots pending (any block gives the same bits).

    ``basis`` (n) and ``nonbasic`` (n + 1) hold the labels of the rows and columns and are
    updated in place; so are T and rhs.  Returns ``(status, pivots)``.  ``x_out`` (n + 1)
    receives the final z and z0; on a ray, ``ray_out`` (n + 1) receives its direction;
    ``z_basic_out`` (n) says which z's end basic.  ``F`` (float64) and ``I`` (int64) are
    work arrays of at least the lengths :func:`work_sizes`, allocated by the caller with
    the tableau (see :func:`solve`).
    """
    n = T.shape[0]
    artificial = 2 * n
    # The float, int, bool and key work arrays lie in the caller's two arrays (an
    # allocation costs about as much as a small pivot), borrowed (linalg.borrow: no
    # reference counts); the flags and the keys are bool and uint64 arrays over the int64 one.
    keys, col = borrow(F, 0, n, np.float64), borrow(F, n, n, np.float64)
    q0 = borrow(F, 2 * n, n, np.float64)
    magb, mags = borrow(F, 3 * n, n, np.float64), borrow(F, 4 * n, n, np.float64)
    prow = borrow(F, 5 * n, n + 1, np.float64)
    U = borrow(F, 6 * n + 1, (n, block), np.float64)
    V = borrow(F, 6 * n + 1 + n * block, (block, n + 1), np.float64)
    pos, start_basis = borrow(I, 0, 2 * n + 1, np.int64), borrow(I, 2 * n + 1, n, np.int64)
    cand, act = borrow(I, 3 * n + 1, n, np.int64), borrow(I, 4 * n + 1, block, np.int64)
    nb = (2 * n + 1 + 7) // 8  # int64 words for the 2n + 1 flags
    is_basic = borrow(I, 4 * n + 1 + block, 2 * n + 1, np.bool_)
    for i in range(2 * n + 1):
        is_basic[i] = False
    # the labels' keys and the cycle detector
    hkeys = borrow(I, 4 * n + 1 + block + nb, 2 * n + 1, np.uint64)
    detector = borrow(I, 4 * n + 1 + block + nb + 2 * n + 1, 3, np.uint64)
    for i in range(n):
        start_basis[i] = basis[i]  # (a loop: see unrevised.copy_column)
        pos[basis[i]] = i
        is_basic[basis[i]] = True
    for j in range(n + 1):
        pos[nonbasic[j]] = j
    k = np.int64(0)  # pivots pending (not a literal 0: see kernels/__init__.py)
    ray_out[:] = 0.0

    status = MAX_PIVOTS
    pivots = 0
    s = pos[artificial]
    current_column(T, U, V, k, s, col)
    # First pivot: z0 rises until every basic variable is >= 0 (pivoting.first_row).
    r = pivoting.first_row(rhs, col, n, tie_tol)
    if r < 0:
        max_pivots = 0
        status = NUMERICAL_FAILURE
    pivoting.fill_label_keys(hkeys)
    h = pivoting.fingerprint(hkeys, basis, n)
    detector[:] = 0
    z0_max = 0.0
    for i in range(n):
        q0[i] = rhs[i]  # the right-hand side of the starting basis
        magb[i] = abs(rhs[i])
    while pivots < max_pivots:
        leaving = basis[r]
        entering = nonbasic[s]
        if not abs(col[r]) < np.inf:  # a NaN or infinite pivot: give up, never index with it
            status = NUMERICAL_FAILURE
            break
        if block == 1:
            pivot_now(T, rhs, magb, r, s, col, prow)
        else:
            k = pivot(T, rhs, magb, r, s, col, U, V, k, prow, act)
        pivots += 1
        pivoting.swap_labels(basis, nonbasic, pos, is_basic, r, s)
        h, stop = pivoting.after_pivot(leaving, entering, artificial, h, hkeys, detector)
        if stop >= 0:
            status = stop
            break
        s = pos[leaving + n if leaving < n else leaving - n]  # the complement enters
        if k == 0:  # current_column, and max |col| for the ratio test (min_ratio's)
            for i in range(n):
                col[i] = T[i, s]
        else:
            current_column(T, U, V, k, s, col)
        cmax = 0.0
        for i in range(n):
            cmax = max(cmax, abs(col[i]))
        if is_basic[artificial]:
            z0_max = max(z0_max, rhs[pos[artificial]])
        # The ratio test (the rule of kernels.pivoting, the columns of the basis inverse read
        # off the tableau), its parts called here: the common pivot, settled by
        # blocking_rows (min_ratio's second half), binds none of the arrays of
        # careful_sizes and lex_ties (a reference count each)
        art = pos[artificial] if is_basic[artificial] else np.int64(-1)  # see kernels/__init__.py
        if careful:
            careful_sizes(T, U, V, k, col, rhs, pos, is_basic, start_basis, q0, magb, mags)
            nc = pivoting.blocking_rows(rhs, mags, col, n, -pivot_tol * cmax, tie_tol, cand, art,
                                        z0_max)
        else:  # the first run: the values are their own sizes
            nc = pivoting.blocking_rows(rhs, rhs, col, n, -pivot_tol * cmax, tie_tol, cand, art,
                                        z0_max)
        if nc <= 1:
            r = cand[0] if nc == 1 else np.int64(-1)
        else:
            r = lex_ties(T, U, V, k, col, basis, pos, is_basic, start_basis, artificial,
                         pivot_tol, tie_tol, cand, keys, nc)
        if r < 0:
            status = RAY_TERMINATION
            entering = nonbasic[s]
            for i in range(n):
                lab = basis[i]
                if lab >= n:
                    ray_out[lab - n] = col[i]
            if entering >= n:
                ray_out[entering - n] = 1.0
            break
    x_out[:] = 0.0
    z_basic_out[:] = False
    for i in range(n):
        lab = basis[i]
        if lab >= n:
            x_out[lab - n] = rhs[i]
            if lab < artificial:
                z_basic_out[lab - n] = True
    return status, pivots


@inline_kernel
def solve(M, q, d, R, C, max_pivots, pivot_tol, tie_tol, x_out, ray_out, z_basic_out,
          careful=False):
    """A cold solve from (M, q, d) with q not >= 0: set up the tableau and pivot.

    Works on the equilibrated system of ``linalg.scaled_system`` (R, C: the row and column
    scales).  Returns ``(status, pivots)``; ``x_out`` gets z and z0 (in the caller's units),
    ``ray_out`` the ray, ``z_basic_out`` the final basic z's.
    """
    n = q.shape[0]
    block = block_size(n)
    nf, ni = work_sizes(n, block)
    # Two allocations for the whole run: the tableau and the floats of lemke, the labels
    # and its ints (at n = 3 each allocation costs about as much as a pivot).
    # T, rhs and the labels borrowed (linalg.borrow): F and I stay referenced through the
    # call of lemke, which gets the rest of each as its work arrays.
    F = np.empty(n * (n + 2) + nf)
    I = np.empty(2 * n + 1 + ni, dtype=np.int64)
    T = borrow(F, 0, (n, n + 1), np.float64)
    rhs = borrow(F, n * (n + 1), n, np.float64)
    d_scale = scaled_into(M, q, d, R, C, T, rhs)
    basis, nonbasic = borrow(I, 0, n, np.int64), borrow(I, n, n + 1, np.int64)
    for i in range(n):
        basis[i] = i
        nonbasic[i] = n + i
    nonbasic[n] = 2 * n
    status, pivots = lemke(T, rhs, basis, nonbasic, max_pivots, pivot_tol, tie_tol, x_out,
                           ray_out, z_basic_out, block, careful, F[n * (n + 2) :],
                           I[2 * n + 1 :])
    unscale(x_out, ray_out, C, 1.0 / d_scale, status == SOLVED)
    return status, pivots


@kernel
def unscale(x_out, ray_out, C, z0_factor, solved):
    """Back to the caller's units: z and its ray times the column scales C, z0 and its ray
    entry times ``z0_factor``; a solved z is clamped at 0 (round-off below zero; anything
    worse fails the check)."""
    n = x_out.shape[0] - 1
    for i in range(n):
        x_out[i] *= C[i]
        ray_out[i] *= C[i]
    x_out[n] *= z0_factor
    ray_out[n] *= z0_factor
    if solved:
        for i in range(n + 1):
            x_out[i] = max(x_out[i], 0.0)
