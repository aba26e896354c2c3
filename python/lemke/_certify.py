"""Acceptance, every kind's, in one module: is a point a solution, is a direction a ray, is
a certificate a proof -- on the caller's data.

The same functions serve the solvers (to accept or downgrade a result), the tests and the
benchmarks, so every part of the project judges answers the same way.  Every check that
decides "solved" is reachable here by name: the LCP's (``check_lcp``, ``is_lcp_solution``,
``is_lcp_ray``), the MLCP's (``check_mlcp``, ``is_mlcp_ray``), the box LCP's
(``box_check``, ``check_scales``, ``is_box_ray``), the QP's (``kkt_check``; the Farkas
vectors and descent directions of a ``Certificate``: ``check_farkas``,
``check_direction``) and the games' (``games_check``); the fronts call them through this
module.  Their code in the C++ core is one module too, ``src/lemke/certify.{hpp,cpp}``
(the LCP's row-wise check, which the kernels fuse into every solve and which *is* the LCP
rule below: ``check_lcp`` calls it, and ``tests/test_certify.py`` checks that the check
inside a solve gives the verdict of ``is_lcp_solution``; the MLCP's; ``boxed::box_check``,
``coupled_check``, ``friction_check``, ``is_ray``; ``qp::kkt_check``; ``games::check``),
where the engines call them.

**What ``tol`` means** (``Options.tol``, default 1e-9, always relative).  Every test
compares a quantity that is zero (or non-negative) in exact arithmetic with ``tol`` times
the size of the terms it is formed from, plus the rounding of forming it:

* **LCP point** (``check_lcp``, ``is_lcp_solution``; ``src/lemke/certify.hpp``): made on the
  caller's data row by row: with ``r_i = |M_i.| |z| + |q_i|`` (the componentwise backward
  error), ``t = tol + (n + 2) eps`` and f_i the rounding of q's largest entry in row i's
  equilibrated units, ``w_i >= -(t r_i + f_i)``, and ``|w_i| <= t r_i + f_i`` unless z_i is
  zero (small enough that zeroing it moves no w_j by more than row j's allowance); z >= 0
  in the same sense; and z must be small enough to be certified at all (in the
  row-equilibrated coordinates, ``eps max_i R_i |M_i.| |z| <= CERTIFIABLE t max(max_i R_i
  |q_i|, 1)``, CERTIFIABLE = 1000: a z such as the |z| ~ 1e16 of a pivot on rounding noise
  answers a different problem).
* **MLCP point** (``check_mlcp``): the LCP rule above on the stacked system ``E x + e``,
  against the size of the whole stacked system (its rows have no common scale once a QP's
  KKT rows are stacked), with ``E x + e`` summed in double-double (its rounding
  allowance EPS_EXT, x86's long double epsilon) and the same ``CERTIFIABLE`` bound.
* **Box LCP point** (``box_check``, with the scales of ``check_scales``): the LCP's t,
  r_i, f_i and certifiability bound, applied to the natural map: z within its bounds (a
  fixed z_i exactly at it), and a w_i beyond ``t r_i + f_i`` in either sign needs z_i at
  the bound it pushes against (its distance from it small enough to count as zero, as for
  an LCP's z_i); with a friction index the caller's z is judged so on the caller's rows,
  with the bounds in force ``-+mu_i z_f`` (z clamped into them first) and the rounding of
  the extended problem's size (``coupled_check``, ``friction_check`` in the core).
* **QP KKT point** (``kkt_check``; ``qp::kkt_check``, the fused path at
  ``min(tol, 1e-12)``; the KKT-MLCP path's answers by the MLCP test of their KKT system,
  reported in qpsolvers' terms): with ``t = tol + 4 eps`` and ``f = 4 (n + 2) eps``,
  stationarity row j may be off by ``t s_j + f (|P_.j|_1 max|x| + |A_.j|_1 max|y| +
  |G_.j|_1 max|z| + max|z_box|)`` (s_j the sum of the sizes of the row's terms), an
  equality or inequality row i by ``t s_i + f max|x| |row_i|_1``, a bound by
  ``t (|bound| + |x_j|) + f max|x|``; z >= 0 and the signs of z_box exactly; a
  multiplier that is not zero needs its row active to within that allowance, or must be
  small enough to count as zero (as must z_i where h_i = +inf).  The ``f`` terms are the
  rounding floor: a computed vector is exact only to about f times its largest entry
  (normwise, not entry by entry), so a row whose terms are all at the rounding level (an
  exact 0 that comes out as 1e-15) is judged against what that rounding can move it by,
  not against 1e-12 of its own tiny terms (``tests/test_qp_kkt_check.py`` states the rule).
* **Game** (``games_check``; ``games::check``): x and y are distributions (no negative
  entry, each sums to 1 within 1e-12 times its length), and each player's regret is at most
  ``tol`` times the range of that player's payoffs, plus rounding (64 eps (m + n) times the
  payoffs' largest size).
* **Directions** -- an LCP ray (``is_lcp_ray``), a box LCP ray (``is_box_ray``), an MLCP
  ray (``is_mlcp_ray``), a Farkas vector (``check_farkas``) and a direction of unbounded
  descent (``check_direction``): normalized to largest entry 1, each condition against
  ``tol`` times the data's size, times ``RAY_SLACK`` (a direction is formed by subtracting
  two points, each accepted with the point allowance).  The LCP ray is judged row by row
  like an LCP point instead (``src/lemke/certify.hpp``), and its z part must be non-zero
  next to the whole direction: a direction that only moves z0 is the primary ray, which
  every LCP has; the box LCP ray row by row too (``boxed::is_ray``).
"""
from __future__ import annotations


import numpy as np

from ._frozen import frozen
from . import _core, _npc
from ._core import boxed  # the box engine's bindings (its checks: at the end)
from ._result import Value
from ._validate import c_aligned, kernel_array, square_matrix, vector

#: The certifiability bound (src/lemke/certify.hpp; the module docstring).
CERTIFIABLE = _core.CERTIFIABLE

EPS = float(np.finfo(np.float64).eps)
#: The rounding allowance of ``E x + e`` in check_mlcp: x86's long double epsilon, in which
#: it was once computed; the double-double sums (``residual2`` of the C++ core,
#: ``src/lemke/linalg.cpp``) are more accurate than that, on every platform alike.
EPS_EXT = 2.0 ** -63
RAY_SLACK = 10.0  # directions (rays, Farkas vectors, descent) get 10x the point's allowance


def lcp_residual(z: np.ndarray, w: np.ndarray) -> float:
    """``max_i |min(z_i, w_i)|``: zero exactly when z, w >= 0 and z'w = 0."""
    return float(np.max(np.abs(np.minimum(z, w)))) if z.size else 0.0


def check_lcp(M: np.ndarray, q: np.ndarray, z: np.ndarray, tol: float):
    """``(w, is_solution, residual)`` for float64 arrays of matching shapes; w = M z + q."""
    w = np.empty_like(q)
    ok, residual = _core.lcp_check(M, q, z, tol, w)
    return w, bool(ok), float(residual)


def is_lcp_solution(M, q, z, tol: float = 1e-9) -> bool:
    """Whether z solves the LCP (M, q) within the relative tolerance ``tol``, row by row:
    with ``r_i = |M_i.| |z| + |q_i|`` and ``t = tol + (n + 2) eps``, every row has
    ``w_i >= -t r_i``, and ``|w_i| <= t r_i`` unless z_i is zero (small enough that zeroing
    it moves no w_j by more than ``t r_j``); z >= 0 in the same sense; and z is not so large
    that the rounding of M z dwarfs the data (see ``src/lemke/certify.hpp``)."""
    M = square_matrix(M)
    q = vector(q, M.shape[0], "q")
    z = vector(z, M.shape[0], "z")
    return check_lcp(M, q, z, float(tol))[1]


def is_lcp_ray(M, q, d, z, z0, ray, tol: float = 1e-9) -> bool:
    """Whether ``(z, z0) + t * ray`` is an almost-complementary ray of the augmented system.

    With ``u = M z + q + d z0`` and ``du = M dz + d dz0`` this asks, row by row (each row
    against the size of its own terms, as :func:`is_lcp_solution` does): the direction is
    non-negative and its z part dz is non-zero (not rounding next to the rest of the
    direction, dz0 included: dz = 0 is the primary ray, which every LCP has), u and du are
    non-negative, and every pair stays complementary along the ray (z_i and dz_i are zero,
    or u_i and du_i are).  For copositive-plus M (positive semidefinite M included) such a
    ray proves that the LCP has no feasible point.
    """
    M = square_matrix(M)
    n = M.shape[0]
    q, d, z = (vector(a, n, name) for a, name in ((q, "q"), (d, "d"), (z, "z")))
    ray = vector(ray, n + 1, "ray")
    return bool(_core.lcp_ray_check(M, q, d, z, float(z0), ray, float(tol)))


# ----------------------------------------------------------------------------- MLCP

def check_mlcp(E, e, n, x, tol):
    """``(w, ok, residual)`` for the stacked MLCP ``E x + e = (0, w)``: the LCP acceptance
    rule (the module docstring) on the pairs, and ``|equation| <= s_w`` on the
    equations, with the tolerances taken from the whole stacked system and ``E x + e``
    summed in double-double (its rounding allowance, EPS_EXT, is that of x86's long
    double).  In the C++ core (``check_mlcp`` in ``src/lemke/certify.cpp``): the numbers of
    :func:`_check_mlcp_numpy`, bit for bit."""
    c = c_aligned
    y = np.empty(e.size)
    ok, residual = _core.check_mlcp(c(E, dtype=np.float64), c(e, dtype=np.float64), int(n),
                                    c(x, dtype=np.float64), float(tol), y)
    return y[n:], ok, residual


def _check_mlcp_numpy(E, e, n, x, tol, residual2):
    """:func:`check_mlcp` in numpy, ``residual2(E, x, e, y)`` summing ``E x + e`` (the
    reference of the core's bits, for the tests)."""
    N = e.size
    # In double-double, so that the test needs no allowance for rounding in computing E x
    # beyond EPS_EXT (an allowance of eps would grow with |x| and pass any huge x).
    y = np.empty(N)
    c = c_aligned
    residual2(c(E, dtype=np.float64), c(x, dtype=np.float64), c(e, dtype=np.float64), y)
    e_max, E_max = absmax(e), absmax(E)
    s_z = tol * max(absmax(x), e_max / E_max if E_max > 0.0 else 0.0)
    s_w = tol * max(e_max, E_max) + 4.0 * N * EPS_EXT * E_max * absmax(x)
    v, w = x[n:], y[n:]
    res_eq = absmax(y[:n])
    # A point so large that rounding it to double moves E x by far more than the tolerance
    # cannot be certified (such points, |x| ~ 1e16 on data ~ 1, come from pivots on noise).
    certifiable = EPS * E_max * absmax(x) <= CERTIFIABLE * tol * max(e_max, E_max)
    ok = certifiable and res_eq <= s_w and bool(
        np.all(v >= -s_z) and np.all(w >= -s_w) and np.all((v <= s_z) | (np.abs(w) <= s_w))
    )
    residual = max(res_eq, float(np.max(np.abs(np.minimum(v, w)))) if v.size else 0.0)
    return w, ok, residual


absmax = _npc.absmax


def is_mlcp_ray(E, n, direction, tol) -> bool:
    """Whether ``direction = (du, dv)`` is a homogeneous direction of the MLCP: non-zero,
    ``A du + C dv = 0``, ``dv >= 0``, ``dw = D du + B dv >= 0`` and ``dv ⊥ dw``, within
    ``tol`` relative to its size and the size of E."""
    scale = absmax(direction)
    if scale == 0.0:
        return False
    d = direction / scale
    y = E @ d
    s = tol * max(absmax(E), 1.0) * RAY_SLACK
    dv, dw = d[n:], y[n:]
    return bool(
        absmax(y[:n]) <= s
        and np.all(dv >= -tol)
        and np.all(dw >= -s)
        and np.all((dv <= tol) | (np.abs(dw) <= s))
    )


# ----------------------------------------------------------------------------- QP

@frozen(eq=False)
class Certificate(Value):
    """A proof that a QP has no optimum, checkable with its data alone.

    ``kind == "primal_infeasible"``: a Farkas vector ``(y, z, z_box)`` with ``z >= 0``,
    ``z_box_j <= 0`` only where lb_j is finite and ``>= 0`` only where ub_j is finite, and
    ``G'z + A'y + z_box = 0``, while ``value = h'z + b'y + lb'min(z_box, 0) +
    ub'max(z_box, 0) < 0``: for any feasible x, ``0 = (G'z + A'y + z_box)'x <= value < 0``.

    ``kind == "dual_infeasible"``: a direction ``dx`` with ``P dx = 0``, ``A dx = 0``,
    ``G dx <= 0``, ``dx_j >= 0`` where only lb_j is finite, ``<= 0`` where only ub_j is,
    ``= 0`` where both are, and ``value = q'dx < 0``: the objective decreases without bound
    along it from any feasible point.

    Both are scaled to largest entry 1.  A QP that is both primal and dual infeasible is
    reported primal infeasible, and its ``"primal_infeasible"`` certificate then holds both
    proofs: the Farkas vector ``(y, z, z_box)`` with its ``value``, and in ``dx`` a
    direction as above (``q'dx < 0``; not part of ``value``), each checked on its own.  On
    a ``"primal_infeasible"`` certificate ``dx`` is None when no such direction was found.
    """

    kind: str
    value: float
    y: np.ndarray | None = None
    z: np.ndarray | None = None
    z_box: np.ndarray | None = None
    dx: np.ndarray | None = None


def normalized(*parts):
    size = max((float(np.max(np.abs(p))) for p in parts if p.size), default=0.0)
    if size == 0.0:
        return None
    return [p / size for p in parts]


def farkas_value(qp, y, z, z_box):
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    return (float(qp.h @ z + qp.b @ y) + float(qp.lb[lo] @ np.minimum(z_box[lo], 0.0))
            + float(qp.ub[up] @ np.maximum(z_box[up], 0.0)))


def data_scale(qp):
    return max([1.0] + [float(np.max(np.abs(a))) for a in (qp.P, qp.G, qp.A, qp.q, qp.h, qp.b) if a.size])


def check_farkas(qp, y, z, tol):
    """A verified primal-infeasibility Certificate from (y, z), or None."""
    parts = normalized(y, z)
    if parts is None:
        return None
    y, z = parts
    if np.any(z < -tol):
        return None
    z = np.maximum(z, 0.0)
    z_box = -(qp.A.T @ y + qp.G.T @ z)
    s = tol * data_scale(qp) * RAY_SLACK
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    # a bound multiplier may only have the sign of a finite bound
    if np.any(z_box[~lo] < -s) or np.any(z_box[~up] > s):
        return None
    z_box[~lo] = np.maximum(z_box[~lo], 0.0)
    z_box[~up] = np.minimum(z_box[~up], 0.0)
    residual = absmax(qp.A.T @ y + qp.G.T @ z + z_box)
    value = farkas_value(qp, y, z, z_box)
    bound = max(1.0, absmax(qp.lb[lo]), absmax(qp.ub[up]))
    if residual > s or value >= -s * bound:
        return None
    return Certificate("primal_infeasible", value, y=y, z=z, z_box=z_box)


def check_direction(qp, dx, tol):
    """A verified dual-infeasibility Certificate from dx, or None."""
    parts = normalized(dx)
    if parts is None:
        return None
    (dx,) = parts
    s = tol * data_scale(qp) * RAY_SLACK
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    if (np.any(dx[lo] < -tol) or np.any(dx[up] > tol)
            or absmax(qp.P @ dx) > s or absmax(qp.A @ dx) > s
            or (qp.h.size and float(np.max(qp.G @ dx)) > s)):
        return None
    dx = dx.copy()
    dx[lo] = np.maximum(dx[lo], 0.0)
    dx[up] = np.minimum(dx[up], 0.0)
    value = float(qp.q @ dx)
    if value >= -s:
        return None
    return Certificate("dual_infeasible", value, dx=dx)


# ----------------------------------------------------------------------------- box LCPs, QPs, games
# Their checks run in the core (src/lemke/certify.cpp, the engines call them there); the
# fronts reach them here, by these names.  The kernels are bound once, at import (a front's
# call costs what a call of the kernel costs).


#: ``box_check(M, q, lo, hi, z, tol, w, R, n_round=0) -> (ok, residual)``: a box LCP's
#: point on the caller's data (the module docstring), w = M z + q into w; R the row scales
#: of :data:`check_scales` (or of the run); n_round the size whose rounding is allowed for.
box_check = boxed.box_check
#: ``check_scales(M, q, lo, hi, R, C)``: the scales :data:`box_check` judges with when no
#: run made them (the equilibration of M and q + M p, p the point of the bounds nearest 0).
check_scales = boxed.check_scales
#: ``games_check(A, B, x, y, tol, out) -> ok``: whether (x, y) is an equilibrium of (A, B)
#: (the module docstring); out (3) gets (regret, row payoff, column payoff).
games_check = _core.games_check
_QP_KKT = _core.qp_kkt_check


def is_box_ray(M, q, lo, hi, d, z, z0, ray, tol=1e-9) -> bool:
    """Whether ``(z, z0) + t ray`` (t >= 0) stays a solution of the augmented box problem
    (w + d z0 in place of w) for every t, judged row by row on the caller's data
    (``boxed::is_ray``, which says how)."""
    a = [kernel_array(np.asarray(x, dtype=float)) for x in (M, q, lo, hi, d, z, ray)]
    return bool(boxed.is_ray(*a[:6], float(z0), a[6], float(tol)))


def kkt_check(data, x, y, z, z_box, tol):
    """``(ok, primal, dual, gap, obj)`` on the validated data ``(P, q, G, h, A, b, lb, ub)``
    (absent rows empty, absent bounds infinite): whether the point passes the fused path's
    row-wise KKT check (``qp::kkt_check``) at ``tol``, and qpsolvers' residuals and
    the objective, each summed there in double-double (their values at the point as given,
    not the rounding of evaluating them)."""
    stats = np.empty(4)
    c = c_aligned
    P, q, G, h, A, b, lb, ub = data
    ok = _QP_KKT(c(P), q, c(G), h, c(A), b, lb, ub, c(x), c(y), c(z), c(z_box), tol, stats)
    return (bool(ok), *stats.tolist())
