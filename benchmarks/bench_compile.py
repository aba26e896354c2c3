#!/usr/bin/env python
"""What the first call costs, per entry point, in fresh processes.  Since the C++ core, no
entry point compiles anything: the table shows each first call beside the second pass's
(both in new processes), and numba's counters (taken where numba is installed, for the
test oracles) stay at zero.

Usage::

    python benchmarks/bench_compile.py [--out benchmarks/RESULTS-compile.md]

The entry points run one after another, each in a new Python process, on one numba cache
directory that starts empty (``NUMBA_CACHE_DIR``): the command line ``lemke solve`` first
(README's install-and-run command: the first call after ``pip install``), then
``solve_lcp``, a warm start, the unrevised method, ``solve_lcp_batch``, ``solve_lcp_many``,
``solve_mlcp``, ``solve_qp`` on its fused and its KKT-MLCP path, ``solve_blcp`` (plain,
then with a friction index and a warm start) and
``solve_bimatrix``.  Each process reports the seconds of ``import lemke`` and of its first
call (wall and CPU), and how many kernel signatures numba compiled (cache misses: what it
did not share with the entry points before it) and loaded (cache hits).  A second pass runs
every entry point again on the filled cache.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_lcp import machine_info, mark_end, report_head, report_parser  # noqa: E402

_STATS = r"""
import json, sys, types
def _stats():
    if "numba" not in sys.modules:  # the package never imports numba: nothing compiled
        return 0, 0
    import numba.core.registry
    hits = misses = 0
    for name, mod in list(sys.modules.items()):
        if not name.startswith("lemke"):
            continue
        for obj in vars(mod).values():
            st = getattr(obj, "stats", None)
            if isinstance(obj, numba.core.registry.CPUDispatcher) and st is not None:
                hits += sum(st.cache_hits.values())
                misses += sum(st.cache_misses.values())
    return hits, misses
"""

_CALLS = {
    "solve_lcp": "lemke.solve_lcp(M, q)",
    "warm start": "r = lemke.solve_lcp(M, q); lemke.solve_lcp(M, q + 1e-9, warm_start=r.warm_start)",
    "solve_lcp (unrevised)": "lemke.solve_lcp(M, q, method='unrevised')",
    "solve_lcp_batch": "lemke.solve_lcp_batch(np.stack([M, M]), np.stack([q, q]))",
    "solve_lcp_many": "lemke.solve_lcp_many([M, M[:2, :2]], [q, q[:2]])",
    "solve_mlcp": ("lemke.solve_mlcp(np.array([[2.0]]), M, np.ones((1, 3)), np.ones((3, 1)), "
                   "np.array([-1.0]), q)"),
    "solve_qp (fused)": "lemke.solve_qp(np.eye(3) * 2, -np.ones(3), G=np.ones((1, 3)), h=np.ones(1))",
    "solve_qp (KKT-MLCP)": "lemke.solve_qp(np.zeros((3, 3)), -np.ones(3), G=np.eye(3), h=np.ones(3))",
    "solve_blcp": "lemke.solve_blcp(M, q, -np.ones(3), np.ones(3))",
    "solve_blcp (findex, warm)": (
        "fi = np.array([-1, 0, -1]); lo = np.array([0.0, -0.5, 0.0]); hi = np.array([np.inf, 0.5, 1.0]); "
        "r = lemke.solve_blcp(M, q, lo, hi, findex=fi); "
        "lemke.solve_blcp(M, q + 1e-9, lo, hi, findex=fi, warm_start=r.warm_start)"),
    "solve_bimatrix": "lemke.solve_bimatrix(M + 5, M.T + 5)",
}

_CHILD = _STATS + r"""
import time
t0 = time.perf_counter()
c0 = time.process_time()
import numpy as np
import lemke
t1 = time.perf_counter()
c1 = time.process_time()
M = np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]])
q = np.array([-1.0, -2.0, 1.0])
exec(sys.argv[1])
t2 = time.perf_counter()
hits, misses = _stats()
print(json.dumps(dict(import_s=t1 - t0, call_s=t2 - t1, cpu_s=time.process_time() - c1, hits=hits,
                      misses=misses)))
"""


def _child(code, cache):
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    out = subprocess.run([sys.executable, "-c", _CHILD, code], capture_output=True, text=True,
                         env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _cli(cache):
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    t0 = time.perf_counter()
    c0 = os.times()
    out = subprocess.run([sys.executable, "-m", "lemke", "solve"], capture_output=True, text=True,
                         env=env, check=True)
    c1 = os.times()
    cpu = (c1.children_user - c0.children_user) + (c1.children_system - c0.children_system)
    return dict(call_s=time.perf_counter() - t0, process_cpu_s=cpu, stderr=out.stderr.strip())


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-compile.md", argv)
    args = parser.parse_args(argv)
    args.argv = argv
    info = machine_info()
    t_start = time.perf_counter()
    first, again = [], []
    with tempfile.TemporaryDirectory(prefix="lemke-compile-") as cache:
        for rows in (first, again):
            cli = _cli(cache)
            rows.append(("command line `lemke solve`", cli))
            print(f"CLI {cli['call_s']:.2f} s, {cli['process_cpu_s']:.2f} s CPU, stderr {cli['stderr']!r}",
                  flush=True)
            for name, code in _CALLS.items():
                r = _child(code, cache)
                rows.append((name, r))
                print(f"{name:24s} {r['call_s']:6.2f} s wall, {r['cpu_s']:6.2f} s CPU, "
                      f"{r['misses']} compiled, {r['hits']} loaded", flush=True)
    mark_end(info)
    L = report_head("First calls per entry point (nothing compiles at run time)", "bench_compile.py", args,
                    time.perf_counter() - t_start, info)
    L += ["", "## Each entry point's first call, in this order, on one cache that starts empty", "",
          "Every row is a new process.  *compiled*: kernel signatures numba compiled there (what "
          "the entry points above did not already leave in the cache); *loaded*: taken from the "
          "cache.  The second column group is a second pass on the filled cache.", "",
          "| entry point | first call (wall) | CPU | compiled | loaded | cached: first call | compiled |",
          "|---|---:|---:|---:|---:|---:|---:|"]
    for (name, r), (_, r2) in zip(first, again):
        if "misses" in r:
            L.append(f"| {name} | {r['call_s'] * 1e3:.1f} ms | {r['cpu_s'] * 1e3:.0f} ms | {r['misses']} | {r['hits']} | "
                     f"{r2['call_s'] * 1e3:.1f} ms | {r2['misses']} |")
        else:
            L.append(f"| {name} (whole process) | {r['call_s']:.1f} s | {r['process_cpu_s']:.1f} s | | | "
                     f"{r2['call_s']:.2f} s | |")
    total = sum(r.get("cpu_s", r.get("process_cpu_s", 0.0)) for _, r in first)
    imports = sorted(r["import_s"] for _, r in first + again if "import_s" in r)
    L += ["", f"CPU seconds of all the first calls together (the command line's whole process "
          f"included): {total:.0f} s.  `import lemke`: median "
          f"{imports[len(imports) // 2]:.2f} s (nothing is compiled at import).", "",
          f"The command line's stderr on the empty cache: `{first[0][1]['stderr'] or '(nothing)'}`; "
          f"on the filled cache: `{again[0][1]['stderr'] or '(nothing)'}`.", ""]
    with open(args.out, "w") as f:
        f.write("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
