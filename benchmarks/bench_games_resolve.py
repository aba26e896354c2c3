#!/usr/bin/env python
"""Benchmark ``solve_bimatrix`` on games whose Lemke-Howson path ends at a point that fails
the check (the kernel's UNCHECKED), so that ``_games._finish`` re-solves the final basis's
support system (``_games._resolve_float``), and the re-solve alone.

Usage::

    python benchmarks/bench_games_resolve.py [--repeats R]

The games: ``tests/data/games/unchecked_36x39.npz`` (label 0) and the (game, label) pairs of
``CASES``, found by a search over 20,000 random integer games (``game(i)``: 10-44 actions a
side, payoffs integers 0..h-1 with h in 2..4, ``numpy.random.default_rng([2026, i])``),
every label dropped: 52 of about 1.5 million paths end UNCHECKED.  Each case is timed
``R`` times (a fresh random order of the cases for every repeat) and its median kept; the
report gives the median and the range over cases: ``solve_bimatrix(A, B, init_label=k)``
(the whole call: the kernel's paths, then the re-solve), ``_games._resolve_float`` alone on
its final basis and, in the same run, the numpy routine ``_resolve_float`` was before the
games kind's basis system (branch gamesbasis: ``numpy_resolve`` below, ratio per case).
Every answer is checked here (SOLVED; each player's regret against every pure strategy
within 1e-9 of the payoff range).  Run it with the base's Python and the branch's, in
alternated processes, to compare builds (the script uses only what both have).
"""
from __future__ import annotations

import argparse
import random
import statistics
import time
from pathlib import Path

import numpy as np

import lemke
from lemke import _core, _games

ROOT = Path(__file__).resolve().parent.parent
CASES = [(295, 13), (790, 15), (902, 62), (1251, 15), (1278, 46), (1361, 10), (2008, 33),
         (2876, 66), (3462, 59), (4191, 78), (4758, 30), (5282, 15), (5503, 79), (5670, 38),
         (6078, 29), (6336, 11), (6599, 62), (6924, 74), (7399, 74), (7862, 11), (7878, 5),
         (8406, 25), (9262, 4), (9828, 46), (10113, 10), (10156, 9), (10297, 68), (10633, 55),
         (11029, 5), (11188, 54), (12481, 30), (12666, 59), (13039, 37), (13208, 21),
         (13229, 39), (14291, 1), (14511, 56), (14754, 8), (14951, 46), (15091, 34),
         (15573, 46), (15613, 29), (15627, 24), (15822, 50), (16139, 23), (16681, 13),
         (16836, 73), (17350, 15), (17555, 53), (19308, 13), (19575, 53), (19825, 38)]


def game(i):
    rng = np.random.default_rng([2026, i])
    m, n = (int(v) for v in rng.integers(10, 45, 2))
    h = int(rng.integers(2, 5))
    return rng.integers(0, h, (m, n)).astype(float), rng.integers(0, h, (m, n)).astype(float)


def numpy_resolve(A, B, basis, tol):
    """_games._resolve_float before branch gamesbasis (numpy.linalg.solve), verbatim."""
    m, n = basis.m, basis.n
    S, J, T, I = _games._supports(basis)
    if len(S) != len(J) or len(T) != len(I) or not S or not T:
        return None
    x = np.zeros(m)
    y = np.zeros(n)
    try:
        for P, sup, tight, v in ((B, S, J, x), (A.T, T, I, y)):
            k = len(sup)
            M = np.zeros((k + 1, k + 1))
            M[:k, :k] = P[np.ix_(sup, tight)].T
            M[:k, k] = -1.0
            M[k, :k] = 1.0
            rhs = np.zeros(k + 1)
            rhs[k] = 1.0
            v[sup] = np.linalg.solve(M, rhs)[:k]
    except np.linalg.LinAlgError:
        return None
    if x.min() < -1e-12 or y.min() < -1e-12:
        return None
    x = np.maximum(x, 0.0)
    y = np.maximum(y, 0.0)
    x /= x.sum()
    y /= y.sum()
    out = np.empty(3)
    return (x, y, out) if _core.games_check(A, B, x, y, tol, out) else None


def regret_ok(A, B, x, y, tol=1e-9):
    Ay, xB = A @ y, x @ B
    return (Ay.max() - x @ Ay <= tol * np.ptp(A) + 1e-13 and xB.max() - xB @ y <= tol * np.ptp(B) + 1e-13
            and abs(x.sum() - 1) < 1e-12 and abs(y.sum() - 1) < 1e-12 and x.min() >= 0 and y.min() >= 0)


def cases():
    d = np.load(ROOT / "tests" / "data" / "games" / "unchecked_36x39.npz")
    out = [("unchecked_36x39", d["A"].astype(float), d["B"].astype(float), int(d["k"]))]
    out += [(f"game {i}", *game(i), k) for i, k in CASES]
    return out


def timed(fn, *args, **kw):
    t = time.perf_counter()
    r = fn(*args, **kw)
    return time.perf_counter() - t, r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=15)
    args = ap.parse_args()
    todo = cases()
    m0, n0 = todo[0][1].shape
    at = _games._layout(m0, n0)
    prep = []
    for name, A, B, k in todo:
        m, n = A.shape
        buf = np.empty(_games._layout(m, n)["length"])
        code = _core.lemke_howson(A, B, k, _games._slack_start(m, n), _games._DEFAULT_PARAMS, buf)[0]
        assert code == _core.GAMES_UNCHECKED, (name, code)  # the case this benchmark is for
        res = lemke.solve_bimatrix(A, B, init_label=k)
        assert res.status == lemke.Status.SOLVED and regret_ok(A, B, np.asarray(res.x), np.asarray(res.y)), name
        prep.append((name, A, B, k, res.basis))
    times = {key: {c[0]: [] for c in prep} for key in ("solve_bimatrix", "resolve", "numpy")}
    for _ in range(args.repeats):
        order = list(prep)
        random.shuffle(order)
        for name, A, B, k, basis in order:
            t, res = timed(lemke.solve_bimatrix, A, B, init_label=k)
            times["solve_bimatrix"][name].append(t)
            jobs = [("resolve", _games._resolve_float), ("numpy", numpy_resolve)]
            random.shuffle(jobs)
            for key, fn in jobs:
                t, r = timed(fn, A, B, basis, 1e-9)
                assert r is not None and regret_ok(A, B, r[0], r[1]), (name, key)
                times[key][name].append(t)
    med = {key: {c: statistics.median(v) for c, v in d.items()} for key, d in times.items()}
    print(f"lemke {lemke.__file__}; {len(prep)} cases, {args.repeats} repeats; load {open('/proc/loadavg').read().split()[0]}")
    for key in ("solve_bimatrix", "resolve", "numpy"):
        v = sorted(med[key].values())
        print(f"{key:15s} median over cases {statistics.median(v) * 1e6:9.1f} us  (min {v[0] * 1e6:.1f}, max {v[-1] * 1e6:.1f})")
    ratio = sorted(med["resolve"][c] / med["numpy"][c] for c in med["resolve"])
    print(f"resolve / numpy per case: median {statistics.median(ratio):.3f} (range {ratio[0]:.3f}-{ratio[-1]:.3f})")
    share = sorted(med["resolve"][c] / med["solve_bimatrix"][c] for c in med["resolve"])
    print(f"resolve / solve_bimatrix per case: median {statistics.median(share):.3f}")
    u = med["solve_bimatrix"]["unchecked_36x39"]
    print(f"unchecked_36x39: solve_bimatrix {u * 1e6:.1f} us, resolve {med['resolve']['unchecked_36x39'] * 1e6:.1f} us, "
          f"numpy {med['numpy']['unchecked_36x39'] * 1e6:.1f} us")


if __name__ == "__main__":
    main()
