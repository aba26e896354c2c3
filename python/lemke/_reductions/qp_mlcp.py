r"""QP -> MLCP: the KKT conditions of a convex QP as a monotone mixed LCP.

The QP, in qpsolvers' convention::

    minimize    1/2 x'P x + q'x
    subject to  G x <= h,   A x = b,   lb <= x <= ub.
Each variable is put in the form that costs least: a free variable stays free (a free
variable of the MLCP, never split into two signs); a variable with one finite bound is
shifted to x' >= 0 (``x = lb + x'`` or ``x = ub - x'``); a variable with two finite bounds is
shifted and gets one extra row ``x' <= ub - lb``; a fixed variable (lb = ub) is substituted.
The equality multipliers y are free variables; the inequality multipliers z pair with the
slacks ``h - G x``.  With u = (x_free, y) and v = (x', z, z_ub), the KKT conditions are the
MLCP ``E (u, v) + e = (0, w)`` with::

            x_free    y        x'          z        z_ub
    E = [ [ P_ff      A_f'     P_fn S      G_f'     0     ]   dual rows of free x  (= 0)
          [ -A_f      0        -A_n S      0        0     ]   b - A x              (= 0)
          [ S P_nf    S A_n'   S P_nn S    S G_n'   I_box ]   dual rows of x'      (⊥ x')
          [ -G_f      0        -G_n S      0        0     ]   h - G x              (⊥ z)
          [ 0         0        -I_box      0        0     ] ] ub - lb - x'         (⊥ z_ub)

(S the signs of the shifts), whose symmetric part is P's: a monotone MLCP, so Lemke's method
solves it or ends on a ray, and the ray splits into a Farkas vector (the QP is infeasible)
or a direction of unbounded descent.
"""
from __future__ import annotations

import numpy as np

from .._npc import filled, nz, sub

EPS = float(np.finfo(np.float64).eps)


class QPToMLCP:
    """The reduction of a validated QP to the MLCP of its KKT conditions.

    ``apply``: building it fills ``E, e, n_free`` (the stacked MLCP ``E (u, v) + e = (0, w)``
    with ``n_free`` free variables first).  ``recover``: :meth:`recover` turns the MLCP's
    point into ``(x, y, z, z_box)``, :meth:`direction` a direction of it into dx; and
    :meth:`forward` maps a QP primal-dual point to the MLCP's variables (the inverse of
    ``recover`` at a KKT point, for tests and warm starts).

    The data (``P, q, G, h, A, b, lb, ub``) are kept as attributes, absent rows as empty
    blocks and absent bounds as infinities."""

    def __init__(self, P, q, G=None, h=None, A=None, b=None, lb=None, ub=None):
        self.n, self.q, self.P = n, q, P = q.size, q, P
        self.G, self.h = (np.zeros((0, n)), np.zeros(0)) if G is None else (G, h)
        self.A, self.b = (np.zeros((0, n)), np.zeros(0)) if A is None else (A, b)
        self.lb = filled(n, -np.inf) if lb is None else lb
        self.ub = filled(n, np.inf) if ub is None else ub
        self._kinds()
        self._stack()

    def _kinds(self):
        lo, up = np.isfinite(self.lb), np.isfinite(self.ub)
        fixed = lo & up & (self.lb == self.ub)
        self.free = nz(~lo & ~up)
        self.shifted = nz((lo | up) & ~fixed)  # x = x0 + sign * x', x' >= 0
        self.fixed = nz(fixed)
        self.sign = np.where(lo[self.shifted], 1.0, -1.0)
        self.boxed = nz(lo[self.shifted] & up[self.shifted])  # positions in shifted
        x0 = np.zeros(self.n)
        x0[lo] = self.lb[lo]
        x0[~lo & up] = self.ub[~lo & up]
        self.x0 = x0

    def _stack(self):
        P, G, A = self.P, self.G, self.A
        F, Nn, S = self.free, self.shifted, self.sign
        nf, nn, nb = F.size, Nn.size, self.boxed.size
        p, mg = A.shape[0], G.shape[0]
        n_free = nf + p
        N = n_free + nn + mg + nb
        E = np.zeros((N, N))
        g0 = P @ self.x0 + self.q
        # column blocks
        cf, cy, cx, cz, cb = 0, nf, nf + p, nf + p + nn, nf + p + nn + mg
        # row blocks: same order (free dual rows, equalities, x' rows, inequality rows, box rows)
        PS = P[:, Nn] * S
        E[cf:cy, cf:cy] = sub(P, F, F)
        E[cf:cy, cy:cx] = A[:, F].T
        E[cf:cy, cx:cz] = PS[F]
        E[cf:cy, cz:cb] = G[:, F].T
        E[cy:cx, cf:cy] = -A[:, F]
        E[cy:cx, cx:cz] = -A[:, Nn] * S
        E[cx:cz, cf:cy] = S[:, None] * sub(P, Nn, F)
        E[cx:cz, cy:cx] = S[:, None] * A[:, Nn].T
        E[cx:cz, cx:cz] = S[:, None] * PS[Nn]
        E[cx:cz, cz:cb] = S[:, None] * G[:, Nn].T
        E[cz:cb, cf:cy] = -G[:, F]
        E[cz:cb, cx:cz] = -G[:, Nn] * S
        E[cx + self.boxed, cb + np.arange(nb)] = 1.0
        E[cb + np.arange(nb), cx + self.boxed] = -1.0
        j_box = Nn[self.boxed]
        e = np.concatenate([
            g0[F], _constant_rows(A, self.b, self.x0, self.fixed),
            S * g0[Nn], _constant_rows(G, self.h, self.x0, self.fixed),
            self.ub[j_box] - self.lb[j_box],
        ])
        self.E, self.e, self.n_free = E, e, n_free
        self.blocks = (cf, cy, cx, cz, cb, N)

    def unpack(self, x_mlcp):
        """(x, y, z, x', z_ub) from the MLCP's stacked (u, v)."""
        cf, cy, cx, cz, cb, N = self.blocks
        x = self.x0.copy()
        x[self.free] = x_mlcp[cf:cy]
        x[self.shifted] += self.sign * x_mlcp[cx:cz]
        return x, x_mlcp[cy:cx], x_mlcp[cz:cb], x_mlcp[cx:cz], x_mlcp[cb:N]

    def recover(self, x_mlcp, w):
        """``(x, y, z, z_box)`` from the MLCP's stacked point (u, v) and its w."""
        x, y, z, _, zu = self.unpack(x_mlcp)
        return x, y, z, bound_multipliers(self, x, y, z, w, zu)

    def forward(self, x, y, z, z_box):
        """The MLCP's stacked (u, v) of a QP point with its multipliers (qpsolvers' signs):
        x' from x, the upper multiplier of a boxed variable from the positive part of
        z_box."""
        cf, cy, cx, cz, cb, N = self.blocks
        out = np.zeros(N)
        out[cf:cy] = x[self.free]
        out[cy:cx] = y
        out[cx:cz] = self.sign * (x[self.shifted] - self.x0[self.shifted])
        out[cz:cb] = z
        out[cb:N] = np.maximum(z_box[self.shifted[self.boxed]], 0.0)
        return out

    def direction(self, d_mlcp):
        """The change of x along a direction of the MLCP's (u, v)."""
        cf, cy, cx, cz, _, _ = self.blocks
        dx = np.zeros(self.n)
        dx[self.free] = d_mlcp[cf:cy]
        dx[self.shifted] = self.sign * d_mlcp[cx:cz]
        return dx


def _constant_rows(M, v, x0, fixed):
    """``v - M x0``, the right-hand sides after the shift, where a row that holds fixed
    variables only (a constant row: it reads 0 = c or 0 <= c) gets exactly 0 when c is at
    the level of the rounding in computing it: 3 * 0.1 = 0.3 must not read as a violated
    row.  Other rows keep their value (the solver handles their rounding)."""
    c = v - M @ x0
    if M.shape[0] and fixed.size:
        moving = np.ones(M.shape[1], dtype=bool)
        moving[fixed] = False
        constant = ~np.any(M[:, moving] != 0.0, axis=1)
        rounding = 4.0 * (fixed.size + 1) * EPS * (np.abs(v) + np.abs(M[:, fixed]) @ np.abs(x0[fixed]))
        c[constant & (np.abs(c) <= rounding)] = 0.0
    return c


def bound_multipliers(qp, x, y, z, w, zu):
    """z_box: minus the bound rows' w for a lower bound, plus it for an upper bound (plus
    the upper multiplier of a boxed variable); for a fixed variable, what makes its dual row
    zero."""
    z_box = np.zeros(qp.n)
    w_x = w[:qp.shifted.size]  # the pairs' w begin with the rows of the shifted x'
    z_box[qp.shifted] = -qp.sign * w_x
    z_box[qp.shifted[qp.boxed]] += zu
    if qp.fixed.size:
        g = qp.P @ x + qp.q + qp.A.T @ y + qp.G.T @ z
        z_box[qp.fixed] = -g[qp.fixed]
    return z_box
