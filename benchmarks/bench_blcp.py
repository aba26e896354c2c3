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


def contact_islands(seed, k):
    """k 2-D contacts (a normal row and its friction row, findex), the Delassus matrix
    M = J J' + 1e-6 I of a random Jacobian (tests/test_blcp.py's ``contacts``)."""
    rng = np.random.default_rng(seed)
    J = rng.standard_normal((2 * k, 3 * max(1, k // 2)))
    M = J @ J.T + 1e-6 * np.eye(2 * k)
    q = rng.standard_normal(2 * k)
    mu = rng.uniform(0.0, 1.0, k)
    lo, hi = np.zeros(2 * k), np.full(2 * k, np.inf)
    findex = np.full(2 * k, -1, dtype=np.int64)
    findex[1::2] = np.arange(0, 2 * k, 2)
    lo[1::2], hi[1::2] = -mu, mu
    return M, q, lo, hi, findex


def interleaved(calls, budget, least=5):
    """Median and fastest time of each call, in a random order drawn afresh every round."""
    rng = np.random.default_rng(0)
    times = {name: [] for name in calls}
    names = list(calls)
    t0 = time.perf_counter()
    gc.disable()
    try:
        while time.perf_counter() - t0 < budget or len(times[names[0]]) < least:
            rng.shuffle(names)
            for name in names:
                s = time.perf_counter()
                calls[name]()
                times[name].append(time.perf_counter() - s)
    finally:
        gc.enable()
    return ({k: statistics.median(v) for k, v in times.items()},
            {k: min(v) for k, v in times.items()})


def warm_part(quick):
    """Part (a), issue 32: a 0-pivot warm re-solve (the last answer's own basis, the same
    problem) against the same call cold, box LCPs (the ``contact`` boxes, no friction
    index) and contact islands with a friction index, n = 6 to 200; target warm <= 0.5x
    cold at every n."""
    rows = []
    for n in (6, 12, 24, 50, 100, 200):
        count = (2 if n >= 100 else 4) if quick else (4 if n >= 100 else 10)
        for family in ("box", "friction"):
            per_c, per_w, rat, rat_min, piv = [], [], [], [], []
            k = 0
            while len(rat) < count and k < 4 * count:
                if family == "box":
                    M, q = bl.make_problem(n, k)
                    lo, hi = boxes(n, "contact")
                    fi = None
                else:
                    M, q, lo, hi, fi = contact_islands(n * 1000 + k, n // 2)
                k += 1
                r = lemke.solve_blcp(M, q, lo, hi, findex=fi)
                ws = r.warm_start
                again = lemke.solve_blcp(M, q, lo, hi, findex=fi, warm_start=ws)
                if not (r.success and again.success and again.pivots == 0):
                    continue  # (a degenerate final basis whose own point fails the check)
                med, fast = interleaved({
                    "cold": lambda: lemke.solve_blcp(M, q, lo, hi, findex=fi),
                    "warm": lambda: lemke.solve_blcp(M, q, lo, hi, findex=fi, warm_start=ws)},
                    0.05 if quick else (0.15 if n < 100 else 0.4))
                per_c.append(med["cold"])
                per_w.append(med["warm"])
                rat.append(med["warm"] / med["cold"])
                rat_min.append(fast["warm"] / fast["cold"])
                piv.append(r.pivots)
            rows.append((family, n, len(rat), statistics.median(per_c), statistics.median(per_w),
                         statistics.median(rat), statistics.median(rat_min), statistics.median(piv)))
            print("warm", rows[-1], file=sys.stderr)
    out = ["## Warm re-solves with 0 pivots (issue 32)", "", warm_part.__doc__.split("\n\n")[0].replace("\n    ", " "),
           "Problems: *box*, the monotone family above with the ``contact`` boxes (no "
           "friction index); *friction*, n/2 2-D contacts (a normal row, a friction row with "
           "findex, M = J J' + 1e-6 I).  Per problem the median of interleaved calls; a problem "
           "whose own final basis needs a pivot again (degenerate) is skipped.", "",
           "| family | n | problems | cold | warm (0 pivots) | warm/cold | warm/cold min | cold pivots |",
           "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for family, n, cnt, c, w, r, rm, p in rows:
        out.append(f"| {family} | {n} | {cnt} | {c * 1e6:.1f} µs | {w * 1e6:.1f} µs | {r:.2f} | {rm:.2f} | {p:g} |")
    out += ["", "Target warm/cold <= 0.5: " + ", ".join(
        f"{family} n = {n} {r:.2f} (**{'met' if r <= 0.5 else 'missed'}**)" for family, n, _, _, _, r, _, _ in rows), ""]
    return out


def islands_part(quick, islands):
    """Part (b), issue 32: the islands of a scene, box LCPs with friction (1-6 contacts, n =
    2-12), in one ``solve_blcp_many`` call, against plain LCP islands of the same M and q
    (z >= 0) in one ``solve_lcp_many`` call; both packed, the next step warm from the
    last step's batch of bases (q moved by 1e-3 relative), the flat z and warm_start read;
    target box/LCP <= 1.5 per island."""
    rng = np.random.default_rng(3)
    ks = rng.integers(1, 7, size=islands)
    probs = [contact_islands(5000 + b, int(k)) for b, k in enumerate(ks)]
    sizes = np.array([p[1].size for p in probs])
    Mp = np.concatenate([p[0].ravel() for p in probs])
    q0 = np.concatenate([p[1] for p in probs])
    q1 = q0 + 1e-3 * np.abs(q0) * rng.standard_normal(q0.size)
    lo = np.concatenate([p[2] for p in probs])
    hi = np.concatenate([p[3] for p in probs])
    fi = np.concatenate([p[4] for p in probs])
    lo0, hi0 = np.zeros(q0.size), np.full(q0.size, np.inf)
    box0 = lemke.solve_blcp_many(Mp, q0, lo, hi, findex=fi, sizes=sizes)
    lcp0 = lemke.solve_lcp_many(Mp, q0, sizes=sizes)
    bw, lw = box0.warm_start, lcp0.warm_start
    res = {}

    def box(workers, warm):
        def f():
            r = lemke.solve_blcp_many(Mp, q1, lo, hi, findex=fi, sizes=sizes,
                                      warm_start=bw if warm else None, workers=workers)
            r.z, r.warm_start
            res[("box", workers, warm)] = r
        return f

    def lcp(workers, warm):
        def f():
            r = lemke.solve_lcp_many(Mp, q1, sizes=sizes, warm_start=lw if warm else None,
                                     workers=workers)
            r.z, r.warm_start
            res[("lcp", workers, warm)] = r
        return f

    def plain_box(workers):  # box islands without a friction index (lo = 0, hi = inf)
        def f():
            r = lemke.solve_blcp_many(Mp, q1, lo0, hi0, sizes=sizes, workers=workers)
            r.z, r.warm_start
        return f

    calls = {}
    for workers in (1, 2):
        for warm in (True, False):
            calls[("box", workers, warm)] = box(workers, warm)
            calls[("lcp", workers, warm)] = lcp(workers, warm)
        calls[("box, no findex, cold", workers, False)] = plain_box(workers)
    med, fast = interleaved(calls, 1.0 if quick else 6.0)
    out = ["## 3. Islands of box LCPs with friction vs plain LCP islands (issue 32)", "",
           islands_part.__doc__.split("\n\n")[0].replace("\n    ", " "), "",
           f"{islands} islands, {int(sizes.sum())} rows; medians of interleaved rounds.", "",
           "| how | workers | time | per island | per island (min) | solved | pivots |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for key in calls:
        kind, workers, warm = key
        r = res.get(key)
        label = {"box": "solve_blcp_many, friction", "lcp": "solve_lcp_many"}.get(
            kind, "solve_blcp_many, no findex (lo = 0, hi = inf)") + (", warm" if warm else ", cold")
        out.append(f"| {label} | {workers} | {med[key] * 1e3:.2f} ms | {med[key] / islands * 1e6:.2f} us | "
                   f"{fast[key] / islands * 1e6:.2f} us | "
                   f"{'' if r is None else int(r.success.sum())} | {'' if r is None else int(r.pivots.sum())} |")
    out.append("")
    for workers in (1, 2):
        for warm in (True, False):
            ratio = med[("box", workers, warm)] / med[("lcp", workers, warm)]
            out.append(f"- box/LCP per island, {'warm' if warm else 'cold'}, {workers} worker(s): "
                       f"{ratio:.2f} (**{'met' if ratio <= 1.5 else 'missed'}**, target 1.5)")
    out.append("")
    return out


def put_section(path, title, lines):
    """Replace the section ``title`` (a ``## `` heading up to the next one) of a results file,
    or append it."""
    path = Path(path)
    text = path.read_text() if path.exists() else ""
    block = "\n".join(lines).rstrip() + "\n"
    i = text.find(title)
    if i < 0:
        path.write_text(text.rstrip() + "\n\n" + block)
        return
    j = text.find("\n## ", i + len(title))
    path.write_text(text[:i] + block + ("" if j < 0 else text[j:]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=str(HERE / "RESULTS-blcp.md"))
    ap.add_argument("--part", choices=("lcp", "warm", "islands"), default="lcp",
                    help="lcp: against the LCP and the 2n reformulation (the default); warm: "
                         "0-pivot warm re-solves (a section of --out); islands: solve_blcp_many "
                         "against solve_lcp_many (a section of --islands-out)")
    ap.add_argument("--islands", type=int, default=3000)
    ap.add_argument("--islands-out", default=str(HERE / "RESULTS-islands.md"))
    args = ap.parse_args(argv)
    if args.part != "lcp":
        info = bl.machine_info()
        load0, up0 = os.getloadavg()[0], _uptime()
        t0 = time.perf_counter()
        lines = warm_part(args.quick) if args.part == "warm" else islands_part(args.quick, args.islands)
        lines[1:1] = ["", f"`python benchmarks/bench_blcp.py --part {args.part}"
                      f"{' --quick' if args.quick else ''}` in {time.perf_counter() - t0:.0f} s, "
                      f"{info['date']}, {info['cpu']} ({info['usable_cores']} usable cores), lemke commit "
                      f"{info['commit']}; `uptime` at the start: {up0}; at the end: {_uptime()} "
                      "(a shared machine: other processes make timings noisier)."]
        title = lines[0]
        put_section(args.out if args.part == "warm" else args.islands_out, title, lines)
        print("\n".join(lines))
        return
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


def _uptime():
    import subprocess
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return "load average %.2f, %.2f, %.2f" % os.getloadavg()


if __name__ == "__main__":
    main()
