#!/usr/bin/env python
"""Cold solves vs quantecon, and warm re-solves of slowly changing LCPs vs Drake.

Usage::

    python benchmarks/bench_warm.py [--cold-sizes 100 300 1000 2000] [--warm-sizes 100 300]
                                    [--steps 30] [--out benchmarks/RESULTS-warm.md]

Needs quantecon (``pip install -e ".[bench]"``) and Drake (``pip install drake``).  The
problems, the machine description, the interleaved timing loop and the answer check come
from ``bench_lcp.py``.

Part 1, cold solves
    The random monotone LCPs of ``bench_lcp.py`` (``M = A A' + (B - B')``, ``q ~ N(0, I)``),
    solved by lemke ``method="unrevised"``, lemke ``method="tableau"`` and quantecon's
    ``lcp_lemke``, called in a random order drawn afresh for every repeat.  Per problem the
    median over repeats; per size the median over problems.

Part 2, sequences of slowly changing problems
    Start from problem k of ``bench_lcp.py`` and move it ``--steps`` times, each step by a
    fresh standard normal perturbation times ``eps`` times the root-mean-square of the
    starting data:

    (a) q only, ``eps = 1e-7`` (the old basis stays a solution);
    (b) q only, ``eps = 1e-3``;
    (c) A, B and q, ``eps = 1e-3`` (``M = A A' + (B - B')`` stays monotone).

    Step 0 is solved cold by everybody and is not timed.  At step k >= 1:

    - lemke warm: ``solve_lcp(M_k, q_k, method=m, warm_start=<the previous step's result
      of the same chain>.warm_start)`` for m = unrevised and tableau;
    - lemke cold: ``solve_lcp(M_k, q_k, method=m)`` for both methods;
    - Drake warm: ``UnrevisedLemkeSolver.Solve(prog_k)`` on ONE solver object per pass
      (Drake keeps the last basis inside the solver object);
    - Drake cold: ``Solve(prog_k)`` on a fresh solver object.

    Each step's ``MathematicalProgram`` (``NewContinuousVariables(n)``,
    ``AddLinearComplementarityConstraint(M, q, z)``) and the fresh solver objects are built
    before the clock starts; only ``Solve`` is timed.  The six calls of a step run in a random
    order drawn afresh for every step.  The whole sequence is run ``--passes`` times (the chains start over
    each pass); a step's time is the median over passes, and the tables give the median and
    the mean over steps.

Checks
    Every answer of every solver (every repeat, every pass) is checked by this script:
    ``w = M z + q`` recomputed, residual ``max_i |min(z_i, w_i)|``; an answer counts as
    correct when the residual is at most ``RESID_RTOL * max(max|M|, max|q|, max|M| max|z|)``.
    A *failure* is a solver reporting failure (lemke status not SOLVED, quantecon status not
    0, Drake ``is_success()`` false); a *wrong answer* is a reported success that fails the
    check.
"""
from __future__ import annotations

import gc
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

BLAS_THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _early_blas_threads(argv):
    """``--blas-threads N`` must act before numpy (and its BLAS) is loaded."""
    for i, a in enumerate(argv):
        if a == "--blas-threads" and i + 1 < len(argv):
            return argv[i + 1]
        if a.startswith("--blas-threads="):
            return a.split("=", 1)[1]
    return None


if __name__ == "__main__" and _early_blas_threads(sys.argv[1:]):
    for _var in BLAS_THREAD_VARS:
        os.environ[_var] = _early_blas_threads(sys.argv[1:])

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_lcp import (  # noqa: E402  (also imports lemke and quantecon, or exits)
    RESID_RTOL,
    SEED,
    _t,
    assemble,
    fmt_range,
    lcp_lemke,
    lemke,
    machine_info,
    make_factors,
    make_problem,
    mark_end,
    publish,
    report_head,
    report_parser,
    resid_scale,
    residual,
    time_interleaved,
)

try:
    from pydrake.solvers import MathematicalProgram, UnrevisedLemkeSolver
except ImportError:
    sys.exit("Drake is needed for the warm-start comparison: pip install drake")

DEFAULT_COLD_SIZES = (100, 300, 1000, 2000)
DEFAULT_WARM_SIZES = (100, 300)
SCENARIOS = {
    "a": dict(eps=1e-7, move_M=False, text="q moved by 1e-7"),
    "b": dict(eps=1e-3, move_M=False, text="q moved by 1e-3"),
    "c": dict(eps=1e-3, move_M=True, text="M and q moved by 1e-3"),
}
METHODS = ("unrevised", "tableau")


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def check(M, q, z, reported_ok):
    """(residual, ok, wrong): ok = reported success and the residual check passes."""
    z = np.asarray(z, dtype=np.float64)
    res = residual(M, q, z)
    good = bool(np.all(np.isfinite(z))) and res <= RESID_RTOL * resid_scale(M, q, z)
    return res, bool(reported_ok and good), bool(reported_ok and not good)


def drake_version():
    try:
        from importlib.metadata import version
        return version("drake")
    except Exception:  # noqa: BLE001
        return "?"


# --------------------------------------------------------------------------- part 1: cold

COLD_SOLVERS = ("lemke unrevised", "lemke tableau", "quantecon")


def cold_calls(M, q):
    return [
        lambda: lemke.solve_lcp(M, q, method="unrevised"),
        lambda: lemke.solve_lcp(M, q, method="tableau"),
        lambda: lcp_lemke(M, q),
    ]


def cold_outcome(name, M, q, r):
    if name == "quantecon":
        res, ok, wrong = check(M, q, r.z, int(r.status) == 0)
        return dict(res=res, ok=ok, wrong=wrong, pivots=int(r.num_iter), status=int(r.status), z=r.z)
    res, ok, wrong = check(M, q, r.z, r.success)
    return dict(res=res, ok=ok, wrong=wrong, pivots=int(r.pivots), status=r.status.name, z=r.z)


def cold_plan(n, args):
    """(problems, repeats or None for auto, prime) for size n."""
    if n <= 100:
        return args.cold_problems or 10, args.cold_repeats, True
    if n <= 300:
        return args.cold_problems or 5, args.cold_repeats, True
    if n <= 1000:
        return args.cold_problems or 3, args.cold_repeats or 3, True
    return args.cold_problems or 2, args.cold_repeats or 1, False


def bench_cold(args):
    rows, details = [], []
    for n in args.cold_sizes:
        count, reps, prime = cold_plan(n, args)
        t_size = time.perf_counter()
        per = []
        for k in range(count):
            M, q = make_problem(n, k)
            calls = cold_calls(M, q)
            extra = [[] for _ in calls]  # untimed / calibration answers, checked as well
            r_here = reps
            if prime:  # one untimed call each; with auto repeats one timed call each to calibrate
                for c, e in zip(calls, extra):
                    e.append(c())
                if reps is None:
                    tt = []
                    for c, e in zip(calls, extra):
                        (ts,), (rs,) = time_interleaved([c], 1)
                        tt.append(ts[0])
                        e.extend(rs)
                    r_here = min(max(math.ceil(args.min_time / max(min(tt), 1e-7)), 3), args.max_repeats)
            times, results = time_interleaved(calls, r_here, keep_results=True,
                                              rng=np.random.default_rng([SEED, n, k, 7]))
            d = dict(n=n, k=k, reps=r_here)
            for name, ts, rs, e in zip(COLD_SOLVERS, times, results, extra):
                outs = [cold_outcome(name, M, q, r) for r in [*e, *rs]]
                d[name] = dict(
                    t=statistics.median(ts), pivots=outs[-1]["pivots"],
                    res=max(o["res"] for o in outs), calls=len(outs),
                    ok=sum(o["ok"] for o in outs), wrong=sum(o["wrong"] for o in outs),
                    status=outs[-1]["status"], z=outs[-1]["z"],
                    pivots_varied=len({o["pivots"] for o in outs}) > 1,
                )
            zs = [np.asarray(d[s]["z"]) for s in COLD_SOLVERS]
            d["dz"] = max(float(np.max(np.abs(z - zs[0]))) for z in zs[1:])
            for s in COLD_SOLVERS:
                del d[s]["z"]
            per.append(d)
            details.append(d)
        row = dict(n=n, problems=count, reps=(min(d["reps"] for d in per), max(d["reps"] for d in per)),
                   dz=max(d["dz"] for d in per))
        for s in COLD_SOLVERS:
            row[s] = dict(
                t=statistics.median(d[s]["t"] for d in per),
                pivots=statistics.median(d[s]["pivots"] for d in per),
                res=max(d[s]["res"] for d in per),
                calls=sum(d[s]["calls"] for d in per),
                ok=sum(d[s]["ok"] for d in per),
                wrong=sum(d[s]["wrong"] for d in per),
            )
        for s in COLD_SOLVERS[:2]:
            row[s]["ratio_qe"] = statistics.median(d[s]["t"] / d["quantecon"]["t"] for d in per)
        rows.append(row)
        log(f"cold n={n}: {count} problems x {row['reps']} repeats in {time.perf_counter() - t_size:.1f} s")
    return rows, details


# --------------------------------------------------------------------------- part 2: warm

WARM_SOLVERS = ("lemke unrevised warm", "lemke tableau warm", "lemke unrevised cold",
                "lemke tableau cold", "Drake warm", "Drake cold")


def make_sequence(n, k, scenario, steps):
    """[(M_0, q_0), ..., (M_steps, q_steps)] for the scenario, starting from problem k."""
    spec = SCENARIOS[scenario]
    A, B, q = make_factors(n, k)
    rng = np.random.default_rng([SEED, n, k, 1000 + ord(scenario)])
    eps = spec["eps"]
    sq = eps * math.sqrt(float(np.mean(q * q)))
    sA = eps * math.sqrt(float(np.mean(A * A)))
    sB = eps * math.sqrt(float(np.mean(B * B)))
    M = assemble(A, B)
    seq = [(M, q)]
    for _ in range(steps):
        q = q + sq * rng.standard_normal(n)
        if spec["move_M"]:
            A = A + sA * rng.standard_normal((n, n))
            B = B + sB * rng.standard_normal((n, n))
            M = assemble(A, B)
        seq.append((M, q))
    return seq


def drake_prog(M, q):
    prog = MathematicalProgram()
    z = prog.NewContinuousVariables(len(q), "z")
    prog.AddLinearComplementarityConstraint(M, q, z)
    return prog, z


def run_sequence(seq, passes, k=0):
    """Time every solver on steps 1.. of seq, ``passes`` times.  Returns per-solver lists over
    steps of dicts (times over passes, pivots, checks), and the max |Δz| lemke vs Drake."""
    progs = [drake_prog(M, q) for M, q in seq]
    nsteps = len(seq) - 1
    data = {s: [dict(times=[], pivots=[], res=0.0, ok=0, wrong=0, calls=0) for _ in range(nsteps)]
            for s in WARM_SOLVERS}
    dz = 0.0
    order_rng = np.random.default_rng([SEED, len(seq[0][1]), k, 8])
    for p in range(passes):
        M0, q0 = seq[0]
        chain = {m: lemke.solve_lcp(M0, q0, method=m) for m in METHODS}  # step 0: cold, untimed
        drake_warm = UnrevisedLemkeSolver()
        drake_warm.Solve(progs[0][0])
        for step in range(1, nsteps + 1):
            M, q = seq[step]
            prog, zvar = progs[step]
            fresh = UnrevisedLemkeSolver()
            ws = {m: chain[m].warm_start for m in METHODS}
            calls = [
                lambda: lemke.solve_lcp(M, q, method="unrevised", warm_start=ws["unrevised"]),
                lambda: lemke.solve_lcp(M, q, method="tableau", warm_start=ws["tableau"]),
                lambda: lemke.solve_lcp(M, q, method="unrevised"),
                lambda: lemke.solve_lcp(M, q, method="tableau"),
                lambda: drake_warm.Solve(prog),
                lambda: fresh.Solve(prog),
            ]
            times, results = time_interleaved(calls, 1, collect=False, rng=order_rng)
            chain = {"unrevised": results[0][0], "tableau": results[1][0]}
            zs = {}
            for name, ts, (r,) in zip(WARM_SOLVERS, times, results):
                e = data[name][step - 1]
                e["times"].append(ts[0])
                if name.startswith("Drake"):
                    z = r.GetSolution(zvar)
                    reported, piv = r.is_success(), None
                else:
                    z, reported, piv = r.z, r.success, int(r.pivots)
                res, ok, wrong = check(M, q, z, reported)
                e["pivots"].append(piv)
                e["res"] = max(e["res"], res)
                e["ok"] += ok
                e["wrong"] += wrong
                e["calls"] += 1
                if not ok:
                    e.setdefault("bad", []).append(dict(k=k, pass_=p, step=step, reported=bool(reported), res=res))
                zs[name] = np.asarray(z)
            dz = max(dz, float(np.max(np.abs(zs["lemke unrevised warm"] - zs["Drake warm"]))),
                     float(np.max(np.abs(zs["lemke tableau warm"] - zs["Drake cold"]))))
        gc.collect()
    return data, dz


def summarize(data):
    """Per solver: statistics over steps of the per-step medians over passes.  *Restart steps*
    are the steps where either lemke warm chain made pivots (its old basis no longer solved
    the problem)."""
    restart = [i for i in range(len(data[WARM_SOLVERS[0]]))
               if data["lemke unrevised warm"][i]["pivots"][0] or data["lemke tableau warm"][i]["pivots"][0]]
    out = {}
    for name, steps in data.items():
        per_step = [statistics.median(e["times"]) for e in steps]
        piv = [e["pivots"][0] for e in steps]
        rs = [per_step[i] for i in restart]
        out[name] = dict(
            med=statistics.median(per_step), mean=statistics.fmean(per_step),
            max=max(per_step), restart_steps=len(rs),
            restart_med=statistics.median(rs) if rs else None,
            restart_pivots=(statistics.median(piv[i] for i in restart)
                            if rs and piv[0] is not None else None),
            pivots_med=None if piv[0] is None else statistics.median(piv),
            pivots_mean=None if piv[0] is None else statistics.fmean(piv),
            pivots_max=None if piv[0] is None else max(piv),
            zero_pivot_steps=None if piv[0] is None else sum(x == 0 for x in piv),
            pivots_varied=any(len(set(e["pivots"])) > 1 for e in steps),
            res=max(e["res"] for e in steps),
            calls=sum(e["calls"] for e in steps), ok=sum(e["ok"] for e in steps),
            wrong=sum(e["wrong"] for e in steps),
            bad=[b for e in steps for b in e.get("bad", [])],
        )
    return out


def bench_warm(args):
    rows = []
    for n in args.warm_sizes:
        passes = args.passes or 5
        for sc in args.scenarios:
            t0 = time.perf_counter()
            merged = None
            dz = 0.0
            for k in range(args.sequences):
                seq = make_sequence(n, k, sc, args.steps)
                data, dzk = run_sequence(seq, passes, k)
                dz = max(dz, dzk)
                if merged is None:
                    merged = data
                else:
                    for s in WARM_SOLVERS:
                        merged[s].extend(data[s])
            rows.append(dict(n=n, scenario=sc, passes=passes, steps=args.steps * args.sequences,
                             sequences=args.sequences, dz=dz, s=summarize(merged)))
            log(f"warm n={n} ({sc}): {args.sequences} x {args.steps} steps x {passes} passes "
                f"in {time.perf_counter() - t0:.1f} s")
    return rows


# --------------------------------------------------------------------------- report

def _p(x):
    if x is None:
        return "n/a"
    return f"{x:g}" if float(x).is_integer() else f"{x:.1f}"


def _met(ok):
    return "**met**" if ok else "**missed**"


def render_head(info, args, total_s, commit_note):
    L = report_head(
        "lemke: cold solves vs quantecon, warm re-solves vs Drake", "bench_warm.py", args, total_s,
        info, extra_versions=f", drake {info['drake']}", commit_note=commit_note,
        extra_lines=[f"- BLAS: numpy uses {info['blas_numpy']}, scipy uses {info['blas_scipy']}; "
                     f"OPENBLAS_NUM_THREADS={info['blas_env']}"])
    a = L.append
    a("## Method")
    a("")
    a("Problems: `M = A A' + (B - B')`, A, B standard normal n x n scaled by 1/sqrt(n), q standard "
      f"normal, from `numpy.random.default_rng([{SEED}, n, k])` (the problems of `bench_lcp.py`). "
      "All solvers get the same float64 arrays and default options; everything is warmed up "
      "(quantecon compiled) before timing. Timings are `time.perf_counter` around one solver call, "
      "garbage collector off. lemke's times include its Python front end (validation, copies, the "
      "answer check on the caller's data, the result object); Drake's include its "
      "`MathematicalProgram` front end (`Solve(prog)` -> result object), but not building the program.")
    a("")
    a("Every answer of every solver (all repeats, all passes) is checked by the script: "
      "`w = M z + q` recomputed, residual `max_i |min(z_i, w_i)|`, correct when "
      f"<= {RESID_RTOL:g} * max(max|M|, max|q|, max|M| max|z|). *ok* counts answers reported as "
      "solved that pass the check; *wrong* counts answers reported as solved that fail it.")
    a("")
    return L


def render_cold(args, cold_rows, cold_details, title, describe=True):
    L = []
    a = L.append
    a(f"## {title}")
    a("")
    if describe:
        a("Solvers called in a random order drawn afresh for every repeat; per problem the median "
          "over repeats, per size the median over problems (times) and the median of the "
          "per-problem ratios. Repeats: auto (about "
          f"{args.min_time:g} s of the fastest solver per problem, at least 3) for n <= 300, 3 at "
          "n = 1000 (after one untimed call), 1 at n = 2000 (no untimed call).")
        a("")
    a("| n | problems | repeats | unrevised | tableau | quantecon | unrevised/qe | tableau/qe | "
      "pivots (unrev/tab/qe) | max residual (unrev/tab/qe) | ok (unrev/tab/qe) | wrong | max \\|Δz\\| |")
    a("|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---:|---:|")
    U, T, Q = COLD_SOLVERS
    for r in cold_rows:
        a(f"| {r['n']} | {r['problems']} | {fmt_range(r['reps'])} | "
          f"{_t(r[U]['t'])} | {_t(r[T]['t'])} | {_t(r[Q]['t'])} | "
          f"{r[U]['ratio_qe']:.2f} | {r[T]['ratio_qe']:.2f} | "
          f"{_p(r[U]['pivots'])}/{_p(r[T]['pivots'])}/{_p(r[Q]['pivots'])} | "
          f"{r[U]['res']:.1e}/{r[T]['res']:.1e}/{r[Q]['res']:.1e} | "
          f"{r[U]['ok']}/{r[U]['calls']}, {r[T]['ok']}/{r[T]['calls']}, {r[Q]['ok']}/{r[Q]['calls']} | "
          f"{r[U]['wrong'] + r[T]['wrong'] + r[Q]['wrong']} | {r['dz']:.1e} |")
    a("")
    a(f"Target{'s' if describe else ''}: cold solves at n >= 300 in at most half of quantecon's time (ratio <= 0.5).")
    a("")
    for r in cold_rows:
        if r["n"] >= 300:
            a(f"- n = {r['n']}: tableau {r[T]['ratio_qe']:.2f} ({_met(r[T]['ratio_qe'] <= 0.5)}), "
              f"unrevised {r[U]['ratio_qe']:.2f} ({_met(r[U]['ratio_qe'] <= 0.5)})")
    a("")
    odd = [d for d in cold_details if any(d[s]["ok"] != d[s]["calls"] or d[s]["pivots_varied"]
                                          for s in COLD_SOLVERS)
           or len({d[s]["pivots"] for s in COLD_SOLVERS}) > 1]
    if odd:
        a("Problems with a failure, a wrong answer, or differing pivot counts "
          "(reproduce with `make_problem(n, k)` from `bench_lcp.py`):")
        a("")
        for d in odd:
            a(f"- n = {d['n']}, k = {d['k']}: " + "; ".join(
                f"{s}: status {d[s]['status']}, {d[s]['pivots']} pivots, ok {d[s]['ok']}/{d[s]['calls']}, "
                f"residual {d[s]['res']:.1e}" for s in COLD_SOLVERS))
    else:
        a("All three solvers solved every problem on every call, with the same pivot count.")
    a("")
    return L


def _warm_description(args):
    L = []
    a = L.append
    a(f"Each sequence starts from problem k (k = 0..{args.sequences - 1}) above and takes "
      f"{args.steps} steps; each step adds `eps * rms(x_0) * N(0, I)` to the moved data x "
      "(q; in (c) also A and B, so M stays monotone), a fresh perturbation every step: "
      "(a) q, eps = 1e-7; (b) q, eps = 1e-3; (c) A, B and q, eps = 1e-3. "
      "Step 0 is solved cold by everybody, untimed. At each later step:")
    a("")
    a("- *lemke warm*: `solve_lcp(M_k, q_k, method=m, warm_start=<previous step's result of the same "
      "chain>.warm_start)`;")
    a("- *lemke cold*: `solve_lcp(M_k, q_k, method=m)`;")
    a("- *Drake warm*: `pydrake.solvers.UnrevisedLemkeSolver().Solve(prog_k)` on one solver object "
      "reused through the sequence (Drake caches the last basis in the object);")
    a("- *Drake cold*: `Solve(prog_k)` on a fresh solver object.")
    a("")
    a("The programs (`NewContinuousVariables(n)`, `AddLinearComplementarityConstraint(M, q, z)`) and "
      "solver objects are built before the clock starts. The six calls of a step run in a random "
      "order, drawn afresh for every step and pass. The whole sequence is run several times "
      "(*passes*, chains restarted each pass); a step's time is its median over passes, *median* and *mean* are over steps. "
      "Pivots are lemke's `result.pivots` (the same on every pass); **Drake's pivot count is not "
      "available from Python**: `result.get_solver_details()` raises \"The solver_details has not "
      "been set yet\" for `UnrevisedLemkeSolver`, and `SolveLcpLemke` (which returns it in C++) is "
      "not bound.")
    a("")
    return L


def render_warm(args, warm_rows, title, describe=True):
    L = []
    a = L.append
    a(f"## {title}")
    a("")
    if describe:
        L.extend(_warm_description(args))
    a("| n | scenario | solver | median / step | mean / step | max / step | median pivots | mean pivots "
      "| steps with 0 pivots | restart steps: median time (pivots) | ok | wrong | max residual |")
    a("|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in warm_rows:
        for s in WARM_SOLVERS:
            x = r["s"][s]
            zp = "n/a" if x["zero_pivot_steps"] is None else f"{x['zero_pivot_steps']}/{r['steps']}"
            pm = "n/a" if x["pivots_mean"] is None else f"{x['pivots_mean']:.1f}"
            rst = "–" if x["restart_med"] is None else (
                f"{_t(x['restart_med'])} ({_p(x['restart_pivots'])})" + (
                    f" on {x['restart_steps']}" if s == WARM_SOLVERS[0] else ""))
            a(f"| {r['n']} | ({r['scenario']}) {SCENARIOS[r['scenario']]['text']} | {s} | {_t(x['med'])} | "
              f"{_t(x['mean'])} | {_t(x['max'])} | {_p(x['pivots_med'])} | "
              f"{pm} | {zp} | {rst} | "
              f"{x['ok']}/{x['calls']} | {x['wrong']} | {x['res']:.1e} |")
    a("")
    a(f"Steps per row: {args.sequences} sequences x {args.steps} steps; passes: "
      + ", ".join(sorted({f"{r['passes']} at n = {r['n']}" for r in warm_rows})) + ". "
      "*Restart steps*: the steps where a lemke warm chain made pivots (the old basis no longer "
      "solved the problem); their count is in the first row of each block; every solver's median "
      "time over those same steps.")
    a("")
    a("### Ratios (of the medians; of the means in brackets)")
    a("")
    a("| n | scenario | unrev warm / Drake warm | tab warm / Drake warm | unrev warm / unrev cold | "
      "tab warm / tab cold | unrev warm / tab cold | Drake warm / Drake cold | max \\|Δz\\| lemke vs Drake |")
    a("|---:|---|---:|---:|---:|---:|---:|---:|---:|")

    def ratio(x, y):
        return f"{x['med'] / y['med']:.3f} ({x['mean'] / y['mean']:.3f})"

    for r in warm_rows:
        s = r["s"]
        uw, tw, uc, tc, dw, dc = (s[k] for k in WARM_SOLVERS)
        a(f"| {r['n']} | ({r['scenario']}) | {ratio(uw, dw)} | {ratio(tw, dw)} | {ratio(uw, uc)} | "
          f"{ratio(tw, tc)} | {ratio(uw, tc)} | {ratio(dw, dc)} | {r['dz']:.1e} |")
    a("")
    a("### Targets")
    a("")
    a("(a): lemke warm <= 1/2 of Drake warm (medians). (b), (c): lemke warm <= 1/5 of lemke's own "
      "cold solve (the same method's, and the faster method's) and <= 1/5 of Drake's median (warm).")
    a("")
    for r in warm_rows:
        s = r["s"]
        best_cold = min(s["lemke unrevised cold"]["med"], s["lemke tableau cold"]["med"])
        for m in METHODS:
            w = s[f"lemke {m} warm"]
            dw = s["Drake warm"]
            if r["scenario"] == "a":
                q = w["med"] / dw["med"]
                a(f"- n = {r['n']} (a), {m}: warm {_t(w['med'])} vs Drake warm {_t(dw['med'])} = "
                  f"{q:.2f} -> {_met(q <= 0.5)}")
            else:
                own = s[f"lemke {m} cold"]["med"]
                q1, q2, q3 = w["med"] / own, w["med"] / best_cold, w["med"] / dw["med"]
                a(f"- n = {r['n']} ({r['scenario']}), {m}: warm {_t(w['med'])}; / own cold {_t(own)} = "
                  f"{q1:.3f} {_met(q1 <= 0.2)}; / fastest lemke cold {_t(best_cold)} = {q2:.3f} "
                  f"{_met(q2 <= 0.2)}; / Drake warm {_t(dw['med'])} = {q3:.3f} {_met(q3 <= 0.2)} "
                  f"(mean: {w['mean'] / dw['mean']:.3f} of Drake's mean)")
    a("")
    varied = [f"n = {r['n']} ({r['scenario']}) {s_}" for r in warm_rows for s_ in WARM_SOLVERS
              if r["s"][s_]["pivots_varied"]]
    if varied:
        a("Pivot counts differed between passes of the same step for: " + "; ".join(varied) + ".")
        a("")
    bad = [(r, s_, b) for r in warm_rows for s_ in WARM_SOLVERS for b in r["s"][s_]["bad"]]
    if bad:
        a("### Failures and wrong answers")
        a("")
        a("Reproduce with `make_sequence(n, k, scenario, steps)` from `bench_warm.py`.")
        a("")
        for r, s_, b in bad[:50]:
            a(f"- n = {r['n']} ({r['scenario']}) {s_}: sequence k = {b['k']}, step {b['step']}, "
              f"pass {b['pass_']}: reported success {b['reported']}, residual {b['res']:.1e}")
        if len(bad) > 50:
            a(f"- ... {len(bad) - 50} more")
    else:
        a("Every warm and cold answer of lemke and Drake passed the check.")
    a("")
    return L


def render(info, args, total_s, commit_note, main_run, other_run=None):
    L = render_head(info, args, total_s, commit_note)
    L += render_cold(args, main_run["cold_rows"], main_run["cold_details"],
                     "1. Cold solves vs quantecon" + main_run["label"])
    L += render_warm(args, main_run["warm_rows"],
                     "2. Warm re-solves of slowly changing problems vs Drake" + main_run["label"])
    if other_run is not None:
        L += [f"## The same measurements{other_run['label']}", "",
              f"Run right after the above, in a subprocess with {other_run['env_text']} (set before numpy "
              "is imported), same problems and settings.", ""]
        L += render_cold(args, other_run["cold_rows"], other_run["cold_details"],
                         "3. Cold solves vs quantecon" + other_run["label"], describe=False)
        L += render_warm(args, other_run["warm_rows"],
                         "4. Warm re-solves vs Drake" + other_run["label"], describe=False)
    return "\n".join(L)


def blas_info():
    def one(mod):
        try:
            d = mod.show_config(mode="dicts")["Build Dependencies"]["blas"]
            return f"{d.get('name', '?')} {d.get('version', '?')}"
        except Exception:  # noqa: BLE001
            return "?"
    import scipy
    return one(np), one(scipy)


def main(argv=None):
    p, argv = report_parser(__doc__, "RESULTS-warm.md", argv)
    p.add_argument("--cold-sizes", type=int, nargs="*", default=list(DEFAULT_COLD_SIZES))
    p.add_argument("--cold-problems", type=int, default=None,
                   help="problems per size (default 10 / 5 / 3 / 2 for n <= 100 / 300 / 1000 / more)")
    p.add_argument("--cold-repeats", type=int, default=None,
                   help="timed calls per solver per problem (default: auto for n <= 300, "
                        "3 up to 1000, 1 above)")
    p.add_argument("--min-time", type=float, default=0.1,
                   help="auto repeats: seconds of the fastest solver per problem (default 0.1)")
    p.add_argument("--max-repeats", type=int, default=2000)
    p.add_argument("--warm-sizes", type=int, nargs="*", default=list(DEFAULT_WARM_SIZES))
    p.add_argument("--scenarios", nargs="*", default=list(SCENARIOS), choices=list(SCENARIOS))
    p.add_argument("--steps", type=int, default=30, help="steps per sequence (default 30)")
    p.add_argument("--sequences", type=int, default=2,
                   help="sequences (starting problems) per size and scenario (default 2)")
    p.add_argument("--passes", type=int, default=None,
                   help="runs of each sequence (default 5)")
    p.add_argument("--blas-threads", default=None,
                   help="set OPENBLAS_NUM_THREADS, OMP_NUM_THREADS and MKL_NUM_THREADS to this "
                        "before numpy is imported (command line only)")
    p.add_argument("--compare-blas-threads", default=None, metavar="N",
                   help="after the run, repeat all measurements in a subprocess with "
                        "--blas-threads N and add them to the report")
    p.add_argument("--commit", default="",
                   help="commit the lemke under test was taken from, when it is not a git checkout "
                        "(e.g. a `git archive` snapshot)")
    p.add_argument("--json", default=None, help="also write the raw results as JSON here")
    args = p.parse_args(argv)
    args.argv = list(argv)
    if any(n < 1 for n in [*args.cold_sizes, *args.warm_sizes]) or args.steps < 1 or args.sequences < 1:
        p.error("sizes, --steps and --sequences must be positive")

    t0 = time.perf_counter()
    info = machine_info()
    info["drake"] = drake_version()
    info["blas_numpy"], info["blas_scipy"] = blas_info()
    info["blas_env"] = os.environ.get("OPENBLAS_NUM_THREADS", "(unset)")
    commit_note = ""
    if args.commit:
        commit_note = (f" (snapshot of commit {args.commit})" if not info["commit"]
                       else f" (--commit {args.commit})")
    # Warm up: both methods (cold and restart paths), quantecon, Drake.
    for n in (3, 10, 30):
        M, q = make_problem(n, 10_000)
        for m in METHODS:
            r = lemke.solve_lcp(M, q, method=m)
            lemke.solve_lcp(M, q + 0.5, method=m, warm_start=r.warm_start)
            lemke.solve_lcp(M, q, method=m, warm_start=r.warm_start)
        lcp_lemke(M, q)
        UnrevisedLemkeSolver().Solve(drake_prog(M, q)[0])
    log(f"warmed up in {time.perf_counter() - t0:.1f} s")
    warm_rows = bench_warm(args) if args.warm_sizes else []
    cold_rows, cold_details = bench_cold(args) if args.cold_sizes else ([], [])
    label = (" (BLAS threads: library default)" if info["blas_env"] == "(unset)"
             else f" (OPENBLAS_NUM_THREADS={info['blas_env']})")
    main_run = dict(label=label, cold_rows=cold_rows, cold_details=cold_details, warm_rows=warm_rows)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(main_run, f)

    other_run = None
    if args.compare_blas_threads:
        skip_with_value = {"--compare-blas-threads", "--out", "--json", "--blas-threads", "--note"}
        sub_argv, it = [], iter(argv)
        for x in it:
            if x in skip_with_value:
                next(it, None)
            elif x.split("=", 1)[0] not in skip_with_value:
                sub_argv.append(x)
        with tempfile.TemporaryDirectory(prefix="bench-warm-") as tmp:
            js = os.path.join(tmp, "run.json")
            cmd = [sys.executable, os.path.abspath(__file__), *sub_argv,
                   "--blas-threads", str(args.compare_blas_threads),
                   "--out", os.path.join(tmp, "run.md"), "--json", js]
            log(f"comparison run: {' '.join(cmd[1:])}")
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            with open(js) as f:
                other_run = json.load(f)
        other_run["env_text"] = ", ".join(f"`{v}={args.compare_blas_threads}`" for v in BLAS_THREAD_VARS)

    mark_end(info)
    text = render(info, args, time.perf_counter() - t0, commit_note, main_run, other_run)
    publish(text, args.out, log)


if __name__ == "__main__":
    main()
