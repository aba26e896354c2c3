"""The unrevised method at small n: interleaved per-call medians (us) of solve_lcp(M, q) (the
tableau), solve_lcp(M, q, method="tableau"), solve_lcp(M, q, method="unrevised") and
quantecon's lcp_lemke, on the harness's psd problems (bench_lcp.make_problem, 4 per size:
the median over them of each one's median of 15 interleaved rounds) and murty(4) (writable
copies), every lemke answer checked. Prints a table to stdout (it writes no RESULTS file: add a dated section by hand).

    python benchmarks/bench_unrevised_small.py
"""
import random
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_lcp as bl  # noqa: E402
import lemke  # noqa: E402
from lemke import problems  # noqa: E402
from quantecon.optimize import lcp_lemke  # noqa: E402

def calls(M, q):
    return {
        "tab": lambda: lemke.solve_lcp(M, q),
        "tab_kw": lambda: lemke.solve_lcp(M, q, method="tableau"),
        "unrev": lambda: lemke.solve_lcp(M, q, method="unrevised"),
        "qe": lambda: lcp_lemke(M, q),
    }
cases = []
for n in (2, 5, 10, 20, 26):
    for k in range(4):
        cases.append((f"psd{n}", *bl.make_problem(n, k)))
mp = problems.murty(4)
cases.append(("murty4", np.array(mp.M), np.array(mp.q)))  # (writable: the read-only arrays took the validation path in the base)
res = {}
for name, M, q in cases:
    c = calls(M, q)
    for f in c.values():
        f()
    for m in ("tableau", "unrevised"):  # every answer checked on the caller's data
        r = lemke.solve_lcp(M, q, method=m)
        w = M @ r.z + q
        scale = 1e-8 * max(1.0, np.abs(M).max(), np.abs(q).max())
        assert r.status == lemke.Status.SOLVED and np.abs(np.minimum(r.z, w)).max() <= scale, (name, m)
    reps = 300 if M.shape[0] <= 10 else 100
    t = {k: [] for k in c}
    for _ in range(15):
        order = list(c)
        random.shuffle(order)
        for key in order:
            f = c[key]
            t0 = time.perf_counter()
            for _ in range(reps):
                f()
            t[key].append((time.perf_counter() - t0) / reps * 1e6)
    for key in c:
        res.setdefault((name, key), []).append(statistics.median(t[key]))
names = sorted({n for n, _ in res}, key=lambda s: (s[:3], int(''.join(ch for ch in s if ch.isdigit()))))
print(f"{'case':8} {'tab':>7} {'tab_kw':>7} {'unrev':>7} {'qe':>7} {'u/tab':>6} {'u/qe':>6} {'tab/qe':>6}")
for name in names:
    v = {k: statistics.median(res[(name, k)]) for k in ("tab", "tab_kw", "unrev", "qe")}  # median over problems
    print(f"{name:8} {v['tab']:7.2f} {v['tab_kw']:7.2f} {v['unrev']:7.2f} {v['qe']:7.2f} {v['unrev']/v['tab']:6.2f} {v['unrev']/v['qe']:6.2f} {v['tab']/v['qe']:6.2f}")
