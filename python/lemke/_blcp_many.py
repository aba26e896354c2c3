"""solve_blcp_many: the islands of a contact scene, box LCPs with friction indices and warm
starts, in one call (the C++ core's ``boxed.batch``, without the GIL), each exactly as
:func:`lemke.solve_blcp` solves it.

Why a function of its own rather than bounds in :func:`lemke.solve_lcp_many`: a box LCP
is another problem (bounds, a friction index whose answer is checked on the coupled bounds,
an extended problem per island), solved by another engine (``src/lemke/boxed.*``), with
another result (the bounds in force) and another basis (each row at lo, at hi or basic:
:class:`BoxWarmStart`, not :class:`WarmStart`).  Folding them into ``solve_lcp_many``
would give one function two kinds of warm start and two kinds of result, and a
``findex`` that means nothing without bounds; one function per kind keeps each signature
and result type exact (``solve_lcp`` / ``solve_blcp``, ``solve_lcp_many`` /
``solve_blcp_many``), and ``solve_lcp_many``'s packed fast path untouched.
"""
from __future__ import annotations

import numpy as np

from ._frozen import frozen
from . import _validate
from ._batch import FEW, _SEQ, _flat, _packed, _plain, _run, _workers
from ._blcp import (BoxWarmStart, _carried, _check_warm, _from_codes, _label_index, _lazy,
                    _row_index, as_blcp, solve_blcp)
from ._core import boxed
from . import _blcp, _core
from ._options import as_options, time_limited, timed
from ._result import ManyItems, Value, _index, cached
from ._status import Status

_ND = np.ndarray
_F64 = np.dtype(np.float64)
_I64 = np.dtype(np.int64)


@frozen(eq=False)
class BoxWarmStartBatch(Value):
    """The final bases of B box LCPs (the islands of a scene) in one value: island b has
    ``n[b]`` rows, and ``state[offsets[b]:offsets[b + 1]]`` holds one int8 code per row,
    its state as :meth:`BoxWarmStart.row_states` gives it (0 at lo, 1 at hi, 2 basic; a
    friction row 3 + 9 s(β+) + 3 s(β-) + s(λ)).  The ``warm_start`` of
    :func:`lemke.solve_blcp_many`'s result: pass it back whole and the kernels read its
    codes as they are (no Python work per island).  ``batch[b]`` is island b's
    :class:`BoxWarmStart` (made when asked); ``len`` and iteration work as on a list.

    Because a row's state does not depend on the other rows, the whole scene's bases can be
    carried over at once, even when the islands split or merge: :meth:`take` /
    :meth:`relabel` map the rows of the whole scene (old islands end to end) to the new
    scene's rows and cut them into the new islands' ``sizes``.

    >>> BoxWarmStartBatch([2, 1], [2, 0, 1])[0]
    BoxWarmStart(n=2, z_basic=(0,), at_upper=(), friction=())
    """

    n: np.ndarray
    state: np.ndarray

    def __post_init__(self):
        n = np.array(self.n, copy=True)
        s = np.array(self.state, copy=True)
        if n.ndim != 1 or (n.size and n.dtype.kind not in "iu"):
            raise TypeError("BoxWarmStartBatch.n must be a 1-D sequence of integers")
        if s.ndim != 1 or (s.size and s.dtype.kind not in "iu"):
            raise TypeError("BoxWarmStartBatch.state must be a 1-D sequence of integer codes")
        n, s = n.astype(np.int64), s.astype(np.int8)
        if (n < 0).any() or int(n.sum()) != s.size:
            raise ValueError(f"BoxWarmStartBatch: n must hold sizes >= 0 summing to len(state) = {s.size}")
        if s.size and (s.min() < 0 or s.max() > 29):
            raise ValueError("BoxWarmStartBatch.state must hold codes in [0, 29]")
        for name, v in (("n", n), ("state", s)):
            v.setflags(write=False)
            object.__setattr__(self, name, v)

    @classmethod
    def _trusted(cls, n, state, read_only=False) -> "BoxWarmStartBatch":
        """Made of arrays of the solver's own (``read_only``: both read-only already)."""
        ws = object.__new__(cls)
        if not read_only:
            n.setflags(write=False)
            state.setflags(write=False)
        d = ws.__dict__
        d["n"], d["state"] = n, state
        return ws

    @classmethod
    def of(cls, warm_starts) -> "BoxWarmStartBatch":
        """The batch of a sequence of :class:`BoxWarmStart` (None is not allowed: a cold
        island's state is all zeros, ``BoxWarmStart(n, (), ())``)."""
        ws = list(warm_starts)
        for b, w in enumerate(ws):
            if not isinstance(w, BoxWarmStart):
                raise TypeError(f"warm_starts[{b}] must be a lemke.BoxWarmStart, got {type(w).__name__}")
        codes = [w.row_states() for w in ws]
        return cls._trusted(np.array([c.size for c in codes], dtype=np.int64),
                            np.concatenate(codes) if codes else np.zeros(0, np.int8))

    def __reduce__(self):
        return (BoxWarmStartBatch._trusted, (self.n.copy(), self.state.copy()))

    @cached
    def offsets(self) -> np.ndarray:
        off = np.zeros(self.n.size + 1, dtype=np.int64)
        np.cumsum(self.n, out=off[1:])
        off.setflags(write=False)
        return off

    def __len__(self) -> int:
        return self.n.size

    def __getitem__(self, b) -> BoxWarmStart:
        b = _index(b, self.n.size)
        kept = self.__dict__.get("_kept")
        if kept is not None and kept[b] is not None:
            return kept[b]
        lo, hi = self.offsets[b: b + 2].tolist()
        return _from_codes(self.state[lo:hi])

    def __iter__(self):
        return iter(self._list())

    def _list(self) -> tuple:
        """Every island's BoxWarmStart: those it was made of where it keeps them (a few
        islands' batch, ``BLCPManyResult._of``: an item's own where it is one that
        ``_from_codes`` made of the same codes), the others made from the codes when first
        asked for, then kept."""
        kept = self.__dict__.get("_kept")
        if kept is None or None in kept:
            off, s = self.offsets.tolist(), self.state
            kept = tuple([kept[b] if kept is not None and kept[b] is not None
                          else _from_codes(s[off[b]:off[b + 1]]) for b in range(self.n.size)])
            self.__dict__["_kept"] = kept  # (kept: the batch is immutable, so are they)
        return kept

    def __repr__(self) -> str:
        return f"BoxWarmStartBatch(B={self.n.size}, rows={self.state.size})"

    def take(self, indices, sizes, findex=None) -> "BoxWarmStartBatch":
        """The bases carried to a new scene: its row i (islands end to end, island b having
        ``sizes[b]`` rows) is row ``indices[i]`` of this scene (its islands end to end), or
        a new row (-1), which starts cold; ``findex``: the new scene's packed friction
        index (only which rows are friction rows matters here), None for none.  The rules
        of :meth:`BoxWarmStart.take`, row by row."""
        idx = _row_index(indices, self.state.size, "indices")
        return BoxWarmStartBatch._trusted(_new_sizes(sizes, idx.size), _carried(self.state, idx, findex))

    def relabel(self, old_labels, new_labels, sizes, findex=None) -> "BoxWarmStartBatch":
        """:meth:`take` by labels, one per row of the whole scene (e.g. contact ids): the
        rules of :meth:`BoxWarmStart.relabel`."""
        idx = _label_index(old_labels, new_labels, self.state.size)
        return BoxWarmStartBatch._trusted(_new_sizes(sizes, idx.size), _carried(self.state, idx, findex))


def _new_sizes(sizes, m):
    n = np.array(sizes, copy=True)
    if n.ndim != 1 or (n.size and n.dtype.kind not in "iu"):
        raise TypeError("sizes must be a 1-D sequence of integers")
    n = n.astype(np.int64)
    if (n < 0).any() or int(n.sum()) != m:
        raise ValueError(f"sizes must be >= 0 and sum to the {m} new rows, got a sum of {int(n.sum())}")
    return n


class BLCPManyResult(ManyItems):
    """The outcome of :func:`lemke.solve_blcp_many`: a sequence of :class:`BLCPResult`,
    item b what :func:`lemke.solve_blcp` gives for island b (bit for bit, whatever the
    number of workers), built when first read, with every island's answer also in flat,
    read-only arrays made by a few numpy calls when first read (no Python object per
    island).

    Attributes
    ----------
    offsets : ndarray of int64, shape (B + 1,)
        Island b's entries of ``z``, ``w``, ``lo``, ``hi`` are ``offsets[b]:offsets[b + 1]``.
    z, w : ndarray of float64, shape (sum of n_b,)
    lo, hi : ndarray of float64, shape (sum of n_b,)
        The bounds in force at z (with a friction index the coupled bounds
        -mu_i z_f, mu_i z_f of the friction rows; else the caller's).
    status : ndarray of int64, shape (B,)
        :class:`Status` codes.
    success : ndarray of bool, shape (B,)
    pivots, recoveries : ndarray of int64, shape (B,)
    residual : ndarray of float64, shape (B,)
    warm_start : BoxWarmStartBatch
        Every island's final basis (each item's ``warm_start``), to pass back whole next
        step, or to carry over to new islands with its ``take`` / ``relabel``.
    """

    def __init__(self, n_b, qoff, out_i, out_f, bufs, buff, ints, ioff, state, fflag,
                 los, his, given, special, answer):
        """The kernels' arrays (``boxed.batch``), the islands' sizes (int64, B: ``qoff``'s
        differences), the problems' flat bounds, the warm starts given (a
        BoxWarmStartBatch, a list, or None), ``special``: ``{b: BLCPResult}``, the islands
        the general path solved, and ``answer``: where each island's z sits in its buffer
        (``boxed.islands``)."""
        for a in (n_b, qoff, out_i, out_f, buff, ioff, state, fflag, answer):
            a.setflags(write=False)
        self._n_rows, self._qoff, self._out_i, self._out_f = n_b, qoff, out_i, out_f
        self._bufs, self._buff, self._ints, self._ioff = bufs, buff, ints, ioff
        self._state, self._fflag, self._los, self._his = state, fflag, los, his
        self._given, self._special, self._answer = given, special, answer
        self._items = [None] * len(n_b)
        for b, res in special.items():
            self._items[b] = res

    @classmethod
    def _of(cls, items) -> "BLCPManyResult":
        """The result of a few islands that ``solve_blcp_many`` solved one by one with
        ``solve_blcp`` (``items``, a list of its results, none empty): the flat fields made
        from them when first read."""
        res = object.__new__(cls)
        res._items = items  # (_special: made when first read)
        return res

    def _of_column(self, field, dtype):
        """A column of a result of ``_of``, read from its items."""
        v = np.array([getattr(r, field) for r in self._items], dtype=dtype)
        v.setflags(write=False)
        return v

    _qoff = _los = _his = None  # (a result of _of: only _items set)

    def _build(self, lo, hi):
        """Items lo..hi-1 not built yet, as solve_blcp builds them (``_blcp._lazy``): views
        of the shared buffers, made when a field is first read."""
        items, bufs, ints, los, his, given = (self._items, self._bufs, self._ints, self._los,
                                              self._his, self._given)
        qo, bo, io = self._qoff.tolist(), self._buff.tolist(), self._ioff.tolist()
        for b, (code, pivots, k, m, rec, stage, N), residual, fr in zip(
                range(lo, hi), self._out_i[lo:hi].tolist(), self._out_f[lo:hi].tolist(),
                self._fflag[lo:hi].tolist()):
            if items[b] is not None:
                continue
            n = qo[b + 1] - qo[b]
            items[b] = _lazy(bufs[bo[b]:bo[b + 1]], ints[io[b]:io[b + 1]], N, k, m, n,
                             los[qo[b]:qo[b + 1]], his[qo[b]:qo[b + 1]], bool(fr) and n > 0,
                             pivots, residual, rec, given[b] if stage == 0 else None)

    # --- the flat fields ------------------------------------------------------------------

    @cached
    def offsets(self) -> np.ndarray:
        if self._qoff is None:  # (_of)
            off = np.zeros(len(self._items) + 1, dtype=np.int64)
            np.cumsum([len(r.z) for r in self._items], out=off[1:])
            off.setflags(write=False)
            return off
        return self._qoff

    def _gather(self, name, shift, flat=None):
        if self._qoff is None:  # (_of: every item built)
            v = np.concatenate([getattr(r, name) for r in self._items])
            v.setflags(write=False)
            return v
        # the field ``shift`` n-blocks after the answer's z (FrontLayout: the caller's z, w,
        # lo, hi with a friction index, the run's z, w without; tests/test_structure.py);
        # lo, hi (``flat`` given): the buffer's with a friction index, else the flat ones
        qo, n = self._qoff, self._n_rows
        v = _core.many_field(self._bufs, self._buff, qo, shift, 0, self._answer,
                             None if flat is None else self._fflag, flat)
        if v is None:  # (the native fronts are off: numpy's gathers, the same values)
            at = np.arange(qo[-1], dtype=np.int64)
            at += np.repeat(self._buff[:-1] + self._answer + shift * n - qo[:-1], n)
            v = self._bufs.take(at)
            if flat is not None:
                v = np.where(np.repeat((self._fflag != 0) & (n > 0), n), v, flat)
        for b, res in self._special.items():
            v[qo[b]:qo[b + 1]] = getattr(res, name)
        v.setflags(write=False)
        return v

    @cached
    def z(self) -> np.ndarray:
        return self._gather("z", 0)

    @cached
    def w(self) -> np.ndarray:
        return self._gather("w", 1)

    @cached
    def lo(self) -> np.ndarray:
        return self._gather("lo", 2, self._los)

    @cached
    def hi(self) -> np.ndarray:
        return self._gather("hi", 3, self._his)

    @cached
    def status(self) -> np.ndarray:
        if self._qoff is None:
            return self._of_column("status", np.int64)
        return self._column(np.zeros(len(self._items), dtype=np.int64), "status", int)

    @cached
    def pivots(self) -> np.ndarray:
        if self._qoff is None:
            return self._of_column("pivots", np.int64)
        return self._column(self._out_i[:, 1], "pivots", int)

    @cached
    def recoveries(self) -> np.ndarray:
        if self._qoff is None:
            return self._of_column("recoveries", np.int64)
        return self._column(self._out_i[:, 4], "recoveries", int)

    @cached
    def residual(self) -> np.ndarray:
        if self._qoff is None:
            return self._of_column("residual", np.float64)
        return self._column(self._out_f, "residual", float)

    @cached
    def warm_start(self) -> BoxWarmStartBatch:
        if self._qoff is None:  # (_of: as the batch path writes a special island's states)
            kept = [r.warm_start for r in self._items]
            codes = [w.row_states() if w is not None else _cold_codes(len(r.z))
                     for w, r in zip(kept, self._items)]  # (read-only, as row_states makes them)
            if len(codes) == 1:
                ws = BoxWarmStartBatch._trusted(_one_size(codes[0].size), codes[0], read_only=True)
            else:
                ws = BoxWarmStartBatch._trusted(np.array([c.size for c in codes], dtype=np.int64),
                                                np.concatenate(codes))
            # the items' own warm starts made from codes (their z_basic, at_upper not set:
            # what _from_codes makes of these codes, so batch[b] is the same value), passed
            # back as they are (an island solved with 0 pivots keeps the one it was given)
            ws.__dict__["_kept"] = tuple([w if w is not None and "z_basic" not in w.__dict__ else None
                                          for w in kept])
            return ws
        return BoxWarmStartBatch._trusted(self._n_rows, self._state, read_only=True)


def _work(n_b, fflag, wflag):
    """A box batch's estimated multiply-adds (``_batch.INLINE_WORK``): the sum of n^3, eight
    times n^3 for a friction island that starts cold (a run on its 2n-row extended problem);
    a warm island's first try is its old basis's point on the caller's rows, as a warm LCP
    island's is (a box batch of 300 small warm islands was handed to the pool at 8 n^3 and
    took twice the time inline)."""
    n = n_b.astype(float)
    return float(np.dot(n * n * n, np.where((fflag != 0) & (wflag == 0), 8.0, 1.0)))


def solve_blcp_many(M, q, lo, hi, *, findex=None, warm_start=None, sizes=None, options=None,
                    workers=None) -> BLCPManyResult:
    r"""Solve the box LCPs of many islands (of different sizes, with friction indices and
    warm starts) in one call, in parallel threads without the GIL: island b is
    ``solve_blcp(M[b], q[b], lo[b], hi[b], findex=findex[b], warm_start=warm_start[b])``.

    Parameters
    ----------
    M, q, lo, hi : sequences of (n_b, n_b), (n_b,), (n_b,) array_like, B of each
        (a bound may be a scalar for its island).  Or, with ``sizes``, packed: 1-D arrays of
        every M_b (row by row) and every q_b, lo_b, hi_b laid end to end (the layout of the
        result's ``z``; a scalar bound applies to every row), with no Python object per
        island.
    findex : sequence of (n_b,) int array_like or None, or a packed int array, optional
        Each island's friction index (as in :func:`solve_blcp`: -1 for an ordinary row,
        ``findex[i] = f`` the island's own row f of the normal), None for an island without;
        packed (with ``sizes``): one 1-D integer array of every island's, end to end, each
        entry an index within its island.
    warm_start : BoxWarmStartBatch, or sequence of BoxWarmStart or None, optional
        The last step's ``result.warm_start`` (taken as it is: no Python work per island),
        carried over with its ``take`` / ``relabel`` when the islands' rows changed, or one
        :class:`BoxWarmStart` per island (None: cold).  Island b of a
        :class:`BoxWarmStartBatch` is warm-started from ``warm_start[b]``.  Its sizes and
        friction rows must match each island's (else ``ValueError`` naming
        ``warm_start[b]``: a changed number of rows needs ``take`` / ``relabel``).
    sizes : 1-D array_like of int, optional
        The n_b of packed input.
    options : Options or dict, optional
    workers : int, optional
        Threads (default: every usable core; 1 runs in the calling thread).  The answers do
        not depend on it.

    Returns
    -------
    BLCPManyResult
        A sequence of :class:`BLCPResult` (item b bit for bit ``solve_blcp``'s for island b,
        built when read) and flat arrays ``z``, ``w``, ``lo``, ``hi`` (island b's at
        ``offsets[b]:offsets[b + 1]``), ``status``, ``success``, ``pivots``,
        ``recoveries``, ``residual``, and ``warm_start``, a :class:`BoxWarmStartBatch`.

    Examples
    --------
    >>> import numpy as np, lemke
    >>> M = np.array([[2.0, 1.0], [1.0, 2.0]])
    >>> r = lemke.solve_blcp_many([M, np.eye(1)], [np.array([-5.0, 1.0]), np.array([-3.0])],
    ...                           [np.array([0.0, -1.0]), np.zeros(1)], [np.array([2.0, 1.0]), np.ones(1)])
    >>> r.z.tolist(), r.offsets.tolist(), r.success.tolist()
    ([2.0, -1.0, 1.0], [0, 2, 3], [True, True])
    >>> again = lemke.solve_blcp_many([M, np.eye(1)], [np.array([-5.0, 1.0]), np.array([-3.0])],
    ...                               [np.array([0.0, -1.0]), np.zeros(1)], [np.array([2.0, 1.0]), np.ones(1)],
    ...                               warm_start=r.warm_start)
    >>> again.pivots.tolist()
    [0, 0]
    """
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_blcp_many, M, q, lo, hi, findex=findex, warm_start=warm_start,
                     sizes=sizes, workers=workers)
    if (options is None and sizes is None and type(M) in _SEQ and 0 < len(M) <= _FEW_SMALL
            and (len(M) <= FEW or _small(q))
            and (workers is None or (type(workers) is int and workers > 0))):
        res = _few(M, q, lo, hi, findex, warm_start)
        if res is None and (c := _validate.plain_islands(M, q, lo, hi, findex)) is not None:
            # array-likes converted once, as as_blcp would convert them (when _few declines
            # them too, all below from the caller's objects, as before)
            res = _few(c[0], c[1], c[2], c[3], c[4] if findex is not None else None, warm_start)
        if res is not None:
            return res
    opts = as_options(options)
    workers = _workers(workers)
    packed = _PACK(M, q, lo, hi, findex) if sizes is None else None  # (lists: made_f64's forms)
    if packed is not None:
        Mflat, qflat, loflat, hiflat, fiflat, fflag, n_b = packed
        fflag = fflag.astype(np.uint8)
        if fiflat is None:
            fiflat = _NO_FINDEX
        B = n_b.size
        mlen = np.zeros(B + 1, dtype=np.int64)
        np.multiply(n_b, n_b, out=mlen[1:])
        fis = None
    elif sizes is None:
        Ms, qs, los, his, fis = _islands(M, q, lo, hi, findex)
        n_b = [len(x) for x in qs]
        B = len(n_b)
        mlen = np.zeros(B + 1, dtype=np.int64)
        mlen[1:] = [x * x for x in n_b]
        Mflat, qflat, loflat, hiflat = _flat(Ms), _flat(qs), _flat(los), _flat(his)
        fflag = np.array([f is not None for f in fis], dtype=np.uint8)
        fiflat = (np.concatenate([np.full(k, -1, np.int64) if f is None else f
                                  for f, k in zip(fis, n_b)]) if fflag.any() else _NO_FINDEX)
        n_b = np.array(n_b, dtype=np.int64)
    else:
        Mflat, qflat, off = _packed(M, q, sizes, buffers=False)
        n_b = off[0, 1:]
        B = n_b.size
        mlen = off[1]
        total = len(qflat)
        loflat, hiflat = (_packed_bound(x, total, name) for x, name in ((lo, "lo"), (hi, "hi")))
        if findex is None:
            fflag, fiflat = np.zeros(B, dtype=np.uint8), _NO_FINDEX
        else:
            fiflat = _validate.kernel_array(_packed_findex(findex, total))
            fflag = np.ones(B, dtype=np.uint8)
        fis = None
    qoff = np.zeros(B + 1, dtype=np.int64)
    np.cumsum(n_b, out=qoff[1:])
    mstart = np.cumsum(mlen)[:-1]
    state, wflag, given = _warm_states(warm_start, B, n_b, qoff, fis)
    # each island's buffers laid end to end (the engine's layout, src/lemke/boxed.hpp
    # FrontLayout), where its answer's z sits in its buffer, its pivot cap; the first warm
    # row of another kind than its row's
    buff, ioff = np.empty(B + 1, dtype=np.int64), np.empty(B + 1, dtype=np.int64)
    answer, limits = np.empty(B, dtype=np.int64), np.empty(B, dtype=np.int64)
    mp = opts.max_pivots
    if boxed.islands(qoff, fiflat, fflag, state, wflag, -1 if mp is None else mp, buff, ioff,
                     answer, limits) >= 0:
        fmask = (fiflat >= 0) & np.repeat(fflag != 0, n_b) if fiflat.size else None
        _same_kinds(state, fmask, qoff, wflag)  # raises, naming the island and row
    bufs = np.empty(int(buff[-1]))
    ints = np.empty(int(ioff[-1]), dtype=np.int64)
    state_out = np.empty(int(qoff[-1]), dtype=np.int8)
    out_i = np.empty((B, 7), dtype=np.int64)
    out_f = np.empty(B)
    _run(boxed.batch, (Mflat, mstart, qflat, loflat, hiflat, qoff, fiflat, fflag, state, wflag),
         (limits, opts.pivot_tol, opts.tie_tol, opts.tol, bufs, buff, ints, ioff, state_out,
          out_i, out_f), B, workers,
         work=None if workers == 1 else _work(n_b, fflag, wflag))  # (1: unread)
    special = {}
    given = _Given(warm_start, given)
    stage = out_i[:, 5]
    for b in np.flatnonzero(stage < 0).tolist():
        o0, o1, m0 = int(qoff[b]), int(qoff[b + 1]), int(mstart[b])
        n = o1 - o0
        args = (Mflat[m0:m0 + n * n].reshape(n, n), qflat[o0:o1], loflat[o0:o1], hiflat[o0:o1],
                fiflat[o0:o1] if fflag[b] else None)
        try:
            if stage[b] == _BAD_DATA:
                as_blcp(*args)  # raises, naming the entry
            res = solve_blcp(*args[:4], findex=args[4], options=opts,
                             warm_start=(given[b] if wflag[b] else None))
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"problem {b}: {exc}") from None
        special[b] = res
        state_out[o0:o1] = (res.warm_start.row_states() if res.warm_start is not None
                            else np.zeros(n, np.int8))
    return BLCPManyResult(n_b, qoff, out_i, out_f, bufs, buff, ints, ioff, state_out, fflag,
                          loflat, hiflat, given, special, answer)


# More islands than FEW also go one by one when they are small (a contact scene's small
# steps: single contacts of 3 rows), up to _FEW_SMALL of them and _SMALL_ROWS rows in all:
# each island's native front costs a few microseconds, the batch's set-up tens, and the
# batch's threads gain nothing on so little work.
_FEW_SMALL, _SMALL_ROWS = 16, 64


def _small(q):
    """Whether q is a list or tuple of ndarrays of _SMALL_ROWS entries in all, at most."""
    if type(q) not in _SEQ:
        return False
    total = 0
    for qb in q:
        if type(qb) is not _ND:
            return False
        total += qb.size
    return total <= _SMALL_ROWS


def _few(M, q, lo, hi, findex, warm_start):
    """solve_blcp_many's result for a few islands (M a list or tuple of at most FEW, or
    of at most _FEW_SMALL small ones) solved
    one by one by ``solve_blcp`` (its native front: microseconds each, where the batch's
    set-up of its flat arrays and offsets costs tens of microseconds), or None for the
    general path: when M_b, q_b are not float64 ndarrays of sizes n_b >= 1, the sequences'
    lengths differ, the warm starts are not None, a BoxWarmStartBatch of the islands' sizes
    or a sequence of BoxWarmStart or None, or a solve refuses its arguments (the general
    path then says what is wrong, naming the island, as it always has). Item b is
    solve_blcp's result either way, bit for bit."""
    if _blcp._FRONT is _NATIVE_FRONT:  # (a test may switch solve_blcp's front off)
        # every island's native front in one call (src/python_front_box.cpp): the items
        # when each call settles its island, else None (then the loop below, from the start)
        items = _FRONT_MANY(M, q, lo, hi, findex, warm_start._list()
                            if type(warm_start) is BoxWarmStartBatch else warm_start)
        if items is not None:
            return BLCPManyResult._of(items)
    B = len(M)
    if not (type(q) in _SEQ and type(lo) in _SEQ and type(hi) in _SEQ
            and len(q) == len(lo) == len(hi) == B):
        return None
    if findex is None:
        fis = (None,) * B
    elif type(findex) in _SEQ and len(findex) == B:
        fis = findex
    else:
        return None
    if not _plain(M, q):
        return None
    if warm_start is None:
        ws = (None,) * B
    elif type(warm_start) is BoxWarmStartBatch:
        if warm_start.n.tolist() != [qb.shape[0] for qb in q]:
            return None
        ws = warm_start._list()
    elif (type(warm_start) in _SEQ and len(warm_start) == B
          and all(w is None or type(w) is BoxWarmStart for w in warm_start)):
        ws = warm_start
    else:
        return None
    front = _blcp._FRONT
    items = []
    try:
        for b in range(B):
            # solve_blcp's own first step (its native front), the rest of solve_blcp (the
            # same call again first) where that does not settle it
            r = front(M[b], q[b], lo[b], hi[b], fis[b], ws[b])
            if r is None or r is False or type(r) is tuple:
                r = solve_blcp(M[b], q[b], lo[b], hi[b], findex=fis[b], warm_start=ws[b])
            items.append(r)
    except (TypeError, ValueError):
        return None
    return BLCPManyResult._of(items)


def _cold_codes(n):
    c = np.zeros(n, np.int8)
    c.setflags(write=False)
    return c


def _one_size(n, _kept={}):
    """The read-only array [n] (the sizes of a one-island batch), made once per n."""
    a = _kept.get(n)
    if a is None:
        a = np.array([n], dtype=np.int64)
        a.setflags(write=False)
        if len(_kept) < 4096:
            _kept[n] = a
    return a


_NATIVE_FRONT, _FRONT_MANY = _core.blcp_front, _core.blcp_front_many
_PACK = _core.blcp_pack  # (src/python_front.cpp: the islands packed, or None)
_NO_FINDEX = np.zeros(0, dtype=np.int64)
_BAD_DATA = -2  # boxed.batch's stage for data the kernels refuse


class _Given:
    """Island b's warm start as given (made from a BoxWarmStartBatch when asked)."""

    __slots__ = ("batch", "items")

    def __init__(self, warm_start, items):
        self.batch = warm_start if type(warm_start) is BoxWarmStartBatch else None
        self.items = items

    def __getitem__(self, b):
        return self.batch[b] if self.items is None else self.items[b]


def _islands(M, q, lo, hi, findex):
    """Lists of islands as float64 arrays ready for the kernels (a ``ValueError`` naming the
    island and the entry otherwise) and their friction indices (int64 or None)."""
    Ms, qs = list(M), list(q)
    B = len(Ms)
    los, his = _per_island(lo, B, "lo"), _per_island(hi, B, "hi")
    fis = [None] * B if findex is None else list(findex)
    for name, v in (("q", qs), ("lo", los), ("hi", his), ("findex", fis)):
        if len(v) != B:
            raise ValueError(f"M and {name} must hold the same number of problems, got {B} and {len(v)}")
    for b in range(B):
        Mb, qb, lb, hb, fb = Ms[b], qs[b], los[b], his[b], fis[b]
        if not (_ready(Mb, qb) and _ready_bound(lb, qb) and _ready_bound(hb, qb)
                and (fb is None or (type(fb) is _ND and fb.dtype == _I64 and fb.shape == qb.shape))):
            try:
                Mb, qb, lb, hb, fb = as_blcp(Mb, qb, lb, hb, fb)
            except (TypeError, ValueError) as exc:
                raise type(exc)(f"problem {b}: {exc}") from None
            Ms[b], qs[b], los[b], his[b], fis[b] = Mb, qb, lb, hb, fb
    return Ms, qs, los, his, fis


def _per_island(v, B, name):
    if isinstance(v, (int, float, np.number)):  # one scalar bound for every island
        return [v] * B
    return list(v)


def _ready(M, q) -> bool:
    return (type(M) is _ND and type(q) is _ND and M.dtype == _F64 and q.dtype == _F64
            and M.ndim == 2 and q.ndim == 1 and M.shape[0] == M.shape[1] == q.shape[0]
            and M.flags.c_contiguous and q.flags.c_contiguous)


def _ready_bound(v, q) -> bool:
    return type(v) is _ND and v.dtype == _F64 and v.shape == q.shape and v.flags.c_contiguous


def _packed_bound(v, total, name):
    """A packed bound: a scalar for every row, or a 1-D array of ``total`` numbers."""
    a = _validate.float64_array(v, name)
    if a.ndim == 0:
        return np.full(total, float(a))
    if a.shape != (total,):
        raise ValueError(f"packed {name} must be a scalar or 1-D with {total} numbers (sum of n_b), "
                         f"got shape {a.shape}")
    return _validate.kernel_array(a)


def _packed_findex(findex, total):
    f = np.asarray(findex)
    if f.shape != (total,) or (f.size and f.dtype.kind not in "iu"):
        raise ValueError(f"packed findex must be 1-D with {total} integers (sum of n_b), got shape "
                         f"{f.shape} and dtype {f.dtype}")
    return f.astype(np.int64)


def _warm_states(warm_start, B, n_b, qoff, fis):
    """The warm starts as the kernel takes them: the row states end to end (int8), a flag
    per island (0: cold), and the list of those given (None for a BoxWarmStartBatch, whose
    codes are taken as they are).  Sizes are checked against the islands' (ValueError
    naming ``warm_start[b]``); the rows' kinds by ``boxed.islands`` (then
    :func:`_same_kinds`)."""
    total = int(qoff[-1])
    if warm_start is None:
        return np.zeros(total, dtype=np.int8), np.zeros(B, dtype=np.uint8), None
    if type(warm_start) is BoxWarmStartBatch:
        if len(warm_start) != B:
            raise ValueError(f"warm_start must hold one basis per problem: {len(warm_start)} for {B} problems")
        bad = np.flatnonzero(warm_start.n != n_b)
        if bad.size:
            b = int(bad[0])
            raise ValueError(f"warm_start[{b}] is for a problem of size {int(warm_start.n[b])}, problem {b} "
                             f"has n = {int(n_b[b])} (carry a basis to new rows with take or relabel)")
        return _validate.kernel_array(warm_start.state), np.ones(B, dtype=np.uint8), None
    _validate.wrong_kind(warm_start, "warm_start", "lemke.BoxWarmStartBatch or a sequence of BoxWarmStart")
    ws = list(warm_start)
    if len(ws) != B:
        raise ValueError(f"warm_start must hold one BoxWarmStart (or None) per problem: {len(ws)} for {B} problems")
    state = np.zeros(total, dtype=np.int8)
    wflag = np.zeros(B, dtype=np.uint8)
    for b, w in enumerate(ws):
        if w is None:
            continue
        if not isinstance(w, BoxWarmStart) or w.rows != n_b[b]:
            _check_warm(w, int(n_b[b]), None, f"warm_start[{b}]", f"problem {b}")  # raises
            raise ValueError(f"warm_start[{b}] is for a problem of {w.rows} rows, problem {b} has "
                             f"n = {int(n_b[b])} (carry a basis to new rows with take or relabel)")
        state[qoff[b]:qoff[b + 1]] = w.row_states()
        wflag[b] = 1
    return state, wflag, ws


def _same_kinds(state, fmask, qoff, wflag=None):
    """Each warm row's kind (friction or not) must be its island's (ValueError naming the
    island and row)."""
    fric = state >= 3
    want = np.zeros(state.size, dtype=bool) if fmask is None else fmask
    bad = fric != want
    if wflag is not None:
        bad &= np.repeat(wflag != 0, np.diff(qoff))
    if bad.any():
        r = int(np.flatnonzero(bad)[0])
        b = int(np.searchsorted(qoff, r, side="right") - 1)
        raise ValueError(f"warm_start[{b}] is for other friction rows: its row {r - int(qoff[b])} is "
                         f"{'a friction' if fric[r] else 'an ordinary'} row, problem {b}'s findex makes it "
                         f"{'a friction' if want[r] else 'an ordinary'} one (carry a basis over with take "
                         "or relabel and the new findex)")
