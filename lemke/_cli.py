"""The ``lemke`` command.  ``main(argv)`` returns the exit code: 0 solved, 1 read but not
solved, 2 usage or input error (one line on stderr, never a traceback)."""
from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from . import problems
from ._lcp import METHODS, solve_lcp
from ._options import Options

DEFAULT_PROBLEM = "cps-4.4.7"


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line and exit code 2, as for any input error
        raise _UsageError(message)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="lemke", description="Solve linear complementarity problems by Lemke's method.")
    sub = p.add_subparsers(dest="command")
    s = sub.add_parser("solve", help="solve a built-in problem (see `lemke problems`)")
    s.add_argument("source", nargs="*", help=f"built-in problem name (default: {DEFAULT_PROBLEM})")
    s.add_argument("--method", default="tableau", choices=METHODS)
    s.add_argument("--max-pivots", type=int, default=None)
    s.add_argument("--tol", type=float, default=None, help="acceptance tolerance (relative)")
    sub.add_parser("problems", help="list the built-in problems")
    return p


def _lookup(name: str) -> problems.Problem:
    base, _, arg = name.partition("-") if name.startswith("murty") else (name, "", "")
    if base not in problems.NAMED:
        raise _UsageError(f"unknown problem {name!r}; see `lemke problems`")
    if arg:
        if not arg.isdigit() or not 1 <= int(arg) <= 30:
            raise _UsageError(f"{name!r}: the size of murty-N must be an integer in 1..30")
        return problems.NAMED[base](int(arg))
    return problems.NAMED[base]()


def _show(vec: np.ndarray, limit: int = 10) -> str:
    head = np.array2string(vec[:limit], precision=6, suppress_small=True, separator=", ")
    return head if vec.size <= limit else f"{head[:-1]}, ...] ({vec.size} entries)"


def _solve(args) -> int:
    names = args.source or [DEFAULT_PROBLEM]
    if not args.source:
        print(f"No problem given: solving the built-in example {DEFAULT_PROBLEM!r}.")
    opts = {}
    if args.max_pivots is not None:
        opts["max_pivots"] = args.max_pivots
    if args.tol is not None:
        opts["tol"] = args.tol
    try:
        options = Options(**opts)
    except (TypeError, ValueError) as exc:
        raise _UsageError(str(exc)) from None
    worst = 0
    for name in names:
        prob = _lookup(name)
        t0 = time.perf_counter()
        res = solve_lcp(prob.M, prob.q, method=args.method, options=options)
        dt = time.perf_counter() - t0
        print(f"{prob.name} (n = {prob.q.size}; {prob.source})")
        print(f"  status   {res.status.name}: {res.message}")
        print(f"  pivots   {res.pivots}")
        print(f"  residual {res.residual:.3g}")
        print(f"  time     {dt * 1e3:.3f} ms")
        print(f"  z        {_show(res.z)}")
        worst = max(worst, 0 if res.success else 1)
    return worst


def main(argv=None) -> int:
    try:
        args = _parser().parse_args(argv)
        if args.command == "problems":
            for name, fn in problems.NAMED.items():
                p = fn()
                print(f"{name:12s} n = {p.q.size:<3d} {p.source}")
            return 0
        if args.command == "solve":
            return _solve(args)
        raise _UsageError("no command given; try `lemke solve` or `lemke problems` (or --help)")
    except _UsageError as exc:
        print(f"lemke: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
