"""Diagnosis of Lemke runs that lose accuracy (issue 11, the contact piles): not a test.

``reference_lemke(M, q)`` runs Lemke's method (d = 1, lexicographic rule, the kernels'
equilibration) with the basis re-solved by LU at every pivot, so each basis has the accuracy
of its own condition; it returns the status, pivots, final basis, z and per pivot the
condition number of the basis.  ``replay(M, q, pivots)`` takes a kernel's pivot sequence
(``(leaving, entering)`` labels) and prints, per pivot, the condition of the basis and
whether the kernel's leaving row is a minimum ratio row of the accurate values.

Measured with them on the pile scene (seed 0, 20 bodies, steps 26-31): the reference run
solves every step in 86-124 pivots (bases of condition up to 1e9); the kernels' first runs
leave the accurate path after a pivot on an entry of 1e-7 (a basis of condition 1e9), then
pivot on entries that are 1e-16 in exact arithmetic (bases of condition 1e16-1e18).
Labels: 0..n-1 for w, n..2n-1 for z, 2n for z0.
"""
import numpy as np
import scipy.linalg as sl

from lemke import _core


def _system(M, q):
    n = q.size
    R, C = np.empty(n), np.empty(n)
    _core.equilibrate(np.ascontiguousarray(M, float), np.ascontiguousarray(q, float), R, C)
    A = R[:, None] * M * C[None, :]
    ds = R / R.max()
    return np.hstack([np.eye(n), -A, -ds[:, None]]), R * q, C


def reference_lemke(M, q, tie=1e-11, ptol=1e-13, max_pivots=5000):
    """``(status, pivots, basis, z, conds)``: Lemke with an LU solve per pivot."""
    n = q.size
    full, qs, C = _system(M, q)
    basis = list(range(n))
    need = qs / full[:, 2 * n]  # z0 needed per row: -q_i / d_i (the column is -d)
    top = need.max()
    r = max(i for i in range(n) if need[i] >= top - tie * abs(top))
    leaving, basis[r] = basis[r], 2 * n
    entering = leaving + n
    conds = []
    for p in range(max_pivots):
        B = full[:, basis]
        lu = sl.lu_factor(B)
        xb, col = sl.lu_solve(lu, qs), sl.lu_solve(lu, full[:, entering])
        conds.append(np.linalg.cond(B))
        blk = np.flatnonzero(col > ptol * np.abs(col).max())
        if blk.size == 0:
            return "ray", p, basis, None, conds
        rat = np.maximum(xb[blk], 0.0) / col[blk]
        cand = blk[rat <= rat.min() * (1 + tie)]
        art = basis.index(2 * n)
        if art in cand:
            r = art
        else:
            Binv = sl.lu_solve(lu, np.eye(n))
            for j in range(n):
                if cand.size == 1:
                    break
                keys = Binv[cand, j] / col[cand]
                cand = cand[keys <= keys.min() + tie * np.maximum(abs(keys), abs(keys.min()))]
            r = cand[np.argmax(col[cand])]
        leaving, basis[r] = basis[r], entering
        if leaving == 2 * n:
            xb = np.linalg.solve(full[:, basis], qs)
            z = np.zeros(n)
            for i, lab in enumerate(basis):
                if n <= lab < 2 * n:
                    z[lab - n] = xb[i]
            return "solved", p + 1, basis, np.maximum(z, 0.0) * C, conds
        entering = leaving + n if leaving < n else leaving - n
    return "cap", max_pivots, basis, None, conds


def replay(M, q, pivots, tie=1e-11):
    """Print, per pivot of a kernel's sequence, the basis condition and whether the leaving
    row is a minimum ratio row of the accurate (LU) values."""
    n = q.size
    full, qs, _ = _system(M, q)
    basis = list(range(n))
    for p, (leaving, entering) in enumerate(pivots):
        B = full[:, basis]
        lu = sl.lu_factor(B)
        xb, col = sl.lu_solve(lu, qs), sl.lu_solve(lu, full[:, entering])
        r = basis.index(leaving)
        if p > 0:
            blk = np.flatnonzero(col > 1e-13 * np.abs(col).max())
            rat = np.maximum(xb[blk], 0.0) / col[blk]
            ok = r in blk and rat[list(blk).index(r)] <= rat.min() * (1 + tie)
            print(f"{p:4d} cond {np.linalg.cond(B):9.3g} pivot {col[r]:10.3g} value {xb[r]:10.3g}"
                  f"{'' if ok else '  <-- not a minimum ratio row'}")
        basis[r] = entering
