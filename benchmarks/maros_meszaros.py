"""Validate solve_qp on the 62 dense Maros-Meszaros problems (qpbenchmark's dense subset).

For each problem: status, pivots, time, the three residuals (qpsolvers' formulas, on the
problem's own data) and the objective (with the constant r) beside the reference optimum of
the data folder's README.  A problem counts as solved at accuracy ``--eps`` (default 1e-9,
qpbenchmark's "high accuracy") when the status is SOLVED and all three residuals are at
most eps, both as the solver reports them (summed in double-double) and as this script
computes them exactly (exact products, ``math.fsum``: ``exact_residuals``); the last two
columns evaluate the same formulas in plain float64, as qpbenchmark does.

    python benchmarks/maros_meszaros.py [--data ../shared/data/maros-meszaros] [--only NAME ...]
        [--method tableau|unrevised] [--out benchmarks/RESULTS-maros-meszaros.md]
"""
from __future__ import annotations

import argparse
import math
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


def _two_product(a, b):
    """``(p, e)``, elementwise, with a b = p + e exactly (Dekker's split)."""
    p = a * b
    t = 134217729.0 * a
    ah = t - (t - a)
    t = 134217729.0 * b
    bh = t - (t - b)
    al, bl = a - ah, b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _exact_sum(*pairs, extra=()):
    """The sum of the exact products given as ``(p, e)`` pairs and of ``extra``, rounded
    once (``math.fsum``)."""
    return math.fsum(np.concatenate([np.ravel(v) for pe in pairs for v in pe] + [np.asarray(extra, float)]))


def exact_residuals(problem, res):
    """qpsolvers' three residuals of the returned point, computed by this script exactly up
    to one final rounding (exact products, ``math.fsum``): independent of lemke's own
    evaluation, which the "ok" column must agree with."""
    P, q, G, h, A, b, lb, ub = problem
    x, y, z, zb = res.x, res.y, res.z, res.z_box
    n = q.size
    dual = 0.0
    for j in range(n):
        pairs = [_two_product(P[j], x)]
        if A is not None:
            pairs.append(_two_product(A[:, j], y))
        if G is not None:
            pairs.append(_two_product(G[:, j], z))
        dual = max(dual, abs(_exact_sum(*pairs, extra=(q[j], zb[j]))))
    primal = 0.0
    for M, v, eq in ((G, h, False), (A, b, True)):
        for i in range(0 if M is None else M.shape[0]):
            r = _exact_sum(_two_product(M[i], x), extra=(-v[i],))
            primal = max(primal, abs(r) if eq else r)
    for bound, sign in ((lb, -1.0), (ub, 1.0)):
        if bound is not None:
            f = np.isfinite(bound)
            primal = max(primal, float(np.max(sign * (x[f] - bound[f]), initial=0.0)))
    # the gap: x'Px + q'x + h'z + b'y + lb'min(zb, 0) + ub'max(zb, 0), every product exact
    pairs = []
    for j in np.flatnonzero(x):
        p, e = _two_product(P[j], x)
        pairs += [_two_product(np.full(n, x[j]), p), _two_product(np.full(n, x[j]), e)]
    pairs.append(_two_product(q, x))
    for v, m in ((h, z), (b, y)):
        if v is not None:
            pairs.append(_two_product(v, m))
    for bound, part in ((lb, np.minimum(zb, 0.0)), (ub, np.maximum(zb, 0.0))):
        if bound is not None:
            f = np.isfinite(bound)
            pairs.append(_two_product(bound[f], part[f]))
    return primal, dual, abs(_exact_sum(*pairs))


def float64_residuals(problem, res):
    """qpsolvers' three residuals evaluated as qpsolvers and qpbenchmark evaluate them: plain
    float64 numpy sums (``Solution.primal_residual`` etc.).  The solver reports the same
    formulas summed in double-double, i.e. their values at the point returned; these add
    the rounding of the evaluation itself, up to about the gap floor."""
    P, q, G, h, A, b, lb, ub = problem
    x, y, z, zb = res.x, res.y, res.z, res.z_box
    Px = P @ x
    primal, dual, gap = 0.0, Px + q + zb, x @ Px + q @ x
    if G is not None:
        primal = max(primal, float(np.max(G @ x - h, initial=0.0)))
        dual = dual + G.T @ z
        gap += h @ z
    if A is not None:
        primal = max(primal, float(np.max(np.abs(A @ x - b), initial=0.0)))
        dual = dual + A.T @ y
        gap += b @ y
    for bound, sign in ((lb, -1.0), (ub, 1.0)):
        if bound is not None:
            f = np.isfinite(bound)
            primal = max(primal, float(np.max(sign * (x[f] - bound[f]), initial=0.0)))
            gap += bound[f] @ (np.minimum(zb[f], 0.0) if sign < 0 else np.maximum(zb[f], 0.0))
    return primal, float(np.max(np.abs(dual), initial=0.0)), abs(float(gap))


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
    rows, passed, passed64 = [], 0, 0
    head = ("| problem | n | status | pivots | time (s) | primal res | dual res | gap | gap floor | "
            "objective | reference | ok | max res in float64 | ok in float64 |")
    print(head)
    print("|" + "---|" * 14)
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
            line = f"| {f.stem} | {problem[1].size} | error: {err[:60]} | | {t:.2f} | | | | | | {ref} | no | | no |"
        else:
            worst = max(exact_residuals(problem, res))
            ok = (res.success and worst <= args.eps
                  and max(res.primal_residual, res.dual_residual, res.duality_gap) <= args.eps)
            worst64 = max(float64_residuals(problem, res))
            ok64 = res.success and worst64 <= args.eps
            passed += ok
            passed64 += ok64
            line = (
                f"| {f.stem} | {problem[1].size} | {res.status.name} | {res.pivots} | {t:.2f} | "
                f"{res.primal_residual:.1e} | {res.dual_residual:.1e} | {res.duality_gap:.1e} | {gap_floor(problem, res):.1e} | "
                f"{res.obj + r:.10g} | {ref} | {'yes' if ok else 'no'} | {worst64:.1e} | {'yes' if ok64 else 'no'} |"
            )
        rows.append(line)
        print(line, flush=True)
    summary = (f"\n**{passed} of {len(files)}** solved with all three residuals <= {args.eps:g} ({args.method}), "
               f"the residuals as lemke reports them (qpsolvers' formulas summed in double-double: their "
               f"values at the point returned, confirmed by this script's exact evaluation); **{passed64} of {len(files)}** with the same formulas "
               "evaluated in plain float64, as qpbenchmark evaluates them (the last two columns). "
               "The gap floor is eps times the sum of the sizes of the duality gap's terms: a float64 "
               "evaluation of the gap is uncertain by about that much, whatever the point.")
    print(summary)
    if args.out:
        machine = f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}"
        text = "\n".join(["# Maros-Meszaros dense set: lemke.solve_qp", "", f"Machine: {machine}; lemke {lemke.__version__}.", "", head, "|" + "---|" * 14, *rows, summary, ""])
        tmp = args.out.with_suffix(".tmp")
        tmp.write_text(text)
        os.replace(tmp, args.out)


if __name__ == "__main__":
    main()
