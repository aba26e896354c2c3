"""Bimatrix games: :func:`solve_bimatrix` (one Nash equilibrium, by Lemke-Howson or the
tracing procedure, optionally certified in exact arithmetic) and :func:`lemke_paths` (every
equilibrium that Lemke-Howson paths reach).

**Convention.**  ``A[i, j]`` and ``B[i, j]`` are the payoffs of the row player and of the
column player when the row player plays i and the column player j; both are m x n.  x (length
m) and y (length n) are their mixed strategies.  Labels ``0..m-1`` are the row player's
actions and ``m..m+n-1`` the column player's (as ``init_pivot`` in quantecon and
``initial_dropped_label`` in nashpy).  In quantecon a player's payoff array has the player's
own actions first, so this game is ``NormalFormGame((Player(A), Player(B.T)))``; in nashpy it
is ``nash.Game(A, B)``.

The kernels are the C++ core's games engine (``lemke._core``: src/lemke/games.cpp, ported
from the former numba kernels with the same arguments, results and bits), the exact
arithmetic in :mod:`lemke._games_exact`.
"""
from __future__ import annotations

import collections
import functools
import math
import numbers
import time
from dataclasses import replace
from fractions import Fraction

import numpy as np

from ._frozen import frozen
from . import _core, _progress, _validate
from ._certify import games_check
from . import _games_exact as ex
from ._options import _DEFAULT, Options, as_options, time_limited, timed
from ._options import deadline as deadline_scope
from ._result import LazyField, Outcome, native_fronts_init
from ._status import STOPPED, Status

SOLVED = int(Status.SOLVED)  # the core's code of a solved run

METHODS = ("lemke-howson", "tracing")
DEFAULT_MAX_PIVOTS = 10**6  # Lemke-Howson paths can be long (quantecon's default cap too)
_F64 = np.dtype(np.float64)
_MATRICES = (2, 2)
#: The games kernels of the C++ core (src/lemke/games.cpp: lemke_howson, trace and check,
#: ported from the former numba kernels with the same arguments, results and bits); module
#: attributes, so that a test can stand a lying kernel in (with ``_FRONT`` set to return
#: None, since the native front calls the engine itself).
_LEMKE_HOWSON = _core.lemke_howson
_TRACE = _core.games_trace
_CHECK = games_check  # (_certify's: every kind's check there, by name)
_FRONT = _core.games_front  # solve_bimatrix's commonest call whole (src/python_games.cpp)
_NOT_FINITE = _core.GAMES_NOT_FINITE  # a payoff is not finite: nothing done
_UNCHECKED = _core.GAMES_UNCHECKED  # every label present, at a point that fails the check
#: The games kernels' codes as statuses, the front's one mapping (``_status``): the public
#: codes as they are, the kernels' own (negative, src/lemke/status.hpp) as NUMERICAL_FAILURE.
_STATUSES = {int(s): s for s in Status}
_STATUSES[_UNCHECKED] = Status.NUMERICAL_FAILURE


def _status(code) -> Status:
    """The Status of a games kernel's code (``_STATUSES``; an unknown code a failure)."""
    return _STATUSES.get(code, Status.NUMERICAL_FAILURE)


@functools.lru_cache(maxsize=256)
def _layout(m, n):
    """The games engine's buffer layout for an m x n game, as the core states it
    (``games.hpp``: ``LHLayout``, ``trace_floats``, ``trace_labels``): the offsets in
    ``lemke_howson``'s buffer of x, y, the regret, the payoffs, the int64 labels and path
    state, its length, and the lengths of ``trace``'s float and label outputs."""
    names = ("x", "y", "regret", "payoffs", "labels", "state", "length", "trace_floats",
             "trace_labels")
    return dict(zip(names, _core.games_layout(m, n)))


@frozen
class GameBasis:
    """A vertex pair of the best-response polytopes, as a plain value: the basic labels of
    the polytope of x (``{x >= 0: B'^T x <= 1}``, n of them: action i < m for x_i, m + j for
    the slack of column j) and of the polytope of y (``{y >= 0: A' y <= 1}``, m of them: i
    for the slack of row i, m + j for y_j).  Pass it back as ``solve_bimatrix(...,
    warm_start=)`` to start a Lemke-Howson path there."""

    m: int
    n: int
    x_basic: tuple[int, ...]
    y_basic: tuple[int, ...]

    @classmethod
    def _trusted(cls, m: int, n: int, labels: np.ndarray) -> "GameBasis":
        """From a kernel's final labels (those of P, then those of Q; anything after them
        is ignored),
        skipping the dataclass ``__init__`` (on the hot path of small games)."""
        b = object.__new__(cls)
        f = b.__dict__
        f["m"] = m
        f["n"] = n
        f["x_basic"] = tuple(sorted(labels[:n].tolist()))
        f["y_basic"] = tuple(sorted(labels[n : n + m].tolist()))
        return b


@frozen(eq=False)
class BimatrixResult(Outcome):
    """The outcome of :func:`solve_bimatrix`.

    Attributes
    ----------
    x, y : ndarray (float) or tuple of Fraction (``exact=True``)
        The row and the column player's mixed strategies.
    payoffs : tuple
        ``(x'A y, x'B y)``, the players' expected payoffs.
    status : Status
        ``SOLVED`` only when (x, y) passed the check on the caller's payoffs: both are
        probability vectors and each player's regret (best payoff against the other's
        strategy minus the payoff obtained) is at most ``options.tol`` times the range of
        that player's payoffs (plus rounding); with ``exact=True``, exactly 0.
    pivots : int
        Pivots made (of every run, restarts and the exact continuation included).
    regret : float or Fraction
        The larger of the two players' regrets, on the caller's payoffs.
    basis : GameBasis or None
        The final vertex pair (a warm start for another path); None when the answer is not
        at a vertex pair (the tracing procedure's may not be) or after an exact run that
        failed.
    init_label : int
        The label dropped (Lemke-Howson).
    method : str
    exact : bool
        Whether x, y, payoffs and regret are exact rationals.
    restarts : int
        Restarts after a cycle or a breakdown (0 on almost every game), plus one for a
        re-solve of the final support system in floating point.
    exact_from : str
        With ``exact=True``, where the exact answer comes from: ``"float basis"`` (the
        floating-point path's final basis, certified), ``"continuation"`` (exact
        Lemke-Howson continued from where the floating-point path stopped, or from a state
        ``walked_back`` pivots before it) or ``"restart"`` (exact Lemke-Howson from the
        artificial equilibrium); ``""`` without ``exact``.
    walked_back : int
        With ``exact_from="continuation"``: how many of the floating-point path's last
        pivots were undone to reach a state that is a vertex pair in exact arithmetic.
    """

    x: object
    y: object
    payoffs: tuple
    status: Status
    pivots: int
    regret: object
    basis: GameBasis | None
    init_label: int
    method: str
    exact: bool = False
    restarts: int = 0
    exact_from: str = ""
    walked_back: int = 0

    @classmethod
    def _lazy(cls, buf, m, n, pivots, init_label, restarts) -> "BimatrixResult":
        """A solved floating-point result whose x, y, payoffs, regret and basis are read
        from the kernel's buffer on first access (``_FromKernel``; see
        ``_layout``: the core's ``LHLayout``; ``exact``, ``exact_from`` and
        ``walked_back`` are the class defaults; ``_core.games_front`` builds the same): a
        small solve pays only for what is read."""
        res = object.__new__(cls)
        res.__dict__.update(status=Status.SOLVED, pivots=pivots, init_label=init_label,
                            method="lemke-howson", restarts=restarts, _lazy=(buf, m, n))
        return res

    def __repr__(self) -> str:
        return (f"BimatrixResult(status={self.status.name}, method={self.method!r}, "
                f"pivots={self.pivots}, regret={float(self.regret):.3g}, exact={self.exact})")



class _FromKernel(LazyField):
    """A field of a result of ``BimatrixResult._lazy``, read from the kernel's buffer on
    first access (``_result.LazyField``; the results built field by field never reach it)."""

    __slots__ = ()

    def make(self, d):
        buf, m, n = d["_lazy"]
        name = self.name
        if name == "x" or name == "y":
            if "x" not in d and "y" not in d:
                buf.flags.writeable = False  # before the first view: views copy the flag
                # both at once (a caller that reads one reads the other)
                d["y"] = y = buf[m : m + n]
                if name == "y":
                    return y
            return buf[:m] if name == "x" else buf[m : m + n]
        at = _layout(m, n)
        if name == "regret":
            return buf[at["regret"]]
        if name == "payoffs":
            p = at["payoffs"]
            return (buf[p], buf[p + 1])
        i = at["labels"]
        return GameBasis._trusted(m, n, buf[i : i + m + n].view(np.int64))


for _name in ("x", "y", "payoffs", "regret", "basis"):
    setattr(BimatrixResult, _name, _FromKernel(_name))


def _as_payoffs(A, B):
    """The validated payoffs ``(A, B)`` (``_validate.bimatrix``)."""
    d = _validate.bimatrix(A, B)
    return d["A"], d["B"]


def _label(init_label, m, n):
    if isinstance(init_label, bool) or not isinstance(init_label, (int, np.integer)):
        raise ValueError(f"init_label must be an integer in [0, {m + n}), got {init_label!r}")
    if not 0 <= init_label < m + n:
        raise ValueError(f"init_label {init_label} is out of range: labels are 0..{m - 1} "
                         f"(row actions) and {m}..{m + n - 1} (column actions)")
    return int(init_label)


def _prior(v, size, who):
    if v is None:
        return np.full(size, 1.0 / size)
    v = np.asarray(v, dtype=np.float64).reshape(-1)
    if v.size != size or not np.all(np.isfinite(v)) or np.any(v < 0) or not v.sum() > 0:
        raise ValueError(f"the prior of the {who} must be {size} finite non-negative numbers "
                         f"with a positive sum, got {v!r}")
    return v / v.sum()


def _max_pivots(opts: Options) -> int:
    return DEFAULT_MAX_PIVOTS if opts.max_pivots is None else opts.max_pivots


def solve_bimatrix(A, B, *, init_label=0, method="lemke-howson", prior=None, warm_start=None,
                   exact=False, options=None) -> BimatrixResult:
    r"""One Nash equilibrium of the bimatrix game (A, B).

    Find mixed strategies x (of the row player, length m) and y (of the column player,
    length n) with

    .. math::  x^\top A y \ge e_i^\top A y \ \forall i, \qquad
               x^\top B y \ge x^\top B e_j \ \forall j .

    Parameters
    ----------
    A, B : (m, n) array_like
        The row player's and the column player's payoffs (see the module docstring for how
        this relates to quantecon's and nashpy's conventions).
    init_label : int
        Lemke-Howson's dropped label: ``0..m-1`` a row action, ``m..m+n-1`` a column action.
        Different labels can lead to different equilibria.
    method : {"lemke-howson", "tracing"}
        ``"lemke-howson"``: the Lemke-Howson method (from the artificial equilibrium, or
        from ``warm_start``).  ``"tracing"``: the van den Elzen-Talman tracing procedure
        from the prior ``(p, q)``; it finds the equilibrium that the prior selects
        (Harsanyi-Selten's linear tracing), which Lemke-Howson may not reach.
    prior : (p, q), optional
        The starting profile of the tracing procedure (default: uniform).
    warm_start : GameBasis, optional
        Start the Lemke-Howson path at this vertex pair (e.g. ``result.basis`` of an
        equilibrium) instead of the artificial equilibrium.
    exact : bool
        Certify the answer in rational arithmetic: after the floating-point path, the
        support system of the final basis is solved exactly and the equilibrium checked
        exactly (regret 0).  If that fails (or the path stopped before its end),
        Lemke-Howson dropping ``init_label`` goes on in integer arithmetic from the state
        where the floating-point path stopped, with the same lexicographic rule; when that
        state is not a vertex pair in exact arithmetic (a pivot chose a wrong row), its last
        pivots are undone one by one (up to 63) until one is, and only when none is does the
        exact path restart from the artificial equilibrium.  ``result.exact_from`` says which
        (``"float basis"``, ``"continuation"``, ``"restart"``; the last two with
        ``method="lemke-howson"``; a tracing path that fails is not continued but replaced
        by a restart), ``walked_back`` how
        many pivots were undone, and ``basis`` is the exact path's final basis.  x, y,
        payoffs and regret are then :class:`fractions.Fraction` (x and y as tuples).
    options : Options or dict, optional
        ``max_pivots`` (default 10**6), ``pivot_tol``, ``tie_tol`` (the shared pivoting
        rule) and ``tol`` (the accepted regret, relative to each player's payoff range).

    Returns
    -------
    BimatrixResult

    Examples
    --------
    >>> import lemke
    >>> A = [[3, 3], [2, 5], [0, 6]]
    >>> B = [[3, 2], [2, 6], [3, 1]]
    >>> r = lemke.solve_bimatrix(A, B, exact=True)
    >>> r.status.name, [str(v) for v in r.x], [str(v) for v in r.y]
    ('SOLVED', ['1', '0', '0'], ['1', '0'])

    References
    ----------
    C. E. Lemke, J. T. Howson, "Equilibrium points of bimatrix games", SIAM J. Appl. Math. 12
    (1964).  B. von Stengel, "Computing equilibria for two-person games", Handbook of Game
    Theory vol. 3 (2002).  A. H. van den Elzen, A. J. J. Talman, "A procedure for finding Nash
    equilibria in bi-matrix games", ZOR 35 (1991).
    """
    if options is None and method == "lemke-howson" and warm_start is None and not exact:
        got = _FRONT(A, B, init_label)  # None: arguments of another kind, done below
        if got is not None:
            return got if type(got) is not tuple else _after_front(A, B, init_label, got)
        if (c := _validate.plain_all((A, B), _MATRICES)) is not None:
            # array-likes converted once, as the validation below would convert them: then
            # the front, through the entry
            return solve_bimatrix(c[0], c[1], init_label=init_label)
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_bimatrix, A, B, init_label=init_label, method=method,
                     prior=prior, warm_start=warm_start, exact=exact)
    if not (type(A) is np.ndarray and type(B) is np.ndarray and (A.dtype is _F64 or A.dtype == _F64)
            and (B.dtype is _F64 or B.dtype == _F64) and A.ndim == 2 and A.shape == B.shape and A.size
            and (fa := A.flags).c_contiguous and (fb := B.flags).c_contiguous) or method != "lemke-howson":
        A, B = _as_payoffs(A, B)  # the common case skips this: the kernel checks finiteness
    elif not (fa.aligned and fb.aligned):  # (the same values aligned: the kernel reads doubles)
        A, B = _validate.c_aligned(A), _validate.c_aligned(B)
    m, n = A.shape
    k = init_label if type(init_label) is int and 0 <= init_label < m + n else _label(init_label, m, n)
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(map(repr, METHODS))}")
    if options is None:
        opts, params = _DEFAULT, _DEFAULT_PARAMS
    else:
        opts = as_options(options)
        params = _params(opts)
    if method == "tracing":
        if warm_start is not None:
            raise ValueError("warm_start is for method='lemke-howson'")
        return _trace(A, B, prior, opts, exact)
    buf = np.empty(_layout(m, n)["length"])
    code, pivots, restarts = _LEMKE_HOWSON(
        A, B, k, _slack_start(m, n) if warm_start is None else _start(warm_start, m, n),
        params, buf)
    if code == SOLVED and not exact:  # the common case, without _finish's detours
        return BimatrixResult._lazy(buf, m, n, pivots, k, restarts)
    return _after_kernel(A, B, k, code, pivots, restarts, buf, opts, exact, warm_start)


def _after_front(A, B, k, got):
    """The result of a call that ``_FRONT`` (``_core.games_front``) ran but did not settle:
    ``got`` is the kernel's (code, pivots, restarts, buf); default options."""
    code, pivots, restarts, buf = got
    return _after_kernel(A, B, k, code, pivots, restarts, buf, _DEFAULT, False, None)


def _after_kernel(A, B, k, code, pivots, restarts, buf, opts, exact, warm_start):
    """The result of a Lemke-Howson kernel call (its output ``buf``) that did not end
    solved, or with ``exact``: the error naming a payoff that is not finite, or
    ``_finish``."""
    if code == _NOT_FINITE:
        _as_payoffs(A, B)  # raises, naming the entry
    m, n = A.shape
    split = _layout(m, n)["labels"]
    ibuf = buf[split:].view(np.int64)
    return _finish(A, B, k, GameBasis._trusted(m, n, ibuf), code, pivots, restarts,
                   "lemke-howson", buf[:split], opts, exact, warm_start is None, ibuf)


def _finish(A, B, k, basis, code, pivots, restarts, method, fbuf, opts, exact, cold, ibuf=None):
    """The result from a kernel's output: re-solve a basis whose point fails the check, the
    exact certificate when asked, the exact method as the last resort of a cold float solve.
    ``ibuf``: the Lemke-Howson kernel's labels and path state (for the exact continuation)."""
    m, n = A.shape
    status = _status(code)
    stopped = status in STOPPED  # by its time limit or an interrupt: no more work
    if status != Status.SOLVED and basis is not None and not exact and not stopped:
        # The path ended with every label present (or broke down) at a point that fails the
        # check: re-solve the final basis' support system afresh (rounding of a long path).
        fixed = _resolve_float(A, B, basis, opts.tol)
        if fixed is not None:
            fbuf[:m], fbuf[m : m + n], fbuf[m + n : m + n + 3] = fixed  # x, y, out: the layout's floats
            status = Status.SOLVED
            restarts += 1
    path = None if ibuf is None else _path_state(ibuf, m, n, k)
    if exact and not stopped:
        return _certify(A, B, k, basis, pivots, restarts, method, _max_pivots(opts), path)
    if status != Status.SOLVED and method == "lemke-howson" and cold and not stopped:
        # Last resort, never needed in the tests: the exact method cannot fail.
        res = _certify(A, B, k, None, pivots, restarts, method, _max_pivots(opts), path)
        if res.success:
            return _as_float(res)
    fbuf.flags.writeable = False
    at = _layout(m, n)
    r, p = at["regret"], at["payoffs"]
    return BimatrixResult._make_from(fbuf[at["x"] : m], fbuf[at["y"] : m + n],
                                     (float(fbuf[p]), float(fbuf[p + 1])), status, int(pivots),
                                     float(fbuf[r]), basis, k, method, False, int(restarts), "", 0)


def _path_state(ibuf, m, n, k):
    """Where the kernel's last Lemke-Howson run stopped (``ibuf``: its labels and path
    state), for :func:`_games_exact.continuation`:
    ``(P labels, Q labels, side of the next pivot, labels that left)``, the labels that left
    in its last pivots oldest first, preceded by k when they reach back to its start."""
    L = m + n
    st = _layout(m, n)["state"] - _layout(m, n)["labels"]  # the path state, in ibuf
    side, run = int(ibuf[st + 1]), int(ibuf[st + 2])
    hist = ibuf[st + 3 :]
    H = hist.shape[0]
    left = [int(hist[t % H]) for t in range(max(0, run - H), run)]
    if run <= H:
        left.insert(0, k)
    return tuple(ibuf[:n].tolist()), tuple(ibuf[n:L].tolist()), side, left


def _trace(A, B, prior, opts, exact):
    m, n = A.shape
    p, q = (None, None) if prior is None else prior
    p, q = _prior(p, m, "row player"), _prior(q, n, "column player")
    at = _layout(m, n)
    labels = np.empty(at["trace_labels"], dtype=np.int64)
    fbuf = np.empty(at["trace_floats"])
    code, pivots = _TRACE(A, B, p, q, _max_pivots(opts), opts.pivot_tol, opts.tie_tol,
                            opts.tol, fbuf[:m], fbuf[m : m + n], labels, fbuf[m + n :])
    return _finish(A, B, 0, _trace_basis(labels, m, n), code, pivots, 0, "tracing", fbuf,
                   opts, exact, False)


@functools.lru_cache(maxsize=64)
def _params(opts: Options) -> np.ndarray:
    """The kernel's packed parameters ``(max_pivots, pivot_tol, tie_tol, tol)``."""
    out = np.array([float(_max_pivots(opts)), opts.pivot_tol, opts.tie_tol, opts.tol])
    out.flags.writeable = False
    return out


_DEFAULT_PARAMS = _params(_DEFAULT)
native_fronts_init()  # (NumPy's layout checked: the front relies on it)
_core.games_front_init(BimatrixResult, Status.SOLVED, "lemke-howson", _DEFAULT_PARAMS)

#: The Python function; ``solve_bimatrix`` is the core's entry that wraps it
#: (src/python_front.cpp, ``games_entry``): the calls ``solve_bimatrix(A, B)`` and
#: ``solve_bimatrix(A, B, init_label=k)`` go to ``_FRONT`` with no Python frame (then
#: ``_after_front`` when it does not settle), every other call (and any the front declines)
#: to it.
_solve_bimatrix = solve_bimatrix
solve_bimatrix = functools.update_wrapper(
    _core.games_entry(_solve_bimatrix, _after_front, globals(), _FRONT), _solve_bimatrix)


@functools.lru_cache(maxsize=64)
def _slack_start(m, n) -> np.ndarray:
    out = np.concatenate([np.arange(m, m + n), np.arange(m)])
    out.flags.writeable = False
    return out


def _start(warm_start, m, n):
    """The start labels (those of P, then those of Q) for the kernel."""
    if warm_start is None:
        return _slack_start(m, n)
    if not isinstance(warm_start, GameBasis) or (warm_start.m, warm_start.n) != (m, n):
        raise ValueError(f"warm_start must be a GameBasis of {_validate.article(m)} {m} x {n} game")
    xs, ys = list(warm_start.x_basic), list(warm_start.y_basic)
    if (len(xs) != n or len(ys) != m or len(set(xs + ys)) != m + n
            or min(xs + ys) < 0 or max(xs + ys) >= m + n):
        # (a label basic in both polytopes is no vertex pair of a path: the kernels would
        # enter a basic variable)
        raise ValueError("warm_start holds labels out of range or repeated (each of the m + n "
                         "labels must be basic in exactly one of x_basic, y_basic)")
    return np.array(xs + ys, dtype=np.int64)


def _trace_basis(labels, m, n):
    """The tracing procedure's final basis as a GameBasis (x_i, y_j basic; a_i, b_j basic
    means the slack of row i / column j is basic), or None if it is not a vertex pair."""
    L = m + n
    xb = [int(v) for v in labels if v < m] + [m + int(v) - L - m for v in labels if L + m <= v < 2 * L]
    yb = [int(v) - L for v in labels if L <= v < L + m] + [int(v) for v in labels if m <= v < L]
    if len(xb) != n or len(yb) != m:
        return None
    return GameBasis(m, n, tuple(sorted(xb)), tuple(sorted(yb)))


def _supports(basis: GameBasis):
    """(S, J, T, I): the row actions in x's support and the column actions that must be best
    responses (non-basic slacks), and the same for y."""
    m, n = basis.m, basis.n
    S = [i for i in basis.x_basic if i < m]
    J = sorted(set(range(n)) - {lab - m for lab in basis.x_basic if lab >= m})
    T = [lab - m for lab in basis.y_basic if lab >= m]
    I = sorted(set(range(m)) - {lab for lab in basis.y_basic if lab < m})
    return S, J, T, I


def _resolve_float(A, B, basis, tol):
    """Solve the support system of ``basis`` in floating point; the checked point or None."""
    if basis is None:
        return None
    m, n = basis.m, basis.n
    S, J, T, I = _supports(basis)
    if len(S) != len(J) or len(T) != len(I) or not S or not T:
        return None
    x = np.zeros(m)
    y = np.zeros(n)
    try:
        for P, sup, tight, v in ((B, S, J, x), (A.T, T, I, y)):
            k = len(sup)
            M = np.zeros((k + 1, k + 1))
            M[:k, :k] = P[np.ix_(sup, tight)].T
            M[:k, k] = -1.0
            M[k, :k] = 1.0
            rhs = np.zeros(k + 1)
            rhs[k] = 1.0
            v[sup] = np.linalg.solve(M, rhs)[:k]
    except np.linalg.LinAlgError:
        return None
    if x.min() < -1e-12 or y.min() < -1e-12:
        return None
    x = np.maximum(x, 0.0)
    y = np.maximum(y, 0.0)
    x /= x.sum()
    y /= y.sum()
    out = np.empty(3)
    return (x, y, out) if _CHECK(A, B, x, y, tol, out) else None


def _certify(A, B, k, basis, pivots, restarts, method, cap, path=None):
    """The exact answer: the support system of ``basis`` solved and checked in rational
    arithmetic; if that is not an equilibrium, exact Lemke-Howson dropping label k,
    continued from the float path's state ``path`` (see :func:`_path_state`) when one is
    given and a state in reach is a vertex pair in exact arithmetic, else from the
    artificial equilibrium."""
    m, n = A.shape
    found = None
    if basis is not None:
        S, J, T, I = _supports(basis)
        if len(S) == len(J) and len(T) == len(I) and S and T:
            found = ex.certify_support(A, B, S, J, T, I)
    if found is not None:
        xs, ys, ra, rb, pa, pb = found
        if ra == 0 and rb == 0:
            return _exact_result(m, n, xs, ys, ra, rb, pa, pb, pivots, basis, k, method,
                                 restarts, "float basis", 0)
    Aint, ea = ex.dyadic(A)
    Bint, eb = ex.dyadic(B)
    run, source, walked = None, "restart", 0
    if path is not None:
        labP, labQ, side, left = path
        run, walked = ex.continuation(Aint, Bint, k, labP, labQ, side, left, cap - pivots)
        if run.status in ("solved", "max_pivots"):
            source = "continuation"
        else:  # no vertex pair in reach, or the run went back to the artificial equilibrium
            pivots += run.pivots
            run, walked = None, 0
    if run is None:
        run = ex.lemke_howson(Aint, Bint, k, cap - pivots)
    pivots += run.pivots
    if run.status != "solved":
        zero = Fraction(0)
        return BimatrixResult(tuple(zero for _ in range(m)), tuple(zero for _ in range(n)),
                              (zero, zero), Status.MAX_PIVOTS, cap, zero, None, k,
                              "lemke-howson", True, restarts, source, walked)
    xs, ys = run.xs, run.ys
    ra, rb, pa, pb = ex.regret(Aint[:, ys[0]], Bint[xs[0], :], ea, eb, xs, ys)
    # (a tracing basis that failed is replaced by this Lemke-Howson path)
    return _exact_result(m, n, xs, ys, ra, rb, pa, pb, pivots, GameBasis(m, n, *run.labels), k,
                         "lemke-howson", restarts, source, walked)


def _exact_result(m, n, xs, ys, ra, rb, pa, pb, pivots, basis, k, method, restarts, source, walked):
    (S, xn, dx), (T, yn, dy) = xs, ys
    ok = ra == 0 and rb == 0
    return BimatrixResult(ex.strategy(m, S, xn, dx), ex.strategy(n, T, yn, dy), (pa, pb),
                          Status.SOLVED if ok else Status.NUMERICAL_FAILURE, int(pivots),
                          max(ra, rb), basis, k, method, True, int(restarts), source, walked)


def _as_float(res: BimatrixResult) -> BimatrixResult:
    x = np.array([float(v) for v in res.x])
    y = np.array([float(v) for v in res.y])
    x.flags.writeable = False
    y.flags.writeable = False
    return BimatrixResult(x, y, tuple(float(v) for v in res.payoffs), res.status, res.pivots,
                          float(res.regret), res.basis, res.init_label, res.method, False,
                          res.restarts + 1, res.exact_from, res.walked_back)


class PathsResult(tuple):
    """What :func:`lemke_paths` returns: a tuple of :class:`BimatrixResult` (it compares,
    hashes, indexes and unpacks as the plain tuple of them), with two attributes:

    Attributes
    ----------
    complete : bool
        True when the search ran to its end (every path from every equilibrium found was
        followed); False when it stopped at ``max_equilibria`` or ``time_limit`` with
        paths left to follow (more equilibria may be reachable).
    stopped : str or None
        Why an incomplete search stopped: ``"max_equilibria"`` or ``"time_limit"``; None
        when it is complete.
    """

    def __new__(cls, items=(), complete=True, stopped=None):
        self = super().__new__(cls, items)
        self.complete = bool(complete)
        self.stopped = stopped
        return self


def _positive_int(value, name):
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a positive integer or None, got {value!r}")
    if value < 1:
        raise ValueError(f"{name} must be a positive integer or None, got {value!r}")
    return int(value)


def _positive_seconds(value, name):
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number of seconds or None, got {value!r}")
    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a positive finite number of seconds or None, got {value!r}")
    return value


def lemke_paths(A, B, *, exact=False, options=None, max_equilibria=None, time_limit=None,
                progress=None) -> PathsResult:
    """Every equilibrium that Lemke-Howson paths reach: from the artificial equilibrium
    dropping each label in turn, then from each equilibrium found dropping each label, until
    no new one appears (the "all Lemke paths" search of Gambit's ``gambit-lcp``).  The
    equilibria are de-duplicated (by their strategies; a degenerate game can have several
    bases for one) and returned in the order found.  With ``exact=True`` each is certified
    as in :func:`solve_bimatrix` as soon as it is found.

    Not every equilibrium is reachable this way in general (Wilson's example in
    Shapley 1974 and von Stengel 2002, section 3.6); it is a search, not an enumeration.
    On a large game it can find a great many (thousands on a random 50 x 50 game) and run
    for a long time: ``max_equilibria`` and ``time_limit`` bound it.

    Parameters
    ----------
    A, B : (m, n) array_like
        The payoffs, as in :func:`solve_bimatrix`.
    exact : bool
        Certify each equilibrium in rational arithmetic (see :func:`solve_bimatrix`).
    options : Options or dict, optional
        As in :func:`solve_bimatrix`, for every path.
    max_equilibria : int, optional
        Stop as soon as this many equilibria are found (a positive integer).
    time_limit : float, optional
        Stop once this many seconds (wall clock, a positive finite number) have passed.
        The clock is read before every path (and every exact certificate), so the search
        ends at most one path (one certificate) after the limit: on a 50 x 50 game a path
        takes well under a millisecond, an exact certificate much longer.
    progress : callable or bool, optional
        Called as ``progress(found, explored, queued)`` (in the calling thread) after each
        start is explored, a start being the artificial equilibrium or an equilibrium basis
        from which every label is dropped in turn: ``found`` equilibria so far,
        ``explored`` starts done, ``queued`` starts waiting; and once more when a budget
        stops the search in the middle of a start (with the final ``found``).  An exception it raises stops
        the search and propagates.  ``True`` shows a bar on stderr (tqdm's when installed:
        ``pip install lemke[progress]``; else a one-line counter).

    Returns
    -------
    PathsResult
        A tuple of :class:`BimatrixResult`, in the order found, with ``complete`` (False
        when ``max_equilibria`` or ``time_limit`` stopped the search) and ``stopped``
        (``"max_equilibria"``, ``"time_limit"`` or None).

    Ctrl-C (KeyboardInterrupt) stops the search within one path and propagates (what was
    found so far is then lost: use ``time_limit`` or ``max_equilibria`` to keep it).
    """
    A, B = _as_payoffs(A, B)
    max_equilibria = _positive_int(max_equilibria, "max_equilibria")
    time_limit = _positive_seconds(time_limit, "time_limit")
    progress = _progress.check(progress)
    opts = as_options(options)
    if opts.time_limit is not None:  # the options' limit, where the argument gives none
        time_limit = opts.time_limit if time_limit is None else min(time_limit, opts.time_limit)
        opts = replace(opts, time_limit=None)
    m, n = A.shape
    interrupts = _core.interrupts()
    clock = time.perf_counter
    deadline = math.inf if time_limit is None else clock() + time_limit
    cap = math.inf if max_equilibria is None else max_equilibria
    seen_bases = set()
    found = []
    keys = set()
    queue = collections.deque()  # the equilibrium bases still to start from
    explored = 0  # the starts every label was dropped from
    reported = None  # the counts last reported
    stopped = None  # why the search stopped, None while it goes on or when it is complete
    start = None  # None: the artificial equilibrium
    complete = False
    with deadline_scope(time_limit), _progress.Reporter(
            progress, "lemke_paths", unit="start",
            describe=lambda f, e, q: (e, f"{f} found, {q} queued")) as report:
        while not complete and stopped is None:
            for k in range(m + n):
                if _core.interrupts() != interrupts:  # Ctrl-C (seen here in any thread)
                    raise KeyboardInterrupt("lemke_paths was interrupted")
                if clock() >= deadline:
                    stopped = "time_limit"
                    break
                if start is None:
                    res = solve_bimatrix(A, B, init_label=k, options=opts)
                else:
                    res = solve_bimatrix(A, B, init_label=k, warm_start=start.basis, options=opts)
                    if res.basis is not None and res.basis.x_basic == tuple(range(m, m + n)):
                        continue  # back at the artificial equilibrium
                if not res.success or res.basis is None or res.basis in seen_bases:
                    continue
                seen_bases.add(res.basis)
                queue.append(res)
                key = (tuple(np.round(np.asarray(res.x, dtype=float), 9)),
                       tuple(np.round(np.asarray(res.y, dtype=float), 9)))
                if key in keys:
                    continue
                keys.add(key)
                if exact:
                    if clock() >= deadline:
                        stopped = "time_limit"
                        break
                    res = _certify(A, B, res.init_label, res.basis, res.pivots, res.restarts,
                                   res.method, _max_pivots(opts))
                found.append(res)
                if len(found) >= cap:
                    stopped = "max_equilibria"
                    break
            else:
                explored += 1
                if queue:
                    start = queue.popleft()
                else:
                    complete = True
            counts = (len(found), explored, len(queue))
            if report.active and counts != reported:
                report.update(*counts)
                reported = counts
    return PathsResult(found, complete, stopped)
