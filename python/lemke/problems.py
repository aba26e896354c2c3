"""Named problems from the literature and random generators (shared by tests, benchmarks and
the command line).  Each named problem is a function returning a :class:`lemke.Problem`;
``NAMED`` maps the names that ``lemke problems`` lists to them."""
from __future__ import annotations

import numpy as np

from ._problem import Problem

__all__ = ["NAMED", "Problem", "bimatrix", "bimatrix_lcp", "contact_box", "contact_like", "cps_447", "degenerate",
           "hs21", "murty", "random_p_matrix", "random_psd"]


def cps_447() -> Problem:
    """Cottle-Pang-Stone Example 4.4.7: the running example of the pivot_column note."""
    M = np.array([[0.0, -1.0, 2.0], [2.0, 0.0, -2.0], [-1.0, 1.0, 0.0]])
    q = np.array([-3.0, 6.0, -1.0])
    return Problem.lcp(M, q, name="cps-4.4.7", source="Cottle, Pang & Stone (1992), Example 4.4.7; solution z = (0, 1, 3)")


def murty(n: int = 6) -> Problem:
    """Murty's exponential example: M upper triangular, 1 on the diagonal and 2 above it,
    q_i = -(2^(n+1) - 2^i) for i = 1..n.  Lemke with d = 1 takes 2^n pivots (counting the
    first one); the solution is z = (0, ..., 0, 2^n)."""
    M = np.triu(np.full((n, n), 2.0), 1) + np.eye(n)
    q = -(2.0 ** (n + 1) - 2.0 ** np.arange(1, n + 1))
    return Problem.lcp(M, q, name=f"murty-{n}", source=f"Murty (1988), Linear Complementarity, chapter 6; Lemke takes 2^{n} pivots")


def degenerate() -> Problem:
    """A singular PSD problem on which the plain argmin ratio test ends on a false ray."""
    M = np.array([[4.0, -4.0], [-4.0, 4.0]])
    q = np.array([2.0, -2.0])
    return Problem.lcp(M, q, name="degenerate", source="lemke's issue tracker (a plain ratio test ends on a false ray); a solution is z = (0, 0.5)")


_GAME_A = [[3.0, 3.0], [2.0, 5.0], [0.0, 6.0]]
_GAME_B = [[3.0, 2.0], [2.0, 6.0], [3.0, 1.0]]


def bimatrix() -> Problem:
    """The 3 x 2 example game of von Stengel (2002), payoffs A to the row player and B to
    the column player: a ``bimatrix`` problem, solved by Lemke-Howson
    (:func:`lemke.solve_bimatrix`).  It has three equilibria: x = (1, 0, 0), y = (1, 0)
    (Lemke-Howson dropping label 0 finds it), x = (0, 1/3, 2/3), y = (1/3, 2/3) and
    x = (4/5, 1/5, 0), y = (2/3, 1/3) (only :func:`lemke.lemke_paths` reaches it)."""
    return Problem.bimatrix(_GAME_A, _GAME_B, name="bimatrix", source=(
        "von Stengel (2002), Computing equilibria for two-person games, 3 x 2 example; "
        "equilibria x = (1, 0, 0), y = (1, 0); (0, 1/3, 2/3), (1/3, 2/3); (4/5, 1/5, 0), (2/3, 1/3)"))


def bimatrix_lcp() -> Problem:
    """The same game as the LCP of Lemke & Howson (1964): with the costs
    A' = 7 - A > 0 and B' = 7 - B > 0, find x, y >= 0 with A' y - 1 >= 0 _|_ x and
    B'^T x - 1 >= 0 _|_ y; x / sum(x), y / sum(y) is then an equilibrium.  Lemke's method with
    a covering vector ends on a secondary ray here (this M is not copositive-plus; the
    Lemke-Howson start from the artificial equilibrium is needed), although the game has
    three equilibria, e.g. the pure one x = (1, 0, 0), y = (1, 0)."""
    A, B = np.array(_GAME_A), np.array(_GAME_B)
    m, k = A.shape
    M = np.block([[np.zeros((m, m)), 7.0 - A], [(7.0 - B).T, np.zeros((k, k))]])
    return Problem.lcp(M, -np.ones(m + k), name="bimatrix-lcp", source=(
        "von Stengel (2002), Computing equilibria for two-person games, 3 x 2 example, as the "
        "Lemke-Howson LCP; Lemke with d = 1 ends on a ray (equilibria exist, e.g. x = (1, 0, 0), y = (1, 0))"))


def contact_box() -> Problem:
    """One time step of a box (1 x 0.6 x 0.4, mass 1) falling flat onto the ground at 1 m/s,
    with frictionless contact points at the 4 bottom corners and a redundant fifth at the centre
    of the bottom face.  Velocity-level scheme (Stewart & Trinkle 1996, Anitescu & Potra 1997):
    M = J W J' (rank 3 for 5 contacts, so the impulses are not unique), q = J (v + h W f) with
    h = 0.01 and gravity; the solution stops the box (J v+ = 0 where z > 0)."""
    size, mass = np.array([1.0, 0.6, 0.4]), 1.0
    inertia = mass / 12.0 * (size[[1, 0, 0]] ** 2 + size[[2, 2, 1]] ** 2)
    W = np.diag(np.r_[np.full(3, 1.0 / mass), 1.0 / inertia])
    normal = np.array([0.0, 0.0, 1.0])
    corners = [(sx * size[0] / 2, sy * size[1] / 2, -size[2] / 2) for sx in (-1, 1) for sy in (-1, 1)]
    points = corners + [(0.0, 0.0, -size[2] / 2)]
    J = np.array([np.r_[normal, np.cross(p, normal)] for p in points])
    h, v0 = 0.01, np.array([0.1, 0.0, -1.0, 0.2, 0.0, 0.0])
    v = v0 + h * W @ np.array([0.0, 0.0, -9.81 * mass, 0.0, 0.0, 0.0])
    return Problem.lcp(J @ W @ J.T, J @ v, name="contact-box", source=(
        "a box landing on a plane, 4 corner contacts + 1 redundant, one step of the "
        "Stewart-Trinkle / Anitescu-Potra scheme: M = J W J' (rank 3), q = J v"))


def hs21() -> Problem:
    """Hock & Schittkowski problem 21 as in the Maros-Meszaros set (HS21): minimize
    0.01 x1^2 + x2^2 - 100 s.t. 10 x1 - x2 >= 10, 2 <= x1 <= 50, -50 <= x2 <= 50.  The
    optimum is -99.96 at x = (2, 0)."""
    return Problem.qp(np.diag([0.02, 2.0]), np.zeros(2), G=np.array([[-10.0, 1.0]]), h=np.array([-10.0]),
                      lb=np.array([2.0, -50.0]), ub=np.array([50.0, 50.0]), objective_constant=-100.0,
                      name="hs21", source=("Hock & Schittkowski (1981) problem 21, Maros & Meszaros (1999) "
                                           "HS21; optimum -99.96 at x = (2, 0)"))


NAMED = {"cps-4.4.7": cps_447, "murty": murty, "degenerate": degenerate, "bimatrix": bimatrix,
         "bimatrix-lcp": bimatrix_lcp, "contact-box": contact_box, "hs21": hs21}


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


def random_convex_qp(n: int, rng: np.random.Generator, m: int | None = None,
                     p: int | None = None, rank: int | None = None):
    """A feasible convex QP ``(P, q, G, h, A, b, lb, ub)`` in qpsolvers' form: P = B B'/n
    (plus 1e-3 I when of full rank; rank-deficient when ``rank < n``), m inequalities
    (default n) and p equalities (default n/5) that a random point x0 satisfies, and a box
    around x0."""
    m = n if m is None else m
    p = max(1, n // 5) if p is None else p
    rank = n if rank is None else rank
    B = rng.standard_normal((n, rank))
    P = B @ B.T / n + (1e-3 * np.eye(n) if rank == n else 0.0)
    q = rng.standard_normal(n)
    x0 = rng.standard_normal(n)
    G = rng.standard_normal((m, n))
    h = G @ x0 + rng.uniform(0.0, 1.0, m)
    A = rng.standard_normal((p, n))
    b = A @ x0
    return P, q, G, h, A, b, x0 - rng.uniform(0.1, 2.0, n), x0 + rng.uniform(0.1, 2.0, n)
