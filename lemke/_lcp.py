"""solve_lcp: validate -> set up the tableau -> kernel -> check on the caller's data -> result."""
from __future__ import annotations

import numpy as np

from . import _validate
from ._certify import check_lcp
from ._options import _DEFAULT, as_options
from ._result import LCPResult, WarmStart
from ._status import Status
from .kernels import cold, linalg

METHODS = tuple(cold.METHODS)
_SOLVE_ONE = cold.solve_one  # a module attribute, so that a test can stand a lying kernel in
_F64 = np.dtype(np.float64)
_NO_D = np.empty(0)


def solve_lcp(M, q, *, method="tableau", d=None, warm_start=None, options=None) -> LCPResult:
    r"""Solve the linear complementarity problem LCP(M, q) by Lemke's method.

    Find z with

    .. math::  z \ge 0, \quad w = M z + q \ge 0, \quad z^\top w = 0 .

    Parameters
    ----------
    M : (n, n) array_like or scipy.sparse matrix
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
        ``max_pivots`` and the tolerances; see :class:`lemke.Options`.

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
    if (d is None and type(M) is np.ndarray and type(q) is np.ndarray
            and M.dtype is _F64 and q.dtype is _F64 and M.ndim == 2 and q.ndim == 1
            and M.shape[0] == M.shape[1] == q.shape[0] and method in cold.METHODS
            and M.flags.c_contiguous and q.flags.c_contiguous and M.flags.writeable and q.flags.writeable
            and (warm_start is None or (type(warm_start) is WarmStart and warm_start.n == q.shape[0]))):
        # The common case in one kernel call (which checks that M and q are finite); no
        # copies: the data are float64 already, and the kernels never write to them.
        opts = _DEFAULT if options is None else as_options(options)
        if warm_start is None or not warm_start.z_basic:
            res = _cold(method, M, q, _NO_D, opts)
        else:
            res = _warm(method, M, q, _NO_D, warm_start, opts)
        if res is not None:
            return res  # else M or q is not finite: the validation below says where
    _validate.method(method, METHODS)
    M, q, d = _validate.lcp(M, q, d)
    M, q = _validate.kernel_array(M), _validate.kernel_array(q)
    opts = as_options(options)
    _validate.warm_start(warm_start, WarmStart, q.size,
                         "warm_start is for a problem of size {ws}, this one has n = {n}")
    d = _NO_D if d is None else d
    if warm_start is not None and warm_start.z_basic:
        return _warm(method, M, q, d, warm_start, opts)
    return _cold(method, M, q, d, opts)


def _views(buf, n):
    """The read-only views ``(z, z0, ray, w, cov, row_scale, col_scale)`` of a kernel's output
    buffer (``kernels.cold.fields``)."""
    buf.setflags(write=False)
    f = cold.fields(n)
    return tuple(buf[f[name]] for name, _ in cold.BUFFER)


_NO_BASIS = np.zeros(0, dtype=np.int64)


def _cold(method, M, q, d, opts):
    """A cold solve (float64, C-contiguous, validated shapes): one kernel call that also
    checks the answer on the caller's data.  None when M or q is not finite."""
    return _solve(method, M, q, d, _NO_BASIS, None, opts)


def _warm(method, M, q, d, warm_start, opts):
    """A warm solve in one kernel call: the old basis's point if it still solves the problem
    (0 pivots), else Lemke restarted from that basis, else a cold solve.  None when M or q
    is not finite."""
    beta = warm_start.__dict__.get("_beta")
    if beta is None:  # the basis as an index array, kept with the (immutable) WarmStart
        beta = warm_start.__dict__["_beta"] = np.array(warm_start.z_basic, dtype=np.int64)
    return _solve(method, M, q, d, beta, warm_start, opts)


def _solve(method, M, q, d, beta, warm_start, opts):
    """``kernels.cold.solve_one``, the one kernel of every LCP solve, cold (``beta`` empty) or
    warm, and its result: built lazily when solved and checked."""
    n = q.shape[0]
    buf = np.empty(cold.buffer_length(n))
    basic = np.empty(n, dtype=np.int64)
    code, pivots, k, ok, residual, recoveries, stage = _SOLVE_ONE(
        cold.METHODS[method], M, q, d, beta, beta.shape[0], opts.pivot_limit(n), opts.pivot_tol,
        opts.tie_tol, opts.tol, buf, basic
    )
    if code == 0 and ok:  # solved and checked: the common case, built lazily
        return LCPResult._lazy(buf, basic, k, Status.SOLVED, pivots, residual, recoveries,
                               warm_start if stage == 0 else None)
    if code == cold.NOT_FINITE:
        return None
    return _outcome(M, q, opts, code, pivots, basic[:k], ok, residual, buf, recoveries)


def _outcome(M, q, opts, code, pivots, basic, ok, residual, buf, recoveries):
    """The result of a kernel's run, from its output buffer (see ``kernels.cold``), the
    basic z's and the kernel's check of the point on the caller's data.

    A solved point that failed the check is recomputed from the final basis (one dense
    solve on the caller's data) and downgraded to NUMERICAL_FAILURE if that fails too; a
    ray was checked on the caller's data by the kernel (``ok``), and is downgraded if it
    failed."""
    n = q.shape[0]
    z, z0, ray, w, cov, rs, cs = _views(buf, n)
    if code == cold.TRIVIAL:
        return LCPResult._make(z, w, Status.SOLVED, 0, 0.0, None, 0.0, cov,
                               WarmStart._trusted(n, ()), rs, cs, 0)
    final_basis = WarmStart._trusted(n, tuple(basic.tolist()))
    if code == 0 and ok:  # Status.SOLVED
        return LCPResult._make(z, w, Status.SOLVED, pivots, residual, None, 0.0, cov,
                               final_basis, rs, cs, recoveries)
    status = Status(code)
    extra = (rs, cs, recoveries)
    if status == Status.SOLVED:
        # Recompute the point of the final basis from the caller's data: one dense solve,
        # more accurate than a tableau that went through many pivots.
        zb = _point_of_basis(linalg.principal_block(M, basic), q, basic)
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
