r"""solve_mlcp: the mixed LCP, reduced to an LCP by exchange pivots, then Lemke's method.

The mixed LCP in Siconos' form (its "storage 2"): find u (free, n of them) and v (m of them)
with

    A u + C v + a = 0,      w = D u + B v + b,      0 <= v ⊥ w >= 0.

Stacked, ``E x + e = (0, w)`` with ``x = (u, v)``, ``E = [[A, C], [D, B]]`` and
``e = (a, b)``.  The steps:

1. equilibrate E (row and column scaling; a pair's row and column get the same factor, which
   keeps v ⊥ w);
2. exchange pivots make every u basic and every equation's slack non-basic (kernels.mlcp):
   the free variables enter and stay basic, never split into two signs;
3. what is left is an LCP in the m pairs (some swapped: v_k basic, w_k the LCP's variable),
   solved by :func:`lemke.solve_lcp`;
4. the answer is recomputed from the final basis on the caller's data (one dense solve with
   a step of refinement) and checked there before it is called solved.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from . import _validate
from ._certify import absmax as _size, check_mlcp, is_mlcp_ray
from ._lcp import METHODS, solve_lcp
from ._options import as_options
from ._result import Outcome, WarmStart
from ._status import Status
from .kernels import mlcp as kmlcp

RANK_TOL = 1e-9  # an exchange pivot must exceed this on the equilibrated data
MAX_RESTARTS = 3  # restarts from a final basis that misses on the caller's data
LARGE_PIVOT_TOL = 1e-7  # the pivot tolerance of the last try after numerical failures
EPS = float(np.finfo(np.float64).eps)
CLEAN = 64 * np.finfo(np.float64).eps  # a residual above CLEAN * scale gets one strict restart


@dataclass(frozen=True)
class MLCPResult(Outcome):
    """The outcome of :func:`lemke.solve_mlcp`.

    Attributes
    ----------
    u, v, w : ndarray
        The free variables, the complementary variables and ``w = D u + B v + b`` recomputed
        from the caller's data.
    status : Status
        ``SOLVED`` only after the check on the caller's data.  ``PRIMAL_INFEASIBLE`` when
        the equations contradict each other whatever v is (a combination of them reads
        0 = c with c != 0); ``RAY_TERMINATION`` when Lemke's method ends on a ray of the
        reduced LCP (for a monotone E this proves there is no solution).
    pivots : int
        Lemke pivots on the reduced LCP (the exchanges that make u basic are not counted).
    residual : float
        ``max(max|A u + C v + a|, max_k |min(v_k, w_k)|)`` on the caller's data.
    ray : ndarray or None
        On ``RAY_TERMINATION``, when it is one: a direction ``(du, dv)`` (length n + m) with
        ``A du + C dv = 0``, ``dv >= 0``, ``dw = D du + B dv >= 0`` and ``dv ⊥ dw``, checked
        on the caller's data.
    warm_start : WarmStart or None
        The final basis as the set of basic v's (``z_basic`` lists the k with v_k basic);
        pass it back to :func:`solve_mlcp` for a nearby problem of the same sizes.
    """

    u: np.ndarray
    v: np.ndarray
    w: np.ndarray
    status: Status
    pivots: int
    residual: float
    ray: np.ndarray | None
    warm_start: WarmStart | None

    def __repr__(self) -> str:
        return (
            f"MLCPResult(status={self.status.name}, pivots={self.pivots}, "
            f"residual={self.residual:.3g}, n={self.u.size}, m={self.v.size})"
        )


def solve_mlcp(A, B, C, D, a, b, *, method="tableau", warm_start=None, options=None) -> MLCPResult:
    r"""Solve the mixed linear complementarity problem

    .. math::  A u + C v + a = 0, \quad w = D u + B v + b, \quad 0 \le v \perp w \ge 0

    with u free (n of them) and v, w paired (m of them): Siconos' standard form.

    Parameters
    ----------
    A : (n, n) array_like      B : (m, m) array_like
    C : (n, m) array_like      D : (m, n) array_like
    a : (n,) array_like        b : (m,) array_like
        Dense or scipy.sparse; n = 0 (a plain LCP), m = 0 (linear equations) and both (an
        empty problem: SOLVED with empty u, v, w) are allowed; ``[]`` is an empty block.
    method : {"tableau", "unrevised"}
        The Lemke method for the reduced LCP (see :func:`lemke.solve_lcp`).
    warm_start : WarmStart, optional
        ``result.warm_start`` of an earlier solve with the same n and m.
    options : Options or dict, optional
        See :class:`lemke.Options`; ``tol`` is the acceptance test on the stacked system
        ``E x + e`` (E = [[A, C], [D, B]]) with the LCP rule of ``Options``.

    Returns
    -------
    MLCPResult

    Notes
    -----
    The free variables are made basic by exchange pivots (largest pivot first; where the
    block A is singular, as for the equality multipliers of a QP, a pair is swapped to make
    room) and then kept basic; the pairs left form an LCP solved by Lemke's method.  On a
    monotone problem (E + E' positive semidefinite, e.g. the KKT system of a convex QP) the
    reduced LCP is monotone too, so Lemke's method solves it or proves it infeasible.

    Examples
    --------
    >>> import lemke
    >>> r = lemke.solve_mlcp([[1.0]], [[2.0]], [[-1.0]], [[1.0]], [-1.0], [-3.0])
    >>> r.status.name, r.u.round(6).tolist(), r.v.round(6).tolist()
    ('SOLVED', [1.666667], [0.666667])
    """
    _validate.method(method, METHODS)
    E, e, n = _as_mlcp(A, B, C, D, a, b)
    m = e.size - n
    _validate.warm_start(warm_start, WarmStart, m, "warm_start is for {ws} pairs, this problem has m = {n}")
    return solve_stacked(E, e, n, method, as_options(options), warm_start)


def _as_mlcp(A, B, C, D, a, b):
    """Validate the six blocks; returns the stacked ``(E, e, n)``."""
    blocks = _validate.mlcp(A, B, C, D, a, b)
    a, b = blocks["a"], blocks["b"]
    n, m = a.size, b.size
    E = np.empty((n + m, n + m))
    E[:n, :n] = blocks["A"]
    E[:n, n:] = blocks["C"]
    E[n:, :n] = blocks["D"]
    E[n:, n:] = blocks["B"]
    return E, np.concatenate([a, b]), n


def _equilibrate(E, n, iterations=10):
    """Scaling vectors ``(r, s)`` that bring every row and column of ``r E s`` near size 1
    (Ruiz's method): free rows and columns get their own factors, and a pair's row and
    column the same one, so that v ⊥ w is kept."""
    N = E.shape[0]
    r = np.ones(N)
    s = np.ones(N)
    if N == 0:  # an empty system: nothing to scale (and max over no entries is undefined)
        return r, s
    absE = np.abs(E)
    for _ in range(iterations):
        S = absE * r[:, None] * s[None, :]
        rows = S.max(axis=1)
        cols = S.max(axis=0)
        rows[rows == 0.0] = 1.0
        cols[cols == 0.0] = 1.0
        r[:n] /= np.sqrt(rows[:n])
        s[:n] /= np.sqrt(cols[:n])
        f = 1.0 / np.sqrt(np.maximum(rows[n:], cols[n:]))
        r[n:] *= f
        s[n:] *= f
        if np.all(np.abs(rows - 1.0) < 0.1) and np.all(np.abs(cols - 1.0) < 0.1):
            break
    return r, s


class _Reduction:
    """The exchanges that make every free variable basic, and the LCP that is left."""

    def __init__(self, E, e, n):
        N = e.size
        self.n, self.N, self.m = n, N, N - n
        self.r, self.s = _equilibrate(E, n)
        T = np.empty((N, N + 1))
        np.multiply(E, self.r[:, None] * self.s[None, :], out=T[:, :N])
        T[:, N] = e * self.r
        self.row_label = np.empty(N, dtype=np.int64)
        self.col_label = np.empty(N, dtype=np.int64)
        self.code, self.bad_row = kmlcp.reduce(
            T, n, RANK_TOL, _size(T[:, N]), self.row_label, self.col_label
        )
        self.T = T
        if self.code != kmlcp.OK:
            return
        # Constants that cancel to zero in exact arithmetic come out at rounding level: a
        # -1e-16 would make Lemke's method start where the exchanged point already solves
        # the problem.  The data is equilibrated, so the exchanges' rounding is below
        # N eps max|T|.
        const = T[:, N]
        const[np.abs(const) < N * EPS * _size(e * self.r)] = 0.0
        # Pair k: output label n + k (w_k), input label N + n + k (v_k).  Where is each?
        where_row = np.full(2 * N, -1)
        where_row[self.row_label] = np.arange(N)
        where_col = np.full(2 * N, -1)
        where_col[self.col_label] = np.arange(N)
        k = np.arange(self.m)
        w_row, v_row = where_row[n + k], where_row[N + n + k]
        self.swapped = v_row >= 0  # v_k basic (in the row), w_k the LCP variable (column)
        self.posr = np.where(self.swapped, v_row, w_row)
        self.posc = np.where(self.swapped, where_col[n + k], where_col[N + n + k])
        self.M = np.ascontiguousarray(T[np.ix_(self.posr, self.posc)])
        self.q = T[self.posr, N].copy()
        # The same for the matrix, as a second try (see solve_stacked): left in, noise can be
        # pivoted on (a column of pure noise passes any test relative to its own size), but
        # zeroing it changes the tie-breaking of degenerate paths, so it is not the first try.
        self.M_clean = np.where(np.abs(self.M) < N * EPS * max(1.0, _size(T[:, :N])), 0.0, self.M)
        # Rows where a free variable is basic, and what stayed behind (redundant pairs).
        self.free_rows = np.flatnonzero((self.row_label >= N) & (self.row_label < N + n))
        self.redundant = np.sort(self.row_label[self.row_label < n])  # equations left out
        undetermined = self.col_label[(self.col_label >= N) & (self.col_label < N + n)] - N
        self.undetermined = np.sort(undetermined)  # free variables set to 0

    def to_reduced(self, v_basic: np.ndarray) -> np.ndarray:
        """Which LCP z's are basic, for the basis where v_k is basic when v_basic[k]."""
        return v_basic ^ self.swapped

    def v_basic(self, z_basic: np.ndarray) -> np.ndarray:
        return z_basic ^ self.swapped

    def point(self, z, z_dir=False):
        """The stacked x = (u, v) of the MLCP from the reduced LCP's z (a direction when
        z_dir: no constant term), in the caller's units."""
        N, n = self.N, self.n
        col = np.zeros(N)
        col[self.posc] = z
        basic = self.T[:, self.posc] @ z
        if not z_dir:
            basic += self.T[:, N]
        xs = np.zeros(N)
        for labels, values in ((self.row_label, basic), (self.col_label, col)):
            inputs = labels >= N
            xs[labels[inputs] - N] = values[inputs]
        return xs * self.s


def solve_stacked(E, e, n, method, opts, warm_start=None) -> MLCPResult:
    """solve_mlcp on the stacked, validated data (also the engine of solve_qp)."""
    N = e.size
    m = N - n
    red = _Reduction(E, e, n)
    if red.code != kmlcp.OK:
        x = np.zeros(N)
        w, _, residual = check_mlcp(E, e, n, x, opts.tol)
        status = Status.PRIMAL_INFEASIBLE if red.code == kmlcp.INCONSISTENT else Status.NUMERICAL_FAILURE
        return _result(x, w, n, status, 0, residual, None, None)

    lcp_ws = None
    if warm_start is not None:
        vb = np.zeros(m, dtype=bool)
        vb[list(warm_start.z_basic)] = True
        lcp_ws = WarmStart._trusted(m, tuple(np.flatnonzero(red.to_reduced(vb)).tolist()))
    # A long pivot sequence on badly scaled data can end one degenerate decision off: the
    # final basis, recomputed from the caller's data, then misses by a little.  Lemke's
    # method restarted from that basis (solve_lcp's warm start: fresh factorization, a few
    # pivots) corrects it.  If it still fails, it is run again on the reduced matrix with
    # its rounding noise zeroed, then with a larger pivot tolerance (a pivot on an entry at
    # rounding level makes garbage of everything after it).
    pivots = 0
    tries = [(red.M, opts), (red.M_clean, opts)]
    if opts.pivot_tol < LARGE_PIVOT_TOL:
        tries.append((red.M, replace(opts, pivot_tol=LARGE_PIVOT_TOL)))
    outcomes = []
    for M, o in tries:
        res = solve_lcp(M, red.q, method=method, warm_start=lcp_ws, options=o)
        pivots += res.pivots
        out = _evaluate(E, e, n, red, res, opts.tol)
        for _ in range(MAX_RESTARTS):
            if out[2] or res.status not in (Status.SOLVED, Status.NUMERICAL_FAILURE):
                break
            res = solve_lcp(M, red.q, method=method, warm_start=res.warm_start, options=o)
            pivots += res.pivots
            out = _evaluate(E, e, n, red, res, opts.tol)
        outcomes.append((M, o, res, out))
        if out[2] or res.status == Status.MAX_PIVOTS:
            break
        lcp_ws = None
    # The first solved try; else the first ray (for its certificate); else the first try.
    M, o, res, (x, w, ok, residual, basis) = next(
        (t for t in outcomes if t[3][2]),
        next((t for t in outcomes if t[2].status == Status.RAY_TERMINATION), outcomes[0]),
    )
    if ok and res.status not in (Status.SOLVED, Status.NUMERICAL_FAILURE):
        # The exchanged point already solves it; rounding in a constant that should be
        # zero made the reduced LCP look unsolved (a ray at once).
        return _result(x, w, n, Status.SOLVED, pivots, residual, None, basis)
    if res.status in (Status.SOLVED, Status.NUMERICAL_FAILURE):
        # Accepted, but not exact to rounding: on a degenerate problem a basic variable
        # that should be zero can come out slightly negative at the accepted basis.  One
        # restart with a much stricter acceptance test moves to the exact basis nearby.
        if ok and residual > CLEAN * max(_size(e), _size(E) * _size(x)):
            res2 = solve_lcp(M, red.q, method=method, warm_start=res.warm_start,
                             options=replace(o, tol=opts.tol * 1e-3))
            out = _evaluate(E, e, n, red, res2, opts.tol)
            if out[2] and out[3] < residual:
                pivots += res2.pivots
                x, w, ok, residual, basis = out
        status = Status.SOLVED if ok else Status.NUMERICAL_FAILURE
        return _result(x, w, n, status, pivots, residual, None, basis)

    ray = None
    if res.status == Status.RAY_TERMINATION and abs(res.ray[m]) <= opts.tol * _size(res.ray):
        direction = red.point(res.ray[:m], z_dir=True)
        if is_mlcp_ray(E, n, direction, opts.tol):
            ray = direction
    return _result(x, w, n, res.status, pivots, residual, ray, basis)


def _evaluate(E, e, n, red, res, tol):
    """The MLCP point of a reduced LCP result, checked on the caller's data: the point the
    pivoting produced, or the point of its final basis recomputed from the caller's data
    (one dense solve, more accurate after many pivots), whichever passes with the smaller
    residual.  Returns ``(x, w, ok, residual, basis)``."""
    m = red.m
    z_basic = np.zeros(m, dtype=bool)
    z_basic[list(res.warm_start.z_basic)] = True
    v_basic = red.v_basic(z_basic)
    basis = WarmStart._trusted(m, tuple(np.flatnonzero(v_basic).tolist()))
    x = red.point(res.z)
    w, ok, residual = check_mlcp(E, e, n, x, tol)
    if res.status in (Status.SOLVED, Status.NUMERICAL_FAILURE):
        xb = _basis_point(E, e, n, v_basic, red)
        if xb is not None:
            wb, okb, rb = check_mlcp(E, e, n, xb, tol)
            if okb and (not ok or rb <= residual):
                x, w, ok, residual = xb, wb, okb, rb
    return x, w, ok, residual, basis


def _basis_point(E, e, n, v_basic, red):
    """The point of the basis (all determined u basic, v_k basic where v_basic[k]) from the
    caller's data: one dense solve and one step of iterative refinement.  None if singular."""
    N = e.size
    keep_eq = np.setdiff1d(np.arange(n), red.redundant)
    keep_u = np.setdiff1d(np.arange(n), red.undetermined)
    vb = n + np.flatnonzero(v_basic)
    rows = np.concatenate([keep_eq, vb])
    cols = np.concatenate([keep_u, vb])
    if rows.size != cols.size:
        return None
    x = np.zeros(N)
    if rows.size:
        xb = _refined_solve(E[np.ix_(rows, cols)], -e[rows])
        if xb is None:
            return None
        x[cols] = xb
    x[n:] = np.maximum(x[n:], 0.0)
    return x


def _refined_solve(K, rhs, steps=2):
    """Solve K x = rhs with iterative refinement whose residuals are computed in extended
    precision (numpy's longdouble): on a degenerate basis a variable that is zero comes
    out zero to the last digits instead of at cond(K) eps.  None if K is singular.

    numpy's LAPACK only, never scipy's: the two carry separate OpenBLAS thread pools, and
    alternating between them on a busy machine made a 200 x 200 Cholesky take 0.4 s."""
    try:
        x = np.linalg.solve(K, rhs)
        K_ext = K.astype(np.longdouble)
        rhs_ext = rhs.astype(np.longdouble)
        for _ in range(steps):
            r = (rhs_ext - K_ext @ x.astype(np.longdouble)).astype(np.float64)
            x = x + np.linalg.solve(K, r)
    except np.linalg.LinAlgError:
        return None
    return x if np.isfinite(x).all() else None


def _result(x, w, n, status, pivots, residual, ray, basis):
    u, v = x[:n].copy(), x[n:].copy()
    for arr in (u, v, w) if ray is None else (u, v, w, ray):
        arr.setflags(write=False)
    return MLCPResult(u, v, w, status, int(pivots), float(residual), ray, basis)
