"""The acceptance test of a solution, row by row (see lemke._options for the rule).

Every row is judged against its own size: with ``r_i = |M_i.| |z| + |q_i|`` (the sizes of
the terms that make up w_i) a point passes row i when ``w_i >= -t r_i`` and, if z_i is not
zero, ``|w_i| <= t r_i``, where ``t = tol + (n + 2) eps`` (the tolerance plus the rounding
of computing one row of M z + q).  This is the componentwise backward error of Oettli and
Prager: the point is an exact solution of a problem whose every entry of M and q moved by at
most a relative t.  No row can hide behind another row's magnitude, and multiplying rows
or columns of M by positive scales changes nothing.

One allowance is added for the rounding of the data itself: in the row-equilibrated units
(rows scaled by the powers of two R of ``linalg.equilibrate``, which undo any scaling the
rows came in), an entry of q below ``(n + 2) eps max_k R_k |q_k|`` cannot be told from zero
(a contact LCP's q_i = -2e-15 next to q_j = 5 is the rounding of a product that is zero), so
row i may miss by ``f_i = (n + 2) eps max_k R_k |q_k| / R_i``: ``s_w,i = t r_i + f_i``.  It is
rounding, not a tolerance, and it does not change when a row of (M, q) is scaled.

A z_i counts as zero when setting it to zero would move every w_j by at most row j's
allowance: ``|z_i| <= min_j (t r_j + f) / |M_ji|`` over the j with M_ji != 0 (0 when column i
is zero), with f the rounding floor below.

A point so large that the rounding of M z dwarfs the data is never accepted, whatever its
residual: in the row-equilibrated coordinates (rows scaled by the powers of two R of
``linalg.equilibrate``), ``eps max_i R_i |M_i.| |z| <= CERTIFIABLE * t * max(max_i R_i |q_i|,
1)``.  (A pivot on rounding noise can give |z| ~ 1e16 on data of size 1; such a z passes
every backward-error test, since any nearby singular matrix has one, but it answers a
different problem.)
"""
import numpy as np

from . import inline_kernel, kernel
from .linalg import row_dot_and_size, equilibrate

EPS = np.finfo(np.float64).eps
CERTIFIABLE = 1e3


@kernel
def zero_size(M, rows, i, t, floors):
    """The largest z_i that counts as zero: zeroing it moves no w_j by more than that row's
    allowance ``t rows[j] + floors[j]``: ``min_j (t rows[j] + floors[j]) / |M_ji|`` over
    M_ji != 0 (0 when column i is zero)."""
    s = np.inf
    for j in range(M.shape[0]):
        a = abs(M[j, i])
        if a > 0.0:
            s = min(s, (t * rows[j] + floors[j]) / a)
    return s if s < np.inf else 0.0


@kernel
def lcp_check(M, q, z, tol, w):
    """Fill ``w = M z + q`` and return ``(is_solution, residual)`` where residual is
    ``max_i |min(z_i, w_i)|``."""
    n = q.shape[0]
    R = np.empty(n)
    C = np.empty(n)
    equilibrate(M, q, R, C)
    return lcp_check_sized(M, q, z, tol, w, R)


@kernel
def lcp_check_sized(M, q, z, tol, w, R):
    """``lcp_check`` when the caller already has the row scales R of ``equilibrate``."""
    n = q.shape[0]
    work = np.empty(2 * n)  # one allocation: it costs about as much as the check at small n
    return check_rows(M, q, z, tol, w, R, work, np.False_)


@kernel
def lcp_check_early(M, q, z, tol, w, R, work):
    """:func:`check_rows` in its early mode, compiled as a function of its own (inlined into
    a large kernel it ran a few per cent slower): the verdict on a point that will mostly
    fail, with the work array (2n floats) given."""
    return check_rows(M, q, z, tol, w, R, work, np.True_)


@inline_kernel
def check_rows(M, q, z, tol, w, R, work, early):
    """The check of :func:`lcp_check_sized`, with its work array (2n floats) given.
    ``early``: stop at the first row that fails, and return ``(False, 0.0)`` with ``w``
    only partly written -- for a caller that only needs the verdict on a point that will
    mostly fail (a warm start's old basis): the verdict is the same, and a point that
    passes gets the same ``w`` and residual, bit for bit.  Rows are judged in order:
    first every ``w_i >= -s_w`` while w is computed (a wrong basis mostly fails there, at
    O(n) a row), then the certifiability bound, then the rows with z_i > 0 (whose
    ``zero_size`` reads a column of M)."""
    n = q.shape[0]
    t = tol + (n + 2) * EPS
    rows, floors = work[:n], work[n:]
    big = 0.0
    data = 1.0
    q_top = 0.0  # the largest |q_i| in the row-equilibrated units
    for i in range(n):
        q_top = max(q_top, R[i] * abs(q[i]))
    for i in range(n):
        mz, size = row_dot_and_size(M, i, z, n)
        w[i] = q[i] + mz
        rows[i] = size + abs(q[i])
        floors[i] = (n + 2) * EPS * q_top / R[i]  # rounding of q's largest row, in row i's units
        big = max(big, R[i] * size)
        data = max(data, R[i] * abs(q[i]))
        if early:
            wi = w[i]
            if wi < -(t * rows[i] + floors[i]) or not (wi == wi and z[i] == z[i]):
                return False, 0.0
    ok = EPS * big <= CERTIFIABLE * t * data
    if early and not ok:
        return False, 0.0
    residual = 0.0
    for i in range(n):
        zi = z[i]
        wi = w[i]
        residual = max(residual, abs(min(zi, wi)))
        s_w = t * rows[i] + floors[i]
        if wi < -s_w or not (wi == wi and zi == zi):
            ok = False
        elif zi < 0.0 or (zi > 0.0 and abs(wi) > s_w):
            if abs(zi) > zero_size(M, rows, i, t, floors):
                ok = False
        if early and not ok:
            return False, 0.0
    return ok, residual


@kernel
def lcp_ray_check(M, q, d, z, z0, ray, tol):
    """Whether ``(z, z0) + t ray`` (t >= 0) is a secondary ray of the augmented system
    ``u = M z + q + d z0``, judged row by row as :func:`lcp_check_sized` judges a solution:
    the direction is non-negative and its z part dz is non-zero, u and du = M dz + d dz0
    stay non-negative, and in every pair either z_i and dz_i are zero or u_i and du_i are.

    **dz must not be zero.**  A direction with dz = 0 is the *primary* ray (z = 0, z0
    growing from its start; complementarity with du = d dz0 > 0 forces z = 0 there), which
    every LCP has and which proves nothing.  Lemke's method leaves it at its first pivot and
    never comes back in exact arithmetic; the proof that a secondary ray certifies
    infeasibility (copositive-plus M: dz' M dz = -dz0 dz'd <= 0 gives dz0 = 0, then
    (M + M') dz = 0 and dz'q < 0 separates q from the feasible set) needs dz >= 0, dz != 0.
    In floating point "non-zero" is measured against the whole direction: in the
    equilibrated units (z = C z~, and z0 in the units where the covering column R d has
    largest entry 1) an entry of dz below ``g = (n + 3) eps`` times the largest entry of
    the direction, dz0 included, is rounding, so a dz that is rounding next to dz0 is the
    primary ray too.  (On a contact pile of issue 11 rounding brought the unrevised method
    back to the primary ray after 80 pivots: dz = 0 exactly, z = 0.)

    **z0 must not be rounding where the ray moves.**  Along a secondary ray u_i = 0 in every
    row with dz_i > 0, so there ``w_i = (M z + q)_i = -d_i z0 < 0``: z0 is what keeps the
    start from being a solution, and ``dz'q + dz'M z = -z0 dz'd < 0`` is the separation the
    infeasibility proof rests on.  So in each such row w_i must be negative beyond the
    row's allowance, ``w_i < -s_u``; if it is not, z0 was read as zero in the very rows
    that carry the proof, and the ray certifies nothing.  (Measured on two contact steps
    with solutions: z0 = 1.6e-14 and 6e-14 on rows whose q is itself rounding, -2e-14; the
    ray moved a z_j with w_j = 0, u_j = d_j z0 within its allowance; every other condition
    held.)

    As for a point, the rounding of the data is allowed for: entries of the direction below
    that bound are read as zero, so is dz0 when d dz0 is below g times the size of M dz,
    and u may miss by the rounding floor of q (in the row-equilibrated units, as there)."""
    n = q.shape[0]
    R = np.empty(2 * n)
    equilibrate(M, q, R[:n], R[n:])
    return lcp_ray_check_scaled(M, q, d, z, z0, ray, tol, R[:n], R[n:])


@kernel
def lcp_ray_check_scaled(M, q, d, z, z0, ray, tol, R, C):
    """:func:`lcp_ray_check` when the caller already has the scales R, C of
    ``equilibrate(M, q)`` (the LCP kernels keep them in their output buffer)."""
    n = q.shape[0]
    g = (n + 3) * EPS
    t = tol + g
    if not z0 == z0:
        return False
    for j in range(n + 1):
        if not abs(ray[j]) < np.inf:
            return False
    work = np.empty(8 * n + 1)  # one allocation for the eight work vectors below
    dz = work[: n + 1]
    floors, no_floor = work[n + 1 : 2 * n + 1], work[2 * n + 1 : 3 * n + 1]
    ru, rdu = work[3 * n + 1 : 4 * n + 1], work[4 * n + 1 : 5 * n + 1]
    u, w, du = work[5 * n + 1 : 6 * n + 1], work[6 * n + 1 : 7 * n + 1], work[7 * n + 1 :]
    # Rounding in the direction: an entry of dz below g times the largest entry of the
    # direction (in the equilibrated units of the columns, dz0 included in the units where
    # the covering column R d has largest entry 1) is zero; so is dz0 when its contribution
    # d dz0 is below g times the size of M dz (dz0 has the units of z0, not of z).
    d_max = 0.0
    d_top = 0.0
    for i in range(n):
        d_max = max(d_max, abs(d[i]))
        d_top = max(d_top, R[i] * abs(d[i]))
    top = abs(ray[n]) * d_top
    for j in range(n):
        top = max(top, abs(ray[j]) / C[j])
    nonzero = False
    for j in range(n):
        dz[j] = ray[j] if abs(ray[j]) / C[j] > g * top else 0.0
        nonzero |= dz[j] != 0.0
    if not nonzero:
        return False  # dz = 0 (to rounding): the primary ray, no certificate (docstring)
    mdz = 0.0
    for i in range(n):
        mdz = max(mdz, row_dot_and_size(M, i, dz, n)[1])
    dz[n] = ray[n] if abs(ray[n]) * d_max > g * mdz else 0.0
    dz0 = dz[n]
    if dz0 < 0.0:
        return False
    q_top = 0.0
    for i in range(n):
        q_top = max(q_top, R[i] * abs(q[i]))
    for i in range(n):
        floors[i] = g * q_top / R[i]
    no_floor[:] = 0.0
    for i in range(n):
        mz, sz = row_dot_and_size(M, i, z, n)
        w[i] = q[i] + mz
        u[i] = w[i] + d[i] * z0
        ru[i] = abs(q[i]) + sz + abs(d[i] * z0)
        md, sd = row_dot_and_size(M, i, dz, n)
        du[i] = md + d[i] * dz0
        rdu[i] = sd + abs(d[i] * dz0)
    for i in range(n):
        s_u = t * ru[i] + floors[i]
        s_du = t * rdu[i]
        if not (u[i] >= -s_u and du[i] >= -s_du):
            return False
        flat = abs(u[i]) <= s_u and abs(du[i]) <= s_du
        zi = z[i]
        di = dz[i]
        if (zi < 0.0 or (zi > 0.0 and not flat)) and abs(zi) > zero_size(M, ru, i, t, floors):
            return False
        if (di < 0.0 or (di > 0.0 and not flat)) and abs(di) > zero_size(M, rdu, i, t, no_floor):
            return False
        if di > 0.0 and not w[i] < -s_u and abs(di) > zero_size(M, rdu, i, t, no_floor):
            return False  # z0 is rounding in a row the ray moves: no certificate (docstring)
    return True
