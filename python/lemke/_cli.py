"""The ``lemke`` command.  ``main(argv)`` returns the exit code, the worst outcome over the
sources: 0 all solved, 1 some problem read but not solved, 2 a usage or input error (one line
on stderr naming the file and what is wrong, never a traceback; the other sources are still
solved and reported), 130 interrupted (Ctrl-C: one line on stderr; the results of the sources
finished before it are reported and written, atomically, to ``--out``).

Options may stand anywhere among the sources (``lemke solve a.json --json b.json``).  The
solves run in a worker thread, so that Ctrl-C is answered at once even while a kernel runs
(the kernels do not look at signals): the main thread waits, and on SIGINT reports what is
finished and ends the process."""
from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import threading
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

from . import problems
from ._io import EXTENSIONS, FORMATS, ProblemFormatError, read_problem, result_to_dict, write_result
from ._kinds import KINDS
from ._options import Options
from ._problem import Problem
from ._status import Status
from ._version import __version__

DEFAULT_PROBLEM = "cps-4.4.7"
_SHOWN = 8  # entries of a solution shown in the human output


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line and exit code 2, as for any input error
        raise _UsageError(message)


class _IntermixedParser(_Parser):
    """A subcommand's parser whose options may stand between its positional arguments
    (``solve a.json --json b.json``): argparse's intermixed parsing, which the parser of
    subcommands calls through ``parse_known_args``."""

    _inside = False

    def parse_known_args(self, args=None, namespace=None):
        if self._inside:  # parse_known_intermixed_args calls back here, twice
            return super().parse_known_args(args, namespace)
        self._inside = True
        try:
            return self.parse_known_intermixed_args(args, namespace)
        finally:
            self._inside = False


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of seconds, got {text!r}") from None
    if not value >= 0.0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


def _tolerance(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not 0.0 <= value < 1.0:  # NaN fails too
        raise argparse.ArgumentTypeError(f"must be in [0, 1), got {text}")
    return value


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="lemke", description="Solve linear complementarity problems (and MLCPs and "
                "convex QPs) by Lemke's method.  Exit code (the worst over the sources): 0 solved, "
                "1 not solved, 2 bad input; 130 interrupted.")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command", parser_class=_IntermixedParser)
    s = sub.add_parser("solve", help="solve problems from files, directories or the built-in list",
                       description="Solve each SOURCE: a problem file (formats: "
                       f"{', '.join(sorted(EXTENSIONS))}; also told by content), a directory (its "
                       "problem files, sorted) or a built-in problem (`lemke problems`).  With no "
                       f"SOURCE, the built-in example {DEFAULT_PROBLEM}.  Options may stand "
                       "anywhere.  A source that cannot be read is reported on its own line and "
                       "the others are still solved; the exit code is the worst outcome.")
    s.add_argument("source", nargs="*", metavar="SOURCE", help="file, directory or built-in name")
    methods = list(dict.fromkeys(m for k in KINDS.values() for m in k.methods))
    s.add_argument("--method", default=None, choices=methods,
                   help="method (default: tableau; lemke-howson for a game)")
    s.add_argument("--format", choices=FORMATS, help="read every file in this format (default: by extension and content)")
    s.add_argument("--max-pivots", type=_count, metavar="N", help="pivot limit (default: 100 (n + 1))")
    s.add_argument("--time-limit", type=_seconds, metavar="SECONDS",
                   help="time limit per source, in seconds (default: none)")
    s.add_argument("--tol", type=_tolerance, metavar="X", help="acceptance tolerance, relative (default: 1e-9)")
    s.add_argument("--pivot-tol", type=_tolerance, metavar="X", help="ratio-test threshold, relative (default: 1e-11)")
    s.add_argument("--tie-tol", type=_tolerance, metavar="X", help="tie threshold, relative (default: 1e-11)")
    s.add_argument("--json", action="store_true", help="print the result(s) as JSON on stdout (a list for several)")
    s.add_argument("--out", metavar="FILE", help="write the result(s) to FILE (.json, or .npz for one problem)")
    s.add_argument("--quiet", action="store_true",
                   help="no progress line on stderr (shown for several sources when stderr is a terminal)")
    sub.add_parser("problems", help="list the built-in problems")
    return p


# --------------------------------------------------------------------------- sources

def _builtin(name: str):
    """The built-in problem ``name`` (``murty-N`` for Murty's example of size N), or None."""
    if name in problems.NAMED:
        return problems.NAMED[name]()
    base, _, size = name.partition("-")
    if base == "murty" and size:
        if not size.isdigit() or not 1 <= int(size) <= 30:
            raise _UsageError(f"{name}: the size N of murty-N must be an integer in 1..30")
        return problems.murty(int(size))
    return None


class _Bad:
    """A source that cannot be solved at all (missing, an unreadable directory, a bad
    built-in name): reported on its own line, in its turn, while the others are solved."""

    def __init__(self, name: str, error: str):
        self.name, self.error = name, error


def _sources(names: list[str]) -> list:
    """Each SOURCE as a Path (a file to read), a Problem (built-in) or a :class:`_Bad`
    (what is wrong with it); directories expanded."""
    out = []
    for name in names:
        try:
            out += _source(name)
        except _UsageError as exc:
            out.append(_Bad(name, str(exc)))
    return out


def _source(name: str) -> list:
    path = Path(name)
    if path.is_dir():
        try:
            files = sorted(p for p in path.iterdir()
                           if p.is_file() and p.suffix.lower() in EXTENSIONS and not p.name.startswith("."))
        except OSError as exc:
            raise _UsageError(f"{name}: cannot list this directory: {exc.strerror or exc}") from None
        if not files:
            raise _UsageError(f"{name}: no problem files ({', '.join(sorted(EXTENSIONS))}) in this directory")
        return files
    if path.exists() or os.path.lexists(path):
        return [path]
    prob = _builtin(name)
    if prob is None and (os.sep in name or path.suffix.lower() in EXTENSIONS):
        raise _UsageError(f"{name}: no such file or directory")
    if prob is None:
        raise _UsageError(f"{name}: no such file, and not a built-in problem (see `lemke problems`)")
    return [prob]


# --------------------------------------------------------------------------- output

def _show(vec) -> str:
    if not isinstance(vec, np.ndarray):  # a tuple: exact fractions, or a game's payoffs
        items = [str(v) if isinstance(v, Fraction) else f"{float(v):.6g}" for v in vec]
        more = f", ...] ({len(items)} entries)" if len(items) > _SHOWN else "]"
        return "[" + ", ".join(items[:_SHOWN]) + more
    head = np.array2string(vec[:_SHOWN], precision=6, suppress_small=True, separator=", ",
                           max_line_width=10**6)
    return head if vec.size <= _SHOWN else f"{head[:-1]}, ...] ({vec.size} entries)"


def _solution(prob, res) -> list[tuple[str, str]]:
    kind = KINDS[prob.kind]
    rows = [(key, _show(getattr(res, key))) for key in kind.answer]
    if kind.has_objective and res.obj is not None and np.isfinite(res.obj):
        constant = f" (incl. the constant {prob.objective_constant:g})" if prob.objective_constant else ""
        rows.append(("objective", f"{res.obj + prob.objective_constant:.10g}{constant}"))
    return rows


#: What each outcome but SOLVED means, in one line, in the command line's terms (the API's
#: ``Status.message`` says it at length, for every kind; the JSON output keeps that).
_STATUS_LINES = {
    Status.MAX_PIVOTS: "stopped at the pivot limit; raise --max-pivots (Lemke's method can need exponentially many)",
    Status.RAY_TERMINATION: "ended on a secondary ray: no solution found (none exists if M is copositive-plus)",
    Status.NUMERICAL_FAILURE: "the final point failed the check on the data (rounding); rescale, or loosen --tol",
    Status.CYCLING: "the method cycled, its restarts too; rescale or perturb the problem, or try another --method",
    Status.TIME_LIMIT: "stopped at the time limit; raise --time-limit",
    Status.INTERRUPTED: "interrupted before it ended",
    Status.PRIMAL_INFEASIBLE: "infeasible: the constraints contradict each other (the certificate is in --json)",
    Status.DUAL_INFEASIBLE: "unbounded below: no optimum (the direction is in --json's certificate)",
}


def _status_line(prob, res) -> str:
    """``SOLVED: z >= 0, ...``: the outcome and what it means for this kind, in one short line."""
    what = KINDS[prob.kind].solved if res.status == Status.SOLVED else _STATUS_LINES.get(res.status, res.message)
    return f"{res.status.name}: {what}"


def _report(prob, res, seconds: float) -> str:
    lines = [f"{prob.name} ({prob.kind.upper()}, {prob.size_text()})", f"  from       {prob.source}",
             f"  status     {_status_line(prob, res)}", f"  pivots     {res.pivots}",
             f"  residual   {KINDS[prob.kind].residual(res):.3g}", f"  time       {_ms(seconds)}"]
    lines += [f"  {key:10s} {text}" for key, text in _solution(prob, res)]
    return "\n".join(lines)


def _ms(seconds: float) -> str:
    return f"{seconds * 1e3:.3f} ms" if seconds < 1 else f"{seconds:.3f} s"


def _size(prob) -> str:
    return KINDS[prob.kind].size_short(prob.shape)


def _table(rows: list[dict], left: int = 0) -> str:
    head = ("name", "kind", "size", "status", "pivots", "residual", "time")
    cells = [head]
    for r in rows:
        if "error" in r:
            cells.append((r["name"], r.get("kind", "-"), r.get("size", "-"), "ERROR", "-", "-", "-"))
        else:
            cells.append((r["name"], r["kind"], r["size"], r["status"], str(r["pivots"]),
                          f"{r['residual_']:.2g}", _ms(r["time_s"])))
    widths = [max(len(c[i]) for c in cells) for i in range(len(head))]
    right = {4, 5, 6}
    lines = ["  ".join(c.rjust(w) if i in right else c.ljust(w) for i, (c, w) in enumerate(zip(cell, widths))).rstrip()
             for cell in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    solved = sum(r.get("status") == "SOLVED" for r in rows)
    errors = sum("error" in r for r in rows)
    total = sum(r.get("time_s", 0.0) for r in rows)
    lines.append(f"{len(rows)} problems: {solved} solved, {len(rows) - solved - errors} not solved, "
                 f"{errors} bad input{' (errors above)' if errors else ''}; solve time {_ms(total)}"
                 + (f"; interrupted, {left} not run" if left else ""))
    kinds = [KINDS[k] for k in dict.fromkeys(r.get("kind") for r in rows) if k in KINDS]
    if kinds and kinds != [next(iter(KINDS.values()))]:  # more than plain LCPs: say what size means
        lines.append("size: " + ", ".join(k.size_legend for k in KINDS.values()))
    return "\n".join(lines)


class _Progress:
    """A one-line progress bar on stderr, only when stderr is a terminal (and not --quiet)."""

    def __init__(self, total: int, quiet: bool = False):
        self.total = total
        self.on = total > 1 and not quiet and sys.stderr.isatty()

    def show(self, done: int, label: str) -> None:
        if self.on:
            filled = 30 * done // self.total
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (30 - filled)}] {done}/{self.total} {label[:40]:40s}")
            sys.stderr.flush()

    def clear(self) -> None:
        if self.on:
            sys.stderr.write("\r" + " " * 80 + "\r")
            sys.stderr.flush()


# --------------------------------------------------------------------------- commands

def _options(args) -> Options:
    opts = {k: getattr(args, k) for k in ("max_pivots", "time_limit", "tol", "pivot_tol", "tie_tol") if getattr(args, k) is not None}
    return Options(**opts)


def _check_out(out: str | None, sources: list) -> None:
    if out is None:
        return
    suffix = Path(out).suffix.lower()
    if suffix not in (".json", ".npz"):
        raise _UsageError(f"--out {out}: the result is written as .json or .npz, not {suffix or 'a file without extension'}")
    if suffix == ".npz" and len(sources) > 1:
        raise _UsageError(f"--out {out}: several results are written as .json (a list), not .npz")
    if Path(out).is_dir():
        raise _UsageError(f"--out {out}: is a directory")
    for src in sources:
        if isinstance(src, Path) and _same(out, src):
            raise _UsageError(f"--out {out}: refusing to write over the input file {src}")


def _same(a, b) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def _solve(args) -> int:
    if not args.source:  # said on stderr under --json, so that stdout stays JSON
        print(f"No problem given: solving the built-in example {DEFAULT_PROBLEM!r} "
              "(`lemke problems` lists the others; `lemke solve FILE` solves a file).",
              file=sys.stderr if args.json else sys.stdout)
    sources = _sources(args.source or [DEFAULT_PROBLEM])
    _check_out(args.out, sources)
    return _in_worker(_Run(args, sources))


class _Run:
    """One ``lemke solve``: the sources, the rows finished so far, and the lock under which
    everything is printed or written, so that an interrupt never cuts an output short."""

    def __init__(self, args, sources: list):
        self.args, self.sources = args, sources
        self.single = len(sources) == 1
        self.rows: list[dict] = []
        self.lock = threading.Lock()
        self.reported = False
        self.progress = _Progress(len(sources), getattr(args, "quiet", False))

    def work(self) -> int:
        """Solve every source, each reported as it ends, then the summary (the worker thread)."""
        options = _options(self.args)
        for k, src in enumerate(self.sources):
            with self.lock:
                self.progress.show(k, src.name)
            row = _run_one(src, self.args, options)
            if row.get("status") == "INTERRUPTED":  # Ctrl-C stopped it: not a finished row
                raise KeyboardInterrupt
            with self.lock:
                self.rows.append(row)
                if "error" in row:
                    self.progress.clear()
                    print(f"lemke: error: {row['error']}", file=sys.stderr, flush=True)
                elif self.single and not self.args.json:
                    print(_report(row["problem"], row["result"], row["time_s"]), flush=True)
        with self.lock:
            self.report()
        return self.code()

    def code(self) -> int:
        """The worst outcome: 2 an input error, 1 not solved, 0 all solved."""
        return max((2 if "error" in r else 0 if r["status"] == "SOLVED" else 1 for r in self.rows), default=0)

    def report(self) -> None:
        """The JSON or the table of the finished rows on stdout, and ``--out``; once.  Called
        with the lock held (by the worker at the end, or by the main thread on an interrupt:
        then the rows are those finished before it)."""
        if self.reported:
            return
        self.reported = True
        self.progress.clear()
        docs = [_doc(row) for row in self.rows]
        left = len(self.sources) - len(self.rows)
        if self.args.json:
            if not self.single:
                print("[\n" + ",\n".join(map(_json, docs)) + "\n]")
            elif docs:
                print(_json(docs[0]))
        elif not self.single and (self.rows or not left):
            print(_table(self.rows, left))
        sys.stdout.flush()
        if self.args.out is not None:
            _write_out(self.args.out, docs, self.rows, self.sources)


#: How often (seconds) the main thread looks whether Ctrl-C was pressed while the worker runs.
_POLL = 0.01


def _in_worker(run: _Run) -> int:
    """``run.work()`` in a worker thread, the main thread waiting for it or for SIGINT.

    On SIGINT (or a KeyboardInterrupt out of the work) the finished rows are reported and
    written, under the run's lock (so no output is cut short, and none is written twice),
    one line says so on stderr, and the exit code is 130: the process ends there
    (``os._exit``) while the worker still runs a kernel, which would not stop."""
    box: dict = {}
    done = threading.Event()
    asked = threading.Event()

    def work():
        try:
            box["code"] = run.work()
        except BaseException as exc:  # given to the main thread, which says it
            box["error"] = exc
        finally:
            done.set()

    on_main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, lambda signum, frame: asked.set()) if on_main else None
    try:
        worker = threading.Thread(target=work, name="lemke-solve", daemon=True)
        worker.start()
        try:
            while not done.wait(_POLL) and not asked.is_set():
                pass
        except KeyboardInterrupt:  # only where another handler was in force before ours
            asked.set()
        if asked.is_set() or isinstance(box.get("error"), KeyboardInterrupt):
            return _interrupted(run, still_running=not done.is_set())
        if "error" in box:
            raise box["error"]
        return box["code"]
    finally:
        if on_main:
            signal.signal(signal.SIGINT, previous if previous is not None else signal.SIG_DFL)


def _interrupted(run: _Run, still_running: bool) -> int:
    """Report and write what is finished, say "interrupted", and end: 130."""
    with run.lock:  # waits for an output in progress; the worker prints nothing after this
        try:
            run.report()
        except _UsageError as exc:  # --out could not be written
            print(f"lemke: error: {exc}", file=sys.stderr)
        except BrokenPipeError:
            pass
        print("lemke: interrupted", file=sys.stderr)
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        if still_running:  # the kernel does not stop: end the process here, not at its end
            os._exit(130)
    return 130


_WARM = set()


def _warm_up(kind: str, method: str) -> None:
    """Load a kind's front and touch its code paths once before timing a problem of that
    kind: the times shown are those of the solves."""
    if (kind, method) not in _WARM:
        _WARM.add((kind, method))
        Problem(kind, KINDS[kind].example).solve(method=method)


def _json(doc: dict) -> str:
    """A result as JSON, one key a line (arrays on one line)."""
    items = (f" {json.dumps(k)}: {json.dumps(v, allow_nan=False)}" for k, v in doc.items())
    return "{\n" + ",\n".join(items) + "\n}"


def _doc(row: dict) -> dict:
    if "error" in row:
        return {"name": row["name"], "error": row["error"]}
    return result_to_dict(row["result"], row["problem"], time_s=row["time_s"])


def _write_out(out: str, docs: list, rows: list, sources: list) -> None:
    """Write the results (atomically: a temporary file, then ``os.replace``): a list for
    several sources (those finished, on an interrupt), the one result for one source (nothing
    when it was not read, or not finished)."""
    protect = [s for s in sources if isinstance(s, Path)]
    try:
        if len(sources) > 1:
            write_result(docs, out, protect=protect)
        elif rows and "error" not in rows[0]:
            row = rows[0]
            write_result(row["result"], out, problem=row["problem"], protect=protect, time_s=row["time_s"])
    except (OSError, ValueError) as exc:
        raise _UsageError(f"--out {out}: cannot write: {getattr(exc, 'strerror', None) or exc}") from None


def _run_one(src, args, options) -> dict:
    """Read and solve one source: its row of the table (with "error", or the result)."""
    if isinstance(src, _Bad):
        return {"name": src.name, "error": src.error}
    if isinstance(src, Path):
        try:
            prob = read_problem(src, format=args.format)
        except ProblemFormatError as exc:
            return {"name": src.name, "error": str(exc)}
        name, where = src.name, str(src)
    else:
        prob, name, where = src, src.name, src.name
    row = {"name": name, "kind": prob.kind, "size": _size(prob), "problem": prob}
    try:
        kind = KINDS[prob.kind]
        method = args.method
        if method is not None and method not in kind.methods:
            raise ValueError(f"--method {method} does not apply to a {prob.kind} problem "
                             f"(its methods: {', '.join(kind.methods)})")
        _warm_up(prob.kind, method)
        t0 = time.perf_counter()
        res = prob.solve(method=method, options=options)
    except (NotImplementedError, ValueError, TypeError) as exc:  # the solver refused the data
        return dict(row, error=f"{where}: {' '.join(str(exc).split())}")
    row.update(status=res.status.name, pivots=res.pivots, residual_=kind.residual(res),
               time_s=time.perf_counter() - t0, result=res)
    return row


def _list_problems() -> int:
    named = [fn() for fn in problems.NAMED.values()]
    width = max(len(p.name) for p in named) + 2
    print("Built-in problems (`lemke solve NAME`; murty-N for Murty's example of size N):")
    for p in named:
        murty = p.name.startswith("murty")
        size = f"n = N (default {p.q.size})" if murty else p.size_text()
        print(f"  {'murty-N' if murty else p.name:{width}s}{p.kind.upper():5s} {size}")
        print(f"  {'':{width}s}{p.source}")
    return 0


def main(argv=None) -> int:
    try:
        args = _parser().parse_args(argv)
        if args.version:
            print(f"lemke {__version__}")
            return 0
        if args.command == "problems":
            return _list_problems()
        if args.command == "solve":
            return _solve(args)
        raise _UsageError("no command given; try `lemke solve` or `lemke problems` (or --help)")
    except _UsageError as exc:
        print(f"lemke: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("lemke: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `lemke solve dir | head`
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 1
    except Exception as exc:  # never a traceback; LEMKE_TRACEBACK=1 shows it
        if os.environ.get("LEMKE_TRACEBACK"):
            raise
        print(f"lemke: error: internal error ({type(exc).__name__}: {' '.join(str(exc).split())}); "
              "set LEMKE_TRACEBACK=1 to see where", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
