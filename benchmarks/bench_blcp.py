#!/usr/bin/env python
"""Box LCPs: the bounded-variable kernel (``lemke.solve_blcp``) against the n-size LCP with
the same M (``lemke.solve_lcp(M, q)``) and against the 2n reformulation through
``solve_lcp`` (building M' = [[M, I], [-I, 0]], q' = [q + M lo; hi - lo] included, and
alone).

Usage::

    python benchmarks/bench_blcp.py [--quick] [--out benchmarks/RESULTS-blcp.md]

Problems: the monotone family of ``bench_lcp.py`` (M = A A' + (B - B'), q standard
normal), with two boxes: ``relay`` (-1 <= z <= 1) and ``contact`` (every other row a
normal row 0 <= z < inf, the rows between friction-like boxes -0.5 <= z <= 0.5).  All
calls are made in one process after compiling, interleaved in a random order drawn afresh
for every repeat; per problem the median over repeats, per size the median over problems
and the median of the per-problem ratios.  Every answer is checked here (plain numpy,
natural-map residual relative to the data's scale); the targets are box/LCP <= 1.2 and
box/2n <= 0.5.
"""
from __future__ import annotations

import argparse
import gc
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import bench_lcp as bl  # noqa: E402  (problems, machine description)

import lemke  # noqa: E402


def boxes(n, kind):
    if kind == "relay":
        return -np.ones(n), np.ones(n)
    lo = np.where(np.arange(n) % 2 == 0, 0.0, -0.5)
    hi = np.where(np.arange(n) % 2 == 0, np.inf, 0.5)
    return lo, hi


def reform(M, q, lo, hi):
    """The 2n reformulation, finite bounds: infinite upper bounds get no slack row."""
    n = q.size
    up = np.flatnonzero(np.isfinite(hi))
    k = up.size
    Mp = np.zeros((n + k, n + k))
    Mp[:n, :n] = M
    Mp[up, n + np.arange(k)] = 1.0
    Mp[n + np.arange(k), up] = -1.0
    qp = np.concatenate([q + M @ lo, (hi - lo)[up]])
    return Mp, qp


def natural_residual(M, q, lo, hi, z):
    w = M @ z + q
    scale = max(1.0, np.abs(q).max(), np.abs(M).max() * np.abs(z).max())
    return np.abs(z - np.clip(z - w, lo, hi)).max() / scale


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=str(HERE / "RESULTS-blcp.md"))
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    load0 = os.getloadavg()[0]
    sizes = {12: 12, 48: 8, 200: 3}
    if args.quick:
        sizes = {12: 3, 48: 2, 200: 1}
    rng = np.random.default_rng(7)
    # compile
    M, q = bl.make_problem(6, 0)
    lemke.solve_blcp(M, q, *boxes(6, "relay"))
    lemke.solve_lcp(M, q)
    rows = []
    for kind in ("relay", "contact"):
        for n, count in sizes.items():
            per = {"box": [], "lcp": [], "2n": [], "2n solve": []}
            fastest = {name: [] for name in per}
            pivots = {"box": [], "lcp": [], "2n": []}
            worst = 0.0
            wrong = 0
            for k in range(count):
                M, q = bl.make_problem(n, k)
                lo, hi = boxes(n, kind)
                Mp, qp = reform(M, q, lo, hi)
                calls = {
                    "box": lambda: lemke.solve_blcp(M, q, lo, hi),
                    "lcp": lambda: lemke.solve_lcp(M, q),
                    "2n": lambda: lemke.solve_lcp(*reform(M, q, lo, hi)),
                    "2n solve": lambda: lemke.solve_lcp(Mp, qp),
                }
                first = {name: f() for name, f in calls.items()}
                rb = first["box"]
                r2 = first["2n"]
                z2 = lo + r2.z[:n]
                for name, z, ok in (("box", rb.z, rb.success), ("2n", z2, r2.success)):
                    res = natural_residual(M, q, lo, hi, z)
                    worst = max(worst, res)
                    wrong += int(ok and res > 1e-8)
                    assert ok, (name, n, k)
                pivots["box"].append(rb.pivots)
                pivots["lcp"].append(first["lcp"].pivots)
                pivots["2n"].append(r2.pivots)
                budget = 0.2 if n < 200 else 0.8
                t0 = time.perf_counter()
                times = {name: [] for name in calls}
                names = list(calls)
                gc.disable()
                while time.perf_counter() - t0 < budget or len(times["box"]) < 5:
                    rng.shuffle(names)
                    for name in names:
                        s = time.perf_counter()
                        calls[name]()
                        times[name].append(time.perf_counter() - s)
                gc.enable()
                for name in calls:
                    per[name].append(statistics.median(times[name]))
                    fastest[name].append(min(times[name]))
            med = {name: statistics.median(v) for name, v in per.items()}
            ratio_lcp = statistics.median(b / l for b, l in zip(per["box"], per["lcp"]))
            ratio_2n = statistics.median(b / l for b, l in zip(per["box"], per["2n"]))
            ratio_2ns = statistics.median(b / l for b, l in zip(per["box"], per["2n solve"]))
            min_lcp = statistics.median(b / l for b, l in zip(fastest["box"], fastest["lcp"]))
            min_2n = statistics.median(b / l for b, l in zip(fastest["box"], fastest["2n"]))
            rows.append((kind, n, count, med, ratio_lcp, ratio_2n, ratio_2ns, min_lcp, min_2n,
                         {k: statistics.median(v) for k, v in pivots.items()}, worst, wrong))
            print(kind, n, {k: f"{v * 1e6:.1f}us" for k, v in med.items()},
                  f"box/lcp {ratio_lcp:.2f} box/2n {ratio_2n:.2f}", file=sys.stderr)
    info = bl.machine_info()
    load1 = os.getloadavg()[0]
    out = ["# Box LCPs: the bounded kernel vs the n-size LCP and the 2n reformulation", "",
           f"Generated by `python benchmarks/bench_blcp.py{' --quick' if args.quick else ''}` "
           f"in {time.perf_counter() - t_start:.0f} s.", "", "## Machine", "",
           f"- Date: {info['date']}", f"- CPU: {info['cpu']}; {info['cores']} logical cores "
           f"({info['usable_cores']} usable)", f"- {info['python']}; numpy {info['numpy']}, "
           f"numba {info['numba']}", f"- lemke {info['lemke']} from `{info['lemke_path']}`, commit {info['commit']}",
           f"- 1-minute load average: {load0:.2f} at the start, {load1:.2f} at the end "
           "(the machine is shared: other processes make timings noisier)", "",
           "## Method", "", __doc__.split("\n\n", 3)[3].strip().replace("\n", " "), "",
           "Columns: median times of `solve_blcp(M, q, lo, hi)` (*box*), `solve_lcp(M, q)` "
           "(*LCP*, the same M and q with z >= 0), `solve_lcp(*reformulate(M, q, lo, hi))` "
           "(*2n*, building M' included; an infinite upper bound gets no slack row) and "
           "`solve_lcp(Mp, qp)` alone (*2n solve*); ratios are medians of per-problem ratios.",
           " *min* ratios are the same from each call's fastest time (less sensitive to a shared "
           "machine's load).",
           "", "| box | n | problems | box | LCP | 2n | 2n solve | box/LCP | box/2n | box/2n solve "
           "| box/LCP min | box/2n min | pivots (box/LCP/2n) | max residual | wrong |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"]
    for kind, n, count, med, rl, r2, r2s, ml, m2, piv, worst, wrong in rows:
        out.append(f"| {kind} | {n} | {count} | {med['box'] * 1e6:.1f} µs | {med['lcp'] * 1e6:.1f} µs | "
                   f"{med['2n'] * 1e6:.1f} µs | {med['2n solve'] * 1e6:.1f} µs | {rl:.2f} | {r2:.2f} | "
                   f"{r2s:.2f} | {ml:.2f} | {m2:.2f} | {piv['box']:g}/{piv['lcp']:g}/{piv['2n']:g} | "
                   f"{worst:.1e} | {wrong} |")
    out += ["", "Targets: box/LCP <= 1.2, box/2n <= 0.5.", ""]
    for kind, n, count, med, rl, r2, r2s, ml, m2, piv, worst, wrong in rows:
        out.append(f"- {kind}, n = {n}: box/LCP {rl:.2f} (**{'met' if rl <= 1.2 else 'missed'}**), "
                   f"box/2n {r2:.2f} (**{'met' if r2 <= 0.5 else 'missed'}**)")
    out += ["", "## Engines", "",
            "pybullet and dartpy are not installed in this environment and were not "
            "installed for this run (not attempted; their box-LCP solvers are reached "
            "from Python only through a whole scene), so they were not timed.", ""]
    Path(args.out).write_text("\n".join(out))
    print("\n".join(out))


if __name__ == "__main__":
    main()
