"""From a mixed LCP to a plain LCP: exchange pivots that make every free variable basic.

The MLCP, in the Siconos form, is ``E x + e = (0, w)`` with ``x = (u, v)``: u (n of them)
free, 0 <= v ⊥ w >= 0 (m pairs).  The kernel works on the dictionary ``T = [E | e]``
(N = n + m rows, N + 1 columns): row r says ``basic_r = sum_c T[r, c] nonbasic_c + T[r, N]``.
Labels: ``0 .. N-1`` are the outputs (the slack of equation i for i < n, then w_k), ``N ..
2N-1`` the inputs (u, then v_k).  At the start the outputs are basic.

``reduce`` exchanges until every free u is basic and every slack of an equation non-basic
(its value is then 0, as the equation demands), keeping each pair complementary: exactly
one of v_k, w_k basic.  What is left is an LCP in the pairs.  Three steps:

1. a u enters in place of an equation's slack (partial pivoting, largest entry first);
2. when that block is singular (an LP, or equality multipliers that only appear in the
   complementarity rows), a pair k is swapped to make room: its non-basic partner enters in
   place of an equation's slack, and then a u enters in place of pair k's old basic
   variable (a 2 x 2 exchange, chosen to make the product of its two pivots largest);
3. what still remains is a redundant equation (all of its row zero: consistent when its
   constant is zero too) paired with a free variable that appears nowhere (set to 0).

Exchanges on a monotone E (a convex QP's KKT matrix) leave a monotone LCP, so Lemke's method
then either solves it or proves it infeasible.
"""
import numpy as np

from . import kernel

OK = 0
INCONSISTENT = 1  # an equation reads 0 = c with c != 0: the MLCP has no solution
SINGULAR = 2  # no exchange makes the free block nonsingular (not seen on monotone E)


@kernel
def exchange(T, r, c, row_label, col_label, prow, nz):
    """Exchange the basic variable of row r with the non-basic one of column c.  ``prow``
    (N + 1 floats) and ``nz`` (N + 1 int64s) are scratch.  A KKT system is sparse (on the
    Maros-Meszaros LPs a few per cent of T is non-zero after every exchange), so where the
    pivot row has few non-zeros only those columns of the other rows are updated: the same
    sums on the entries that change, and none on the others."""
    rows, cols = T.shape
    inv = 1.0 / T[r, c]
    m = 0
    for k in range(cols):  # (prow[c] is not set to inv: the rows' entries c are overwritten)
        v = -T[r, k] * inv
        prow[k] = v
        T[r, k] = v
        if v != 0.0 and k != c:
            nz[m] = k
            m += 1
    T[r, c] = inv
    sparse = 4 * m < cols
    for i in range(rows):  # T indexed directly: a row view per row costs refcounting
        if i == r:
            continue
        f = T[i, c]
        if f == 0.0:
            continue
        if sparse:
            for t in range(m):
                k = nz[t]
                T[i, k] += f * prow[k]
        else:
            for k in range(cols):
                T[i, k] += f * prow[k]
        T[i, c] = f * inv
    tmp = row_label[r]
    row_label[r] = col_label[c]
    col_label[c] = tmp


@kernel
def enter_free(T, c, n, rank_tol, row_label, col_label, prow, nz):
    """The free variable of column c enters in place of the slack of an equation, the one
    with the largest entry in that column, if that entry exceeds rank_tol."""
    best, r_best = 0.0, np.int64(-1)  # not a literal: see kernels/__init__.py
    for r in range(T.shape[0]):
        if row_label[r] < n and abs(T[r, c]) > best:
            best, r_best = abs(T[r, c]), r
    if r_best >= 0 and best > rank_tol:
        exchange(T, r_best, c, row_label, col_label, prow, nz)


@kernel
def reduce(T, n, rank_tol, e_size, row_label, col_label):
    """Make every free variable basic (see the module docstring).  Returns ``(code, row)``;
    ``row`` is the offending row when code is INCONSISTENT or SINGULAR.  The data should be
    equilibrated (entries of E at most 1 in size): an entry is a pivot when it exceeds
    ``rank_tol``, and an equation's constant is zero when below ``rank_tol * e_size``."""
    N = T.shape[0]
    prow = np.empty(N + 1)
    nz = np.empty(N + 1, dtype=np.int64)
    for i in range(N):
        row_label[i] = i
        col_label[i] = N + i
    # 1. u_c enters in place of the slack of an equation (column by column, largest pivot).
    for c in range(n):
        enter_free(T, c, n, rank_tol, row_label, col_label, prow, nz)

    # 2. Swap a pair k to make room: 2 x 2 exchanges while slacks and free columns remain.
    # Each round lists the free columns still non-basic, the rows of slacks and where each
    # non-basic label is (O(N)), so that its search reads only those entries of T.
    fcols = np.empty(N, dtype=np.int64)
    srows = np.empty(N, dtype=np.int64)
    col_of = np.empty(2 * N, dtype=np.int64)
    while True:
        nf = 0
        col_of[:] = -1
        for c in range(N):
            lc = col_label[c]
            col_of[lc] = c
            if N <= lc < N + n:
                fcols[nf] = c
                nf += 1
        ns = 0
        for r in range(N):
            if row_label[r] < n:
                srows[ns] = r
                ns += 1
        # Rows of pair variables: for each, its largest entry over the free columns.
        best = 0.0
        r_best, k_col, k_row = np.int64(-1), np.int64(-1), np.int64(-1)  # see kernels/__init__.py
        for i in range(N):
            li = row_label[i]
            if li < n or (N <= li < N + n):
                continue  # a slack or a free variable: not a pair's row
            rmax = 0.0
            for t in range(nf):
                rmax = max(rmax, abs(T[i, fcols[t]]))
            if rmax <= rank_tol:
                continue
            # This row's pair partner is non-basic in some column j.
            j = col_of[li - N if li >= N else li + N]
            for t in range(ns):
                r = srows[t]
                v = abs(T[r, j])
                if v > rank_tol and v * rmax > best:
                    best, r_best, k_col, k_row = v * rmax, r, j, i
        if r_best < 0:
            break
        exchange(T, r_best, k_col, row_label, col_label, prow, nz)
        c_best, cbest = np.int64(-1), 0.0  # not a literal: see kernels/__init__.py
        for c in range(N):
            if N <= col_label[c] < N + n and abs(T[k_row, c]) > cbest:
                cbest, c_best = abs(T[k_row, c]), c
        exchange(T, k_row, c_best, row_label, col_label, prow, nz)
        # The 1-step pivot may now succeed in a column that failed before.
        for c in range(N):
            if N <= col_label[c] < N + n:
                enter_free(T, c, n, rank_tol, row_label, col_label, prow, nz)

    # 3. What remains must be redundant: zero rows (slacks) and zero columns (free variables).
    for r in range(N):
        if row_label[r] >= n:
            continue
        for c in range(N):
            lc = col_label[c]
            if lc >= n and abs(T[r, c]) > rank_tol:
                return SINGULAR, r  # a non-zero row left: not seen on monotone problems
        if abs(T[r, N]) > rank_tol * e_size:
            return INCONSISTENT, r
    for c in range(N):
        if not (N <= col_label[c] < N + n):
            continue
        for r in range(N):
            lr = row_label[r]
            if lr >= n and not (N <= lr < N + n) and abs(T[r, c]) > rank_tol:
                return SINGULAR, r  # it moves a pair: it is not free to be set to 0
    return OK, -1


@kernel
def equilibrate(E, n, iterations, r, s):
    """Ruiz scaling of the stacked E (see ``_reductions.mlcp_lcp.equilibrate``) into r and s
    (both all ones on entry), the same operations in the same order as numpy's, so the same
    bits: per sweep the largest entry of each row and column of ``|E| r s``, the free rows
    and columns divided by its square root, and a pair's row and column both multiplied by
    one over the square root of the larger of the two.  Stops early once every row and
    column is within 0.1 of 1."""
    N = E.shape[0]
    rows = np.empty(N)
    cols = np.empty(N)
    for _ in range(iterations):
        for i in range(N):
            rows[i] = -np.inf
            cols[i] = -np.inf
        for i in range(N):
            Ei = E[i]
            ri = r[i]
            for j in range(N):
                v = abs(Ei[j]) * ri * s[j]
                if v > rows[i] or v != v:
                    rows[i] = v
                if v > cols[j] or v != v:
                    cols[j] = v
        done = True
        for i in range(N):
            if rows[i] == 0.0:
                rows[i] = 1.0
            if cols[i] == 0.0:
                cols[i] = 1.0
            if not (abs(rows[i] - 1.0) < 0.1 and abs(cols[i] - 1.0) < 0.1):
                done = False
        for i in range(n):
            r[i] /= np.sqrt(rows[i])
            s[i] /= np.sqrt(cols[i])
        for i in range(n, N):
            a = rows[i]
            b = cols[i]
            f = 1.0 / np.sqrt(a if (a >= b or a != a) else b)
            r[i] *= f
            s[i] *= f
        if done:
            break
