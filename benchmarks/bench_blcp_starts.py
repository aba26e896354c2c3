#!/usr/bin/env python
"""Box LCPs: pivots of the bounded kernel from other starting bounds and covering vectors
(issue 31: can a start cut relay's pivots?).

Usage::

    python benchmarks/bench_blcp_starts.py > /tmp/starts.md

Each variant is one ``lemke._core.boxed.solve`` run from a start given as warm flags (no z
basic, the z's at hi flagged; on finite boxes this is the cold run from those bounds, the
cold default reproduced exactly) or, for the covering vectors, the cold run with another
``cov_mode``.  Starts: *q sign* (the default: hi where q_i < 0), *mid* (hi where
(q + M mid)_i < 0, mid the box's centre), *w sign* (hi where the default start's w_i < 0),
*unconstrained* (hi where the unconstrained -M^-1 q is above the centre; one LU more), and
*oracle* (each z at the bound the answer puts it at, or hi where the answer's w_i < 0: the
best a bound-only start can know); beside them the z's basic at the answer (each entered
the basis at least once) and the pivots of the LCP of the same M and q.  Problems: ``bench_blcp.py``'s relay and contact
families (n = 12 / 48 / 200), tests/test_blcp.py's seeded family (its finite boxes) and the
Siconos relay files.  Per variant: total pivots, the problems with fewer / more pivots than
the default, and the runs whose answer failed the kernel's check.  Pivots only: no timing.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

import bench_lcp as bl  # noqa: E402
from bench_blcp import boxes  # noqa: E402
from test_blcp import RELAY, family, read_relay  # noqa: E402

import lemke  # noqa: E402
from lemke._blcp import _layout  # noqa: E402
from lemke._core import boxed  # noqa: E402


def run(M, q, lo, hi, at_hi, mode=0):
    """(pivots, checked) of one kernel run from the bounds `at_hi`, covering vector `mode`."""
    n = q.size
    warm = np.concatenate([np.zeros(n, bool), at_hi & np.isfinite(hi)])
    buf, final = np.empty(_layout(n)["length"]), np.empty(n, dtype=np.int64)
    out = boxed.solve(M, q, lo, hi, warm, mode, 100 * (n + 1), 1e-12, 1e-12, 1e-8, buf, final)
    return out[1], out[3]


def variants(M, q, lo, hi):
    lo_f, hi_f = np.isfinite(lo), np.isfinite(hi)
    mid = np.where(lo_f & hi_f, (lo + hi) / 2, np.where(lo_f, lo, np.where(hi_f, hi, 0.0)))
    start = q < 0
    out = {"q sign": run(M, q, lo, hi, start)}
    out["mid"] = run(M, q, lo, hi, q + M @ mid < 0)
    z0 = np.where(start & hi_f, hi, np.where(lo_f, lo, 0.0))
    out["w sign"] = run(M, q, lo, hi, q + M @ z0 < 0)
    try:
        out["unconstrained"] = run(M, q, lo, hi, np.linalg.solve(M, -q) > mid)
    except np.linalg.LinAlgError:
        out["unconstrained"] = out["q sign"]
    r = lemke.solve_blcp(M, q, lo, hi)
    if r.success:
        z, w = r.z, M @ r.z + q
        out["oracle"] = run(M, q, lo, hi, (z >= hi) | ((z > lo) & (w < 0)))
        out["basic z at the answer"] = (int(np.sum((z > lo) & (z < hi))), True)
    for mode in (1, 2):
        out[f"covering {mode}"] = run(M, q, lo, hi, start, mode)
    out["LCP (z >= 0)"] = (lemke.solve_lcp(M, q).pivots, True)
    return out


PLAIN = ("basic z at the answer", "LCP (z >= 0)")  # (counts, not runs)


def row(name, problems):
    tot, fewer, more, bad = {}, {}, {}, {}
    for M, q, lo, hi in problems:
        v = variants(M, q, lo, hi)
        base = v["q sign"][0]
        for k, (p, ok) in v.items():
            tot[k] = tot.get(k, 0) + p
            fewer[k] = fewer.get(k, 0) + (p < base)
            more[k] = more.get(k, 0) + (p > base)
            bad[k] = bad.get(k, 0) + (not ok)
    cells = [f"{tot[k]} (-{fewer[k]} / +{more[k]}{f', {bad[k]} failed' if bad[k] else ''})"
             if k not in PLAIN else f"{tot[k]}" for k in tot]
    return f"| {name} | {len(problems)} | " + " | ".join(cells) + " |", list(tot)


def main():
    sets = []
    for kind in ("relay", "contact"):
        for n, count in ((12, 40), (48, 20), (200, 6)):
            sets.append((f"{kind} n = {n}", [(*bl.make_problem(n, k), *boxes(n, kind))
                                             for k in range(count)]))
    fam = [p for p in map(family, range(240)) if np.all(np.isfinite(p[2]) & np.isfinite(p[3]))]
    sets.append(("test_blcp family (finite boxes)", fam))
    sets.append(("Siconos relay", [read_relay(p) for p in sorted(RELAY.glob("*.dat"))]))
    lines = []
    for name, probs in sets:
        line, keys = row(name, probs)
        lines.append(line)
        print(line, file=sys.stderr, flush=True)
    print("| problems | count | " + " | ".join(keys) + " |")
    print("|---|---:|" + "---:|" * len(keys))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
