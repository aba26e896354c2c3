"""Named problems from the literature and random generators (shared by tests, benchmarks and
the command line).  Each named problem is a function returning an :class:`Problem`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Problem:
    """An LCP with its provenance."""

    name: str
    M: np.ndarray
    q: np.ndarray
    source: str


def cps_447() -> Problem:
    """Cottle-Pang-Stone Example 4.4.7: the running example of the pivot_column note."""
    M = np.array([[0.0, -1.0, 2.0], [2.0, 0.0, -2.0], [-1.0, 1.0, 0.0]])
    q = np.array([-3.0, 6.0, -1.0])
    return Problem("cps-4.4.7", M, q, "Cottle, Pang & Stone (1992), Example 4.4.7; solution z = (0, 1, 3)")


def murty(n: int = 6) -> Problem:
    """Murty's exponential example: M upper triangular, 1 on the diagonal and 2 above it,
    q_i = -(2^(n+1) - 2^i) for i = 1..n.  Lemke with d = 1 takes 2^n pivots (counting the
    first one); the solution is z = (0, ..., 0, 2^n)."""
    M = np.triu(np.full((n, n), 2.0), 1) + np.eye(n)
    q = -(2.0 ** (n + 1) - 2.0 ** np.arange(1, n + 1))
    return Problem(f"murty-{n}", M, q, "Murty (1988), Linear Complementarity, chapter 6")


def degenerate() -> Problem:
    """A singular PSD problem on which the plain argmin ratio test ends on a false ray."""
    M = np.array([[4.0, -4.0], [-4.0, 4.0]])
    q = np.array([2.0, -2.0])
    return Problem("degenerate", M, q, "lemke's issue tracker; a solution is z = (0, 0.5)")


NAMED = {"cps-4.4.7": cps_447, "murty": murty, "degenerate": degenerate}


def random_psd(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """M = A A' + (B - B') scaled by 1/n: positive semidefinite plus skew (monotone)."""
    A = rng.standard_normal((n, n))
    B = rng.standard_normal((n, n))
    return (A @ A.T + B - B.T) / n, rng.standard_normal(n)


def random_p_matrix(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A nonsymmetric P-matrix (positive definite symmetric part plus skew part)."""
    A = rng.standard_normal((n, n))
    B = rng.standard_normal((n, n))
    return (A @ A.T) / n + 0.1 * np.eye(n) + (B - B.T) / n, rng.standard_normal(n)


def contact_like(n: int, rng: np.random.Generator, bodies: int | None = None):
    """A rank-deficient contact LCP: M = J W J' with more contacts than body velocities,
    repeated (redundant) contact rows and q = J v with ties, as in a rigid-body step."""
    dof = bodies * 6 if bodies else max(1, n // 2)
    J = rng.standard_normal((n, dof))
    if n >= 4:
        J[n // 2] = J[0]  # a redundant contact
        J[n - 1] = 2.0 * J[1]
    W = np.diag(rng.uniform(0.5, 2.0, dof))
    v = rng.standard_normal(dof)
    q = J @ v
    q[n // 2] = q[0]
    return J @ W @ J.T, q
