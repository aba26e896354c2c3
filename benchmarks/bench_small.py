#!/usr/bin/env python
"""Small problems at the hardware's pace: cold and warm solves at n <= 48 against quantecon,
and islands of a contact scene in one call.

Usage::

    python benchmarks/bench_small.py [--sizes 3 12 24 48] [--reps 3000] [--islands 400]
                                     [--island-sizes 1 12] [--out benchmarks/RESULTS-small.md]
    # issue 14's islands target (part 2 alone: 3,000 islands of 3-12 rows)
    python benchmarks/bench_small.py --sizes --pile 0 --islands 3000 --island-sizes 3 12 \
                                     --out benchmarks/RESULTS-islands.md

Part 1, one problem at a time (random monotone LCPs ``M = A A' + 0.1 I``, ``q ~ N(0, I)``,
seeded): lemke cold (tableau), lemke warm with the basis unchanged (q moved by 1e-9: the old
basis still solves it, 0 pivots), lemke warm from a wrong basis (q moved by 0.3: a restart),
quantecon's ``lcp_lemke``.  The four calls run interleaved in a random order for every repeat;
the table gives medians in microseconds and ratios to quantecon.

Part 2, islands: ``--islands`` contact-like LCPs of ``--island-sizes`` rows (default 1..12;
``lemke.problems.contact_like``, rank-deficient with repeated rows) and the next step of
each (q moved by 1e-3), solved warm from the first step's bases: a Python loop of
``solve_lcp``, one ``solve_lcp_many`` call with 1 and 2 workers (the bases as a list of
``WarmStart``), and a loop of quantecon (cold; it has no warm start).  lemke's results build
their items and arrays when first read, so some rows read back what a simulation needs
(each island's z, and its warm start for the next step; quantecon's z): item by item
(``r.z``, ``r.warm_start`` of each ``LCPResult``), or flat (the result's ``z``, ``offsets``
and ``warm_start``, a ``WarmStartBatch``, with the first step's ``WarmStartBatch`` passed
in: what a simulation that keeps its islands' bases in one batch does each step); the
packed rows pass the islands as two flat arrays and their sizes (``sizes=``).  Medians
of ``--rounds`` interleaved rounds.  Every answer is checked (``w = M z + q`` recomputed;
the flat rows' z split at the offsets).  Issue 14's target: 3,000 islands of 3-12 rows
(``--islands 3000 --island-sizes 3 12``) at <= 3 us per island on one core, warm starts
and reading included.

Part 3, a pile simulation: ``--pile`` disks dropped into a bin with friction
(``tests/contact_sim.py``, seed 1), one LCP per time step whose size changes as contacts
appear and vanish.  The trajectory is fixed first (lemke warm advances the scene); then
``--passes`` passes over the steps, in order, time per step: lemke warm (the last step's
``warm_start`` carried by the contacts' labels with ``WarmStart.relabel``, included in the
time; once with the scene's tuple labels, once with the same labels as ints), lemke cold, Drake's ``UnrevisedLemkeSolver`` kept across the steps of a pass (it
keeps its last basis: Drake's warm start), quantecon cold; the calls of a step in a random
order.  A step's time is its median over passes; the table gives medians over the settled
steps (from step 100) grouped by size.
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


def islands(count, lo=1, hi=12):
    """Part 2's islands (seed 15): lists of M, q and the next step's q."""
    r = np.random.default_rng(15)
    Ms, qs, qs2 = [], [], []
    for _ in range(count):
        n = int(r.integers(lo, hi + 1))
        M, q = problems.contact_like(n, r) if n >= 2 else (np.array([[2.0]]), np.array([-1.0]))
        Ms.append(np.ascontiguousarray(M))
        qs.append(q)
        qs2.append(q + 1e-3 * r.standard_normal(n))
    return Ms, qs, qs2


def part2(count, rounds, rng, lo=1, hi=12):
    Ms, qs, qs2 = islands(count, lo, hi)
    ws = [lemke.solve_lcp(M, q).warm_start for M, q in zip(Ms, qs)]
    calls = {
        "solve_lcp loop, warm": lambda: [lemke.solve_lcp(M, q, warm_start=w) for M, q, w in zip(Ms, qs2, ws)],
        "solve_lcp_many, warm, 1 worker": lambda: lemke.solve_lcp_many(Ms, qs2, warm_start=ws, workers=1),
        "solve_lcp_many, warm, 2 workers": lambda: lemke.solve_lcp_many(Ms, qs2, warm_start=ws, workers=2),
        "solve_lcp loop, cold": lambda: [lemke.solve_lcp(M, q) for M, q in zip(Ms, qs2)],
    }
    if lcp_lemke is not None:
        calls["quantecon loop, cold"] = lambda: [lcp_lemke(M, q) for M, q in zip(Ms, qs2)]

    def read(rs):  # what a simulation reads back: each island's z and its next warm start
        for r in rs:
            r.z, r.warm_start
        return rs
    calls["solve_lcp_many, warm, 1 worker, z and warm_start read"] = lambda: read(
        lemke.solve_lcp_many(Ms, qs2, warm_start=ws, workers=1))
    if lcp_lemke is not None:
        calls["quantecon loop, cold, z read"] = lambda: [lcp_lemke(M, q).z for M, q in zip(Ms, qs2)]
    batch = lemke.solve_lcp_many(Ms, qs, workers=1).warm_start  # the first step's bases, one WarmStartBatch
    assert list(batch) == ws

    def read_flat(rs):  # the same, flat: z and its offsets, every warm start in one object
        rs.z, rs.offsets, rs.warm_start
        return rs
    calls["solve_lcp_many, warm (WarmStartBatch), 1 worker, flat z and warm_start read"] = lambda: read_flat(
        lemke.solve_lcp_many(Ms, qs2, warm_start=batch, workers=1))
    calls["solve_lcp_many, warm (WarmStartBatch), 2 workers, flat z and warm_start read"] = lambda: read_flat(
        lemke.solve_lcp_many(Ms, qs2, warm_start=batch, workers=2))
    # the islands packed (every M row by row and every q end to end, with their sizes): what a
    # scene that keeps its islands in flat buffers passes, no Python object per island
    sizes = np.array([len(q) for q in qs2])
    Mp, qp2 = np.concatenate([M.ravel() for M in Ms] + [np.zeros(0)]), np.concatenate(qs2 + [np.zeros(0)])
    for w in (1, 2):
        calls[f"solve_lcp_many, packed, warm (WarmStartBatch), {w} worker{'s' * (w > 1)}, flat z and warm_start read"] = (
            lambda w=w: read_flat(lemke.solve_lcp_many(Mp, qp2, sizes=sizes, warm_start=batch, workers=w)))
    results = {k: f() for k, f in calls.items()}
    solved = {}
    for k, res in results.items():
        if "flat" in k:
            zs = np.split(res.z, res.offsets[1:-1])
            assert all(a.tobytes() == b.z.tobytes() for a, b in zip(zs, results["solve_lcp loop, warm"]))
        else:
            zs = [x if isinstance(x, np.ndarray) else x.z for x in res]
        solved[k] = sum(_ok(M, q, z) for M, q, z in zip(Ms, qs2, zs))
    times = _interleaved(calls, rounds, rng)
    return {k: np.median(v) * 1e3 for k, v in times.items()}, solved


def part3(bodies, steps, passes, rng):
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
    import contact_sim

    try:
        from pydrake.solvers import MathematicalProgram, UnrevisedLemkeSolver
    except ImportError:  # pragma: no cover
        MathematicalProgram = None
    sc = contact_sim.Scene(1, bodies, False)
    seq, ws, labels, ids, arr = [], None, [], [], None
    for step in range(steps):
        M, q, apply = contact_sim.step_lcp(sc, step)
        start = None if ws is None else ws.relabel(labels, apply.labels)
        assert ws is None or ws.relabel(ids, apply.ids) == start  # the int ids are the same labels
        assert ws is None or ws.relabel(arr, apply.id_array) == start  # and as int64 arrays
        seq.append((M, q, ws, labels, apply.labels, start, ids, apply.ids, arr, apply.id_array))
        r = lemke.solve_lcp(M, q, warm_start=start)
        apply(r.z if r.success else None)
        ws, labels, ids, arr = r.warm_start, apply.labels, apply.ids, apply.id_array
    progs = []
    if MathematicalProgram is not None:
        for M, q, *_ in seq:
            prog = MathematicalProgram()
            z = prog.NewContinuousVariables(len(q), "z")
            prog.AddLinearComplementarityConstraint(M, q, z)
            progs.append((prog, z))
    names = ["lemke warm", "lemke warm, int ids", "lemke warm, int64 array ids", "lemke warm solve", "lemke cold", "Drake persistent", "quantecon cold"]
    times = {k: [[] for _ in seq] for k in names}
    ok = {k: 0 for k in names}
    pivots = {k: [0] * len(seq) for k in names if k.startswith("lemke")}
    gc.disable()
    try:
        for p in range(passes):
            drake = UnrevisedLemkeSolver() if progs else None
            for step, (M, q, ws, old, new, start, old_ids, new_ids, old_arr, new_arr) in enumerate(seq):
                calls = {"lemke warm": lambda: lemke.solve_lcp(
                             M, q, warm_start=None if ws is None else ws.relabel(old, new)),
                         "lemke warm, int ids": lambda: lemke.solve_lcp(
                             M, q, warm_start=None if ws is None else ws.relabel(old_ids, new_ids)),
                         "lemke warm, int64 array ids": lambda: lemke.solve_lcp(
                             M, q, warm_start=None if ws is None else ws.relabel(old_arr, new_arr)),
                         "lemke warm solve": lambda: lemke.solve_lcp(M, q, warm_start=start),
                         "lemke cold": lambda: lemke.solve_lcp(M, q)}
                if progs:
                    calls["Drake persistent"] = lambda: drake.Solve(progs[step][0])
                if lcp_lemke is not None:
                    calls["quantecon cold"] = lambda: lcp_lemke(M, q)
                order = list(calls)
                rng.shuffle(order)
                for k in order:
                    t = time.perf_counter()
                    r = calls[k]()
                    times[k][step].append(time.perf_counter() - t)
                    if p == 0:
                        if k == "Drake persistent":
                            z, claimed = r.GetSolution(progs[step][1]), r.is_success()
                        elif k == "quantecon cold":
                            z, claimed = r.z, r.status == 0
                        else:
                            z, claimed = r.z, r.success
                            pivots[k][step] = r.pivots
                        ok[k] += bool(claimed and (len(q) == 0 or _ok(M, q, z)))
    finally:
        gc.enable()
    sizes = np.array([len(s[1]) for s in seq])
    med = {k: np.array([np.median(t) if t else np.nan for t in v]) * 1e6 for k, v in times.items()}
    groups = []
    settled = np.arange(len(seq)) >= 100
    for lo, hi in ((1, 131), (132, 168), (169, 10**6)):
        sel = settled & (sizes >= lo) & (sizes <= hi)
        if sel.any():
            groups.append((lo, hi, int(sel.sum()), int(sizes[sel].min()), int(sizes[sel].max()),
                           {k: float(np.median(v[sel])) for k, v in med.items()},
                           {k: float(np.median(np.array(pivots[k])[sel])) for k in ("lemke warm", "lemke cold")}))
    return groups, ok, len(seq)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--sizes", type=int, nargs="*", default=[3, 12, 24, 48])
    p.add_argument("--reps", type=int, default=3000)
    p.add_argument("--islands", type=int, default=400)
    p.add_argument("--island-sizes", type=int, nargs=2, default=[1, 12], metavar=("LO", "HI"),
                   help="the islands' rows, from LO to HI (issue 14's target: 3 12, with --islands 3000)")
    p.add_argument("--rounds", type=int, default=40)
    p.add_argument("--pile", type=int, default=16, help="disks in the pile simulation (0: skip part 3)")
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--passes", type=int, default=5)
    p.add_argument("--out", default=None)
    p.add_argument("--note", default="")
    args = p.parse_args(argv)
    args.argv = sys.argv[1:] if argv is None else argv
    rng = np.random.default_rng(0)
    info = machine_info()
    t0 = time.time()
    rows = part1(args.sizes, args.reps, rng)
    islands, solved = part2(args.islands, args.rounds, rng, *args.island_sizes)
    pile = part3(args.pile, args.steps, args.passes, rng) if args.pile else None
    mark_end(info)
    L = report_head("Small problems: cold and warm solves vs quantecon, islands in one call",
                    "bench_small.py", args, time.time() - t0, info)
    if rows:
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
    lo, hi = args.island_sizes
    L += ["", f"## 2. {args.islands} islands of {lo}..{hi} rows, the next step warm (medians of {args.rounds} "
          "rounds, ms)", "",
          "| how | time | per island | per island / quantecon's loop (z read) | solved and checked |",
          "|---|---:|---:|---:|---:|"]
    qe = islands.get("quantecon loop, cold, z read", float("nan"))
    for k, t in islands.items():
        L.append(f"| {k} | {t:.2f} ms | {t / args.islands * 1e3:.2f} us | {t / qe:.2f} | {solved[k]}/{args.islands} |")
    if pile:
        groups, ok, nsteps = pile
        L += ["", f"## 3. A pile of {args.pile} disks: {nsteps} steps, medians per step over {args.passes} passes "
              "(microseconds)", "",
              "Settled steps (from step 100), grouped by the LCP's size. *lemke warm (relabel + solve)*: "
              "`solve_lcp(M, q, warm_start=last.warm_start.relabel(old_labels, new_labels))`, the labels being "
              "the scene's tuples (each label is hashed: the relabel is Python work proportional to n); "
              "*int ids*: the same with the labels as ints (`apply.ids`, one int per label: "
              "what a simulation that wants the relabel fast passes); *int64 array ids*: the same ids as "
              "int64 arrays (`apply.id_array`: relabel's kernel path, hash tables in one call); "
              "*the solve*: the same call with the relabeled warm start made beforehand. Ratios: of the "
              "relabel + solve column. Target (issue 14): a warm step at n of about 150 (132-168) <= 120 us.", "",
              "| sizes | steps | lemke warm (relabel + solve) | lemke warm, int ids | lemke warm, int64 array ids | lemke warm, the solve | lemke cold | Drake persistent | "
              "quantecon cold | warm / Drake | warm / cold | pivots warm / cold |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        for lo, hi, count, smin, smax, t, piv in groups:
            L.append(f"| {smin}-{smax} | {count} | {t['lemke warm']:.1f} | {t['lemke warm, int ids']:.1f} | {t['lemke warm, int64 array ids']:.1f} | {t['lemke warm solve']:.1f} | {t['lemke cold']:.1f} | "
                     f"{t['Drake persistent']:.1f} | {t['quantecon cold']:.1f} | "
                     f"{t['lemke warm'] / t['Drake persistent']:.2f} | {t['lemke warm'] / t['lemke cold']:.2f} | "
                     f"{piv['lemke warm']:g} / {piv['lemke cold']:g} |")
        L += ["", "Answers reported solved and passing the script's own check, all steps of the first pass: "
              + ", ".join(f"{k} {v}/{nsteps}" for k, v in ok.items()) + "."]
    text = "\n".join(L) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
