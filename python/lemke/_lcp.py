"""solve_lcp: validate -> set up the tableau -> kernel -> check on the caller's data -> result."""
from __future__ import annotations

import functools
import inspect

import numpy as np

from . import _core, _progress, _validate
from ._certify import check_lcp
from ._options import _DEFAULT, as_options, time_limited, timed
from ._result import LCPResult, WarmStart, native_fronts_init
from ._status import Status
from . import _layout

METHODS = tuple(_layout.METHODS)
#: The C++ core's LCP driver (src/lemke/lcp.cpp), its buffer laid out as _layout.py states;
#: module attributes, so that a test can stand a lying kernel in.  ``_SOLVE_ONE``: a whole solve, warm or cold, with its
#: recoveries, either method.
_SOLVE_ONE = _core.solve_one
#: The commonest call whole (src/python_front.cpp): plain float64 M and q, either method
#: (a fifth argument 1: the unrevised method), defaults; a result, the core's answer and
#: buffer as a tuple, or None (not plain).
_FRONT = _core.lcp_front
#: The first stages of a solve by the tableau, cold or warm: the C++ core's port of
#: ``_layout.first_run`` (the same arguments, results and bits; src/lemke/lcp.cpp).
_FIRST_RUN = _core.first_run
_F64 = np.dtype(np.float64)
_NO_D = None  # no covering vector (all ones); the core takes None for it, for no warm
_NO_BASIS = None  # basis and for the buffer's own basic z's (an array costs 0.14 us a call)
_CODES = _layout.METHODS
_ND = np.ndarray
_I64 = np.dtype(np.int64)
_SOLVED = Status.SOLVED
_SETTLED = _layout.SETTLED
_RAY = int(Status.RAY_TERMINATION)
_new = object.__new__
_empty = np.empty
#: _layout.buffer_length(n) = _LEN_N * n + _LEN_1 (the layout's lengths are linear in n)
_LEN_1 = _layout.buffer_length(0)
_LEN_N = _layout.buffer_length(1) - _LEN_1
_PIVOT_TOL, _TIE_TOL, _TOL = _DEFAULT.pivot_tol, _DEFAULT.tie_tol, _DEFAULT.tol
#: {method: the compiled entry point of its kernel for the fast path's argument types}
_ENTRY: dict = {}


def solve_lcp(M, q, *, method="tableau", d=None, warm_start=None, options=None,
              progress=None, _ray_stop=False) -> LCPResult:
    r"""Solve the linear complementarity problem LCP(M, q) by Lemke's method.

    Find z with

    .. math::  z \ge 0, \quad w = M z + q \ge 0, \quad z^\top w = 0 .

    Parameters
    ----------
    M : (n, n) array_like or scipy.sparse matrix
        A sparse M is made dense (no sparse engine yet): with a
        :class:`lemke.DensifyWarning` when the dense copy takes 64 MiB or more, refused
        (``ValueError``) when it would not fit in the memory available.
    q : (n,) array_like
    method : {"tableau", "unrevised"}
        ``"tableau"``: complementary pivoting on a condensed tableau.  ``"unrevised"``: the
        method of Dai & Drumwright, which keeps only the index sets and the inverse of the
        block M[alpha, beta], updated in O(k^2) a pivot.  Both use the same rules (minimum
        ratio, ties to the artificial variable, then lexicographic: no cycling) and give the
        same pivots.
    d : (n,) array_like, optional
        Covering vector, the artificial variable's column (positive; default all ones).
    warm_start : WarmStart, optional
        The ``warm_start`` of an earlier result (either method) for a problem of the same
        size.  If that basis still solves this problem the answer comes with zero pivots;
        otherwise Lemke restarts from it (the unrevised method on the principal pivoting
        transform by that basis, with a constant covering vector there; ``d`` is not used),
        and if that fails too, the problem is solved cold.
    options : Options or dict, optional
        ``max_pivots``, the tolerances and ``time_limit``; see :class:`lemke.Options`.
    progress : callable or True, optional
        For long solves: ``progress(pivots, seconds)`` about every 0.1 s while the core
        pivots (the pivots of the run in progress, the seconds since the call began), in
        the calling thread; an exception it raises stops the solve and propagates.
        ``True`` draws a bar on stderr (tqdm when installed, else a counter).  A short solve
        makes no report.

    Returns
    -------
    LCPResult
        ``status`` is ``SOLVED`` only when the answer passed the check on the caller's M
        and q; a point that fails it is reported as ``NUMERICAL_FAILURE``.

    Examples
    --------
    >>> import lemke
    >>> r = lemke.solve_lcp([[2.0, 1.0], [1.0, 2.0]], [-5.0, -6.0])
    >>> r.status.name, r.z.round(6).tolist()
    ('SOLVED', [1.333333, 2.333333])

    References
    ----------
    C. E. Lemke, "Bimatrix equilibrium points and mathematical programming",
    Management Science 11 (1965).  R. W. Cottle, J.-S. Pang, R. E. Stone, *The Linear
    Complementarity Problem*, Academic Press (1992), section 4.4.
    """
    # (_ray_stop, private: the MLCP ladder's step with another after it, whose recovery runs
    # end at their first ray: _core.solve_one's stop_at_ray, src/lemke/lcp.hpp)
    if progress is not None and progress is not False:
        return _progress.reported(_progress.check(progress), "solve_lcp", solve_lcp, M, q,
                                  method=method, d=d, warm_start=warm_start, options=options,
                                  _ray_stop=_ray_stop)
    if d is None and options is None and (method == "tableau" or method == "unrevised"):
        # The commonest calls, whole in one native call (src/python_front.cpp): plain
        # float64 arrays give the result (or what first_run left to do), others None.
        if warm_start is None:
            r = _FRONT(M, q, None, None) if method == "tableau" else _FRONT(M, q, None, None, 1)
            beta = _NO_BASIS
        elif type(warm_start) is WarmStart and type(q) is _ND and warm_start.n == len(q):
            try:
                beta = warm_start._beta  # (an attribute read: cheaper than __dict__.get)
            except AttributeError:
                beta = warm_start.__dict__["_beta"] = np.array(warm_start.z_basic, dtype=np.int64)
            r = _FRONT(M, q, warm_start, beta) if method == "tableau" else _FRONT(
                M, q, warm_start, beta, 1)
        else:
            r = None
        if r is not None:
            return r if type(r) is not tuple else _after_front(M, q, warm_start, beta, r, method)
        if (c := _validate.plain_lcp(M, q)) is not None:
            # array-likes (lists, int or float32 arrays, another order...) converted once,
            # as the validation below would convert them: then the front, through the entry
            return solve_lcp(c[0], c[1], method=method, warm_start=warm_start)
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_lcp, M, q, method=method, d=d, warm_start=warm_start,
                     _ray_stop=_ray_stop)
    ws = warm_start
    # (``is`` first, for speed; ``==`` for a float64 dtype that is not numpy's own object,
    # such as one made by ``dtype.newbyteorder("=")``.)
    if (type(M) is _ND and type(q) is _ND and d is None and q.ndim == 1 and M.ndim == 2
            and (M.dtype is _F64 or M.dtype == _F64) and (q.dtype is _F64 or q.dtype == _F64)
            and M.flags.carray and q.flags.carray
            and method in _CODES and (ws is None or (type(ws) is WarmStart and ws.n == len(q)))):
        # The common case: float64, C-contiguous, aligned and writable already (the kernels
        # never write to M and q, and check that they are finite and that their sizes
        # match: NOT_FINITE below when not), so no copies, and the kernel called through
        # its compiled entry point for exactly these types.  (Each Python step here is a
        # visible share of a small solve: ``len(q)``, not ``q.shape[0]``.)
        run = _ENTRY.get(method) or _entry_point(method)
        n = len(q)
        d = _NO_D
        if options is None:
            opts = _DEFAULT
            mp, pivot_tol, tie_tol, tol = 100 * (n + 1), _PIVOT_TOL, _TIE_TOL, _TOL
        else:
            opts = as_options(options)
            mp, pivot_tol, tie_tol, tol = opts.max_pivots, opts.pivot_tol, opts.tie_tol, opts.tol
    else:
        _validate.method(method, METHODS)
        M, q, d = _validate.lcp(M, q, d)
        M, q = _validate.kernel_array(M), _validate.kernel_array(q)
        opts = as_options(options)
        _validate.warm_start(ws, WarmStart, q.size,
                             "warm_start is for a problem of size {ws}, this one has n = {n}")
        d = _NO_D if d is None else d  # (None: all ones)
        run = _FIRST_RUN if method == "tableau" else _SOLVE_ONE
        n = q.shape[0]
        mp, pivot_tol, tie_tol, tol = opts.max_pivots, opts.pivot_tol, opts.tie_tol, opts.tol
    if mp is None:
        mp = 100 * (n + 1)  # (Options.pivot_limit inlined)
    if ws is None:
        beta = _NO_BASIS
        kb = 0
    else:  # the basis as an index array, kept with the (immutable) WarmStart
        try:
            beta = ws._beta  # (an attribute read: cheaper than ws.__dict__.get)
        except AttributeError:
            beta = ws.__dict__["_beta"] = np.array(ws.z_basic, dtype=np.int64)
        kb = len(beta)
    # One buffer: _layout.buffer_length(n) floats, then the n int64 of the basic z's (an empty
    # ``basic`` argument tells the kernel so: _layout.own_basic).
    at = _LEN_N * n + _LEN_1
    buf = _empty(at + n)
    if _ray_stop and run is _SOLVE_ONE:
        out = run(_CODES[method], M, q, d, beta, kb, mp, pivot_tol, tie_tol, tol, buf, _NO_BASIS,
                  True)
    else:
        out = run(_CODES[method], M, q, d, beta, kb, mp, pivot_tol, tie_tol, tol, buf, _NO_BASIS)
    code, pivots, k, ok, residual, recoveries, stage = out
    if ok and code in _SETTLED:
        # Solved and checked (or q >= 0: z = 0), or a checked ray: the common cases, built
        # lazily (LCPResult._lazy, inlined).
        res = _new(LCPResult)
        f = res.__dict__
        f["status"] = _SOLVED if code != _RAY else Status.RAY_TERMINATION
        f["pivots"] = pivots
        f["residual"] = residual
        if recoveries:
            f["recoveries"] = recoveries
        f["_src"] = (buf, 0, None, at, n, k)
        if stage == 0:
            f["warm_start"] = ws
        return res
    return _go_on(M, q, d, method, opts, ws, beta, kb, mp, pivot_tol, tie_tol, tol, buf, at, n,
                  code, pivots, k, ok, residual, recoveries, stage, _ray_stop)


def _after_front(M, q, warm_start, beta, r, method="tableau"):
    """solve_lcp after its native front (``_FRONT``, default options) handed back the
    core's answer ``r`` and buffer (the tableau: first_run's; the unrevised method:
    solve_one's, never stage < 0): the driver goes on from there."""
    n = len(q)
    return _go_on(M, q, _NO_D, method, _DEFAULT, warm_start, beta,
                  0 if beta is None else len(beta), 100 * (n + 1), _PIVOT_TOL, _TIE_TOL, _TOL,
                  r[7], _LEN_N * n + _LEN_1, n, *r[:7])


def _go_on(M, q, d, method, opts, ws, beta, kb, mp, pivot_tol, tie_tol, tol, buf, at, n,
           code, pivots, k, ok, residual, recoveries, stage, ray_stop=False):
    """solve_lcp after a first call of the core that did not settle the solve: the rest of
    the driver (stage < 0), then the result (``ray_stop``: solve_lcp's ``_ray_stop``)."""
    if stage < 0:
        # A solve by the tableau that the lean kernel (_layout.first_run) could not finish: a
        # cold run with a cycle, a ray to check or recovery runs to make (stage -1: the full
        # kernel goes on from there), or a warm start to restart from its old basis (-2).
        resume = stage == -1
        code, pivots, k, ok, residual, recoveries, stage = _SOLVE_ONE(
            _CODES[method], M, q, d, np.array([code, pivots], dtype=np.int64) if resume else beta,
            -1 if resume else -2 - kb, mp, pivot_tol, tie_tol, tol, buf, _NO_BASIS, ray_stop)
        if ok and (code == 0 or code == _RAY):
            return LCPResult._lazy(_SOLVED if code != _RAY else Status.RAY_TERMINATION, pivots,
                                   residual, recoveries, (buf, 0, None, at, n, k))
    if code == _layout.NOT_FINITE:
        _validate.lcp(M, q)  # raises, saying where (a NaN, an infinity, the sizes)
        raise AssertionError("the kernel found a NaN or an infinity that validation did not")
    return _outcome(M, q, opts, code, pivots, buf[at : at + k].view(_I64), ok, residual, buf,
                    recoveries)


def _entry_point(method):
    """The function the fast path calls for a solve by ``method``: the C++ core's
    ``first_run`` for the tableau (cold or warm; what it does not settle goes on in
    ``_SOLVE_ONE``), its ``solve_one`` for the unrevised method."""
    run = _FIRST_RUN if method == "tableau" else _SOLVE_ONE
    _ENTRY[method] = run
    return run


def _views(buf, n):
    """The read-only views ``(z, z0, ray, w, cov, row_scale, col_scale)`` of a kernel's output
    buffer (``_layout.fields``)."""
    buf.setflags(write=False)
    f = _layout.fields(n)
    return tuple(buf[f[name]] for name, _ in _layout.BUFFER)



def _outcome(M, q, opts, code, pivots, basic, ok, residual, buf, recoveries):
    """The result of a kernel's run that is not built lazily (neither solved and checked,
    nor q >= 0, nor a checked ray), from its output buffer (see ``_layout``), the
    basic z's and the kernel's check of the point on the caller's data.

    A solved point that failed the check is recomputed from the final basis (one dense
    solve on the caller's data) and downgraded to NUMERICAL_FAILURE if that fails too; a
    ray was checked on the caller's data by the kernel (``ok``), and is downgraded if it
    failed."""
    n = q.shape[0]
    z, z0, ray, w, cov, rs, cs = _views(buf, n)
    final_basis = WarmStart._trusted(n, tuple(basic.tolist()))
    status = Status(code)
    extra = (rs, cs, recoveries)
    if status == Status.SOLVED:
        # Recompute the point of the final basis from the caller's data: one dense solve,
        # more accurate than a tableau that went through many pivots.
        zb = _point_of_basis(_core.principal_block(M, basic), q, basic)
        if zb is not None:
            wb, ok, rb = check_lcp(M, q, zb, opts.tol)
            if ok:
                z, w, residual = zb, wb, rb
        if not ok:
            status = Status.NUMERICAL_FAILURE
        return _result(z, w, residual, status, pivots, None, 0.0, cov, final_basis, *extra)
    z0 = float(z0)
    if status == Status.RAY_TERMINATION and not ok:  # the kernel's verdict on the ray
        status = Status.NUMERICAL_FAILURE
    return _result(z, w, residual, status, pivots, ray if status == Status.RAY_TERMINATION else None,
                   z0, cov, final_basis, *extra)


def _point_of_basis(Mbb, q, beta):
    """The point of the complementary basis with z_beta basic (Mbb = M[beta, beta]), or
    None if Mbb is singular: ``z_beta = -Mbb^-1 q_beta``, the other z zero."""
    z = np.zeros(q.size)
    if beta.size:
        try:
            z[beta] = np.linalg.solve(Mbb, -q[beta])
        except np.linalg.LinAlgError:
            return None
        if not np.isfinite(z).all():
            return None
    return np.maximum(z, 0.0)  # a negative z_beta beyond round-off makes it no solution


def _result(z, w, residual, status, pivots, ray, z0, cov, warm_start, row_scale, col_scale,
            recoveries):
    """The result, its arrays made read-only (all are the solver's own, never the caller's)."""
    for a in (z, w, cov) if ray is None else (z, w, cov, ray):
        a.setflags(write=False)
    return LCPResult._make(z, w, status, int(pivots), float(residual), ray, float(z0), cov,
                           warm_start, row_scale, col_scale, int(recoveries))


native_fronts_init()  # (solve_lcp's front and the layout check the native fronts rely on)

#: The Python function; ``solve_lcp`` is the core's entry that wraps it (src/python_front.cpp,
#: ``lcp_entry``): the calls ``solve_lcp(M, q)`` and ``solve_lcp(M, q, warm_start=ws)`` go
#: to ``_FRONT`` with no Python frame, every other call (and any the front declines) to it.
_solve_lcp = solve_lcp
_sig = inspect.signature(_solve_lcp)  # shown without the private _ray_stop
_solve_lcp.__signature__ = _sig.replace(
    parameters=[p for p in _sig.parameters.values() if p.name != "_ray_stop"])
solve_lcp = functools.update_wrapper(
    _core.lcp_entry(_solve_lcp, _after_front, globals(), _FRONT, WarmStart), _solve_lcp)
