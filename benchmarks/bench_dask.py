#!/usr/bin/env python
"""Where a Dask cluster starts to pay: solve_lcp_batch_dask against solve_lcp_batch on one
machine, by the work in each Dask task.

Usage::

    python benchmarks/bench_dask.py [--n 24 100] [--batch 2000] [--rounds 3]
                                    [--out benchmarks/RESULTS-dask.md]

Random monotone LCPs (``M_b = A A' + 0.1 I``, ``q ~ N(0, I)``, seeded), one per problem.
One machine: ``solve_lcp_batch`` with 1 thread and with every core.  Dask: a
``LocalCluster`` of one single-threaded worker process per core, ``chunk_size`` chosen so
that a task holds about 1 ms ... 1 s of solving (measured on one thread first).  Medians of
``--rounds`` interleaved rounds; every Dask result is compared bit for bit with the
one-machine result.  On one machine Dask can only add cost (the same cores, plus
scheduling, pickling and the copies between processes); the table shows that cost per
task, which a cluster's extra machines must repay.  Each problem here has its own M
(n x n doubles), so the chunks' data are shipped to the worker processes too.
"""
from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_lcp import machine_info, mark_end, report_head, report_parser  # noqa: E402

import lemke  # noqa: E402


def _problems(B, n, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(B, n, n))
    M = A @ A.transpose(0, 2, 1) / n + 0.1 * np.eye(n)
    return M, rng.normal(size=(B, n))


def _time(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-dask.md", argv)
    parser.add_argument("--n", type=int, nargs="*", default=[24, 100])
    parser.add_argument("--batch", type=int, default=2000)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    args.argv = argv
    import distributed

    info = machine_info()
    cores = lemke._batch.usable_cores()
    t_start = time.perf_counter()
    cluster = distributed.LocalCluster(n_workers=cores, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=50)
    client = distributed.Client(cluster)
    rows = []
    for n in args.n:
        M, Q = _problems(args.batch, n)
        lemke.solve_lcp_batch(M[:4], Q[:4])  # compiled (and loaded by every worker) first
        lemke.solve_lcp_batch_dask(M[:4], Q[:4], client=client)
        one, ref = _time(lambda: lemke.solve_lcp_batch(M, Q, workers=1))
        per_problem = one / args.batch
        sizes = sorted({max(1, min(args.batch, round(w / per_problem))) for w in (1e-3, 1e-2, 1e-1, 1.0)})
        times = {"1 thread": [], f"{cores} threads": []}
        times.update({c: [] for c in sizes})
        for _ in range(args.rounds):
            t, r = _time(lambda: lemke.solve_lcp_batch(M, Q, workers=1))
            times["1 thread"].append(t)
            t, r = _time(lambda: lemke.solve_lcp_batch(M, Q, workers=cores))
            times[f"{cores} threads"].append(t)
            for c in sizes:
                t, r = _time(lambda: lemke.solve_lcp_batch_dask(M, Q, chunk_size=c, client=client))
                assert r == ref, "Dask's answer differs from one machine's"
                times[c].append(t)
        med = {k: float(np.median(v)) for k, v in times.items()}
        local = med[f"{cores} threads"]
        for c in sizes:
            tasks = math.ceil(args.batch / c)
            rows.append((n, c, c * per_problem, tasks, med[c], med[c] / local,
                         max(0.0, med[c] - local) / tasks * cores))
            print(f"n={n} chunk={c} work/task={c * per_problem * 1e3:.1f} ms: dask {med[c]:.3f} s, "
                  f"local {local:.3f} s, ratio {med[c] / local:.2f}", flush=True)
        rows.append((n, None, per_problem, med["1 thread"], local))
    client.close()
    cluster.close()
    mark_end(info)
    L = report_head("A batch over Dask: where it starts to pay", "bench_dask.py", args,
                    time.perf_counter() - t_start, info)
    L += ["", f"## {args.batch} problems per batch, {cores} single-threaded Dask worker processes", "",
          "| n | one machine, 1 thread | one machine, all cores | problems per task | work per task | tasks | "
          "Dask | Dask / all cores | Dask's cost per task (core-ms) |",
          "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    by_n = {r[0]: r for r in rows if r[1] is None}
    for r in rows:
        if r[1] is None:
            continue
        n, c, work, tasks, td, ratio, over = r
        _, _, per, t1, tl = by_n[n]
        L.append(f"| {n} | {t1:.3f} s | {tl:.3f} s | {c} | {work * 1e3:.1f} ms | {tasks} | {td:.3f} s | "
                 f"{ratio:.2f} | {over * 1e3:.2f} |")
    L += ["", "Every Dask result was bit for bit the one-machine result.", ""]
    with open(args.out, "w") as f:
        f.write("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
