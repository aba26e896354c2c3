"""Checks made on the caller's data: is a point a solution, is a direction a ray.

The same functions serve the solver (to accept or downgrade a result), the tests and the
benchmarks, so every part of the project judges answers the same way.
"""
from __future__ import annotations

import numpy as np

from ._problem import as_matrix, as_vector
from .kernels import certify

def lcp_scales(M: np.ndarray, q: np.ndarray, z: np.ndarray, tol: float):
    """Absolute tolerances ``(s_z, s_w)`` for z and w (see :mod:`lemke._options`)."""
    def size(a):
        return float(np.max(np.abs(a))) if a.size else 0.0

    return certify.tolerances(q.size, size(M), size(q), size(z), float(tol))


def lcp_residual(z: np.ndarray, w: np.ndarray) -> float:
    """``max_i |min(z_i, w_i)|``: zero exactly when z, w >= 0 and z'w = 0."""
    return float(np.max(np.abs(np.minimum(z, w)))) if z.size else 0.0


def check_lcp(M: np.ndarray, q: np.ndarray, z: np.ndarray, tol: float):
    """``(w, is_solution, residual)`` for float64 arrays of matching shapes; w = M z + q."""
    w = np.empty_like(q)
    ok, residual = certify.lcp_check(M, q, z, tol, w)
    return w, bool(ok), float(residual)


def is_lcp_solution(M, q, z, tol: float = 1e-9) -> bool:
    """Whether z solves the LCP (M, q) within the scale-aware tolerance ``tol``: with
    ``s_w = tol * max(max|q|, max|M|) + 4 n eps max|M| max|z|`` and
    ``s_z = tol * max(max|z|, max|q| / max|M|)``, it asks ``z >= -s_z``, ``w >= -s_w`` and,
    for each i, ``z_i <= s_z`` or ``|w_i| <= s_w``."""
    M = as_matrix(M)
    q = as_vector(q, M.shape[0], "q")
    z = as_vector(z, M.shape[0], "z")
    return check_lcp(M, q, z, float(tol))[1]


def is_lcp_ray(M, q, d, z, z0, ray, tol: float = 1e-9) -> bool:
    """Whether ``(z, z0) + t * ray`` is an almost-complementary ray of the augmented system.

    With ``u = M z + q + d z0`` and ``du = M dz + d dz0`` this asks: the direction is
    non-zero and non-negative, u and du are non-negative, and every pair stays
    complementary along the ray (``z_i u_i``, ``z_i du_i``, ``dz_i u_i`` and ``dz_i du_i``
    all vanish), all within the tolerance.  For copositive-plus M (positive semidefinite M
    included) such a ray proves that the LCP has no feasible point.
    """
    M = np.asarray(M, dtype=np.float64)
    q, d, z = (np.asarray(a, dtype=np.float64) for a in (q, d, z))
    ray = np.asarray(ray, dtype=np.float64)
    n = q.size
    dz, dz0 = ray[:n], float(ray[n])
    r_max = float(np.max(np.abs(ray)))
    if r_max == 0.0 or dz0 < -tol * r_max or np.any(dz < -tol * r_max):
        return False
    u = M @ z + q + d * z0
    du = M @ dz + d * dz0
    s_z, s_u = lcp_scales(M, q, z, tol)
    s_u += tol * float(np.max(np.abs(d))) * abs(z0)
    s_du = tol * r_max * max(float(np.max(np.abs(M))), float(np.max(np.abs(d))))
    s_dz = tol * r_max
    if np.any(z < -s_z) or np.any(u < -s_u) or np.any(du < -s_du):
        return False
    z_zero = z <= s_z
    dz_zero = dz <= s_dz
    u_zero = np.abs(u) <= s_u
    du_zero = np.abs(du) <= s_du
    return bool(np.all((z_zero | (u_zero & du_zero)) & (dz_zero | (u_zero & du_zero))))
