"""solve_lcp_batch: many LCPs of one size, solved in parallel threads (the kernels release
the GIL), each exactly as :func:`lemke.solve_lcp` solves it."""
from __future__ import annotations

import functools
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from itertools import chain
from operator import attrgetter

import numpy as np

from . import _core, _lcp, _progress, _validate
from ._lcp import METHODS, _outcome, solve_lcp as _solve_lcp
from ._options import as_options, time_limited, timed
from ._result import LCPBatchResult, LCPManyResult, WarmStart, WarmStartBatch
from ._status import Status
from ._validate import real_array
from ._npc import every as _every
from . import _layout

#: The batch kernel: the C++ core's (src/lemke/lcp.cpp, ``lemke::batch``), the port of
#: ``_core.batch`` (a module attribute, so that a test can stand another in).
_BATCH = _core.batch

_pool = None
_pool_lock = threading.Lock()


def usable_cores() -> int:
    """CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _executor():
    global _pool
    with _pool_lock:
        if _pool is None:
            _pool = ThreadPoolExecutor(usable_cores(), thread_name_prefix="lemke-batch")
        return _pool


def _forget_pool():
    """In a child made by fork: the parent's pool threads do not exist there (work handed to
    them would wait forever), and its lock may have been held; the child starts its own."""
    global _pool, _pool_lock
    _pool, _pool_lock = None, threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def _workers(workers) -> int:
    workers = _validate.positive_int_or_none(workers, "workers")
    return usable_cores() if workers is None else workers


#: Estimated multiply-adds (sum of n^3 over the problems) under which a batch runs in the
#: calling thread whatever ``workers`` says: handing chunks to pool threads costs some tens
#: to hundreds of microseconds (a thread's wake-up on a shared machine), more than such a
#: batch takes to solve.  The results are the same either way.
INLINE_WORK = 200_000


def _run(kernel, args, tail, B, workers, progress=None, what="", work=None):
    """``kernel(*args, lo, hi, *tail)`` over chunks of the B problems: in the calling thread
    when one worker (or one chunk), else by the calling thread and ``workers - 1`` threads of
    the pool, each taking the next chunk until none is left.  The calling thread starts at
    once, so a pool thread that is slow to wake (an idle core of a shared machine can take
    a millisecond) only takes fewer chunks.  Every problem is solved by the same kernel
    whatever the chunking and whichever thread runs it, so the results do not depend on
    the number of workers.  The pool's threads take the caller's deadline (Options'
    time_limit) and take no chunk after an interrupt (Ctrl-C; the call then raises
    KeyboardInterrupt).  ``progress`` (checked by ``_progress.check``): when neither
    None nor False, the work goes through :func:`_run_reporting`, the reports named
    ``what``.  ``work``: the batch's estimated multiply-adds (see INLINE_WORK)."""
    if progress is not None and progress is not False:
        return _run_reporting(kernel, args, tail, B, workers, progress, what)
    if work is not None and work < INLINE_WORK:
        workers = 1
    chunks = min(B, CHUNKS_PER_WORKER * workers) if workers > 1 else min(B, 1)
    if chunks <= 1:  # one chunk, all B (none when B = 0), in the calling thread
        if chunks:
            kernel(*args, 0, B, *tail)
        return
    bounds = np.linspace(0, B, chunks + 1).astype(int).tolist()
    spans = iter(list(zip(bounds[:-1], bounds[1:])))
    lock = threading.Lock()
    deadline, seen = _core.deadline(), _core.interrupts()  # the caller's budget, for the pool's

    def take(worker=True):
        if worker:
            _core.restore_deadline(deadline)
        try:
            while True:
                with lock:
                    span = next(spans, None) if _core.interrupts() == seen else None
                if span is None:
                    return
                kernel(*args, span[0], span[1], *tail)
        finally:
            if worker:
                _core.restore_deadline(0)

    pool = _executor()
    helpers = [pool.submit(take) for _ in range(min(workers, chunks) - 1)]
    try:
        take(False)
    finally:
        for f in helpers:
            f.result()
    if next(spans, None) is not None:  # chunks left untaken: interrupted (Ctrl-C)
        raise KeyboardInterrupt("the batch was interrupted")


def _run_reporting(kernel, args, tail, B, workers, progress, what):
    """:func:`_run` calling ``progress(done, total)`` in the calling thread as chunks finish
    (``done`` problems of ``total = B``, growing; the last call ``(B, B)``).  The chunks are
    solved by ``workers`` threads of the pool while the calling thread waits and reports;
    there are at least PROGRESS_CHUNKS of them (fewer when B is smaller), also with one
    worker, so that the reports come at a useful rate (the results are the same whatever
    the chunking).  Should the calling thread stop (an exception of ``progress``, Ctrl-C),
    the threads take no new chunk, and it returns once their chunks in hand are done."""
    with _progress.Reporter(progress, what, total=B, unit="problem") as report:
        chunks = min(B, max(CHUNKS_PER_WORKER * workers, PROGRESS_CHUNKS))
        bounds = np.linspace(0, B, chunks + 1).astype(int).tolist() if chunks else [0]
        spans = iter(list(zip(bounds[:-1], bounds[1:])))
        cond = threading.Condition()
        state = {"done": 0, "running": min(workers, chunks), "stop": False}
        deadline, seen = _core.deadline(), _core.interrupts()

        def take():
            _core.restore_deadline(deadline)
            try:
                while True:
                    with cond:
                        stop = state["stop"] or _core.interrupts() != seen
                        span = None if stop else next(spans, None)
                    if span is None:
                        return
                    kernel(*args, span[0], span[1], *tail)
                    with cond:
                        state["done"] += span[1] - span[0]
                        cond.notify_all()
            finally:
                _core.restore_deadline(0)
                with cond:
                    state["running"] -= 1
                    cond.notify_all()

        pool = _executor()
        threads = [pool.submit(take) for _ in range(state["running"])]
        reported = 0
        try:
            while True:
                with cond:
                    cond.wait_for(lambda: state["done"] > reported or not state["running"])
                    done, running = state["done"], state["running"]
                if done > reported or B == 0:
                    reported = done
                    report.update(done, B)
                if not running:
                    break
        finally:
            with cond:
                state["stop"] = True
            for f in threads:
                f.result()
        if state["done"] < B:  # chunks left untaken: interrupted (Ctrl-C)
            raise KeyboardInterrupt("the batch was interrupted")


#: Chunks per worker: enough that a late thread leaves little for the others to wait on,
#: few enough that a kernel call's set-up (a few microseconds) stays negligible.
CHUNKS_PER_WORKER = 8
#: The fewest chunks of a batch with a progress report (a report per chunk).
PROGRESS_CHUNKS = 64


def _bases(warm_start, B, sizes):
    """The warm starts as one index array and offsets (an empty basis: cold), and the list of
    them (None when not given, or given as a WarmStartBatch, whose arrays are taken as they
    are).  ``sizes``: the problems' sizes, a list."""
    if warm_start is None:
        return np.zeros(0, dtype=np.int64), np.zeros(B + 1, dtype=np.int64), None
    if type(warm_start) is WarmStartBatch:
        if len(warm_start) != B:
            raise ValueError(f"warm_start must hold one basis per problem: {len(warm_start)} for {B} problems")
        if warm_start.n.tolist() != sizes:
            b = int(np.flatnonzero(warm_start.n != sizes)[0])
            raise ValueError(f"warm_start[{b}] is for a problem of size {warm_start.n[b]}, problem {b} "
                             f"has n = {sizes[b]}")
        return warm_start.z_basic, warm_start.offsets, None  # (the core reads them in place)
    _validate.wrong_kind(warm_start, "warm_start", "lemke.WarmStartBatch or a sequence of WarmStart")
    ws = list(warm_start)
    if len(ws) != B:
        raise ValueError(f"warm_start must hold one WarmStart (or None) per problem: {len(ws)} for {B} problems")
    kinds = set(map(type, ws))
    if kinds == {WarmStart}:  # the common case, checked at C speed
        if list(map(_n_of, ws)) != sizes:
            _check_bases(ws, sizes)
        try:  # the index arrays that results' warm starts carry (see _result._FromBuffer)
            bases = list(map(_beta_of, ws))
        except AttributeError:
            bases = list(map(_z_basic_of, ws))
    else:
        if not kinds <= {WarmStart, type(None)} or [n if w is None else w.n for w, n in zip(ws, sizes)] != sizes:
            _check_bases(ws, sizes)
        bases = [() if w is None else w.z_basic for w in ws]
    lengths = np.zeros(B + 1, dtype=np.int64)
    lengths[1:] = list(map(len, bases))
    np.cumsum(lengths, out=lengths)
    if bases and type(bases[0]) is np.ndarray:
        flat = np.frombuffer(bytearray().join(bases), np.int64)
        if not flat.flags.aligned:
            flat = flat.copy()
    else:
        flat = np.fromiter(chain.from_iterable(bases), np.int64, int(lengths[-1]))
    return flat, lengths, ws


_n_of = attrgetter("n")
_z_basic_of = attrgetter("z_basic")
_beta_of = attrgetter("_beta")


def _check_bases(ws, sizes):
    """Each warm start checked (``_validate.warm_start``): raises naming the first bad one."""
    for b, w in enumerate(ws):
        if w is not None:
            _validate.warm_start(w, WarmStart, sizes[b],
                                 f"warm_start[{b}] is for a problem of size {{ws}}, problem {b} has n = {{n}}")


def solve_lcp_batch(M, q, *, method="tableau", options=None, workers=None, warm_start=None,
                    progress=None) -> LCPBatchResult:
    r"""Solve B linear complementarity problems of one size n by Lemke's method, in parallel.

    Problem b asks for z with :math:`z \ge 0`, :math:`w = M_b z + q_b \ge 0`,
    :math:`z^\top w = 0`.  Each problem is solved cold exactly as
    ``solve_lcp(M_b, q_b, method=method, options=options)`` solves it, answer check
    (and its downgrade to NUMERICAL_FAILURE) included: the same status, pivots and z, bit
    for bit.  The kernels run without the GIL, in a pool of threads.

    Parameters
    ----------
    M : (B, n, n) array_like, or (n, n) shared by all problems
    q : (B, n) array_like
        B = 0 (no problem) and n = 0 (empty problems, each SOLVED) are allowed.
    method : {"tableau", "unrevised"}
    options : Options or dict, optional
    workers : int, optional
        Threads to use (default: every CPU core the process may run on; 1 runs in the
        calling thread).
    warm_start : sequence of WarmStart or None, optional
        One per problem (None: cold), e.g. the ``warm_start`` of each problem's last solve.
    progress : callable or bool, optional
        Called as ``progress(done, total)`` in the calling thread as chunks of problems
        are solved (``done`` of the ``total = B`` problems; the last call is ``(B, B)``).
        The batch is then cut into at least 64 chunks (one report each), also with one
        worker; the results do not change.  ``True`` shows a bar on stderr (tqdm's when
        installed, ``pip install lemke[progress]``; else a one-line counter).

    Returns
    -------
    LCPBatchResult
        Arrays ``z``, ``w`` (B, n), ``status``, ``pivots``, ``residual`` (B,).

    Examples
    --------
    >>> import numpy as np, lemke
    >>> M = np.array([[2.0, 1.0], [1.0, 2.0]])
    >>> r = lemke.solve_lcp_batch(M, [[-5.0, -6.0], [1.0, -1.0]])
    >>> r.status.tolist(), r.z.round(6).tolist()
    ([0, 0], [[1.333333, 2.333333], [0.0, 0.5]])
    """
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_lcp_batch, M, q, method=method, workers=workers,
                     warm_start=warm_start, progress=progress)
    _validate.method(method, METHODS)
    opts = as_options(options)
    progress = _progress.check(progress)
    M, q = batch_arrays(M, q)
    B, n = q.shape
    workers = _workers(workers)
    beta, boff, _ = _bases(warm_start, B, [n] * B)

    L = _layout.buffer_length(n)
    bufs = np.empty((B, L))
    basics = np.empty((B, n), dtype=np.int64)
    out_i = np.empty((B, 5), dtype=np.int64)
    out_f = np.empty((B, 2))
    # The kernel of solve_lcp_many, with the problems laid end to end in the arrays as they
    # are (row-major views, no copies); a shared M starts every problem at offset 0.
    mstart = np.zeros(B, dtype=np.int64) if M.shape[0] == 1 else np.arange(B, dtype=np.int64) * (n * n)
    qoff = np.arange(B + 1, dtype=np.int64) * n
    limits = np.full(B, opts.pivot_limit(n), dtype=np.int64)
    _run(_BATCH, (_layout.METHODS[method], M.reshape(-1), mstart, q.reshape(-1), qoff, beta, boff),
         (limits, opts.pivot_tol, opts.tie_tol, opts.tol, bufs.reshape(-1),
          np.arange(B + 1, dtype=np.int64) * L, basics.reshape(-1), out_i, out_f), B, workers,
         progress, "solve_lcp_batch", work=B * n ** 3)

    f = _layout.fields(n)
    z = np.ascontiguousarray(bufs[:, f["z"]])
    w = np.ascontiguousarray(bufs[:, f["w"]])
    status = _layout.public_status(out_i[:, 0])
    pivots = out_i[:, 1].copy()
    residual = out_f[:, 1].copy()
    # Everything but a checked solution (and q >= 0, always checked) goes through solve_lcp's
    # own logic: the recomputation from the final basis, the ray check, the downgrades.
    for b in np.flatnonzero((status != 0) | (out_f[:, 0] == 0.0)):
        code, piv, k, recoveries, _ = (int(v) for v in out_i[b])
        res = _outcome(M[0 if M.shape[0] == 1 else b], q[b], opts, code, piv, basics[b, :k],
                       bool(out_f[b, 0]), float(out_f[b, 1]), bufs[b].copy(), recoveries)
        z[b], w[b], status[b], residual[b] = res.z, res.w, int(res.status), res.residual
    for a in (z, w, status, pivots, residual):
        a.setflags(write=False)
    return LCPBatchResult(z, w, status, pivots, residual)


def batch_arrays(M, q):
    """``(M, q)`` of a batch as float64 C-contiguous arrays of shapes (1 or B, n, n) and
    (B, n) (a shared M gets a leading axis of 1), or a ``ValueError`` naming the shape."""
    M = real_array(M, "M")
    q = real_array(q, "q")
    if q.ndim != 2:
        raise ValueError(f"q must have shape (B, n), got shape {q.shape}")
    B, n = q.shape
    if n == 0 and M.size == 0 and M.ndim < 3:
        M = np.zeros((0, 0))  # [] is the empty matrix, shared
    if M.ndim == 2:
        if M.shape != (n, n):
            raise ValueError(f"a shared M must have shape ({n}, {n}) to match q of shape {q.shape}, got {M.shape}")
        M = M[None]
    elif M.ndim != 3 or M.shape != (B, n, n):
        raise ValueError(f"M must have shape ({B}, {n}, {n}) or ({n}, {n}) to match q of shape {q.shape}, got {M.shape}")
    return _validate.kernel_array(M), _validate.kernel_array(q)


def solve_lcp_many(M, q, *, method="tableau", options=None, workers=None,
                   warm_start=None, sizes=None, progress=None) -> LCPManyResult:
    r"""Solve LCPs of different sizes (the islands of a contact scene) in one call, in
    parallel threads without the GIL: problem b is ``(M[b], q[b])`` with its own n_b.

    Parameters
    ----------
    M, q : sequences of (n_b, n_b) and (n_b,) array_like, of the same length B
        Or, with ``sizes``, packed: 1-D arrays of every M_b (row by row) and every q_b
        laid end to end -- the layout of the result's ``z`` -- with no Python object per
        problem (what a scene that keeps its islands in flat buffers has at hand; about
        0.4 us an island less than the lists).
    sizes : 1-D array_like of int, optional
        The n_b of packed ``M`` and ``q`` (B of them; ``M`` then holds sum n_b^2 numbers and
        ``q`` sum n_b).  Problem b is ``M[mo:mo + n_b**2].reshape(n_b, n_b)``, ``q[o:o + n_b]``
        with mo and o the sums of the earlier n^2 and n.
    method : {"tableau", "unrevised"}
    options : Options or dict, optional
    workers : int, optional
        Threads (default: every usable core; 1 runs in the calling thread).
    warm_start : WarmStartBatch, or sequence of WarmStart or None, optional
        The last step's ``result.warm_start`` (a :class:`WarmStartBatch`, taken as it is: no
        Python work per problem), or one WarmStart per problem (None: cold), e.g. each
        island's last ``warm_start``, carried over with :meth:`WarmStart.relabel` when its
        contacts changed.
    progress : callable or bool, optional
        As in :func:`solve_lcp_batch`: ``progress(done, total)`` as chunks of problems are
        solved, or ``True`` for a bar on stderr.

    Returns
    -------
    LCPManyResult
        A sequence of :class:`LCPResult`: item b is what ``solve_lcp(M[b], q[b],
        method=method, warm_start=warm_start[b], options=options)`` returns, bit for bit,
        whatever the number of workers, built when first read.  The same answers lie in
        flat arrays, read without a Python object per problem: ``z`` and ``w`` end to end
        (problem b's at ``offsets[b]:offsets[b + 1]``), ``status``, ``success``,
        ``pivots``, ``residual``, and ``warm_start``, every final basis in one
        :class:`WarmStartBatch` to pass back.

    Examples
    --------
    >>> import lemke
    >>> rs = lemke.solve_lcp_many([[[2.0]], [[2.0, 1.0], [1.0, 2.0]]], [[-1.0], [-5.0, -6.0]])
    >>> [r.z.round(6).tolist() for r in rs]
    [[0.5], [1.333333, 2.333333]]
    >>> rs.z.round(6).tolist(), rs.offsets.tolist(), rs.success.tolist()
    ([0.5, 1.333333, 2.333333], [0, 1, 3], [True, True])
    >>> nxt = lemke.solve_lcp_many([[[2.0]], [[2.0, 1.0], [1.0, 2.0]]], [[-1.1], [-5.0, -6.1]],
    ...                            warm_start=rs.warm_start)
    >>> nxt.pivots.tolist()  # the old bases still solve them
    [0, 0]
    """
    if options is not None and (timing := time_limited(options)):
        return timed(timing, solve_lcp_many, M, q, method=method, workers=workers,
                     warm_start=warm_start, sizes=sizes, progress=progress)
    if method != "tableau":
        _validate.method(method, METHODS)
    if (options is None and sizes is None and (progress is None or progress is False)
            and type(M) in _SEQ and type(q) in _SEQ and 0 < len(M) <= FEW):
        if workers is not None:
            _validate.positive_int_or_none(workers, "workers")
        res = _few(M, q, method, warm_start)
        if res is None and (c := _validate.plain_many(M, q)) is not None:
            # array-likes converted once, as _checked below would convert them (when _few
            # declines them too, all below from the caller's objects, as before)
            res = _few(c[0], c[1], method, warm_start)
        if res is not None:
            return res
    opts = as_options(options)
    workers = _workers(workers)
    if progress is not None:
        progress = _progress.check(progress)
    # offsets: of q and the basic z's, of M, of the output buffers (_layout.buffer_length)
    packed = _core.lcp_pack(M, q) if sizes is None else None  # lists ready or converted (made_f64)
    cap = -1 if opts.max_pivots is None else opts.max_pivots
    # ready packed arrays (or the lists packed): every array the kernels take in one call
    setup = None
    if packed is not None:
        Mflat, qflat, n_b = packed
        setup = _core.many_setup(n_b, Mflat, qflat, cap)
    elif type(sizes) is _ND:
        Mflat, qflat = M, q
        setup = _core.many_setup(sizes, M, q, cap)
    if setup is not None:
        off, limits, work, sizes, bufs, basics, out_i, out_f = setup
        B = len(sizes)
        return _many(method, opts, workers, progress, warm_start, Mflat, qflat, B, sizes, off, limits,
                     work, bufs, basics, out_i, out_f)
    if packed is not None:
        off = _offsets(n_b)
        sizes = n_b.tolist()
        B = len(sizes)
    elif sizes is None:
        Ms, qs = list(M), list(q)
        B = len(Ms)
        if B != len(qs):
            raise ValueError(f"M and q must hold the same number of problems, got {B} and {len(qs)}")
        given = None
        # Every problem ready for the kernels (float64 ndarrays, M square of q's size) is the
        # common case, checked in one pass; else each problem is checked and converted.
        if len([None for Mb, qb in zip(Ms, qs)
                if type(Mb) is _ND and type(qb) is _ND
                and (Mb.dtype is _F64 or Mb.dtype == _F64) and (qb.dtype is _F64 or qb.dtype == _F64)
                and qb.ndim == 1 and Mb.shape == qb.shape * 2]) != B:
            # (array-likes converted at once as _checked converts them, their finiteness
            # checked below; if any is of another kind, each is checked in turn)
            if (c := _validate.plain_many(Ms, qs)) is not None:
                given, (Ms, qs) = (Ms, qs), c
            else:
                Ms, qs = zip(*[(Mb, qb) if _ready(Mb, qb) else _checked(b, Mb, qb)
                               for b, (Mb, qb) in enumerate(zip(Ms, qs))]) if B else ((), ())
        sizes = list(map(len, qs))
        off = _offsets(sizes)
        Mflat, qflat = _flat(Ms), _flat(qs)
        if given is not None and not (_every(_isfinite(Mflat)) and _every(_isfinite(qflat))):
            for b, (Mb, qb) in enumerate(zip(*given)):
                _checked(b, Mb, qb)  # raises at the first fault, as the checks above would
    else:
        Mflat, qflat, off = _packed(M, q, sizes)
        sizes = off[0, 1:].tolist()
        B = len(sizes)
    n_b = off[0, 1:]
    limits = np.empty(B, dtype=np.int64)
    limits[:] = opts.pivot_limit(n_b)
    work = _cubes(n_b)  # (before the sums below: n_b is a view of off)
    np.cumsum(off, axis=1, out=off)
    bufs = np.empty(int(off[2, -1]))
    basics = np.empty(int(off[0, -1]), dtype=np.int64)
    out_i = np.empty((B, 5), dtype=np.int64)
    out_f = np.empty((B, 2))
    return _many(method, opts, workers, progress, warm_start, Mflat, qflat, B, sizes, off, limits, work,
                 bufs, basics, out_i, out_f)


def _many(method, opts, workers, progress, warm_start, Mflat, qflat, B, sizes, off, limits, work,
          bufs, basics, out_i, out_f):
    """solve_lcp_many's batch from its arrays (those of ``_core.many_setup``: the offsets
    summed, the pivot caps, the work, the sizes as a list, the kernels' outputs), the warm
    starts as given."""
    beta, boff, ws = _bases(warm_start, B, sizes)
    qoff, mstart, buff = off[0], off[1, :-1], off[2]
    _run(_BATCH, (_layout.METHODS[method], Mflat, mstart, qflat, qoff, beta, boff),
         (limits, opts.pivot_tol, opts.tie_tol, opts.tol, bufs, buff, basics, out_i, out_f), B, workers,
         progress, "solve_lcp_many", work=work)
    picked = _core.many_unsettled(out_i, out_f)  # (None: the native fronts are off)
    if picked is None:
        code = out_i[:, 0]
        status = _layout.public_status(code)
        picked = (np.flatnonzero(code == _layout.NOT_FINITE).tolist(), np.flatnonzero(
            (out_f[:, 0] == 0.0) | ((status != 0) & (status != _RAY))).tolist())
    not_finite, unsettled = picked
    for b in not_finite:
        n, m, o = sizes[b], int(mstart[b]), int(qoff[b])
        _checked(b, Mflat[m : m + n * n].reshape(n, n), qflat[o : o + n])  # raises, naming the entry
    # Everything but a checked solution (and q >= 0), or a checked ray, goes through
    # solve_lcp's own logic now (the recomputation from the final basis, the downgrades),
    # from problem b's own copy of (M, q) in the flat arrays; the result builds the others
    # (lazily, from the shared buffers) only when its items are read.
    special = {}
    for b in unsettled:
        c, pivots, k, recoveries, _ = out_i[b].tolist()
        n, m, o, bo = sizes[b], int(mstart[b]), int(qoff[b]), int(buff[b])
        special[b] = _outcome(Mflat[m : m + n * n].reshape(n, n), qflat[o : o + n], opts, c, pivots,
                              basics[o : o + k], bool(out_f[b, 0]), float(out_f[b, 1]),
                              bufs[bo : int(buff[b + 1])], recoveries)
    return LCPManyResult(sizes, off, out_i, out_f, bufs, basics, ws, special)


#: The Python function; ``solve_lcp_many`` is the core's entry that wraps it
#: (src/python_front.cpp, ``lcp_many_entry``): a call ``solve_lcp_many(Ms, qs)`` or
#: ``solve_lcp_many(Ms, qs, warm_start=ws)`` of up to FEW plain problems (float64 arrays,
#: warm starts None or WarmStart) that ``_lcp._FRONT`` settles is made there whole, as
#: ``_few`` makes it, with no Python frame; every other call is the function's.
_solve_lcp_many = solve_lcp_many
solve_lcp_many = functools.update_wrapper(
    _core.lcp_many_entry(_solve_lcp_many, _lcp.__dict__, _lcp._FRONT, WarmStart, globals(),
                         LCPManyResult), _solve_lcp_many)

_RAY = int(Status.RAY_TERMINATION)
_isfinite = np.isfinite
#: The most problems that solve_lcp_many solves one by one with solve_lcp (its native front:
#: a microsecond or so each), when each is ready for the kernels, with the default options
#: and no progress report: the batch's own set-up (its arrays and offsets, some tens of
#: numpy calls) costs about 30 us, more than such a batch takes to solve; the answers are
#: the same (item b is solve_lcp's result, bit for bit, either way).
FEW = 4
_SEQ = (list, tuple)


def _plain(M, q):
    """Whether every (M_b, q_b) is a float64 ndarray pair, M_b square of q_b's size n_b >= 1
    (M and q sequences of the same length): the problems a few-problem call solves one by
    one."""
    for Mb, qb in zip(M, q):
        if not (type(Mb) is _ND and type(qb) is _ND and Mb.dtype is _F64 and qb.dtype is _F64
                and qb.ndim == 1 and Mb.shape == qb.shape * 2 and qb.shape[0]):
            return False
    return True


def _few(M, q, method, warm_start):
    """solve_lcp_many's result for the few problems (M, q) (lists or tuples of the same
    length, at most FEW) solved one by one by ``solve_lcp``, or None when they are not all
    float64 ndarrays, a square M_b of q_b's size n_b >= 1 (a problem the batch path would
    convert or refuse before solving any: it then does all, saying what is wrong), or the
    warm starts are not None, a WarmStartBatch or a sequence of WarmStart or None, all of
    the problems' sizes."""
    B = len(M)
    if len(q) != B or not _plain(M, q):
        return None
    if warm_start is None:
        ws = (None,) * B
    elif type(warm_start) is WarmStartBatch:
        if len(warm_start) != B or warm_start.n.tolist() != [len(qb) for qb in q]:
            return None
        ws = list(warm_start)
    elif type(warm_start) in _SEQ and len(warm_start) == B and all(
            w is None or (type(w) is WarmStart and w.n == len(qb)) for w, qb in zip(warm_start, q)):
        ws = warm_start
    else:
        return None
    items = []
    try:
        if method == "tableau":  # (solve_lcp's native entry takes (M, q, warm_start=) whole)
            for b in range(B):
                items.append(_solve_lcp(M[b], q[b], warm_start=ws[b]))
        else:
            for b in range(B):
                items.append(_solve_lcp(M[b], q[b], method=method, warm_start=ws[b]))
    except ValueError as exc:  # NaN or infinity: as _checked says it, naming the problem
        raise ValueError(f"problem {len(items)}: {exc}") from None
    return LCPManyResult._of(items)



def _cubes(n_b):
    """The sum of n^3 over the sizes n_b (an int64 array): a batch's estimated work."""
    return float(np.dot(n_b.astype(float) ** 2, n_b))


def _offsets(sizes, buffers=True):
    """int64 (3, B + 1): row 0, 1, 2 from index 1 on the problems' n, n^2 and output buffer
    lengths (``_layout.BUFFER``; left 0 without ``buffers``), to be summed into offsets."""
    off = np.zeros((3, len(sizes) + 1), dtype=np.int64)
    n_b = off[0, 1:]
    n_b[:] = sizes
    off[1, 1:] = n_b * n_b
    if buffers:
        off[2, 1:] = sum(length(n_b) for _, length in _layout.BUFFER)
    return off


def _packed(M, q, sizes, buffers=True):
    """Packed problems (see solve_lcp_many): ``(M, q, offsets)`` with M and q float64 1-D
    arrays ready for the kernels (the caller's own when they are already), or a
    ``ValueError``/``TypeError`` naming what is wrong (``buffers``: the LCP's output
    buffers' lengths in the offsets' row 2, as :func:`_offsets`).  Finiteness is left to
    the kernels (an error then names the problem and the entry)."""
    try:
        n_b = np.asarray(sizes)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"sizes must be a 1-D array of integers: {exc}") from None
    if n_b.ndim != 1 or (n_b.dtype.kind not in "iu" and n_b.size):
        raise TypeError(f"sizes must be a 1-D array of integers, got shape {n_b.shape} and dtype {n_b.dtype}")
    if n_b.size and n_b.min() < 0:
        raise ValueError(f"sizes must be >= 0, got {int(n_b.min())} at index {int(np.argmin(n_b))}")
    off = _offsets(n_b, buffers)
    flat = []
    for name, x, need in (("M", M, int(off[1].sum())), ("q", q, int(off[0].sum()))):
        a = _validate.float64_array(x, name)
        if a.ndim != 1 or a.size != need:
            raise ValueError(f"packed {name} must be 1-D with {need} numbers for these sizes "
                             f"(sum of n_b{'^2' if name == 'M' else ''}), got shape {a.shape}")
        flat.append(_validate.kernel_array(a))
    return flat[0], flat[1], off


def _flat(arrays):
    """The arrays (float64) end to end in one writable, aligned float64 vector: their bytes
    joined (a tenth of a microsecond per array; np.concatenate takes four), or
    np.concatenate when one is not C-contiguous."""
    try:
        flat = np.frombuffer(bytearray().join(arrays), np.float64)
    except (BufferError, ValueError, TypeError):
        return np.concatenate([a.ravel() for a in arrays])
    return flat if flat.flags.aligned else flat.copy()


_ND = np.ndarray
_F64 = np.dtype(np.float64)


def _ready(M, q) -> bool:
    """Whether (M, q) can go to the kernels as it is (float64, C-contiguous, square M and a
    vector q of its size): the kernels check finiteness themselves."""
    return (type(M) is np.ndarray and type(q) is np.ndarray and (M.dtype is _F64 or M.dtype == _F64)
            and (q.dtype is _F64 or q.dtype == _F64) and M.ndim == 2 and q.ndim == 1
            and M.shape[0] == M.shape[1] == q.shape[0] and M.flags.c_contiguous)


def _checked(b, M, q):
    """Problem b validated (``_validate.lcp``), its errors naming the problem."""
    try:
        M, q, _ = _validate.lcp(M, q)
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"problem {b}: {exc}") from None
    return M, q
