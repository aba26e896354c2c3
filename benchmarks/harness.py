#!/usr/bin/env python
"""One command for every benchmark: lemke against every installed peer, side by side.

Usage::

    python benchmarks/harness.py [--quick] [--out benchmarks/RESULTS.md]

Runs in one process, on the same problems, interleaved (a random solver order drawn afresh
for every repeat), with everything compiled beforehand:

* cold LCP solves, families ``psd`` (M = A A' + (B - B'), the problems of ``bench_lcp.py``),
  ``pmatrix``, ``contact`` (rank-deficient with ties), ``murty`` (2^n pivots) and
  ``siconos`` (every file in tests/data/siconos/lcp): lemke (each method), quantecon's
  ``lcp_lemke``, Drake's ``UnrevisedLemkeSolver`` and ``MobyLcpSolver`` (through
  ``MathematicalProgram``; the program and a fresh solver object are built before the clock
  starts, so only ``Solve`` is timed);
* warm-start sequences (q, or M and q, moved a little at every step): lemke chaining
  ``warm_start``, Drake reusing one solver object (it keeps the last basis), both cold;
* batches: ``solve_lcp_batch`` on one thread and on all cores, against Python loops over
  ``solve_lcp`` and over quantecon;
* convex QPs (dense, strictly convex, with inequalities and equalities): ``lemke.solve_qp``
  against quadprog, daqp, proxqp (proxsuite) and piqp through qpsolvers, each answer compared
  with quadprog's;
* the first call: ``import lemke`` and the first solve, in fresh subprocesses.

Every answer is checked by this script on the caller's data (residual ``max|min(z, Mz+q)|``
against ``1e-8`` times the data's scale); a *wrong* answer is one reported as solved that
fails the check.  A peer that is not installed is skipped with a note.  Writes the markdown
report (``--out``), a Dolan-More performance profile (``--plot``, PNG, needs matplotlib) and,
with ``--json``, the raw numbers.
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))  # the Siconos reader

import bench_lcp as bl  # noqa: E402  (machine description, first call, problems, checks)

import lemke  # noqa: E402
from lemke import problems as lp  # noqa: E402

RNG_SEED = 20240601
NOTES: list[str] = []


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- peers

def _peers():
    """Which optional peers are importable: {name: module or None}, notes for the missing."""
    found = {}
    try:
        from quantecon.optimize import lcp_lemke
        found["quantecon"] = lcp_lemke
    except ImportError:
        NOTES.append("quantecon is not installed: skipped (`pip install -e \".[bench]\"`).")
    try:
        from pydrake.solvers import MathematicalProgram, MobyLcpSolver, UnrevisedLemkeSolver
        found["drake"] = (MathematicalProgram, UnrevisedLemkeSolver, MobyLcpSolver)
    except ImportError:
        NOTES.append("pydrake is not installed: Drake's solvers skipped (`pip install drake`).")
    try:
        import qpsolvers
        found["qpsolvers"] = qpsolvers
        for s in ("quadprog", "daqp", "proxqp", "piqp"):
            if s not in qpsolvers.available_solvers:
                NOTES.append(f"qpsolvers has no {s}: skipped.")
    except ImportError:
        NOTES.append("qpsolvers is not installed: the QP peers are skipped.")
    return found


PEERS = _peers()


def checked(M, q, z, reported_ok):
    """``(residual, ok, wrong)``: ok = reported solved and passes this script's check."""
    if z is None:
        return math.inf, False, False
    z = np.asarray(z, dtype=np.float64)
    res = bl.residual(M, q, z)
    good = bool(np.all(np.isfinite(z))) and res <= bl.RESID_RTOL * bl.resid_scale(M, q, z)
    return res, bool(reported_ok and good), bool(reported_ok and not good)


class Solver:
    """An LCP solver: ``setup(M, q)`` (untimed, once per problem) returns a context;
    ``prepare(ctx)`` (untimed, before every call) returns the function that is timed, which
    returns ``(z, reported_ok, pivots or None)``."""

    def __init__(self, name, setup, prepare, lemke_=False, max_n=None):
        self.name, self.setup, self.prepare, self.lemke, self.max_n = name, setup, prepare, lemke_, max_n


def lcp_solvers():
    out = []
    for m in lemke.METHODS:
        def prep(ctx, m=m):
            M, q = ctx
            def call():
                r = lemke.solve_lcp(M, q, method=m)
                return r.z, r.status == lemke.Status.SOLVED, r.pivots
            return call
        out.append(Solver(f"lemke {m}", lambda M, q: (M, q), prep, lemke_=True))
    if "quantecon" in PEERS:
        qe = PEERS["quantecon"]

        def prep_qe(ctx):
            M, q = ctx
            def call():
                r = qe(M, q)
                return r.z, int(r.status) == 0, int(r.num_iter)
            return call
        out.append(Solver("quantecon", lambda M, q: (M, q), prep_qe))
    if "drake" in PEERS:
        MP, Unrevised, Moby = PEERS["drake"]

        def setup_drake(M, q):
            prog = MP()
            z = prog.NewContinuousVariables(len(q), "z")
            prog.AddLinearComplementarityConstraint(M, q, z)
            return prog, z

        for name, cls in (("drake unrevised", Unrevised), ("drake moby", Moby)):
            def prep_drake(ctx, cls=cls):
                prog, z = ctx
                solver = cls()  # fresh: UnrevisedLemkeSolver keeps the last basis inside
                def call():
                    r = solver.Solve(prog)
                    return r.GetSolution(z), r.is_success(), None
                return call
            out.append(Solver(name, setup_drake, prep_drake))
    return out


# --------------------------------------------------------------------------- timing

def time_problem(solvers, M, q, args, rng):
    """Median seconds of each solver on (M, q), interleaved in random order, plus each
    solver's checked outcome."""
    ctx = {s.name: s.setup(M, q) for s in solvers}
    first = {}
    for s in solvers:  # untimed call (memory, caches), then a timed one to calibrate
        s.prepare(ctx[s.name])()
        f = s.prepare(ctx[s.name])
        t0 = time.perf_counter()
        out = f()
        first[s.name] = (time.perf_counter() - t0, out)
    fastest = min(t for t, _ in first.values())
    total = sum(t for t, _ in first.values())
    reps = max(3, min(args.max_repeats, math.ceil(args.min_time / max(fastest, 1e-7)),
                      int(args.problem_budget / max(total, 1e-9))))
    if total > args.problem_budget:
        reps = 1
    times = {s.name: [] for s in solvers}
    pc = time.perf_counter
    for _ in range(reps):
        for j in rng.permutation(len(solvers)):
            s = solvers[j]
            f = s.prepare(ctx[s.name])
            t0 = pc()
            f()
            times[s.name].append(pc() - t0)
    rows = {}
    for s in solvers:
        z, rep_ok, piv = first[s.name][1]
        res, ok, wrong = checked(M, q, z, rep_ok)
        rows[s.name] = dict(t=statistics.median(times[s.name]), reps=reps, pivots=piv,
                            residual=res, ok=ok, wrong=wrong, reported=bool(rep_ok))
    return rows


def family_problems(family, n, count):
    """``count`` problems of the family at size n (fixed seeds)."""
    if family == "psd":
        return [bl.make_problem(n, k) for k in range(count)]
    if family == "murty":
        p = lp.murty(n)
        return [(p.M, p.q)]
    gen = {"pmatrix": lp.random_p_matrix, "contact": lp.contact_like}[family]
    return [gen(n, np.random.default_rng([RNG_SEED, n, k, 7])) for k in range(count)]


def siconos_problems():
    from siconos_dat import read_lcp
    for path in sorted((HERE.parent / "tests" / "data" / "siconos" / "lcp").glob("*.dat")):
        M, q = read_lcp(path)
        yield path.stem, np.ascontiguousarray(M), np.ascontiguousarray(q)


def problem_count(n, quick):
    counts = [(20, 10), (100, 5), (300, 3), (1000, 2)] if not quick else [(20, 5), (100, 3), (300, 2)]
    return next((c for lim, c in counts if n <= lim), 1)


def bench_lcp_families(args, rng):
    solvers = lcp_solvers()
    records = []  # one per (family, n, problem): {solver: row}
    for family, sizes in args.families.items():
        too_slow = set()
        if family == "siconos":
            for name, M, q in siconos_problems():
                rows = time_problem(solvers, M, q, args, rng)
                records.append(dict(family=family, n=q.size, problem=name, rows=rows))
            log(f"siconos: {len(records)} problems so far")
            continue
        for n in sizes:
            active = [s for s in solvers if s.name not in too_slow]
            per = []
            t_size = time.perf_counter()
            for k, (M, q) in enumerate(family_problems(family, n, problem_count(n, args.quick))):
                rows = time_problem(active, M, q, args, rng)
                per.append(rows)
                records.append(dict(family=family, n=n, problem=k, rows=rows))
            for s in active:
                if not s.lemke and statistics.median(r[s.name]["t"] for r in per) > args.max_call:
                    too_slow.add(s.name)
                    NOTES.append(f"{family}: {s.name} took more than {args.max_call:g} s a call at "
                                 f"n = {n}; not run at larger n.")
            log(f"{family} n={n}: {len(per)} problems in {time.perf_counter() - t_size:.1f} s")
    return records


# --------------------------------------------------------------------------- warm starts

def warm_sequences(args, rng):
    """Sequences of slowly changing problems, re-solved warm and cold."""
    out = []
    has_drake = "drake" in PEERS
    for n in args.warm_sizes:
        for scen, eps in (("q moved by 1e-3", 1e-3), ("M and q moved by 1e-3", 1e-3)):
            A, B, q = bl.make_factors(n, 0)
            srng = np.random.default_rng([RNG_SEED, n, 99])
            seq = []
            for _ in range(args.steps + 1):
                seq.append((bl.assemble(A, B), q.copy()))
                q = q + eps * srng.standard_normal(n) * np.sqrt(np.mean(q**2))
                if scen.startswith("M"):
                    A = A + eps * srng.standard_normal((n, n)) * np.sqrt(np.mean(A**2))
                    B = B + eps * srng.standard_normal((n, n)) * np.sqrt(np.mean(B**2))
            names = ["lemke warm", "lemke cold"] + (["drake warm", "drake cold"] if has_drake else []) \
                + (["quantecon cold"] if "quantecon" in PEERS else [])
            times = {k: [] for k in names}
            piv = []
            bad = {k: 0 for k in names}
            prev = lemke.solve_lcp(*seq[0])
            if has_drake:
                MP, Unrevised, _ = PEERS["drake"]
                dwarm = Unrevised()
                progs = []
                for M, qq in seq:
                    prog = MP()
                    z = prog.NewContinuousVariables(n, "z")
                    prog.AddLinearComplementarityConstraint(M, qq, z)
                    progs.append((prog, z))
                dwarm.Solve(progs[0][0])
            for step in range(1, len(seq)):
                M, qq = seq[step]
                calls = {
                    "lemke warm": lambda: lemke.solve_lcp(M, qq, warm_start=prev.warm_start),
                    "lemke cold": lambda: lemke.solve_lcp(M, qq),
                }
                if has_drake:
                    prog, z = progs[step]
                    fresh = Unrevised()
                    calls["drake warm"] = lambda: dwarm.Solve(prog)
                    calls["drake cold"] = lambda: fresh.Solve(prog)
                if "quantecon" in PEERS:
                    calls["quantecon cold"] = lambda: PEERS["quantecon"](M, qq)
                results = {}
                for j in rng.permutation(len(names)):
                    k = names[j]
                    t0 = time.perf_counter()
                    results[k] = calls[k]()
                    times[k].append(time.perf_counter() - t0)
                for k, r in results.items():
                    if k.startswith("lemke"):
                        zz, rep = r.z, r.success
                    elif k.startswith("drake"):
                        zz, rep = r.GetSolution(progs[step][1]), r.is_success()
                    else:
                        zz, rep = r.z, int(r.status) == 0
                    _, ok, _ = checked(M, qq, zz, rep)
                    bad[k] += not ok
                prev = results["lemke warm"]
                piv.append(prev.pivots)
            out.append(dict(n=n, scenario=scen, steps=args.steps, pivots=statistics.median(piv),
                            zero=sum(p == 0 for p in piv),
                            t={k: statistics.median(v) for k, v in times.items()}, bad=bad))
            log(f"warm n={n} {scen}: done")
    return out


# --------------------------------------------------------------------------- batches

def bench_batches(args, rng):
    out = []
    qe = PEERS.get("quantecon")
    for n, B in args.batches:
        pairs = [bl.make_problem(n, 1000 + b) for b in range(B)]
        M = np.stack([m for m, _ in pairs])
        q = np.stack([v for _, v in pairs])
        calls = {
            "batch, 1 thread": lambda: lemke.solve_lcp_batch(M, q, workers=1),
            "batch, all cores": lambda: lemke.solve_lcp_batch(M, q),
            "loop over solve_lcp": lambda: [lemke.solve_lcp(M[b], q[b]) for b in range(B)],
        }
        if qe is not None:
            calls["loop over quantecon"] = lambda: [qe(M[b], q[b]) for b in range(B)]
        names = list(calls)
        for f in calls.values():
            f()
        times = {k: [] for k in names}
        for _ in range(args.batch_repeats):
            for j in rng.permutation(len(names)):
                t0 = time.perf_counter()
                calls[names[j]]()
                times[names[j]].append(time.perf_counter() - t0)
        res = lemke.solve_lcp_batch(M, q)
        wrong = sum(not checked(M[b], q[b], res.z[b], True)[1] for b in range(B))
        out.append(dict(n=n, B=B, t={k: statistics.median(v) / B for k, v in times.items()},
                        solved=int(res.success.sum()), wrong=wrong))
        log(f"batch n={n} B={B}: done")
    return out


# --------------------------------------------------------------------------- QP

def qp_problem(n, k):
    """A dense strictly convex QP with n // 2 inequalities (about half active at the
    optimum's neighbourhood) and n // 4 equalities, feasible by construction."""
    rng = np.random.default_rng([RNG_SEED, n, k, 11])
    m, p = n // 2, max(1, n // 4)
    L = rng.standard_normal((n, n)) / np.sqrt(n)
    P = L @ L.T + 0.1 * np.eye(n)
    q = rng.standard_normal(n)
    x0 = rng.standard_normal(n)
    G = rng.standard_normal((m, n))
    h = G @ x0 + np.where(rng.random(m) < 0.5, 0.0, rng.random(m))
    A = rng.standard_normal((p, n))
    return P, q, G, h, A, A @ x0


def bench_qp(args, rng):
    qps = PEERS.get("qpsolvers")
    peers = [s for s in ("quadprog", "daqp", "proxqp", "piqp") if qps and s in qps.available_solvers]
    names = [f"lemke {m}" for m in lemke.METHODS] + peers
    rows = []
    for n in args.qp_sizes:
        for k in range(args.qp_problems):
            P, q, G, h, A, b = qp_problem(n, k)
            calls = {f"lemke {m}": (lambda m=m: lemke.solve_qp(P, q, G, h, A, b, method=m))
                     for m in lemke.METHODS}
            for s in peers:
                calls[s] = lambda s=s: qps.solve_qp(P, q, G, h, A, b, solver=s)
            outs = {k2: f() for k2, f in calls.items()}
            t_fast = []
            for k2, f in calls.items():
                t0 = time.perf_counter()
                f()
                t_fast.append(time.perf_counter() - t0)
            reps = max(3, min(args.max_repeats, math.ceil(args.min_time / max(min(t_fast), 1e-7))))
            times = {k2: [] for k2 in names}
            for _ in range(reps):
                for j in rng.permutation(len(names)):
                    t0 = time.perf_counter()
                    calls[names[j]]()
                    times[names[j]].append(time.perf_counter() - t0)
            xs = {}
            for k2, r in outs.items():
                x = r.x if k2.startswith("lemke") and r.success else (r if not k2.startswith("lemke") else None)
                xs[k2] = None if x is None else np.asarray(x, dtype=float)
            ref = xs.get("quadprog")
            row = dict(n=n, k=k, reps=reps)
            for k2 in names:
                x = xs[k2]
                feas = math.inf if x is None else max(
                    float(np.max(np.abs(A @ x - b))), float(np.max(np.maximum(G @ x - h, 0.0))))
                obj = math.inf if x is None else float(0.5 * x @ P @ x + q @ x)
                dx = math.nan if ref is None or x is None else float(np.max(np.abs(x - ref)))
                dobj = math.nan if ref is None or x is None else abs(obj - float(0.5 * ref @ P @ ref + q @ ref))
                row[k2] = dict(t=statistics.median(times[k2]), ok=x is not None and feas <= 1e-6 * (1 + np.abs(b).max() + np.abs(h).max()),
                               feas=feas, obj=obj, dx=dx, dobj=dobj,
                               pivots=outs[k2].pivots if k2.startswith("lemke") else None)
            rows.append(row)
        log(f"qp n={n}: done")
    return names, rows


# --------------------------------------------------------------------------- report

def fmt_t(s):
    return "–" if s is None or not math.isfinite(s) else bl._t(s)


def solver_names(records):
    names = []
    for rec in records:
        for k in rec["rows"]:
            if k not in names:
                names.append(k)
    return names


def lcp_tables(records):
    names = solver_names(records)
    peers = [s for s in names if not s.startswith("lemke")]
    L = []
    a = L.append
    a("| family | n | problems | " + " | ".join(names) + " | best peer | lemke tableau / best | lemke unrevised / best | pivots (lemke / qe) | wrong answers |")
    a("|---|---:|---:|" + "---:|" * len(names) + "---|---:|---:|---|---|")
    groups = {}
    for rec in records:
        key = (rec["family"], rec["n"] if rec["family"] != "siconos" else rec["problem"])
        groups.setdefault(key, []).append(rec)
    for (family, n), recs in groups.items():
        med = {}
        for s in names:
            ts = [r["rows"][s]["t"] for r in recs if s in r["rows"]]
            med[s] = statistics.median(ts) if ts else None
        ratios = {}
        best_names = []
        for m in ("lemke tableau", "lemke unrevised"):
            rs = []
            for r in recs:
                good = [(r["rows"][p]["t"], p) for p in peers if p in r["rows"] and r["rows"][p]["ok"]]
                if good and m in r["rows"] and r["rows"][m]["ok"]:
                    tb, pb = min(good)
                    rs.append(r["rows"][m]["t"] / tb)
                    best_names.append(pb)
            ratios[m] = statistics.median(rs) if rs else None
        best = max(set(best_names), key=best_names.count) if best_names else "–"
        piv_l = statistics.median(r["rows"]["lemke tableau"]["pivots"] for r in recs)
        piv_q = [r["rows"]["quantecon"]["pivots"] for r in recs if "quantecon" in r["rows"]]
        wrong = ", ".join(f"{s} {sum(r['rows'][s]['wrong'] for r in recs if s in r['rows'])}"
                          for s in names if any(r["rows"].get(s, {}).get("wrong") for r in recs)) or "0"
        failed = [s for s in names if any(s in r["rows"] and not r["rows"][s]["ok"] and not r["rows"][s]["wrong"] for r in recs)]
        label = n if family != "siconos" else f"{n} (n={recs[0]['n']})"
        a(f"| {family} | {label} | {len(recs)} | " + " | ".join(
            fmt_t(med[s]) + ("" if s not in failed else " ✗") for s in names)
          + f" | {best} | " + " | ".join("–" if ratios[m] is None else f"{ratios[m]:.2f}" for m in ("lemke tableau", "lemke unrevised"))
          + f" | {piv_l:g} / {statistics.median(piv_q) if piv_q else '–'} | {wrong} |")
    return L


def targets(records):
    """Ratios to quantecon on the psd family, against the issue's targets."""
    L = ["| n | lemke tableau / quantecon | lemke unrevised / quantecon | target | met |",
         "|---:|---:|---:|---:|---|"]
    psd = {}
    for rec in records:
        if rec["family"] == "psd" and "quantecon" in rec["rows"]:
            psd.setdefault(rec["n"], []).append(rec["rows"])
    for n, rows in sorted(psd.items()):
        r = {m: statistics.median(x[m]["t"] / x["quantecon"]["t"] for x in rows)
             for m in ("lemke tableau", "lemke unrevised") if all(m in x for x in rows)}
        target = 1.0 if n <= 20 else 0.25 if n >= 1000 else 0.5 if n >= 100 else None
        best = min(r.values())
        met = "–" if target is None else ("yes" if best <= target else f"**no** (best {best:.2f})")
        a_t = "–" if target is None else f"{target:g}"
        L.append(f"| {n} | " + " | ".join(f"{r[m]:.2f}" if m in r else "–" for m in ("lemke tableau", "lemke unrevised"))
                 + f" | {a_t} | {met} |")
    return L


def profile_plot(records, qp_names, qp_rows, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        NOTES.append("matplotlib is not installed: no performance-profile plot.")
        return False
    panels = [("Cold LCP solves (all families)", solver_names(records),
               [{s: (r["rows"][s]["t"] if r["rows"][s]["ok"] else math.inf) for s in r["rows"]} for r in records])]
    if qp_rows:
        panels.append(("Convex QPs", qp_names,
                       [{s: (r[s]["t"] if r[s]["ok"] else math.inf) for s in qp_names} for r in qp_rows]))
    fig, axes = plt.subplots(1, len(panels), figsize=(6.5 * len(panels), 4.5), squeeze=False)
    for ax, (title, names, probs) in zip(axes[0], panels):
        taus = np.logspace(0, 7, 400, base=2.0)
        for s in names:
            ratios = []
            for p in probs:
                best = min(v for v in p.values())
                ratios.append(p.get(s, math.inf) / best if math.isfinite(best) else math.inf)
            ratios = np.array(ratios)
            ax.step(taus, [(ratios <= t).mean() for t in taus], where="post", label=s,
                    lw=2.2 if s.startswith("lemke") else 1.4)
        ax.set_xscale("log", base=2)
        ax.set_xlabel("τ (time / best time on the problem)")
        ax.set_ylabel("fraction of problems solved within τ")
        ax.set_title(f"{title}: {len(probs)} problems")
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return True


def section(a, title, text, head, align):
    """A report section: title, a paragraph, and the head of its table (``align``: one
    markdown alignment cell per column)."""
    for line in (f"## {title}", "", text, "", "| " + " | ".join(head) + " |", "|" + "|".join(align) + "|"):
        a(line)


def render(info, args, records, warm, batches, qp_names, qp_rows, fc, plotted, total_s):
    versions = ""
    try:
        from importlib.metadata import version
        for pkg in ("drake", "qpsolvers", "quadprog", "daqp", "proxsuite", "piqp", "matplotlib"):
            try:
                versions += f", {pkg} {version(pkg)}"
            except Exception:  # noqa: BLE001  (not installed)
                pass
    except ImportError:
        pass
    L = bl.report_head("lemke against every installed peer", "harness.py", args, total_s, info,
                       extra_versions=versions)
    a = L.append
    a("Every solver gets the same float64 arrays and its default options; everything is compiled "
      "before timing. For each problem the solvers are called in a random order, drawn afresh "
      "for every repeat; a problem's time is the median over repeats (enough for about "
      f"{args.min_time:g} s of the fastest, at least 3, at most {args.problem_budget:g} s a problem "
      "in all). lemke's times include its Python front end (validation, the check of the answer "
      "on the caller's data, the result object); Drake's include `Solve(prog)` but not building "
      "the program or the solver object (a fresh one per call: `UnrevisedLemkeSolver` keeps the "
      "last basis inside it).")
    a("")
    a("Every answer is checked by this script: residual `max|min(z, Mz + q)|` on the caller's "
      f"data, correct when at most {bl.RESID_RTOL:g} x max(max|M|, max|q|, max|M| max|z|). "
      "✗ marks a solver that failed (reported failure) on some problem of the row; *wrong "
      "answers* count reported successes that fail the check. *best peer*: the fastest correct "
      "non-lemke solver (the most frequent one over the row's problems); the ratios are medians "
      "of per-problem ratios (< 1: lemke faster).")
    a("")
    if NOTES:
        a("Notes:")
        a("")
        for note in NOTES:
            a(f"- {note}")
        a("")
    a("## Targets (random PSD family, ratio to quantecon, same run)")
    a("")
    L.extend(targets(records))
    a("")
    a("## Cold LCP solves")
    a("")
    if plotted:
        a(f"![performance profile]({os.path.basename(args.plot)})")
        a("")
        a("Dolan–Moré performance profile: for each solver the fraction of problems it solved "
          "correctly within a factor τ of the fastest solver on that problem (a failure or a "
          "wrong answer counts as never).")
        a("")
    L.extend(lcp_tables(records))
    a("")
    if batches:
        names = list(batches[0]["t"])
        section(a, "Batches: `solve_lcp_batch` (time per problem)",
                f"Random PSD problems (distinct M per problem), {args.batch_repeats} interleaved "
                f"repeats, medians; {info['usable_cores']} usable cores.",
                ["n", "B", *names, "speed-up on all cores", "quantecon loop / batch", "solved", "wrong"],
                ["---:"] * (len(names) + 6))
        for b in batches:
            t = b["t"]
            sp = t["batch, 1 thread"] / t["batch, all cores"]
            vq = f"{t['loop over quantecon'] / t['batch, all cores']:.1f}x" if "loop over quantecon" in t else "–"
            a(f"| {b['n']} | {b['B']} | " + " | ".join(fmt_t(t[k]) for k in names)
              + f" | {sp:.2f}x | {vq} | {b['solved']}/{b['B']} | {b['wrong']} |")
        a("")
    if warm:
        names = list(warm[0]["t"])
        section(a, "Warm-start sequences",
                f"Problem 0 of the psd family, moved {args.steps} times (each step a fresh standard "
                "normal perturbation times 1e-3 times the rms of the moved data); median time a "
                "step. *lemke warm* passes the previous step's `warm_start`; *drake warm* reuses one "
                "`UnrevisedLemkeSolver` (it keeps the last basis inside); *cold* solves from scratch.",
                ["n", "moved", *names, "lemke warm pivots (median)", "steps with 0 pivots", "wrong or failed"],
                ["---:", "---", *["---:"] * (len(names) + 2), "---"])
        for w in warm:
            bad = ", ".join(f"{k} {v}" for k, v in w["bad"].items() if v) or "0"
            a(f"| {w['n']} | {w['scenario']} | " + " | ".join(fmt_t(w["t"][k]) for k in names)
              + f" | {w['pivots']:g} | {w['zero']}/{w['steps']} | {bad} |")
        a("")
    if qp_rows:
        section(a, "Convex QPs",
                "Dense strictly convex QPs `min 1/2 x'Px + q'x` s.t. `Gx <= h` (n/2 rows), `Ax = b` "
                "(n/4 rows), P = L L' + 0.1 I, feasible by construction. Peers through "
                "`qpsolvers.solve_qp` (its conversion overhead included), default settings. *|Δx|*, "
                "*|Δobj|*: largest difference from quadprog's answer over the problems; *ok*: an "
                "answer with constraint violation <= 1e-6 (relative).",
                ["n", "problems", *qp_names, "lemke tableau / best peer",
                 "max \\|Δx\\| (" + ", ".join(qp_names) + ")", "max \\|Δobj\\| lemke", "ok"],
                ["---:"] * (len(qp_names) + 3) + ["---", "---:", "---"])
        peers = [s for s in qp_names if not s.startswith("lemke")]
        for n in sorted({r["n"] for r in qp_rows}):
            rs = [r for r in qp_rows if r["n"] == n]
            med = {s: statistics.median(r[s]["t"] for r in rs) for s in qp_names}
            rat = [r["lemke tableau"]["t"] / min(r[p]["t"] for p in peers if r[p]["ok"])
                   for r in rs if any(r[p]["ok"] for p in peers)]
            dx = ", ".join(f"{max(r[s]['dx'] for r in rs):.1e}" for s in qp_names)
            dobj = max(r["lemke tableau"]["dobj"] for r in rs)
            ok = ", ".join(f"{sum(r[s]['ok'] for r in rs)}" for s in qp_names)
            a(f"| {n} | {len(rs)} | " + " | ".join(fmt_t(med[s]) for s in qp_names)
              + f" | {statistics.median(rat) if rat else float('nan'):.2f} | {dx} | {dobj:.1e} | {ok} |")
        a("")
    if fc:
        a("## First call (fresh subprocesses)")
        a("")
        med = bl._med
        a("| measurement | median | runs |")
        a("|---|---:|---|")
        a(f"| `import lemke` | {bl._t(med(fc['imports'], 'import_s'))} | "
          + ", ".join(bl._t(x["import_s"]) for x in fc["imports"]) + " |")
        a(f"| first `solve_lcp` (n = 10), first process | {bl._t(med(fc['cold'], 'first_s'))} | "
          + ", ".join(bl._t(x["first_s"]) for x in fc["cold"]) + " |")
        a(f"| first `solve_lcp`, second process | {bl._t(med(fc['warm'], 'first_s'))} | "
          + ", ".join(bl._t(x["first_s"]) for x in fc["warm"]) + " |")
        a(f"| second `solve_lcp` (same process) | {bl._t(med(fc['warm'], 'second_s'))} | "
          + ", ".join(bl._t(x["second_s"]) for x in fc["warm"]) + " |")
        a("")
    return "\n".join(L) + "\n"


# --------------------------------------------------------------------------- main

def main(argv=None):
    p, argv = bl.report_parser(__doc__, "RESULTS.md", argv)
    p.add_argument("--quick", action="store_true", help="small sizes, few problems (a few minutes)")
    p.add_argument("--plot", default=str(HERE / "performance_profile.png"))
    p.add_argument("--json", default=None, help="also write the raw numbers here")
    p.add_argument("--min-time", type=float, default=None)
    p.add_argument("--max-repeats", type=int, default=20000)
    p.add_argument("--problem-budget", type=float, default=None,
                   help="seconds of timed calls per problem, all solvers together")
    p.add_argument("--max-call", type=float, default=None,
                   help="a solver slower than this (seconds a call, median) at some n is not run at larger n")
    p.add_argument("--first-call-runs", type=int, default=None)
    p.add_argument("--skip", nargs="*", default=[], choices=["lcp", "warm", "batch", "qp", "first-call"])
    p.add_argument("--families", nargs="*", default=None, metavar="NAME[:N,N...]",
                   help="LCP families to run, each optionally with its sizes (psd:100,300)")
    args = p.parse_args(argv)
    args.argv = list(argv)
    q = args.quick
    args.min_time = args.min_time if args.min_time is not None else (0.05 if q else 0.2)
    args.problem_budget = args.problem_budget if args.problem_budget is not None else (2.0 if q else 8.0)
    args.max_call = args.max_call if args.max_call is not None else (0.3 if q else 0.2)
    args.first_call_runs = args.first_call_runs if args.first_call_runs is not None else (1 if q else 3)
    fams = {
        "psd": [5, 20, 100, 300] if q else [5, 20, 50, 100, 300, 1000, 2000],
        "pmatrix": [5, 20, 100] if q else [5, 20, 100, 300],
        "contact": [5, 20, 100] if q else [5, 20, 100, 300],
        "murty": [4, 8] if q else [4, 8, 12],
        "siconos": [None],
    }
    if args.families is not None:
        chosen = {}
        for spec in args.families:
            name, _, sizes = spec.partition(":")
            if name not in fams:
                p.error(f"unknown family {name!r}; choose from {', '.join(fams)}")
            chosen[name] = [int(v) for v in sizes.split(",")] if sizes else fams[name]
        fams = chosen
    args.families = fams
    args.warm_sizes = [100] if q else [100, 300]
    args.steps = 10 if q else 30
    args.batches = [(5, 2000), (20, 500), (100, 50)] if q else [(5, 4000), (20, 2000), (100, 200), (300, 20)]
    args.batch_repeats = 3 if q else 7
    args.qp_sizes = [10, 50] if q else [10, 50, 200]
    args.qp_problems = 2 if q else 5

    t0 = time.perf_counter()
    rng = np.random.default_rng(RNG_SEED)
    info = bl.machine_info()
    for n in (3, 10):  # compile everything before timing
        M, qq = bl.make_problem(n, 10_000)
        for m in lemke.METHODS:
            lemke.solve_lcp(M, qq, method=m)
            lemke.solve_lcp_batch(M, qq[None], method=m)
    records = bench_lcp_families(args, rng) if "lcp" not in args.skip else []
    warm = warm_sequences(args, rng) if "warm" not in args.skip else []
    batches = bench_batches(args, rng) if "batch" not in args.skip else []
    qp_names, qp_rows = bench_qp(args, rng) if "qp" not in args.skip else ([], [])
    fc = bl.first_call(args.first_call_runs, log) if "first-call" not in args.skip and args.first_call_runs else None
    plotted = bool(records) and profile_plot(records, qp_names, qp_rows, args.plot)
    bl.mark_end(info)
    if args.json:  # before rendering, so that the numbers survive a bug in the report
        import json
        Path(args.json).write_text(json.dumps(dict(records=records, warm=warm, batches=batches,
                                                   qp=qp_rows, first_call=fc), default=str, indent=1))
    text = render(info, args, records, warm, batches, qp_names, qp_rows, fc, plotted,
                  time.perf_counter() - t0)
    bl.publish(text, args.out, log)


if __name__ == "__main__":
    main()
