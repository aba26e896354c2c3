r"""solve_qp: convex quadratic programs through the mixed LCP of their KKT conditions.

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

from dataclasses import dataclass, replace

import numpy as np

from ._lcp import _KERNELS, METHODS
from ._mlcp import _size, solve_stacked
from ._options import as_options
from ._problem import _to_float_array
from ._result import Outcome, WarmStart
from ._status import Status
from .kernels import qp as kqp

EPS = float(np.finfo(np.float64).eps)
INFINITY = 1e20  # bounds at least this large in magnitude are infinite, as in qpsolvers
SYMMETRY_TOL = 1e-10  # relative: a larger asymmetry of P is an error, a smaller one rounding
CONVEXITY_TOL = 1e-10  # relative: P + CONVEXITY_TOL max|P| I must have a Cholesky factor


@dataclass(frozen=True)
class Certificate:
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


@dataclass(frozen=True)
class QPResult(Outcome):
    """The outcome of :func:`lemke.solve_qp`.

    Attributes
    ----------
    x : ndarray
        The primal solution (where the method stopped if not solved).
    y, z, z_box : ndarray
        Multipliers of ``A x = b``, of ``G x <= h`` (>= 0) and of the bounds (negative at an
        active lower bound, positive at an active upper bound), qpsolvers' convention:
        ``P x + q + A'y + G'z + z_box = 0``.
    obj : float
        ``1/2 x'P x + q'x``.
    status : Status
        ``SOLVED``, ``PRIMAL_INFEASIBLE`` or ``DUAL_INFEASIBLE`` (with ``certificate``),
        ``MAX_PIVOTS`` or ``NUMERICAL_FAILURE``.
    pivots : int
    primal_residual, dual_residual, duality_gap : float
        qpsolvers' formulas on the caller's data: ``max(|Ax - b|, [Gx - h]+, [lb - x]+,
        [x - ub]+)``, ``|P x + q + A'y + G'z + z_box|`` (max norms) and ``|x'Px + q'x + b'y +
        h'z + lb'min(z_box, 0) + ub'max(z_box, 0)|``.
    certificate : Certificate or None
        On ``PRIMAL_INFEASIBLE`` a Farkas vector, whose ``dx`` is also a direction of
        unbounded descent when the QP is dual infeasible as well (else None); on
        ``DUAL_INFEASIBLE`` a direction ``dx``.  None otherwise.
    warm_start : WarmStart or None
        The final basis; pass it back for a nearby QP with the same structure.
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    z_box: np.ndarray
    obj: float
    status: Status
    pivots: int
    primal_residual: float
    dual_residual: float
    duality_gap: float
    certificate: Certificate | None
    warm_start: WarmStart | None

    @classmethod
    def _make(cls, x, y, z, z_box, obj, status, pivots, primal, dual, gap, certificate,
              warm_start) -> "QPResult":
        """Build from the solver's own values, skipping the frozen dataclass ``__init__``
        (as ``LCPResult._make``): this is on the hot path of small problems."""
        res = object.__new__(cls)
        res.__dict__.update(x=x, y=y, z=z, z_box=z_box, obj=obj, status=status, pivots=pivots,
                            primal_residual=primal, dual_residual=dual, duality_gap=gap,
                            certificate=certificate, warm_start=warm_start)
        return res

    def __repr__(self) -> str:
        return (
            f"QPResult(status={self.status.name}, obj={self.obj:.10g}, pivots={self.pivots}, "
            f"primal_residual={self.primal_residual:.3g}, dual_residual={self.dual_residual:.3g}, "
            f"duality_gap={self.duality_gap:.3g}, n={self.x.size})"
        )


def solve_qp(P, q, G=None, h=None, A=None, b=None, lb=None, ub=None, *, method="tableau",
             warm_start=None, options=None) -> QPResult:
    r"""Solve the convex quadratic program

    .. math::  \min_x \tfrac12 x^\top P x + q^\top x \quad \text{s.t.} \quad
               G x \le h, \; A x = b, \; lb \le x \le ub

    by Lemke's method on the mixed LCP of its KKT conditions (qpsolvers' argument order and
    meaning).

    Parameters
    ----------
    P : (n, n) array_like
        Symmetric positive semidefinite (P = 0, a linear program, included; n = 0, no
        variables, too: the constraints are then the constant rows 0 <= h, 0 = b).  It is
        symmetrized as (P + P')/2; an asymmetry beyond ``1e-10 max|P|`` is an error (a
        triangular P is a common slip), and so is a P that is not positive semidefinite.
    q : (n,) array_like
    G, h : (m, n) and (m,) array_like, optional
        Inequalities; a 1-D G is one row.  h must be finite.
    A, b : (p, n) and (p,) array_like, optional
        Equalities.
    lb, ub : (n,) array_like, optional
        Bounds; entries of magnitude >= 1e20 and infinities mean no bound.  lb = ub fixes a
        variable (every variable may be fixed); its z_box is what makes its row of
        ``P x + q + A'y + G'z + z_box = 0`` hold.
    method : {"tableau", "unrevised"}
        The Lemke method (see :func:`lemke.solve_lcp`).
    warm_start : WarmStart, optional
        ``result.warm_start`` of an earlier QP with the same sizes and the same kinds of
        bounds.
    options : Options or dict, optional
        See :class:`lemke.Options`.

    Returns
    -------
    QPResult
        ``SOLVED`` only after the KKT point passed the check on the data.  An infeasible or
        unbounded QP ends ``PRIMAL_INFEASIBLE`` or ``DUAL_INFEASIBLE`` with a checked
        :class:`Certificate`; one that is both ends ``PRIMAL_INFEASIBLE``, its certificate
        carrying the direction too (``certificate.dx``).

    Examples
    --------
    >>> import lemke
    >>> r = lemke.solve_qp([[2.0, 0.0], [0.0, 2.0]], [-2.0, -5.0], G=[[1.0, 1.0]], h=[1.0])
    >>> r.status.name, r.x.round(6).tolist(), r.z.round(6).tolist()
    ('SOLVED', [-0.25, 1.25], [2.5])
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(map(repr, METHODS))}")
    opts = as_options(options)
    if warm_start is not None and not isinstance(warm_start, WarmStart):
        raise TypeError(f"warm_start must be a lemke.WarmStart, got {type(warm_start).__name__}")
    if warm_start is None:
        plain = _plain_args(P, q, G, h, A, b, lb, ub)
        if plain is not None:
            res = _solve_definite(plain, method, opts)
            if res is not None:
                return res
    (P, q, G, h, A, b, lb, ub), keep = qpsolvers_form(P, q, G, h, A, b, lb, ub)
    qp = _QP(P, q, G, h, A, b, lb, ub)
    return _restore_rows(_solve(qp, method, opts, warm_start, certify=True), keep)


def solve_qpsolvers_problem(problem, *, method="tableau", options=None):
    """qpsolvers' ``solve_problem`` with lemke: a ``qpsolvers.Problem`` in, a
    ``qpsolvers.Solution`` out (qpsolvers must be installed), so that code written for
    qpsolvers switches by one call.  ``found`` is ``result.success``; x, y, z, z_box and
    obj are set only when found, as qpsolvers does; ``extras["lemke"]`` holds the
    :class:`QPResult` (status, certificate, pivots, warm start); ``solve_time`` is the
    call's time.  The Solution's residual methods recompute qpsolvers' formulas."""
    import time

    import qpsolvers

    t0 = time.perf_counter()
    res = solve_qp(problem.P, problem.q, problem.G, problem.h, problem.A, problem.b,
                   problem.lb, problem.ub, method=method, options=options)
    sol = qpsolvers.Solution(problem)
    sol.solve_time = time.perf_counter() - t0
    sol.found = res.success
    sol.extras = {"lemke": res}
    if res.success:
        sol.x, sol.y, sol.z, sol.z_box, sol.obj = res.x, res.y, res.z, res.z_box, res.obj
    return sol


def qpsolvers_form(P, q, G, h, A, b, lb, ub):
    """qpsolvers' conventions, applied before the validation: column vectors of shape
    (k, 1) for q, h, b, lb and ub are flattened, a 1-D P of one entry is the 1 x 1 matrix
    (n = 1), and a row of G whose h_i is +inf is no constraint and is dropped (infinite
    bounds already mean no bound).  A NaN or -inf in h is an error naming the entry.

    Returns the arguments and ``keep``: None when no row was dropped, else ``(rows, m)``:
    the indices of the rows of G kept and the number of rows given (see
    :func:`_restore_rows`)."""
    def flat(v):
        return v.reshape(-1) if isinstance(v, np.ndarray) and v.ndim == 2 and v.shape[1] == 1 else v

    q, h, b, lb, ub = (flat(np.asarray(v)) if v is not None and np.ndim(v) == 2 else v
                       for v in (q, h, b, lb, ub))
    if P is not None and np.ndim(P) <= 1 and np.size(P) == 1 and np.size(q) == 1:
        P = np.reshape(_to_float_array(P, "P"), (1, 1))
    keep = None
    if G is not None and h is not None:
        h = np.asarray(h)
        if h.dtype.kind not in "fiub":
            return (P, q, G, h, A, b, lb, ub), None  # the validation raises TypeError
        h = h.astype(np.float64, copy=False)
        bad = np.argwhere(np.isnan(h) | np.isneginf(h))
        if len(bad):
            i = tuple(int(k) for k in bad[0])
            what = "a NaN" if np.isnan(h[i]) else "an entry -inf (an infinite right-hand side below every row value)"
            raise ValueError(f"h has {what} at index {i if len(i) > 1 else i[0]}")
        if h.ndim == 1 and np.isposinf(h).any():
            G = _to_float_array(G, "G")
            if G.ndim == 1 and G.size:
                G = G.reshape(1, -1)  # one row
            rows = np.flatnonzero(~np.isposinf(h))
            if G.ndim == 2 and G.shape[0] == h.size:
                G, h, keep = G[rows], h[rows], (rows, h.size)
            else:
                keep = None  # the shapes do not match: the validation says so
    return (P, q, G, h, A, b, lb, ub), keep


def _restore_rows(res, keep):
    """The result on the caller's rows of G: z (and a certificate's z) back to their full
    length, 0 for the rows dropped by :func:`qpsolvers_form`."""
    if keep is None:
        return res
    rows, m = keep

    def full(v):
        out = np.zeros(m)
        out[rows] = v
        out.setflags(write=False)
        return out

    cert = res.certificate
    if cert is not None and cert.z is not None:
        cert = replace(cert, z=full(cert.z))
    return replace(res, z=full(res.z), certificate=cert)


def _plain_args(P, q, G, h, A, b, lb, ub):
    """The arguments as float64 C-contiguous arrays of exactly the shapes the fused kernel
    takes (column vectors flattened and absent constraints empty, as in
    :func:`qpsolvers_form`), or None when any is in another form: the full validation then
    converts it or raises.  Values are not looked at (``kernels.qp.screen`` does that)."""
    try:
        f64 = np.float64
        q = np.ascontiguousarray(q, dtype=f64)
        if q.ndim == 2 and q.shape[1] == 1:
            q = q.reshape(-1)
        n = q.shape[0] if q.ndim == 1 else 0
        if n == 0:
            return None
        P = np.ascontiguousarray(P, dtype=f64)
        if P.shape != (n, n):
            if not (n == 1 and P.size == 1 and P.ndim <= 1):
                return None
            P = P.reshape(1, 1)
        out = [P, q]
        for M, v in ((G, h), (A, b)):
            if M is None and v is None:
                out += [np.zeros((0, n)), np.zeros(0)]
                continue
            M = np.ascontiguousarray(M, dtype=f64)
            v = np.ascontiguousarray(v, dtype=f64)
            if v.ndim == 2 and v.shape[1] == 1:
                v = v.reshape(-1)
            if M.ndim != 2 or v.ndim != 1 or M.shape != (v.shape[0], n):
                return None
            out += [M, v]
        for v, inf in ((lb, -np.inf), (ub, np.inf)):
            if v is None:
                out.append(np.full(n, inf))
                continue
            v = np.ascontiguousarray(v, dtype=f64)
            if v.ndim == 2 and v.shape[1] == 1:
                v = v.reshape(-1)
            if v.shape != (n,):
                return None
            out.append(v)
    except (TypeError, ValueError):
        return None
    return out


def _solve_definite(args, method, opts):
    """The fused cold path for a positive definite P (``kernels.qp``): one kernel call that
    screens the data, factors P, solves the LCP of the inequality multipliers and checks
    the KKT point on the data.  None when it does not apply (data that needs the full
    validation, P only semidefinite, dependent equalities) or did not end solved and
    checked: the caller then takes the KKT-MLCP path, which also finds the certificates of
    infeasible and unbounded QPs."""
    P, q, G, h, A, b, lb, ub = args
    n, p, m = q.shape[0], A.shape[0], G.shape[0]
    out = np.empty(2 * n + p + m + 4)  # kqp.out_size
    basic = np.empty(m + 2 * n, dtype=np.int64)
    code, pivots, k, pairs = kqp.solve(
        P, q, G, h, A, b, lb, ub, _KERNELS[method],
        -1 if opts.max_pivots is None else opts.max_pivots, opts.pivot_tol, opts.tie_tol,
        opts.tol, out, basic)
    if code != kqp.OK:
        return None
    out.setflags(write=False)  # the views below are read-only too
    primal, dual, gap, obj = out[-4:].tolist()
    return QPResult._make(out[:n], out[n:n + p], out[n + p:n + p + m],
                          out[n + p + m:2 * n + p + m], obj, Status.SOLVED, pivots, primal, dual,
                          gap, None, WarmStart._trusted(pairs, tuple(basic[:k].tolist())))


class _QP:
    """The validated data, the variables' kinds and the KKT system as a stacked MLCP."""

    def __init__(self, P, q, G, h, A, b, lb, ub):
        q = _to_float_array(q, "q")
        if q.ndim != 1:
            raise ValueError(f"q must be a vector, got shape {q.shape}")
        n = q.size  # n = 0 is allowed: the constraints are then constant rows 0 <= h, 0 = b
        P = _to_float_array(P, "P")
        if n == 0 and P.size == 0:
            P = np.zeros((0, 0))  # [] or any other empty array
        if P.shape != (n, n):
            raise ValueError(f"P must have shape ({n}, {n}) to match q, got {P.shape}")
        self.n, self.q = n, q
        self.P = _symmetric(P)
        self.G, self.h = _rows(G, h, n, "G", "h")
        self.A, self.b = _rows(A, b, n, "A", "b")
        self.lb = _bound(lb, n, "lb", -np.inf)
        self.ub = _bound(ub, n, "ub", np.inf)
        bad = np.flatnonzero(self.lb > self.ub)
        if bad.size:
            j = int(bad[0])
            raise ValueError(f"lb[{j}] = {self.lb[j]} exceeds ub[{j}] = {self.ub[j]}: no x satisfies the bounds")
        _check_psd(self.P)
        self._kinds()
        self._stack()

    def _kinds(self):
        lo, up = np.isfinite(self.lb), np.isfinite(self.ub)
        fixed = lo & up & (self.lb == self.ub)
        self.free = np.flatnonzero(~lo & ~up)
        self.shifted = np.flatnonzero((lo | up) & ~fixed)  # x = x0 + sign * x', x' >= 0
        self.fixed = np.flatnonzero(fixed)
        self.sign = np.where(lo[self.shifted], 1.0, -1.0)
        self.boxed = np.flatnonzero(lo[self.shifted] & up[self.shifted])  # positions in shifted
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
        E[cf:cy, cf:cy] = P[np.ix_(F, F)]
        E[cf:cy, cy:cx] = A[:, F].T
        E[cf:cy, cx:cz] = PS[F]
        E[cf:cy, cz:cb] = G[:, F].T
        E[cy:cx, cf:cy] = -A[:, F]
        E[cy:cx, cx:cz] = -A[:, Nn] * S
        E[cx:cz, cf:cy] = S[:, None] * P[np.ix_(Nn, F)]
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


def _symmetric(P):
    """(P + P')/2, or an error naming the largest asymmetry beyond rounding."""
    scale = float(np.max(np.abs(P))) if P.size else 0.0
    if scale == 0.0:
        return np.zeros_like(P)
    asym = np.abs(P - P.T)
    if asym.max() > SYMMETRY_TOL * scale:
        i, j = np.unravel_index(int(np.argmax(asym)), asym.shape)
        raise ValueError(
            f"P is not symmetric: P[{i}, {j}] = {P[i, j]:.6g} but P[{j}, {i}] = {P[j, i]:.6g} "
            "(pass the full symmetric matrix, not one triangle)"
        )
    return 0.5 * (P + P.T)


def _check_psd(Ps):
    """Raise unless the symmetric Ps is positive semidefinite (to CONVEXITY_TOL)."""
    scale = float(np.max(np.abs(Ps))) if Ps.size else 0.0
    if scale == 0.0:
        return
    try:
        np.linalg.cholesky(Ps + (CONVEXITY_TOL * scale) * np.eye(Ps.shape[0]))
    except np.linalg.LinAlgError:
        lam = np.linalg.eigvalsh(Ps)
        raise ValueError(
            f"P is not positive semidefinite: its smallest eigenvalue is {lam[0]:.3g} (largest "
            f"{lam[-1]:.3g}); solve_qp solves convex QPs only, a KKT point of a non-convex one "
            "need not be a minimum"
        ) from None


def _rows(M, v, n, mname, vname):
    if M is None and v is None:
        return np.zeros((0, n)), np.zeros(0)
    if M is None or v is None:
        given, missing = (mname, vname) if v is None else (vname, mname)
        raise ValueError(f"{given} was given without {missing}: pass both or neither")
    M = _to_float_array(M, mname)
    v = _to_float_array(v, vname).reshape(-1) if np.ndim(v) == 0 else _to_float_array(v, vname)
    if M.ndim == 1 and M.size == 0 and v.ndim == 1 and (n == 0 or v.size == 0):
        M = np.zeros((v.size, n))  # [] for rows of no variables, or for no rows at all
    elif M.ndim == 1:
        M = M.reshape(1, -1)
    if M.ndim != 2 or M.shape[1] != n:
        raise ValueError(f"{mname} must have {n} columns (the size of q), got shape {M.shape}")
    if v.shape != (M.shape[0],):
        raise ValueError(f"{vname} must have shape ({M.shape[0]},) to match {mname}, got {v.shape}")
    return M, v


def _bound(v, n, name, infinite):
    if v is None:
        return np.full(n, infinite)
    try:
        a = np.array(v, dtype=np.float64).reshape(-1) if np.ndim(v) else np.full(n, float(v))
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric vector: {exc}") from None
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},) to match q, got {a.shape}")
    if np.isnan(a).any():
        raise ValueError(f"{name} has a NaN entry at index {int(np.flatnonzero(np.isnan(a))[0])}")
    a[a >= INFINITY] = np.inf
    a[a <= -INFINITY] = -np.inf
    if infinite < 0 and np.isposinf(a).any():
        raise ValueError(f"{name} has an entry +inf: a lower bound must be below +inf")
    if infinite > 0 and np.isneginf(a).any():
        raise ValueError(f"{name} has an entry -inf: an upper bound must be above -inf")
    return a


def _solve(qp, method, opts, warm_start, certify):
    m_pairs = qp.e.size - qp.n_free
    if warm_start is not None and warm_start.n != m_pairs:
        warm_start = None  # a basis of a QP with another structure: solve cold
    r = solve_stacked(qp.E, qp.e, qp.n_free, method, opts, warm_start)
    x, y, z, _, zu = qp.unpack(np.concatenate([r.u, r.v]))
    z_box = _bound_multipliers(qp, x, y, z, r.w, zu)
    status, certificate = r.status, None
    if certify and status != Status.SOLVED and status != Status.MAX_PIVOTS:
        status, certificate = _verdict(qp, r, method, opts)
    elif status in (Status.RAY_TERMINATION, Status.PRIMAL_INFEASIBLE):
        status = Status.NUMERICAL_FAILURE  # an auxiliary problem: no certificate sought
    return _result(qp, x, y, z, z_box, status, r.pivots, certificate, r.warm_start)


def _bound_multipliers(qp, x, y, z, w, zu):
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


def residuals(qp, x, y, z, z_box):
    """qpsolvers' primal residual, dual residual and duality gap on the validated data."""
    P, q, G, h, A, b, lb, ub = qp.P, qp.q, qp.G, qp.h, qp.A, qp.b, qp.lb, qp.ub
    Px = P @ x
    primal = max(
        0.0,
        float(np.max(G @ x - h, initial=0.0)),
        _size(A @ x - b),
        float(np.max(lb - x, initial=0.0)),
        float(np.max(x - ub, initial=0.0)),
    )
    dual = _size(Px + q + A.T @ y + G.T @ z + z_box)
    lo, up = np.isfinite(lb), np.isfinite(ub)
    gap = abs(
        float(x @ Px + q @ x + h @ z + b @ y)
        + float(lb[lo] @ np.minimum(z_box[lo], 0.0))
        + float(ub[up] @ np.maximum(z_box[up], 0.0))
    )
    return primal, dual, gap


def _result(qp, x, y, z, z_box, status, pivots, certificate, warm_start):
    y, z = y.copy(), z.copy()
    primal, dual, gap = residuals(qp, x, y, z, z_box)
    obj = float(0.5 * x @ (qp.P @ x) + qp.q @ x)
    for a in (x, y, z, z_box):
        a.setflags(write=False)
    return QPResult(x, y, z, z_box, obj, status, int(pivots), primal, dual, gap, certificate, warm_start)


# ----------------------------------------------------------------------------- certificates

def _normalized(*parts):
    size = max((float(np.max(np.abs(p))) for p in parts if p.size), default=0.0)
    if size == 0.0:
        return None
    return [p / size for p in parts]


def farkas_value(qp, y, z, z_box):
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    return (float(qp.h @ z + qp.b @ y) + float(qp.lb[lo] @ np.minimum(z_box[lo], 0.0))
            + float(qp.ub[up] @ np.maximum(z_box[up], 0.0)))


def _data_scale(qp):
    return max([1.0] + [float(np.max(np.abs(a))) for a in (qp.P, qp.G, qp.A, qp.q, qp.h, qp.b) if a.size])


def _check_farkas(qp, y, z, tol):
    """A verified primal-infeasibility Certificate from (y, z), or None."""
    parts = _normalized(y, z)
    if parts is None:
        return None
    y, z = parts
    if np.any(z < -tol):
        return None
    z = np.maximum(z, 0.0)
    z_box = -(qp.A.T @ y + qp.G.T @ z)
    s = tol * _data_scale(qp) * 10.0
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    # a bound multiplier may only have the sign of a finite bound
    if np.any(z_box[~lo] < -s) or np.any(z_box[~up] > s):
        return None
    z_box[~lo] = np.maximum(z_box[~lo], 0.0)
    z_box[~up] = np.minimum(z_box[~up], 0.0)
    residual = _size(qp.A.T @ y + qp.G.T @ z + z_box)
    value = farkas_value(qp, y, z, z_box)
    bound = max(1.0, _size(qp.lb[lo]), _size(qp.ub[up]))
    if residual > s or value >= -s * bound:
        return None
    return Certificate("primal_infeasible", value, y=y, z=z, z_box=z_box)


def _check_direction(qp, dx, tol):
    """A verified dual-infeasibility Certificate from dx, or None."""
    parts = _normalized(dx)
    if parts is None:
        return None
    (dx,) = parts
    s = tol * _data_scale(qp) * 10.0
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    if (np.any(dx[lo] < -tol) or np.any(dx[up] > tol)
            or _size(qp.P @ dx) > s or _size(qp.A @ dx) > s
            or (qp.h.size and float(np.max(qp.G @ dx)) > s)):
        return None
    dx = dx.copy()
    dx[lo] = np.maximum(dx[lo], 0.0)
    dx[up] = np.minimum(dx[up], 0.0)
    value = float(qp.q @ dx)
    if value >= -s:
        return None
    return Certificate("dual_infeasible", value, dx=dx)


def _verdict(qp, r, method, opts):
    """``(status, certificate)`` for a KKT system without a solution found.

    Along a ray of a monotone KKT system P dx = 0, and the ray splits in two: (dy, dz) is a
    Farkas vector when h'dz + b'dy + ... < 0, and dx a direction of descent when q'dx < 0.
    Whichever of the two the ray does not give (there is no ray when the equations were
    inconsistent or the method failed) is looked for by a small bounded LP, solved by the
    same method: both are always sought, since a QP can be primal and dual infeasible at
    once.  Primal
    infeasibility wins the status: a QP with no feasible point is reported so, and when it
    is also dual infeasible its certificate carries the direction too (``dx``), each part
    checked on its own.  Nothing verified: NUMERICAL_FAILURE."""
    farkas = direction = None
    if r.ray is not None:
        _, dy, dz, _, _ = qp.unpack(r.ray)
        farkas = _check_farkas(qp, dy, dz, opts.tol)
        direction = _check_direction(qp, qp.direction(r.ray), opts.tol)
    if farkas is None:
        farkas = _farkas_by_lp(qp, method, opts)
    if direction is None:
        direction = _direction_by_lp(qp, method, opts)
    if farkas is not None:
        if direction is not None:
            farkas = replace(farkas, dx=direction.dx)
        return Status.PRIMAL_INFEASIBLE, farkas
    if direction is not None:
        return Status.DUAL_INFEASIBLE, direction
    return Status.NUMERICAL_FAILURE, None


def _farkas_by_lp(qp, method, opts):
    """min h'z + b'y - lb'zl + ub'zu  s.t.  A'y + G'z - zl + zu = 0, y in [-1, 1], the
    others in [0, 1]: a negative optimum is a Farkas vector."""
    n = qp.n
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    p, mg = qp.A.shape[0], qp.G.shape[0]
    il, iu = np.flatnonzero(lo), np.flatnonzero(up)
    k = p + mg + il.size + iu.size
    if k == 0:
        return None
    Aeq = np.zeros((n, k))
    Aeq[:, :p] = qp.A.T
    Aeq[:, p:p + mg] = qp.G.T
    Aeq[il, p + mg + np.arange(il.size)] = -1.0
    Aeq[iu, p + mg + il.size + np.arange(iu.size)] = 1.0
    c = np.concatenate([qp.b, qp.h, -qp.lb[il], qp.ub[iu]])
    lbx = np.concatenate([-np.ones(p), np.zeros(k - p)])
    aux = _QP(np.zeros((k, k)), c, None, None, Aeq, np.zeros(n), lbx, np.ones(k))
    r = _solve(aux, method, opts, None, certify=False)
    if r.status != Status.SOLVED:
        return None
    return _check_farkas(qp, r.x[:p], r.x[p:p + mg], opts.tol)


def _direction_by_lp(qp, method, opts):
    """min q'd  s.t.  P d = 0, A d = 0, G d <= delta, d in the bounds' cone: a negative
    optimum is a direction of unbounded descent (then checked by _check_direction).

    The LP is posed on d = N t, N an orthonormal basis of P's null space (the eigenvectors
    of eigenvalue at most ``tol`` times the data's size; all of R^n when P = 0), with t in
    [-1, 1]: P d = 0 then holds by construction, not as n nearly dependent equations that
    can leave the LP's KKT system too ill-conditioned to solve.  The bounds' cone becomes
    rows (-N_j t <= 0 where only lb_j is finite, N_j t <= 0 where only ub_j is, N_j t = 0
    where both are).  The rows of G get the slack ``delta = tol`` times the data's size,
    a tenth of what the check allows: a row that is orthogonal to the direction only up
    to rounding (g'd = 1e-14 where it is 0 in exact arithmetic) must not block it, and
    the LP would otherwise return d = 0."""
    if qp.free.size + qp.shifted.size == 0:
        return None  # no variable can move (none at all, or every one fixed)
    scale = _data_scale(qp)
    lo, up = np.isfinite(qp.lb), np.isfinite(qp.ub)
    slack = np.full(qp.G.shape[0], opts.tol * scale)
    if not np.any(qp.P != 0.0):  # an LP: N = I, and the cone is bounds on d itself
        N = np.eye(qp.n)
        aux = _QP(np.zeros((qp.n, qp.n)), qp.q, qp.G, slack, qp.A, np.zeros(qp.A.shape[0]),
                  np.where(lo, 0.0, -1.0), np.where(up, 0.0, 1.0))
    else:
        lam, V = np.linalg.eigh(qp.P)
        N = V[:, lam <= opts.tol * scale]
        k = N.shape[1]
        if k == 0:
            return None  # P is definite: P d = 0 only for d = 0
        G = np.vstack([qp.G @ N, -N[lo & ~up], N[up & ~lo]])
        h = np.concatenate([slack, np.zeros(G.shape[0] - slack.size)])
        A = np.vstack([qp.A @ N, N[lo & up]])
        aux = _QP(np.zeros((k, k)), N.T @ qp.q, G, h, A, np.zeros(A.shape[0]), -np.ones(k), np.ones(k))
    r = _solve(aux, method, opts, None, certify=False)
    if r.status != Status.SOLVED:
        return None
    return _check_direction(qp, N @ r.x, opts.tol)
