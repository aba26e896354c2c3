"""Exact arithmetic for bimatrix games: payoffs as integers, the support system solved
without rounding, the exact regret, and Lemke-Howson by integer pivoting.

Every float is a dyadic rational, so a payoff matrix is ``Aint * 2**e`` with ``Aint``
integers (:func:`dyadic`); scaling a player's payoffs by 2**-e changes no equilibrium, so
everything here works on Python integers (object arrays) and only the regret is scaled back.
Linear systems are solved by fraction-free Gauss-Jordan elimination (Bareiss): every
division is exact and the numbers stay as small as the determinants.  Strategies are kept
as ``(numerators, denominator)`` pairs and handed to the user as :class:`fractions.Fraction`.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np


def dyadic(A: np.ndarray) -> tuple[np.ndarray, int]:
    """``(Aint, e)`` with ``A == Aint * 2.0**e`` exactly, Aint an object array of ints."""
    if A.size == 0 or (np.all(A == np.rint(A)) and np.abs(A).max() < 2.0**53):
        return A.astype(np.int64).astype(object), 0
    mant, ex = np.frexp(A)  # A = mant * 2**ex with 0.5 <= |mant| < 1
    mi = (mant * 2.0**53).astype(np.int64)  # exact: 53 bits
    ee = ex.astype(np.int64) - 53
    nz = mi != 0
    emin = int(ee[nz].min()) if nz.any() else 0
    shift = np.where(nz, ee - emin, 0)
    return mi.astype(object) * (2 ** shift.astype(object)), emin


def solve_integer(M: np.ndarray, b: np.ndarray):
    """Solve ``M x = b`` (object arrays of ints, M square) by Bareiss' fraction-free
    elimination and back substitution; returns ``(numerators, denominator)`` with
    denominator > 0, or None if M is singular.

    Forward: after step c every entry below row c is a minor of M (exact divisions by the
    previous pivot), the last pivot is det(M).  Backward: X = det(M) x is an integer vector
    (Cramer's rule), and row i of the triangle gives ``U_ii X_i = det b'_i - sum_j>i U_ij X_j``
    with an exact division."""
    k = M.shape[0]
    D = np.concatenate([M, b.reshape(-1, 1)], axis=1).astype(object)
    prev = 1
    for c in range(k):
        nz = [i for i in range(c, k) if D[i, c] != 0]
        if not nz:
            return None
        r = nz[0]
        if r != c:
            D[[c, r]] = D[[r, c]]
        p = D[c, c]
        if c + 1 < k:
            below = D[c + 1 :, c:]
            D[c + 1 :, c:] = (below * p - np.outer(below[:, 0], D[c, c:])) // prev
        prev = p
    det = prev
    X = [0] * k
    for i in range(k - 1, -1, -1):
        t = det * D[i, k]
        for j in range(i + 1, k):
            t -= D[i, j] * X[j]
        X[i] = t // D[i, i]
    num = np.array(X, dtype=object)
    if det < 0:
        num, det = -num, -det
    return num, det


def support_strategy(P: np.ndarray, S, J):
    """The strategy with support S that makes the opponent (payoffs P, one column per
    opponent action... here rows of ``P.T``) indifferent among J: ``P[S, J]^T s = v 1``,
    ``sum s = 1``; returns ``(numerators over S, denominator)`` or None when singular."""
    k = len(S)
    M = np.zeros((k + 1, k + 1), dtype=object)
    M[:k, :k] = P[np.ix_(S, J)].T if k else M[:k, :k]
    M[:k, k] = -1
    M[k, :k] = 1
    M[k, k] = 0
    b = np.zeros(k + 1, dtype=object)
    b[k] = 1
    sol = solve_integer(M, b)
    if sol is None:
        return None
    num, den = sol
    return num[:k], den


def regret(AT, BS, ea, eb, xs, ys):
    """Exact ``(row regret, column regret, row payoff, column payoff)`` as Fractions of the
    profile ``xs = (support S, numerators, denominator)`` and ``ys = (T, ...)``, given only
    the payoffs they involve: ``AT = A[:, T] / 2**ea`` and ``BS = B[S, :] / 2**eb`` (ints)."""
    S, xn, dx = xs
    T, yn, dy = ys
    Ay = AT.dot(yn)  # (A y)_i times dy
    Bx = BS.T.dot(xn)  # (B'x)_j times dx
    pay_a = sum(int(a) * int(b) for a, b in zip(xn, Ay[S]))  # times dx dy
    pay_b = sum(int(a) * int(b) for a, b in zip(yn, Bx[T]))
    scale_a, scale_b = Fraction(2) ** ea, Fraction(2) ** eb
    ra = Fraction(int(max(Ay)) * dx - pay_a, dx * dy) * scale_a
    rb = Fraction(int(max(Bx)) * dy - pay_b, dx * dy) * scale_b
    return ra, rb, Fraction(pay_a, dx * dy) * scale_a, Fraction(pay_b, dx * dy) * scale_b


def certify_support(A, B, S, J, T, I):
    """Solve the support system of a vertex pair exactly and check it: x on S making the
    column actions J indifferent, y on T making the row actions I indifferent.  Converts
    only the payoffs involved (A[:, T] and B[S, :]) to integers.  Returns ``(xs, ys, ra, rb,
    pa, pb)`` (see :func:`regret`) or None when the system is singular or a strategy has a
    negative entry."""
    AT, ea = dyadic(np.ascontiguousarray(A[:, T]))
    BS, eb = dyadic(np.ascontiguousarray(B[S, :]))
    xs = support_strategy(BS, list(range(len(S))), J)
    ys = support_strategy(AT.T, list(range(len(T))), I)
    if xs is None or ys is None or min(xs[0]) < 0 or min(ys[0]) < 0:
        return None
    xs, ys = (S, *xs), (T, *ys)
    return (xs, ys, *regret(AT, BS, ea, eb, xs, ys))


def strategy(size, support, num, den) -> tuple[Fraction, ...]:
    out = [Fraction(0)] * size
    for i, v in zip(support, num):
        out[i] = Fraction(int(v), den)
    return tuple(out)


def lemke_howson(Aint, Bint, k, max_pivots):
    """Lemke-Howson dropping label k from the artificial equilibrium, in integer arithmetic
    (integer pivoting: each tableau row is ``det`` times its true row, and a pivot divides
    exactly by the previous pivot), with the lexicographic rule relative to the slack basis.
    Returns ``(xs, ys, pivots)`` with xs = (support, numerators, denominator), or None at the
    pivot cap."""
    m, n = Aint.shape
    Ap = Aint - min(Aint.ravel()) + 1  # positive payoffs
    Bp = Bint - min(Bint.ravel()) + 1
    # P: rows s_j, columns [x (m) | s (n) | rhs]; Q: rows r_i, columns [y (n) | r (m) | rhs].
    DP = np.concatenate([Bp.T, np.eye(n, dtype=np.int64).astype(object), np.ones((n, 1), dtype=object)], axis=1)
    DQ = np.concatenate([Ap, np.eye(m, dtype=np.int64).astype(object), np.ones((m, 1), dtype=object)], axis=1)
    sides = [
        {"D": DP, "det": 1, "basis": list(range(m, m + n)), "col": lambda lab: lab, "slack": m},
        {"D": DQ, "det": 1, "basis": list(range(m)), "col": lambda lab: lab - m if lab >= m else n + lab, "slack": n},
    ]
    side = 0 if k < m else 1
    entering = k
    pivots = 0
    while pivots < max_pivots:
        t = sides[side]
        D = t["D"]
        s = t["col"](entering)
        rows = [i for i in range(D.shape[0]) if D[i, s] > 0]
        # Lexicographic minimum of [rhs | slack columns] / D[i, s] (all D[i, s] > 0).
        keys = [-1] + list(range(t["slack"], t["slack"] + D.shape[0]))
        for c in keys:
            best = []
            for i in rows:
                if not best:
                    best = [i]
                    continue
                j = best[0]
                lhs, rhs = D[i, c] * D[j, s], D[j, c] * D[i, s]
                if lhs < rhs:
                    best = [i]
                elif lhs == rhs:
                    best.append(i)
            rows = best
            if len(rows) == 1:
                break
        r = rows[0]
        p = D[r, s]
        row = D[r].copy()
        D = (D * p - np.outer(D[:, s], row)) // t["det"]
        D[r] = row
        t["D"], t["det"] = D, p
        leaving = t["basis"][r]
        t["basis"][r] = entering
        pivots += 1
        if leaving == k:
            break
        entering = leaving
        side = 1 - side
    else:
        return None
    P, Q = sides
    S = [lab for lab in P["basis"] if lab < m]
    xn = [P["D"][P["basis"].index(lab), -1] for lab in S]
    T = [lab - m for lab in Q["basis"] if lab >= m]
    yn = [Q["D"][Q["basis"].index(lab + m), -1] for lab in T]
    return (S, *_normalized(xn)), (T, *_normalized(yn)), pivots


def _normalized(num):
    """Numerators over a common denominator summing to 1 (they share one det already)."""
    total = sum(int(v) for v in num)
    return np.array([int(v) for v in num], dtype=object), total
