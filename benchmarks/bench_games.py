#!/usr/bin/env python
"""Benchmark ``lemke.solve_bimatrix`` against quantecon's ``lemke_howson`` (and nashpy's).

Usage::

    python benchmarks/bench_games.py [--quick] [--out benchmarks/RESULTS-games.md]

Square games in three families, seeds 0..4 (``--quick``: 0..1): ``unif`` (payoffs
U[0, 1)), ``int100`` (integers 0..99) and ``int3`` (integers {0, 1, 2}, very degenerate);
label 0 dropped.  In one process, everything compiled beforehand, the solvers are called in
turn on each game (a fresh random order for every repeat) and each game's median time is
kept; the table gives the medians over games and the median of the per-game ratios
lemke / quantecon.  Every answer is checked here by the regret of either player computed in
numpy: at most 1e-9 times the payoff range, else it counts as a failure (so does
quantecon's ``converged=False``).  quantecon cycles on some int3 games up to its 10**6-pivot
cap (seconds), so on int3 it is run once per game and only counted.  nashpy (pure Python)
runs once per game at n = 20 only, in a child process given 10 s (it loops forever on some
degenerate games); its time includes the fork.  ``exact=True`` (float path, then the support system
solved and checked in rational arithmetic) is timed at n = 100.
"""
from __future__ import annotations

import os
import random
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_lcp as bl  # noqa: E402  (machine description, report helpers)

import lemke  # noqa: E402

try:
    from quantecon.game_theory import NormalFormGame, Player, lemke_howson
except ImportError:  # pragma: no cover
    lemke_howson = None
try:
    import nashpy
except ImportError:  # pragma: no cover
    nashpy = None

SIZES = (20, 50, 100)
FAMILIES = ("unif", "int100", "int3")


def game(family, n, seed):
    """The game of the tests' families: (A, B), both n x n float arrays."""
    rng = np.random.default_rng(seed)
    if family == "unif":
        return rng.random((n, n)), rng.random((n, n))
    top = 100 if family == "int100" else 3
    return rng.integers(0, top, (n, n)).astype(float), rng.integers(0, top, (n, n)).astype(float)


def ok(A, B, x, y) -> bool:
    """An equilibrium: probability vectors with regret <= 1e-9 times the payoff range."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.shape != (A.shape[0],) or y.shape != (A.shape[1],) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        return False
    if x.min() < -1e-12 or y.min() < -1e-12 or abs(x.sum() - 1) > 1e-9 or abs(y.sum() - 1) > 1e-9:
        return False
    reg = max((A @ y).max() - x @ A @ y, (B.T @ x).max() - x @ B @ y)
    return reg <= 1e-9 * max(np.ptp(A), np.ptp(B))


def run_lemke(A, B, g=None):
    r = lemke.solve_bimatrix(A, B)
    return r.x, r.y, r.success, r.pivots


def run_exact(A, B, g=None):
    r = lemke.solve_bimatrix(A, B, exact=True)
    return np.array([float(v) for v in r.x]), np.array([float(v) for v in r.y]), r.success and r.regret == 0, r.pivots


def run_qe(A, B, g):
    NE, res = lemke_howson(g, full_output=True)
    return NE[0], NE[1], res.converged, res.num_iter


NASHPY_TIMEOUT = 10.0  # s: nashpy loops forever on some degenerate games (NaN tableaux)


def _nashpy_child(A, B, queue):
    import warnings
    warnings.simplefilter("ignore")
    try:
        x, y = nashpy.Game(A, B).lemke_howson(initial_dropped_label=0)
        queue.put((np.asarray(x), np.asarray(y), None))
    except Exception as err:  # noqa: BLE001 (reported as a failure)
        queue.put((None, None, f"{type(err).__name__}"))


def run_nashpy(A, B, g=None):
    """nashpy in a child process (fork), given NASHPY_TIMEOUT; the time includes the fork."""
    import multiprocessing as mp
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    proc = ctx.Process(target=_nashpy_child, args=(A, B, queue))
    proc.start()
    try:
        x, y, err = queue.get(timeout=NASHPY_TIMEOUT)
    except Exception:  # noqa: BLE001 (queue.Empty: it did not finish)
        proc.kill()
        proc.join()
        raise TimeoutError(f"no answer in {NASHPY_TIMEOUT:.0f} s") from None
    proc.join()
    if err:
        raise RuntimeError(err)
    return x, y, True, -1


def timed(fn, A, B, g):
    t = time.perf_counter()
    out = fn(A, B, g)
    return time.perf_counter() - t, out


def bench(family, n, seeds, reps, log):
    """Rows: per solver, median time, failures, pivots; and per-game ratios."""
    solvers = {"lemke": run_lemke}
    timed_peers = {}
    once = {}
    if lemke_howson:
        (once if family == "int3" else timed_peers)["quantecon"] = run_qe
    if nashpy and n == 20:
        once["nashpy"] = run_nashpy
    if n == 100:
        solvers["lemke exact"] = run_exact
    solvers.update(timed_peers)
    times = {k: [] for k in list(solvers) + list(once)}
    fails = {k: 0 for k in times}
    pivots = {k: [] for k in times}
    ratios = []
    extra = []  # per game: exact minus float (the rational solve and check)
    rng = random.Random(1000 * n + len(family))
    loads = []
    for seed in seeds:
        A, B = game(family, n, seed)
        g = NormalFormGame((Player(A), Player(B.T))) if lemke_howson else None
        per = {k: [] for k in times}
        for k, fn in solvers.items():  # warm-up (and the answer checked)
            _, (x, y, success, piv) = timed(fn, A, B, g)
            if not (success and ok(A, B, x, y)):
                fails[k] += 1
            pivots[k].append(piv)
        for k, fn in once.items():
            try:
                dt, (x, y, success, piv) = timed(fn, A, B, g)
                good = success and ok(A, B, x, y)
            except Exception as err:  # nashpy raises or hangs on some degenerate games
                dt, good, piv = NASHPY_TIMEOUT if isinstance(err, TimeoutError) else float("nan"), False, -1
                log(f"  {k} raised {type(err).__name__} on {family} {n} seed {seed}")
            fails[k] += not good
            per[k].append(dt)
            pivots[k].append(piv)
        for _ in range(reps):
            order = list(solvers)
            rng.shuffle(order)
            for k in order:
                dt, _ = timed(solvers[k], A, B, g)
                per[k].append(dt)
        for k in times:
            times[k].append(statistics.median(per[k]))
        if "lemke exact" in solvers:
            extra.append(statistics.median(per["lemke exact"]) - statistics.median(per["lemke"]))
        if "quantecon" in timed_peers:
            ratios.append(statistics.median(per["lemke"]) / statistics.median(per["quantecon"]))
        loads.append(os.getloadavg()[0])
        log(f"  {family} n={n} seed {seed}: " + ", ".join(f"{k} {bl._t(times[k][-1])}" for k in times))
    return times, fails, pivots, ratios, extra, loads


def main(argv=None):
    parser, argv = bl.report_parser(__doc__, "RESULTS-games.md", argv)
    parser.add_argument("--quick", action="store_true", help="seeds 0..1 and fewer repeats")
    args = parser.parse_args(argv)
    args.argv = argv
    log = lambda m: print(m, file=sys.stderr, flush=True)  # noqa: E731
    seeds = range(2) if args.quick else range(5)
    info = bl.machine_info()
    t0 = time.perf_counter()
    lemke.solve_bimatrix(np.eye(3), np.eye(3))  # compile
    lemke.solve_bimatrix(np.eye(3), np.eye(3), exact=True)
    rows = []
    for family in FAMILIES:
        for n in SIZES:
            reps = 3 if args.quick else (5 if n == 100 else 9)
            rows.append((family, n, *bench(family, n, seeds, reps, log)))
    bl.mark_end(info)
    total = time.perf_counter() - t0
    versions = []
    if nashpy:
        versions.append(f"nashpy {nashpy.__version__}")
    L = bl.report_head("Bimatrix games: lemke.solve_bimatrix vs quantecon's lemke_howson", "bench_games.py",
                       args, total, info, extra_versions=", " + ", ".join(versions) if versions else "")
    a = L.append
    a("## Method")
    a("")
    a(__doc__.split("\n\n", 3)[3].strip())
    a("")
    a("## Results")
    a("")
    a("Times: median over games of each game's median. Ratio: median (max) over games of "
      "lemke / quantecon, each game's medians. Failures: answers that fail the regret check "
      "(or quantecon's `converged=False`), out of the games run. Exact: the whole "
      "`exact=True` solve (float path included), and its rational part alone (exact minus float, "
      "per game). Load: 1-minute load average after each game (min-max).")
    a("")
    a("| family | n | lemke | pivots (lemke) | quantecon | pivots (qe) | **ratio** | failures lemke / qe | nashpy (n = 20, once) | exact (n = 100) | load |")
    a("|---|---|---|---|---|---|---|---|---|---|---|")
    for family, n, times, fails, pivots, ratios, extra, loads in rows:
        games = len(times["lemke"])
        med = lambda k: bl._t(statistics.median(times[k])) if k in times else "-"  # noqa: E731
        rng_p = lambda k: f"{min(pivots[k])}–{max(pivots[k])}" if k in pivots and pivots[k] else "-"  # noqa: E731
        ratio = f"**{statistics.median(ratios):.2f}** ({max(ratios):.2f})" if ratios else "- (run once)"
        qfail = fails.get("quantecon", "-")
        nash = (f"{bl._t(statistics.median(v for v in times['nashpy'] if v == v))}, {fails['nashpy']}/{games} failed"
                if "nashpy" in times and any(v == v for v in times["nashpy"]) else
                (f"{fails['nashpy']}/{games} failed" if "nashpy" in times else "-"))
        exact = (f"{med('lemke exact')} (max {bl._t(max(times['lemke exact']))}; rational part "
                 f"{bl._t(statistics.median(extra))}, max {bl._t(max(extra))}), {fails['lemke exact']} failed"
                 if "lemke exact" in times else "-")
        a(f"| {family} | {n} | {med('lemke')} | {rng_p('lemke')} | {med('quantecon')} | {rng_p('quantecon')} | "
          f"{ratio} | {fails['lemke']}/{games} / {qfail}/{games} | {nash} | {exact} | {min(loads):.1f}–{max(loads):.1f} |")
    a("")
    bl.publish("\n".join(L) + "\n", args.out, log)


if __name__ == "__main__":
    main()
