"""Validate solve_qp on the 62 dense Maros-Meszaros problems (qpbenchmark's dense subset).

For each problem: status, pivots, time, the three residuals (qpsolvers' formulas, on the
problem's own data) and the objective (with the constant r) beside the reference optimum of
the data folder's README.  A problem counts as solved at accuracy ``--eps`` (default 1e-9,
qpbenchmark's "high accuracy") when the status is SOLVED and all three residuals are at
most eps.

    python benchmarks/maros_meszaros.py [--data ../shared/data/maros-meszaros] [--only NAME ...]
        [--method tableau|unrevised] [--out benchmarks/RESULTS-maros-meszaros.md]
"""
from __future__ import annotations

import argparse
import os
import platform
import re
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import lemke  # noqa: E402

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = HERE.parents[0].parent / "shared" / "data" / "maros-meszaros"


def load(path: Path):
    """The problem in qpsolvers' form ``(P, q, G, h, A, b, lb, ub)`` and its constant r, read
    by ``lemke.read_problem`` (the conversion of the data folder's README: equalities when
    u - l < 1e-10, |value| > 9e19 is infinite, each finite side of a general row one row of
    G)."""
    p = lemke.read_problem(path)
    return tuple(getattr(p, k) for k in ("P", "q", "G", "h", "A", "b", "lb", "ub")), p.objective_constant


def references(readme: Path) -> dict:
    """Reference optima (with r) from the README's table; None where not a plain number."""
    refs = {}
    for line in readme.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 12 and re.fullmatch(r"[A-Z0-9_]+", cells[0]):
            m = re.match(r"^-?[0-9.]+(e[-+]?\d+)?", cells[10])
            refs[cells[0]] = float(m.group(0)) if m else None
    return refs


def gap_floor(problem, res) -> float:
    """The rounding floor of the duality gap's own formula: eps times the sum of the sizes
    of its terms (|x|'|P||x| + |q|'|x| + |h|'|z| + |b|'|y| + the bound terms).  A gap below
    it cannot be told from zero in double precision, whatever the solver."""
    P, q, G, h, A, b, lb, ub = problem
    x, y, z, zb = (np.abs(a) for a in (res.x, res.y, res.z, res.z_box))
    total = x @ np.abs(P) @ x + np.abs(q) @ x
    if h is not None:
        total += np.abs(h) @ z
    if b is not None:
        total += np.abs(b) @ y
    for bound in (lb, ub):
        if bound is not None:
            finite = np.isfinite(bound)
            total += np.abs(bound[finite]) @ zb[finite]
    return float(np.finfo(float).eps * total)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA)
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--method", default="tableau", choices=lemke.METHODS)
    ap.add_argument("--eps", type=float, default=1e-9)
    ap.add_argument("--out", type=Path)
    args = ap.parse_args(argv)
    refs = references(args.data / "README.md")
    files = sorted(args.data.glob("*.mat"))
    if args.only:
        files = [f for f in files if f.stem in set(args.only)]
    rows, passed = [], 0
    head = "| problem | n | status | pivots | time (s) | primal res | dual res | gap | gap floor | objective | reference | ok |"
    print(head)
    print("|" + "---|" * 12)
    for f in files:
        problem, r = load(f)
        t = time.perf_counter()
        try:
            res = lemke.solve_qp(*problem, method=args.method)
            err = None
        except ValueError as exc:
            res, err = None, str(exc)
        t = time.perf_counter() - t
        ref = refs.get(f.stem)
        if res is None:
            line = f"| {f.stem} | {problem[1].size} | error: {err[:60]} | | {t:.2f} | | | | | | {ref} | no |"
        else:
            ok = res.success and max(res.primal_residual, res.dual_residual, res.duality_gap) <= args.eps
            passed += ok
            line = (
                f"| {f.stem} | {problem[1].size} | {res.status.name} | {res.pivots} | {t:.2f} | "
                f"{res.primal_residual:.1e} | {res.dual_residual:.1e} | {res.duality_gap:.1e} | {gap_floor(problem, res):.1e} | "
                f"{res.obj + r:.10g} | {ref} | {'yes' if ok else 'no'} |"
            )
        rows.append(line)
        print(line, flush=True)
    summary = (f"\n**{passed} of {len(files)}** solved with all three residuals <= {args.eps:g} ({args.method}). "
               "The gap floor is eps times the sum of the sizes of the duality gap's terms: a gap "
               "below it is rounding in the gap's own formula, out of reach of any double-precision "
               "solver.")
    print(summary)
    if args.out:
        machine = f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}"
        text = "\n".join(["# Maros-Meszaros dense set: lemke.solve_qp", "", f"Machine: {machine}; lemke {lemke.__version__}.", "", head, "|" + "---|" * 12, *rows, summary, ""])
        tmp = args.out.with_suffix(".tmp")
        tmp.write_text(text)
        os.replace(tmp, args.out)


if __name__ == "__main__":
    main()
