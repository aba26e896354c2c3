#!/usr/bin/env python
"""Benchmark ``lemke.solve_lcp`` against ``quantecon.optimize.lcp_lemke``.

Usage::

    python benchmarks/bench_lcp.py [--sizes 5 20 100 300 1000] [--repeats N]
                                   [--min-time 0.2] [--out benchmarks/RESULTS-lcp.md]

Problems
    Random monotone LCPs, generated identically for both solvers:
    ``M = A A' + (B - B')`` with A, B standard normal n x n scaled by 1/sqrt(n)
    (positive semidefinite symmetric part plus a skew part), ``q`` standard normal.
    Problem k of size n uses ``numpy.random.default_rng([SEED, n, k])``.

Timing
    Both solvers are compiled (warmed up) before anything is timed.  For every problem the
    two solvers are called alternately (solver order swapped on every repeat), each call
    timed with ``time.perf_counter``; the per-problem time is the median over repeats.
    Without ``--repeats`` the repeat count is chosen so the faster solver gets about
    ``--min-time`` seconds per problem (at least 3 repeats).  Per size the table gives the
    median over problems of those per-problem medians, and the median of the per-problem
    ratios lemke / quantecon.

Checks
    Both answers are checked the same way by this script: ``w = M z + q`` recomputed from M
    and q, residual ``max_i |min(z_i, w_i)|``.  lemke counts as solved when its status is
    SOLVED; quantecon when its status is 0 and the residual is at most
    ``RESID_RTOL * max(max|M|, max|q|, max|M| max|z|)``.

First call
    In fresh subprocesses: ``import lemke`` time, and the first ``solve_lcp`` call, in a
    first process and again in a second one (nothing is compiled at run time: the two
    differ by the OS's file cache only).
"""
from __future__ import annotations

import argparse
import datetime as _dt
import gc
import json
import math
import os
import platform
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time

import numpy as np

try:
    import lemke
except ImportError:  # running from a checkout without `pip install -e .`
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import lemke

try:
    import quantecon
    from quantecon.optimize import lcp_lemke
except ImportError:  # main() says so; harness.py imports this module without quantecon too
    quantecon = lcp_lemke = None

SEED = 20240601
RESID_RTOL = 1e-8
DEFAULT_SIZES = (5, 20, 100, 300, 1000)
LEMKE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(lemke.__file__)))


# --------------------------------------------------------------------------- problems

def make_factors(n: int, k: int):
    """The data of problem k of size n: A, B (standard normal / sqrt(n)) and q ~ N(0, I)."""
    rng = np.random.default_rng([SEED, n, k])
    s = 1.0 / math.sqrt(n)
    A = rng.standard_normal((n, n)) * s
    B = rng.standard_normal((n, n)) * s
    q = rng.standard_normal(n)
    return A, B, q


def assemble(A, B):
    """M = A A' + (B - B'): positive semidefinite symmetric part plus a skew part."""
    return np.ascontiguousarray(A @ A.T + (B - B.T))


def make_problem(n: int, k: int):
    """Problem k of size n: M = A A' + (B - B'), q ~ N(0, I)."""
    A, B, q = make_factors(n, k)
    return assemble(A, B), q


def default_problem_count(n: int) -> int:
    if n <= 20:
        return 20
    if n <= 100:
        return 10
    if n <= 300:
        return 5
    return 3


def residual(M, q, z) -> float:
    z = np.asarray(z, dtype=np.float64)
    w = M @ z + q
    return float(np.max(np.abs(np.minimum(z, w)))) if z.size else 0.0


def resid_scale(M, q, z) -> float:
    mM = float(np.max(np.abs(M)))
    return max(mM, float(np.max(np.abs(q))), mM * float(np.max(np.abs(z))))


# --------------------------------------------------------------------------- timing

def run_lemke(M, q):
    return lemke.solve_lcp(M, q)


def run_qe(M, q):
    return lcp_lemke(M, q)


def warm_up():
    """Warm both solvers up (quantecon compiles its kernels) before anything is timed."""
    for n in (3, 10):
        M, q = make_problem(n, 10_000)
        run_lemke(M, q)
        run_qe(M, q)


def time_problem(M, q, repeats, min_time, max_repeats):
    # One untimed call each (also primes memory), then one timed call each to calibrate.
    run_lemke(M, q)
    run_qe(M, q)
    t = time.perf_counter()
    rl = run_lemke(M, q)
    t_l = time.perf_counter() - t
    t = time.perf_counter()
    rq = run_qe(M, q)
    t_q = time.perf_counter() - t
    if repeats is None:
        reps = math.ceil(min_time / max(min(t_l, t_q), 1e-7))
        reps = min(max(reps, 3), max_repeats)
    else:
        reps = repeats
    (tl, tq), _ = time_interleaved([lambda: run_lemke(M, q), lambda: run_qe(M, q)], reps)
    return rl, rq, statistics.median(tl), statistics.median(tq), reps


def time_interleaved(calls, reps, start=0, collect=True, keep_results=False, rng=None):
    """Call every function in ``calls`` (no arguments) ``reps`` times, interleaved: repeat i
    runs them in the order rotated by ``start + i`` (for two calls: order swapped every
    repeat), or, given a numpy Generator ``rng``, in a random order drawn from it for every
    repeat (with three or more calls a rotation keeps each call's predecessor fixed, which
    can bias the times through cache effects).  Each call is timed with
    ``time.perf_counter``; the garbage collector is off during the loop (after a
    ``gc.collect()`` unless ``collect`` is false).

    Returns ``(times, results)``: ``times[j]`` lists the seconds of every call of
    ``calls[j]``; ``results[j]`` lists what those calls returned (all of them with
    ``keep_results``, else only the last one's).
    """
    k = len(calls)
    times = [[] for _ in range(k)]
    results = [[] for _ in range(k)]
    gc_was_enabled = gc.isenabled()
    if collect:
        gc.collect()
    gc.disable()
    try:
        pc = time.perf_counter
        for i in range(reps):
            if rng is not None:
                order = rng.permutation(k).tolist()
            else:
                r = (start + i) % k if k else 0
                order = [*range(r, k), *range(r)]
            for j in order:
                f = calls[j]
                t0 = pc()
                out = f()
                t1 = pc()
                times[j].append(t1 - t0)
                if keep_results:
                    results[j].append(out)
                else:
                    results[j] = [out]
    finally:
        if gc_was_enabled:
            gc.enable()
    return times, results


def bench_sizes(sizes, problems, repeats, min_time, max_repeats, log):
    rows, details = [], []
    for n in sizes:
        count = problems if problems is not None else default_problem_count(n)
        per = []
        t_size = time.perf_counter()
        for k in range(count):
            M, q = make_problem(n, k)
            rl, rq, t_l, t_q, reps = time_problem(M, q, repeats, min_time, max_repeats)
            zl = np.asarray(rl.z)
            zq = np.asarray(rq.z)
            res_l = residual(M, q, zl)
            res_q = residual(M, q, zq)
            ok_l = rl.status == lemke.Status.SOLVED
            ok_q = int(rq.status) == 0 and res_q <= RESID_RTOL * resid_scale(M, q, zq)
            d = dict(
                n=n, k=k, reps=reps, t_lemke=t_l, t_qe=t_q, ratio=t_l / t_q,
                piv_lemke=int(rl.pivots), piv_qe=int(rq.num_iter),
                res_lemke=res_l, res_qe=res_q, lemke_reported_res=float(rl.residual),
                status_lemke=rl.status.name, status_qe=int(rq.status),
                ok_lemke=bool(ok_l), ok_qe=bool(ok_q),
                dz=float(np.max(np.abs(zl - zq))) if n else 0.0,
            )
            per.append(d)
            details.append(d)
        rows.append(dict(
            n=n, problems=count,
            t_lemke=statistics.median(d["t_lemke"] for d in per),
            t_qe=statistics.median(d["t_qe"] for d in per),
            ratio=statistics.median(d["ratio"] for d in per),
            piv_lemke=statistics.median(d["piv_lemke"] for d in per),
            piv_qe=statistics.median(d["piv_qe"] for d in per),
            res_lemke=max(d["res_lemke"] for d in per),
            res_qe=max(d["res_qe"] for d in per),
            ok_lemke=sum(d["ok_lemke"] for d in per),
            ok_qe=sum(d["ok_qe"] for d in per),
            dz=max(d["dz"] for d in per),
            reps=(min(d["reps"] for d in per), max(d["reps"] for d in per)),
        ))
        log(f"n={n}: {count} problems in {time.perf_counter() - t_size:.1f} s")
    return rows, details


# --------------------------------------------------------------------------- first call

_FIRST_CALL = textwrap.dedent("""
    import json, time
    t0 = time.perf_counter()
    import lemke
    t1 = time.perf_counter()
    import numpy as np
    rng = np.random.default_rng(7)
    n = 10
    A = rng.standard_normal((n, n)); B = rng.standard_normal((n, n))
    M = A @ A.T + (B - B.T); q = rng.standard_normal(n)
    t2 = time.perf_counter()
    r = lemke.solve_lcp(M, q)
    t3 = time.perf_counter()
    lemke.solve_lcp(M, q)
    t4 = time.perf_counter()
    print(json.dumps(dict(import_s=t1 - t0, first_s=t3 - t2, second_s=t4 - t3,
                          status=r.status.name, pivots=r.pivots)))
""")

_IMPORT_ONLY = textwrap.dedent("""
    import json, sys, time
    t0 = time.perf_counter()
    import lemke
    t1 = time.perf_counter()
    print(json.dumps(dict(import_s=t1 - t0, scipy_loaded="scipy" in sys.modules)))
""")

_IMPORT_BREAKDOWN = textwrap.dedent("""
    import json, time
    t0 = time.perf_counter()
    import numpy
    t1 = time.perf_counter()
    import lemke
    t3 = time.perf_counter()
    print(json.dumps(dict(numpy_s=t1 - t0, lemke_rest_s=t3 - t1)))
""")


def _subprocess(code, extra_env=None, args=()):
    env = dict(os.environ)
    env["PYTHONPATH"] = LEMKE_ROOT + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    if extra_env:
        env.update(extra_env)
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True, text=True,
                       cwd=tempfile.gettempdir())
    wall = time.perf_counter() - t
    if p.returncode != 0:
        raise RuntimeError(f"subprocess failed ({p.returncode}):\n{p.stderr}")
    out = json.loads(p.stdout.strip().splitlines()[-1])
    out["wall_s"] = wall
    return out


def first_call(runs, log):
    cold, warm = [], []
    for _ in range(runs):
        cold.append(_subprocess(_FIRST_CALL))
        warm.append(_subprocess(_FIRST_CALL))
    imports = [_subprocess(_IMPORT_ONLY) for _ in range(max(runs, 5))]
    breakdown = [_subprocess(_IMPORT_BREAKDOWN) for _ in range(max(runs, 5))]
    log(f"first call: {runs} + {runs} subprocesses")
    return dict(cold=cold, warm=warm, imports=imports, breakdown=breakdown)


# --------------------------------------------------------------------------- machine

def machine_info():
    cpu = None
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    cpu = cpu or platform.processor() or platform.machine()
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count()
    import scipy
    try:
        import numba  # quantecon's compiler (the peer's), where installed
        numba_version = numba.__version__
    except ImportError:
        numba_version = "not installed"
    commit = None
    try:
        commit = subprocess.run(["git", "-C", LEMKE_ROOT, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", LEMKE_ROOT, "status", "--porcelain", "lemke"],
                               capture_output=True, text=True, check=True).stdout.strip()
        if dirty:
            commit += " (plus uncommitted or untracked files under lemke/)"
    except (OSError, subprocess.CalledProcessError):
        pass
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):
        load = None
    return dict(
        load=load, lemke_path=os.path.dirname(os.path.abspath(lemke.__file__)),
        date=_dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        cpu=cpu, cores=os.cpu_count(), usable_cores=usable,
        platform=platform.platform(),
        python=f"{platform.python_implementation()} {platform.python_version()}",
        numpy=np.__version__, scipy=scipy.__version__, numba=numba_version,
        quantecon=quantecon.__version__ if quantecon else "not installed", lemke=getattr(lemke, "__version__", "?"),
        commit=commit,
    )


# --------------------------------------------------------------------------- report

def _t(s):
    if s < 1e-3:
        return f"{s * 1e6:.1f} µs"
    if s < 1.0:
        return f"{s * 1e3:.2f} ms"
    return f"{s:.2f} s"


def _med(xs, key):
    return statistics.median(x[key] for x in xs)


def _code(text):
    """``text`` as a markdown code span (a longer fence when it contains backticks)."""
    fence = "`" * (max((len(m) for m in re.findall("`+", text)), default=0) + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def fmt_range(pair):
    """``(lo, hi)`` as ``lo`` or ``lo–hi``."""
    lo, hi = pair
    return f"{lo}" if lo == hi else f"{lo}–{hi}"


def report_head(title, script, args, total_s, info, extra_versions="", commit_note="",
                extra_lines=()):
    """The lines every benchmark report starts with: title, the command line that made it
    (``args.argv``, shell-quoted) and the "Machine" section from ``info`` (``machine_info()``,
    updated by ``mark_end``).  ``extra_versions`` is appended to the versions line,
    ``commit_note`` to the lemke line, ``extra_lines`` (bullets) go before ``args.note``."""
    cmd = " ".join([f"python benchmarks/{script}", *map(shlex.quote, args.argv)])
    L = [f"# {title}", "", f"Generated by {_code(cmd)} in {total_s:.0f} s.", "", "## Machine", ""]
    a = L.append
    a(f"- Date: {info['date']}")
    a(f"- CPU: {info['cpu']}; {info['cores']} logical cores ({info['usable_cores']} usable)")
    a(f"- Platform: {info['platform']}")
    a(f"- {info['python']}; numpy {info['numpy']}, scipy {info['scipy']}, numba {info['numba']}, "
      f"quantecon {info['quantecon']}{extra_versions}")
    a(f"- lemke {info['lemke']} from `{info['lemke_path']}`"
      + (f", commit {info['commit']}" if info["commit"] else "") + commit_note)
    if info.get("end_commit") != info["commit"]:
        a(f"- **The lemke checkout changed during the run**: at the end it was "
          f"{info.get('end_commit')}; rerun on a quiet checkout.")
    if info["load"] is not None:
        a(f"- 1-minute load average: {info['load']:.2f} at the start, "
          f"{info.get('end_load', float('nan')):.2f} at the end (other processes on the "
          "machine make the timings noisier)")
    L.extend(extra_lines)
    if args.note:
        a(f"- Note: {args.note}")
    a("")
    return L


def mark_end(info):
    """Record the commit and load at the end of the run in ``info`` (for ``report_head``)."""
    end = machine_info()
    info["end_commit"], info["end_load"] = end["commit"], end["load"]


def report_parser(doc, default_name, argv=None):
    """``(parser, argv)``: an argument parser described by the first paragraph of ``doc``, with
    the report options ``--note`` and ``--out`` (default: ``default_name`` next to this
    script); ``argv`` defaults to ``sys.argv[1:]``."""
    argv = sys.argv[1:] if argv is None else argv
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--note", default="", help="free text for the report's machine section")
    parser.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                      default_name),
                        help=f"the markdown report (default benchmarks/{default_name})")
    return parser, argv


def publish(text, path, log):
    """Write the report atomically to ``path`` and print it."""
    write_atomic(path, text)
    print(text)
    log(f"wrote {path}")


def render(info, args, rows, details, fc, total_s):
    L = report_head("lemke vs quantecon: LCP benchmark", "bench_lcp.py", args, total_s, info)
    a = L.append
    a("## Problems and method")
    a("")
    a("Random monotone LCPs: `M = A A' + (B - B')`, A and B standard normal n x n scaled by "
      "1/sqrt(n), `q` standard normal; problem k of size n uses "
      f"`numpy.random.default_rng([{SEED}, n, k])`. Both solvers get the same float64 arrays "
      "and default options.")
    a("")
    a("Each problem: both solvers warmed up (quantecon's compilation excluded), then called "
      "alternately, solver order swapped every repeat, each call timed with "
      "`time.perf_counter` (GC off); per-problem time = median over repeats. "
      + ("Repeats per problem: " + (f"{args.repeats} (fixed)." if args.repeats else
         f"enough for ~{args.min_time:g} s of the faster solver, at least 3.")))
    a("Per size: *time* = median over problems of the per-problem medians; *ratio* = median of "
      "the per-problem ratios lemke / quantecon (< 1: lemke faster). Timings of lemke include "
      "its Python front end (input validation and copies, the check of the answer on the "
      "caller's data, building the result).")
    a("")
    a("*Residual* = max over problems of `max_i |min(z_i, w_i)|`, with `w = M z + q` recomputed "
      "by this script for both solvers. *Solved*: lemke `status == SOLVED`; quantecon "
      f"`status == 0` and residual <= {RESID_RTOL:g} * max(max|M|, max|q|, max|M| max|z|). "
      "*max |Δz|*: largest difference between the two solvers' z (M is positive definite "
      "here, so the solution is unique).")
    a("")
    a("## Results")
    a("")
    a("| n | problems | repeats | lemke time | quantecon time | ratio lemke/qe | pivots lemke | "
      "pivots qe | residual lemke | residual qe | solved lemke | solved qe | max \\|Δz\\| |")
    a("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        a(f"| {r['n']} | {r['problems']} | {fmt_range(r['reps'])} | {_t(r['t_lemke'])} | {_t(r['t_qe'])} | "
          f"{r['ratio']:.2f} | {r['piv_lemke']:g} | {r['piv_qe']:g} | {r['res_lemke']:.1e} | "
          f"{r['res_qe']:.1e} | {r['ok_lemke']}/{r['problems']} | {r['ok_qe']}/{r['problems']} | "
          f"{r['dz']:.1e} |")
    a("")
    odd = [d for d in details if not d["ok_lemke"] or not d["ok_qe"] or d["piv_lemke"] != d["piv_qe"]]
    if odd:
        a("### Problems where the solvers disagree or fail")
        a("")
        a("| n | k | status lemke | status qe | pivots lemke | pivots qe | residual lemke | residual qe |")
        a("|---:|---:|---|---:|---:|---:|---:|---:|")
        for d in odd:
            a(f"| {d['n']} | {d['k']} | {d['status_lemke']} | {d['status_qe']} | {d['piv_lemke']} | "
              f"{d['piv_qe']} | {d['res_lemke']:.1e} | {d['res_qe']:.1e} |")
        a("")
        a("Reproduce one with `make_problem(n, k)` from this script.")
    else:
        a("Both solvers solved every problem, with the same pivot count on every problem.")
    a("")
    a("## First call and import (fresh subprocesses)")
    a("")
    runs = len(fc["cold"])
    a(f"Problem: n = 10 random PSD LCP. Times measured inside the subprocess with "
      f"`time.perf_counter` (interpreter start-up excluded); median of {runs} runs "
      f"(imports: {len(fc['imports'])} runs); every run listed.")
    a("")
    a("| measurement | median | runs |")
    a("|---|---:|---|")

    def line(name, xs, key):
        vals = ", ".join(_t(x[key]) + ("*" if x.get("cache_rewritten") else "") for x in xs)
        a(f"| {name} | {_t(_med(xs, key))} | {vals} |")

    line("`import lemke` (fresh process, nothing imported before)", fc["imports"], "import_s")
    line("  ↳ same runs, whole process wall time (incl. interpreter start-up)", fc["imports"], "wall_s")
    line("  ↳ split (separate runs): `import numpy`", fc["breakdown"], "numpy_s")
    line("  ↳ split: then `import lemke`", fc["breakdown"], "lemke_rest_s")
    line("first `solve_lcp` call, first process", fc["cold"], "first_s")
    line("first `solve_lcp` call, second process", fc["warm"], "first_s")
    line("second `solve_lcp` call (same process, for reference)", fc["warm"], "second_s")
    a("")
    a(f"After `import lemke`, scipy is loaded: {fc['imports'][0]['scipy_loaded']}.")
    a("")
    a("## Per-problem data")
    a("")
    a("<details><summary>all problems</summary>")
    a("")
    a("| n | k | repeats | lemke | quantecon | ratio | pivots l/qe | residual lemke | residual qe |")
    a("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for d in details:
        a(f"| {d['n']} | {d['k']} | {d['reps']} | {_t(d['t_lemke'])} | {_t(d['t_qe'])} | "
          f"{d['ratio']:.2f} | {d['piv_lemke']}/{d['piv_qe']} | {d['res_lemke']:.1e} | "
          f"{d['res_qe']:.1e} |")
    a("")
    a("</details>")
    a("")
    return "\n".join(L)


def write_atomic(path, text):
    """Write the report in one step (lemke's own atomic writer: a reader never sees half)."""
    from lemke._io.common import atomic_write

    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    atomic_write(path, lambda fh: fh.write(text.encode("utf-8")))


def main(argv=None):
    if quantecon is None:
        sys.exit("quantecon is needed for the comparison: pip install -e \".[bench]\"")
    p, argv = report_parser(__doc__, "RESULTS-lcp.md", argv)
    p.add_argument("--sizes", type=int, nargs="+", default=list(DEFAULT_SIZES))
    p.add_argument("--repeats", type=int, default=None,
                   help="timed calls per solver per problem (default: auto, see --min-time)")
    p.add_argument("--min-time", type=float, default=0.2,
                   help="with auto repeats: seconds of timed calls for the faster solver per "
                        "problem (default 0.2; at least 3 repeats)")
    p.add_argument("--max-repeats", type=int, default=20000)
    p.add_argument("--problems", type=int, default=None,
                   help="problems per size (default: 20 for n <= 20, 10 for n <= 100, "
                        "5 for n <= 300, else 3)")
    p.add_argument("--first-call-runs", type=int, default=3,
                   help="fresh subprocesses per first-call measurement (0: skip)")
    args = p.parse_args(argv)
    args.argv = list(argv)
    if args.repeats is not None and args.repeats < 1:
        p.error("--repeats must be >= 1")
    if any(n < 1 for n in args.sizes):
        p.error("--sizes must be positive")

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    t0 = time.perf_counter()
    info = machine_info()
    warm_up()
    rows, details = bench_sizes(args.sizes, args.problems, args.repeats, args.min_time,
                                args.max_repeats, log)
    if args.first_call_runs > 0:
        fc = first_call(args.first_call_runs, log)
    else:
        fc = None
    mark_end(info)
    text = render(info, args, rows, details, fc, time.perf_counter() - t0) if fc else \
        render_no_fc(info, args, rows, details, time.perf_counter() - t0)
    publish(text, args.out, log)


def render_no_fc(info, args, rows, details, total_s):
    text = render(info, args, rows, details, _EMPTY_FC, total_s)
    head, _, tail = text.partition("## First call and import")
    _, _, rest = tail.partition("## Per-problem data")
    return head + "## Per-problem data" + rest


_EMPTY_FC = dict(
    cold=[dict(first_s=float("nan"))], warm=[dict(first_s=float("nan"), second_s=float("nan"))],
    imports=[dict(import_s=float("nan"), wall_s=float("nan"), scipy_loaded=None)],
    breakdown=[dict(numpy_s=float("nan"), lemke_rest_s=float("nan"))],
)

if __name__ == "__main__":
    main()
