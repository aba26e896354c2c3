"""solve_lcp_batch_dask: a batch of LCPs of one size split over a Dask cluster (the optional
extra ``lemke[dask]``).

Each Dask task is one chunk of consecutive problems solved by ``solve_lcp_batch(...,
workers=1)`` on a worker; the chunks' arrays are put back together in order.  A problem is
solved by the same kernel, with the same options and warm start, whichever chunk, worker,
process or machine it lands on, so the result is bit for bit that of one machine.

Where it pays: a task costs Dask a few milliseconds (scheduling, pickling the chunk and its
result, the network); ``benchmarks/bench_dask.py`` measures it.  A chunk needs about a
second of solving before the cluster's extra cores repay that, so small batches belong to
:func:`lemke.solve_lcp_batch` on one machine.
"""
from __future__ import annotations

import math

import numpy as np

from ._batch import _bases, batch_arrays, solve_lcp_batch
from ._lcp import METHODS
from ._options import as_options
from ._result import LCPBatchResult
from . import _validate


def _chunk(M, q, method, options, warm_start):
    """One Dask task: a chunk solved on one thread of its worker."""
    return solve_lcp_batch(M, q, method=method, options=options, warm_start=warm_start, workers=1)


def solve_lcp_batch_dask(M, q, *, method="tableau", options=None, warm_start=None, chunk_size=None,
                         client=None) -> LCPBatchResult:
    r"""Solve B linear complementarity problems of one size over a Dask cluster.

    Takes what :func:`lemke.solve_lcp_batch` takes and returns the same
    :class:`LCPBatchResult`, bit for bit: problem b is solved exactly as
    ``solve_lcp(M_b, q_b, method=method, options=options, warm_start=warm_start[b])`` solves
    it, whatever the chunking and the cluster.

    Parameters
    ----------
    M : (B, n, n) array_like, or (n, n) shared by all problems (sent to every worker once)
    q : (B, n) array_like
    method : {"tableau", "unrevised"}
    options : Options or dict, optional
    warm_start : sequence of WarmStart or None, optional
        One per problem (None: cold).
    chunk_size : int, optional
        Problems per Dask task (default: enough chunks for four per worker thread).  Each
        task should hold about a second of work or more: below that, Dask's cost per task
        (milliseconds) outweighs what the extra cores give.
    client : distributed.Client, optional
        The cluster (default: the current client, ``distributed.get_client()``).

    Examples
    --------
    >>> from distributed import Client, LocalCluster                      # doctest: +SKIP
    >>> client = Client(LocalCluster(n_workers=4, threads_per_worker=1))  # doctest: +SKIP
    >>> r = lemke.solve_lcp_batch_dask(M, Q, client=client)               # doctest: +SKIP
    """
    try:
        import distributed
    except ImportError:
        raise ImportError("solve_lcp_batch_dask needs Dask's distributed scheduler: "
                          "pip install 'lemke[dask]'") from None
    _validate.method(method, METHODS)
    opts = as_options(options)
    M, q = batch_arrays(M, q)
    B, n = q.shape
    _bases(warm_start, B, [n] * B)  # bad warm starts raise here, naming the problem
    ws = None if warm_start is None else list(warm_start)
    chunk_size = _validate.positive_int_or_none(chunk_size, "chunk_size")
    if client is None:
        try:
            client = distributed.get_client()
        except ValueError:
            raise ValueError("no Dask client: pass client= or create a distributed.Client first") from None
    shared = M.shape[0] == 1
    if B == 0:
        return solve_lcp_batch(M[0] if shared else M, q, method=method, options=opts, workers=1)
    if chunk_size is None:
        threads = max(1, sum(client.nthreads().values()))
        chunk_size = max(1, math.ceil(B / (4 * threads)))
    M_all = client.scatter(M[0], broadcast=True) if shared else None
    bounds = [(lo, min(B, lo + chunk_size)) for lo in range(0, B, chunk_size)]
    # The chunks' data go to the workers as data (scatter), not inside the task graph.
    qs = client.scatter([q[lo:hi] for lo, hi in bounds])
    Ms = [M_all] * len(bounds) if shared else client.scatter([M[lo:hi] for lo, hi in bounds])
    futures = [client.submit(_chunk, Mc, qc, method, opts, None if ws is None else ws[lo:hi], pure=False)
               for (lo, hi), Mc, qc in zip(bounds, Ms, qs)]
    parts = client.gather(futures)
    arrays = [np.concatenate([getattr(p, f) for p in parts]) for f in ("z", "w", "status", "pivots", "residual")]
    for a in arrays:
        a.setflags(write=False)
    return LCPBatchResult(*arrays)
