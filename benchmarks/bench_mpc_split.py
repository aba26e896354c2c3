#!/usr/bin/env python
"""Where a step of bench_mpc.py's MPC loop spends its time, warm and cold: ``solve_qp``
against its native front (``_core.qp_front``, src/python_front_qp.cpp: the kernel plus the
result's construction) called directly, so the difference is solve_qp's Python lines.

Usage::

    python benchmarks/bench_mpc_split.py [--passes 5] [--evict-mb 0]

For each step of ``mpc_problem.sequence()`` (from the previous step's ``warm_start``) the
four calls run in a random order, each timed alone, medians over passes and steps; with
``--evict-mb N`` an N MB array is written before each timed call (the caches emptied of the
solver's data, as in bench_mpc.py, where daqp's calls run between lemke's).  Also reported:
reading ``result.warm_start`` (the deferred fields built on first read, which a real MPC
loop pays each step and bench_mpc.py does not time).  Prints a table; writes nothing.
"""
from __future__ import annotations

import argparse
import os
import random
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mpc_problem  # noqa: E402

import lemke  # noqa: E402
from lemke import _core  # noqa: E402

NAMES = ("solve_qp warm", "front warm", "solve_qp cold", "front cold", "read warm_start")


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--evict-mb", type=float, default=0.0)
    args = ap.parse_args(argv)
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=100, seed=0)
    junk = np.zeros(int(args.evict_mb * (1 << 17))) if args.evict_mb > 0 else None
    T = {k: [] for k in NAMES}
    rng = random.Random(0)
    pf = time.perf_counter
    load0 = os.getloadavg()[0]
    for _ in range(args.passes):
        ws = None
        for q, b in steps:
            r0 = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
            if ws is not None:
                order = list(NAMES[:4])
                rng.shuffle(order)
                for k in order:
                    if junk is not None:
                        junk += 1.0
                    if k == "solve_qp warm":
                        t0 = pf()
                        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
                        dt = pf() - t0
                        t0 = pf()
                        r.warm_start
                        T["read warm_start"].append((pf() - t0) * 1e6)
                    elif k == "front warm":
                        t0 = pf()
                        r = _core.qp_front(P, q, G, h, A, b, lb, ub, ws.n, ws._beta, None)
                        dt = pf() - t0
                    elif k == "solve_qp cold":
                        t0 = pf()
                        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
                        dt = pf() - t0
                    else:
                        t0 = pf()
                        r = _core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, None)
                        dt = pf() - t0
                    assert r.status == lemke.Status.SOLVED, (k, r)
                    T[k].append(dt * 1e6)
            ws = r0.warm_start
    med = {k: float(np.median(T[k])) for k in NAMES}
    print(f"evict {args.evict_mb} MB, {args.passes} passes, load {load0:.2f} -> "
          f"{os.getloadavg()[0]:.2f}; medians in us")
    for k in NAMES:
        print(f"| {k} | {med[k]:.2f} |")
    print(f"- warm / cold: solve_qp {med['solve_qp warm'] / med['solve_qp cold']:.3f}, "
          f"front {med['front warm'] / med['front cold']:.3f}")
    print(f"- solve_qp's Python lines (solve_qp - front): warm "
          f"{med['solve_qp warm'] - med['front warm']:.2f}, cold "
          f"{med['solve_qp cold'] - med['front cold']:.2f}")


if __name__ == "__main__":
    main()
