#!/usr/bin/env python
"""The fused QP kernel alone on bench_mpc.py's MPC steps, warm and cold, with or without the
caches emptied before each call: ``_core.qp_solve_warm`` from the previous step's basis and
``_core.qp_solve`` (the factor cache hit either way: the same P, A, G), each call timed alone,
the median of ``--reps`` per step, then the median over the 99 steps.

Usage::

    python benchmarks/bench_mpc_kernel.py [--evict-mb 4] [--reps 5] [--only warm|cold]

With ``--evict-mb N`` an N MB array is written before each timed call (as daqp's calls do
between lemke's in bench_mpc.py). Prints one line; writes nothing. Compare two builds in
alternated processes (the machine's speed varies between processes).
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mpc_problem  # noqa: E402

import lemke  # noqa: E402
from lemke import _core, _qp  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--evict-mb", type=float, default=0.0)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--only", choices=("warm", "cold"), default=None)
    args = ap.parse_args(argv)
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=100, seed=0)
    n, p, m = P.shape[0], A.shape[0], G.shape[0]
    out = np.empty(_qp._layout(n, p, m)[-1])
    junk = np.zeros(int(args.evict_mb * (1 << 17))) if args.evict_mb > 0 else None
    starts, ws = [], None
    for q, b in steps:
        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
        if ws is not None:
            starts.append((q, b, np.array(ws.z_basic, dtype=np.int64), ws.n))
        ws = r.warm_start
    args_ = (0, -1, 1e-11, 1e-11, 1e-9, out)
    tw, tc = [], []
    pf = time.perf_counter
    for q, b, wv, wn in starts:
        a, c = [], []
        for _ in range(args.reps):
            if args.only != "cold":
                if junk is not None:
                    junk += 1.0
                t0 = pf()
                _core.qp_solve_warm(P, q, G, h, A, b, lb, ub, *args_, wv, wn)
                a.append(pf() - t0)
            if args.only != "warm":
                if junk is not None:
                    junk += 1.0
                t0 = pf()
                _core.qp_solve(P, q, G, h, A, b, lb, ub, *args_)
                c.append(pf() - t0)
        if a:
            tw.append(np.median(a))
        if c:
            tc.append(np.median(c))
    line = f"evict {args.evict_mb} MB, load {os.getloadavg()[0]:.2f}:"
    if tw:
        line += f" kernel warm {np.median(tw) * 1e6:.2f} us"
    if tc:
        line += f" cold {np.median(tc) * 1e6:.2f} us"
    if tw and tc:
        line += f" warm / cold (median per step) {np.median(np.array(tw) / np.array(tc)):.3f}"
    print(line)


if __name__ == "__main__":
    main()
