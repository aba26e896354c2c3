"""solve_lcp: validate -> set up the tableau -> kernel -> check on the caller's data -> result."""
from __future__ import annotations

import numpy as np

from ._certify import check_lcp, is_lcp_ray
from ._options import as_options
from ._problem import as_lcp
from ._result import LCPResult, WarmStart, frozen_array
from ._status import Status
from .kernels import tableau

METHODS = ("tableau",)


def solve_lcp(M, q, *, method="tableau", d=None, warm_start=None, options=None) -> LCPResult:
    r"""Solve the linear complementarity problem LCP(M, q) by Lemke's method.

    Find z with

    .. math::  z \ge 0, \quad w = M z + q \ge 0, \quad z^\top w = 0 .

    Parameters
    ----------
    M : (n, n) array_like or scipy.sparse matrix
    q : (n,) array_like
    method : {"tableau"}
        ``"tableau"``: complementary pivoting on a condensed tableau with a lexicographic
        ratio test (no cycling on degenerate problems).
    d : (n,) array_like, optional
        Covering vector, the artificial variable's column (positive; default all ones).
    warm_start : WarmStart, optional
        The ``warm_start`` of an earlier result for a problem of the same size.  If that
        basis still solves this problem the answer comes with zero pivots; otherwise the
        problem is solved from scratch.
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
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(map(repr, METHODS))}")
    M, q, d = as_lcp(M, q, d)
    opts = as_options(options)
    n = q.size
    if warm_start is not None:
        if not isinstance(warm_start, WarmStart):
            raise TypeError(f"warm_start must be a lemke.WarmStart, got {type(warm_start).__name__}")
        if warm_start.n != n:
            raise ValueError(f"warm_start is for a problem of size {warm_start.n}, this one has n = {n}")
    if d is None:
        d = np.ones(n)

    if warm_start is not None and warm_start.z_basic:
        z = _basis_point(M, q, np.asarray(warm_start.z_basic, dtype=np.int64))
        if z is not None:
            w, ok, residual = check_lcp(M, q, z, opts.tol)
            if ok:
                return _result(z, w, residual, Status.SOLVED, 0, None, 0.0, d, warm_start)

    if n == 0 or q.min() >= 0.0:
        z = np.zeros(n)
        return _result(z, q.copy(), 0.0, Status.SOLVED, 0, None, 0.0, d, WarmStart(n, ()))

    x = np.empty(n + 1)
    ray = np.empty(n + 1)
    basis = np.empty(n, dtype=np.int64)
    code, pivots = tableau.solve(
        M, q, d, opts.pivot_limit(n), opts.pivot_tol, opts.tie_tol, x, ray, basis
    )
    z, z0 = x[:n], float(x[n])
    w, ok, residual = check_lcp(M, q, z, opts.tol)  # on the caller's data, whatever the status
    beta = np.sort(basis[(basis >= n) & (basis < 2 * n)] - n)
    final_basis = WarmStart._trusted(n, tuple(beta.tolist()))
    status = Status(code)

    if status == Status.SOLVED:
        if not ok:
            # Recompute the point of the final basis from the caller's data: one dense
            # solve, more accurate than a tableau that went through many pivots.
            zb = _basis_point(M, q, beta)
            if zb is not None:
                wb, ok, rb = check_lcp(M, q, zb, opts.tol)
                if ok:
                    z, w, residual = zb, wb, rb
            if not ok:
                status = Status.NUMERICAL_FAILURE
        return _result(z, w, residual, status, pivots, None, 0.0, d, final_basis)

    if status == Status.RAY_TERMINATION and not is_lcp_ray(M, q, d, z, z0, ray, opts.tol):
        status = Status.NUMERICAL_FAILURE
    if status != Status.RAY_TERMINATION:
        ray = None
    return _result(z, w, residual, status, pivots, ray, z0, d, final_basis)


def _basis_point(M, q, beta):
    """The point of the complementary basis with z_beta basic, or None if M_beta,beta is
    singular: ``z_beta = -M_bb^-1 q_beta``, other z zero."""
    z = np.zeros(q.size)
    if beta.size:
        try:
            z[beta] = np.linalg.solve(M[np.ix_(beta, beta)], -q[beta])
        except np.linalg.LinAlgError:
            return None
        if not np.isfinite(z).all():
            return None
    return np.maximum(z, 0.0)  # a negative z_beta beyond round-off makes it no solution


def _result(z, w, residual, status, pivots, ray, z0, d, warm_start):
    return LCPResult(
        z=frozen_array(z),
        w=frozen_array(w),
        status=status,
        pivots=int(pivots),
        residual=float(residual),
        ray=None if ray is None else frozen_array(ray),
        z0=float(z0),
        covering=frozen_array(d.copy()),  # d may be the caller's array
        warm_start=warm_start,
    )
