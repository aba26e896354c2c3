"""solve_lcp: validate -> set up the tableau -> kernel -> check on the caller's data -> result."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ._certify import check_lcp, is_lcp_ray
from ._options import as_options
from ._problem import as_lcp
from ._result import LCPResult, WarmStart
from ._status import Status
from .kernels import linalg, tableau, unrevised

METHODS = ("tableau", "unrevised")


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

    restart_pivots = 0
    if warm_start is not None and warm_start.z_basic:
        beta = np.zeros(n, dtype=np.bool_)
        beta[list(warm_start.z_basic)] = True
        b = np.flatnonzero(beta)
        Mbb = linalg.principal_block(M, b)
        z = _basis_point(Mbb, q, b)
        if z is not None:
            w, ok, residual = check_lcp(M, q, z, opts.tol)
            if ok:  # the old basis still solves it
                return _result(z, w, residual, Status.SOLVED, 0, None, 0.0, d, warm_start)
            # Restart Lemke from the old basis (see _lemke for its covering vector).
            res = _lemke(method, M, q, None, beta, opts, Mbb)
            if res is not None and res.status == Status.SOLVED:
                return res
            restart_pivots = 0 if res is None else res.pivots  # fall back to a cold solve

    if n == 0 or q.min() >= 0.0:
        z = np.zeros(n)
        return _result(z, q.copy(), 0.0, Status.SOLVED, 0, None, 0.0, d, WarmStart(n, ()))
    res = _lemke(method, M, q, d, None, opts)
    if restart_pivots:
        res = replace(res, pivots=res.pivots + restart_pivots)
    return res


def _lemke(method, M, q, d, z_start, opts, Mbb=None):
    """Run Lemke's method, then check the outcome on the caller's data.

    Cold when ``z_start`` is None, with covering vector d.  Otherwise (d is None) a restart
    from the complementary basis with z_i basic where z_start[i], whose block is Mbb: Lemke
    on the principal pivoting transform of (M, q) by that basis, with a constant covering
    vector in the transformed coordinates.  In the caller's coordinates that is the column
    c e_alpha - M[:, beta] 1, with c = max|M| so that z rows and w rows get the same
    constant in scaled units.  None when the starting block is singular."""
    n = q.size
    x = np.empty(n + 1)
    ray = np.empty(n + 1)
    z_basic = np.empty(n, dtype=np.bool_)
    max_pivots = opts.pivot_limit(n)
    if method == "tableau" and z_start is None:
        code, pivots = tableau.solve(
            M, q, d, max_pivots, opts.pivot_tol, opts.tie_tol, x, ray, z_basic
        )
    else:
        # The same scaled units as tableau.solve: max|M| = 1, max|d| = 1.
        m_scale = max(M.max(), -M.min()) or 1.0
        if z_start is not None:
            d = m_scale * (~z_start) - M[:, z_start].sum(axis=1)
        d_scale = max(d.max(), -d.min())
        A = np.empty((n, n + 1))
        np.multiply(M, 1.0 / m_scale, out=A[:, :n])
        np.multiply(d, 1.0 / d_scale, out=A[:, n])
        qs = q * (1.0 / m_scale)
        start = np.zeros(n, dtype=np.bool_) if z_start is None else z_start
        G0 = np.empty((0, 0))
        if z_start is not None:
            try:  # numpy's LAPACK, like _basis_point (two BLAS thread pools would collide)
                G0 = np.linalg.inv(Mbb) * m_scale
            except np.linalg.LinAlgError:
                return None
            if not np.isfinite(G0).all():
                return None
        # A restart always runs the unrevised method: it needs only the inverse of the old
        # block, where the tableau would need the whole transformed tableau (O(n^3)).
        code, pivots = unrevised.lemke(
            A, qs, start, G0, max_pivots, opts.pivot_tol, opts.tie_tol, x, ray, z_basic
        )
        x[n] *= m_scale / d_scale
        ray[n] *= m_scale / d_scale
        if code == Status.SOLVED:
            np.maximum(x, 0.0, out=x)
    if code == Status.NUMERICAL_FAILURE and z_start is not None and pivots == 0:
        return None  # singular starting block
    z, z0 = x[:n], float(x[n])
    w, ok, residual = check_lcp(M, q, z, opts.tol)  # on the caller's data, whatever the status
    final_beta = np.flatnonzero(z_basic)
    final_basis = WarmStart._trusted(n, tuple(final_beta.tolist()))
    status = Status(code)

    if status == Status.SOLVED:
        if not ok:
            # Recompute the point of the final basis from the caller's data: one dense
            # solve, more accurate than a tableau that went through many pivots.
            zb = _basis_point(linalg.principal_block(M, final_beta), q, final_beta)
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


def _basis_point(Mbb, q, beta):
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


def _result(z, w, residual, status, pivots, ray, z0, d, warm_start):
    """The result, its arrays made read-only (all are the solver's own, never the caller's)."""
    d = d.copy()  # d may be the caller's array
    for a in (z, w, d) if ray is None else (z, w, d, ray):
        a.setflags(write=False)
    return LCPResult(z, w, status, int(pivots), float(residual), ray, float(z0), d, warm_start)
