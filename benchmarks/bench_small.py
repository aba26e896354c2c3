#!/usr/bin/env python
"""Small problems at the hardware's pace: cold and warm solves at n <= 48 against quantecon,
and islands of a contact scene in one call.

Usage::

    python benchmarks/bench_small.py [--sizes 3 12 24 48] [--reps 3000] [--islands 400]
                                     [--out benchmarks/RESULTS-small.md]

Part 1, one problem at a time (random monotone LCPs ``M = A A' + 0.1 I``, ``q ~ N(0, I)``,
seeded): lemke cold (tableau), lemke warm with the basis unchanged (q moved by 1e-9: the old
basis still solves it, 0 pivots), lemke warm from a wrong basis (q moved by 0.3: a restart),
quantecon's ``lcp_lemke``.  The four calls run interleaved in a random order for every repeat;
the table gives medians in microseconds and ratios to quantecon.

Part 2, islands: ``--islands`` contact-like LCPs of 1..12 rows (``lemke.problems.contact_like``,
rank-deficient with repeated rows) and the next step of each (q moved by 1e-3), solved warm
from the first step's bases: a Python loop of ``solve_lcp``, one ``solve_lcp_many`` call
with 1 and 2 workers, and a loop of quantecon (cold; it has no warm start).  Medians of
``--rounds`` interleaved rounds.  Every answer is checked (``w = M z + q`` recomputed).
"""
from __future__ import annotations

import argparse
import gc
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_lcp import machine_info, mark_end, report_head  # noqa: E402

import lemke  # noqa: E402
from lemke import problems  # noqa: E402

try:
    from quantecon.optimize import lcp_lemke
except ImportError:  # pragma: no cover
    lcp_lemke = None


def _ok(M, q, z, tol=1e-8):
    w = M @ z + q
    s = tol * max(1.0, np.abs(M).max(initial=0) * np.abs(z).max(initial=0), np.abs(q).max(initial=0))
    return bool(np.all(z >= -s) and np.all(w >= -s) and np.all(np.abs(np.minimum(z, w)) <= s))


def _interleaved(calls, reps, rng):
    """``{name: [seconds, ...]}``: every call timed ``reps`` times, in a fresh random order
    each round, with the garbage collector off."""
    times = {k: [] for k in calls}
    names = list(calls)
    gc.disable()
    try:
        for _ in range(reps):
            rng.shuffle(names)
            for k in names:
                t = time.perf_counter()
                calls[k]()
                times[k].append(time.perf_counter() - t)
    finally:
        gc.enable()
    return times


def part1(sizes, reps, rng):
    rows = []
    for n in sizes:
        r = np.random.default_rng([14, n])
        A = r.standard_normal((n, n))
        M, q = A @ A.T + 0.1 * np.eye(n), r.standard_normal(n)
        base = lemke.solve_lcp(M, q)
        q_same = q + 1e-9 * r.standard_normal(n)
        q_far = q + 0.3 * r.standard_normal(n)
        ws = base.warm_start
        calls = {
            "cold": lambda: lemke.solve_lcp(M, q_same),
            "warm, basis unchanged": lambda: lemke.solve_lcp(M, q_same, warm_start=ws),
            "warm, wrong basis": lambda: lemke.solve_lcp(M, q_far, warm_start=ws),
            "cold, far": lambda: lemke.solve_lcp(M, q_far),
        }
        if lcp_lemke is not None:
            calls["quantecon"] = lambda: lcp_lemke(M, q_same)
        for f in calls.values():
            f()
        times = _interleaved(calls, reps, rng)
        checks = [_ok(M, q_same, calls["cold"]().z), _ok(M, q_same, calls["warm, basis unchanged"]().z),
                  _ok(M, q_far, calls["warm, wrong basis"]().z), _ok(M, q_far, calls["cold, far"]().z)]
        pivots = tuple(calls[k]().pivots for k in ("cold", "warm, basis unchanged", "warm, wrong basis", "cold, far"))
        rows.append((n, {k: np.median(v) * 1e6 for k, v in times.items()}, all(checks), pivots))
    return rows


def part2(count, rounds, rng):
    r = np.random.default_rng(15)
    Ms, qs, qs2 = [], [], []
    for _ in range(count):
        n = int(r.integers(1, 13))
        M, q = problems.contact_like(n, r) if n >= 2 else (np.array([[2.0]]), np.array([-1.0]))
        Ms.append(np.ascontiguousarray(M))
        qs.append(q)
        qs2.append(q + 1e-3 * r.standard_normal(n))
    ws = [lemke.solve_lcp(M, q).warm_start for M, q in zip(Ms, qs)]
    calls = {
        "solve_lcp loop, warm": lambda: [lemke.solve_lcp(M, q, warm_start=w) for M, q, w in zip(Ms, qs2, ws)],
        "solve_lcp_many, warm, 1 worker": lambda: lemke.solve_lcp_many(Ms, qs2, warm_start=ws, workers=1),
        "solve_lcp_many, warm, 2 workers": lambda: lemke.solve_lcp_many(Ms, qs2, warm_start=ws, workers=2),
        "solve_lcp loop, cold": lambda: [lemke.solve_lcp(M, q) for M, q in zip(Ms, qs2)],
    }
    if lcp_lemke is not None:
        calls["quantecon loop, cold"] = lambda: [lcp_lemke(M, q) for M, q in zip(Ms, qs2)]
    results = {k: f() for k, f in calls.items()}
    solved = {}
    for k, res in results.items():
        zs = [x.z for x in res]
        solved[k] = sum(_ok(M, q, z) for M, q, z in zip(Ms, qs2, zs))
    times = _interleaved(calls, rounds, rng)
    return {k: np.median(v) * 1e3 for k, v in times.items()}, solved


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--sizes", type=int, nargs="*", default=[3, 12, 24, 48])
    p.add_argument("--reps", type=int, default=3000)
    p.add_argument("--islands", type=int, default=400)
    p.add_argument("--rounds", type=int, default=40)
    p.add_argument("--out", default=None)
    p.add_argument("--note", default="")
    args = p.parse_args(argv)
    args.argv = sys.argv[1:] if argv is None else argv
    rng = np.random.default_rng(0)
    info = machine_info()
    t0 = time.time()
    rows = part1(args.sizes, args.reps, rng)
    islands, solved = part2(args.islands, args.rounds, rng)
    mark_end(info)
    L = report_head("Small problems: cold and warm solves vs quantecon, islands in one call",
                    "bench_small.py", args, time.time() - t0, info)
    L += ["", "## 1. One problem at a time (medians, microseconds)", "",
          f"{args.reps} interleaved repeats per size; ratios to quantecon's `lcp_lemke`. *warm, wrong basis* "
          "solves q moved by 0.3 (normal) from the basis of the unmoved q, and *wrong/cold* divides it by a "
          "cold solve of that same moved q (*cold, far*). Pivots: cold / warm unchanged / warm wrong basis / cold, far.", "",
          "| n | cold | warm, basis unchanged | warm, wrong basis | cold, far | quantecon | cold/qe | warm unchanged/qe | warm unchanged/cold | wrong/cold | pivots | all answers checked |",
          "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|"]
    for n, t, ok, piv in rows:
        qe = t.get("quantecon", float("nan"))
        L.append(f"| {n} | {t['cold']:.1f} | {t['warm, basis unchanged']:.1f} | {t['warm, wrong basis']:.1f} | "
                 f"{t['cold, far']:.1f} | {qe:.1f} | {t['cold'] / qe:.2f} | {t['warm, basis unchanged'] / qe:.2f} | "
                 f"{t['warm, basis unchanged'] / t['cold']:.2f} | {t['warm, wrong basis'] / t['cold, far']:.2f} | "
                 f"{'/'.join(map(str, piv))} | {'yes' if ok else 'NO'} |")
    L += ["", f"## 2. {args.islands} islands of 1..12 rows, the next step warm (medians of {args.rounds} rounds, ms)", "",
          "| how | time | per island | solved and checked |", "|---|---:|---:|---:|"]
    for k, t in islands.items():
        L.append(f"| {k} | {t:.2f} ms | {t / args.islands * 1e3:.1f} us | {solved[k]}/{args.islands} |")
    text = "\n".join(L) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
