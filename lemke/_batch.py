"""solve_lcp_batch: many LCPs of one size, solved in parallel threads (the kernels release
the GIL), each exactly as :func:`lemke.solve_lcp` solves it."""
from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import _validate
from ._lcp import METHODS, _outcome
from ._options import as_options
from ._result import LCPBatchResult
from ._validate import real_array
from .kernels import cold

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


def solve_lcp_batch(M, q, *, method="tableau", options=None, workers=None) -> LCPBatchResult:
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
    _validate.method(method, METHODS)
    opts = as_options(options)
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
    M = np.ascontiguousarray(M)  # never a view the kernels could write through: they only read
    q = np.ascontiguousarray(q)
    if workers is None:
        workers = usable_cores()
    elif isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers must be a positive integer or None, got {workers!r}")

    bufs = np.empty((B, cold.buffer_length(n)))
    basics = np.empty((B, n), dtype=np.int64)
    out_i = np.empty((B, 4), dtype=np.int64)
    out_f = np.empty((B, 2))
    args = (cold.METHODS[method], M, q)
    tail = (opts.pivot_limit(n), opts.pivot_tol, opts.tie_tol, opts.tol, bufs, basics, out_i, out_f)
    chunks = min(B, 2 * workers) if workers > 1 else min(B, 1)
    bounds = np.linspace(0, B, chunks + 1).astype(int) if chunks else np.zeros(1, dtype=int)
    if chunks <= 1:
        for lo, hi in zip(bounds[:-1], bounds[1:]):
            cold.batch(*args, int(lo), int(hi), *tail)
    else:
        pool = _executor()
        futures = [pool.submit(cold.batch, *args, int(lo), int(hi), *tail)
                   for lo, hi in zip(bounds[:-1], bounds[1:])]
        for f in futures:
            f.result()

    f = cold.fields(n)
    z = np.ascontiguousarray(bufs[:, f["z"]])
    w = np.ascontiguousarray(bufs[:, f["w"]])
    status = np.where(out_i[:, 0] == cold.TRIVIAL, 0, out_i[:, 0])
    pivots = out_i[:, 1].copy()
    residual = out_f[:, 1].copy()
    # Everything but a checked solution (and q >= 0) goes through solve_lcp's own logic:
    # the recomputation from the final basis, the ray check, the downgrades.
    for b in np.flatnonzero((out_i[:, 0] != cold.TRIVIAL) & ((out_i[:, 0] != 0) | (out_f[:, 0] == 0.0))):
        code, piv, k, recoveries = (int(v) for v in out_i[b])
        res = _outcome(M[0 if M.shape[0] == 1 else b], q[b], opts, code, piv, basics[b, :k],
                       bool(out_f[b, 0]), float(out_f[b, 1]), bufs[b].copy(), recoveries)
        z[b], w[b], status[b], residual[b] = res.z, res.w, int(res.status), res.residual
    for a in (z, w, status, pivots, residual):
        a.setflags(write=False)
    return LCPBatchResult(z, w, status, pivots, residual)
