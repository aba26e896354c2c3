#!/usr/bin/env python
"""MPC: 100 closed-loop steps of one QP whose matrices stay and whose right-hand sides move.

Usage::

    python benchmarks/bench_mpc.py [--steps 100] [--passes 5] [--out benchmarks/RESULTS-mpc.md]

The problem (``benchmarks/mpc_problem.py``): two masses and a spring, horizon 10, 60
variables, 40 dynamics equalities, 20 inequalities (5 with h = +inf), bounds (some
infinite); q (a moving reference) and b (the measured state) change every step.  Each step
is solved, in a random order per step (interleaved), by

- **lemke cold**: ``solve_qp`` with no start (P, A, G the same as the last call: the
  kernel's factor cache hits, as it does for any caller that solves the same matrices);
- **lemke cold, fresh factors**: the same after a 2-variable QP (untimed) has evicted the
  cache: the cost of a first solve of new matrices;
- **lemke warm**: ``warm_start=`` the previous step's ``result.warm_start``;
- **lemke initvals**: ``initvals=`` the previous step's x shifted by one stage (qpsolvers
  style);
- **daqp (qpsolvers)**: ``qpsolvers.solve_qp(..., solver="daqp")``, cold;
- **daqp native**: ``daqp.solve`` on the same problem (bounds, G, A as sense 5), cold;
- **daqp native warm**: the same with the previous step's active set (from its ``lam``)
  as the starting working set (``sense`` bits), daqp's hot start.

Every lemke answer is SOLVED and checked by the kernel on the data, and its x is compared
with lemke cold's here (max deviation reported); daqp's x too (its tolerance is 1e-6).
Medians over the passes per step, then the median and mean over steps; pivots are means.
"""
from __future__ import annotations

import argparse
import os
import platform
import random
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import mpc_problem  # noqa: E402

import lemke  # noqa: E402

NU, NX = mpc_problem.NU, mpc_problem.NX
STAGE = NU + NX


def load():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def daqp_form(P, G, h, A, lb, ub):
    """daqp's arrays: bounds first (|x| >= 1e30 none), then the rows of G, then A as
    equalities (sense 5)."""
    big = 1e30
    n, m, p = P.shape[0], G.shape[0], A.shape[0]
    AA = np.vstack([G, A])
    lo_b = np.where(np.isfinite(lb), lb, -big)
    up_b = np.where(np.isfinite(ub), ub, big)
    hh = np.where(np.isfinite(h), h, big)
    sense = np.concatenate([np.zeros(n + m, dtype=np.int32), np.full(p, 5, dtype=np.int32)])

    def bounds(b):
        return (np.ascontiguousarray(np.concatenate([up_b, hh, b])),
                np.ascontiguousarray(np.concatenate([lo_b, np.full(m, -big), b])))
    return np.ascontiguousarray(AA), sense, bounds


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--out", default=os.path.join(HERE, "RESULTS-mpc.md"))
    args = ap.parse_args(argv)
    load0 = load()
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=args.steps, seed=0)
    n = P.shape[0]
    try:
        import qpsolvers
        import daqp
    except ImportError:
        qpsolvers = daqp = None
    names = ["lemke cold", "lemke cold, fresh factors", "lemke warm", "lemke initvals"]
    if daqp is not None:
        names += ["daqp (qpsolvers)", "daqp native", "daqp native warm"]
        AA, sense0, dbounds = daqp_form(P, G, h, A, lb, ub)
        n_bounds = n
    T = {k: np.zeros((args.passes, len(steps))) for k in names}
    piv = {k: np.zeros((args.passes, len(steps))) for k in names}
    dev = {k: 0.0 for k in names}
    tiny = (np.eye(2), np.array([1.0, -1.0]))
    rng = random.Random(0)
    for ps in range(args.passes):
        ws, x_prev, lam_prev = None, None, None
        for t, (q, b) in enumerate(steps):
            order = names[:]
            rng.shuffle(order)
            ref = None
            got = {}
            for name in order:
                if name == "lemke cold":
                    t0 = time.perf_counter()
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
                    dt = time.perf_counter() - t0
                elif name == "lemke cold, fresh factors":
                    lemke.solve_qp(*tiny)
                    t0 = time.perf_counter()
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
                    dt = time.perf_counter() - t0
                elif name == "lemke warm":
                    t0 = time.perf_counter()
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
                    dt = time.perf_counter() - t0
                    ws = r.warm_start
                elif name == "lemke initvals":
                    guess = None if x_prev is None else np.concatenate([x_prev[STAGE:], x_prev[-STAGE:]])
                    t0 = time.perf_counter()
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, initvals=guess)
                    dt = time.perf_counter() - t0
                    x_prev = r.x
                elif name == "daqp (qpsolvers)":
                    t0 = time.perf_counter()
                    x = qpsolvers.solve_qp(P, q, G, h, A, b, lb, ub, solver="daqp")
                    dt = time.perf_counter() - t0
                    r = None
                else:
                    bu, bl = dbounds(b)
                    sense = sense0.copy()
                    if name == "daqp native warm" and lam_prev is not None:
                        on = lam_prev != 0.0
                        sense[on & (lam_prev > 0)] |= 1
                        sense[on & (lam_prev < 0)] |= 3
                    t0 = time.perf_counter()
                    x, fval, flag, info = daqp.solve(P, q, AA, bu, bl, sense)
                    dt = time.perf_counter() - t0
                    assert flag == 1, (name, flag)
                    if name == "daqp native warm":
                        lam_prev = np.asarray(info["lam"])
                    piv[name][ps, t] = info["iterations"]
                    r = None
                if r is not None:
                    assert r.status == lemke.Status.SOLVED, (name, r)
                    x = r.x
                    piv[name][ps, t] = r.pivots
                got[name] = np.asarray(x)
                T[name][ps, t] = dt
            ref = got["lemke cold"]
            for name in names:
                dev[name] = max(dev[name], float(np.abs(got[name] - ref).max()))
    load1 = load()
    per_step = {k: np.median(T[k], axis=0) * 1e6 for k in names}
    med = {k: float(np.median(per_step[k])) for k in names}
    mean = {k: float(np.mean(per_step[k])) for k in names}
    lines = []
    lines.append("# MPC: 100 closed-loop steps, matrices fixed, right-hand sides moving\n")
    lines.append(f"`python benchmarks/bench_mpc.py --steps {args.steps} --passes {args.passes}`; "
                 f"{platform.processor() or platform.machine()}, {len(os.sched_getaffinity(0))} usable cores "
                 "shared with other jobs; load average (1, 5, 15 min) "
                 f"{load0} at the start, {load1} at the end; lemke {lemke.__version__}"
                 f" ({_commit()}).\n")
    lines.append("Problem: `benchmarks/mpc_problem.py` (60 variables, 40 equalities, 20 rows of G "
                 "of which 5 with h = +inf, bounds with some infinite; 115 inequality rows in "
                 "the fused kernel's LCP). Times per step in microseconds: the median over "
                 f"{args.passes} passes per step, then the median and the mean over the steps. "
                 "Calls interleaved in a random order within each step.\n")
    lines.append("| solver | median us/step | mean us/step | mean pivots (daqp: iterations) | x vs lemke cold, max |")
    lines.append("|---|---:|---:|---:|---:|")
    for k in names:
        lines.append(f"| {k} | {med[k]:.1f} | {mean[k]:.1f} | {piv[k].mean():.2f} | {dev[k]:.1e} |")
    lines.append("")
    w, c, f = med["lemke warm"], med["lemke cold"], med["lemke cold, fresh factors"]
    lines.append(f"- lemke warm / lemke cold: {w / c:.2f} (target <= 0.5); "
                 f"warm / cold with fresh factors: {w / f:.2f}")
    lines.append(f"- lemke initvals / lemke cold: {med['lemke initvals'] / c:.2f}")
    if daqp is not None:
        for d in ("daqp (qpsolvers)", "daqp native", "daqp native warm"):
            lines.append(f"- lemke warm / {d}: {w / med[d]:.2f} (target <= 1.0)")
    kr = kernel_ratios(P, G, h, A, lb, ub, steps)
    lines.append(f"- the kernel alone (`_core.qp_solve_warm` from the previous step's basis against "
                 f"`_core.qp_solve`, best of 15 each, on the {kr[2]} steps both solve and check): "
                 f"warm / cold median {kr[0]:.2f}, worst step {kr[1]:.2f}")
    lines.append(f"- steps that leave the fused kernel for the KKT-MLCP path (its code not OK: "
                 f"a failed KKT check, ...): cold {kr[3]} of {len(steps)}, warm {kr[4]} of "
                 f"{len(steps) - 1}")
    if kr[5] is not None:
        lines.append(f"- the kernel's warm steps end on the old active set or its updates "
                     f"{kr[5][0]}, on Lemke's method restarted from the nearest set tried "
                     f"{kr[5][1]}, on the cold LCP {kr[5][2]} (`_core.qp_warm_ends`)")
    fr = far_ratios(P, G, h, A, lb, ub, steps)
    lines.append(f"- far-off warm starts, the kernel alone (best of 7 each): this problem from "
                 f"another step's basis (20 steps on) and from the reversed problem's, "
                 f"{fr[0]} solves: warm / cold median {fr[1]:.2f}, worst {fr[2]:.2f}; "
                 f"{fr[3]} random QPs (`random_convex_qp`, 20-80 variables) from the answer of "
                 f"a far-off q: median {fr[4]:.2f}, 90th percentile {fr[5]:.2f}, worst "
                 f"{fr[6]:.2f}, above 1.1: {100 * fr[7]:.0f} %")
    zero = (piv["lemke warm"] == 0).mean()
    lines.append(f"- lemke warm steps with 0 pivots (the old active set solved the new step): {100 * zero:.0f} %")
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text)


def kernel_ratios(P, G, h, A, lb, ub, steps, repeats=15):
    """(median, worst, count, cold fallbacks, warm fallbacks, ends): the per-step ratio of
    the fused kernel's time from the previous step's basis to its cold time (the best of
    ``repeats`` calls each, interleaved), over the steps where both end solved and checked
    (code 0), no Python front; the number of steps where the cold kernel, and the warm
    one, does not (the front then takes the KKT-MLCP path); and how the warm steps' first
    calls ended (kept, restarted, cold: ``_core.qp_warm_ends``, None where the kernel has
    no such count)."""
    from lemke import _core, _qp
    n, p, m = P.shape[0], A.shape[0], G.shape[0]
    out = np.empty(_qp._layout(n, p, m)[-1])  # (qp::OutLayout's length)
    ends = getattr(_core, "qp_warm_ends", None)
    ws, ratios, cold_out, warm_out, ended = None, [], 0, 0, np.zeros(3, dtype=int)
    for q, b in steps:
        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
        cold_out += _core.qp_solve(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out)[0] != 0
        if ws is not None:
            wv = np.array(ws.z_basic, dtype=np.int64)
            tw, tc = [], []
            for rep in range(repeats):
                e0 = np.array(ends()) if ends is not None and rep == 0 else None
                t0 = time.perf_counter()
                cw = _core.qp_solve_warm(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out, wv, ws.n)
                tw.append(time.perf_counter() - t0)
                if e0 is not None:
                    ended += np.array(ends()) - e0
                t0 = time.perf_counter()
                cc = _core.qp_solve(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out)
                tc.append(time.perf_counter() - t0)
            warm_out += cw[0] != 0
            if cw[0] == 0 and cc[0] == 0:
                ratios.append(min(tw) / min(tc))
        ws = r.warm_start
    return (float(np.median(ratios)), float(np.max(ratios)), len(ratios), cold_out, warm_out,
            None if ends is None else ended.tolist())


def _kernel_ratio(P, q, G, h, A, b, lb, ub, ws, repeats=7):
    """The fused kernel's best time from the warm start ws over its best cold time on one
    QP (calls interleaved), or None when either does not end solved and checked."""
    from lemke import _core, _qp
    out = np.empty(_qp._layout(P.shape[0], A.shape[0], G.shape[0])[-1])
    wv = np.array(ws.z_basic, dtype=np.int64)
    tw, tc = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        cw = _core.qp_solve_warm(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out, wv, ws.n)
        tw.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        cc = _core.qp_solve(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out)
        tc.append(time.perf_counter() - t0)
    return min(tw) / min(tc) if cw[0] == 0 and cc[0] == 0 else None


def far_ratios(P, G, h, A, lb, ub, steps, n_random=150, seed=0):
    """Warm starts far from the answer, kernel warm / cold per solve: (count, median, worst)
    on this problem (each 4th step from the basis of the step 20 on, and from the basis of
    the problem with q and b reversed), then (count, median, 90th percentile, worst, share
    above 1.1) on random convex QPs warm from the answer of the same QP with q moved by
    0.1, 1 or 10 times a standard normal."""
    from lemke.problems import random_convex_qp
    mine = []
    for t in range(0, len(steps) - 20, 4):
        q, b = steps[t]
        q2, b2 = steps[t + 20]
        for ws in (lemke.solve_qp(P, q2, G, h, A, b2, lb, ub).warm_start,
                   lemke.solve_qp(P, -q, G, h, A, -b, lb, ub).warm_start):
            r = _kernel_ratio(P, q, G, h, A, b, lb, ub, ws)
            if r is not None:
                mine.append(r)
    rng = np.random.default_rng(seed)
    rand = []
    for _ in range(n_random):
        n = int(rng.integers(20, 80))
        m, p = int(rng.integers(n // 2, 3 * n)), int(rng.integers(0, n // 2))
        Pr, q, Gr, hr, Ar, br, lbr, ubr = random_convex_qp(n, rng, m, p)
        q2 = q + rng.standard_normal(n) * rng.choice([0.1, 1.0, 10.0])
        far = lemke.solve_qp(Pr, q2, Gr, hr, Ar, br, lbr, ubr)
        if far.status != lemke.Status.SOLVED or far.warm_start is None:
            continue
        r = _kernel_ratio(Pr, q, Gr, hr, Ar, br, lbr, ubr, far.warm_start)
        if r is not None:
            rand.append(r)
    mine, rand = np.array(mine), np.array(rand)
    return (len(mine), float(np.median(mine)), float(mine.max()), len(rand),
            float(np.median(rand)), float(np.percentile(rand, 90)), float(rand.max()),
            float((rand > 1.1).mean()))


def _commit():
    try:
        return subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown commit"


if __name__ == "__main__":
    main()
