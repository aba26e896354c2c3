"""Checks made on the caller's data: is a point a solution, is a direction a ray.

The same functions serve the solver (to accept or downgrade a result), the tests and the
benchmarks, so every part of the project judges answers the same way.
"""
from __future__ import annotations

import numpy as np

from ._validate import square_matrix, vector
from .kernels import certify

def lcp_residual(z: np.ndarray, w: np.ndarray) -> float:
    """``max_i |min(z_i, w_i)|``: zero exactly when z, w >= 0 and z'w = 0."""
    return float(np.max(np.abs(np.minimum(z, w)))) if z.size else 0.0


def check_lcp(M: np.ndarray, q: np.ndarray, z: np.ndarray, tol: float):
    """``(w, is_solution, residual)`` for float64 arrays of matching shapes; w = M z + q."""
    w = np.empty_like(q)
    ok, residual = certify.lcp_check(M, q, z, tol, w)
    return w, bool(ok), float(residual)


def is_lcp_solution(M, q, z, tol: float = 1e-9) -> bool:
    """Whether z solves the LCP (M, q) within the relative tolerance ``tol``, row by row:
    with ``r_i = |M_i.| |z| + |q_i|`` and ``t = tol + (n + 2) eps``, every row has
    ``w_i >= -t r_i``, and ``|w_i| <= t r_i`` unless z_i is zero (small enough that zeroing
    it moves no w_j by more than ``t r_j``); z >= 0 in the same sense; and z is not so large
    that the rounding of M z dwarfs the data (see ``lemke.kernels.certify``)."""
    M = square_matrix(M)
    q = vector(q, M.shape[0], "q")
    z = vector(z, M.shape[0], "z")
    return check_lcp(M, q, z, float(tol))[1]


def is_lcp_ray(M, q, d, z, z0, ray, tol: float = 1e-9) -> bool:
    """Whether ``(z, z0) + t * ray`` is an almost-complementary ray of the augmented system.

    With ``u = M z + q + d z0`` and ``du = M dz + d dz0`` this asks, row by row (each row
    against the size of its own terms, as :func:`is_lcp_solution` does): the direction is
    non-zero and non-negative, u and du are non-negative, and every pair stays
    complementary along the ray (z_i and dz_i are zero, or u_i and du_i are).  For
    copositive-plus M (positive semidefinite M included) such a ray proves that the LCP has
    no feasible point.
    """
    M = square_matrix(M)
    n = M.shape[0]
    q, d, z = (vector(a, n, name) for a, name in ((q, "q"), (d, "d"), (z, "z")))
    ray = vector(ray, n + 1, "ray")
    return bool(certify.lcp_ray_check(M, q, d, z, float(z0), ray, float(tol)))
