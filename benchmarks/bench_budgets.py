#!/usr/bin/env python
"""How well Options(time_limit=...) is kept, and how fast Ctrl-C stops a solve (issue 33).

Each path runs a problem far longer than its budget (Murty's problem, n = 26: 2^26 pivots;
a 60 x 60 game from lemke_paths' search; a random convex QP of 200 variables) with
``time_limit`` = 5 ms, repeated; the overrun is the call's wall time minus the budget
(Python's part included: arguments, the result).  Then a 10 s budget once per LCP method.
Then SIGINT sent to a child process one second into a solve of Murty's problem at n = 28:
the time from the signal to the child's KeyboardInterrupt handler.

    python benchmarks/bench_budgets.py [--repeats 30] [--long 10] [--out benchmarks/RESULTS-budgets.md]
"""
from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import textwrap
import time

import numpy as np

import lemke
from lemke import problems

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
from helpers import interrupt_child  # noqa: E402

ENDLESS = {"max_pivots": 10**12}


def paths():
    murty = problems.murty(26)
    n = 26
    rng = np.random.default_rng(0)
    A, B = rng.random((60, 60)), rng.random((60, 60))
    qp = problems.random_convex_qp(200, np.random.default_rng(1))
    return {
        "solve_lcp tableau (Murty 26)": lambda o: lemke.solve_lcp(murty.M, murty.q, options=o),
        "solve_lcp unrevised (Murty 26)": lambda o: lemke.solve_lcp(murty.M, murty.q, method="unrevised", options=o),
        "solve_blcp (Murty 26, z >= 0)": lambda o: lemke.solve_blcp(murty.M, murty.q, np.zeros(n), np.full(n, np.inf), options=o),
        "solve_lcp_many (4 x Murty 26, 2 workers)": lambda o: lemke.solve_lcp_many([murty.M] * 4, [murty.q] * 4, workers=2, options=o),
        "lemke_paths (60 x 60 game)": lambda o: lemke.lemke_paths(A, B, options=o),
        "solve_qp (n = 200, 200 rows; solves in ~20 ms)": lambda o: lemke.solve_qp(*qp, method="unrevised", options=o),
    }


def overruns(f, budget, repeats):
    out = []
    for _ in range(repeats):
        t = time.perf_counter()
        f({**ENDLESS, "time_limit": budget})
        out.append(time.perf_counter() - t - budget)
    return out


CHILD = textwrap.dedent("""
    import sys, time
    import lemke
    from lemke import problems
    p = problems.murty(28)
    print("ready", flush=True)
    try:
        lemke.solve_lcp(p.M, p.q, method=sys.argv[1], options={"max_pivots": 10**12})
    except KeyboardInterrupt:
        print(f"interrupted {time.time():.6f}", flush=True)
        sys.exit(130)
""")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=30)
    ap.add_argument("--long", type=float, default=10.0)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = ["# Time limits and Ctrl-C (issue 33)", "",
             f"- machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
             f"load before: {os.getloadavg()[0]:.2f}",
             f"- Python {platform.python_version()}, numpy {np.__version__}, lemke {lemke.__version__}",
             f"- command: `python benchmarks/bench_budgets.py --repeats {args.repeats} --long {args.long}`", "",
             f"## 5 ms budget, {args.repeats} calls each: overrun = wall time - 5 ms", "",
             "| path | median overrun (ms) | max overrun (ms) | status |", "|---|---|---|---|"]
    for name, f in paths().items():
        f({"time_limit": 0.001})  # warm: imports, first allocations
        st = f({**ENDLESS, "time_limit": 0.005})
        status = getattr(st, "status", None)
        status = status.name if hasattr(status, "name") else (
            "TIME_LIMIT x4" if hasattr(st, "offsets") else f"complete={getattr(st, 'complete', '?')}")
        o = overruns(f, 0.005, args.repeats)
        lines.append(f"| {name} | {statistics.median(o) * 1e3:.3f} | {max(o) * 1e3:.3f} | {status} |")
        print(lines[-1], flush=True)
    lines += ["", f"## {args.long:g} s budget, once each", "", "| path | overrun (ms) | overrun (% of budget) |", "|---|---|---|"]
    for name in ("solve_lcp tableau (Murty 26)", "solve_lcp unrevised (Murty 26)"):
        (o,) = overruns(paths()[name], args.long, 1)
        lines.append(f"| {name} | {o * 1e3:.3f} | {100 * o / args.long:.4f} % |")
        print(lines[-1], flush=True)
    lines += ["", "## SIGINT one second into Murty 28 (child process): signal to KeyboardInterrupt", "",
              "| method | latency (ms) |", "|---|---|"]
    for method in ("tableau", "unrevised"):
        got = []
        for _ in range(5):
            line, rc, sent, _ = interrupt_child(CHILD, method)
            got.append(float(line.split()[1]) - sent)
        lines.append(f"| {method} | median {statistics.median(got) * 1e3:.2f}, max {max(got) * 1e3:.2f} (5 runs) |")
        print(lines[-1], flush=True)
    lines += ["", f"Load after: {os.getloadavg()[0]:.2f}."]
    text = "\n".join(lines) + "\n"
    if args.out:
        with open(args.out + ".tmp", "w") as fh:
            fh.write(text)
        os.replace(args.out + ".tmp", args.out)
    else:
        print(text)


if __name__ == "__main__":
    main()
