"""Random dense strictly convex QPs: lemke.solve_qp (its fused path for a positive definite
P) against daqp called natively and through qpsolvers, and quadprog through qpsolvers,
interleaved in one run.

Three families (a fourth on request), each at n = 10, 100, 300 by default: P = B B'/n + I/10
(B n x n Gaussian);

- ``mixed``: n/2 inequalities and n/4 equalities (Gaussian rows) that a random point x0
  satisfies, the inequalities with a slack uniform in [0, 1] there;
- ``ineq``: the same n/2 inequalities, no equalities;
- ``box``: bounds only, x0 -/+ uniform [0.1, 1];
- ``rows`` (not run by default): 20 n inequalities as in ``ineq``, many more than the
  variables (the kernel's step 7, the LCP in factored form).

q is Gaussian with standard deviation 3, so that a good share of the constraints is active
at the optimum.  "daqp native" times ``daqp.solve`` alone on arguments built beforehand
(qpsolvers' own conversion, not timed); the others are timed on the full call.  Each
problem is solved ``--reps`` times, so from its second call on lemke's kernel reuses the
factors of P, A and G it kept (its per-thread factor cache: the same matrices again);
"lemke, fresh factors" times the same call after an untimed 2-variable QP has evicted
them (the cost of a first solve of new matrices).  lemke's
old path (the KKT-MLCP, what solve_qp did before the fused path; ``--old``) is timed by
calling it directly.  Every answer is compared with quadprog's x.

    python benchmarks/bench_qp_fast.py [--sizes 10 100 300] [--families mixed ineq box]
        [--problems 5] [--reps 7] [--old]
"""
from __future__ import annotations

import os
import statistics
import sys
import time
from ctypes import c_int

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from bench_lcp import mark_end, machine_info, publish, report_head, report_parser, time_interleaved  # noqa: E402

import lemke  # noqa: E402
from lemke import _qp  # noqa: E402


def make_qp(family, n, rng):
    """``(P, q, G, h, A, b, lb, ub)`` of the family (see the module docstring)."""
    B = rng.standard_normal((n, n))
    P = B @ B.T / n + 0.1 * np.eye(n)
    q = 3.0 * rng.standard_normal(n)
    x0 = rng.standard_normal(n)
    G = h = A = b = lb = ub = None
    if family in ("mixed", "ineq", "rows"):
        m = 20 * n if family == "rows" else max(1, n // 2)
        G = rng.standard_normal((m, n))
        h = G @ x0 + rng.uniform(0.0, 1.0, m)
    if family == "mixed":
        p = max(1, n // 4)
        A = rng.standard_normal((p, n))
        b = A @ x0
    if family == "box":
        lb = x0 - rng.uniform(0.1, 1.0, n)
        ub = x0 + rng.uniform(0.1, 1.0, n)
    return P, q, G, h, A, b, lb, ub


def daqp_args(P, q, G, h, A, b, lb, ub):
    """daqp.solve's arguments as qpsolvers builds them: bounds first, then inequalities,
    then equalities (sense 5)."""
    n = q.size
    ms = n if lb is not None or ub is not None else 0
    mi = 0 if G is None else G.shape[0]
    me = 0 if A is None else A.shape[0]
    upper = np.full(ms + mi + me, 1e30)
    lower = np.full(ms + mi + me, -1e30)
    if ms:
        if ub is not None:
            upper[:ms] = ub
        if lb is not None:
            lower[:ms] = lb
    if mi:
        upper[ms:ms + mi] = h
    if me:
        upper[ms + mi:] = b
        lower[ms + mi:] = b
    rows = [a for a in (G, A) if a is not None]
    Atot = np.ascontiguousarray(np.vstack(rows)) if rows else np.zeros((0, n))
    sense = np.zeros(ms + mi + me, dtype=c_int)
    sense[ms + mi:] = 5
    return P, q, Atot, upper, lower, sense


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-qp-fast.md", argv)
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 300])
    parser.add_argument("--families", nargs="+", default=["mixed", "ineq", "box"])
    parser.add_argument("--problems", type=int, default=5)
    parser.add_argument("--reps", type=int, default=7)
    parser.add_argument("--old", action="store_true", help="also time the KKT-MLCP path")
    args = parser.parse_args(argv)
    args.argv = argv
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    t_start = time.perf_counter()
    info = machine_info()
    import daqp
    import qpsolvers
    rng = np.random.default_rng(2026)
    for fam in args.families:  # compile / load the kernels outside the timing
        lemke.solve_qp(*make_qp(fam, 4, rng))

    def old_path(prob):
        qp = _qp._QP(*prob)
        return _qp._solve(qp, "tableau", lemke.Options(), None, True)

    names = ["lemke", "daqp native", "daqp (qpsolvers)", "quadprog (qpsolvers)",
             "lemke, fresh factors"]
    if args.old:
        names.append("lemke old path")
    tiny = (np.eye(2), np.array([1.0, -1.0]))

    def fresh(prob):
        """(result, seconds) of solve_qp after the factor cache was evicted (untimed)."""
        lemke.solve_qp(*tiny)
        t0 = time.perf_counter()
        r = lemke.solve_qp(*prob)
        return r, time.perf_counter() - t0
    rows = []
    for fam in args.families:
        for n in args.sizes:
            med = {s: [] for s in names}
            dev = {s: 0.0 for s in names}
            wrong = {s: 0 for s in names}
            pivots, fast = [], 0
            for _ in range(args.problems):
                prob = make_qp(fam, n, rng)
                da = daqp_args(*prob)
                calls = [
                    lambda: lemke.solve_qp(*prob),
                    lambda: daqp.solve(*da),
                    lambda: qpsolvers.solve_qp(*prob, solver="daqp"),
                    lambda: qpsolvers.solve_qp(*prob, solver="quadprog"),
                    lambda: fresh(prob),
                ]
                if args.old:
                    calls.append(lambda: old_path(prob))
                times, results = time_interleaved(calls, args.reps, keep_results=True, rng=rng)
                times[4] = [dt for _, dt in results[4]]  # (its own timing, eviction left out)
                results = [[r[-1]] for r in results]
                results[4] = [results[4][0][0]]
                res = results[0][0]
                pivots.append(res.pivots)
                fast += res.certificate is None and res.success
                xs = {"lemke": res.x if res.success else None,
                      "daqp native": results[1][0][0] if results[1][0][2] == 1 else None,
                      "daqp (qpsolvers)": results[2][0], "quadprog (qpsolvers)": results[3][0],
                      "lemke, fresh factors": results[4][0].x if results[4][0].success else None}
                if args.old:
                    xs["lemke old path"] = results[5][0].x if results[5][0].success else None
                ref = xs["quadprog (qpsolvers)"]
                for j, s in enumerate(names):
                    med[s].append(statistics.median(times[j]))
                    if xs[s] is None or ref is None:
                        wrong[s] += 1
                        continue
                    d = float(np.max(np.abs(xs[s] - ref)))
                    dev[s] = max(dev[s], d)
                    wrong[s] += d > 1e-6 * max(1.0, float(np.max(np.abs(ref))))
            t_daqp = statistics.median(med["daqp native"])
            for s in names:
                t = statistics.median(med[s])
                rows.append((fam, n, s, t, t / t_daqp, dev[s], wrong[s],
                             int(np.median(pivots)) if s == "lemke" else None))
            log(f"{fam} n = {n} done ({os.getloadavg()[0]:.2f} load)")
    mark_end(info)
    versions = f", qpsolvers {qpsolvers.__version__}, daqp {getattr(daqp, '__version__', '?')}"
    L = report_head("Dense strictly convex QPs: the fused path against daqp and quadprog",
                    "bench_qp_fast.py", args, time.perf_counter() - t_start, info,
                    extra_versions=versions)
    L += [f"{args.problems} problems per family and size, {args.reps} interleaved repeats each "
          "(random order); median over problems of each problem's median time.  Ratio: to "
          "daqp native.  Deviation: max |x - x_quadprog|; wrong: off quadprog's x by more than "
          "1e-6 (relative) or no answer.", "",
          "| family | n | solver | median time | / daqp native | max deviation | wrong | lemke pivots |",
          "|---|---:|---|---:|---:|---:|---:|---:|"]
    for fam, n, s, t, ratio, d, w, piv in rows:
        L.append(f"| {fam} | {n} | {s} | {t * 1e3:.3f} ms | {ratio:.2f} | {d:.1e} | {w} | "
                 f"{'' if piv is None else piv} |")
    publish("\n".join(L) + "\n", args.out, log)


if __name__ == "__main__":
    main()
