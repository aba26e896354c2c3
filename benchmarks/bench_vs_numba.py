#!/usr/bin/env python
"""Issue 31's targets measured on today's package and on the last numba package (c63f157),
through the public API only, in alternated fresh processes.

Usage::

    # one process: every row below, measured with the lemke this Python imports; JSON on stdout
    python benchmarks/bench_vs_numba.py [--budget 0.3] [--mpc-data FILE]
        [--groups lcp islands qp games blcp mpc]
    # the driver: OLD and NEW are two environments' Pythons (the numba package's, today's);
    # steady-state processes alternated old, new, old, new, ... (--pairs), then the first calls
    python benchmarks/bench_vs_numba.py --compare OLD_PYTHON NEW_PYTHON [--pairs 3]
        [--parts steady first] [--groups ...] [--runs 3] [--no-empty]
        [--out /tmp/RESULTS-vs-numba.md] [--json FILE]
    # the report again from the numbers --json kept; of several runs, a summary over them
    python benchmarks/bench_vs_numba.py --from-json FILE [FILE ...] [--out FILE]

The same script runs unchanged on both packages: it calls only what ``lemke`` exported at
c63f157 (``solve_lcp``, ``solve_lcp_many`` with ``sizes=`` and ``WarmStartBatch``,
``solve_qp`` with ``warm_start=``, ``solve_blcp``, ``solve_bimatrix``, ``solve_mlcp``, the
``lemke solve`` command; ``solve_blcp_many`` and ``solve_qp``'s ``initvals=`` came later and
are not measured), and the problem generators of the other benchmark scripts, imported from
them.  Rows of one process (medians after two untimed warm-up calls of every callable,
so numba's compile and cache load are left out; ``bench_core.time_calls``: interleaved
rounds in a random order, each round a batch of calls of ~2 ms, within ``--budget``
seconds):

- *cold* ``solve_lcp(M, q)`` at n = 3, 12, 24, 100, 300, 1000 on bench_core.py's problems
  (``bench_core.problem`` drawn in bench_core's order from its seed), beside quantecon's
  ``lcp_lemke`` (the peer; target <= 0.5x at n <= 300, <= 0.25x at 1000);
- the fixed cost, ``solve_lcp`` at n = 1 with q >= 0 (target <= 1.0 us);
- *0-pivot warm* re-solves (q moved by 1e-9, ``warm_start=`` the cold result's) at n = 3,
  12, 24, 48, 100, 300 on the same problems, the cold call in the same rounds (target warm
  <= 0.5x its own cold);
- the *unrevised* method at n = 100, 300 beside the tableau in the same rounds (target
  <= 1.2x);
- a *batch of one*, ``solve_lcp_many([M], [q])`` at n = 1, q < 0, beside ``solve_lcp``
  (target <= 1.5x);
- *400 islands* of 1-12 rows, warm (bench_small.py section 2: ``problems.contact_like``
  from seed 15, the next step's q moved by 1e-3, the first step's bases as one
  ``WarmStartBatch``), 1 worker, flat z, offsets and warm start read: packed (``sizes=``)
  and from lists of arrays; microseconds per island (targets <= 0.5 / 1.0 us); the peer a
  loop of quantecon, cold, z read;
- *QPs* at n = 10, 100, 300 (bench_qp_fast.py's ``make_qp``, families ``mixed`` and
  ``ineq``, two problems each, seed 2026 here: the same generator, not the same draws),
  ``solve_qp`` called again on the same matrices (*cached*: today's factor cache hits) and
  after an untimed 2-variable QP (*fresh*), beside ``daqp.solve`` on qpsolvers' arrays
  (the peer; target <= 1.0x at n = 10, <= 0.5x at 100 and 300); single calls timed, at
  least 7 rounds;
- *games* n = 20, 50, 100 (bench_games.py's ``game``, families ``unif`` and ``int100``,
  seeds 0-2, label 0), ``solve_bimatrix`` beside quantecon's ``lemke_howson`` (target
  <= 0.5x), medians over the games of per-game medians and ratios;
- *box LCPs without friction* at n = 12, 48, 200 (bench_blcp.py's ``relay`` and
  ``contact`` boxes on ``bench_lcp.make_problem(n, k)``, its 12 / 8 / 3 problems), ``solve_blcp`` beside
  ``solve_lcp`` on the same M, q in the same rounds (target box <= 1.2x the LCP);
- the *MPC loop* (bench_mpc.py's problem, ``mpc_problem.sequence``: 100 steps), per step in
  a random order: ``solve_qp`` cold, warm (the previous step's ``warm_start``, chained) and
  ``daqp.solve`` (the peer), 2 passes; the median over steps of each step's median (targets:
  warm <= 0.5x cold, warm <= 1.0x daqp).  ``--mpc-data`` loads the steps the driver
  computed once, so that both packages solve the same right-hand sides.

Beside each median, the least thread CPU time (``time.thread_time``) of single calls of the
row's lemke call (``cpu``; for islands per island, for QPs, games and boxes the median over
the problems): the time other processes take on a loaded machine is not in it.

Every answer is checked here once before timing (LCPs: ``bench_core.checked``; QPs: x against
daqp's within 1e-6 relative; games: ``bench_games.ok``; box LCPs: the natural residual
<= 1e-8; MPC: SOLVED and x against daqp's).  Pivots are recorded beside the times.

First calls (``--parts first``): per entry point of bench_compile.py (its child code), a
whole fresh process (``python -c``: Python's start, ``import numpy``, ``import lemke``, the
call), timed from outside, min of ``--runs`` processes alternated old, new, with Python's
bytecode cache on (``PYTHONDONTWRITEBYTECODE`` unset, as an installed package has it); the
numba package with its filled cache (``NUMBA_CACHE_DIR``, filled by an untimed process
first) and once with an empty one (a fresh directory; 10-40 s each; for the entry points
proper, ``EMPTY_CACHE``).  ``lemke solve`` (the command, its built-in problem) the same way.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

COLD_SIZES = (3, 12, 24, 100, 300, 1000)
WARM_SIZES = (3, 12, 24, 48, 100, 300)
CORE_SIZES = (1, 3, 12, 24, 48, 100, 300, 1000)  # bench_core's default sizes: its draws' order
CORE_SEED = 20261128  # bench_core's
NUMBA_CACHE = "/tmp/numba-cache-numbacol"
# bench_compile's entry points timed here (solve_blcp_many did not exist at c63f157; the QP's
# other paths and lemke_paths reach kernels these reach); EMPTY_CACHE: those also timed once
# with an empty numba cache (the entry points proper; 10-40 s each)
FIRST_CALLS = ("solve_lcp", "warm start", "solve_lcp (unrevised)", "solve_lcp_many", "solve_mlcp",
               "solve_qp (fused)", "solve_blcp", "solve_bimatrix")
EMPTY_CACHE = ("solve_lcp", "solve_lcp_many", "solve_mlcp", "solve_qp (fused)", "solve_blcp",
               "solve_bimatrix", "lemke solve")


# ----------------------------------------------------------------------------- one process

def _cpu_min(f, budget, prepare=None):
    """The least thread CPU time (``time.thread_time``) of single calls of f, at least 3 and
    within ``budget`` seconds: on a loaded machine the time other processes take is not in it
    (at load 10 on 2 cores a 3 ms call's wall time was 4-10x its CPU time)."""
    best, k, end = float("inf"), 0, time.perf_counter() + budget
    while k < 3 or (k < 200 and time.perf_counter() < end):
        if prepare:
            prepare()
        t = time.thread_time()
        f()
        best = min(best, time.thread_time() - t)
        k += 1
    return best


def _warm_then_time(calls, budget, cpu=()):
    """bench_core.time_calls after two untimed calls of each (numba's compile left out); and
    ``"cpu " + name``: _cpu_min of the calls named in ``cpu``."""
    from bench_core import time_calls
    for f in calls.values():
        f()
        f()
    t = time_calls(calls, budget)
    t.update({"cpu " + k: _cpu_min(calls[k], budget / 4) for k in cpu})
    return t


def _rounds(calls, budget, least=7, prepare=None, cpu=()):
    """{name: median seconds} of single calls in a random order each round (for calls of tens
    of microseconds and more); ``prepare[name]()`` runs untimed before its call; ``cpu`` as
    for _warm_then_time."""
    rng = np.random.default_rng(0)
    names, times = list(calls), {k: [] for k in calls}
    for f in calls.values():
        f()
    end = time.perf_counter() + budget
    while len(times[names[0]]) < least or time.perf_counter() < end:
        rng.shuffle(names)
        for k in names:
            if prepare and k in prepare:
                prepare[k]()
            t = time.perf_counter()
            calls[k]()
            times[k].append(time.perf_counter() - t)
    out = {k: statistics.median(v) for k, v in times.items()}
    out.update({"cpu " + k: _cpu_min(calls[k], budget / 4, (prepare or {}).get(k)) for k in cpu})
    return out


def lcp_rows(budget):
    import lemke
    from bench_core import checked, problem
    from quantecon.optimize import lcp_lemke
    rng = np.random.default_rng(CORE_SEED)
    probs = {n: problem(n, rng) for n in CORE_SIZES}
    rows = {}
    for n in sorted(set(COLD_SIZES) | set(WARM_SIZES)):
        M, q = probs[n]
        r = lemke.solve_lcp(M, q)
        assert r.success
        checked(M, q, r.z)
        checked(M, q, lcp_lemke(M, q).z)
        calls = {"lemke": lambda: lemke.solve_lcp(M, q), "quantecon": lambda: lcp_lemke(M, q)}
        q2, ws = q + 1e-9, r.warm_start
        if n in WARM_SIZES:
            rw = lemke.solve_lcp(M, q2, warm_start=ws)
            assert rw.pivots == 0 and rw.success
            checked(M, q2, rw.z)
            calls["warm"] = lambda: lemke.solve_lcp(M, q2, warm_start=ws)
        if n in (100, 300):
            ru = lemke.solve_lcp(M, q, method="unrevised")
            assert ru.success
            checked(M, q, ru.z)
            calls["unrevised"] = lambda: lemke.solve_lcp(M, q, method="unrevised")
        t = _warm_then_time(calls, budget, cpu=[k for k in calls if k != "quantecon"])
        if n in COLD_SIZES:
            rows[f"cold n={n}"] = dict(t=t["lemke"], peer=t["quantecon"], pivots=r.pivots, cpu=t["cpu lemke"])
        if n in WARM_SIZES:
            rows[f"warm n={n}"] = dict(t=t["warm"], ratio=t["warm"] / t["lemke"], pivots=0, cpu=t["cpu warm"])
        if n in (100, 300):
            rows[f"unrevised n={n}"] = dict(t=t["unrevised"], ratio=t["unrevised"] / t["lemke"],
                                            pivots=ru.pivots, cpu=t["cpu unrevised"])
    M1, qpos, qneg = np.array([[2.0]]), np.array([1.0]), np.array([-1.0])
    M1s, q1s = [M1], [qneg]
    assert lemke.solve_lcp_many(M1s, q1s).z[0] == 0.5
    t = _warm_then_time({"pos": lambda: lemke.solve_lcp(M1, qpos),
                         "one": lambda: lemke.solve_lcp(M1, qneg),
                         "many": lambda: lemke.solve_lcp_many(M1s, q1s)}, budget, cpu=("pos", "many"))
    rows["fixed n=1 q>=0"] = dict(t=t["pos"], cpu=t["cpu pos"])
    rows["batch of one"] = dict(t=t["many"], ratio=t["many"] / t["one"], cpu=t["cpu many"])
    return rows


def island_rows(budget, count=400, lo=1, hi=12):
    import lemke
    from bench_small import _ok, islands
    from quantecon.optimize import lcp_lemke
    Ms, qs, qs2 = islands(count, lo, hi)
    batch = lemke.solve_lcp_many(Ms, qs, workers=1).warm_start
    sizes = np.array([len(q) for q in qs2])
    Mp, qp2 = np.concatenate([M.ravel() for M in Ms]), np.concatenate(qs2)

    def flat(rs):
        rs.z, rs.offsets, rs.warm_start
        return rs
    calls = {"packed": lambda: flat(lemke.solve_lcp_many(Mp, qp2, sizes=sizes, warm_start=batch, workers=1)),
             "lists": lambda: flat(lemke.solve_lcp_many(Ms, qs2, warm_start=batch, workers=1)),
             "quantecon": lambda: [lcp_lemke(M, q).z for M, q in zip(Ms, qs2)]}
    right = {}
    for k in ("packed", "lists"):  # bench_small's check; it counts, as here, the islands it solves
        res = calls[k]()
        right[k] = sum(_ok(M, q, z) for M, q, z in zip(Ms, qs2, np.split(res.z, res.offsets[1:-1])))
    t = _warm_then_time(calls, budget, cpu=("packed", "lists"))
    return {f"islands {k}": dict(t=t[k] / count, peer=t["quantecon"] / count, solved=right[k],
                                 cpu=t["cpu " + k] / count) for k in ("packed", "lists")}


def qp_rows(budget, sizes=(10, 100, 300), families=("mixed", "ineq"), problems_each=2):
    import daqp
    import lemke
    from bench_qp_fast import daqp_args, make_qp
    rng = np.random.default_rng(2026)
    tiny = (np.eye(2), np.array([1.0, -1.0]))
    rows = {}
    for n in sizes:
        per = {"cached": [], "fresh": [], "daqp": [], "cpu cached": [], "cpu fresh": []}
        pivots = []
        for fam in families:
            for _ in range(problems_each):
                prob = make_qp(fam, n, rng)
                da = daqp_args(*prob)
                r = lemke.solve_qp(*prob)
                x, _, flag, _ = daqp.solve(*da)
                assert r.success and flag == 1
                assert np.abs(r.x - x).max() <= 1e-6 * max(1.0, np.abs(x).max())
                pivots.append(r.pivots)
                t = _rounds({"cached": lambda: lemke.solve_qp(*prob), "fresh": lambda: lemke.solve_qp(*prob),
                             "daqp": lambda: daqp.solve(*da)}, budget,
                            prepare={"fresh": lambda: lemke.solve_qp(*tiny)}, cpu=("cached", "fresh"))
                for k in per:
                    per[k].append(t[k])
        med = {k: statistics.median(v) for k, v in per.items()}
        for k in ("cached", "fresh"):
            rows[f"qp {k} n={n}"] = dict(t=med[k], peer=med["daqp"], pivots=statistics.median(pivots),
                                         cpu=med["cpu " + k])
    return rows


def game_rows(budget, sizes=(20, 50, 100), families=("unif", "int100"), seeds=(0, 1, 2)):
    import lemke
    from bench_games import game, ok
    from quantecon.game_theory import NormalFormGame, Player, lemke_howson
    rows = {}
    for n in sizes:
        tl, tq, ratio, pivots, cpu = [], [], [], [], []
        for fam in families:
            for seed in seeds:
                A, B = game(fam, n, seed)
                g = NormalFormGame((Player(A), Player(B.T)))
                r = lemke.solve_bimatrix(A, B)
                assert r.success and ok(A, B, r.x, r.y)
                NE, res = lemke_howson(g, full_output=True)
                assert res.converged and ok(A, B, NE[0], NE[1])
                pivots.append(r.pivots)
                t = _warm_then_time({"lemke": lambda: lemke.solve_bimatrix(A, B),
                                     "qe": lambda: lemke_howson(g)}, budget / 3, cpu=("lemke",))
                tl.append(t["lemke"])
                cpu.append(t["cpu lemke"])
                tq.append(t["qe"])
                ratio.append(t["lemke"] / t["qe"])
        rows[f"games n={n}"] = dict(t=statistics.median(tl), peer=statistics.median(tq),
                                    peer_ratio=statistics.median(ratio), pivots=statistics.median(pivots),
                                    cpu=statistics.median(cpu))
    return rows


def blcp_rows(budget, counts=((12, 12), (48, 8), (200, 3))):
    import lemke
    from bench_blcp import boxes, natural_residual
    from bench_lcp import make_problem
    rows = {}
    for kind in ("relay", "contact"):
        for n, count in counts:
            tb, ratio, pivots, cpu = [], [], [], []
            for k in range(count):
                M, q = make_problem(n, k)
                lo, hi = boxes(n, kind)
                rb = lemke.solve_blcp(M, q, lo, hi)
                assert rb.success and natural_residual(M, q, lo, hi, rb.z) <= 1e-8
                pivots.append(rb.pivots)
                t = _warm_then_time({"box": lambda: lemke.solve_blcp(M, q, lo, hi),
                                     "lcp": lambda: lemke.solve_lcp(M, q)}, budget / 3, cpu=("box",))
                tb.append(t["box"])
                cpu.append(t["cpu box"])
                ratio.append(t["box"] / t["lcp"])
            rows[f"box {kind} n={n}"] = dict(t=statistics.median(tb), ratio=statistics.median(ratio),
                                             pivots=statistics.median(pivots), cpu=statistics.median(cpu))
    return rows


def mpc_data(steps=100):
    import mpc_problem
    (P, G, h, A, lb, ub), seq = mpc_problem.sequence(steps=steps, seed=0)
    return dict(P=P, G=G, h=h, A=A, lb=lb, ub=ub, q=np.array([q for q, _ in seq]),
                b=np.array([b for _, b in seq]))


def mpc_rows(data, passes=2):
    import daqp
    import lemke
    from bench_mpc import daqp_form
    P, G, h, A, lb, ub = (data[k] for k in ("P", "G", "h", "A", "lb", "ub"))
    steps = list(zip(data["q"], data["b"]))
    AA, sense, dbounds = daqp_form(P, G, h, A, lb, ub)
    names = ["cold", "warm", "daqp"]
    T = {k: np.zeros((passes, len(steps))) for k in names}
    piv = {k: [] for k in ("cold", "warm")}
    rng = np.random.default_rng(0)
    lemke.solve_qp(P, steps[0][0], G, h, A, steps[0][1], lb, ub)  # compile / load (numba)
    for ps in range(passes):
        ws = None
        for s, (q, b) in enumerate(steps):
            rng.shuffle(names)
            bu, bl = dbounds(b)
            got = {}
            for k in names:
                t0 = time.perf_counter()
                if k == "cold":
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
                elif k == "warm":
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
                else:
                    x, _, flag, _ = daqp.solve(P, q, AA, bu, bl, sense)
                T[k][ps, s] = time.perf_counter() - t0
                if k == "daqp":
                    assert flag == 1
                    got[k] = x
                else:
                    assert r.status == lemke.Status.SOLVED
                    got[k] = r.x
                    if ps == 0:
                        piv[k].append(r.pivots)
                    if k == "warm":
                        ws = r.warm_start
            for k in ("cold", "warm"):
                assert np.abs(got[k] - got["daqp"]).max() <= 1e-5 * max(1.0, np.abs(got["daqp"]).max())
    med = {k: float(np.median(np.median(T[k], axis=0))) for k in T}
    return {"mpc cold": dict(t=med["cold"], peer=med["daqp"], pivots=float(np.mean(piv["cold"]))),
            "mpc warm": dict(t=med["warm"], peer=med["daqp"], ratio=med["warm"] / med["cold"],
                             pivots=float(np.mean(piv["warm"])))}


GROUPS = {"lcp": lcp_rows, "islands": island_rows, "qp": qp_rows, "games": game_rows,
          "blcp": blcp_rows, "mpc": mpc_rows}


def measure(args):
    import lemke
    from bench_lcp import machine_info
    info = machine_info()
    t0 = time.perf_counter()
    rows = {}
    for group in args.groups:
        if group == "mpc":
            if args.mpc_data:
                with np.load(args.mpc_data) as f:
                    data = dict(f)
            else:
                data = mpc_data()
            rows.update(mpc_rows(data))
        else:
            rows.update(GROUPS[group](args.budget / 2 if group == "qp" else args.budget))
    try:
        import numba
        numba_version = numba.__version__
    except ImportError:
        numba_version = None
    return dict(lemke=lemke.__version__, path=info["lemke_path"], commit=info["commit"],
                numba=numba_version, uses_numba="numba" in _requires(),
                load=[info["load"], os.getloadavg()[0]], seconds=time.perf_counter() - t0, rows=rows)


def _requires():
    try:
        from importlib.metadata import requires
        return " ".join(requires("lemke") or [])
    except Exception:  # noqa: BLE001 (a checkout without metadata)
        return ""


# ----------------------------------------------------------------------------- the driver

def _env(numba_cache=NUMBA_CACHE, bytecode=False):
    env = dict(os.environ, NUMBA_CACHE_DIR=numba_cache)
    if bytecode:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def _steady(python, args, mpc_file):
    cmd = [python, os.path.abspath(__file__), "--budget", str(args.budget), "--mpc-data", mpc_file,
           "--groups", *args.groups]
    out = subprocess.run(cmd, capture_output=True, text=True, env=_env(), cwd=tempfile.gettempdir())
    if out.returncode:
        raise RuntimeError(f"{python}: {out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def _first(python, name, numba_cache):
    """(whole process seconds timed from outside, the child's own JSON) of one entry point."""
    from bench_compile import _CHILD, _CALLS
    if name == "lemke solve":
        cmd = [python, "-m", "lemke", "solve"]
    else:
        cmd = [python, "-c", _CHILD, _CALLS[name]]
    t = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, env=_env(numba_cache, bytecode=True),
                         cwd=tempfile.gettempdir())
    wall = time.perf_counter() - t
    if out.returncode:
        raise RuntimeError(f"{python} {name}: {out.stderr[-2000:]}")
    inner = json.loads(out.stdout.strip().splitlines()[-1]) if name != "lemke solve" else {}
    return wall, inner


def first_calls(old, new, runs, empty, log):
    names = ["import lemke", *FIRST_CALLS, "lemke solve"]
    res = {}
    for name in names:
        key = "solve_lcp" if name == "import lemke" else name
        _first(old, key, NUMBA_CACHE)  # untimed: the numba cache filled
        rec = {"old": [], "new": []}
        for _ in range(runs):
            for side, py in (("old", old), ("new", new)):
                rec[side].append(_first(py, key, NUMBA_CACHE))
        row = {}
        for side in ("old", "new"):
            if name == "import lemke":
                row[side] = min(r[1]["import_s"] for r in rec[side])
            else:
                row[side] = min(r[0] for r in rec[side])
                if name != "lemke solve":
                    row[side + " call"] = min(r[1]["call_s"] for r in rec[side])
        if empty and name in EMPTY_CACHE:
            d = tempfile.mkdtemp(prefix="numba-empty-")
            try:
                row["old empty"] = _first(old, key, d)[0]
            finally:
                shutil.rmtree(d, ignore_errors=True)
        res[name] = row
        log(f"first call {name}: " + ", ".join(f"{k} {v:.3f} s" for k, v in row.items()))
    return res


def _span(v):
    return f"{min(v):.3g}-{max(v):.3g}" if len(v) > 1 and min(v) != max(v) else f"{v[0]:.3g}"


def _num(x):
    return f"{x:.0f}" if x >= 100 else f"{x:.1f}" if x >= 10 else f"{x:.2f}"


def _us(v):
    return f"{_num(statistics.median(v) * 1e6)} ({_num(min(v) * 1e6)}-{_num(max(v) * 1e6)})"


# (row key prefix, target's measure, what the target's ratio is taken against)
TARGETS = [
    ("cold n=", "cold <= 0.5x quantecon (n <= 300), <= 0.25x (n = 1000)", "peer"),
    ("fixed n=1", "fixed cost, n = 1, q >= 0, <= 1.0 us", None),
    ("warm n=", "0-pivot warm <= 0.5x own cold", "ratio"),
    ("islands", "400 islands warm <= 0.5 us packed, <= 1.0 us lists (per island)", "peer"),
    ("batch of one", "a batch of one <= 1.5x solve_lcp", "ratio"),
    ("qp ", "QP n = 10 <= 1.0x daqp, n = 100 / 300 <= 0.5x", "peer"),
    ("games", "games <= 0.5x quantecon", "peer_ratio"),
    ("box ", "box LCP without friction <= 1.2x the LCP", "ratio"),
    ("unrevised", "unrevised <= 1.2x tableau", "ratio"),
    ("mpc cold", "MPC cold step (issue 32's base)", "peer"),
    ("mpc warm", "MPC warm <= 0.5x own cold (ratio), <= 1.0x daqp (peer)", "ratio"),
]


def _cpu_ratio(olds, news, key):
    """Today's least thread CPU time of the row's call over the old package's, over all
    processes ("" where the row has none)."""
    if "cpu" not in news[0]["rows"][key] or "cpu" not in olds[0]["rows"][key]:
        return ""
    return f"{min(r['rows'][key]['cpu'] for r in news) / min(r['rows'][key]['cpu'] for r in olds):.2f}"


def _target_ratio(row, how):
    if how == "peer":
        return row["t"] / row["peer"]
    return row.get(how)


def report(data, args):
    olds, news = data["old"], data["new"]
    L = ["# Today's lemke against the last numba package (c63f157)", ""]
    L.append(f"`python benchmarks/bench_vs_numba.py --compare {args.compare[0]} {args.compare[1]} "
             f"--pairs {args.pairs} --budget {args.budget} --runs {args.runs}`, {data['date']}, "
             f"{data['cpu']}, {data['usable']} usable cores (shared); 1-minute load "
             f"{data['load'][0]:.2f} at the start, {data['load'][1]:.2f} at the end; compare "
             f"{data['seconds']:.0f} s.")
    if olds:
        o, n = olds[0], news[0]
        L.append(f"Old: lemke {o['lemke']} from `{o['path']}` (commit {o['commit']}, numba "
                 f"{o['numba']}); today: lemke {n['lemke']} from `{n['path']}` (commit {n['commit']}).")
        loads = [x for r in olds + news for x in r["load"]]
        L.append(f"Steady-state processes: {len(olds)} pair(s) (old, new alternated), their load "
                 f"{min(loads):.1f}-{max(loads):.1f}.")
        L += ["", "Times: the median over processes of each process's median, the range over processes "
              "in brackets, microseconds.  today/old: per pair (one old process and the next new one), "
              "median and range; *minima*: today's fastest process over the old package's fastest; *CPU*: "
              "the same of the least thread CPU time of a call (time other processes took left out).  "
              "Target ratio: the target's own measure per process (lemke over the "
              "peer in the same rounds, warm over its own cold, box over the LCP, ...), median and "
              "range.  Peer: its median over all processes (both packages' runs).", "",
              "| row | target | old numba package (us) | today (us) | today/old | today/old, minima | "
              "today/old, CPU | target ratio, old | target ratio, today | peer (us) | pivots old / today |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        for key in news[0]["rows"]:
            what, how = next((t, h) for p, t, h in TARGETS if key.startswith(p))
            to = [r["rows"][key]["t"] for r in olds]
            tn = [r["rows"][key]["t"] for r in news]
            pair = [b / a for a, b in zip(to, tn)]
            ro = [_target_ratio(r["rows"][key], how) for r in olds] if how else []
            rn = [_target_ratio(r["rows"][key], how) for r in news] if how else []
            peers = [r["rows"][key]["peer"] for r in olds + news if "peer" in r["rows"][key]]
            pv = (olds[0]["rows"][key].get("pivots"), news[0]["rows"][key].get("pivots"))
            cells = [key, what, _us(to), _us(tn), f"{statistics.median(pair):.2f} ({_span(pair)})",
                     f"{min(tn) / min(to):.2f}", _cpu_ratio(olds, news, key)]
            cells += [f"{statistics.median(r):.2f} ({_span(r)})" if r else "" for r in (ro, rn)]
            cells.append(_num(statistics.median(peers) * 1e6) if peers else "")
            cells.append("" if pv[0] is None else f"{pv[0]:g} / {pv[1]:g}")
            L.append("| " + " | ".join(cells) + " |")
        slower = [k for k in news[0]["rows"]
                  if statistics.median([b["rows"][k]["t"] / a["rows"][k]["t"] for a, b in zip(olds, news)]) > 1.0]
        L += ["", "Rows where today is slower than the numba package (median per-pair ratio above 1): "
              + (", ".join(slower) if slower else "none") + "."]
    if data.get("first"):
        L += ["", "## First calls in a fresh process (seconds, min of "
              f"{args.runs} processes, alternated old, new)", "",
              "Whole process timed from outside (Python's start, `import numpy`, `import lemke`, the "
              "call: bench_compile.py's child code); *call*: the first call alone inside it.  "
              "*import lemke*: the import alone (after numpy).  Old with a filled numba cache "
              f"(`NUMBA_CACHE_DIR={NUMBA_CACHE}`) and once with an empty one.", "",
              "| entry point | old, cache filled | old, empty cache | today | today/old (filled) | "
              "first call old / today |", "|---|---:|---:|---:|---:|---|"]
        for name, row in data["first"].items():
            call = (f"{row['old call'] * 1e3:.1f} ms / {row['new call'] * 1e3:.2f} ms"
                    if "old call" in row else "")
            empty = f"{row['old empty']:.2f}" if "old empty" in row else ""
            L.append(f"| {name} | {row['old']:.3f} | {empty} | {row['new']:.3f} | "
                     f"{row['new'] / row['old']:.2f} | {call} |")
    return "\n".join(L) + "\n"


def summary(runs):
    """One line per row over several compares: each run's median per-pair today/old, the range
    over all their pairs, each run's ratio of minima (wall, and thread CPU time where the run
    has it), and the target ratio of either package
    (median over all its processes, and range)."""
    L = ["| row | today/old, each run's median | range over all pairs | minima, each run | CPU, each run | "
         "target ratio old, median (range) | target ratio today, median (range) |",
         "|---|---|---:|---|---|---:|---:|"]
    keys = [k for k in runs[0]["new"][0]["rows"] if all(k in r["new"][0]["rows"] for r in runs)]
    for key in keys:
        how = next(h for p, _, h in TARGETS if key.startswith(p))
        meds, pairs, minima, target, target_old = [], [], [], [], []
        for r in runs:
            to = [x["rows"][key]["t"] for x in r["old"]]
            tn = [x["rows"][key]["t"] for x in r["new"]]
            pair = [b / a for a, b in zip(to, tn)]
            meds.append(statistics.median(pair))
            pairs += pair
            minima.append(min(tn) / min(to))
            target += [_target_ratio(x["rows"][key], how) for x in r["new"]] if how else []
            target_old += [_target_ratio(x["rows"][key], how) for x in r["old"]] if how else []
        cells = [key, " / ".join(f"{m:.2f}" for m in meds), f"{min(pairs):.2f}-{max(pairs):.2f}",
                 " / ".join(f"{m:.2f}" for m in minima),
                 " / ".join(_cpu_ratio(r["old"], r["new"], key) for r in runs).strip(" /")]
        cells += [f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})" if v else ""
                  for v in (target_old, target)]
        L.append("| " + " | ".join(cells) + " |")
    return "\n".join(L) + "\n"


def compare(args):
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    from bench_lcp import machine_info
    info = machine_info()
    t0 = time.perf_counter()
    old, new = args.compare
    data = dict(date=info["date"], cpu=info["cpu"], usable=info["usable_cores"], compare=[old, new],
                load=[os.getloadavg()[0]], old=[], new=[])
    if "steady" in args.parts:
        mpc_file = os.path.join(tempfile.gettempdir(), f"bench_vs_numba_mpc_{os.getpid()}.npz")
        np.savez(mpc_file, **mpc_data())
        try:
            for k in range(args.pairs):
                for side, py in (("old", old), ("new", new)):
                    data[side].append(_steady(py, args, mpc_file))
                    r = data[side][-1]
                    log(f"pair {k + 1} {side}: {r['seconds']:.0f} s, load {r['load']}")
        finally:
            os.unlink(mpc_file)
    if "first" in args.parts:
        data["first"] = first_calls(old, new, args.runs, not args.no_empty, log)
    data["load"].append(os.getloadavg()[0])
    data["seconds"] = time.perf_counter() - t0
    if args.json:
        with open(args.json, "w") as f:
            json.dump(data, f)
    text = report(data, args)
    with open(args.out, "w") as f:
        f.write(text)
    print(text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--budget", type=float, default=0.3, help="seconds per group of interleaved calls")
    ap.add_argument("--mpc-data", help="the MPC steps (an .npz the driver writes)")
    ap.add_argument("--groups", nargs="+", choices=tuple(GROUPS), default=list(GROUPS),
                    help="the rows to measure (all by default)")
    ap.add_argument("--compare", nargs=2, metavar=("OLD_PYTHON", "NEW_PYTHON"))
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--runs", type=int, default=3, help="fresh processes per first call and side")
    ap.add_argument("--parts", nargs="+", choices=("steady", "first"), default=["steady", "first"])
    ap.add_argument("--no-empty", action="store_true", help="skip the numba package's empty-cache runs")
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "RESULTS-vs-numba.md"))
    ap.add_argument("--json", help="keep the raw numbers")
    ap.add_argument("--from-json", nargs="+", help="measure nothing: the report of the numbers "
                    "--json kept; of several such files, a summary table over them")
    args = ap.parse_args(argv)
    if args.from_json:
        runs = []
        for path in args.from_json:
            with open(path) as f:
                runs.append(json.load(f))
        args.compare, args.pairs = runs[0].get("compare", ["OLD", "NEW"]), len(runs[0]["old"])
        with open(args.out, "w") as f:
            f.write(report(runs[0], args) if len(runs) == 1 else summary(runs))
    elif args.compare:
        compare(args)
    else:
        print(json.dumps(measure(args)))


if __name__ == "__main__":
    main()
