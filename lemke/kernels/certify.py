"""The acceptance test of a solution, in one pass over M (see lemke._options for the rule)."""
import numpy as np

from . import kernel
from .linalg import absmax, dot

EPS = np.finfo(np.float64).eps
CERTIFIABLE = 1e3  # see lcp_check_sized


@kernel
def tolerances(n, m_max, q_max, z_max, tol):
    """The absolute tolerances ``(s_z, s_w)`` of the acceptance test from the sizes of the
    data: s_w is the data's size plus the rounding floor of computing M z."""
    s_w = tol * max(q_max, m_max) + 4.0 * n * EPS * m_max * z_max
    s_z = tol * max(z_max, q_max / m_max if m_max > 0.0 else 0.0)
    return s_z, s_w


@kernel
def lcp_check(M, q, z, tol, w):
    """Fill ``w = M z + q`` and return ``(is_solution, residual)`` where residual is
    ``max_i |min(z_i, w_i)|``."""
    n = q.shape[0]
    m_max = 0.0
    for i in range(n):
        m_max = max(m_max, absmax(M[i], n))
    return lcp_check_sized(M, q, z, tol, w, m_max)


@kernel
def lcp_check_sized(M, q, z, tol, w, m_max):
    """``lcp_check`` when the caller already knows ``m_max = max|M|``."""
    n = q.shape[0]
    q_max = 0.0
    z_max = 0.0
    for j in range(n):
        z_max = max(z_max, abs(z[j]))
    for i in range(n):
        w[i] = q[i] + dot(M[i], z, n)
        q_max = max(q_max, abs(q[i]))
    s_z, s_w = tolerances(n, m_max, q_max, z_max, tol)
    # The allowance for rounding grows with |z|: a z so large that rounding it to double
    # moves M z by far more than the tolerance (|z| ~ 1e16 on data ~ 1, as after a pivot on
    # noise) would pass anything, so it is never accepted.
    ok = EPS * m_max * z_max <= CERTIFIABLE * tol * max(q_max, m_max)
    residual = 0.0
    for i in range(n):
        zi = z[i]
        wi = w[i]
        residual = max(residual, abs(min(zi, wi)))
        if zi < -s_z or wi < -s_w or (zi > s_z and abs(wi) > s_w):
            ok = False
    return ok, residual
