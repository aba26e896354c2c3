"""Issue 31's islands call alone: 400 islands of 1-12 rows solved warm in one
``solve_lcp_many`` call (one worker, the last step's bases as one ``WarmStartBatch``, the flat
``z``, ``offsets`` and ``warm_start`` read), packed (``sizes=``) and from lists of arrays,
the two calls interleaved in a random order each round.

    python benchmarks/bench_islands_step.py [--islands 400] [--rounds 300] [--variants 16]

Two workloads: *same q* solves one moved q every round (``bench_small.py``'s part 2: its
islands and moved q); *new q* takes the next of ``--variants`` q's each round (each the first
step's q moved by 1e-3), as a simulation's steps do. The CPU's branch predictors learn the
400 islands' branches when the same q comes back every round: the same kernel runs ~1.45x
longer per island on new q's (benchmarks/RESULTS-small.md, branch ``isl400``). Prints medians
and 10th percentiles in microseconds per island, the pivots and the machine's load; every
answer is checked (complementarity within 1e-8, relative) and packed and lists give the same
bits.
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_small import _interleaved, _ok  # noqa: E402

import lemke  # noqa: E402
from lemke import problems  # noqa: E402


def islands(count, variants, seed=15):
    """The islands of bench_small.py's part 2 (its generator and seed: the same M's, q's and
    moved q, ``moved[0]``), and ``variants - 1`` more moved q's from a second generator."""
    r = np.random.default_rng(seed)
    Ms, qs, moved = [], [], [[] for _ in range(variants)]
    for _ in range(count):
        n = int(r.integers(1, 13))
        M, q = problems.contact_like(n, r) if n >= 2 else (np.array([[2.0]]), np.array([-1.0]))
        Ms.append(np.ascontiguousarray(M))
        qs.append(q)
        moved[0].append(q + 1e-3 * r.standard_normal(n))
    r = np.random.default_rng(seed + 1)
    for k in range(1, variants):
        moved[k] = [q + 1e-3 * r.standard_normal(len(q)) for q in qs]
    return Ms, qs, moved


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--islands", type=int, default=400)
    p.add_argument("--rounds", type=int, default=300)
    p.add_argument("--variants", type=int, default=16, help="the new-q workload's q's, in turn")
    args = p.parse_args(argv)
    Ms, qs, moved = islands(args.islands, args.variants)
    first = lemke.solve_lcp_many(Ms, qs, workers=1).warm_start
    sizes = np.array([len(q) for q in qs])
    Mp = np.concatenate([M.ravel() for M in Ms])
    packed_qs = [np.concatenate(q2) for q2 in moved]

    def read(rs):
        rs.z, rs.offsets, rs.warm_start
        return rs

    turn = {"k": 0}

    def new_q():
        turn["k"] = (turn["k"] + 1) % args.variants
        return turn["k"]

    calls = {
        ("same q", "packed"): lambda: read(lemke.solve_lcp_many(Mp, packed_qs[0], sizes=sizes, warm_start=first, workers=1)),
        ("same q", "lists"): lambda: read(lemke.solve_lcp_many(Ms, moved[0], warm_start=first, workers=1)),
        ("new q", "packed"): lambda: read(lemke.solve_lcp_many(Mp, packed_qs[new_q()], sizes=sizes, warm_start=first, workers=1)),
        ("new q", "lists"): lambda: read(lemke.solve_lcp_many(Ms, moved[new_q()], warm_start=first, workers=1)),
    }
    pivots = []
    for k in range(args.variants):  # every answer checked, packed and lists the same bits
        a = lemke.solve_lcp_many(Mp, packed_qs[k], sizes=sizes, warm_start=first, workers=1)
        b = lemke.solve_lcp_many(Ms, moved[k], warm_start=first, workers=1)
        assert a == b and a.z.tobytes() == b.z.tobytes()
        zs = np.split(a.z, a.offsets[1:-1])
        solved = a.success.sum()
        assert sum(_ok(M, q, z) for M, q, z, s in zip(Ms, moved[k], zs, a.success) if s) == solved
        pivots.append(int(a.pivots.sum()))
    load0 = os.getloadavg()[0]
    times = _interleaved(calls, args.rounds, np.random.default_rng(0))
    print(f"{args.islands} islands, {args.rounds} rounds, lemke {lemke.__version__}, "
          f"1-minute load {load0:.2f} -> {os.getloadavg()[0]:.2f}; pivots per call "
          f"{pivots[0]} (same q), {min(pivots)}-{max(pivots)} (new q)")
    print("| workload | call | median us/island | p10 us/island |")
    print("|---|---|---:|---:|")
    for (work, call), v in times.items():
        v = np.array(v) / args.islands * 1e6
        print(f"| {work} | {call} | {np.median(v):.3f} | {np.percentile(v, 10):.3f} |")


if __name__ == "__main__":
    main()
