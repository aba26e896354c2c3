#!/usr/bin/env python
"""``method="unrevised"`` against ``method="tableau"`` on a quiet and on a loaded machine.

Usage::

    python benchmarks/bench_threads.py                       # this checkout's lemke
    python benchmarks/bench_threads.py --versions before=/tmp/lemke_old after=.

Times the two methods of ``lemke.solve_lcp`` interleaved (the order swapped every repeat,
medians over repeats) on two families at n = 100 and 300, a random P-matrix (positive
definite symmetric part plus a skew part, ``lemke.problems.random_p_matrix``) and a
rank-deficient contact-like LCP (``lemke.problems.contact_like``), in four sections:

* ``quiet``: nothing else started by this script;
* ``loaded``: beside a second process that keeps the CPU busy (numpy matrix products in a
  loop, with numpy's default BLAS threads: one per core);
* ``batch`` and ``batch-loaded``: ``lemke.solve_lcp_batch`` on all the problems of a family
  and size at once (``--workers``, 2), without and with that second process.

The quiet and loaded sections also time warm starts at every size (``solve_lcp`` with the
tableau's final ``warm_start`` on q moved by 1e-9 times a random vector, where the old basis
still solves it, and by 0.05 times one, where Lemke restarts from it; for the contact
family the vector is non-negative so that the problem stays solvable): their factorization
is called from the Python side.

Each section runs in a fresh subprocess per lemke version (``--versions LABEL=PATH``: PATH is
put first on PYTHONPATH, so it is a directory holding a ``lemke`` package), the versions
alternating order from section to section.  A version that still compiles its kernels
(those before the C++ core) does so once into a numba cache of its own (``NUMBA_CACHE_DIR``, a temporary directory): numba's on-disk cache
keys a kernel by its own source file only, so a cache left by an older ``unrevised.py``
would still serve ``cold.py``'s kernels that inline it.  The subprocesses and the load
process run with the BLAS thread variables (``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS``,
``MKL_NUM_THREADS``) removed from their environment, so numpy and scipy use their default
thread pools, unless ``--blas-threads N`` sets them.  Every answer is checked by lemke
itself (a status other than SOLVED is marked in the report) and the two methods' pivot
counts are compared.

The report gives the machine (``nproc``, CPU model), the load average sampled while each
subprocess runs and the CPU time the load process used, and per family and size the median
times and the ratio unrevised / tableau (median over the problems of the per-problem ratio
of medians; the batch ratio is that of the median batch times), in wall-clock time and in
the CPU time of the whole process (a BLAS thread pool spinning beside the solver shows up
in the second).
"""
from __future__ import annotations

import argparse
import datetime as _dt
import gc
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEED = 20251107
FAMILIES = ("pmatrix", "contact")
SECTIONS = ("quiet", "loaded", "batch", "batch-loaded")
WARM_MOVES = (1e-9, 0.05)  # the old basis still solves it; Lemke restarts from it
BLAS_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")

LOADER = r"""
import sys, numpy as np
a = np.random.default_rng(0).standard_normal((400, 400))
b = a.copy()
c = a @ b
print("ready", flush=True)
while True:
    c = a @ b
    a, b = b, c / np.abs(c).max()
"""


# --------------------------------------------------------------------- in the subprocess

def problems(family, n, count):
    import numpy as np
    from lemke import problems as lp

    gen = {"pmatrix": lp.random_p_matrix, "contact": lp.contact_like}[family]
    return [gen(n, np.random.default_rng([SEED, n, k, FAMILIES.index(family)]))
            for k in range(count)]


def loadavg():
    try:
        with open("/proc/loadavg") as f:
            return f.read().split()[0]
    except OSError:
        return "?"


def time_pair(call, repeats, min_time):
    """Median seconds of ``call(method)`` for both methods, interleaved: wall-clock time,
    and the CPU time of the whole process (every thread: BLAS threads and batch workers
    included) as ``cpu_<method>``.  At least ``repeats`` calls each, more if that takes
    less than ``min_time`` seconds (judged from one call of each)."""
    t0 = time.perf_counter()
    call("tableau")
    call("unrevised")
    once = (time.perf_counter() - t0) / 2
    repeats = max(repeats, min(int(min_time / max(once, 1e-6)), 50 * repeats))
    times = {m: [] for m in ("tableau", "unrevised", "cpu_tableau", "cpu_unrevised")}
    for r in range(repeats):
        for m in ("tableau", "unrevised") if r % 2 == 0 else ("unrevised", "tableau"):
            c0 = time.process_time()
            t0 = time.perf_counter()
            call(m)
            times[m].append(time.perf_counter() - t0)
            times["cpu_" + m].append(time.process_time() - c0)
    return {m: statistics.median(v) for m, v in times.items()}


def child(args):
    import numpy as np
    import lemke

    batch = args.child.startswith("batch")
    rows = []
    # Warm everything up first (older versions compile their kernels here).
    for family in FAMILIES:
        M, q = problems(family, 8, 1)[0]
        for m in ("tableau", "unrevised"):
            r = lemke.solve_lcp(M, q, method=m)
            lemke.solve_lcp(M, q + 1e-3, warm_start=r.warm_start)
            lemke.solve_lcp_batch(np.stack([M, M]), np.stack([q, q]), method=m, workers=args.workers)
    gc.collect()
    gc.disable()
    for n in args.sizes:
        for family in FAMILIES:
            probs = problems(family, n, args.problems)
            row = dict(family=family, n=n)
            if batch:
                Ms = np.stack([M for M, _ in probs])
                qs = np.stack([q for _, q in probs])
                res = {m: lemke.solve_lcp_batch(Ms, qs, method=m, workers=args.workers)
                       for m in ("tableau", "unrevised")}
                t = time_pair(lambda m: lemke.solve_lcp_batch(Ms, qs, method=m, workers=args.workers),
                              args.repeats, args.min_time)
                row.update(t_tab=t["tableau"], t_unr=t["unrevised"],
                           ratio=t["unrevised"] / t["tableau"],
                           cpu_ratio=t["cpu_unrevised"] / t["cpu_tableau"],
                           solved=bool(all(r.success.all() for r in res.values())),
                           pivots=[int(p) for p in res["tableau"].pivots],
                           agree=bool((res["tableau"].pivots == res["unrevised"].pivots).all()))
            else:
                per = []
                for M, q in probs:
                    res = {m: lemke.solve_lcp(M, q, method=m) for m in ("tableau", "unrevised")}
                    t = time_pair(lambda m: lemke.solve_lcp(M, q, method=m), args.repeats, args.min_time)
                    # Warm starts from the tableau's final basis.
                    noise = np.random.default_rng([SEED, n, 99]).standard_normal(n)
                    if family == "contact":  # q only moves up: it stays solvable
                        noise = np.abs(noise)
                    ws = res["tableau"].warm_start
                    warm = {}
                    for eps in WARM_MOVES:
                        q2 = q + eps * noise
                        r2 = lemke.solve_lcp(M, q2, warm_start=ws)
                        tw = []
                        for _ in range(args.repeats):
                            t0 = time.perf_counter()
                            lemke.solve_lcp(M, q2, warm_start=ws)
                            tw.append(time.perf_counter() - t0)
                        warm[str(eps)] = (statistics.median(tw), int(r2.pivots), bool(r2.success))
                    per.append(dict(t_tab=t["tableau"], t_unr=t["unrevised"],
                                    ratio=t["unrevised"] / t["tableau"],
                                    cpu_ratio=t["cpu_unrevised"] / max(t["cpu_tableau"], 1e-9),
                                    solved=bool(all(r.success for r in res.values())),
                                    pivots=int(res["tableau"].pivots),
                                    agree=res["tableau"].pivots == res["unrevised"].pivots,
                                    warm=warm))
                row.update(
                    t_tab=statistics.median(p["t_tab"] for p in per),
                    t_unr=statistics.median(p["t_unr"] for p in per),
                    ratio=statistics.median(p["ratio"] for p in per),
                    ratio_max=max(p["ratio"] for p in per),
                    cpu_ratio=statistics.median(p["cpu_ratio"] for p in per),
                    solved=all(p["solved"] for p in per),
                    pivots=[p["pivots"] for p in per],
                    agree=all(p["agree"] for p in per),
                    warm={eps: dict(t=statistics.median(p["warm"][eps][0] for p in per),
                                    pivots=[p["warm"][eps][1] for p in per],
                                    solved=all(p["warm"][eps][2] for p in per))
                          for eps in map(str, WARM_MOVES)},
                )
            rows.append(row)
            print(f"  {args.child} {family} n={n}: unrevised/tableau {row['ratio']:.2f} "
                  f"(load {loadavg()})", file=sys.stderr, flush=True)
    print(json.dumps(dict(rows=rows, lemke=os.path.dirname(os.path.abspath(lemke.__file__)),
                          numpy=np.__version__)))


# --------------------------------------------------------------------- the orchestrator

def clean_env(path, blas_threads, cache_dir=None):
    env = dict(os.environ)
    if cache_dir:
        env["NUMBA_CACHE_DIR"] = cache_dir
    for v in BLAS_VARS:
        env.pop(v, None)
        if blas_threads:
            env[v] = str(blas_threads)
    if path is not None:
        env["PYTHONPATH"] = os.path.abspath(path) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def cpu_seconds(pid):
    """utime + stime of a process from /proc (None where there is no /proc)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


def run_section(section, label, path, args):
    loader = None
    if section.endswith("loaded"):
        loader = subprocess.Popen([sys.executable, "-c", LOADER], stdout=subprocess.PIPE,
                                  env=clean_env(None, args.blas_threads), text=True)
        loader.stdout.readline()  # "ready": its thread pool is running
    samples = []
    stop = threading.Event()

    def sample():
        while True:
            samples.append(loadavg())
            if stop.wait(5.0):
                return

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    t0 = time.perf_counter()
    cmd = [sys.executable, os.path.abspath(__file__), "--child", section,
           "--sizes", *map(str, args.sizes), "--problems", str(args.problems),
           "--repeats", str(args.repeats), "--min-time", str(args.min_time),
           "--workers", str(args.workers)]
    cache = os.path.join(args.cache_root, label)
    proc = subprocess.run(cmd, env=clean_env(path, args.blas_threads, cache), stdout=subprocess.PIPE,
                          text=True, check=True)
    wall = time.perf_counter() - t0
    stop.set()
    sampler.join()
    samples.append(loadavg())
    load_cpu = None
    if loader is not None:
        load_cpu = cpu_seconds(loader.pid)
        loader.terminate()
        loader.wait()
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    out.update(section=section, label=label, wall=wall, loadavg=samples,
               loader_cores=None if load_cpu is None else load_cpu / wall)
    return out


def machine_info(args):
    model = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    except OSError:
        nproc = str(os.cpu_count())
    import numpy
    import scipy
    try:
        import numba  # what older versions compiled with (and quantecon), where installed
        numba_version = numba.__version__
    except ImportError:
        numba_version = "not installed"

    return dict(cpu=model, nproc=nproc, python=platform.python_version(), numpy=numpy.__version__,
                scipy=scipy.__version__, numba=numba_version,
                date=_dt.datetime.now().isoformat(timespec="seconds"),
                blas=("default (BLAS thread variables removed)" if not args.blas_threads
                      else f"{', '.join(BLAS_VARS)} = {args.blas_threads}"))


def fmt_ms(s):
    return f"{s * 1e3:.2f}"


def render(info, args, results, total):
    labels = [lab for lab, _ in args.versions]
    out = ["# `method=\"unrevised\"` vs `\"tableau\"`, quiet and under load (`bench_threads.py`)", ""]
    if args.note:
        out += [args.note, ""]
    out += [f"Machine: {info['cpu']}, `nproc` = {info['nproc']}; Python {info['python']}, numpy "
            f"{info['numpy']}, scipy {info['scipy']}, numba {info['numba']}; BLAS threads: "
            f"{info['blas']}; {info['date']}; {total:.0f} s in all.", "",
            f"Versions: {', '.join(f'`{lab}` = {p}' for lab, p in args.versions)}.  "
            f"{args.problems} problems per family and size, at least {args.repeats} interleaved "
            f"repeats (more where {args.repeats} take less than {args.min_time} s); "
            f"batches of all {args.problems} with `workers={args.workers}`.", ""]
    out += ["## Load", "", "| section | version | load average while it ran (1 min, sampled every 5 s) "
            "| load process | wall s |", "|---|---|---|---|---|"]
    for r in results:
        lp = "—" if r["loader_cores"] is None else f"{r['loader_cores']:.2f} cores"
        out.append(f"| {r['section']} | {r['label']} | {' '.join(r['loadavg'])} | {lp} | {r['wall']:.0f} |")
    out.append("")
    for section in args.sections:
        batch = section.startswith("batch")
        by = {r["label"]: r for r in results if r["section"] == section}
        unit = "ms per batch" if batch else "ms, median over problems"
        out += [f"## {section}", ""]
        head = "| family | n | pivots (tableau) |"
        rule = "|---|---|---|"
        for lab in labels:
            head += f" {lab}: tableau | {lab}: unrevised | {lab}: **ratio** | {lab}: CPU ratio |"
            rule += "---|---|---|---|"
        out += [f"Wall-clock times in {unit}; ratio = unrevised / tableau"
                + ("" if batch else " (median over problems; max in brackets)")
                + "; CPU ratio: the same for the CPU time of the whole process (all its threads).",
                "", head, rule]
        first = by[labels[0]]["rows"]
        for i, row0 in enumerate(first):
            piv = row0["pivots"]
            line = f"| {row0['family']} | {row0['n']} | {min(piv)}–{max(piv)} |"
            for lab in labels:
                r = by[lab]["rows"][i]
                flag = "" if r["solved"] and r["agree"] else " ✗" if not r["solved"] else " (pivots differ)"
                ratio = f"**{r['ratio']:.2f}**" + ("" if batch else f" ({r['ratio_max']:.2f})")
                line += (f" {fmt_ms(r['t_tab'])} | {fmt_ms(r['t_unr'])} | {ratio}{flag} |"
                         f" {r['cpu_ratio']:.2f} |")
            out.append(line)
        out.append("")
        if not batch:
            out += [f"Warm starts in this section (`solve_lcp` with the tableau's final basis, "
                    f"ms, median over problems; pivots of the restart):", ""]
            head = "| family | n | q moved by |"
            rule = "|---|---|---|"
            for lab in labels:
                head += f" {lab} |"
                rule += "---|"
            out += [head, rule]
            for i, row0 in enumerate(first):
                for eps, name in zip(map(str, WARM_MOVES), ("1e-9 (0 pivots)", "0.05 (restart)")):
                    piv = row0["warm"][eps]["pivots"]
                    line = f"| {row0['family']} | {row0['n']} | {name}, {min(piv)}–{max(piv)} pivots |"
                    for lab in labels:
                        w = by[lab]["rows"][i]["warm"][eps]
                        line += f" {fmt_ms(w['t'])}{'' if w['solved'] else ' ✗'} |"
                    out.append(line)
            out.append("")
    out += ["Every answer above was SOLVED unless marked ✗; \"(pivots differ)\" would mark a "
            "row where the two methods took different numbers of pivots.", ""]
    return "\n".join(out)


def parse_version(s):
    label, sep, path = s.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError("expected LABEL=PATH")
    return label, path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--versions", nargs="+", type=parse_version, default=[("current", ROOT)],
                    metavar="LABEL=PATH", help="lemke versions to compare (PATH holds a lemke package)")
    ap.add_argument("--sizes", nargs="+", type=int, default=[100, 300])
    ap.add_argument("--problems", type=int, default=6)
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--min-time", type=float, default=0.2,
                    help="more repeats for fast calls: at least this many seconds per method")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--sections", nargs="+", choices=SECTIONS, default=list(SECTIONS))
    ap.add_argument("--blas-threads", type=int, default=0,
                    help="set the BLAS thread variables in the subprocesses (default: removed)")
    ap.add_argument("--note", default="")
    ap.add_argument("--out", default=os.path.join(ROOT, "benchmarks", "RESULTS-threads.md"))
    ap.add_argument("--json", default=None, help="also write the raw results here")
    ap.add_argument("--child", choices=SECTIONS, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return child(args)

    sys.path.insert(0, ROOT)
    from lemke._io.common import atomic_write

    info = machine_info(args)
    t0 = time.perf_counter()
    results = []
    with tempfile.TemporaryDirectory(prefix="bench_threads_") as args.cache_root:
        for i, section in enumerate(args.sections):
            order = args.versions if i % 2 == 0 else args.versions[::-1]
            for label, path in order:
                print(f"{section}, {label} ({path}) ...", file=sys.stderr, flush=True)
                results.append(run_section(section, label, path, args))
    report = render(info, args, results, time.perf_counter() - t0)
    print(report)
    if args.out:
        atomic_write(args.out, lambda fh: fh.write(report.encode()))
    if args.json:
        atomic_write(args.json, lambda fh: fh.write(json.dumps(dict(info=info, results=results),
                                                                indent=1).encode()))


if __name__ == "__main__":
    main()
