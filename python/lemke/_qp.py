r"""solve_qp: convex quadratic programs through the mixed LCP of their KKT conditions.

The QP, in qpsolvers' convention::

    minimize    1/2 x'P x + q'x
    subject to  G x <= h,   A x = b,   lb <= x <= ub.

The front validates the data (``_validate.qp``, and P symmetric positive semidefinite),
reduces the QP to a monotone MLCP (``_reductions.qp_mlcp``, where the KKT layout is
written out), solves that (``_mlcp.solve_stacked``) and recovers x and the multipliers.  A
ray of the MLCP splits into a Farkas vector (the QP is infeasible) or a direction of
unbounded descent; whichever is missing is sought by a small LP (see ``_verdict``), and every
certificate is checked (``_certify``) before it is returned.
"""
from __future__ import annotations

import functools
from dataclasses import replace

import numpy as np

from ._frozen import frozen
from . import _progress, _validate
from ._npc import count, every, filled
from ._blcp import solve_blcp
from ._certify import Certificate, data_scale as _data_scale
from ._certify import check_direction as _check_direction, check_farkas as _check_farkas
from ._certify import kkt_check as kkt  # the fused path's KKT check (qp::kkt_check)
from ._ladder import Rung, always, climb
from ._lcp import METHODS
from ._mlcp import solve_stacked
from ._options import as_options, time_limited, timed
from ._reductions.qp_mlcp import QPToMLCP
from ._result import LazyField, Outcome, WarmStart
from ._status import STOPPED, Status
from . import _core
from ._layout import METHODS as _METHOD_NAMES

BOX_FIRST = 16  # box-only QPs: below, plain data goes to _core.qp_solve_box; from here, solve_blcp first


@frozen(eq=False)
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
        ``MAX_PIVOTS`` or ``NUMERICAL_FAILURE``; ``TIME_LIMIT`` or ``INTERRUPTED`` when
        stopped (on the fused and box paths x and the multipliers are then zeros and the
        residuals NaN).
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
    def _deferred(cls, eager, resolve, args):
        """A result with the fields in ``eager`` set now and the others made by
        ``resolve(*args)`` (a dict of them) when one of them is first read; until then the
        result holds ``args``.  Equality, hashing, ``repr``, ``replace`` and pickling read
        the fields, so they resolve it first: it is the same value as one built eagerly."""
        res = object.__new__(cls)
        d = res.__dict__
        d.update(eager)
        d["_resolve"] = (resolve, args)
        return res

    def __getattr__(self, name):  # only for names not (yet) in __dict__
        d = self.__dict__
        deferred = d.pop("_resolve", None)
        if deferred is None:
            raise AttributeError(f"'QPResult' object has no attribute {name!r}")
        resolve, args = deferred
        d.update(resolve(*args))
        return getattr(self, name)

    def __getstate__(self):
        if "_resolve" in self.__dict__:
            self.__getattr__("x")  # resolve
        return self.__dict__

    def __repr__(self) -> str:
        return (
            f"QPResult(status={self.status.name}, obj={self.obj:.10g}, pivots={self.pivots}, "
            f"primal_residual={self.primal_residual:.3g}, dual_residual={self.dual_residual:.3g}, "
            f"duality_gap={self.duality_gap:.3g}, n={self.x.size})"
        )


class _Deferred(LazyField):
    """A field of :class:`QPResult` not (yet) in the result's ``__dict__``: a deferred
    result's fields made by its ``_resolve`` when one is first read (``result.warm_start``
    in an MPC loop each step) without ``__getattr__``'s fallback, which first raises an
    AttributeError (about half a microsecond of the ~4 us read)."""

    __slots__ = ()

    def make(self, d):
        deferred = d.pop("_resolve", None)
        if deferred is not None:
            d.update(deferred[0](*deferred[1]))
        try:
            return d[self.name]
        except KeyError:
            raise AttributeError(f"'QPResult' object has no attribute {self.name!r}") from None


for _name in QPResult.__dataclass_fields__:  # (no defaults: a class attribute is free)
    setattr(QPResult, _name, _Deferred(_name))


def solve_qp(P, q, G=None, h=None, A=None, b=None, lb=None, ub=None, *, method="tableau",
             warm_start=None, initvals=None, options=None, progress=None) -> QPResult:
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
        The Lemke method (see :func:`lemke.solve_lcp`).  A cold QP with at least 4n
        inequalities (bounds counted) first tries the unrevised method on its multiplier
        LCP in factored form, whatever the method (see src/lemke/qp.cpp, step 7); so does
        one whose P is only semidefinite where its flat directions are few (as many as the
        equalities, one more with more rows of G than bound rows, any up to 32 variables;
        step 8), and one whose fused point failed its KKT check.
    warm_start : WarmStart, optional
        ``result.warm_start`` of an earlier QP with the same structure: the same number of
        variables, the same rows of G with a finite h and the same kinds of bounds (its
        ``n``, the number of pairs of the KKT-MLCP, must match: else ``ValueError``).  Its
        active set is tried first: with P definite the fused kernel solves the old active
        set's KKT system on the new data and checks it (0 pivots when it holds), else
        makes up to 3 active-set updates (3 more while each moves a single row), else
        restarts Lemke's method from the nearest set those tried (kept when its point passes
        the KKT check), else solves cold; P, A and G equal to the last call's (on
        the same thread) reuse its factors whether warm or cold.  Another kind of warm start
        (a ``BoxWarmStart``, a ``WarmStartBatch``) is a ``ValueError``, anything else a
        ``TypeError``.
    initvals : (n,) array_like, optional
        qpsolvers' primal guess x0, turned into a warm start: the rows of G tight or violated
        at x0 (``G_i x0 >= h_i - 1e-9 (|h_i| + |G_i| |x0|)``) and the bounds x0 is at or
        beyond (``x0_j <= lb_j + 1e-9 (|lb_j| + |x0_j|)``, the same for ub) form the active
        set (a variable within that of both bounds takes the nearer).  A guess is only a
        start: the answer is solved and checked as without it.  A shape other than (n,) or
        a non-finite entry is a ``ValueError`` naming ``initvals``; giving both
        ``initvals`` and ``warm_start`` is a ``ValueError``.
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
    if progress is not None and progress is not False:
        return _progress.reported(_progress.check(progress), "solve_qp", solve_qp, P, q, G, h, A,
                                  b, lb, ub, method=method, warm_start=warm_start,
                                  initvals=initvals, options=options)
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_qp, P, q, G, h, A, b, lb, ub, method=method,
                     warm_start=warm_start, initvals=initvals)
    tried = warm_tried = False
    cold = None  # the native front's code of a cold call it ran and did not solve
    if options is None and type(method) is str and method == "tableau" and (
            warm_start is None or type(warm_start) is WarmStart and initvals is None):
        # The call whole in one native call (src/python_front_qp.cpp), cold or warm (a
        # WarmStart, or qpsolvers' initvals): plain data (as the inline lines below take it,
        # and a plain float64 initvals), or array-likes it converts (made_f64's forms, scalar
        # bounds), gives the result, or the kernel's code when it did not end solved and
        # checked (with the converted arguments, if any; the steps below then go on without
        # calling it again); others None (the steps below do everything).
        if warm_start is not None:
            try:
                beta = warm_start._beta  # (an attribute read: cheaper than __dict__.get)
            except AttributeError:
                beta = warm_start.__dict__["_beta"] = np.array(warm_start.z_basic, dtype=_I64)
            r = _QP_FRONT(P, q, G, h, A, b, lb, ub, warm_start.n, beta, None)
        else:
            r = _QP_FRONT(P, q, G, h, A, b, lb, ub, 0, None, initvals)
        if r is not None:
            if type(r) is not tuple:
                return r
            if len(r) > 4:  # (array-likes the front converted: the steps below take them)
                P, q, G, h, A, b, lb, ub, initvals = r[4]
            code, pivots, k, pairs = r[:4]
            if code == _BAD_WARM:
                raise _bad_warm(warm_start, pairs)
            if code in _STOP_CODES:
                return _stopped(code, pivots, len(q), 0 if A is None else len(A),
                                0 if G is None else len(G))
            if warm_start is None and initvals is None:
                cold = code
                # (it ran _solve_definite's kernels, the semidefinite step included, on all
                # but a small box-only QP, whose box kernel it ran: the steps below go on)
                tried = not (G is None and h is None and A is None and b is None
                             and (lb is not None or ub is not None))
            else:
                warm_tried = True
        elif (c := _validate.plain_all((P, q, G, h, A, b, lb, ub, initvals), _RANKS)) is not None:
            # array-likes the front declined (NumPy's other forms) converted once, as the
            # validation below would convert them: then the front
            return solve_qp(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], method=method,
                            warm_start=warm_start, initvals=c[8])
    if ((warm_start is None or type(warm_start) is WarmStart) and initvals is None
            and not warm_tried and cold is None
            and type(P) is _ND and type(q) is _ND
            and (P.dtype is _F64 or P.dtype == _F64) and (q.dtype is _F64 or q.dtype == _F64)
            and P.ndim == 2 and q.ndim == 1 and P.flags.carray and q.flags.carray
            and len(q) and type(method) is str and method in METHODS):
        # The common cold call, inline: plain data (float64 ndarrays, C-contiguous, aligned
        # and writable, of the fused kernel's ranks: what _plain_args would return as it is;
        # the kernels compare the shapes) goes to its kernel's compiled entry point with no
        # other Python step (each call and attribute read here costs about a tenth of a
        # microsecond warm, several times that when the caches are cold; len(a) is a
        # third of a.shape[0]).  A box-only QP
        # below BOX_FIRST variables takes the box kernel (_solve_box_small), any other the
        # fused kernel (as _solve_definite); what they do not solve and check, or data in
        # another form, takes the steps below (which do not call the fused kernel again).
        n = len(q)
        absent = _ABSENT.get(n) or _absent(n)
        box = G is None and h is None and A is None and b is None
        plain = True
        if G is None:
            if h is not None:
                plain = False
            Gk, hk = absent[0], absent[1]
        elif (type(G) is _ND and type(h) is _ND and (G.dtype is _F64 or G.dtype == _F64)
                  and (h.dtype is _F64 or h.dtype == _F64) and G.ndim == 2 and h.ndim == 1
                  and G.flags.carray and h.flags.carray):
            Gk, hk = G, h
        else:
            plain = False
        if A is None:
            if b is not None:
                plain = False
            Ak, bk = absent[0], absent[1]
        elif (type(A) is _ND and type(b) is _ND and (A.dtype is _F64 or A.dtype == _F64)
                  and (b.dtype is _F64 or b.dtype == _F64) and A.ndim == 2 and b.ndim == 1
                  and A.flags.carray and b.flags.carray):
            Ak, bk = A, b
        else:
            plain = False
        if lb is None:
            lo = absent[2]
        elif (type(lb) is _ND and (lb.dtype is _F64 or lb.dtype == _F64) and lb.ndim == 1
              and lb.flags.carray):
            lo = lb
        else:
            plain = False
        if ub is None:
            up = absent[3]
        elif (type(ub) is _ND and (ub.dtype is _F64 or ub.dtype == _F64) and ub.ndim == 1
              and ub.flags.carray):
            up = ub
        else:
            plain = False
        if plain and warm_start is not None:  # the fused kernel from the warm start
            # (with options or another method: the native front above takes the others)
            opts = _DEFAULT_OPTIONS if options is None else as_options(options)
            res = _solve_warm((P, q, Gk, hk, Ak, bk, lo, up), method, opts, warm_start)
            if res is not None:
                return res
            warm_tried = True
        elif plain:
            opts = _DEFAULT_OPTIONS if options is None else as_options(options)
            if box and (lb is not None or ub is not None):
                if n < BOX_FIRST:
                    res = _solve_box_small((P, q, Gk, hk, Ak, bk, lo, up), opts)
                    if res is not None:
                        return res
            elif len(Gk) + n * ((lb is not None) + (ub is not None)) >= _GRAM_RATIO * n:
                res = _solve_definite((P, q, Gk, hk, Ak, bk, lo, up), method, opts)
                if res is not None:
                    return res
                tried = True
            else:  # _solve_definite, inline
                p, m = len(Ak), len(Gk)
                out = np.empty(_layout(n, p, m)[-1])
                mp = opts.max_pivots
                code, pivots, k, pairs = _core.qp_solve(
                    P, q, Gk, hk, Ak, bk, lo, up, _METHOD_CODES[method],
                    -1 if mp is None else mp, opts.pivot_tol, opts.tie_tol, opts.tol, out)
                if code == _OK:
                    return _fused_result(out, n, p, m, k, pairs, pivots)
                if code in _STOP_CODES:
                    return _stopped(code, pivots, n, len(Ak), len(Gk))
                if code == _NOT_DEFINITE or (code == _CHECK_FAILED and _RELAXED):  # step 8
                    res = _solve_semidefinite((P, q, Gk, hk, Ak, bk, lo, up), opts)
                    if res is not None:
                        return res
                tried = True
    _validate.method(method, METHODS)
    opts = as_options(options)
    if warm_start is not None and not isinstance(warm_start, WarmStart):  # of any size: a basis
        _validate.wrong_kind(warm_start, "warm_start", "lemke.WarmStart")
        raise TypeError(f"warm_start must be a lemke.WarmStart, got {type(warm_start).__name__}")
    if initvals is not None:
        if warm_start is not None:
            raise ValueError("give warm_start or initvals, not both")
        plain = None if warm_tried else _plain_args(P, q, G, h, A, b, lb, ub)
        if plain is not None:  # the fused kernel reads the guess's active set itself
            res = _solve_warm(plain, method, opts, None, _guess_vector(initvals, plain[1].shape[0]))
            if res is not None:
                return res
            warm_tried = True
        warm_start = _initvals_start(initvals, P, q, G, h, A, b, lb, ub)  # for the KKT-MLCP path
    if warm_start is not None and not warm_tried:
        plain = _plain_args(P, q, G, h, A, b, lb, ub)
        if plain is not None:
            res = _solve_warm(plain, method, opts, warm_start)
            if res is not None:
                return res
    # Cold, the fast paths first (for data the first lines did not take, or a QP they did
    # not solve): a box-only QP of at least BOX_FIRST variables through the bounded kernel,
    # a definite P through the fused kernel (also a P semidefinite to rounding when m >= 4n:
    # its step 7; not again when the first lines tried it), a smaller box-only QP through
    # the bounded kernel with its recovery runs; else, or when they do not end solved and
    # checked, the KKT-MLCP path.
    box_only = warm_start is None and G is None and h is None and A is None and b is None and (
        lb is not None or ub is not None)
    box_first = box_only and np.size(q) >= BOX_FIRST
    if box_first:
        res = _solve_box(P, q, lb, ub, opts)
        if res is not None:
            return res
    if warm_start is None and not tried:
        plain = _plain_args(P, q, G, h, A, b, lb, ub)
        if plain is not None:
            res = _solve_definite(plain, method, opts)
            if res is not None:
                return res
    if box_only and not box_first:
        res = _solve_box(P, q, lb, ub, opts)
        if res is not None:
            return res
    (P, q, G, h, A, b, lb, ub), keep = qpsolvers_form(P, q, G, h, A, b, lb, ub)
    qp = _QP(P, q, G, h, A, b, lb, ub)
    return _restore_rows(_solve(qp, method, opts, warm_start, certify=True), keep)


def solve_qpsolvers_problem(problem, *, method="tableau", initvals=None, options=None):
    """qpsolvers' ``solve_problem`` with lemke: a ``qpsolvers.Problem`` in, a
    ``qpsolvers.Solution`` out (qpsolvers must be installed), so that code written for
    qpsolvers switches by one call.  ``found`` is ``result.success``; x, y, z, z_box and
    obj are set only when found, as qpsolvers does; ``extras["lemke"]`` holds the
    :class:`QPResult` (status, certificate, pivots, warm start); ``solve_time`` is the
    call's time.  The Solution's residual methods recompute qpsolvers' formulas.
    ``initvals`` is qpsolvers' primal guess (see :func:`solve_qp`)."""
    import time

    import qpsolvers

    t0 = time.perf_counter()
    res = solve_qp(problem.P, problem.q, problem.G, problem.h, problem.A, problem.b,
                   problem.lb, problem.ub, method=method, initvals=initvals, options=options)
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
        P = np.reshape(_validate.real_array(P, "P"), (1, 1))
    keep = None
    if type(h) is _ND and h.dtype == _F64 and h.ndim == 1 and every(np.isfinite(h)):
        pass  # finite float64 rows, each a constraint: nothing to do (numpy's ufuncs alone)
    elif G is not None and h is not None:
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
            G = _validate.real_array(G, "G")
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


_ABSENT: dict = {}  # n -> _absent(n), the last 64 sizes


def _absent(n):
    """``(G or A, h or b, lb, ub)`` of a QP of n variables without them: empty rows and
    infinite bounds, made once per n (a fresh ``np.full`` costs about 1 us, a fifth of a
    small solve) and kept for the last 64 sizes.  Private to the fused path, whose kernel
    only reads them."""
    absent = _ABSENT.get(n)
    if absent is None:
        absent = np.zeros((0, n)), np.zeros(0), filled(n, -np.inf), filled(n, np.inf)
        if len(_ABSENT) >= 64:
            del _ABSENT[next(iter(_ABSENT))]
        _ABSENT[n] = absent
    return absent


_F64 = np.dtype(np.float64)


def _kernel_array(x):
    """float64, C-contiguous, aligned and writable (see ``_validate.kernel_array``); a plain
    float64 ndarray that already is goes through without a call into numpy."""
    if type(x) is np.ndarray and x.dtype == _F64 and x.flags.carray:
        return x
    x = _validate.kernel_array(np.asarray(x, dtype=np.float64))
    return x if x.flags.aligned else x.copy()  # (the fused kernel's entry point: aligned)


def _kernel_vector(v):
    """:func:`_kernel_array`, a column (k, 1) flattened."""
    v = _kernel_array(v)
    if v.ndim == 2 and v.shape[1] == 1:
        v = v.reshape(-1)
    return v


_ND = np.ndarray


def _plain_args(P, q, G, h, A, b, lb, ub):
    """The arguments as float64 C-contiguous arrays of exactly the shapes the fused kernel
    takes (column vectors flattened and absent constraints empty, as in
    :func:`qpsolvers_form`), or None when any is in another form: the full validation then
    converts it or raises.  Values are not looked at (``qp::screen`` does that)."""
    try:
        q = _kernel_vector(q)
        if q.ndim != 1 or not q.shape[0]:
            return None
        n = q.shape[0]
        P = _kernel_array(P)
        if P.shape != (n, n):
            if not (n == 1 and P.size == 1 and P.ndim <= 1):
                return None
            P = P.reshape(1, 1)
        absent = _absent(n)
        if G is None and h is None:
            G, h = absent[0], absent[1]
        else:
            G = _kernel_array(G)
            h = _kernel_vector(h)
            if G.ndim != 2 or h.ndim != 1 or G.shape != (h.shape[0], n):
                return None
        if A is None and b is None:
            A, b = absent[0], absent[1]
        else:
            A = _kernel_array(A)
            b = _kernel_vector(b)
            if A.ndim != 2 or b.ndim != 1 or A.shape != (b.shape[0], n):
                return None
        if lb is None:
            lb = absent[2]
        else:
            lb = _kernel_vector(lb)
            if lb.shape != (n,):
                return None
        if ub is None:
            ub = absent[3]
        else:
            ub = _kernel_vector(ub)
            if ub.shape != (n,):
                return None
    except (TypeError, ValueError):
        return None
    return [P, q, G, h, A, b, lb, ub]


def _solve_box(P, q, lb, ub, opts):
    """A QP whose only constraints are bounds, as the box LCP it is: the KKT conditions of
    min 1/2 x'Px + q'x s.t. lb <= x <= ub say lb <= x <= ub with w = P x + q >= 0 where
    x_j = lb_j, <= 0 where x_j = ub_j and = 0 between, and z_box = -w.  Solved by the
    bounded-variable kernel (``lemke.solve_blcp``, whatever ``method``): n pairs, where the
    KKT-MLCP pivots on a row per bound.  Its answer is checked on the data (the natural
    map, row by row), which is the KKT check here.  None unless solved: the KKT-MLCP path
    then runs and finds the certificates.

    Plain data (:func:`_box_screened`: float64 arrays, finite, symmetric, P definite) skips
    the front's validation and its LAPACK Cholesky (the same arrays, bit for bit); the
    residuals, objective and basis are built when first read (``QPResult._deferred``)."""
    fast = _box_screened(P, q, lb, ub)
    if fast is not None:
        P, q, lo, up = fast
        n = q.size
    else:
        d = _validate.qp(P, q, None, None, None, None, lb, ub)
        q = d["q"]
        n = q.size
        if n == 0:
            return None
        P = _validate.symmetric_psd(d["P"])
        lo = d.get("lb", np.full(n, -np.inf))
        up = d.get("ub", np.full(n, np.inf))
    r = solve_blcp(P, q, lo, up, options=opts)
    if r.status in STOPPED:
        return _stopped(int(r.status), r.pivots, n, 0, 0)
    if r.status != Status.SOLVED:
        return None
    empty = np.zeros(0)
    empty.setflags(write=False)
    z_box = -r.w
    z_box.setflags(write=False)
    return QPResult._deferred(
        {"x": r.z, "y": empty, "z": empty, "z_box": z_box, "status": Status.SOLVED,
         "pivots": r.pivots, "certificate": None},
        _box_fields, (P, q, lo, up, r.z, z_box, r.warm_start))


def _solve_box_small(args, opts):
    """A box-only QP with plain data (as :func:`solve_qp`'s first lines take it) of fewer
    than BOX_FIRST variables in one kernel call, ``_core.qp_solve_box`` (the port of
    ``qp::solve_box``, src/lemke/qp.cpp): the screen and P
    definite as the fused path's, one run of the box kernel (as :func:`_solve_box`'s first
    run), its natural-map check, then the fused path's KKT check (``qp::kkt_check``
    at ``min(tol, STRICT_TOL)``: what the fused path answered these QPs with before).  The box LCP has n
    pairs where the fused path's LCP has a row per bound (2n for a boxed variable): at
    n = 10, 2 to 5 us of kernel against 13.  None unless solved and checked: the fused path
    and then :func:`_solve_box` (with its recovery runs) decide.  Residuals, multipliers
    and the basis are read from the kernel's buffer when first read."""
    P, q, G, h, A, b, lb, ub = args
    n = q.shape[0]
    at = _box_layout(n)  # qp::BoxOutLayout: the final bases (int64) in the buffer's tail
    out = np.empty(at[-1])
    final = out[at[3]:].view(_I64)
    mp = opts.max_pivots
    code, pivots, k, pairs = _core.qp_solve_box(P, q, G, h, A, b, lb, ub, _NO_WARM[n],
                                                100 * (n + 1) if mp is None else mp,  # (solve_blcp's)
                                                opts.pivot_tol, opts.tie_tol, opts.tol, out, final)
    if code in _STOP_CODES:
        return _stopped(code, pivots, n, 0, 0)
    if code != _OK:
        return None
    out.setflags(False)
    res = _new(QPResult)
    d = res.__dict__
    d["x"] = out[:n]
    d["status"] = _SOLVED
    d["pivots"] = pivots
    d["certificate"] = None
    d["_resolve"] = (_box_small_fields, (out, n, k, pairs))
    return res


def _box_small_fields(out, n, k, pairs):
    """The deferred fields of a result of :func:`_solve_box_small` (the basis numbered as
    :func:`_box_basis` numbers it, by the kernel: ``qp::box_basis``, the port of
    ``qp::box_basis``; in the buffer's tail after boxed's own final basis)."""
    _, zb, stats, final, _ = _box_layout(n)
    primal, dual, gap, obj = out[stats:final].tolist()
    basic = out[final:].view(_I64)[n:n + k]
    return {"y": _EMPTY, "z": _EMPTY, "z_box": out[zb:stats], "obj": obj,
            "primal_residual": primal, "dual_residual": dual, "duality_gap": gap,
            "warm_start": WarmStart._trusted(pairs, tuple(basic.tolist()))}


_EMPTY = np.zeros(0)
_EMPTY.setflags(write=False)
_NO_WARM = [np.zeros(2 * n, dtype=np.bool_) for n in range(BOX_FIRST)]  # no warm start


def _box_screened(P, q, lb, ub):
    """``(Ps, q, lo, up)`` of a box-only QP whose data the fused path's screen passes
    (``qp::screen``: finite, symmetric to the front's tolerance, lb <= ub, bounds
    beyond 1e20 infinite) and whose symmetric part has a Cholesky factor
    (``qp::cholesky``: definite, so the front's positive-semidefinite check passes);
    None otherwise (the full validation then decides).  ``Ps = (P + P')/2`` elementwise,
    the bits of ``_validate.symmetric_psd``."""
    plain = _plain_args(P, q, None, None, None, None, lb, ub)
    if plain is None:
        return None
    ok, Ps, lo, up = _core.qp_screen(*plain)
    if not ok or not _core.qp_cholesky(Ps, np.empty_like(Ps)):
        return None
    return Ps, plain[1], lo, up


def _box_fields(P, q, lo, up, x, z_box, ws):
    """The deferred fields of a result of :func:`_solve_box`."""
    n = q.size
    empty = np.zeros(0)
    _, primal, dual, gap, obj = kkt((P, q, np.zeros((0, n)), empty, np.zeros((0, n)), empty,
                                     lo, up), x, empty, empty, z_box, 0.0)
    return {"obj": obj, "primal_residual": primal, "dual_residual": dual, "duality_gap": gap,
            "warm_start": _box_basis(lo, up, ws)}


def _box_basis(lo, up, ws):
    """The box LCP's final basis as the KKT-MLCP's (``_reductions.qp_mlcp``), so that it can
    warm-start ``solve_qp``: pair k of a shifted variable (x' = x - lb, or ub - x when only
    ub is finite) is basic when x' can be positive there, and a boxed variable's upper
    multiplier when it sits at ub."""
    lo_f, up_f = np.isfinite(lo), np.isfinite(up)
    fixed = lo_f & up_f & (lo == up)
    shifted = np.flatnonzero((lo_f | up_f) & ~fixed)
    basic, upper = set(ws.z_basic), set(ws.at_upper)
    pairs = [k for k, j in enumerate(shifted) if j in basic or (lo_f[j] and j in upper)]
    boxed = [j for j in shifted if lo_f[j] and up_f[j]]
    pairs += [shifted.size + b for b, j in enumerate(boxed) if j in upper]
    return WarmStart._trusted(int(shifted.size + len(boxed)), tuple(pairs))


def _bad_warm(warm_start, pairs):
    """The ValueError of a warm start of a QP with another structure."""
    return ValueError(f"warm_start has {warm_start.n} pairs, this QP has {pairs} (one per "
                      "variable with a finite bound, per row of G with a finite h, and one more "
                      "per variable with both bounds): a basis of a QP with another structure")


def _solve_warm(args, method, opts, warm_start, x0=None):
    """The fused kernel from a warm start (``_core.qp_solve_warm``), or from qpsolvers'
    initvals x0 (``_core.qp_solve_guess``, which reads the rows active at x0 itself, the
    rule of :func:`_initvals_start`): that active set first (its KKT point on the new data,
    checked; a few active-set updates; Lemke's method restarted from the nearest set
    tried), else cold; the factors of P, A, G reused when they
    are the last call's.  None when it does not end solved and checked (P not definite,
    dependent equalities, ...): the caller then takes the KKT-MLCP path from the same start.
    A warm start with another number of pairs is a ValueError."""
    P, q, G, h, A, b, lb, ub = args
    n, p, m = q.shape[0], A.shape[0], G.shape[0]
    out = np.empty(_layout(n, p, m)[-1])
    mp = -1 if opts.max_pivots is None else opts.max_pivots
    if x0 is not None:
        code, pivots, k, pairs = _core.qp_solve_guess(
            P, q, G, h, A, b, lb, ub, _METHOD_CODES[method], mp, opts.pivot_tol, opts.tie_tol,
            opts.tol, out, x0)
    else:
        try:
            warm = warm_start._beta  # kept on the warm start (as solve_lcp keeps it)
        except AttributeError:
            warm = warm_start.__dict__["_beta"] = np.array(warm_start.z_basic, dtype=_I64)
        code, pivots, k, pairs = _core.qp_solve_warm(
            P, q, G, h, A, b, lb, ub, _METHOD_CODES[method], mp, opts.pivot_tol, opts.tie_tol,
            opts.tol, out, warm, warm_start.n)
        if code == _BAD_WARM:
            raise _bad_warm(warm_start, pairs)
    if code in _STOP_CODES:
        return _stopped(code, pivots, n, p, m)
    if code != _OK:
        return None
    return _fused_result(out, n, p, m, k, pairs, pivots)


ACTIVE_TOL = 1e-9  # initvals: a row or bound within this (relative) of tight counts as active (qp::ACTIVE_TOL)


def _guess_vector(initvals, n):
    """initvals as a finite float64 vector of n entries (a column (n, 1) flattened), or a
    ValueError naming it."""
    try:
        x0 = np.asarray(initvals, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"initvals must be a real vector of shape ({n},)") from None
    if x0.ndim == 2 and x0.shape[1] == 1:
        x0 = x0.reshape(-1)
    if x0.shape != (n,):
        raise ValueError(f"initvals must have shape ({n},) (one entry per variable), got {x0.shape}")
    if not np.isfinite(x0).all():
        bad = np.flatnonzero(~np.isfinite(x0))
        raise ValueError(f"initvals has a non-finite entry at index {int(bad[0])}")
    return _validate.c_aligned(x0)


def _initvals_start(initvals, P, q, G, h, A, b, lb, ub):
    """The warm start of a primal guess (qpsolvers' ``initvals``): the KKT-MLCP's basis
    (``_reductions.qp_mlcp``'s numbering, as ``qp::mlcp_basis`` writes it) whose
    active set is the rows of G and the bounds tight or violated at x0 (``ACTIVE_TOL``,
    relative to the sizes of the terms).  The data is read after qpsolvers' conventions
    and the validation (rows with h = +inf dropped, bounds beyond 1e20 infinite)."""
    plain = _plain_args(P, q, G, h, A, b, lb, ub)
    if plain is not None:  # float64 arrays of the kernel's shapes: the kernel checks the values
        d = dict(zip(("P", "q", "G", "h", "A", "b", "lb", "ub"), plain))
    else:
        (P, q, G, h, A, b, lb, ub), _ = qpsolvers_form(P, q, G, h, A, b, lb, ub)
        d = _validate.qp(P, q, G, h, A, b, lb, ub)
    n = d["q"].size
    x0 = _guess_vector(initvals, n)
    lo = d.get("lb", np.full(n, -np.inf))
    up = d.get("ub", np.full(n, np.inf))
    lo = np.where(lo > -1e20, lo, -np.inf)
    up = np.where(up < 1e20, up, np.inf)
    lo_f, up_f = np.isfinite(lo), np.isfinite(up)
    fixed = lo_f & up_f & (lo == up)
    ax = np.abs(x0)
    with np.errstate(invalid="ignore"):
        d_lo = np.where(lo_f, x0 - lo, np.inf)  # distance above lb
        d_up = np.where(up_f, up - x0, np.inf)  # distance below ub
        at_lo = lo_f & (d_lo <= ACTIVE_TOL * (np.abs(np.where(lo_f, lo, 0.0)) + ax))
        at_up = up_f & (d_up <= ACTIVE_TOL * (np.abs(np.where(up_f, up, 0.0)) + ax))
    both = at_lo & at_up
    at_lo &= ~both | (d_lo <= d_up)
    at_up &= ~both | (d_up < d_lo)
    shifted = np.flatnonzero((lo_f | up_f) & ~fixed)
    boxed = shifted[lo_f[shifted] & up_f[shifted]]
    # pair of a shifted variable: basic unless the bound it is measured from is active
    held = np.where(lo_f[shifted], at_lo[shifted], at_up[shifted])
    pairs = [np.flatnonzero(~held)]
    G = d.get("G")
    if G is not None and G.shape[0]:
        hh = d["h"]
        if np.isposinf(hh).any():  # no constraint (qpsolvers' convention): not a pair
            G, hh = G[~np.isposinf(hh)], hh[~np.isposinf(hh)]
        r = G @ x0 - hh
        scale = np.abs(hh) + np.abs(G) @ ax
        pairs.append(shifted.size + np.flatnonzero(r >= -ACTIVE_TOL * scale))
        m_g = G.shape[0]
    else:
        m_g = 0
    pairs.append(shifted.size + m_g + np.flatnonzero(at_up[boxed]))
    basic = np.concatenate(pairs)
    return WarmStart._trusted(int(shifted.size + m_g + boxed.size), tuple(basic.tolist()))


def _solve_definite(args, method, opts):
    """The fused cold path for a positive definite P (``qp::solve``, src/lemke/qp.cpp): one
    kernel call that screens the data, factors P, solves the LCP of the inequality
    multipliers and checks the KKT point on the data; with m >= 4n inequalities, first its
    LCP in factored form (``_core.qp_solve_gram``, the kernel's step 7, whatever ``method``;
    also for a P that is semidefinite to rounding; and, step 8, for a P that is not definite
    whose flat directions are few enough, or where the fused kernel's point failed its
    check).  None when it does not apply (data that needs the full validation, P only
    semidefinite, dependent equalities) or did not end solved and checked: the caller then
    takes the KKT-MLCP path, which also finds the certificates of infeasible and unbounded
    QPs."""
    P, q, G, h, A, b, lb, ub = args
    n, p, m = q.shape[0], A.shape[0], G.shape[0]
    out = np.empty(_layout(n, p, m)[-1])
    max_pivots = opts.max_pivots
    if max_pivots is None:
        max_pivots = -1
    absent = _ABSENT.get(n) or _absent(n)
    # The ladder (_ladder.py; the native front's `cold` has the same rungs): step 7, the
    # fused kernel, step 8; solved and checked, or a stop, settles it.
    ran = [None, 0, 0, 0]  # the last kernel's (code, pivots, k, pairs)
    tried = False  # step 7 ran (it did not answer NOT_APPLICABLE)
    semi = None  # step 8's result

    def gram():  # at most that many inequalities: perhaps many more than variables (the
        # kernel's step 7, an entry of its own; it counts them exactly: NOT_APPLICABLE)
        nonlocal tried
        ran[:] = _core.qp_solve_gram(P, q, G, h, A, b, lb, ub, max_pivots, opts.pivot_tol,
                                     opts.tie_tol, opts.tol, out, _basis_view(out, n, p, m),
                                     False)
        tried = ran[0] != _NOT_APPLICABLE

    def fused():
        ran[:] = _core.qp_solve(P, q, G, h, A, b, lb, ub, _METHOD_CODES[method], max_pivots,
                                opts.pivot_tol, opts.tie_tol, opts.tol, out)

    def semidefinite():
        nonlocal semi
        semi = _solve_semidefinite(args, opts)

    last = climb(lambda: ran[0] == _OK or ran[0] in _STOP_CODES,
                 Rung("the factored path (step 7)", lambda: m + n * (
                     (lb is not absent[2]) + (ub is not absent[3])) >= _GRAM_RATIO * n, gram),
                 Rung("the fused kernel", always, fused),
                 Rung("the proximal factored path (step 8)", lambda: (
                     ran[0] == _NOT_DEFINITE or (ran[0] == _CHECK_FAILED and _RELAXED))
                      and not tried, semidefinite))
    if last == 2:
        return semi
    code, pivots, k, pairs = ran
    if code in _STOP_CODES:
        return _stopped(code, pivots, n, p, m)
    if code != _OK:
        return None
    return _fused_result(out, n, p, m, k, pairs, pivots)


def _solve_semidefinite(args, opts):
    """The kernel's step 8 for a P that the fused kernel found not definite (or whose point
    failed its KKT check): its proximal factor and the factored path, where P's flat
    directions are few enough (``_core.qp_solve_gram`` with ``semidefinite``;
    NOT_APPLICABLE where they are not: as many as the equality rows, one more where the
    rows of G outnumber the bounds' rows, any number up to ``SMALL_FLAT`` variables,
    ``qp::flat_allowed``).  None when it does not end solved and checked."""
    P, q, G, h, A, b, lb, ub = args
    n, p, m = q.shape[0], A.shape[0], G.shape[0]
    allowed = _core.qp_flat_allowed(h, p, lb, ub) if _RELAXED else p + count(lb == ub)
    if count(P.diagonal() == 0.0) > allowed:
        # more zero diagonal entries (flat directions) than that: the kernel would decline at
        # once (qp::zero_diagonal); a linear program, say, does not call it
        return None
    out = np.empty(_layout(n, p, m)[-1])
    max_pivots = -1 if opts.max_pivots is None else opts.max_pivots
    code, pivots, k, pairs = _core.qp_solve_gram(P, q, G, h, A, b, lb, ub, max_pivots,
                                                 opts.pivot_tol, opts.tie_tol, opts.tol, out,
                                                 _basis_view(out, n, p, m), True, _RELAXED)
    if code in _STOP_CODES:
        return _stopped(code, pivots, n, p, m)
    if code != _OK:
        return None
    return _fused_result(out, n, p, m, k, pairs, pivots)


#: The fused kernels' codes of an LCP stopped by its budget (Status.TIME_LIMIT, INTERRUPTED).
_STOP_CODES = frozenset(int(s) for s in STOPPED)


def _stopped(code, pivots, n, p, m):
    """The result of a fast path stopped by its time limit or an interrupt: no other path
    is tried.  The kernels keep no point then: x and the multipliers are zeros, the
    residuals and the objective NaN."""
    x, y, z, z_box = np.zeros(n), np.zeros(p), np.zeros(m), np.zeros(n)
    for a in (x, y, z, z_box):
        a.setflags(write=False)
    nan = float("nan")
    return QPResult(x, y, z, z_box, nan, Status(code), int(pivots), nan, nan, nan, None, None)


def _fused_result(out, n, p, m, k, pairs, pivots):
    """The result of the fused kernels' output: x and the status now, the rest deferred."""
    out.setflags(False)  # (write=False, positional: a third of the time) the views too
    # x and the status now; the multipliers, residuals and the basis when first read
    # (QPResult._deferred, inlined): building them costs as much as a small solve's LCP.
    res = _new(QPResult)
    d = res.__dict__
    d["x"] = out[:n]
    d["status"] = _SOLVED
    d["pivots"] = pivots
    d["certificate"] = None
    d["_resolve"] = (_fused_fields, (out, n, p, m, k, pairs))
    return res


def _basis_view(out, n, p, m):
    """The int64 view of the fused kernels' basis in ``out``'s tail (``_core.qp_solve`` makes
    the same view inside)."""
    return out[_layout(n, p, m)[5]:].view(_I64)


@functools.lru_cache(maxsize=256)
def _layout(n, p, m):
    """The fused kernels' output buffer for n variables, p equalities and m inequalities,
    as the C++ core states it (``qp::OutLayout``): the offsets of x, y, z, z_box, the stats
    (primal, dual, gap, obj) and the basis (int64), and the length."""
    return _core.qp_layout(n, p, m)


@functools.lru_cache(maxsize=64)
def _box_layout(n):
    """The box kernel's output buffer (``qp::BoxOutLayout``): the offsets of x, z_box, the
    stats and the final bases (int64), and the length."""
    return _core.qp_box_layout(n)


_new = object.__new__
_DEFAULT_OPTIONS = as_options(None)
_SOLVED = Status.SOLVED
_I64 = np.dtype(np.int64)
_METHOD_CODES = dict(_METHOD_NAMES)
_OK, _NOT_DEFINITE, _GRAM_RATIO = _core.QP_OK, _core.QP_NOT_DEFINITE, _core.QP_GRAM_RATIO
_NOT_APPLICABLE = _core.QP_NOT_APPLICABLE
_CHECK_FAILED = _core.QP_CHECK_FAILED
#: Step 8's reach on the Python path: P's flat directions up to qp::flat_allowed, and after
#: the dense kernel's CHECK_FAILED (as the native front always does); False: the kernel's own
#: rule (flat directions up to the equalities) after NOT_DEFINITE only, the routing the
#: frozen references of the KKT-MLCP path's support calls were recorded with
#: (tests/test_core_support.py switches the front off and this off).
_RELAXED = True
_BAD_WARM = _core.QP_BAD_WARM
#: The ranks of solve_qp's arrays (P, q, G, h, A, b, lb, ub, initvals) as its front reads them
_RANKS = (2, 1, 2, 1, 2, 1, 1, 1, 1)
_QP_FRONT = _core.qp_front  # solve_qp's warm call, native (src/python_front_qp.cpp)


def _fused_fields(out, n, p, m, k, pairs):
    """The deferred fields of a result of the fused path (see :func:`_solve_definite`)."""
    _, y, z, zb, s, basis, _ = _layout(n, p, m)
    primal, dual, gap, obj = out[s:basis].tolist()
    basic = out[basis:basis + k].view(_I64)
    ws = WarmStart._trusted(pairs, tuple(basic.tolist()))
    ws.__dict__["_beta"] = basic  # the index array the warm path takes (read-only, as out)
    return {"y": out[y:z], "z": out[z:zb], "z_box": out[zb:s],
            "obj": obj, "primal_residual": primal, "dual_residual": dual, "duality_gap": gap,
            "warm_start": ws}


def _QP(P, q, G=None, h=None, A=None, b=None, lb=None, ub=None) -> QPToMLCP:
    """Validate a QP (P symmetric positive semidefinite) and reduce it to its KKT MLCP."""
    d = _validate.qp(P, q, G, h, A, b, lb, ub)
    d["P"] = _validate.symmetric_psd(d["P"])
    return QPToMLCP(**d)


def _solve(qp, method, opts, warm_start, certify):
    m_pairs = qp.e.size - qp.n_free
    if warm_start is not None and warm_start.n != m_pairs:
        raise _bad_warm(warm_start, m_pairs)
    r = solve_stacked(qp.E, qp.e, qp.n_free, method, opts, warm_start)
    x, y, z, z_box = qp.recover(np.concatenate([r.u, r.v]), r.w)
    status, certificate, stats = r.status, None, None
    if certify and status == Status.SOLVED:
        (x, y, z, z_box), stats = _polished(qp, (x, y, z, z_box), r.warm_start, opts.tol)
    if certify and status != Status.SOLVED and status != Status.MAX_PIVOTS and status not in STOPPED:
        status, certificate = _verdict(qp, r, method, opts)
    elif status in (Status.RAY_TERMINATION, Status.PRIMAL_INFEASIBLE):
        status = Status.NUMERICAL_FAILURE  # an auxiliary problem: no certificate sought
    return _result(qp, x, y, z, z_box, status, r.pivots, certificate, r.warm_start, stats)


def _data(qp):
    return qp.P, qp.q, qp.G, qp.h, qp.A, qp.b, qp.lb, qp.ub


def _result(qp, x, y, z, z_box, status, pivots, certificate, warm_start, stats=None):
    """The QPResult of the point; ``stats``: kkt's (primal, dual, gap, obj) at it when the
    caller has them (they do not depend on kkt's tol), else they are computed here."""
    y, z = y.copy(), z.copy()
    primal, dual, gap, obj = kkt(_data(qp), x, y, z, z_box, 0.0)[1:] if stats is None else stats
    for a in (x, y, z, z_box):
        a.setflags(write=False)
    return QPResult(x, y, z, z_box, obj, status, int(pivots), primal, dual, gap, certificate, warm_start)


def _polished(qp, point, basis, tol):
    """Final-basis polishing: the KKT point of the final basis's active set, solved afresh
    on the validated data, kept when it is better.

    The basis (the KKT-MLCP's, see ``_reductions.qp_mlcp``) says which constraints hold
    with equality: a row of G whose multiplier is basic, a bound whose shifted variable is
    non-basic (or whose upper multiplier is basic), every fixed variable.  Their KKT system

        P x + A'y + G_S'z_S + I_B'zb_B = -q,   A x = b,   G_S x = h_S,   x_B = bound_B

    is solved for the variables not held at a bound (F) and the multipliers of A and G_S,
    with ``x_B`` given, by the seam's KKT basis system (``KktBasis`` in
    src/lemke/basis.hpp, through ``_core.kkt_basis``): the rows of F, A and G_S, factored
    once (``refined_solve`` of src/lemke/linalg.cpp: LU on one thread, of the size of F plus
    the active rows, not of all n variables and the bounds) and refined with residuals
    summed in double-double over every column, x_B's included, and the solution carried in
    double-double.  The bound multipliers zb_B then follow from the rows of B at that exact
    solution, summed in double-double too.  The point the MLCP path
    recovers has been through the shift of the bounds (``x = lb + x'``) and the MLCP's own
    rounding, this one only through the rounding of the answer (multipliers at the
    rounding level of the solve made zero).  It replaces ``point`` only when it passes the
    row-wise KKT check at ``tol`` (the system's check, ``qp::kkt_check``) and its largest
    residual (primal, dual, gap, summed in double-double) is smaller; a singular system
    (dependent active rows) leaves ``point`` as it is.  Returns ``(point, stats)``: the
    point kept and kkt's (primal, dual, gap, obj) at it, None where they were not
    computed."""
    try:
        beta = basis._beta  # (kept on the warm start, as solve_lcp keeps it)
    except AttributeError:
        beta = basis.__dict__["_beta"] = np.array(basis.z_basic, dtype=_I64)
    c = _validate.c_aligned
    code, new, res, _ = _core.kkt_basis(c(qp.P), qp.q, c(qp.G), qp.h, c(qp.A), qp.b, qp.lb,
                                        qp.ub, beta, tol)
    if code != 0:
        return point, None
    res = res.tolist()
    res0 = kkt(_data(qp), *point, tol)[1:]
    return (new, res) if max(res[:3]) < max(res0[:3]) else (point, res0)


# ----------------------------------------------------------------------------- certificates

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


# The native warm front builds its results as _fused_result does (it stays off, returning
# None, where lcp_front_init found another NumPy layout).
_core.qp_front_init(QPResult, _SOLVED, _fused_fields, _box_small_fields, BOX_FIRST,
                    _METHOD_CODES["tableau"],
                    _DEFAULT_OPTIONS.pivot_tol, _DEFAULT_OPTIONS.tie_tol, _DEFAULT_OPTIONS.tol)
