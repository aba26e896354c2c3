r"""solve_mlcp: the mixed LCP, reduced to an LCP by exchange pivots, then Lemke's method.

The mixed LCP in Siconos' form (its "storage 2"): find u (free, n of them) and v (m of them)
with

    A u + C v + a = 0,      w = D u + B v + b,      0 <= v ⊥ w >= 0.

Stacked, ``E x + e = (0, w)`` with ``x = (u, v)``, ``E = [[A, C], [D, B]]`` and
``e = (a, b)``.  The steps:

1. the reduction ``_reductions.mlcp_lcp.MLCPToLCP`` equilibrates E and makes every free
   variable basic by exchange pivots; what is left is an LCP in the m pairs;
2. that LCP is solved by :func:`lemke.solve_lcp`, along the retry ladder ``LADDER``
   (each step restarted from its final basis while its point misses on the caller's data);
3. the answer is recomputed from the final basis on the caller's data (one dense solve with
   refinement) and checked there (``_certify.check_mlcp``) before it is called solved.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ._frozen import frozen
from . import _core, _progress, _validate
from ._certify import absmax as _size, check_mlcp, is_mlcp_ray
from ._ladder import Rung, always, climb
from ._lcp import METHODS, solve_lcp
from ._npc import nz
from ._options import as_options, time_limited, timed
from ._reductions.mlcp_lcp import MLCPToLCP
from ._result import Outcome, WarmStart
from ._status import STOPPED, Status

MAX_RESTARTS = 3  # restarts from a final basis that misses on the caller's data
LARGE_PIVOT_TOL = 1e-7  # the pivot tolerance of the last try after numerical failures
EPS = float(np.finfo(np.float64).eps)
CLEAN = 64 * np.finfo(np.float64).eps  # a residual above CLEAN * scale gets one strict restart


@frozen(eq=False)
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


def solve_mlcp(A, B, C, D, a, b, *, method="tableau", warm_start=None, options=None,
               progress=None) -> MLCPResult:
    r"""Solve the mixed linear complementarity problem

    .. math::  A u + C v + a = 0, \quad w = D u + B v + b, \quad 0 \le v \perp w \ge 0

    with u free (n of them) and v, w paired (m of them): Siconos' standard form.

    Parameters
    ----------
    A : (n, n) array_like      B : (m, m) array_like
    C : (n, m) array_like      D : (m, n) array_like
    a : (n,) array_like        b : (m,) array_like
        Dense or scipy.sparse (made dense, as in :func:`lemke.solve_lcp`); n = 0 (a plain LCP), m = 0 (linear equations) and both (an
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
    if progress is not None and progress is not False:
        return _progress.reported(_progress.check(progress), "solve_mlcp", solve_mlcp, A, B, C, D,
                                  a, b, method=method, warm_start=warm_start, options=options)
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_mlcp, A, B, C, D, a, b, method=method, warm_start=warm_start)
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


def solve_stacked(E, e, n, method, opts, warm_start=None) -> MLCPResult:
    """solve_mlcp on the stacked, validated data (also the engine of solve_qp)."""
    N = e.size
    m = N - n
    red = MLCPToLCP(E, e, n)
    if red.code != _core.MLCP_OK:
        x = np.zeros(N)
        w, _, residual = check_mlcp(E, e, n, x, opts.tol)
        status = Status.PRIMAL_INFEASIBLE if red.code == _core.MLCP_INCONSISTENT else Status.NUMERICAL_FAILURE
        return _result(x, w, n, status, 0, residual, None, None)

    lcp_ws = None
    if warm_start is not None:
        vb = np.zeros(m, dtype=bool)
        vb[list(warm_start.z_basic)] = True
        lcp_ws = WarmStart._trusted(m, tuple(nz(red.to_reduced(vb)).tolist()))
    outcomes = []  # (M, options, result, evaluation, pivots) of each rung run
    steps = list(_ladder(red, opts))

    def step(i, M, o):
        def run():
            # (a step with another after it ends its recovery runs at their first ray, which
            # _evaluate checks on the caller's data: solve_lcp's private _ray_stop, the
            # core's stop_at_ray; the last step tries them all; the warm start is the first
            # step's)
            res, out, p = _restarted(E, e, n, red, M, o, method, lcp_ws if i == 0 else None,
                                     opts.tol, i + 1 < len(steps))
            outcomes.append((M, o, res, out, p))
        return run

    def settled():  # a point that passes on the caller's data, or a cap or stop reached
        _, _, res, out, _ = outcomes[-1]
        return out[2] or res.status == Status.MAX_PIVOTS or res.status in STOPPED

    climb(settled, *(Rung(name, always, step(i, M, o)) for i, (name, M, o) in enumerate(steps)))
    pivots = sum(t[4] for t in outcomes)
    # The first solved try; else the first ray (for its certificate); else the first try.
    M, o, res, (x, w, ok, residual, basis), _ = next(
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


#: The retry ladder: the reduced LCP is solved by each step in turn until one gives a point
#: that passes on the caller's data.  A long pivot sequence on badly scaled data can end one
#: degenerate decision off; if restarting from the final basis (in ``_restarted``) does not
#: correct it, the LCP is solved again with its rounding noise zeroed (left in, noise can be
#: pivoted on: a column of pure noise passes any test relative to its own size; but zeroing
#: it changes the tie-breaking of degenerate paths, so it is not the first step), then with a
#: larger pivot tolerance (a pivot on an entry at rounding level makes garbage of everything
#: after it).  Each step: (name, the reduction's matrix to use, the pivot tolerance or None).
LADDER = (
    ("as reduced", "M", None),
    ("rounding noise zeroed", "M_clean", None),
    ("large pivot tolerance", "M", LARGE_PIVOT_TOL),
)


def _ladder(red, opts):
    """The steps of ``LADDER`` that apply: ``(name, M, options)``; the last one only when
    the caller's pivot tolerance is below it.  ``solve_stacked`` climbs them as rungs
    (``_ladder.climb``), each ``_restarted``; they apply by the options alone, so they are
    chosen here, before the climb (a step knows whether another comes after it)."""
    for name, matrix, pivot_tol in LADDER:
        if pivot_tol is not None and opts.pivot_tol >= pivot_tol:
            continue
        yield name, getattr(red, matrix), opts if pivot_tol is None else replace(opts, pivot_tol=pivot_tol)


def _restarted(E, e, n, red, M, o, method, lcp_ws, tol, ray_stop=False):
    """One step of the ladder: solve the reduced LCP (M, red.q), then restart Lemke's method
    from the final basis (solve_lcp's warm start: a fresh factorization, a few pivots) up to
    ``MAX_RESTARTS`` times while the point misses on the caller's data.  ``ray_stop``: every
    solve's recovery runs end at their first ray (solve_lcp's ``_ray_stop``).  Returns
    ``(result, evaluation, pivots)``."""
    res = out = None
    pivots = 0

    def solve(warm):  # a rung: solve_lcp from the basis warm() gives, its point evaluated
        def run():
            nonlocal res, out, pivots
            res = solve_lcp(M, red.q, method=method, warm_start=warm(), options=o,
                            _ray_stop=ray_stop)
            pivots += res.pivots
            out = _evaluate(E, e, n, red, res, tol)
        return run

    restart = solve(lambda: res.warm_start)
    climb(lambda: out[2] or res.status not in (Status.SOLVED, Status.NUMERICAL_FAILURE),
          Rung("the step's solve", always, solve(lambda: lcp_ws)),
          *(Rung("restart from the final basis", always, restart) for _ in range(MAX_RESTARTS)))
    return res, out, pivots


def _evaluate(E, e, n, red, res, tol):
    """The MLCP point of a reduced LCP result, checked on the caller's data: the point the
    pivoting produced, or the point of its final basis recomputed from the caller's data
    (one dense solve, more accurate after many pivots), whichever passes with the smaller
    residual.  Returns ``(x, w, ok, residual, basis)``."""
    m = red.m
    z_basic = np.zeros(m, dtype=bool)
    z_basic[list(res.warm_start.z_basic)] = True
    v_basic = red.v_basic(z_basic)
    basis = WarmStart._trusted(m, tuple(nz(v_basic).tolist()))
    x = red.point(res.z)
    w, ok, residual = check_mlcp(E, e, n, x, tol)
    if res.status in (Status.SOLVED, Status.NUMERICAL_FAILURE):
        xb = red.basis_point(E, e, v_basic)
        if xb is not None:
            wb, okb, rb = check_mlcp(E, e, n, xb, tol)
            if okb and (not ok or rb <= residual):
                x, w, ok, residual = xb, wb, okb, rb
    return x, w, ok, residual, basis


def _result(x, w, n, status, pivots, residual, ray, basis):
    u, v = x[:n].copy(), x[n:].copy()
    for arr in (u, v, w) if ray is None else (u, v, w, ray):
        arr.setflags(write=False)
    return MLCPResult(u, v, w, status, int(pivots), float(residual), ray, basis)
