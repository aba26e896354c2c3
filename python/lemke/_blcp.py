r"""solve_blcp: box-constrained LCPs (lo <= z <= hi), with an optional friction index.

The box LCP: find z with lo <= z <= hi and w = M z + q such that w_i >= 0 where z_i = lo_i,
w_i <= 0 where z_i = hi_i, and w_i = 0 where lo_i < z_i < hi_i; equivalently the natural
map z - mid(lo, hi, z - w) is zero.  It is solved by Lemke's method with bounded variables
(the C++ core's box engine, ``src/lemke/boxed.*``, bound as ``lemke._core.boxed``): n
pairs, each z_i at a bound or basic.

**Friction index** (``findex``, the convention of ODE and Bullet).  Row i with
``f = findex[i] >= 0`` is a friction row of the contact whose normal impulse is z_f; its
given bounds are the friction coefficient folded in, ``lo_i = -mu_i``, ``hi_i = mu_i``, and
the bounds in force are ``-mu_i z_f <= z_i <= mu_i z_f``: they move with the answer.  They
are solved exactly, not by freezing them at a first guess: each friction row becomes the
three complementarity rows of Stewart and Trinkle's LCP (one λ per friction row, as the
engines' box is per row),

.. math::

    z_i = \beta^+_i - \beta^-_i, \qquad
    0 \le \beta^+_i \perp \lambda_i + w_i \ge 0, \qquad
    0 \le \beta^-_i \perp \lambda_i - w_i \ge 0, \qquad
    0 \le \lambda_i \perp \mu_i z_f - \beta^+_i - \beta^-_i \ge 0 .

λ_i = 0 gives w_i = 0 with |z_i| <= mu_i z_f (sticking); λ_i > 0 gives |z_i| = mu_i z_f
with w_i = -λ_i sign(z_i) (sliding against the motion); z_f = 0 gives z_i = 0 with any
w_i: exactly the box [-mu_i z_f, mu_i z_f] at the final z_f.  Every other row keeps its box,
so the problem stays a box LCP, of size n + 2 n_friction, that the same kernel solves; its
matrix is M with the friction columns and rows doubled (+, -) and the λ coupling, built
once (no other densification).  When M is positive semidefinite its β block is too, and
the coupling is the one of Anitescu and Potra's analysis, under which Lemke's method ends
at a solution.  The answer is then checked on the caller's data with the coupled bounds
evaluated at the final z.
"""
from __future__ import annotations

from dataclasses import replace
from functools import lru_cache, update_wrapper
from itertools import repeat

import numpy as np

from ._frozen import frozen
from ._options import _DEFAULT, as_options, time_limited, timed
from . import _progress, _validate
from ._ladder import Cap, Rung, always, climb
from ._result import LazyField, Outcome, lazy_state, native_fronts_init
from ._status import STOPPED, Status
from ._core import boxed  # the C++ core's box engine (src/lemke/boxed.*)
from ._core import refined_solve
from . import _certify, _core
from ._certify import is_box_ray  # (the box LCP's checks: _certify, by name)

METHODS = ("bounded",)
_F64 = np.dtype(np.float64)
_SOLVED = Status.SOLVED
_new = object.__new__
_COLD = (0, 1, 2)  # covering vectors of the cold runs (boxed::solve's cov_mode)
# A warm run: covering vector 1, and a warm basis that is singular kept in part (PARTIAL: the
# z's the exchange pivots cannot make basic stay at their bounds), not given up for a cold run.
_WARM = 1 | boxed.PARTIAL


@frozen
class BoxWarmStart:
    """A final basis of a box LCP, as a plain value: which z are basic (``z_basic``) and
    which non-basic z sit at their upper bounds (``at_upper``; the others at their lower
    bounds), sorted 0-based indices, for a problem of size n.  With a friction index the
    basis is that of the extended problem (see the module docstring), so n is larger than
    the caller's n: ``n = rows + 2 len(friction)``, where ``friction`` lists (sorted) the
    caller's friction rows; the extended variables are the caller's rows (β+ for a friction
    row), then β- of each friction row in that order, then λ of each.  Pass it back for a
    problem of the same size and the same friction rows (anything else is a ``ValueError``
    naming ``warm_start``); when rows appear, vanish or move, carry it over with
    :meth:`take` or :meth:`relabel`.

    Each caller's row has a *state*: an ordinary row's z_i is at lo (the cold start's
    state), at hi or basic; a friction row's state is that of its three variables (β+, β-,
    λ).  :meth:`take` and :meth:`relabel` move these states with the rows."""

    n: int
    z_basic: tuple[int, ...]
    at_upper: tuple[int, ...]
    friction: tuple[int, ...] = ()

    def __post_init__(self):
        n = self.n
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"BoxWarmStart.n must be a non-negative integer, got {n!r}")
        for name in ("z_basic", "at_upper", "friction"):
            try:
                idx = tuple(sorted(int(i) for i in getattr(self, name)))
            except (TypeError, ValueError):
                raise TypeError(f"BoxWarmStart.{name} must be a sequence of integers") from None
            if len(set(idx)) != len(idx) or (idx and (idx[0] < 0 or idx[-1] >= n)):
                raise ValueError(f"BoxWarmStart.{name} must hold distinct indices in [0, {n}), got {idx}")
            object.__setattr__(self, name, idx)
        if set(self.z_basic) & set(self.at_upper):
            raise ValueError("BoxWarmStart: an index cannot be basic and at its upper bound")
        nf = len(self.friction)
        if nf and (n - 2 * nf <= self.friction[-1]):
            raise ValueError(f"BoxWarmStart.friction: {nf} friction rows need n >= rows + {2 * nf} "
                             f"with every friction row below rows; got n = {n}, rows {self.friction}")
        object.__setattr__(self, "n", int(n))

    @property
    def rows(self) -> int:
        """The caller's number of rows (n less the two extended variables of each friction
        row)."""
        return self.n - 2 * len(self.friction)

    def take(self, indices, findex=None) -> "BoxWarmStart":
        """The basis carried to a problem whose row i is row ``indices[i]`` of this one (the
        meaning of :meth:`lemke.WarmStart.take`), for when contacts come and go between
        steps: a kept row keeps its state (at lo, at hi or basic; a friction row its three
        variables'), a row of the old problem that no index names is dropped, and a new row
        (``indices[i] == -1``) starts cold, at its lower bound (a new friction row: its β+,
        β- and λ at 0).  ``len(indices)`` is the new number of rows.

        ``findex``: the new problem's friction index (the one you pass to
        :func:`solve_blcp`; only which rows are friction rows matters here), None for none.
        Relabel it yourself as the rows move (``findex[i]`` names the new row of the
        normal).  A kept row must keep its kind: a friction row stays a friction row, an
        ordinary row an ordinary one (else ``ValueError`` naming ``findex``).

        >>> BoxWarmStart(3, (0,), (2,)).take([2, -1, 0])   # old row 2 -> 0, new row 1, 0 -> 2
        BoxWarmStart(n=3, z_basic=(2,), at_upper=(0,), friction=())
        """
        idx = _row_index(indices, self.rows, "indices")
        return _take_codes(self.row_states(), idx, findex)

    def relabel(self, old_labels, new_labels, findex=None) -> "BoxWarmStart":
        """:meth:`take` by labels (the meaning of :meth:`lemke.WarmStart.relabel`): row j of
        this problem carries label ``old_labels[j]``, row i of the new one
        ``new_labels[i]``; a label not in ``old_labels`` is a new row (it starts cold, at its
        lower bound), an old label not in ``new_labels`` a dropped row.  Labels are hashable
        values distinct within each list; two 1-D integer numpy arrays are matched by
        sorting, with no Python object per label.  ``findex``: as in :meth:`take`."""
        return _take_codes(self.row_states(), _label_index(old_labels, new_labels, self.rows), findex)

    def row_states(self) -> np.ndarray:
        """The state of each of the caller's rows, one int8 code per row (the codes of
        :class:`BoxWarmStartBatch`): an ordinary row 0 (z at lo), 1 (at hi) or 2 (basic); a
        friction row ``3 + 9 s(β+) + 3 s(β-) + s(λ)`` with s in {0, 1, 2} the same way."""
        d = self.__dict__
        c = d.get("_codes")
        if c is None:
            s = np.zeros(self.n, dtype=np.int8)
            s[list(self.at_upper)] = 1
            s[list(self.z_basic)] = 2
            rows, F = self.rows, np.array(self.friction, dtype=np.int64)
            c = s[:rows].copy()
            if F.size:
                nf = F.size
                c[F] = 3 + 9 * s[F] + 3 * s[rows:rows + nf] + s[rows + nf:]
            c.setflags(write=False)
            d["_codes"] = c
        return c

    @classmethod
    def from_row_states(cls, states) -> "BoxWarmStart":
        """The warm start whose :meth:`row_states` are ``states`` (codes 0..29)."""
        c = np.asarray(states)
        if c.ndim != 1 or (c.size and c.dtype.kind not in "iu"):
            raise TypeError("states must be a 1-D sequence of integer codes")
        if c.size and (c.min() < 0 or c.max() > 29):
            raise ValueError(f"states must be codes in [0, 29], got {int(c.min())} .. {int(c.max())}")
        return _from_codes(c.astype(np.int8))

    @classmethod
    def _trusted(cls, n, z_basic, at_upper, friction=()) -> "BoxWarmStart":
        """Build from values the solver made itself (sorted, in range): no checks."""
        ws = object.__new__(cls)
        ws.__dict__.update(n=n, z_basic=z_basic, at_upper=at_upper, friction=friction)
        return ws

    def __getstate__(self):
        # the fields only, not the arrays kept with it
        return {"n": self.n, "z_basic": self.z_basic, "at_upper": self.at_upper,
                "friction": self.friction}

    def _kernel_flags(self):
        """Its basis as ``boxed::solve`` and ``front`` take it: 2n flags, the basic
        z's then the non-basic z's at hi; made once and kept with the (immutable) warm
        start, as ``WarmStart``'s index array in ``_lcp``."""
        d = self.__dict__
        f = d.get("_flags")
        if f is None:
            n = self.n
            f = np.zeros(2 * n, dtype=np.bool_)
            idx = d.get("_final")  # (final[:m], k) of the kernel run that made it
            if idx is None:
                f[list(self.z_basic)] = True
                f[n:][list(self.at_upper)] = True
            else:
                f[idx[0][: idx[1]]] = True
                f[n:][idx[0][idx[1]:]] = True
            d["_flags"] = f
        return f


def _row_index(indices, n, name):
    """``indices`` as an int64 array of old rows in [-1, n) naming each old row at most
    once, or a TypeError/ValueError naming ``name``."""
    idx = np.asarray(indices)
    if idx.ndim != 1 or (idx.size and idx.dtype.kind not in "iu"):
        raise TypeError(f"{name} must be a 1-D sequence of integers")
    idx = idx.astype(np.int64)
    if idx.size and (idx.min() < -1 or idx.max() >= n):
        raise ValueError(f"{name} must lie in [-1, {n}), got {idx.min()} .. {idx.max()}")
    kept = idx[idx >= 0]
    if np.unique(kept).size != kept.size:
        raise ValueError(f"{name} name an old row twice")
    return idx


def _label_index(old_labels, new_labels, n):
    """The old row of each new label (-1: a new one), as :meth:`BoxWarmStart.take` takes
    it; ValueError when a list holds a label twice or ``old_labels`` has not n labels."""
    if (type(old_labels) is np.ndarray and type(new_labels) is np.ndarray and old_labels.ndim == 1
            and new_labels.ndim == 1 and old_labels.dtype.kind in "iu" and new_labels.dtype.kind in "iu"):
        old, new = old_labels.astype(np.int64), new_labels.astype(np.int64)
        if old.size != n:
            raise ValueError(f"old_labels has {old.size} labels for a basis of {n} rows")
        order = np.argsort(old, kind="stable")
        srt = old[order]
        if srt.size > 1 and (srt[1:] == srt[:-1]).any():
            raise ValueError("old_labels holds a label twice")
        if new.size > 1 and np.unique(new).size != new.size:
            raise ValueError("new_labels holds a label twice")
        pos = np.minimum(np.searchsorted(srt, new), max(n - 1, 0))
        found = (srt[pos] == new) if n else np.zeros(new.size, dtype=bool)
        return np.where(found, order[pos] if n else -1, -1).astype(np.int64)
    old = list(old_labels)
    if len(old) != n:
        raise ValueError(f"old_labels has {len(old)} labels for a basis of {n} rows")
    where = dict(zip(old, range(n)))
    if len(where) != n:
        raise ValueError("old_labels holds a label twice")
    new = list(new_labels)
    if len(set(new)) != len(new):
        raise ValueError("new_labels holds a label twice")
    return np.fromiter(map(where.get, new, repeat(-1)), np.int64, len(new))


def _friction_mask(findex, m, name="findex"):
    """Which of the m new rows are friction rows (``findex[i] >= 0``)."""
    if findex is None:
        return np.zeros(m, dtype=bool)
    f = np.asarray(findex)
    if f.shape != (m,) or (f.size and f.dtype.kind not in "iu"):
        raise ValueError(f"{name} must be None or {m} integers (one per new row), got shape {f.shape}"
                         f" and dtype {f.dtype}")
    return f >= 0


def _take_codes(codes, idx, findex):
    """The warm start of the rows ``idx`` (-1: new) of the row states ``codes``, the new
    rows' kinds from ``findex``."""
    return _from_codes(_carried(codes, idx, findex))


def _carried(codes, idx, findex):
    """The row states ``codes`` carried to the new rows ``idx`` (-1: a new row, cold), the
    new rows' kinds from ``findex`` (the rules of :meth:`BoxWarmStart.take`)."""
    fric = _friction_mask(findex, idx.size)
    new = np.append(codes, np.int8(0))[idx]
    was = new >= 3
    kept = idx >= 0
    bad = np.flatnonzero(kept & (was != fric))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"findex makes new row {i} {'a friction' if fric[i] else 'an ordinary'} row, "
                         f"but old row {int(idx[i])}, carried to it, was {'a friction' if was[i] else 'an ordinary'}"
                         " row: a row keeps its kind (pass the new problem's findex)")
    new[~kept & fric] = 3  # a new friction row: beta+, beta-, lambda at 0
    return new


def _from_codes(c):
    """The BoxWarmStart of the row states c (int8, codes 0..29): its size, friction rows and
    codes now, its ``z_basic`` and ``at_upper`` when first read (:class:`_FromCodes`; the
    kernels take the codes, so a warm start passed straight back builds neither)."""
    if c.size <= _FEW_ROWS:
        F = tuple([i for i, x in enumerate(c.tolist()) if x >= 3])
    else:
        F = tuple(np.flatnonzero(c >= 3).tolist())
    ws = _new(BoxWarmStart)
    c = c.copy()
    c.setflags(write=False)
    ws.__dict__.update(n=c.size + 2 * len(F), friction=F, _codes=c)
    return ws


_FEW_ROWS = 48  # up to this many rows, the codes are read in a Python loop: cheaper than numpy


def _basis_of_codes(c):
    """``(z_basic, at_upper)`` of the row states c (the extended variables in their order:
    the caller's rows, then β- and λ of each friction row)."""
    rows = c.size
    if rows <= _FEW_ROWS:
        return _basis_of_codes_small(c)
    F = np.flatnonzero(c >= 3)
    nf = F.size
    s = np.zeros(rows + 2 * nf, dtype=np.int8)
    s[:rows] = c
    if nf:
        e = c[F] - 3
        s[F] = e // 9
        s[rows:rows + nf] = (e // 3) % 3
        s[rows + nf:] = e % 3
    return tuple(np.flatnonzero(s == 2).tolist()), tuple(np.flatnonzero(s == 1).tolist())


def _basis_of_codes_small(c):
    """:func:`_basis_of_codes` for a few rows, by a loop over c's codes."""
    cl = c.tolist()
    F = [i for i, x in enumerate(cl) if x >= 3]
    states = [x if x < 3 else (x - 3) // 9 for x in cl]
    if F:
        states += [((cl[i] - 3) // 3) % 3 for i in F]
        states += [(cl[i] - 3) % 3 for i in F]
    return (tuple([i for i, s in enumerate(states) if s == 2]),
            tuple([i for i, s in enumerate(states) if s == 1]))


class _FromCodes(LazyField):
    """``z_basic`` / ``at_upper`` of a BoxWarmStart made from row states (``_from_codes``),
    from its ``_codes`` when first read; a warm start built with its fields never reaches
    it (they are in its ``__dict__``)."""

    __slots__ = ()

    def make(self, d):
        codes = d.get("_codes")
        if codes is None:
            raise AttributeError(f"'BoxWarmStart' object has no attribute {self.name!r}")
        z_basic, at_upper = _basis_of_codes(codes)
        d["z_basic"], d["at_upper"] = z_basic, at_upper  # (both at once)
        return z_basic if self.name == "z_basic" else at_upper


BoxWarmStart.z_basic = _FromCodes("z_basic")
BoxWarmStart.at_upper = _FromCodes("at_upper")


@frozen(eq=False)
class BLCPResult(Outcome):
    """The outcome of :func:`lemke.solve_blcp`.

    Attributes
    ----------
    z, w : ndarray
        The final point and ``w = M z + q`` recomputed from the caller's data.
    status : Status
        ``SOLVED`` only when the point passed the check on the caller's data (with a
        friction index: on the coupled bounds at the final z).
    pivots : int
        Pivots made, bound flips and exchange pivots included.
    residual : float
        ``max_i |z_i - mid(lo_i, hi_i, z_i - w_i)|`` on the caller's data (bounds in force).
    ray : ndarray or None
        On ``RAY_TERMINATION`` (checked), the direction (dz, dz0) of the secondary ray of
        the augmented problem ``w + covering * z0``: along it the point stays feasible and
        complementary for every step, which for a positive semidefinite M proves that the
        problem has no solution.  With a friction index, of the extended problem.
    z0 : float
        The artificial variable's final value.
    covering : ndarray
        The covering vector in the caller's rows (the augmented rows read w + covering z0).
    warm_start : BoxWarmStart or None
    lo, hi : ndarray
        The bounds in force at z: the caller's, or with a friction index the coupled
        bounds -mu_i z_f, mu_i z_f of the friction rows.
    row_scale, col_scale : ndarray
        The equilibration the kernel pivoted on (powers of two).
    recoveries : int
        Runs after the first (other covering vectors, exact ties, a cold start after a
        warm one that failed).
    """

    z: np.ndarray
    w: np.ndarray
    status: Status
    pivots: int
    residual: float
    ray: np.ndarray | None
    z0: float
    covering: np.ndarray
    warm_start: BoxWarmStart | None
    lo: np.ndarray
    hi: np.ndarray
    row_scale: np.ndarray
    col_scale: np.ndarray
    recoveries: int = 0

    def __repr__(self) -> str:
        return (f"BLCPResult(status={self.status.name}, pivots={self.pivots}, "
                f"residual={self.residual:.3g}, n={self.z.size})")

    def __getstate__(self):
        return lazy_state(self, _BOX_FIELDS)


class _BoxField(LazyField):
    """A field of a solved box result built by ``solve_blcp``'s one-call paths: a view of
    the kernel's buffer, or its warm start (``_result.LazyField``; a small solve that reads
    only ``z`` pays for no other view).  ``_src`` is ``(buf, final, N, k, m, spans)``: the
    buffer, the final basis (``final[:k]`` basic, ``final[k:m]`` at hi; None from
    ``_core.blcp_front`` where the result keeps its warm start, which is then never made
    here) of a problem of size N, and where each field sits in the buffer (:func:`_spans`)."""

    __slots__ = ()

    def make(self, d):
        src = d.get("_src")
        if src is None:
            raise AttributeError(f"'BLCPResult' object has no attribute {self.name!r}")
        buf, final, N, k, m, spans = src
        if self.name == "warm_start":
            nf = (final.size - N) // 2  # (friction: ints, the friction rows after the basis)
            F = final[slice(*_layout(N - 2 * nf, nf, True)["friction_rows"])] if nf > 0 else ()
            v = BoxWarmStart._trusted(N, *_split(final, k, m), tuple(F.tolist()) if nf > 0 else ())
            v.__dict__["_final"] = (final[:m], k)  # for its flags, if it is passed back
            return v
        if buf.flags.writeable:  # the result's arrays are read-only, as the others'
            buf.setflags(write=False)
        a, b = spans[self.name]
        return buf[a:b]


def _split(final, k, m):
    idx = final[:m].tolist()
    return tuple(idx[:k]), tuple(idx[k:])


@lru_cache(maxsize=1024)
def _layout(n, nf=0, friction=False):
    """The box engine's buffers for n rows with nf friction rows (``friction``: a friction
    index is given): ``{field: (start, stop)}`` and their lengths, as the C++ core states
    them once (``src/lemke/boxed.hpp``: ``BoxLayout``, ``FrontLayout``; exported as
    ``_core.boxed.layout``, whose docstring lists the names).  Every size and slice of
    these buffers here and in ``_blcp_many`` derives from it."""
    return boxed.layout(n, nf, friction)


def _spans(n, N, friction):
    """Where the fields of a result of size n sit in the buffer of the box engine: without
    a friction index, the run's (:func:`_layout`); with one (an extended problem of size
    N), that problem's covering vector there, and the caller's arrays after it."""
    key = (n, N, friction)
    s = _SPANS.get(key)
    if s is None:
        L = _layout(n, (N - n) // 2, friction)
        names = ("z", "w", "lo", "hi", "row_scale", "col_scale") if friction else \
            ("z", "w", "covering", "row_scale", "col_scale")
        s = {name: L["caller_" + name if friction else name] for name in names}
        if friction:
            s["covering"] = L["covering"]
        s = _SPANS.setdefault(key, s)
    return s


_SPANS = {}

#: The lazy fields (lo and hi only with a friction index: else the caller's arrays).
_BOX_FIELDS = ("z", "w", "covering", "row_scale", "col_scale", "warm_start", "lo", "hi")
for _name in _BOX_FIELDS:
    setattr(BLCPResult, _name, _BoxField(_name))
del _name


class _Run:
    """The output arrays of one kernel run and what it returned."""

    __slots__ = ("z", "w", "ray", "d", "R", "C", "buf", "final", "code", "pivots", "z0",
                 "ok", "residual", "k", "m")

    def __init__(self, n, buf=None, final=None):
        # One buffer, sliced as the engine lays it out (_layout: BoxLayout).
        L = _layout(n)
        buf = np.empty(L["length"]) if buf is None else buf
        self.z, self.w, self.d = buf[slice(*L["z"])], buf[slice(*L["w"])], buf[slice(*L["covering"])]
        self.R, self.C = buf[slice(*L["row_scale"])], buf[slice(*L["col_scale"])]
        self.ray = buf[slice(*L["ray"])]
        self.buf = buf
        self.final = np.empty(n, dtype=np.int64) if final is None else final
        self.k = self.m = 0

    def go(self, M, q, lo, hi, warm, mode, opts, max_pivots, tie_tol):
        """Run ``boxed::solve``; ``warm`` (2n flags): the basic z's, then the
        non-basic z's at hi."""
        (self.code, self.pivots, self.z0, self.ok, self.residual, self.k, self.m) = boxed.solve(
            M, q, lo, hi, warm, mode, max_pivots, opts.pivot_tol, tie_tol, opts.tol,
            self.buf, self.final)
        return self

    def set_basis(self, zb, zh):
        """Record the final basis from flags (a point computed outside the kernel)."""
        b, h = np.flatnonzero(zb), np.flatnonzero(zh & ~zb)
        self.k, self.m = b.size, b.size + h.size
        self.final[: self.m] = np.concatenate([b, h])

    def basis_flags(self, n):
        return _basis_flags(self.final, self.k, self.m, n)

    def warm(self, n):
        idx = self.final.tolist()
        return BoxWarmStart._trusted(n, tuple(idx[: self.k]), tuple(idx[self.k: self.m]))


def solve_blcp(M, q, lo, hi, *, findex=None, method="bounded", warm_start=None,
               options=None, progress=None) -> BLCPResult:
    r"""Solve the box LCP: lo <= z <= hi, w = M z + q, w_i >= 0 where z_i = lo_i, w_i <= 0
    where z_i = hi_i, w_i = 0 in between.

    Parameters
    ----------
    M : (n, n) array_like
    q : (n,) array_like
    lo, hi : (n,) array_like or scalars
        The bounds; lo may hold -inf and hi +inf (one-sided and free variables); lo_i = hi_i
        fixes z_i.  No NaN; lo <= hi.
    findex : (n,) array_like of int, optional
        Friction index, as in ODE and Bullet: -1 for an ordinary row; ``f = findex[i] >= 0``
        makes row i a friction row of the contact whose normal impulse is z_f, with
        ``lo_i = -mu_i``, ``hi_i = mu_i`` (mu_i >= 0) and the bounds in force
        ``-mu_i z_f <= z_i <= mu_i z_f`` at the answer (see the module docstring for how
        they are solved exactly).  f must not be i nor a friction row, and lo_f >= 0.
    method : {"bounded"}
        Lemke's method with bounded variables (``src/lemke/boxed.cpp``).
    warm_start : BoxWarmStart, optional
        The ``warm_start`` of an earlier result of the same size (and friction structure):
        if its basis still solves this problem the answer comes with 0 pivots; otherwise
        Lemke restarts from it (from the part of it that can be made basic, where its block
        is singular; with a friction index, when that run fails, once more from it with the
        friction rows cold), and then cold if that fails.
    options : Options or dict, optional
        As for :func:`lemke.solve_lcp`.

    Returns
    -------
    BLCPResult

    Examples
    --------
    >>> import lemke
    >>> r = lemke.solve_blcp([[2.0, 1.0], [1.0, 2.0]], [-5.0, 1.0], [0.0, -1.0], [2.0, 1.0])
    >>> r.status.name, r.z.tolist()
    ('SOLVED', [2.0, -1.0])
    """
    if progress is not None and progress is not False:
        return _progress.reported(_progress.check(progress), "solve_blcp", solve_blcp, M, q, lo,
                                  hi, findex=findex, method=method, warm_start=warm_start,
                                  options=options)
    if options is None and method == "bounded":
        # The commonest calls, whole in one native call (src/python_front_box.cpp): plain
        # float64 arrays give the result, or what is left to do (the cold run's answer and
        # buffers for _finish; False: the general path, where _one_call would go), else None.
        r = _FRONT(M, q, lo, hi, findex, warm_start)
        if r is not None:
            if r is False or type(r) is tuple:
                return _after_front(M, q, lo, hi, findex, warm_start, r)
            return r
        if (c := _validate.plain_blcp(M, q, lo, hi, findex)) is not None:
            # array-likes (and scalar bounds) converted once, as as_blcp below would
            # convert them: then the front, through the entry
            return solve_blcp(c[0], c[1], c[2], c[3], findex=c[4], warm_start=warm_start)
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_blcp, M, q, lo, hi, findex=findex, method=method,
                     warm_start=warm_start)
    if (type(M) is _ND and type(q) is _ND and type(lo) is _ND and type(hi) is _ND
            and (M.dtype is _F64 or M.dtype == _F64) and (q.dtype is _F64 or q.dtype == _F64)
            and (lo.dtype is _F64 or lo.dtype == _F64) and (hi.dtype is _F64 or hi.dtype == _F64)
            and M.ndim == 2 and q.ndim == 1
            and M.shape[0] == M.shape[1] == q.shape[0] == lo.shape[0] == hi.shape[0]
            and lo.ndim == 1 and hi.ndim == 1 and method == "bounded" and M.flags.c_contiguous):
        n = q.shape[0]
        if findex is None and warm_start is None:
            # The common case: no copies, one kernel call (the C++ core's boxed.solve, GIL
            # released) that also validates the data.
            opts = _DEFAULT if options is None else as_options(options)
            if n < len(_NO):
                buf = np.empty(_layout(n)["length"])
                final = np.empty(n, dtype=np.int64)
                mp = opts.max_pivots
                out = boxed.solve(M, q, lo, hi, _NO[n], 0, 100 * (n + 1) if mp is None else mp,
                                  opts.pivot_tol, opts.tie_tol, opts.tol, buf, final)  # (pivot_limit inlined)
                if out[0] == 0 and out[3]:  # solved and checked: the result, built lazily
                    res = _new(BLCPResult)  # (_lazy, inlined: the common case)
                    d = res.__dict__
                    d["status"] = _SOLVED
                    d["pivots"] = out[1]
                    d["residual"] = out[4]
                    d["ray"] = None
                    d["z0"] = 0.0
                    d["lo"] = lo
                    d["hi"] = hi
                    d["_src"] = (buf, final, n, out[5], out[6],
                                 _SPANS.get((n, n, False)) or _spans(n, n, False))
                    return res
                if out[0] >= 0:
                    run = _Run(n, buf, final)
                    run.code, run.pivots, run.z0, run.ok, run.residual, run.k, run.m = out
                    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                        return _from_final(_finish(M, q, lo, hi, opts, run), M, q, lo, hi,
                                           None, opts)
        elif ((findex is None or (type(findex) is np.ndarray and findex.dtype == _I64
                                  and findex.shape == q.shape and findex.flags.carray))
              and (warm_start is None or type(warm_start) is BoxWarmStart)
              and M.flags.carray and q.flags.carray and lo.flags.carray and hi.flags.carray):
            # A friction index and/or a warm start on plain data: one kernel call that also
            # validates the data (the general path below when it says the runs need more).
            opts = _DEFAULT if options is None else as_options(options)
            res = _one_call(M, q, lo, hi, findex, warm_start, opts, validated=False)
            if res is not None:
                return res
            return _general(M, q, lo, hi, findex, warm_start, opts)
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(map(repr, METHODS))}")
    M, q, lo, hi, findex = as_blcp(M, q, lo, hi, findex)
    opts = as_options(options)
    # The numpy parts (a basis point recomputed, a ray checked) may overflow on data near
    # the float range; they judge their results themselves.
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        if findex is None:
            res = _solve(M, q, lo, hi, opts, warm_start)
        else:
            res = _solve_friction(M, q, lo, hi, findex, opts, warm_start)
        return _from_final(res, M, q, lo, hi, findex, opts)


def _after_front(M, q, lo, hi, findex, warm_start, r):
    """The result of a call that ``_FRONT`` (``_core.blcp_front``) ran but did not settle
    (default options): ``r`` False, the general path (where _one_call would go), or the cold
    run's (code, pivots, z0, ok, residual, k, m, buf, final) for _finish."""
    if r is False:
        return _general(M, q, lo, hi, findex, warm_start, _DEFAULT)
    run = _Run(q.shape[0], r[7], r[8])
    run.code, run.pivots, run.z0, run.ok, run.residual, run.k, run.m = r[:7]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _from_final(_finish(M, q, lo, hi, _DEFAULT, run), M, q, lo, hi, None, _DEFAULT)


def _general(M, q, lo, hi, findex, warm_start, opts):
    """The general path after ``_one_call`` left the runs undecided (its kernel calls are
    not made again)."""
    M, q, lo, hi, findex = as_blcp(M, q, lo, hi, findex)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        if findex is None:
            res = _solve(M, q, lo, hi, opts, warm_start, tried=True)
        else:
            res = _solve_friction(M, q, lo, hi, findex, opts, warm_start, tried=True)
        return _from_final(res, M, q, lo, hi, findex, opts)


def _from_final(res, M, q, lo, hi, findex, opts):
    """The last recovery of a box LCP: when every run ended on a point that fails the check
    on the caller's data (NUMERICAL_FAILURE), Lemke's method once more, warm-started from
    the final basis of those runs (the restart from the best basis seen, as issue 11's
    recovery order has it).  A degenerate contact step (a resting contact whose row of the
    data is all rounding, |q_i| ~ 1e-13) ended with that contact's impulse at 0 and w_i =
    -6e-13 against terms of 6e-13: wrong in its own row's terms, and the restart from that
    basis makes the contact's impulse basic and solves it.  Its pivots and one more
    recovery are added to the result's; its answer is judged by the same check."""
    ws = res.warm_start
    if res.status != Status.NUMERICAL_FAILURE or ws is None:
        return res
    if findex is None:
        again = _solve(M, q, lo, hi, opts, ws)
    else:
        again = _solve_friction(M, q, lo, hi, findex, opts, ws)
    if again.status != Status.SOLVED:
        return res
    return replace(again, pivots=res.pivots + again.pivots,
                   recoveries=res.recoveries + again.recoveries + 1)


_NO = [np.zeros(2 * n, dtype=np.bool_) for n in range(257)]  # no warm start, per size
_ND = np.ndarray
_I64 = np.dtype(np.int64)
_NO_FINDEX = np.empty(0, dtype=np.int64)
_NO_WORK = np.empty(0)
_NEED_RUN, _UNDECIDED = boxed.NEED_RUN, boxed.UNDECIDED


def _no_warm(N):
    return _NO[N] if N < len(_NO) else np.zeros(2 * N, dtype=np.bool_)


def _one_call(M, q, lo, hi, findex, ws, opts, validated):
    """``boxed::front`` (validation, the extended problem of a friction index, a warm
    start's own point, the check on the caller's data) around the runs of
    ``boxed::solve`` that ``_solve`` and ``_finish`` would make (from the warm start,
    cold, the ladder): the result, built lazily, when they end solved and checked; None
    when the general path must decide (a checked ray, a failed ladder, a friction answer
    that fails the check), or when a warm start of another size comes with data not
    ``validated`` yet (the general path says which is wrong).  Raises, naming the entry,
    on data the kernel refuses.  The warm start's own point costs one kernel call."""
    n = q.shape[0]
    friction = findex is not None and n > 0
    nf = int(np.count_nonzero(findex >= 0)) if friction else 0
    L = _layout(n, nf, friction)
    N = L["N"]
    if ws is None:
        warm = _no_warm(N)
    else:
        if ws.n != N or (ws.friction and not nf):
            if validated:
                _check_warm(ws, N, ())  # raises
            return None
        warm = ws._kernel_flags()
    buf = np.empty(L["length"])
    ints = np.empty(L["ints_length"], dtype=np.int64)
    work = np.empty(L["work_length"]) if nf else _NO_WORK
    fi = findex if friction else _NO_FINDEX
    tol = opts.tol
    front = boxed.front
    code, residual = front(boxed.PREPARE, M, q, lo, hi, fi, warm, ws is not None, tol, buf, ints,
                           work)
    if nf and ws is not None and (code == 0 or code == _NEED_RUN or code == _UNDECIDED):
        # the data passed: F (the friction rows) is in ints
        F = tuple(ints[slice(*L["friction_rows"])].tolist())
        if ws.friction != F:  # a basis of other friction rows
            if validated:
                _check_warm(ws, N, F)  # raises
            return None
    if code == 0:  # the warm start's own point: 0 pivots
        return _lazy(buf, ints, N, 0, 0, n, lo, hi, friction, 0, residual, 0, ws)
    if code != boxed.NEED_RUN:
        if code == boxed.UNDECIDED:
            return None
        as_blcp(M, q, lo, hi, findex)  # raises, naming the entry
        raise AssertionError("the kernel refused data that validation accepts")
    if nf:
        A = work[slice(*L["work_M"])].reshape(N, N)
        qa, la, ha = (work[slice(*L[name])] for name in ("work_q", "work_lo", "work_hi"))
        final = ints[slice(*L["final"])]
    else:
        A, qa, la, ha, final = M, q, lo, hi, ints
    ext = buf[: L["run_length"]]  # the run's fields (the extended problem's with friction rows)
    ez, ew, ed, eR, eray = (slice(*L[name]) for name in ("z", "w", "covering", "row_scale", "ray"))
    limit, pt, tt = opts.pivot_limit(N), opts.pivot_tol, opts.tie_tol
    solve = boxed.solve
    rec = 0

    def done(k, m, pivots, residual, rec, from_warm):
        # a run solved and checked: with a friction index the check on the caller's data
        # decides (front's SOLVED_RUN phase; failed: the general path)
        if friction:
            code, residual = front(boxed.SOLVED_RUN, M, q, lo, hi, fi, warm, from_warm, tol, buf,
                                   ints, work)
            if code != 0:
                return None
        return _lazy(buf, ints, N, k, m, n, lo, hi, friction, pivots, residual, rec, None)
    # The ladder (_ladder.py; boxed::batch's one_call has the same rungs): the warm start's
    # basis (_warm), the same with its friction rows cold (_reset), _solve's cold run, then
    # _finish's rungs (other covering vectors, exact ties); a run solved and checked settles
    # it; a checked ray (the general path reports it) or a stop in any rung ends it.
    cap = Cap(limit)
    cold = _no_warm(N)
    c = k = m = 0
    residual = 0.0
    accepted = ended = False

    def go(flags, mode, left, tie):
        nonlocal c, k, m, residual, accepted
        c, p, z0, ok, residual, k, m = solve(A, qa, la, ha, flags, mode, left, pt, tie, tol,
                                             ext, final)
        cap.charge(p)
        accepted = c == 0 and ok
        return z0, ok

    def from_warm():
        nonlocal residual, accepted, rec
        _, ok = go(warm, _WARM, limit, tt)
        if not accepted:  # _finish: the point of its final basis, recomputed
            point = _checked_point(A, qa, la, ha, *_basis_flags(final, k, m, N), tol, ext[eR])
            if point is not None:
                ok = True
                ext[ez], ext[ew], residual = point
        accepted = ok
        if not ok:
            rec = 1

    def friction_cold():
        nonlocal rec
        go(_reset(warm, N, _friction_vars(ints[slice(*L["friction_rows"])], n)), _WARM,
           max(0, cap.left()), tt)
        if not accepted:
            rec = 2

    def cold_run():
        nonlocal ended
        z0, _ = go(cold, 0, max(0, cap.left()), tt)
        ended = (not accepted and c == Status.RAY_TERMINATION
                 and is_box_ray(A, qa, la, ha, ext[ed], ext[ez], z0, ext[eray], tol))

    def other(mode, tie):
        def run():
            nonlocal rec
            go(cold, mode, cap.left(), tie)
            rec += 1
        return run

    def left():
        return cap.left() > 0

    solved_by = climb(lambda: accepted or ended or c in STOPPED,
                      Rung("the warm start's basis", lambda: ws is not None, from_warm),
                      Rung("its friction rows cold", lambda: ws is not None and nf,
                           friction_cold),
                      Rung("cold", always, cold_run),
                      Rung("other covering vectors", left, other(1, tt)),
                      Rung("exact ties", left, other(2, 0.0)))
    if not accepted:
        return None
    return done(k, m, cap.pivots, residual, rec, solved_by < 2)


def _lazy(buf, final, N, k, m, n, lo, hi, friction, pivots, residual, rec, ws):
    """A solved result built lazily from the kernels' buffer (``_BoxField``); ``ws``: the
    warm start whose own basis it is, else None (made from ``final`` when read)."""
    res = _new(BLCPResult)
    d = res.__dict__
    d["status"] = _SOLVED
    d["pivots"] = pivots
    d["residual"] = residual
    d["ray"] = None
    d["z0"] = 0.0
    if not friction:
        d["lo"] = lo
        d["hi"] = hi
    if rec:
        d["recoveries"] = rec
    if ws is not None:
        d["warm_start"] = ws
    d["_src"] = (buf, final, N, k, m, _spans(n, N, friction))
    return res


def as_blcp(M, q, lo, hi, findex=None):
    """The validated box LCP ``(M, q, lo, hi, findex)`` (``_validate.blcp``)."""
    d = _validate.blcp(M, q, lo, hi, findex)
    return d["M"], d["q"], d["lo"], d["hi"], d.get("findex")


def _check_warm(ws, n, friction=(), what="warm_start", problem="this one"):
    """``ws`` must be None or a BoxWarmStart of size n (extended, with a friction index) for
    the friction rows ``friction`` (a tuple; None: not checked).  A WarmStart of an LCP (or
    either kind of batch) is a ValueError, any other object a TypeError, naming ``what``."""
    if ws is not None:
        if not isinstance(ws, BoxWarmStart):
            _validate.wrong_kind(ws, what, "lemke.BoxWarmStart")
            raise TypeError(f"{what} must be a lemke.BoxWarmStart, got {type(ws).__name__}")
        if ws.n != n:
            raise ValueError(f"{what} is for a problem of size {ws.n}, {problem} has n = {n}"
                             " (carry a basis to new rows with BoxWarmStart.take or .relabel)")
        if friction is not None and ws.friction != friction:
            raise ValueError(f"{what} is for friction rows {list(ws.friction)}, {problem} has "
                             f"friction rows {list(friction)} (carry a basis to new rows with "
                             "BoxWarmStart.take or .relabel)")


def _solve(M, q, lo, hi, opts, warm_start, tried=False, friction=(), reset=None):
    """A validated box LCP: a warm start if given (first in one kernel call, unless
    ``tried`` already), then, when a run from it fails and ``reset`` (variables) is given,
    a run from it with those variables cold (:func:`_reset`), then the cold runs."""
    n = q.size
    extra, rec = 0, 0
    _check_warm(warm_start, n, friction)
    res = warm = None  # the result a rung settled it with; the warm run's

    # The ladder (_ladder.py): the warm start in one kernel call (_one_call), its basis
    # (_warm), its friction rows cold (_reset), then cold and _finish's rungs.
    def one_call():
        nonlocal res
        res = _one_call(*_kernel_arrays(M, q, lo, hi), None, warm_start, opts, validated=True)

    def from_warm():
        nonlocal res, warm, extra, rec
        warm = _warm(M, q, lo, hi, opts, warm_start)
        if warm.status == Status.SOLVED or warm.status in STOPPED:
            res = warm  # (a stop ends the ladder: an interrupt reaches only the run it hit)
        else:
            extra, rec = warm.pivots, 1

    def friction_cold():  # as _one_call
        nonlocal res, extra, rec
        run = _Run(n).go(M, q, lo, hi, _reset(warm_start._kernel_flags(), n, reset), _WARM,
                         opts, max(0, opts.pivot_limit(n) - extra), opts.tie_tol)
        if run.code == 0 and run.ok:
            res = _solved(run, n, lo, hi, rec, extra + run.pivots)
        elif run.code in STOPPED:
            res = _finish(M, q, lo, hi, opts, run, extra, rec)
        else:
            extra, rec = extra + max(run.pivots, 0), 2

    def cold():
        nonlocal res
        run = _Run(n).go(M, q, lo, hi, np.zeros(2 * n, dtype=np.bool_), 0, opts, max(0, opts.pivot_limit(n) - extra), opts.tie_tol)
        if run.code == boxed.NOT_FINITE:
            raise ValueError("M and q must be finite")  # as_blcp has said where, for lo and hi
        res = _finish(M, q, lo, hi, opts, run, extra, rec)

    climb(lambda: res is not None,
          Rung("the warm start in one call", lambda: warm_start is not None and not tried,
               one_call),
          Rung("the warm start's basis", lambda: warm_start is not None, from_warm),
          Rung("its friction rows cold",
               lambda: warm is not None and reset is not None and warm.status not in STOPPED,
               friction_cold),
          Rung("cold", always, cold))
    return res


def _friction_vars(F, n):
    """The extended problem's variables of the friction rows F (β+, β-, λ of each), for
    :func:`_reset`."""
    return np.concatenate([F, n + np.arange(2 * F.size)])


def _reset(flags, N, idx):
    """Warm flags (2N: basic, then at hi) with the variables ``idx`` cold (non-basic at lo).

    A warm run from a basis that no longer solves the problem ends, on the scene of issue
    32, on a secondary ray for about a third of the islands (the extended problem of a
    friction index is not positive semidefinite, and its warm bases are not the start that
    Anitescu and Potra's argument covers); the same basis with its friction rows cold (the
    normal impulses' states kept) then solves most of them in about half the pivots of a
    cold solve."""
    out = flags.copy()
    out[idx] = False
    out[N + idx] = False
    return out


def _kernel_arrays(M, q, lo, hi):
    k = _validate.kernel_array
    return k(M), k(q), k(lo), k(hi)


def _warm(M, q, lo, hi, opts, ws):
    """The warm start's basis: its point if it still solves the problem (0 pivots), else a
    kernel run from it (exchange pivots, then Lemke)."""
    n = q.size
    zb = np.zeros(n, dtype=np.bool_)
    zb[list(ws.z_basic)] = True
    zh = np.zeros(n, dtype=np.bool_)
    zh[list(ws.at_upper)] = True
    run = _Run(n)
    if boxed.basis_point(M, q, lo, hi, zb, zh, True, run.z):
        _certify.check_scales(M, q, lo, hi, run.R, run.C)
        ok, residual = _certify.box_check(M, q, lo, hi, run.z, opts.tol, run.w, run.R)
        if ok:
            run.code, run.pivots, run.z0, run.ok, run.residual = 0, 0, 0.0, True, residual
            run.d[:] = 0.0
            run.set_basis(zb, zh)
            return _solved(run, n, lo, hi, 0)
    run = _Run(n).go(M, q, lo, hi, np.concatenate([zb, zh & ~zb]), _WARM, opts, opts.pivot_limit(n), opts.tie_tol)
    return _finish(M, q, lo, hi, opts, run, ladder=False)


def _finish(M, q, lo, hi, opts, run, extra=0, rec=0, ladder=True):
    """The result of a run that did not end solved and checked: the other covering vectors
    and exact ties (``ladder``), the point of the final basis recomputed, a ray checked."""
    n = q.size
    if run.code == boxed.BAD_BOUNDS or run.code == boxed.NOT_FINITE:
        as_blcp(M, q, lo, hi)  # raises, naming the entry
        raise ValueError("M and q must be finite")
    pivots = extra + max(run.pivots, 0)
    if ladder and not (run.code == 0 and run.ok) and run.code not in STOPPED:
        # The ladder (_ladder.py): a ray checked ends it; else cold runs with the other
        # covering vectors, then exact ties, while pivots are left; a run solved and checked
        # settles it, a ray is kept over a run that ended otherwise.
        cap = Cap(opts.pivot_limit(n), pivots)
        ray = False

        def ray_checked():
            nonlocal ray
            ray = is_box_ray(M, q, lo, hi, run.d, run.z, run.z0, run.ray, opts.tol)

        def cold(mode, tie):
            def go():
                nonlocal run, rec
                nxt = _Run(n).go(M, q, lo, hi, np.zeros(2 * n, dtype=np.bool_), mode, opts,
                                 cap.left(), tie)
                cap.charge(nxt.pivots)
                rec += 1
                if (nxt.code == 0 and nxt.ok) or nxt.code in STOPPED or (
                        nxt.code == Status.RAY_TERMINATION and run.code != Status.RAY_TERMINATION):
                    run = nxt
            return go

        def left():
            return cap.left() > 0

        climb(lambda: ray or (run.code == 0 and run.ok) or run.code in STOPPED,
              Rung("the ray checked", lambda: run.code == Status.RAY_TERMINATION, ray_checked),
              Rung("other covering vectors", left, cold(1, opts.tie_tol)),
              Rung("exact ties", left, cold(2, 0.0)))
        pivots = cap.pivots
    if run.code == 0 and run.ok:
        return _solved(run, n, lo, hi, rec, pivots)
    status = Status(run.code) if run.code >= 0 else Status.NUMERICAL_FAILURE
    z, w, residual = run.z, run.w, run.residual
    if (status == Status.SOLVED or not run.ok) and status not in STOPPED:
        point = _checked_point(M, q, lo, hi, *run.basis_flags(n), opts.tol, run.R)
        if point is not None:
            run.z, run.w, run.residual = point
            run.ok, run.code = True, 0
            return _solved(run, n, lo, hi, rec, pivots)
        if status == Status.SOLVED:
            status = Status.NUMERICAL_FAILURE
    ray = None
    if status == Status.RAY_TERMINATION:
        if is_box_ray(M, q, lo, hi, run.d, run.z, run.z0, run.ray, opts.tol):
            ray = run.ray
        else:
            status = Status.NUMERICAL_FAILURE
    return BLCPResult(z, w, status, int(pivots), float(residual), ray, float(run.z0), run.d,
                      run.warm(n), lo, hi, run.R, run.C, rec)


def _solved(run, n, lo, hi, rec, pivots=None):
    run.z.setflags(write=False)
    run.w.setflags(write=False)
    run.d.setflags(write=False)
    return BLCPResult._make_from(run.z, run.w, Status.SOLVED, run.pivots if pivots is None else pivots,
                            run.residual, None, 0.0, run.d, run.warm(n), lo, hi, run.R, run.C, rec)


def _basis_point(M, q, lo, hi, zb, zh):
    """The point of the basis (z basic where ``zb``, the others at lo, or hi where ``zh``)
    from the caller's data by one dense solve (``boxed::basis_point``: no LAPACK),
    clamped into the box; None if singular."""
    z = np.empty(q.size)
    return z if boxed.basis_point(M, q, lo, hi, zb, zh, False, z) else None


def _basis_flags(final, k, m, n):
    """The flags ``(zb, zh)`` of a final basis as the kernels give it: ``final[:k]`` basic,
    ``final[k:m]`` non-basic at hi."""
    zb = np.zeros(n, dtype=np.bool_)
    zh = np.zeros(n, dtype=np.bool_)
    zb[final[:k]] = True
    zh[final[k:m]] = True
    return zb, zh


def _checked_point(M, q, lo, hi, zb, zh, tol, R):
    """The point of the basis ``(zb, zh)`` recomputed (:func:`_basis_point`) and judged by
    ``box_check`` with the row scales R: ``(z, w, residual)`` when it passes, else None."""
    z = _basis_point(M, q, lo, hi, zb, zh)
    if z is None:
        return None
    w = np.empty(q.size)
    ok, residual = _certify.box_check(M, q, lo, hi, z, tol, w, R)
    return (z, w, residual) if ok else None


# --------------------------------------------------------------------------- friction


def friction_lcp(M, q, lo, hi, findex):
    """The box LCP that solves the friction index exactly (module docstring): returns
    ``(Mx, qx, lox, hix, F, normal)``, where F lists the friction rows and ``normal`` their
    normal rows.  Variables: the caller's z with beta+ in place of each friction z_i, then
    beta- and lambda per friction row.  (Built by ``boxed::extend``, as
    ``boxed::front`` builds it.)"""
    M, q, lo, hi = _kernel_arrays(M, q, lo, hi)
    findex = _validate.kernel_array(np.asarray(findex, dtype=np.int64))
    n = q.size
    k = int(np.count_nonzero(findex >= 0))
    F = np.empty(2 * k, dtype=np.int64)
    Mx, qx, lox, hix = boxed.extend(M, q, lo, hi, findex, k, np.empty(_layout(n, k, True)["work_length"]), F)
    return Mx, qx, lox, hix, F[:k], F[k:]


def _caller_point(M, q, lo, hi, F, normal, zb, zh, tol):
    """The point of an extended problem's basis (``zb`` basic, ``zh`` at hi; N = n + 2 nf
    variables) computed on the caller's n rows, judged there by the core's check with the
    coupled bounds (``boxed.friction_recover`` on the caller's z: FrictionBox's check):
    ``(z, w, residual, lo_in, hi_in)`` when it passes, else None.

    Each caller's row gives one equation, read from the states of its variables: an
    ordinary row w_i = 0 when z_i is basic, else z_i at its bound; a friction row i (normal
    row f, ``mu = hi_i``) z_i = mu z_f when β+ and λ are basic (sliding, β- at 0),
    z_i = -mu z_f when β- and λ are, w_i = 0 when λ is at 0 and β+ or β- basic, or when
    both are (sticking), z_i = 0 when β+ and β- are both at 0.  The system is solved by one LU with refinement
    in double-double (``refined_solve``).  Why: near a contact whose normal impulse is 0
    the extended block is singular (λ basic with β+ and β- at 0 makes λ's column zero in
    the block), and the tableau's point of such a basis carries errors of cond eps in rows
    whose own terms are ~1e-11, so that it fails the row-wise check that the caller's
    solution meets; the caller's system has no such column and its refined solution meets
    the check in every row (issue 32's scene, islands of 75-120 rows).  A warm start's own
    point is this system first too, unrefined and with each sliding row substituted into
    its normal's column (``boxed.friction_point``, in ``boxed::front``), where the
    patterns that make the extended block singular are left to the extended point.

    Why this system stays here rather than in the core (``FrictionBasis``, which builds the
    same rows): FrictionBasis substitutes each sliding row into its normal's column and
    solves once, unrefined, while this path solves the n x n system with the sliding rows
    kept as rows and refines it in double-double; the accepted points (and so the goldens'
    and frozen digests' bits of the general path) are this solve's, and it runs only after
    the extended point and its dense re-solve have failed the check (not a hot path).  The
    map back and the check are the core's."""
    n = q.size
    k = F.size
    K = np.zeros((n, n))
    rhs = np.zeros(n)
    c_of = np.full(n, -1, dtype=np.int64)
    c_of[F] = np.arange(k)
    for i in range(n):
        c = c_of[i]
        if c < 0:
            if zb[i] or (lo[i] == -np.inf and hi[i] == np.inf):
                K[i] = M[i]
                rhs[i] = -q[i]
            else:
                v = hi[i] if zh[i] and hi[i] < np.inf else (lo[i] if lo[i] > -np.inf else hi[i])
                K[i, i] = 1.0
                rhs[i] = v if np.isfinite(v) else 0.0
            continue
        bp, bm, lam = zb[i], zb[n + c], zb[n + k + c]
        K[i, i] = 1.0
        if lam and bp != bm:
            K[i, normal[c]] = -hi[i] if bp else hi[i]
        elif bp or bm:
            K[i] = M[i]
            rhs[i] = -q[i]
    z = np.empty(n)
    if not refined_solve(K, rhs, 2, z, np.empty(n)) or not np.all(np.isfinite(z)):
        return None
    ok, residual, z, w, lo_in, hi_in, _, _ = boxed.friction_recover(
        M, q, lo, hi, np.concatenate([F, normal]), z, tol)
    return (z, w, residual, lo_in, hi_in) if ok else None


def _warm_friction(M, q, lo, hi, Mx, qx, lox, hix, F, normal, ws, opts):
    """A warm start's own point with a friction index (``boxed::front``'s PREPARE
    phase): the point of its basis solved on the caller's rows (``boxed.friction_point``: a
    sliding row's z_i = +-mu z_f substituted, no extended matrix), else on the extended
    data, judged by the check that decides 'solved', on the caller's rows with the coupled
    bounds, without the extended problem's own check; the result with 0 pivots when one of
    them passes with the point's normal impulses in their boxes (the friction rows' bounds
    are then those of the z returned), else None (the extended problem's check then decides
    first, as :func:`_solve` makes it)."""
    n, N = q.size, qx.size
    flags = ws._kernel_flags()
    got = None
    z = np.empty(n)
    FN = np.concatenate([F, normal])
    if boxed.friction_point(M, q, lo, hi, FN, flags[:N], flags[N:], z):
        got = _judged(M, q, lo, hi, FN, normal, z, opts.tol)
    if got is None:
        zx = np.empty(N)
        if not boxed.basis_point(Mx, qx, lox, hix, flags[:N], flags[N:], True, zx):
            return None
        boxed.friction_z(FN, zx, z)  # (FrictionBox's recover)
        got = _judged(M, q, lo, hi, FN, normal, z, opts.tol)
        if got is None:
            return None
    z, w, residual, lo_in, hi_in, R, C = got
    d = np.zeros(N)
    for a in (z, w, lo_in, hi_in, R, C, d):
        a.setflags(write=False)
    return BLCPResult(z, w, Status.SOLVED, 0, float(residual), None, 0.0, d, ws, lo_in, hi_in,
                      R, C, 0)


def _judged(M, q, lo, hi, FN, normal, z, tol):
    """The caller's point z of a warm friction basis judged as ``_warm_friction`` judges it
    (its normals in their boxes, then the core's check with the coupled bounds,
    ``boxed.friction_recover`` on the caller's z; FN: the friction rows, then ``normal``):
    ``(z, w, residual, lo_in, hi_in, R, C)`` when it passes, else None."""
    zn = z[normal]
    if not np.all((zn >= lo[normal]) & (zn <= hi[normal])):
        return None
    ok, residual, z, w, lo_in, hi_in, R, C = boxed.friction_recover(M, q, lo, hi, FN, z, tol)
    return (z, w, residual, lo_in, hi_in, R, C) if ok else None


def _solve_friction(M, q, lo, hi, findex, opts, warm_start, tried=False):
    """A validated box LCP with a friction index: first in one kernel call (unless
    ``tried`` already), else the extended problem by the general path and the answer
    judged on the caller's data here."""
    n = q.size
    F0 = np.flatnonzero(findex >= 0)
    _check_warm(warm_start, n + 2 * F0.size, tuple(F0.tolist()))
    if not tried:
        res = _one_call(*_kernel_arrays(M, q, lo, hi), _validate.kernel_array(findex),
                        warm_start, opts, validated=True)
        if res is not None:
            return res
    Mx, qx, lox, hix, F, normal = friction_lcp(M, q, lo, hi, findex)
    if warm_start is not None and F.size:
        got = _warm_friction(M, q, lo, hi, Mx, qx, lox, hix, F, normal, warm_start, opts)
        if got is not None:
            return got
    inner = _solve(Mx, qx, lox, hix, opts, warm_start, tried=True, friction=None,
                   reset=_friction_vars(F, n) if F.size and warm_start is not None else None)
    k = F.size
    FN = np.concatenate([F, normal])
    zx = inner.z
    z = np.empty(n)
    boxed.friction_z(FN, zx, z)  # (FrictionBox's recover: the point returned if none passes)
    # The check on the caller's data decides, whatever the extended problem's own check said
    # (its rows λ ± w_i are sums of larger terms, and can miss that check by rounding where
    # the caller's rows pass): the core's pair, FrictionBox's check on z.
    status = inner.status
    ok, residual, zc, w, lo_in, hi_in, R, C = boxed.friction_recover(M, q, lo, hi, FN, z, opts.tol)
    flags = None if ok or inner.warm_start is None else inner.warm_start._kernel_flags()
    if flags is not None:
        # The point of the final basis, from the extended data by one dense solve (more
        # accurate than the tableau after many pivots), judged again.
        zx2 = _basis_point(Mx, qx, lox, hix, flags[:qx.size], flags[qx.size:])
        if zx2 is not None:
            ok2, res2, z2, w2, lo2, hi2, _, _ = boxed.friction_recover(M, q, lo, hi, FN, zx2,
                                                                       opts.tol)
            if ok2:
                ok, residual, zc, w, lo_in, hi_in = ok2, res2, z2, w2, lo2, hi2
        if not ok and flags is not None:
            # The same basis read as equations on the caller's n rows, solved with
            # refinement (the extended block can be singular where the caller's is not).
            got = _caller_point(M, q, lo, hi, F, normal, flags[:qx.size], flags[qx.size:],
                                opts.tol)
            if got is not None:
                ok = True
                zc, w, residual, lo_in, hi_in = got
    if ok:
        status, z = Status.SOLVED, zc
    else:
        if status == Status.SOLVED:
            status = Status.NUMERICAL_FAILURE
        _certify.box_check(M, q, lo_in, hi_in, z, opts.tol, w, R, qx.size)  # w of the point returned
    for a in (z, w, lo_in, hi_in, R, C):
        a.setflags(write=False)
    ws = inner.warm_start
    if ws is not None and k:  # the extended problem's basis, for these friction rows
        ws = BoxWarmStart._trusted(ws.n, ws.z_basic, ws.at_upper, tuple(F.tolist()))
    solved = status == Status.SOLVED
    return BLCPResult(z, w, status, inner.pivots, float(residual),
                      None if solved else inner.ray, 0.0 if solved else inner.z0, inner.covering,
                      ws, lo_in, hi_in, R, C, inner.recoveries)


#: The commonest calls whole (src/python_front_box.cpp): plain float64 M, q, lo, hi, the
#: default options, cold or with a friction index and/or a BoxWarmStart; a result, what is
#: left to do (a tuple for _finish, False for _general), or None (not plain: all here).
_FRONT = _core.blcp_front
native_fronts_init()  # (NumPy's layout checked: _FRONT relies on it)
_core.blcp_front_init(BLCPResult, BoxWarmStart, Status.SOLVED, _spans, _DEFAULT.pivot_tol,
                      _DEFAULT.tie_tol, _DEFAULT.tol)

#: The Python function; ``solve_blcp`` is the core's entry that wraps it (src/python_front.cpp,
#: ``blcp_entry``): the calls ``solve_blcp(M, q, lo, hi)`` with no keyword but ``findex=``
#: and/or ``warm_start=`` go to ``_FRONT`` with no Python frame (then ``_after_front`` when
#: it does not settle), every other call (and any the front declines) to it.
_solve_blcp = solve_blcp
solve_blcp = update_wrapper(
    _core.blcp_entry(_solve_blcp, _after_front, globals(), _FRONT), _solve_blcp)
