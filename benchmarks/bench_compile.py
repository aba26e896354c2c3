#!/usr/bin/env python
"""What the first call costs: numba's compile, per entry point, in fresh processes.

Usage::

    python benchmarks/bench_compile.py [--runs 1] [--out benchmarks/RESULTS-compile.md]

Every entry point (``solve_lcp`` with each method, a warm start, ``solve_lcp_batch``,
``solve_lcp_many``, ``solve_mlcp``, ``solve_qp`` on its fused and its KKT-MLCP path,
``solve_blcp``, ``solve_bimatrix``, the command line, and everything in one process) is
run in a new Python process with an empty ``NUMBA_CACHE_DIR`` ("cold": what the first call
after ``pip install`` costs), then again in a new process on the cache the first one filled
("cached": every later first call).  Each child reports the seconds of ``import lemke`` and
of its first call, and how many kernel signatures numba compiled (cache misses) and loaded
(cache hits).

"Shared" rows check that entry points share compiled kernels: the command line runs first
on an empty cache, then the Python API in another process on that cache; a shared kernel
is loaded there, not compiled again.
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
import numba.core.registry
def _stats():
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
    "solve_lcp (tableau)": "lemke.solve_lcp(M, q)",
    "solve_lcp (unrevised)": "lemke.solve_lcp(M, q, method='unrevised')",
    "warm start": "r = lemke.solve_lcp(M, q); lemke.solve_lcp(M, q + 1e-9, warm_start=r.warm_start)",
    "solve_lcp_batch": "lemke.solve_lcp_batch(np.stack([M, M]), np.stack([q, q]))",
    "solve_lcp_many": "lemke.solve_lcp_many([M, M[:2, :2]], [q, q[:2]])",
    "solve_mlcp": ("lemke.solve_mlcp(np.array([[2.0]]), M, np.ones((1, 3)), np.ones((3, 1)), "
                   "np.array([-1.0]), q)"),
    "solve_qp (fused)": "lemke.solve_qp(np.eye(3) * 2, -np.ones(3), G=np.ones((1, 3)), h=np.ones(1))",
    "solve_qp (KKT-MLCP)": "lemke.solve_qp(np.zeros((3, 3)), -np.ones(3), G=np.eye(3), h=np.ones(3))",
    "solve_blcp": "lemke.solve_blcp(M, q, -np.ones(3), np.ones(3))",
    "solve_bimatrix": "lemke.solve_bimatrix(M + 5, M.T + 5)",
}
_CALLS["everything"] = "; ".join(_CALLS.values())

_CHILD = _STATS + r"""
import time
t0 = time.perf_counter()
import numpy as np
import lemke
t1 = time.perf_counter()
M = np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]])
q = np.array([-1.0, -2.0, 1.0])
exec(sys.argv[1])
t2 = time.perf_counter()
hits, misses = _stats()
print(json.dumps(dict(import_s=t1 - t0, call_s=t2 - t1, hits=hits, misses=misses)))
"""


def _child(code, cache):
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    out = subprocess.run([sys.executable, "-c", _CHILD, code], capture_output=True, text=True,
                         env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _cli(cache):
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "lemke", "solve"], capture_output=True, text=True,
                         env=env, check=True)
    return dict(call_s=time.perf_counter() - t0, stderr=out.stderr.strip())


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-compile.md", argv)
    parser.add_argument("--runs", type=int, default=1)
    args = parser.parse_args(argv)
    args.argv = argv
    info = machine_info()
    t_start = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory(prefix="lemke-compile-") as root:
        for run in range(args.runs):
            for name, code in _CALLS.items():
                cache = os.path.join(root, f"{run}-{len(rows)}")
                os.mkdir(cache)
                cold, cached = _child(code, cache), _child(code, cache)
                rows.append((name, cold, cached))
                print(f"{name:24s} cold {cold['call_s']:6.1f} s ({cold['misses']} compiled)  "
                      f"cached {cached['call_s']:5.2f} s ({cached['misses']} compiled, "
                      f"{cached['hits']} loaded)", flush=True)
            cache = os.path.join(root, f"{run}-cli")
            os.mkdir(cache)
            cli_cold, cli_cached = _cli(cache), _cli(cache)
            api = _child(_CALLS["solve_lcp (tableau)"], cache)
            rows.append(("command line `lemke solve`", cli_cold, cli_cached))
            rows.append(("solve_lcp after the CLI", api, None))
            print(f"CLI cold {cli_cold['call_s']:.1f} s, stderr: {cli_cold['stderr']!r}; cached "
                  f"{cli_cached['call_s']:.2f} s, stderr: {cli_cached['stderr']!r}; API after CLI: "
                  f"{api['misses']} compiled, {api['hits']} loaded", flush=True)
    mark_end(info)
    L = report_head("First calls: numba's compile per entry point", "bench_compile.py", args,
                    time.perf_counter() - t_start, info)
    L += ["", "## First call per entry point", "",
          "Each row is a new process; *cold* with an empty `NUMBA_CACHE_DIR` (the first call after "
          "install), *cached* in a second new process on the cache the first one filled. "
          "Seconds of the first call (after `import lemke`); *compiled* / *loaded* count kernel "
          "signatures that numba compiled or took from the cache.", "",
          "| entry point | cold: first call | compiled | cached: first call | compiled | loaded |",
          "|---|---:|---:|---:|---:|---:|"]
    for name, cold, cached in rows:
        if cached is None:
            L.append(f"| {name} (same cache) | {cold['call_s']:.2f} s | {cold['misses']} | | | "
                     f"{cold['hits']} |")
        elif "misses" not in cold:
            L.append(f"| {name} (whole process) | {cold['call_s']:.1f} s | | {cached['call_s']:.2f} s | | |")
        else:
            L.append(f"| {name} | {cold['call_s']:.1f} s | {cold['misses']} | {cached['call_s']:.3f} s | "
                     f"{cached['misses']} | {cached['hits']} |")
    imports = sorted(c["import_s"] for _, c, _ in rows if "import_s" in c)
    L += ["", f"`import lemke`: median {imports[len(imports) // 2]:.2f} s over {len(imports)} processes "
          "(nothing is compiled at import).", ""]
    cli = [r for r in rows if r[0].startswith("command line")][-1]
    L += [f"The command line's stderr on the cold run: `{cli[1]['stderr']}`; on the cached run: "
          f"`{cli[2]['stderr'] or '(nothing)'}`.", ""]
    with open(args.out, "w") as f:
        f.write("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
