"""Immutable results.  ``success`` and ``message`` are derived from ``status``, never stored.

Results are values: two results are equal (``==``) when every field is bit for bit the same
(arrays by shape, dtype and bytes; floats by their bits, so a NaN residual equals itself),
and ``hash`` follows the same fields, so results can be dict keys and set members.
"""
from __future__ import annotations

import importlib
import operator
import struct
from collections.abc import Sequence
from dataclasses import fields
from itertools import compress, repeat
from operator import itemgetter

import numpy as np

from ._frozen import frozen
from . import _core
from ._options import _DEFAULT
from ._status import Status

_SOLVED_CODE = int(Status.SOLVED)
from ._validate import kernel_array
from . import _layout


@frozen
class WarmStart:
    """A complementary basis, as a plain value: pass it back as ``solve_lcp(..., warm_start=)``.

    ``z_basic`` lists (sorted, 0-based) the indices i whose z_i is basic; for every other i,
    w_i is basic.  It is hashable and picklable and holds nothing else.
    """

    n: int
    z_basic: tuple[int, ...]

    def __post_init__(self):
        n = self.n
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"WarmStart.n must be a non-negative integer, got {n!r}")
        try:
            idx = tuple(sorted(int(i) for i in self.z_basic))
        except (TypeError, ValueError):
            raise TypeError("WarmStart.z_basic must be a sequence of integers") from None
        if len(set(idx)) != len(idx) or (idx and (idx[0] < 0 or idx[-1] >= n)):
            raise ValueError(f"WarmStart.z_basic must hold distinct indices in [0, {n}), got {idx}")
        object.__setattr__(self, "n", int(n))
        object.__setattr__(self, "z_basic", idx)

    def take(self, indices) -> "WarmStart":
        """The basis carried to a problem whose row i is row ``indices[i]`` of this one, for
        when rows appear, vanish or move (contacts come and go between steps): z_i is basic
        where old row ``indices[i]`` had z basic; a new row (``indices[i] == -1``) starts
        with w_i basic.  ``len(indices)`` is the new size.

        >>> WarmStart(3, (0, 2)).take([2, -1, 1, 0])  # old row 2 -> 0, a new row 1, ...
        WarmStart(n=4, z_basic=(0, 3))
        """
        idx = np.asarray(indices)
        if idx.ndim != 1 or (idx.size and idx.dtype.kind not in "iu"):
            raise TypeError("indices must be a 1-D sequence of integers")
        idx = idx.astype(np.int64)
        if idx.size and (idx.min() < -1 or idx.max() >= self.n):
            raise ValueError(f"indices must lie in [-1, {self.n}), got {idx.min()} .. {idx.max()}")
        kept = idx[idx >= 0]
        if np.unique(kept).size != kept.size:
            raise ValueError("indices name an old row twice")
        basic = np.zeros(self.n + 1, dtype=bool)  # the last entry: new rows, never basic
        basic[list(self.z_basic)] = True
        return WarmStart._trusted(int(idx.size), tuple(np.flatnonzero(basic[idx]).tolist()))

    def relabel(self, old_labels, new_labels) -> "WarmStart":
        """:meth:`take` by labels: row i of the new problem carries label ``new_labels[i]``
        (a contact's id, say), row j of this one ``old_labels[j]``; a label not seen before is
        a new row.  Labels are any hashable values, distinct within each list (each is hashed
        once per call: ints and short strings hash fastest, a tuple is hashed item by item).
        Two 1-D integer numpy arrays are matched in one kernel call instead, with no Python
        object per label: the fastest form (a contact's id as an int64, say)."""
        if type(old_labels) is np.ndarray and type(new_labels) is np.ndarray:
            carried = self._relabel_ids(old_labels, new_labels)
            if carried is not None:
                return carried
        old = old_labels if type(old_labels) in (list, tuple) else list(old_labels)
        n = self.n
        if len(old) != n:
            raise ValueError(f"old_labels has {len(old)} labels for a basis of size {n}")
        # Pure Python, every pass over the labels a C loop (dict, map, set, itemgetter,
        # compress: no Python bytecode per label): each label is hashed once; index n (one
        # past the old rows) marks a new row, never basic.  At a pile's n = 150-200 the
        # numpy steps of take() cost more than the hashing.
        where = dict(zip(old, range(n)))
        if len(where) != n:
            raise ValueError("old_labels holds a label twice")
        idx = list(map(where.get, new_labels, repeat(n)))
        m = len(idx)
        carried = m - idx.count(n)  # rows of the new problem that an old row carries to
        if carried and len(set(idx)) - (carried != m) != carried:
            raise ValueError("new_labels holds a label twice")
        basic = bytearray(n + 1)
        for j in self.z_basic:
            basic[j] = 1
        flags = itemgetter(*idx)(basic) if m > 1 else tuple(basic[j] for j in idx)
        return WarmStart._trusted(m, tuple(compress(range(m), flags)))

    def _relabel_ids(self, old, new):
        """:meth:`relabel` for labels given as 1-D integer arrays: one call of the C++ core
        (``relabel_ids``, src/lemke/carry.cpp), no Python object per row; None for
        other arrays (the general path takes them)."""
        if old.ndim != 1 or new.ndim != 1 or old.dtype.kind not in "iu" or new.dtype.kind not in "iu":
            return None
        if old.size != self.n:
            raise ValueError(f"old_labels has {old.size} labels for a basis of size {self.n}")
        # int64 (a uint64 label above 2**63 wraps: still one int64 per label, distinct),
        # of the kernel's one compiled type
        old = kernel_array(old.astype(np.int64, copy=False))
        new = kernel_array(new.astype(np.int64, copy=False))
        beta = self.__dict__.get("_beta")
        if beta is None:  # kept, as solve_lcp keeps it
            beta = self.__dict__["_beta"] = np.array(self.z_basic, dtype=np.int64)
        out = np.empty(new.size, dtype=np.int64)
        count = _core.relabel_ids(old, new, beta, out)
        if count < 0:
            raise ValueError(f"{'old' if count == -1 else 'new'}_labels holds a label twice")
        ws = WarmStart._trusted(new.size, tuple(out[:count].tolist()))
        ws.__dict__["_beta"] = out[:count]  # the index array that solve_lcp's warm path takes
        return ws

    def __getstate__(self):
        # the fields only: not the index array that solve_lcp keeps with it (``_beta``, its
        # own C-contiguous, aligned int64 array, which the kernels' fast path trusts)
        return {"n": self.n, "z_basic": self.z_basic}

    @classmethod
    def _trusted(cls, n: int, z_basic: tuple) -> "WarmStart":
        """Build from values the solver made itself (sorted, in range): no checks."""
        ws = object.__new__(cls)
        f = ws.__dict__
        f["n"] = n
        f["z_basic"] = z_basic
        return ws


def _key(v):
    """What ``==`` and ``hash`` compare for one field: arrays and floats by their bits."""
    if isinstance(v, np.ndarray):
        return ("array", v.shape, v.dtype.str, v.tobytes())
    if isinstance(v, (float, np.floating)):
        return ("float", struct.pack("<d", float(v)))
    if isinstance(v, Value):
        return v._keys()
    return v


class cached:
    """``functools.cached_property`` without its lock (before Python 3.12 a first read takes
    a lock of the class: ~0.7 us where this costs ~0.2 us, the most of a small batch
    result's fields): the value made when first read and kept in the instance's
    ``__dict__``, which comes first from then on (a non-data descriptor).  Two threads
    reading a new result at once both make equal values."""

    def __init__(self, f):
        self.f, self.name, self.__doc__ = f, f.__name__, f.__doc__

    def __get__(self, obj, cls=None):
        if obj is None:
            return self
        v = obj.__dict__[self.name] = self.f(obj)
        return v


class Value:
    """Equality and hashing by fields, bit for bit (see the module docstring)."""

    __slots__ = ()

    def _keys(self) -> tuple:
        return (type(self).__name__,) + tuple(_key(getattr(self, f.name)) for f in fields(self))

    def __eq__(self, other):
        if type(other) is not type(self):
            return NotImplemented
        return self._keys() == other._keys()

    def __hash__(self) -> int:
        return hash(self._keys())

    @classmethod
    def _make_from(cls, *values):
        """Build from the solver's own values in field order, skipping the frozen dataclass'
        ``__init__`` (it sets every field through ``object.__setattr__``): the hot path of
        small problems."""
        names = _FIELD_NAMES.get(cls)
        if names is None:
            names = _FIELD_NAMES[cls] = tuple(f.name for f in fields(cls))
        res = object.__new__(cls)
        res.__dict__.update(zip(names, values))
        return res


_FIELD_NAMES: dict = {}


class Outcome(Value):
    """What every result derives from its ``status``: ``success`` and ``message``."""

    __slots__ = ()

    @property
    def success(self) -> bool:
        s = self.status
        return s is Status.SOLVED or s == Status.SOLVED  # (`is`: IntEnum's == costs ~0.3 us)

    @property
    def message(self) -> str:
        return self.status.message


@frozen(eq=False)
class LCPResult(Outcome):
    """The outcome of :func:`lemke.solve_lcp`.

    Attributes
    ----------
    z, w : ndarray
        The final point and ``w = M z + q`` recomputed from the caller's data.  On a solved
        problem they are the solution; otherwise z is where the method stopped.
    status : Status
    pivots : int
        Pivots made, counting the first pivot (the artificial variable entering) and the
        last (the artificial variable leaving).
    residual : float
        ``max_i |min(z_i, w_i)|`` from the caller's data (0 for an exact solution).
    ray : ndarray or None
        On ``RAY_TERMINATION`` the direction of the secondary ray, length n + 1: the
        direction of z followed by that of the artificial variable z0.  Along it,
        ``(z + t ray[:n], z0 + t ray[n])`` stays almost complementary for all t >= 0.
    z0 : float
        The artificial variable's final value (0 when solved).
    covering : ndarray
        The covering vector d actually used, in the caller's coordinates (the artificial
        variable's column: ``w = M z + q + d z0``); needed to check the ray.
    warm_start : WarmStart or None
        The final basis, to pass back for a nearby problem.
    row_scale, col_scale : ndarray
        The equilibration the kernels pivoted on: powers of two R and C such that every
        row and column of ``diag(R) M diag(C)`` has its largest entry near 1 (see
        ``equilibrate`` in ``src/lemke/linalg.cpp``).  In exact arithmetic they change nothing.
    recoveries : int
        How many times the solve was restarted after the method revisited a basis (see
        ``lemke._layout``); 0 on almost every problem.
    """

    z: np.ndarray
    w: np.ndarray
    status: Status
    pivots: int
    residual: float
    ray: np.ndarray | None
    z0: float
    covering: np.ndarray
    warm_start: WarmStart | None
    row_scale: np.ndarray
    col_scale: np.ndarray
    recoveries: int = 0

    @classmethod
    def _make(cls, z, w, status, pivots, residual, ray, z0, covering, warm_start, row_scale,
              col_scale, recoveries) -> "LCPResult":
        """Build from the solver's own values, skipping the dataclass ``__init__`` (a frozen
        one sets every field through ``object.__setattr__``): this is on the hot path of
        small problems."""
        res = object.__new__(cls)
        res.__dict__.update(z=z, w=w, status=status, pivots=pivots, residual=residual, ray=ray,
                            z0=z0, covering=covering, warm_start=warm_start,
                            row_scale=row_scale, col_scale=col_scale, recoveries=recoveries)
        return res

    @classmethod
    def _lazy(cls, status, pivots, residual, recoveries, src, warm_start=None) -> "LCPResult":
        """A result whose arrays are views of a kernel's output buffer, each made when first
        read (see :meth:`__getattr__`); ``src = (buf, o, basic, bo, n, k)``: the buffer of
        problem size n starts at ``buf[o]`` (``_layout.fields``), its basic z's are
        ``basic[bo:bo + k]``.  ``solve_lcp`` gives each result a buffer of its own,
        ``solve_lcp_many`` one buffer for all.  ``status`` is SOLVED (``ray`` None, ``z0``
        0) or a checked RAY_TERMINATION (both read from the buffer).  ``warm_start``, when
        given, is the result's (the one the caller passed, when it still solved); else it is
        made from the basic z's.  The fronts inline this (it is on the hot path of small
        problems); it states what they put in ``__dict__``.  The other fields are
        :class:`_FromBuffer` descriptors of the class, which put the field in the result's
        ``__dict__`` when first read."""
        res = object.__new__(cls)
        d = res.__dict__
        d["status"] = status
        d["pivots"] = pivots
        d["residual"] = residual
        if recoveries:  # else the class default, 0
            d["recoveries"] = recoveries
        d["_src"] = src
        if warm_start is not None:
            d["warm_start"] = warm_start
        return res

    def __getstate__(self):
        return lazy_state(self, _LAZY_FIELDS)

    def __repr__(self) -> str:
        return (
            f"LCPResult(status={self.status.name}, pivots={self.pivots}, "
            f"residual={self.residual:.3g}, n={self.z.size})"
        )


def lazy_state(res, names):
    """The state of a result built lazily (``_src`` in its ``__dict__``) for pickling and
    copying: every field in ``names`` made, and the kernel's buffers left behind."""
    d = res.__dict__
    if "_src" in d:
        for name in names:
            getattr(res, name)
        d = {key: v for key, v in d.items() if key != "_src"}
    return d


class LazyField:
    """A field of a result built lazily: ``make(d)`` (``d``: the result's ``__dict__``, which
    holds what the maker left there) computes it when first read, and it is then kept in
    ``d``, which comes first from then on (a non-data descriptor; no ``__getattr__``
    fallback, which costs a microsecond).  ``solve_blcp``'s and ``solve_bimatrix``'s lazy
    results use it; ``_FromBuffer`` below is the LCP's own, inlined for its hot path."""

    __slots__ = ("name",)

    def __init__(self, name):
        self.name = name

    def __get__(self, res, cls=None):
        if res is None:
            return self
        d = res.__dict__
        v = d[self.name] = self.make(d)
        return v


class _FromBuffer:
    """A field of a :meth:`LCPResult._lazy` result, made from its ``_src`` when first read
    and then kept in the result's ``__dict__``, which comes first from then on (a non-data
    descriptor: a lookup that finds the field costs nothing more, and one that does not
    raises no AttributeError on the way, unlike ``__getattr__``, whose fallback costs a
    microsecond).  Results built with every field (``_make``, ``__init__``) never reach it.
    Safe when two threads read a new result at once: both make equal values."""

    __slots__ = ("name", "a", "c", "l", "l0")

    def __init__(self, name):
        self.name = name
        if name in _SPANS:
            self.a, self.c, self.l, self.l0 = _SPANS[name]

    def __get__(self, res, cls=None):
        if res is None:
            return self
        d = res.__dict__
        name = self.name
        src = d.get("_src")
        if src is None:
            raise AttributeError(f"'LCPResult' object has no attribute {name!r}")
        buf, o, basic, bo, n, k = src
        if name == "warm_start":
            # basic None: the int64 are in buf from bo on (solve_lcp's one buffer)
            beta = (buf.view(np.int64) if basic is None else basic)[bo : bo + k]
            if not beta.flags.writeable:
                beta = beta.copy()  # (a read-only array would compile the kernels again)
            v = _new(WarmStart)  # WarmStart._trusted, inlined
            f = v.__dict__
            f["n"] = n
            f["z_basic"] = tuple(beta.tolist())
            f["_beta"] = beta  # the index array that solve_lcp's warm path takes
        elif name == "z0":
            v = 0.0 if d["status"] is Status.SOLVED else float(buf[o + n])
        elif name == "ray" and d["status"] is Status.SOLVED:
            v = None
        else:
            if buf.flags.writeable:  # the result's arrays are read-only, as the others'
                buf.setflags(write=False)
            start = o + self.a * n + self.c
            v = buf[start : start + self.l * n + self.l0]
        d[name] = v
        return v


def _spans():
    """``{field: (a, c, l, l0)}``: in the output buffer of size n (``_layout.fields``,
    whose offsets and lengths are linear in n) the field starts at ``a n + c`` and holds
    ``l n + l0`` entries."""
    f0, f1 = _layout.fields(0), _layout.fields(1)
    out = {}
    for name in ("z", "ray", "w", "covering", "row_scale", "col_scale"):
        s0, s1 = f0[name], f1[name]
        l0 = s0.stop - s0.start
        out[name] = (s1.start - s0.start, s0.start, (s1.stop - s1.start) - l0, l0)
    return out


_SPANS = _spans()
_new = object.__new__
#: The fields a _lazy result makes when first read (set on the class after the dataclass
#: decorator, so that they are no defaults of its __init__).
_LAZY_FIELDS = ("z", "z0", "ray", "w", "covering", "row_scale", "col_scale", "warm_start")
for _name in _LAZY_FIELDS:
    setattr(LCPResult, _name, _FromBuffer(_name))
del _name


@frozen(eq=False)
class WarmStartBatch(Value):
    """The complementary bases of B problems in one value: problem b has size ``n[b]``, and
    ``z_basic[offsets[b]:offsets[b + 1]]`` lists (sorted, 0-based) the i whose z_i is basic,
    as one :class:`WarmStart` would.  The ``warm_start`` of :func:`lemke.solve_lcp_many`'s
    result; pass it back whole, ``solve_lcp_many(..., warm_start=batch)`` (or to
    :func:`lemke.solve_lcp_batch`), and the kernels take its arrays as they are: no Python
    work per problem.  An empty basis is a cold start.  ``batch[b]`` is problem b's
    :class:`WarmStart` (made when asked), ``len`` and iteration work as on a list of them.
    Its arrays are read-only int64; ``==`` and ``hash`` compare them bit for bit.

    >>> WarmStartBatch([2, 3], [1, 0, 2], [0, 1, 3])[1]
    WarmStart(n=3, z_basic=(0, 2))
    """

    n: np.ndarray
    z_basic: np.ndarray
    offsets: np.ndarray

    def __post_init__(self):
        n, z, off = (_int_vector(getattr(self, name), name) for name in ("n", "z_basic", "offsets"))
        if off.size != n.size + 1 or off[0] != 0 or off[-1] != z.size or (np.diff(off) < 0).any():
            raise ValueError("WarmStartBatch.offsets must rise from 0 to len(z_basic), one more "
                             f"entry than n: got {off.size} offsets for {n.size} problems, ending at "
                             f"{off[-1]} for {z.size} indices")
        if (n < 0).any():
            raise ValueError("WarmStartBatch.n must hold non-negative sizes")
        counts = np.diff(off)
        rising = np.ones(z.size, dtype=bool)  # z_basic rises within each problem's segment
        rising[1:] = np.diff(z) > 0
        rising[off[:-1][counts > 0]] = True
        if (z < 0).any() or (z >= np.repeat(n, counts)).any() or not rising.all():
            raise ValueError("WarmStartBatch.z_basic must hold, for each problem b, distinct sorted "
                             "indices in [0, n[b])")
        for name, v in (("n", n), ("z_basic", z), ("offsets", off)):
            object.__setattr__(self, name, v)

    @classmethod
    def _trusted(cls, n, z_basic, offsets) -> "WarmStartBatch":
        """Build from int64 arrays the solver made itself (no checks; made read-only)."""
        ws = object.__new__(cls)
        f = ws.__dict__
        for name, v in (("n", n), ("z_basic", z_basic), ("offsets", offsets)):
            v.setflags(write=False)
            f[name] = v
        return ws

    def __reduce__(self):
        return (WarmStartBatch._trusted, (self.n.copy(), self.z_basic.copy(), self.offsets.copy()))

    def __len__(self) -> int:
        return len(self.n)

    def __getitem__(self, b) -> WarmStart:
        b = _index(b, len(self.n))
        lo, hi = self.offsets[b : b + 2].tolist()
        beta = self.z_basic[lo:hi].copy()  # writable: a read-only one compiles the kernels again
        ws = WarmStart._trusted(int(self.n[b]), tuple(beta.tolist()))
        ws.__dict__["_beta"] = beta  # the index array that solve_lcp's warm path takes
        return ws

    def __iter__(self):
        return map(self.__getitem__, range(len(self.n)))

    def __repr__(self) -> str:
        return f"WarmStartBatch(B={len(self.n)}, basic z's={self.z_basic.size})"


def _int_vector(v, name):
    """``v`` as a new read-only 1-D int64 array, or a TypeError naming the field."""
    a = np.array(v, copy=True)
    if a.ndim != 1 or (a.size and a.dtype.kind not in "iu"):
        raise TypeError(f"WarmStartBatch.{name} must be a 1-D sequence of integers")
    a = a.astype(np.int64)
    a.setflags(write=False)
    return a


def _index(b, size) -> int:
    """``b`` (an integer, negative from the end) as an index into ``size`` items."""
    b = operator.index(b)
    if b < 0:
        b += size
    if not 0 <= b < size:
        raise IndexError(f"index {b} out of range for {size} problems")
    return b


class ManyItems(Sequence):
    """What a batch result of many problems shares (:class:`LCPManyResult`,
    ``_blcp_many.BLCPManyResult``): a sequence of per-problem results held in ``_items``
    (None until built by ``_build(lo, hi)``) that compares, hashes and adds as their list,
    and flat columns read from the kernels' arrays with the results built already
    (``_special``, ``{b: result}``) patched in."""

    def __len__(self) -> int:
        return len(self._items)

    def __getitem__(self, b):
        if isinstance(b, slice):
            return self._all()[b]
        b = _index(b, len(self._items))
        res = self._items[b]
        if res is None:
            self._build(b, b + 1)
            res = self._items[b]
        return res

    def __iter__(self):
        return iter(self._all())

    def _all(self) -> list:
        """Every item, built now where not yet (one loop, the cheapest per problem)."""
        items = self._items
        if None in items:
            self._build(0, len(items))
        return items

    def __eq__(self, other):
        if isinstance(other, type(self)):
            return self is other or self._all() == other._all()
        if isinstance(other, list):
            return self._all() == other
        return NotImplemented

    def __hash__(self) -> int:
        return hash(tuple(self._all()))

    def __add__(self, other):
        if isinstance(other, (list, type(self))):
            return list(self._all()) + list(other)
        return NotImplemented

    def __radd__(self, other):
        if isinstance(other, list):
            return other + self._all()
        return NotImplemented

    def __repr__(self) -> str:
        return f"{type(self).__name__}(B={len(self)}, solved={int(self.success.sum())}/{len(self)})"

    @cached
    def _special(self) -> dict:
        """``{b: result}`` of the results built already: set by ``__init__``; made here, when
        first read, for a result of ``_of`` (every item built: all of them)."""
        return dict(enumerate(self._items))

    def _column(self, values, field, convert):
        v = values.copy()
        for b, res in self._special.items():
            v[b] = convert(getattr(res, field))
        v.setflags(write=False)
        return v

    @cached
    def success(self) -> np.ndarray:
        v = self.status == _SOLVED_CODE  # (an int: numpy compares an IntEnum member in ~5 us)
        v.setflags(write=False)
        return v

    def __setstate__(self, state):  # (pickle loses the arrays' read-only flags)
        self.__dict__.update(state)
        for v in self.__dict__.values():
            if isinstance(v, np.ndarray):
                v.setflags(write=False)


class LCPManyResult(ManyItems):
    """The outcome of :func:`lemke.solve_lcp_many`: a sequence of :class:`LCPResult`, item b
    what :func:`lemke.solve_lcp` gives for problem b (bit for bit), with every problem's
    answer also in flat arrays, each made by a few numpy calls when first read.

    Neither holds a Python object per problem until asked: an item is built when first
    indexed (then kept), all of them when the sequence is iterated, compared or added to a
    list (``len``, indexing, iteration, slices, ``==`` with a list of results or another
    ``LCPManyResult``, ``+`` with a list, ``in`` and ``index`` give what the list of results
    would; it is a ``collections.abc.Sequence``).

    Attributes
    ----------
    offsets : ndarray of int64, shape (B + 1,)
        Problem b's entries of ``z`` and ``w`` are ``offsets[b]:offsets[b + 1]`` (its size
        n_b = ``offsets[b + 1] - offsets[b]``).
    z, w : ndarray of float64, shape (sum of n_b,)
        Every problem's ``z`` and ``w`` laid end to end.
    status : ndarray of int64, shape (B,)
        :class:`Status` codes (``lemke.Status(result.status[b])`` names one).
    success : ndarray of bool, shape (B,)
        Which problems were solved (status SOLVED).
    pivots, recoveries : ndarray of int64, shape (B,)
    residual : ndarray of float64, shape (B,)
    warm_start : WarmStartBatch
        Every problem's final basis (each item's ``warm_start``), to pass back whole as
        ``solve_lcp_many(..., warm_start=result.warm_start)``.

    The arrays are read-only.  ``ray``, ``z0``, ``covering`` and the scales are read on the
    items.
    """

    #: None in a result of ``_of`` (the items made one by one), which sets only ``_items``;
    #: ``__init__`` sets the kernels' offsets.
    _off = None

    def __init__(self, sizes, off, out_i, out_f, bufs, basics, ws, special):
        """``sizes`` (a list) and ``off`` (int64 (3, B + 1): the offsets of q and the basic
        z's, of M, of the output buffers), the kernels' ``out_i``, ``out_f``, ``bufs`` and
        ``basics`` (``_core.batch``), the warm starts given (a list, or None) and
        ``special``: ``{b: LCPResult}``, the results built already (those not solved and
        checked, nor q >= 0, nor a checked ray: see ``_batch.solve_lcp_many``)."""
        for a in (off, out_i, out_f, bufs):
            a.setflags(write=False)
        # basics stays writable (it is never shown: the items' warm starts keep views of it
        # as their index arrays, which the kernels take writable; a read-only one would be
        # copied by each item's warm_start, 0.3 us an island)
        self._sizes, self._off, self._out_i, self._out_f = sizes, off, out_i, out_f
        self._bufs, self._basics, self._ws, self._special = bufs, basics, ws, special
        self._items = [None] * len(sizes)
        for b, res in special.items():
            self._items[b] = res

    @classmethod
    def _of(cls, items) -> "LCPManyResult":
        """The result of a few problems that ``solve_lcp_many`` solved one by one with
        ``solve_lcp`` (``items``, a list of its results, none empty): the flat fields made
        from them when first read, as the kernels' arrays give them (the final bases read
        from the items' buffers, as the batch reads its own)."""
        res = object.__new__(cls)
        res._items = items  # (_off: the class's None; _special: made when first read)
        return res

    def _build(self, lo, hi, _new=object.__new__, _SOLVED=Status.SOLVED,
               _RAY_TERMINATION=Status.RAY_TERMINATION, _RAY=int(Status.RAY_TERMINATION)):
        """Items lo..hi-1 not built yet, as solve_lcp builds them (``LCPResult._lazy``,
        inlined: this loop is most of their Python time): they share the output buffers,
        and each makes its views when a field is first read."""
        items, bufs, basics, ws = self._items, self._bufs, self._basics, self._ws
        for b, (code, pivots, k, recoveries, stage), (ok, residual), qo, bo, n in zip(
                range(lo, hi), self._out_i[lo:hi].tolist(), self._out_f[lo:hi].tolist(),
                self._off[0, lo:hi].tolist(), self._off[2, lo:hi].tolist(), self._sizes[lo:hi]):
            if items[b] is not None:
                continue
            res = _new(LCPResult)
            f = res.__dict__
            f["status"] = _RAY_TERMINATION if code == _RAY else _SOLVED
            f["pivots"] = pivots
            f["residual"] = residual
            if recoveries:
                f["recoveries"] = recoveries
            f["_src"] = (bufs, bo, basics, qo, n, k)
            if stage == 0 and ws is not None:
                f["warm_start"] = ws[b]  # the one given (it still solved the problem)
            items[b] = res

    # --- the flat fields ------------------------------------------------------------------

    @cached
    def offsets(self) -> np.ndarray:
        if self._off is None:  # (_of)
            off = np.zeros(len(self._items) + 1, dtype=np.int64)
            np.cumsum([len(r.z) for r in self._items], out=off[1:])
            off.setflags(write=False)
            return off
        return self._off[0]

    def _gather(self, name):
        """Field ``name`` (``z`` or ``w``) of every problem, end to end: read from the output
        buffers, and from the results built already (their points recomputed)."""
        if self._off is None:  # (_of)
            v = np.concatenate([getattr(r, name) for r in self._items])
            v.setflags(write=False)
            return v
        a, c, _, _ = _SPANS[name]
        qo, bo = self._off[0], self._off[2]
        v = _core.many_field(self._bufs, bo, qo, a, c)  # (a copy; None: the native fronts are off)
        if v is None:
            n = np.diff(qo)
            idx = np.arange(qo[-1], dtype=np.int64)
            idx += np.repeat(bo[:-1] + a * n + c - qo[:-1], n)
            v = self._bufs.take(idx)
        for b, res in self._special.items():
            v[qo[b] : qo[b + 1]] = getattr(res, name)
        v.setflags(write=False)
        return v

    @cached
    def z(self) -> np.ndarray:
        return self._gather("z")

    @cached
    def w(self) -> np.ndarray:
        return self._gather("w")

    def _ints(self, j):
        """Column j of the kernels' integer results (zeros for _of: every item patched in)."""
        return np.zeros(len(self._items), dtype=np.int64) if self._off is None else self._out_i[:, j]

    @cached
    def status(self) -> np.ndarray:
        code = self._ints(0)
        return self._column(_layout.public_status(code), "status", int)

    @cached
    def pivots(self) -> np.ndarray:
        return self._column(self._ints(1), "pivots", int)

    @cached
    def recoveries(self) -> np.ndarray:
        return self._column(self._ints(3), "recoveries", int)

    @cached
    def residual(self) -> np.ndarray:
        if self._off is None:
            return self._column(np.zeros(len(self._items)), "residual", float)
        return self._column(self._out_f[:, 1], "residual", float)

    @cached
    def warm_start(self) -> WarmStartBatch:
        if self._off is None:  # (_of) each item's final basis, from its buffer when it has one
            bases = [_final_basis(r) for r in self._items]
            off = np.zeros(len(bases) + 1, dtype=np.int64)
            np.cumsum([len(b) for b in bases], out=off[1:])
            return WarmStartBatch._trusted(np.diff(self.offsets), np.concatenate(bases), off)
        got = _core.many_bases(self._basics, self._off[0], self._out_i)
        if got is None:  # (the native fronts are off)
            k = self._out_i[:, 2]
            off = np.zeros(len(k) + 1, dtype=np.int64)
            np.cumsum(k, out=off[1:])
            idx = np.arange(off[-1], dtype=np.int64)
            idx += np.repeat(self._off[0, :-1] - off[:-1], k)
            got = self._basics.take(idx), off, np.diff(self._off[0])
        z_basic, off, n = got
        return WarmStartBatch._trusted(n, z_basic, off)


def _final_basis(res) -> np.ndarray:
    """The final basic z's of a result of solve_lcp (int64): as the kernel left them in its
    buffer (a lazily built result), else its warm start's."""
    src = res.__dict__.get("_src")
    if src is None:
        return np.array(res.warm_start.z_basic, dtype=np.int64)
    buf, _, basic, bo, _, k = src
    return (buf.view(np.int64) if basic is None else basic)[bo : bo + k].copy()


@frozen(eq=False)
class LCPBatchResult(Value):
    """The outcome of :func:`lemke.solve_lcp_batch`: row b of every array is what
    :func:`lemke.solve_lcp` gives for problem b (the same status, pivots and bits).

    Attributes
    ----------
    z, w : ndarray, shape (B, n)
        The final points and ``w = M z + q`` on the caller's data.
    status : ndarray of int, shape (B,)
        :class:`Status` codes (``lemke.Status(result.status[b])`` names one).
    pivots : ndarray of int, shape (B,)
    residual : ndarray of float, shape (B,)
        ``max_i |min(z_i, w_i)|`` per problem.
    """

    z: np.ndarray
    w: np.ndarray
    status: np.ndarray
    pivots: np.ndarray
    residual: np.ndarray

    @property
    def success(self) -> np.ndarray:
        """Boolean array: which problems were solved."""
        return self.status == Status.SOLVED

    def __repr__(self) -> str:
        b, n = self.z.shape
        return f"LCPBatchResult(B={b}, n={n}, solved={int(self.success.sum())}/{b})"


def native_fronts_init():
    """Give solve_lcp's native front (``_core.lcp_front``, src/python_front.cpp) what it
    builds results with, and let it check NumPy's array layout on probes: every native front
    (solve_lcp's, solve_blcp's) stays off, returning None, where that layout differs.  Run by
    the first of ``_lcp`` and ``_blcp`` imported; once."""
    if _core.lcp_front_on():
        return
    probe = np.zeros((2, 3))
    ro = np.zeros(3)
    ro.setflags(write=False)
    _core.lcp_front_init(np.ndarray, LCPResult, Status.SOLVED, Status.RAY_TERMINATION, np.empty,
                         _DEFAULT.pivot_tol, _DEFAULT.tie_tol, _DEFAULT.tol, probe,
                         probe.__array_interface__["data"][0], ro, np.zeros(3, dtype=np.int64),
                         np.zeros(3, dtype=np.dtype(np.float64).newbyteorder()), _numpy_api())


def _numpy_api():
    """NumPy's C API table (the ``_ARRAY_API`` capsule of its ``_multiarray_umath``; NumPy
    2.x, then 1.x), or None: the native fronts then make their arrays with ``numpy.empty``."""
    for name in ("numpy._core._multiarray_umath", "numpy.core._multiarray_umath"):
        try:
            return importlib.import_module(name)._ARRAY_API
        except (ImportError, AttributeError):
            pass
    return None
