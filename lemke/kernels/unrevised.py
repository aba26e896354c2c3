"""Lemke's method without a tableau: the "unrevised" method of Dai & Drumwright.

Only the index sets are kept.  With A = [M | d] (d: the artificial variable z0's column),
let alpha be the indices of the non-basic w's and beta those of the basic z's (z0 is index
n).  They have the same size k, and the basic point solves the k x k system

    H z_beta = -q_alpha,        H = A[alpha, beta],

with every basic w_i = q_i + A[i, beta] z_beta.  The change of the basic variables per unit
of a driving variable comes from the same block, so each pivot needs only products with
G = H^-1.  G is updated from pivot to pivot in O(k^2) (one of four cases: the block gains a
row and a column, loses them, or has one row or one column replaced); it is refactored from
scratch every ``REFACTOR_EVERY`` pivots and whenever the basic point fails its residual
check.

Labels and rules are those of the tableau kernel: 0..n-1 for w, n..2n-1 for z, 2n for z0;
minimum ratio, ties to the artificial variable, then the lexicographic rule on the basis
inverse relative to the starting basis (whose row j holds the basic variable of pair j).
"""
import numpy as np

from . import kernel
from .tableau import MAX_PIVOTS, RAY_TERMINATION, SOLVED

NUMERICAL_FAILURE = 3
REFACTOR_EVERY = 100


@kernel
def invert(A, alist, blist, k, G, W):
    """G[:k, :k] = inverse of A[alist, blist] by Gauss-Jordan with partial pivoting, using
    W (at least k x 2k) as scratch.  Returns False when the block is numerically singular."""
    for r in range(k):
        for c in range(k):
            W[r, c] = A[alist[r], blist[c]]
            W[r, k + c] = 1.0 if r == c else 0.0
    scale = 0.0
    for r in range(k):
        for c in range(k):
            scale = max(scale, abs(W[r, c]))
    tiny = 1e-14 * scale * k
    for c in range(k):
        p = c
        for r in range(c + 1, k):
            if abs(W[r, c]) > abs(W[p, c]):
                p = r
        if abs(W[p, c]) <= tiny:
            return False
        if p != c:
            for j in range(2 * k):
                t = W[p, j]
                W[p, j] = W[c, j]
                W[c, j] = t
        inv = 1.0 / W[c, c]
        for j in range(2 * k):
            W[c, j] *= inv
        for r in range(k):
            if r != c:
                f = W[r, c]
                if f != 0.0:
                    for j in range(2 * k):
                        W[r, j] -= f * W[c, j]
    for r in range(k):
        for c in range(k):
            G[r, c] = W[r, k + c]
    return True


@kernel
def basic_point(A, q, alist, blist, k, G, apos, zb, wv, tmp):
    """z_beta = -G q_alpha with one step of refinement, and w_i for the basic w's.
    Returns the relative residual of H z_beta + q_alpha before refinement."""
    n = q.shape[0]
    for p in range(k):
        acc = 0.0
        for c in range(k):
            acc -= G[p, c] * q[alist[c]]
        zb[p] = acc
    res = 0.0
    size = 0.0
    for r in range(k):
        i = alist[r]
        acc = q[i]
        big = abs(q[i])
        for c in range(k):
            t = A[i, blist[c]] * zb[c]
            acc += t
            big = max(big, abs(t))
        tmp[r] = acc
        res = max(res, abs(acc))
        size = max(size, big)
    for p in range(k):
        acc = 0.0
        for c in range(k):
            acc += G[p, c] * tmp[c]
        zb[p] -= acc
    for i in range(n):
        if apos[i] < 0:
            acc = q[i]
            for c in range(k):
                acc += A[i, blist[c]] * zb[c]
            wv[i] = acc
    return res / size if size > 0.0 else 0.0


@kernel
def direction(A, label, n, alist, blist, k, G, apos, dzb, dw):
    """The change of every basic variable per unit increase of the non-basic ``label``:
    dzb (k, for the basic z's in beta order) and dw (n, read at the basic w's)."""
    if label < n:  # a w leaves zero: H dz_beta = e_p
        p = apos[label]
        for r in range(k):
            dzb[r] = G[r, p]
        for i in range(n):
            if apos[i] < 0:
                acc = 0.0
                for c in range(k):
                    acc += A[i, blist[c]] * dzb[c]
                dw[i] = acc
    else:  # a z (or z0) enters: H dz_beta = -A[alpha, e]
        e = label - n
        for r in range(k):
            acc = 0.0
            for c in range(k):
                acc -= G[r, c] * A[alist[c], e]
            dzb[r] = acc
        for i in range(n):
            if apos[i] < 0:
                acc = A[i, e]
                for c in range(k):
                    acc += A[i, blist[c]] * dzb[c]
                dw[i] = acc


@kernel
def lemke(A, q, z_start, max_pivots, pivot_tol, tie_abs, x_out, ray_out, z_basic_out):
    """Lemke's method from the complementary basis with z_i basic where z_start[i].

    ``A`` = [M | d] (n x (n + 1)) and q, in the scaled units of tableau.solve.  Returns
    ``(status, pivots)``; x_out gets z and z0, ray_out the ray on RAY_TERMINATION and
    z_basic_out the final set of basic z's.
    """
    n = q.shape[0]
    art = 2 * n
    alist = np.empty(n, dtype=np.int64)  # H's rows: the non-basic w's
    blist = np.empty(n, dtype=np.int64)  # H's columns: the basic z's (n stands for z0)
    apos = np.full(n, -1, dtype=np.int64)
    bpos = np.full(n + 1, -1, dtype=np.int64)
    k = 0
    for i in range(n):
        if z_start[i]:
            alist[k] = i
            blist[k] = i
            apos[i] = k
            bpos[i] = k
            k += 1
    G = np.empty((n, n))
    W = np.empty((n, 2 * n))
    zb = np.empty(n)
    wv = np.empty(n)
    dzb = np.empty(n)
    dw = np.empty(n)
    lz = np.empty(n)
    lw = np.empty(n)
    tmp = np.empty(n)
    row = np.empty(n)
    cand = np.empty(n, dtype=np.int64)  # candidates as labels
    vals = np.empty(n)
    ray_out[:] = 0.0
    x_out[:] = 0.0

    status = MAX_PIVOTS
    if not invert(A, alist, blist, k, G, W):
        status = NUMERICAL_FAILURE
        max_pivots = 0
    basic_point(A, q, alist, blist, k, G, apos, zb, wv, tmp)
    pivots = 0
    since_refactor = 0
    entering = art
    while pivots < max_pivots:
        direction(A, entering, n, alist, blist, k, G, apos, dzb, dw)
        # --- choose the leaving variable -------------------------------------------------
        leaving = -1
        if pivots == 0:
            # z0 rises until every basic variable is >= 0; the one that needs the most
            # leaves, ties to the highest pair index (the lexicographic choice).
            need = -np.inf
            for i in range(n):
                v = zb[bpos[i]] if bpos[i] >= 0 else wv[i]
                dv = dzb[bpos[i]] if bpos[i] >= 0 else dw[i]
                t = -v / dv
                if t > need:
                    need = t
            for i in range(n):
                v = zb[bpos[i]] if bpos[i] >= 0 else wv[i]
                dv = dzb[bpos[i]] if bpos[i] >= 0 else dw[i]
                if v + dv * need <= tie_abs:
                    leaving = n + i if bpos[i] >= 0 else i
        else:
            cmax = 0.0
            for p in range(k):
                cmax = max(cmax, abs(dzb[p]))
            for i in range(n):
                if apos[i] < 0:
                    cmax = max(cmax, abs(dw[i]))
            thr = -pivot_tol * cmax
            theta = np.inf
            for p in range(k):
                if dzb[p] < thr:
                    theta = min(theta, zb[p] / -dzb[p])
            for i in range(n):
                if apos[i] < 0 and dw[i] < thr:
                    theta = min(theta, wv[i] / -dw[i])
            if theta == np.inf:
                status = RAY_TERMINATION
                if entering >= n:
                    ray_out[entering - n] = 1.0
                for p in range(k):
                    ray_out[blist[p]] = dzb[p]
                break
            nc = 0
            art_tied = False
            for p in range(k):
                if dzb[p] < thr and zb[p] + dzb[p] * theta <= tie_abs:
                    cand[nc] = n + blist[p]
                    nc += 1
                    if blist[p] == n:
                        art_tied = True
            for i in range(n):
                if apos[i] < 0 and dw[i] < thr and wv[i] + dw[i] * theta <= tie_abs:
                    cand[nc] = i
                    nc += 1
            if art_tied:
                leaving = art
            elif nc == 1:
                leaving = cand[0]
            else:
                leaving = lex_choice(A, n, alist, blist, k, G, apos, bpos, cand, nc, vals,
                                     z_start, dzb, dw, lz, lw, pivot_tol)
        # --- exchange ------------------------------------------------------------------
        ok = exchange(A, n, entering, leaving, alist, blist, apos, bpos, k, G, dzb, dw, row)
        if entering >= n and leaving < n:
            k += 1  # the block gained a row and a column
        elif entering < n and leaving >= n:
            k -= 1  # the block lost a row and a column
        pivots += 1
        since_refactor += 1
        if not ok or since_refactor >= REFACTOR_EVERY:
            since_refactor = 0
            if not invert(A, alist, blist, k, G, W):
                status = NUMERICAL_FAILURE
                break
        if basic_point(A, q, alist, blist, k, G, apos, zb, wv, tmp) > 1e-9:
            since_refactor = 0
            if not invert(A, alist, blist, k, G, W):
                status = NUMERICAL_FAILURE
                break
            basic_point(A, q, alist, blist, k, G, apos, zb, wv, tmp)
        if leaving == art:
            status = SOLVED
            break
        entering = leaving + n if leaving < n else leaving - n
    for p in range(k):
        x_out[blist[p]] = zb[p]
    for i in range(n):
        z_basic_out[i] = bpos[i] >= 0
    return status, pivots


@kernel
def lex_choice(A, n, alist, blist, k, G, apos, bpos, cand, nc, vals, z_start, dzb, dw, lz, lw,
               pivot_tol):
    """Break a ratio tie by the lexicographic rule (columns of the basis inverse relative
    to the starting basis, whose row j holds z_j if z_start[j] else w_j)."""
    for j in range(n):
        lab = n + j if z_start[j] else j
        basic = bpos[j] >= 0 if z_start[j] else apos[j] < 0
        if not basic:
            direction(A, lab, n, alist, blist, k, G, apos, lz, lw)
        vmin = np.inf
        vabs = 0.0
        for c in range(nc):
            cl = cand[c]
            if basic:
                b = 1.0 if cl == lab else 0.0
            else:
                b = -(lz[bpos[cl - n]] if cl >= n else lw[cl])
                if abs(b) <= pivot_tol:
                    b = 0.0
            piv = dzb[bpos[cl - n]] if cl >= n else dw[cl]
            v = b / -piv
            vals[c] = v
            vmin = min(vmin, v)
            vabs = max(vabs, abs(v))
        lim = vmin + pivot_tol * vabs
        kk = 0
        for c in range(nc):
            if vals[c] <= lim:
                cand[kk] = cand[c]
                kk += 1
        nc = kk
        if nc == 1:
            return cand[0]
    best = cand[0]
    bestp = 0.0
    for c in range(nc):
        cl = cand[c]
        piv = abs(dzb[bpos[cl - n]] if cl >= n else dw[cl])
        if piv > bestp:
            bestp = piv
            best = cl
    return best


@kernel
def exchange(A, n, entering, leaving, alist, blist, apos, bpos, k, G, dzb, dw, row):
    """Update the index sets and G = H^-1 for ``entering`` replacing ``leaving``.
    Returns False when the update's pivot is too small to trust (then refactor)."""
    if entering >= n and leaving < n:
        # z_e enters, w_i leaves: H gains row i and column e (bordering).
        e = entering - n
        i = leaving
        s = dw[i]  # = A[i,e] + A[i,beta] dz_beta, the Schur complement
        for c in range(k):  # row = A[i, beta] G
            acc = 0.0
            for p in range(k):
                acc += A[i, blist[p]] * G[p, c]
            row[c] = acc
        for p in range(k):  # u = G A[alpha, e] = -dzb
            f = -dzb[p] / s
            for c in range(k):
                G[p, c] += f * row[c]
            G[p, k] = -(-dzb[p]) / s
        for c in range(k):
            G[k, c] = -row[c] / s
        G[k, k] = 1.0 / s
        alist[k] = i
        apos[i] = k
        blist[k] = e
        bpos[e] = k
        return abs(s) > 1e-13
    if entering >= n:
        # z_e replaces z_l in H's columns (Sherman-Morrison on column p).
        e = entering - n
        l = leaving - n
        p = bpos[l]
        piv = -dzb[p]  # = (G A[alpha, e])[p]
        for c in range(k):
            row[c] = G[p, c] / piv
        for r in range(k):
            u = -dzb[r] - (1.0 if r == p else 0.0)
            if u != 0.0:
                for c in range(k):
                    G[r, c] -= u * row[c]
        blist[p] = e
        bpos[l] = -1
        bpos[e] = p
        return abs(piv) > 1e-13
    if leaving < n:
        # w_j enters (leaves alpha), w_i leaves (joins alpha): row p of H becomes A[i, beta].
        j = entering
        i = leaving
        p = apos[j]
        for c in range(k):  # row = A[i, beta] G
            acc = 0.0
            for r in range(k):
                acc += A[i, blist[r]] * G[r, c]
            row[c] = acc
        piv = row[p]  # = A[i, beta] G[:, p] = dw[i]
        row[p] -= 1.0
        for r in range(k):
            f = dzb[r] / piv  # G[:, p] / piv
            if f != 0.0:
                for c in range(k):
                    G[r, c] -= f * row[c]
        alist[p] = i
        apos[j] = -1
        apos[i] = p
        return abs(piv) > 1e-13
    # w_j enters, z_l leaves: H loses row p (w_j) and column m (z_l).
    j = entering
    l = leaving - n
    p = apos[j]
    m = bpos[l]
    piv = G[m, p]
    for r in range(k):
        if r != m:
            f = G[r, p] / piv
            if f != 0.0:
                for c in range(k):
                    G[r, c] -= f * G[m, c]
    last = k - 1
    for c in range(k):  # move the last row of G into row m
        G[m, c] = G[last, c]
    for r in range(last):  # and the last column into column p
        G[r, p] = G[r, last]
    bl = blist[last]
    blist[m] = bl
    bpos[bl] = m
    bpos[l] = -1
    al = alist[last]
    alist[p] = al
    apos[al] = p
    apos[j] = -1
    return abs(piv) > 1e-13
