"""solve_lcp: validate -> set up the tableau -> kernel -> check on the caller's data -> result."""
from __future__ import annotations

import numpy as np

from ._certify import is_lcp_ray, is_lcp_solution, lcp_residual
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
        beta = np.asarray(warm_start.z_basic, dtype=np.int64)
        z = _basis_point(M, q, beta)
        if z is not None and is_lcp_solution(M, q, z, opts.tol):
            return _result(M, q, z, Status.SOLVED, 0, None, 0.0, d, warm_start)

    if n == 0 or q.min() >= 0.0:
        return _result(M, q, np.zeros(n), Status.SOLVED, 0, None, 0.0, d, WarmStart(n, ()))

    # Work in units where max|M| = 1 and max|d| = 1: z keeps its units, w and z0 are
    # rescaled, and the relative tolerances then compare like with like (the result does
    # not change when M and q are multiplied by a constant).
    m_scale = float(np.max(np.abs(M))) or 1.0
    d_scale = float(np.max(d))
    T = np.empty((n, n + 1))
    np.multiply(M, 1.0 / m_scale, out=T[:, :n])
    np.multiply(d, 1.0 / d_scale, out=T[:, n])
    rhs = q * (1.0 / m_scale)
    basis = np.arange(n, dtype=np.int64)
    nonbasic = np.arange(n, 2 * n + 1, dtype=np.int64)
    x = np.empty(n + 1)
    ray = np.empty(n + 1)
    tie_abs = opts.tie_tol * float(np.max(np.abs(rhs)))
    code, pivots = tableau.lemke(
        T, rhs, basis, nonbasic, opts.pivot_limit(n), opts.pivot_tol, tie_abs, x, ray
    )
    x[n] *= m_scale / d_scale  # z0 back in the caller's units
    ray[n] *= m_scale / d_scale
    z, z0 = x[:n], float(x[n])
    beta = np.sort(basis[(basis >= n) & (basis < 2 * n)] - n)
    basis_value = WarmStart(n, tuple(beta.tolist()))
    status = Status(code)

    if status == Status.SOLVED:
        z = np.maximum(z, 0.0)  # round-off below zero; anything worse fails the check
        if not is_lcp_solution(M, q, z, opts.tol):
            # Recompute the point of the final basis from the caller's data: one dense
            # solve, more accurate than a tableau that went through many pivots.
            zb = _basis_point(M, q, beta)
            if zb is not None and is_lcp_solution(M, q, zb, opts.tol):
                z = zb
            else:
                status = Status.NUMERICAL_FAILURE
        return _result(M, q, z, status, pivots, None, 0.0, d, basis_value)
    if status == Status.RAY_TERMINATION:
        if not is_lcp_ray(M, q, d, z, z0, ray, opts.tol):
            status = Status.NUMERICAL_FAILURE
            ray = None
        return _result(M, q, z, status, pivots, ray, z0, d, basis_value)
    return _result(M, q, z, status, pivots, None, z0, d, basis_value)


def _basis_point(M, q, beta):
    """The point of the complementary basis with z_beta basic, or None if M_beta,beta is
    singular: ``z_beta = -M_bb^-1 q_beta``, other z zero."""
    z = np.zeros(q.size)
    if beta.size:
        try:
            z[beta] = np.linalg.solve(M[np.ix_(beta, beta)], -q[beta])
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(z)):
            return None
    return np.maximum(z, 0.0)  # a negative z_beta beyond round-off makes it no solution


def _result(M, q, z, status, pivots, ray, z0, d, warm_start):
    z = np.array(z, dtype=np.float64)
    w = M @ z + q
    return LCPResult(
        z=frozen_array(z),
        w=frozen_array(w),
        status=status,
        pivots=int(pivots),
        residual=lcp_residual(z, w),
        ray=None if ray is None else frozen_array(np.array(ray)),
        z0=float(z0),
        covering=frozen_array(np.array(d)),
        warm_start=warm_start,
    )
