"""Random dense strictly convex QPs: lemke.solve_qp against quadprog, daqp, proxsuite (ProxQP),
piqp, Clarabel and OSQP through qpsolvers (their default settings), interleaved in one run.

Each problem (n = 10, 50, 200 by default): P = B B'/n + 1e-3 I, m = n inequalities and
n/5 equalities that a random point satisfies, and a box around that point (qpsolvers'
form, as in tests/test_qp.py). Every solver's answer is checked against quadprog's x and
objective; the report gives median times, the ratio to the fastest peer and the worst
deviation from quadprog. Peers missing from the environment are skipped with a note.

    python benchmarks/bench_qp.py [--sizes 10 50 200] [--problems 5] [--reps 7]
"""
from __future__ import annotations

import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from bench_lcp import mark_end, machine_info, publish, report_head, report_parser, time_interleaved  # noqa: E402

import lemke  # noqa: E402
from lemke.problems import random_convex_qp  # noqa: E402

PEERS = ("quadprog", "daqp", "proxqp", "piqp", "clarabel", "osqp")


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-qp.md", argv)
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 50, 200])
    parser.add_argument("--problems", type=int, default=5)
    parser.add_argument("--reps", type=int, default=7)
    args = parser.parse_args(argv)
    args.argv = argv
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    t_start = time.perf_counter()
    info = machine_info()
    try:
        import qpsolvers
        peers = [s for s in PEERS if s in qpsolvers.available_solvers]
    except ImportError:
        qpsolvers, peers = None, []
    missing = [s for s in PEERS if s not in peers]
    rng = np.random.default_rng(2026)
    order_rng = np.random.default_rng(2027)  # the call orders: the problems do not depend on the peers installed
    lemke.solve_qp(*random_convex_qp(5, rng))  # compile / load the kernels outside the timing
    rows = []
    for n in args.sizes:
        med = {s: [] for s in ["lemke", *peers]}
        dev = {s: 0.0 for s in med}
        pivots, wrong = [], {s: 0 for s in med}
        for _ in range(args.problems):
            prob = random_convex_qp(n, rng)
            calls = [lambda: lemke.solve_qp(*prob)]
            calls += [lambda s=s: qpsolvers.solve_qp(*prob, solver=s) for s in peers]
            times, results = time_interleaved(calls, args.reps, rng=order_rng)
            res = results[0][0]
            pivots.append(res.pivots)
            if not res.success:
                wrong["lemke"] += 1
            xs = {"lemke": res.x, **{s: results[j + 1][0] for j, s in enumerate(peers)}}
            ref = xs.get("quadprog", res.x)
            f = lambda x: 0.5 * x @ prob[0] @ x + prob[1] @ x  # noqa: E731
            for s, x in xs.items():
                med[s].append(statistics.median(times[["lemke", *peers].index(s)]))
                if x is None:
                    wrong[s] += 1
                    continue
                d = float(np.max(np.abs(x - ref)))
                dev[s] = max(dev[s], d)
                if abs(f(x) - f(ref)) > 1e-6 * max(1.0, abs(f(ref))):
                    wrong[s] += 1
        best_peer = min((statistics.median(med[s]) for s in peers), default=float("nan"))
        for s in med:
            t = statistics.median(med[s])
            rows.append((n, s, t, t / best_peer, dev[s], wrong[s], int(np.median(pivots)) if s == "lemke" else None))
        log(f"n = {n} done")
    mark_end(info)
    versions = ""
    if qpsolvers is not None:
        versions = f", qpsolvers {qpsolvers.__version__}"
    L = report_head("Dense convex QPs: lemke.solve_qp against qpsolvers' peers", "bench_qp.py", args,
                    time.perf_counter() - t_start, info, extra_versions=versions)
    if missing:
        L += [f"Skipped (not installed): {', '.join(missing)}.", ""]
    L += [f"{args.problems} problems per size, {args.reps} interleaved repeats each (random order); "
          "median over problems of each problem's median time. Deviation: max |x - x_quadprog|; "
          "wrong: objective off quadprog's by more than 1e-6 (relative) or no answer.", "",
          "| n | solver | median time | ratio to fastest peer | max deviation | wrong | lemke pivots |",
          "|---:|---|---:|---:|---:|---:|---:|"]
    for n, s, t, ratio, d, w, piv in rows:
        L.append(f"| {n} | {s} | {t * 1e3:.3f} ms | {ratio:.2f} | {d:.1e} | {w} | {'' if piv is None else piv} |")
    publish("\n".join(L) + "\n", args.out, log)


if __name__ == "__main__":
    main()
