#!/usr/bin/env python
"""What the first call costs, per entry point, in fresh processes: ``import lemke``, the
first call after it and the second (the same call again), medians of ``--runs`` fresh
processes (5).  Since the C++ core, no entry point compiles anything at run time.

Usage::

    env -u PYTHONDONTWRITEBYTECODE python benchmarks/bench_compile.py [--runs 5] [--out benchmarks/RESULTS-compile.md]

(an installed package has its bytecode: with ``PYTHONDONTWRITEBYTECODE`` set and an
editable install, every import would compile the sources again).  The entry points run in
turn, each in a new Python process, round after round: the command line ``lemke solve``
(README's install-and-run command, a whole process), then ``solve_lcp``, a warm start, the
unrevised method, ``solve_lcp_batch``, ``solve_lcp_many``, ``solve_mlcp``, ``solve_qp`` on
its box, fused and KKT-MLCP paths, ``solve_blcp`` (plain, then with a friction index and a
warm start), ``solve_blcp_many``, ``solve_bimatrix`` and ``lemke_paths``.  Each process
reports the seconds of ``import numpy``, of ``import lemke`` after it, of its first call
and of the same call again (wall).
"""
from __future__ import annotations

import json
import os
import statistics
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
    "solve_qp (box)": "lemke.solve_qp(np.eye(3) * 2, -np.ones(3), lb=-np.ones(3), ub=np.ones(3))",
    "solve_qp (fused)": "lemke.solve_qp(np.eye(3) * 2, -np.ones(3), G=np.ones((1, 3)), h=np.ones(1))",
    "solve_qp (KKT-MLCP)": "lemke.solve_qp(np.zeros((3, 3)), -np.ones(3), G=np.eye(3), h=np.ones(3))",
    "solve_blcp": "lemke.solve_blcp(M, q, -np.ones(3), np.ones(3))",
    "solve_blcp (findex, warm)": (
        "fi = np.array([-1, 0, -1]); lo = np.array([0.0, -0.5, 0.0]); hi = np.array([np.inf, 0.5, 1.0]); "
        "r = lemke.solve_blcp(M, q, lo, hi, findex=fi); "
        "lemke.solve_blcp(M, q + 1e-9, lo, hi, findex=fi, warm_start=r.warm_start)"),
    "solve_blcp_many": "lemke.solve_blcp_many([M, M[:2, :2]], [q, q[:2]], [-np.ones(3), -np.ones(2)], [np.ones(3), np.ones(2)])",
    "solve_bimatrix": "lemke.solve_bimatrix(M + 5, M.T + 5)",
    "lemke_paths": "lemke.lemke_paths(M + 5, M.T + 5)",
}

_CHILD = r"""
import json, sys
import time
t0 = time.perf_counter()
import numpy as np
t1 = time.perf_counter()
import lemke
t2 = time.perf_counter()
M = np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]])
q = np.array([-1.0, -2.0, 1.0])
code = compile(sys.argv[1], "<call>", "exec")
t3 = time.perf_counter()
exec(code)
t4 = time.perf_counter()
exec(code)
t5 = time.perf_counter()
print(json.dumps(dict(numpy_s=t1 - t0, import_s=t2 - t1, call_s=t4 - t3, again_s=t5 - t4)))
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


def _median(rows, key):
    return statistics.median(r[key] for r in rows)


def main(argv=None):
    parser, argv = report_parser(__doc__, "RESULTS-compile.md", argv)
    parser.add_argument("--runs", type=int, default=5, help="fresh processes per entry point")
    args = parser.parse_args(argv)
    args.argv = argv
    info = machine_info()
    t_start = time.perf_counter()
    runs = {name: [] for name in ["cli", *_CALLS]}
    # rounds one after another (nothing is cached between processes but the OS's files)
    for k in range(args.runs):
        runs["cli"].append(_cli())
        for name, code in _CALLS.items():
            runs[name].append(_child(code))
        print(f"round {k + 1}/{args.runs}: CLI {runs['cli'][-1]['call_s']:.2f} s; " + ", ".join(
            f"{name} {r[-1]['call_s'] * 1e6:.0f}/{r[-1]['again_s'] * 1e6:.0f} us"
            for name, r in runs.items() if name != "cli"), flush=True)
    mark_end(info)
    L = report_head("First calls per entry point (nothing compiles at run time)", "bench_compile.py", args,
                    time.perf_counter() - t_start, info)
    L += ["", f"## Each entry point in a fresh process: medians of {args.runs} processes", "",
          "Every row is a new process per run: *import numpy*, then *import lemke* (which imports "
          "every solver's module and solves one tiny problem on each engine), then the entry "
          "point's *first call* and the same call *again*.", "",
          "| entry point | import numpy | import lemke | first call | second call | first / second |",
          "|---|---:|---:|---:|---:|---:|"]
    for name, rows in runs.items():
        if name == "cli":
            continue
        first, again = _median(rows, "call_s"), _median(rows, "again_s")
        L.append(f"| {name} | {_median(rows, 'numpy_s') * 1e3:.1f} ms | {_median(rows, 'import_s') * 1e3:.1f} ms | "
                 f"{first * 1e6:.0f} us | {again * 1e6:.0f} us | {first / again:.1f} |")
    cli = runs["cli"]
    L += ["", f"The command line `lemke solve` (a whole process, Python's start included): median "
          f"{_median(cli, 'call_s'):.2f} s, {_median(cli, 'process_cpu_s'):.2f} s of CPU; its stderr: "
          f"`{cli[0]['stderr'] or '(nothing)'}`.", ""]
    with open(args.out, "w") as f:
        f.write("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
