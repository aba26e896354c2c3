#!/usr/bin/env python
"""The 3-D contact scene of ``examples/contact_3d.py``: lemke (cold, warm, islands) against
DART's Dantzig solver, quantecon and a projected Gauss-Seidel on the same step problems.

Usage::

    python benchmarks/bench_contact_3d.py [--quick] [--steps 1000] [--bodies 20] [--repeats 3]
        [--qe-every 20] [--note TEXT] [--out benchmarks/RESULTS-contact-3d.md]

Needs ``dartpy`` and ``quantecon`` (a missing one is reported, not fatal); numba for the
PGS loop.  ``--quick`` is 100 steps of 8 spheres, 2 repeats.

Problems
    The scene is run once (``contact_3d.simulate``, lemke warm-started by label, every
    answer checked) and every island of every step recorded: the box LCP (A, b, lo, hi,
    findex: a normal row and two tangent rows per contact, the tangents' findex at the
    normal row, lo/hi = -+mu), its row labels and the warm start that the run carried to it
    by label from the previous step.  Then each solver solves the recorded islands; a
    step's time is the sum over its islands, measured ``--repeats`` times with the solvers
    interleaved in a random order drawn afresh for every step and repeat, and the step's
    figure is the median of its repeats.

Solvers
    *lemke cold*: ``solve_blcp(A, b, lo, hi, findex=findex)`` per island.  *lemke warm*: the
    same with the recorded warm start (the previous step's final bases carried by label
    through contact changes, merges and splits of islands: ``BoxWarmStartBatch.relabel`` in
    ``contact_3d.carry``), and a cold solve after a warm one that does not end SOLVED,
    counted in its time.  *lemke islands, one call*: the step's islands in one
    ``solve_blcp_many`` call with the same warm starts (the step's ``BoxWarmStartBatch``
    passed whole), ``workers=1`` (one thread, as every other solver here), and the same cold
    re-solve of an island that does not end SOLVED.  *DART Dantzig*: DART's ``DantzigBoxedLcpSolver``
    (ODE's Dantzig with the friction index) through ctypes, exactly as ``bench_engines.py``
    calls it (padded row stride, b = -q, fresh copies outside the timed region).  *quantecon*:
    ``quantecon.optimize.lcp_lemke`` takes no bounds, so it gets the box LCP as the
    equivalent standard LCP (Stewart-Trinkle: a tangent row becomes beta+ and beta- >= 0 and
    one lambda row, the extended problem lemke solves internally, built here in numpy outside
    the timed region) and its z is mapped back (z_t = beta+ - beta-); it is timed on every
    ``--qe-every``-th step only (its dense tableau takes about 0.1 s a step on the large
    islands).  *PGS*: projected Gauss-Seidel written here as a numba-compiled loop (the
    method most engines use; ODE's and DART's PGS, Bullet's sequential impulse): rows in
    order, ``z_i <- clip(z_i - (A z + b)_i / A_ii, lo_i', hi_i')`` with a friction row's
    bounds at the current normal impulse, a fixed number of sweeps (30, DART's default, and
    300), from zero (*cold*) and from the previous step's PGS answer carried by label
    (*warm*, as engines warm-start).

Accuracy
    Every answer is checked here with numpy: the natural-map residual ``max |z - clip(z - w,
    lo', hi')|`` with the coupled bounds at the answer (``lo'_i = lo_i z_f``), relative to
    ``max(1, |b|, |A| |z|)``: ``bench_engines.coupled_residual``.  A step is *right* when
    every island's residual is at most 1e-8, whatever its solver reported.
"""
from __future__ import annotations

import os

BLAS_THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
if __name__ == "__main__":
    for _var in BLAS_THREAD_VARS:  # as bench_engines: one BLAS thread, like the engines
        os.environ.setdefault(_var, "1")

import gc  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "examples"))

import bench_engines as be  # noqa: E402  (DART through ctypes, the coupled residual)
import bench_lcp as bl  # noqa: E402  (machine description, report head)
import contact_3d as c3  # noqa: E402  (the scene)

import lemke  # noqa: E402

RIGHT = 1e-8
PGS_SWEEPS = (30, 300)


# --------------------------------------------------------------------------- PGS


def _pgs_kernel():
    from numba import njit

    @njit(cache=False, fastmath=False)
    def pgs(A, b, lo, hi, findex, z, sweeps):
        n = b.size
        for _ in range(sweeps):
            for i in range(n):
                r = b[i]
                for j in range(n):
                    r += A[i, j] * z[j]
                zi = z[i] - r / A[i, i]
                f = findex[i]
                if f >= 0:
                    lo_i = lo[i] * z[f]
                    hi_i = hi[i] * z[f]
                else:
                    lo_i = lo[i]
                    hi_i = hi[i]
                z[i] = min(max(zi, lo_i), hi_i)
        return z

    return pgs


# --------------------------------------------------------------------------- quantecon


def extended_lcp(A, b, lo, hi, findex):
    """The standard LCP (M, q) equivalent to the friction box LCP (every row lo = 0, hi =
    inf after the extension), rows ordered as ``contact_3d.extended_labels``: the caller's
    rows (a friction row as beta+), then beta- and lambda per friction row."""
    n = b.size
    F = np.flatnonzero(findex >= 0)
    nf = F.size
    if np.any(lo[findex < 0] != 0.0) or np.any(np.isfinite(hi[findex < 0])):
        raise ValueError("ordinary rows must be 0 <= z")
    N = n + 2 * nf
    M = np.zeros((N, N))
    M[:n, :n] = A
    M[:n, n:n + nf] = -A[:, F]
    M[n:n + nf, :n] = -A[F, :]
    M[n:n + nf, n:n + nf] = A[np.ix_(F, F)]
    lam = n + nf + np.arange(nf)
    M[F, lam] = 1.0
    M[n + np.arange(nf), lam] = 1.0
    M[lam, findex[F]] = hi[F]
    M[lam, F] = -1.0
    M[lam, n + np.arange(nf)] = -1.0
    q = np.concatenate([b, -b[F], np.zeros(nf)])
    return M, q, F


def from_extended(x, n, F):
    z = x[:n].copy()
    z[F] -= x[n:n + F.size]
    return z


# --------------------------------------------------------------------------- the steps


def record(bodies, steps, seed=0):
    rec = []
    hist = c3.simulate(bodies, steps, seed=seed, cold=False, record=rec)
    by_step = [[] for _ in range(steps)]
    for r in rec:
        by_step[r["step"]].append(r)
    return hist, by_step


def pgs_warm_starts(by_step, pgs, sweeps):
    """The PGS warm chain, untimed: each island's start is the previous step's PGS answer of
    the rows with the same label (0 for a new row)."""
    prev = {}
    out = []
    for isl in by_step:
        starts, now = [], {}
        for r in isl:
            x0 = np.array([prev.get(lab, 0.0) for lab in r["labels"].tolist()])
            starts.append(x0)
            z = pgs(r["A"], r["b"], r["lo"], r["hi"], r["findex"], x0.copy(), sweeps)
            now.update(zip(r["labels"].tolist(), z.tolist()))
        prev = now
        out.append(starts)
    return out


def islands_in_one_call():
    """The library's batched box solver, if it has one (None: not on this version)."""
    return getattr(lemke, "solve_blcp_many", None)


def step_solvers(isl, dart, pgs, pgs_starts, qe, qe_problems):
    """name -> prep for one step; prep() gives (call, get); get(out) -> [(reported_ok, z)]."""
    out = {}

    def lem(warm):
        def call():
            res = []
            for r in isl:
                ws = r["carried"] if warm else None
                x = lemke.solve_blcp(r["A"], r["b"], r["lo"], r["hi"], findex=r["findex"], warm_start=ws)
                if warm and not x.success and ws is not None:
                    x = lemke.solve_blcp(r["A"], r["b"], r["lo"], r["hi"], findex=r["findex"])
                res.append(x)
            return res
        return lambda: (call, lambda res: [(x.success, np.asarray(x.z)) for x in res])

    out["lemke cold"] = lem(False)
    out["lemke warm"] = lem(True)
    many = islands_in_one_call()
    if many is not None:
        args = ([r["A"] for r in isl], [r["b"] for r in isl], [r["lo"] for r in isl], [r["hi"] for r in isl])
        kw = dict(findex=[r["findex"] for r in isl], warm_start=isl[0]["batch"], workers=1)

        def one_call():
            res = many(*args, **kw)
            if res.success.all():
                return list(res)
            return [x if x.success else lemke.solve_blcp(r["A"], r["b"], r["lo"], r["hi"], findex=r["findex"])
                    for x, r in zip(res, isl)]
        out["lemke islands, one call"] = lambda: (one_call, lambda res: [(x.success, np.asarray(x.z)) for x in res])
    if dart is not None:
        def dantzig():
            calls = [dart.prepare("DantzigBoxedLcpSolver", r["A"], r["b"], r["lo"], r["hi"], r["findex"]) for r in isl]
            return (lambda: [c() for c, _ in calls],
                    lambda oks: [(bool(ok), x.copy()) for ok, (_, x) in zip(oks, calls)])
        out["DART Dantzig"] = dantzig
    if pgs is not None:
        for sweeps in PGS_SWEEPS:
            for warm in (False, True):
                def prep(sweeps=sweeps, warm=warm):
                    x0 = [(pgs_starts[sweeps][k].copy() if warm else np.zeros(r["b"].size)) for k, r in enumerate(isl)]
                    return (lambda: [pgs(r["A"], r["b"], r["lo"], r["hi"], r["findex"], x, sweeps) for r, x in zip(isl, x0)],
                            lambda zs: [(True, z) for z in zs])
                out[f"PGS {sweeps} sweeps{' warm' if warm else ''}"] = prep
    if qe is not None and qe_problems is not None:
        def quantecon():
            return (lambda: [qe(M, q) for M, q, _ in qe_problems],
                    lambda res: [(bool(x.success), from_extended(x.z, r["b"].size, F))
                                 for x, r, (_, _, F) in zip(res, isl, qe_problems)])
        out["quantecon lcp_lemke"] = quantecon
    return out


def time_step(preps, rng, repeats):
    names = list(preps)
    times = {k: [] for k in names}
    last = {}
    pc = time.perf_counter
    for _ in range(repeats):
        for j in rng.permutation(len(names)):
            call, get = preps[names[j]]()
            s = pc()
            out = call()
            e = pc()
            times[names[j]].append(e - s)
            last[names[j]] = get(out)
    return {k: statistics.median(v) for k, v in times.items()}, last


def run(args):
    rng = np.random.default_rng(5)
    missing = []
    try:
        dart = be.Dart()
    except Exception as e:  # noqa: BLE001  (reported, not fatal)
        dart = None
        missing.append(f"DART ({type(e).__name__}: {e})")
    try:
        from quantecon.optimize import lcp_lemke as qe
        qe(np.eye(2), -np.ones(2))  # compile
    except ImportError as e:
        qe = None
        missing.append(f"quantecon ({e})")
    try:
        pgs = _pgs_kernel()
        pgs(np.eye(2), -np.ones(2), np.zeros(2), np.full(2, np.inf), np.array([-1, -1]), np.zeros(2), 1)
    except ImportError as e:
        pgs = None
        missing.append(f"numba, for the PGS loop ({e})")
    if islands_in_one_call() is None:
        missing.append("lemke islands in one call: this lemke has no batched box solver "
                       "(`solve_blcp_many`); the hook is `islands_in_one_call()`")
    t0 = time.perf_counter()
    hist, by_step = record(args.bodies, args.steps)
    t_rec = time.perf_counter() - t0
    pgs_starts = {s: pgs_warm_starts(by_step, pgs, s) for s in PGS_SWEEPS} if pgs else None
    per = {}  # name -> list of dict per step
    gc.collect()
    gc.disable()
    try:
        for s, isl in enumerate(by_step):
            if not isl:
                continue
            qe_problems = None
            if qe is not None and s % args.qe_every == 0:
                qe_problems = [extended_lcp(r["A"], r["b"], r["lo"], r["hi"], r["findex"]) for r in isl]
            starts = {k: v[s] for k, v in pgs_starts.items()} if pgs_starts else None
            med, ans = time_step(step_solvers(isl, dart, pgs, starts, qe, qe_problems), rng, args.repeats)
            for name, t in med.items():
                res = [be.coupled_residual(r["A"], r["b"], r["lo"], r["hi"], r["findex"], z)
                       for r, (_, z) in zip(isl, ans[name])]
                per.setdefault(name, []).append(dict(
                    step=s, t=t, res=max(res), ok=all(ok for ok, _ in ans[name]),
                    rows=sum(r["b"].size for r in isl), changed=hist["changed"][s]))
    finally:
        gc.enable()
    return hist, per, missing, t_rec


# --------------------------------------------------------------------------- report


def summarize(per):
    cold = {p["step"]: p["t"] for p in per["lemke cold"]}
    rows = []
    for name, recs in per.items():
        t = np.array([p["t"] for p in recs])
        base = np.array([cold[p["step"]] for p in recs])
        right = np.array([p["res"] <= RIGHT for p in recs])
        rows.append(dict(
            solver=name, steps=len(recs), right=int(right.sum()),
            said_ok_wrong=sum(p["ok"] and p["res"] > RIGHT for p in recs),
            said_fail=sum(not p["ok"] for p in recs),
            total=float(t.sum()), vs_cold=float(t.sum() / base.sum()), med=float(np.median(t)),
            med_res=float(np.median([p["res"] for p in recs])), max_res=float(max(p["res"] for p in recs))))
    return rows


def versus_dantzig(per):
    """On the steps where Dantzig's answer is right: per-step times against it."""
    if "DART Dantzig" not in per:
        return None
    d = {p["step"]: p for p in per["DART Dantzig"]}
    good = sorted(s for s, p in d.items() if p["res"] <= RIGHT)
    out = dict(steps=len(good), of=len(d), rows=[])
    if not good:
        return out
    for name in ("lemke warm", "lemke cold", "lemke islands, one call"):
        if name not in per:
            continue
        mine = {p["step"]: p for p in per[name]}
        ratio = [mine[s]["t"] / d[s]["t"] for s in good]
        out["rows"].append(dict(solver=name, med_ratio=statistics.median(ratio),
                                not_slower=sum(r <= 1.0 for r in ratio),
                                med=statistics.median(mine[s]["t"] for s in good),
                                dantzig=statistics.median(d[s]["t"] for s in good),
                                rows=(min(mine[s]["rows"] for s in good), max(mine[s]["rows"] for s in good))))
    return out


def uptime():
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unavailable"


def render(info, args, total_s, hist, per, missing, t_rec, up0, up1):
    s = c3.summary(hist)
    L = bl.report_head("3-D contact scene: lemke vs DART's Dantzig, quantecon and PGS on the same step problems",
                       "bench_contact_3d.py", args, total_s, info,
                       extra_versions=f", dartpy {be.version('dartpy')}",
                       extra_lines=["- BLAS threads: " + ", ".join(f"`{v}={os.environ.get(v)}`" for v in BLAS_THREAD_VARS),
                                    f"- `uptime` at the start: `{up0}`", f"- `uptime` at the end: `{up1}`"])
    L += be.method_section(__doc__)
    L += [f"- Not timed: {m}." for m in missing]
    L += ["", "## The scene", "",
          f"{args.bodies} spheres, {s['steps']} steps of 10 ms (recorded in {t_rec:.1f} s); "
          f"{s['solved']} steps with contacts, {s['rows'][0]}–{s['rows'][1]} rows a step; "
          f"{s['changed']} steps where the contact set changed; {sum(hist['islands'])} islands in all "
          f"(up to {max(hist['islands'])} a step).  Every island's recorded answer (lemke warm) passed the "
          f"example's numpy check (worst residual {s['worst']:.1e}); lemke's own check refused "
          f"{s['refused']} of them (see below).", "",
          "## Per step", "",
          "*time*: sum over the steps of each step's median (all its islands); *vs cold*: that sum over "
          "lemke cold's on the same steps; *right*: steps whose every island has residual <= 1e-8; "
          "*said ok, wrong*: the solver reported success on a step that is not right; *said failed*: "
          "it reported a failure on some island.", "",
          "| solver | steps | time, sum | vs lemke cold | median per step | right | said ok, wrong | "
          "said failed | median residual | max residual |",
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in summarize(per):
        L.append(f"| {r['solver']} | {r['steps']} | {bl._t(r['total'])} | {r['vs_cold']:.3f} | {bl._t(r['med'])} | "
                 f"{r['right']}/{r['steps']} | {r['said_ok_wrong']} | {r['said_fail']} | {r['med_res']:.1e} | "
                 f"{r['max_res']:.1e} |")
    if "lemke warm" in per:
        w = per["lemke warm"]
        cold = {p["step"]: p["t"] for p in per["lemke cold"]}
        for label, sel in (("steps where the contact set changed", True), ("steps where it did not", False)):
            ws = [p for p in w if p["changed"] == sel]
            if ws:
                L.append(f"- lemke warm on {label} ({len(ws)}): {bl._t(sum(p['t'] for p in ws))} against cold's "
                         f"{bl._t(sum(cold[p['step']] for p in ws))} ({sum(p['t'] for p in ws) / sum(cold[p['step']] for p in ws):.3f}).")
        L.append(f"- pivots in the recording run: warm {s['warm_pivots']}, and {sum(1 for p in hist['pivots'] if p == 0)} "
                 f"of {s['steps']} steps with no pivot.")
    vd = versus_dantzig(per)
    if vd is not None:
        L += ["", "## Against DART's Dantzig where it is right", "",
              f"Dantzig's answer is right (residual <= 1e-8) on {vd['steps']} of {vd['of']} steps; on those:", "",
              "| solver | rows | median per step | Dantzig's median | median ratio to Dantzig | steps not slower |",
              "|---|---|---:|---:|---:|---:|"]
        for r in vd["rows"]:
            L.append(f"| {r['solver']} | {bl.fmt_range(r['rows'])} | {bl._t(r['med'])} | {bl._t(r['dantzig'])} | "
                     f"{r['med_ratio']:.2f} | {r['not_slower']}/{vd['steps']} |")
    L.append("")
    return "\n".join(L)


def main(argv=None):
    parser, argv = bl.report_parser(__doc__, "RESULTS-contact-3d.md", argv)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--bodies", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--qe-every", type=int, default=20)
    args = parser.parse_args(argv)
    args.argv = argv
    if args.quick:
        args.steps, args.bodies, args.repeats, args.qe_every = 100, 8, 2, 5
    info = bl.machine_info()
    up0 = uptime()
    t0 = time.perf_counter()
    hist, per, missing, t_rec = run(args)
    bl.mark_end(info)
    text = render(info, args, time.perf_counter() - t0, hist, per, missing, t_rec, up0, uptime())
    bl.publish(text, args.out, lambda m: print(m, file=sys.stderr))


if __name__ == "__main__":
    main()
