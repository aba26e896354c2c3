#!/usr/bin/env python
"""What the first call costs, per entry point, in fresh processes.  Since the C++ core, no
entry point compiles anything: the table shows each first call beside the second pass's
(both in new processes).

Usage::

    python benchmarks/bench_compile.py [--out benchmarks/RESULTS-compile.md]

The entry points run one after another, each in a new Python process: the command line
``lemke solve`` first (README's install-and-run command: the first call after ``pip
install``), then ``solve_lcp``, a warm start, the unrevised method, ``solve_lcp_batch``,
``solve_lcp_many``, ``solve_mlcp``, ``solve_qp`` on its fused and its KKT-MLCP path,
``solve_blcp`` (plain, then with a friction index and a warm start) and ``solve_bimatrix``.
Each process reports the seconds of ``import lemke`` and of its first call (wall and CPU).
A second pass runs every entry point again (the OS's file cache warm).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_lcp import machine_info, mark_end, report_head, report_parser  # noqa: E402

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

_CHILD = r"""
import json, sys
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
print(json.dumps(dict(import_s=t1 - t0, call_s=t2 - t1, cpu_s=time.process_time() - c1)))
"""


def _child(code):
    out = subprocess.run([sys.executable, "-c", _CHILD, code], capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _cli():
    t0 = time.perf_counter()
    c0 = os.times()
    out = subprocess.run([sys.executable, "-m", "lemke", "solve"], capture_output=True, text=True,
                         check=True)
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
    for rows in (first, again):
        cli = _cli()
        rows.append(("command line `lemke solve`", cli))
        print(f"CLI {cli['call_s']:.2f} s, {cli['process_cpu_s']:.2f} s CPU, stderr {cli['stderr']!r}",
              flush=True)
        for name, code in _CALLS.items():
            r = _child(code)
            rows.append((name, r))
            print(f"{name:24s} {r['call_s']:6.2f} s wall, {r['cpu_s']:6.2f} s CPU", flush=True)
    mark_end(info)
    L = report_head("First calls per entry point (nothing compiles at run time)", "bench_compile.py", args,
                    time.perf_counter() - t_start, info)
    L += ["", "## Each entry point's first call, in this order", "",
          "Every row is a new process.  The last column is a second pass.", "",
          "| entry point | first call (wall) | CPU | second pass: first call |",
          "|---|---:|---:|---:|"]
    for (name, r), (_, r2) in zip(first, again):
        if "cpu_s" in r:
            L.append(f"| {name} | {r['call_s'] * 1e3:.1f} ms | {r['cpu_s'] * 1e3:.0f} ms | "
                     f"{r2['call_s'] * 1e3:.1f} ms |")
        else:
            L.append(f"| {name} (whole process) | {r['call_s']:.1f} s | {r['process_cpu_s']:.1f} s | "
                     f"{r2['call_s']:.2f} s |")
    total = sum(r.get("cpu_s", r.get("process_cpu_s", 0.0)) for _, r in first)
    imports = sorted(r["import_s"] for _, r in first + again if "import_s" in r)
    L += ["", f"CPU seconds of all the first calls together (the command line's whole process "
          f"included): {total:.0f} s.  `import lemke`: median "
          f"{imports[len(imports) // 2]:.2f} s (nothing is compiled at import).", "",
          f"The command line's stderr, first pass: `{first[0][1]['stderr'] or '(nothing)'}`; "
          f"second pass: `{again[0][1]['stderr'] or '(nothing)'}`.", ""]
    with open(args.out, "w") as f:
        f.write("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
