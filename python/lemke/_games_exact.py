"""Exact arithmetic for bimatrix games: payoffs as integers, the support system solved
without rounding, the exact regret, and Lemke-Howson by integer pivoting (:class:`Tableau`),
from the artificial equilibrium or continued from the state where a floating-point path
stopped (:func:`continuation`).

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


class Tableau:
    """One best-response polytope in integer arithmetic: ``D`` is ``det`` times the tableau
    ``B^-1 [M | I | 1]`` of the current basis (integer pivoting: every entry is a minor, and
    a pivot divides exactly by the previous pivot), ``det > 0`` once :meth:`place` is done.
    ``basis[r]`` is the label basic in row r; ``column(label)`` its column in D; the identity
    columns (``slack`` onwards) are those of the slack basis, so ``D[:, slack:-1]`` is
    ``det`` times the basis inverse in the order of the lexicographic rule."""

    def __init__(self, payT, first, L):
        rows, cols = payT.shape
        self.D = np.concatenate([payT, np.eye(rows, dtype=np.int64).astype(object),
                                 np.ones((rows, 1), dtype=object)], axis=1)
        self.det = 1
        self.first = first  # the label of column 0 (x_0 in P, y_0 in Q)
        self.L = L
        self.slack = cols
        self.basis = [(first + cols + r) % L for r in range(rows)]

    def column(self, label):
        return (label - self.first) % self.L

    def pivot(self, r, s):
        """The variable of column s replaces row r's; returns the label that left."""
        D = self.D
        p = D[r, s]
        row = D[r].copy()
        D = (D * p - np.outer(D[:, s], row)) // self.det
        D[r] = row
        self.D, self.det = D, p
        leaving = self.basis[r]
        self.basis[r] = (self.first + s) % self.L
        return leaving

    def place(self, labels) -> bool:
        """Pivot until ``labels`` are the basic ones (False if that basis is singular),
        then make ``det`` positive."""
        want = set(labels)
        for lab in labels:
            if lab in self.basis:
                continue
            s = self.column(lab)
            rows = [i for i, b in enumerate(self.basis) if b not in want and self.D[i, s] != 0]
            if not rows:
                return False
            self.pivot(rows[0], s)
        if self.det < 0:
            self.D, self.det = -self.D, -self.det
        return True

    def lex_feasible(self) -> bool:
        """Every row of ``[rhs | basis inverse]`` lexicographically positive: the basis is
        a vertex of the lexicographically perturbed polytope (so the rule keeps it one)."""
        for i in range(self.D.shape[0]):
            for c in [-1, *range(self.slack, self.D.shape[1] - 1)]:
                v = self.D[i, c]
                if v != 0:
                    if v < 0:
                        return False
                    break
        return True

    def leaving_row(self, s):
        """The lexicographic minimum ratio test for column s (all candidates ``D[i, s] >
        0``): the right-hand side, then the basis inverse's columns in slack order."""
        D = self.D
        rows = [i for i in range(D.shape[0]) if D[i, s] > 0]
        for c in [-1, *range(self.slack, D.shape[1] - 1)]:
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
            if len(rows) <= 1:
                break
        return rows[0] if rows else -1

    def strategy(self, labels):
        """``(support, numerators, denominator)`` of the basic ``labels`` (in order),
        normalized to sum 1; the denominator is 0 when they are all 0."""
        num = [self.D[self.basis.index(lab), -1] for lab in labels]
        return _normalized(num)


def tableaux(Aint, Bint):
    """P (rows s_j, columns [x | s | rhs]) and Q (rows r_i, columns [y | r | rhs]) at the
    artificial equilibrium, on payoffs made positive (an integer shift)."""
    m, n = Aint.shape
    Ap = Aint - min(Aint.ravel()) + 1
    Bp = Bint - min(Bint.ravel()) + 1
    return Tableau(Bp.T, 0, m + n), Tableau(Ap, m, m + n)


class Path:
    """How an exact Lemke-Howson run ended: ``status`` is ``"solved"`` (every label present
    at a vertex pair other than the artificial one; xs, ys its strategies, ``labels`` the
    basic labels of P and of Q), ``"artificial"`` (it ended at the artificial equilibrium: a
    continuation that ran backward), ``"cycle"`` (it came back to its start: a start on a
    cycle of the graph), ``"max_pivots"``, or ``"infeasible"`` (the start basis is singular
    or not lexicographically feasible in exact arithmetic; no pivot made)."""

    def __init__(self, status, pivots, xs=None, ys=None, labels=None):
        self.status, self.pivots, self.xs, self.ys, self.labels = status, pivots, xs, ys, labels


def lemke_howson(Aint, Bint, k, max_pivots, start=None) -> Path:
    """Lemke-Howson dropping label k in integer arithmetic with the lexicographic rule
    relative to the slack basis (the rule of the float kernels), from the artificial
    equilibrium, or with ``start = (P labels, Q labels, entering, side)`` from that vertex
    pair, where the label ``entering`` is about to enter in tableau ``side`` (0: P, 1: Q):
    the state a float path reports (``_core.lemke_howson``, src/lemke/games.cpp).  Such a start must be a
    vertex pair of the perturbed polytopes (non-singular, lexicographically feasible, which
    is checked: else ``"infeasible"``) whose label ``entering`` is non-basic in ``side``."""
    m, n = Aint.shape
    P, Q = tableaux(Aint, Bint)
    if start is None:
        return _run(P, Q, k, k, 0 if k < m else 1, max_pivots, m, False)
    labP, labQ, entering, side = start
    if not (P.place(list(labP)) and Q.place(list(labQ))):
        return Path("infeasible", 0)
    return _run(P, Q, k, entering, side, max_pivots, m, True)


def _run(P, Q, k, entering, side, max_pivots, m, check_start):
    """The path from the state (P, Q, ``entering`` about to enter in ``side``); with
    ``check_start``, the state is first checked to be a vertex pair of the perturbed
    polytopes, and a return to it is reported as a cycle."""
    sides = (P, Q)
    if check_start:
        if not (almost_complementary(P, Q, k, entering) and P.lex_feasible() and Q.lex_feasible()):
            return Path("infeasible", 0)
        begin = (frozenset(P.basis), frozenset(Q.basis))
    pivots = 0
    while True:
        if pivots >= max_pivots:
            return Path("max_pivots", pivots)
        t = sides[side]
        s = t.column(entering)
        r = t.leaving_row(s)
        if r < 0:  # impossible from a vertex pair (the polytopes are bounded)
            return Path("infeasible", pivots)
        leaving = t.pivot(r, s)
        pivots += 1
        entering, side = leaving, 1 - side
        if leaving == k:
            break
        if check_start and (frozenset(P.basis), frozenset(Q.basis)) == begin:
            return Path("cycle", pivots)
    S = [lab for lab in P.basis if lab < m]
    if not S:
        return Path("artificial", pivots)
    T = [lab for lab in Q.basis if lab >= m]
    return Path("solved", pivots, (S, *P.strategy(S)), ([lab - m for lab in T], *Q.strategy(T)),
                (tuple(sorted(P.basis)), tuple(sorted(Q.basis))))


def almost_complementary(P, Q, k, entering) -> bool:
    """Is (P, Q) a state of a path dropping k with ``entering`` next: k basic in both
    tableaux, ``entering`` in neither, every other label in exactly one?"""
    basic = [0] * P.L
    for lab in P.basis + Q.basis:
        basic[lab] += 1
    return all(b == (2 if lab == k else 0 if lab == entering else 1)
               for lab, b in enumerate(basic))


def continuation(Aint, Bint, k, labP, labQ, side, left, max_pivots):
    """Exact Lemke-Howson from where a float path stopped: the vertex pair ``(labP, labQ)``
    with the label ``left[-1]`` about to enter in ``side``, or, when that state is not a
    vertex pair in exact arithmetic (or is the path's end, ``left[-1] == k``, whose basis
    failed the exact check), from the latest earlier state that is, found by undoing the
    float path's pivots one by one (exactly, on the tableaux of the final basis).
    ``left``: the labels that left the path's last pivots, oldest first, preceded by k
    when they go back to the path's start (the label that left a pivot entered in the
    next, the first entering label being k).  Returns ``(Path, pivots undone)``; the Path is
    ``"infeasible"`` when no state in reach is a vertex pair."""
    m = Aint.shape[0]
    P, Q = tableaux(Aint, Bint)
    if not (P.place(list(labP)) and Q.place(list(labQ))):
        return Path("infeasible", 0), 0
    sides = (P, Q)
    left = list(left)
    walked = 0
    while True:
        entering = left[-1]
        if (entering != k and almost_complementary(P, Q, k, entering) and P.lex_feasible()
                and Q.lex_feasible()):
            return _run(P, Q, k, entering, side, max_pivots, m, True), walked
        if len(left) < 2:
            return Path("infeasible", 0), walked
        # Undo the last pivot: it was made in the other tableau, where ``entering`` left and
        # the label before it entered.
        gone = left.pop()
        side = 1 - side
        t = sides[side]
        came = left[-1]
        if gone in t.basis or came not in t.basis:
            return Path("infeasible", 0), walked  # not the state of a path
        s, r = t.column(gone), t.basis.index(came)
        if t.D[r, s] == 0:
            return Path("infeasible", 0), walked
        t.pivot(r, s)
        if t.det < 0:
            t.D, t.det = -t.D, -t.det
        walked += 1


def _normalized(num):
    """Numerators over a common denominator summing to 1 (they share one det already)."""
    total = sum(int(v) for v in num)
    return np.array([int(v) for v in num], dtype=object), total
