#!/usr/bin/env python
"""The C++ core against quantecon, in one process.

Usage::

    python benchmarks/bench_core.py [--sizes 1 3 12 24 48 100 300 1000] [--budget 2.0]
                                    [--out benchmarks/RESULTS-core.md]

For each n, a random monotone LCP (``M = A A' + 0.1 I``, ``q ~ N(0, I)``, seeded) is solved
by ``lemke.solve_lcp`` two ways and by quantecon, interleaved in a random order each
repeat, each answer checked (``w = M z + q`` recomputed here):

- **core**: ``solve_lcp``'s Python fast path with the C++ core's first run (the tableau);
- **shipped**: the plain call ``solve_lcp(M, q)`` as a user makes it (the native front,
  ``src/python_front.cpp``, one native call);
- **quantecon**: ``quantecon.optimize.lcp_lemke`` (cold);

and, in the same rounds, the unrevised method and the box LCP engine (lo = 0, hi = inf) on
the same problem, both in the core.

Then the 0-pivot warm re-solve (q moved by 1e-9, the old basis still solves it), timed in
the same interleaved rounds as the cold calls again (its ratio compares one time window),
and the fixed cost at n = 1 with q >= 0 (no pivot) and q < 0 (one pivot), with a batch of
one (``solve_lcp_many([M], [q])``) beside ``solve_lcp(M, q)``.  The table
gives medians in microseconds (each repeat times a batch of calls, so small n is not timer
noise) and the ratios; the machine's load is recorded at both ends.

The former column of the kernel the core was ported from (put back into the same front, in
the same process) went with that kernel; RESULTS-core.md's rows of it were measured at commit
129530f.  To compare with an older version, run this script in that version's checkout (its
own build) on the same machine.
"""
from __future__ import annotations

import os
import random
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_lcp import machine_info, mark_end, report_head, report_parser  # noqa: E402

import lemke  # noqa: E402
from lemke import _lcp  # noqa: E402


def same_wrapper(run, a1, i1):
    """``run`` behind one Python wrapper that maps None to ``a1``/``i1`` (the calling
    convention the former kernel rows needed; kept so the core row measures what it
    measured)."""
    def call(method, M, q, d, beta, k, mp, pt, tt, tol, buf, basic):
        return run(method, M, q, a1 if d is None else d, i1 if beta is None else beta, k, mp, pt,
                   tt, tol, buf, i1 if basic is None else basic)
    return call


def with_kernel(run, f):
    """f() with solve_lcp's tableau path calling ``run``."""
    saved = _lcp._ENTRY.get("tableau"), _lcp._FIRST_RUN, _lcp._FRONT
    _lcp._ENTRY["tableau"], _lcp._FIRST_RUN, _lcp._FRONT = run, run, _no_front
    try:
        return f()
    finally:
        _lcp._ENTRY["tableau"], _lcp._FIRST_RUN, _lcp._FRONT = saved


def _no_front(M, q, ws, beta):
    """The native front declining: solve_lcp's Python fast path runs (with_kernel's kernel)."""
    return None


def checked(M, q, z):
    w = M @ z + q
    scale = max(1.0, np.abs(q).max()) * max(1.0, np.abs(z).max())
    assert (z >= -1e-9 * scale).all() and (w >= -1e-7 * scale).all()
    assert np.abs(z * w).max() <= 1e-7 * scale * max(1.0, np.abs(M).max())


def problem(n, rng):
    A = rng.standard_normal((n, n))
    q = rng.standard_normal(n)
    q[0] = -1.0 - abs(q[0])  # at least one negative entry: never the trivial z = 0
    return A @ A.T + 0.1 * np.eye(n), q


def time_calls(calls, budget):
    """{name: median seconds per call} of interleaved repeats within ``budget`` seconds."""
    names = list(calls)
    per = {k: [] for k in names}
    # calls per repeat so that one repeat of each takes about 2 ms
    reps = {}
    for k in names:
        t = time.perf_counter()
        calls[k]()
        dt = max(time.perf_counter() - t, 1e-7)
        reps[k] = max(1, int(2e-3 / dt))
    end = time.perf_counter() + budget
    rounds = 0
    while rounds < 5 or (time.perf_counter() < end and rounds < 2000):
        random.shuffle(names)
        for k in names:
            f, r = calls[k], reps[k]
            t = time.perf_counter()
            for _ in range(r):
                f()
            per[k].append((time.perf_counter() - t) / r)
        rounds += 1
    return {k: float(np.median(v)) for k, v in per.items()}


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-core.md", argv)
    parser.add_argument("--sizes", type=int, nargs="*", default=[1, 3, 12, 24, 48, 100, 300, 1000])
    parser.add_argument("--budget", type=float, default=2.0, help="seconds per size and table")
    args = parser.parse_args(argv)
    args.argv = argv
    info = machine_info()
    t_start = time.time()
    from quantecon.optimize import lcp_lemke

    core = same_wrapper(_lcp._FIRST_RUN, None, None)  # (the core takes None itself)
    rng = np.random.default_rng(20261128)
    rows_cold, rows_warm = [], []
    for n in args.sizes:
        M, q = problem(n, rng)
        r = lemke.solve_lcp(M, q)
        assert r.success
        checked(M, q, r.z)
        qe = lcp_lemke(M, q)
        checked(M, q, qe.z)
        inf = np.full(n, np.inf)
        zero = np.zeros(n)
        rb = lemke.solve_blcp(M, q, zero, inf)
        assert rb.success
        checked(M, q, rb.z)
        t = time_calls({
            "unrevised": lambda: lemke.solve_lcp(M, q, method="unrevised"),
            "box": lambda: lemke.solve_blcp(M, q, zero, inf),
            "core": lambda: with_kernel(core, lambda: lemke.solve_lcp(M, q)),
            "front": lambda: lemke.solve_lcp(M, q),
            "quantecon": lambda: lcp_lemke(M, q),
        }, args.budget)
        rows_cold.append((n, r.pivots, t))
        q2 = q + 1e-9
        ws = r.warm_start
        assert lemke.solve_lcp(M, q2, warm_start=ws).pivots == 0
        # the cold calls again, interleaved with the warm ones: the ratios compare one time
        # window (a machine slowed for a second or two moves both; timed apart, a slow window
        # over the warm calls alone read as warm/cold 1.2 at n = 12)
        tw = time_calls({
            "core": lambda: with_kernel(core, lambda: lemke.solve_lcp(M, q2, warm_start=ws)),
            "front": lambda: lemke.solve_lcp(M, q2, warm_start=ws),
            "core cold": lambda: with_kernel(core, lambda: lemke.solve_lcp(M, q)),
            "front cold": lambda: lemke.solve_lcp(M, q),
        }, args.budget)
        rows_warm.append((n, tw, t))
        print(f"n={n}: cold core {t['core']*1e6:.2f} us, quantecon {t['quantecon']*1e6:.2f}; "
              f"warm core {tw['core']*1e6:.2f}", flush=True)
    M1 = np.array([[2.0]])
    q1, M1s, q1s = np.array([-1.0]), [M1], [np.array([-1.0])]
    fixed = time_calls({
        "solve_lcp(M, q), q < 0, the arrays made before": lambda: lemke.solve_lcp(M1, q1),
        "solve_lcp_many([M], [q]) of the same (a batch of one)": lambda: lemke.solve_lcp_many(M1s, q1s),
        "core, q >= 0 (plain call: the native front)": lambda: lemke.solve_lcp(M1, np.array([1.0])),
        "core, q < 0 (plain call: the native front)": lambda: lemke.solve_lcp(M1, np.array([-1.0])),
        "core, q >= 0": lambda: with_kernel(core, lambda: lemke.solve_lcp(M1, np.array([1.0]))),
        "core, q < 0": lambda: with_kernel(core, lambda: lemke.solve_lcp(M1, np.array([-1.0]))),
        "quantecon, q < 0": lambda: lcp_lemke(M1, np.array([-1.0])),
    }, args.budget)
    mark_end(info)
    L = report_head("The C++ core against quantecon", "bench_core.py", args,
                    time.time() - t_start, info)
    a = L.append
    a("")
    a("The core's rows put the core's `first_run` into the front's Python fast path "
      "(`with_kernel`: two dictionary writes and a closure, a few hundred nanoseconds); the "
      "plain call (shipped) is listed apart.")
    a("")
    a("## Cold solves (medians, microseconds)")
    a("")
    a("| n | pivots | core | shipped | quantecon | core/quantecon | shipped/quantecon | unrevised/tableau | box LCP/LCP |")
    a("|---|---|---|---|---|---|---|---|---|")
    for n, piv, t in rows_cold:
        a(f"| {n} | {piv} | {t['core']*1e6:.2f} | {t['front']*1e6:.2f} | "
          f"{t['quantecon']*1e6:.2f} | "
          f"{t['core']/t['quantecon']:.2f} | {t['front']/t['quantecon']:.2f} | "
          f"{t['unrevised']/t['core']:.2f} | {t['box']/t['core']:.2f} |")
    a("")
    a("(shipped: the plain call `solve_lcp(M, q)` as a user makes it: the native front, "
      "src/python_front.cpp, one native call; core: the Python fast path with the core's first_run.)")
    a("")
    a("(unrevised: `solve_lcp(method=\"unrevised\")`; box LCP: `solve_blcp` with lo = 0, hi = inf, the same "
      "LCP through the box engine; both in the core, timed in the same interleaved rounds.)")
    a("")
    a("## 0-pivot warm re-solves (q moved by 1e-9)")
    a("")
    a("| n | core | shipped | core warm/core cold | shipped warm/shipped cold |")
    a("|---|---|---|---|---|")
    for n, tw, t in rows_warm:
        a(f"| {n} | {tw['core']*1e6:.2f} | {tw['front']*1e6:.2f} | "
          f"{tw['core']/tw['core cold']:.2f} | {tw['front']/tw['front cold']:.2f} |")
    a("")
    a("(The ratios' cold calls are timed in the same interleaved rounds as the warm ones.)")
    a("")
    a("## Fixed cost, n = 1 (medians, microseconds)")
    a("")
    for k, v in fixed.items():
        a(f"- {k}: {v*1e6:.2f}")
    one = "solve_lcp(M, q), q < 0, the arrays made before"
    a(f"- a batch of one / solve_lcp: {fixed['solve_lcp_many([M], [q]) of the same (a batch of one)'] / fixed[one]:.2f}")
    text = "\n".join(L) + "\n"
    with open(args.out, "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
