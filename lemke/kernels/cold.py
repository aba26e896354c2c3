"""A cold solve in one kernel call: check the data, pivot, check the answer on the caller's
data.  ``solve_lcp`` and ``solve_lcp_batch`` both go through these kernels, so a problem
in a batch gets exactly the same answer as on its own.

Every output goes into one float64 buffer of length 4n + 2 (the front makes read-only views
of it), laid out as ``[z | z0 | ray (n + 1) | w | covering d]``, and the indices of the basic
z's into an int64 array of length n.
"""
import numpy as np

from . import kernel, tableau, unrevised
from .certify import lcp_check_sized
from .linalg import finite_absmax, nan_probe

NOT_FINITE = -1  # M or q has a NaN or an infinity: the front reports it
TRIVIAL = -2  # q >= 0: z = 0 solves it, no pivot
TABLEAU = 0
UNREVISED = 1


@kernel
def layout(n, buf):
    """The views ``(x, ray, w, cov)`` of the output buffer (x = z followed by z0)."""
    return buf[: n + 1], buf[n + 1 : 2 * n + 2], buf[2 * n + 2 : 3 * n + 2], buf[3 * n + 2 :]


@kernel
def prologue(M, q, d, buf):
    """Check that M and q are finite and fill the covering vector (an empty d stands for
    all ones).  Returns ``(code, m_scale)``: code NOT_FINITE, TRIVIAL (q >= 0: z = 0 and
    w = q written) or 0; m_scale = max|M| (1 when M = 0)."""
    n = q.shape[0]
    x, ray, w, cov = layout(n, buf)
    finite, m_max = finite_absmax(M)
    finite &= nan_probe(q, n) == 0.0
    if not finite:
        return NOT_FINITE, m_max
    q_min = 0.0
    for i in range(n):
        q_min = min(q_min, q[i])
        cov[i] = d[i] if d.shape[0] else 1.0
    if q_min >= 0.0:
        x[:] = 0.0
        ray[:] = 0.0
        w[:] = q
        return TRIVIAL, m_max
    return 0, m_max


@kernel
def epilogue(M, q, m_max, tol, buf, code, pivots, z_basic, basic):
    """After the pivoting (when ``code`` is a status of the kernels): check the point in
    ``buf`` on (M, q), filling w, and list the basic z's in ``basic``.  Returns the
    ``(code, pivots, k, ok, residual)`` of the ``checked_*`` kernels."""
    if code < 0:  # the prologue's NOT_FINITE or TRIVIAL
        return code, 0, 0, code == TRIVIAL, 0.0
    n = q.shape[0]
    x, ray, w, cov = layout(n, buf)
    ok, residual = lcp_check_sized(M, q, x[:n], tol, w, m_max)
    k = 0
    for i in range(n):
        if z_basic[i]:
            basic[k] = i
            k += 1
    return code, pivots, k, ok, residual


@kernel
def checked_tableau(M, q, d, max_pivots, pivot_tol, tie_tol, tol, buf, basic):
    """Solve LCP(M, q) cold by the tableau method with covering vector d (empty: all ones),
    then check the answer on (M, q).

    Returns ``(code, pivots, k, ok, residual)``: code is a status of the kernels, or
    NOT_FINITE (nothing else done) or TRIVIAL (z = 0, w = q); the first k entries of
    ``basic`` are the basic z's; ok and residual are the result of ``lcp_check``.
    """
    (code, m_max), pivots, z_basic = prologue(M, q, d, buf), 0, np.empty(q.shape[0], dtype=np.bool_)
    if code == 0:
        x, ray, w, cov = layout(q.shape[0], buf)
        code, pivots = tableau.solve(M, q, cov, m_max if m_max > 0.0 else 1.0, max_pivots,
                                     pivot_tol, tie_tol, x, ray, z_basic)
    return epilogue(M, q, m_max, tol, buf, code, pivots, z_basic, basic)


@kernel
def checked_unrevised(M, q, d, max_pivots, pivot_tol, tie_tol, tol, buf, basic):
    """:func:`checked_tableau` by the unrevised method, from the all-w basis."""
    n = q.shape[0]
    (code, m_max), pivots, z_basic = prologue(M, q, d, buf), 0, np.empty(n, dtype=np.bool_)
    if code == 0:
        x, ray, w, cov = layout(n, buf)
        code, pivots = unrevised.solve(M, q, cov, m_max if m_max > 0.0 else 1.0,
                                       np.zeros(n, dtype=np.bool_), np.empty((0, 0)),
                                       max_pivots, pivot_tol, tie_tol, x, ray, z_basic)
    return epilogue(M, q, m_max, tol, buf, code, pivots, z_basic, basic)


@kernel
def batch(method, M, q, lo, hi, max_pivots, pivot_tol, tie_tol, tol, bufs, basics, out_i,
          out_f):
    """``checked_tableau`` or ``checked_unrevised`` (``method``) on problems ``lo..hi-1`` of a batch: M (B, n, n), or (1, n, n) shared
    by all, and q (B, n).  Row b of ``out_i`` gets (code, pivots, k), of ``out_f``
    (ok, residual)."""
    no_d = np.empty(0)
    shared = M.shape[0] == 1
    for b in range(lo, hi):
        Mb = M[0 if shared else b]
        if method == TABLEAU:
            code, pivots, k, ok, residual = checked_tableau(
                Mb, q[b], no_d, max_pivots, pivot_tol, tie_tol, tol, bufs[b], basics[b])
        else:
            code, pivots, k, ok, residual = checked_unrevised(
                Mb, q[b], no_d, max_pivots, pivot_tol, tie_tol, tol, bufs[b], basics[b])
        out_i[b, 0] = code
        out_i[b, 1] = pivots
        out_i[b, 2] = k
        out_f[b, 0] = 1.0 if ok else 0.0
        out_f[b, 1] = residual
