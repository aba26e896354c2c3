"""solve_lcp: validate -> set up the tableau -> kernel -> check on the caller's data -> result."""
from __future__ import annotations

import numpy as np

from . import _validate
from ._certify import check_lcp, is_lcp_ray
from ._options import _DEFAULT, as_options
from ._result import LCPResult, WarmStart
from ._status import Status
from .kernels import certify, cold, linalg, unrevised

METHODS = tuple(cold.METHODS)
_CHECKED = cold.checked  # a module attribute, so that a test can stand a lying kernel in
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
    if (d is None and warm_start is None and type(M) is np.ndarray and type(q) is np.ndarray
            and M.dtype is _F64 and q.dtype is _F64 and M.ndim == 2 and q.ndim == 1
            and M.shape[0] == M.shape[1] == q.shape[0] and method in cold.METHODS
            and M.flags.c_contiguous):
        # The common case in one kernel call (which checks that M and q are finite); no
        # copies: the data are float64 already, and the kernels never write to them.
        res = _cold(method, M, q, _NO_D, _DEFAULT if options is None else as_options(options))
        if res is not None:
            return res  # else M or q is not finite: the validation below says where
    _validate.method(method, METHODS)
    M, q, d = _validate.lcp(M, q, d)
    opts = as_options(options)
    n = q.size
    _validate.warm_start(warm_start, WarmStart, n,
                         "warm_start is for a problem of size {ws}, this one has n = {n}")

    restart_pivots = 0
    if warm_start is not None and warm_start.z_basic:
        beta = np.zeros(n, dtype=np.bool_)
        beta[list(warm_start.z_basic)] = True
        b = np.flatnonzero(beta)
        Mbb = linalg.principal_block(M, b)
        z = _point_of_basis(Mbb, q, b)
        if z is not None:
            R, C, w = np.empty(n), np.empty(n), np.empty(n)
            linalg.equilibrate(M, q, R, C)  # once: the check and the result use them
            ok, residual = certify.lcp_check_sized(M, q, z, opts.tol, w, R)
            if ok:  # the old basis still solves it
                cov = np.ones(n) if d is None else d.copy()
                return _result(z, w, residual, Status.SOLVED, 0, None, 0.0, cov, warm_start,
                               R, C, 0)
            res = _restart(M, q, beta, opts)
            if res is not None and res.status == Status.SOLVED:
                return res
            restart_pivots = 0 if res is None else res.pivots  # fall back to a cold solve

    return _cold(method, M, q, _NO_D if d is None else d, opts, restart_pivots)


def _views(buf, n):
    """The read-only views ``(z, z0, ray, w, cov, row_scale, col_scale)`` of a kernel's output
    buffer (``kernels.cold.fields``)."""
    buf.setflags(write=False)
    f = cold.fields(n)
    return tuple(buf[f[name]] for name, _ in cold.BUFFER)


def _cold(method, M, q, d, opts, extra_pivots=0):
    """A cold solve (float64, C-contiguous, validated shapes): one kernel call that also
    checks the answer on the caller's data, then :func:`_outcome`.  None when M or q is not
    finite."""
    n = q.shape[0]
    buf = np.empty(cold.buffer_length(n))
    basic = np.empty(n, dtype=np.int64)
    code, pivots, k, ok, residual, recoveries = _CHECKED(
        cold.METHODS[method], M, q, d, max(0, opts.pivot_limit(n) - extra_pivots), opts.pivot_tol,
        opts.tie_tol, opts.tol, buf, basic
    )
    if code == 0 and ok:  # solved and checked: the common case, inline
        z, z0, ray, w, cov, rs, cs = _views(buf, n)
        return LCPResult._make(
            z, w, Status.SOLVED, pivots + extra_pivots, residual, None, 0.0, cov,
            WarmStart._trusted(n, tuple(basic.tolist()[:k])), rs, cs, recoveries,
        )
    if code == cold.NOT_FINITE:
        return None
    return _outcome(M, q, opts, code, pivots + extra_pivots, basic[:k], ok, residual, buf,
                    recoveries)


def _restart(M, q, beta, opts):
    """Lemke from the complementary basis with z_i basic where beta[i]: on the principal
    pivoting transform of (M, q) by that basis, with a constant covering vector in the
    transformed coordinates.  In the caller's coordinates that is the column
    c e_alpha - M[:, beta] 1, with c = max|M| so that z rows and w rows get the same
    constant.  It always runs the unrevised method: that needs only the inverse of the old
    block, where the tableau would need the whole transformed tableau (O(n^3)).  None when
    the starting block is singular."""
    n = q.size
    m_scale = max(M.max(), -M.min()) or 1.0
    buf = np.empty(cold.buffer_length(n))
    x, ray, w, cov, R, C = cold.layout(n, buf)
    np.subtract(m_scale * (~beta), M[:, beta].sum(axis=1), out=cov)
    linalg.equilibrate(M, q, R, C)
    z_basic = np.empty(n, dtype=np.bool_)
    code, pivots = unrevised.solve(M, q, cov, R, C, beta, np.empty((0, 0)), opts.pivot_limit(n),
                                   opts.pivot_tol, opts.tie_tol, x, ray, z_basic)
    if code == Status.NUMERICAL_FAILURE and pivots == 0:
        return None  # singular starting block
    ok, residual = certify.lcp_check_sized(M, q, x[:n], opts.tol, w, R)
    if ok:
        code = Status.SOLVED  # the point where it stopped solves the LCP (see kernels.cold)
    return _outcome(M, q, opts, code, pivots, np.flatnonzero(z_basic), ok, residual, buf, 0)


def _outcome(M, q, opts, code, pivots, basic, ok, residual, buf, recoveries):
    """The result of a kernel's run, from its output buffer (see ``kernels.cold``), the
    basic z's and the kernel's check of the point on the caller's data.

    A solved point that failed the check is recomputed from the final basis (one dense
    solve on the caller's data) and downgraded to NUMERICAL_FAILURE if that fails too; a
    ray is checked on the caller's data, and downgraded if it fails."""
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
    if status == Status.RAY_TERMINATION and not is_lcp_ray(M, q, cov, z, z0, ray, opts.tol):
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
