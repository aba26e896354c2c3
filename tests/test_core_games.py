"""The C++ bimatrix games engine (``lemke._core.lemke_howson``, ``games_trace``,
``games_check``; src/lemke/games.cpp) against its frozen references (tests/frozen.py: the
outputs of the kernels it was ported from), bit for bit: every
returned number and every byte of the output buffers (the strategies, the regret and the
payoffs, the final labels and the path state), on the games of tests/test_games.py (the
textbook games, von Stengel's, Selten's, one-action and constant games, zero-sum games),
random games from 2 x 2 to 50 x 50 (uniform, integer 0..99, integer {0, 1, 2}, and
degenerate ones with repeated rows, columns and payoffs), with every label dropped, from
warm starts (every equilibrium basis found, and singular start bases), capped and
restarted runs (a pivot cap, exact ties, a pivot tolerance that breaks the paths so that
the perturbed restart runs), the tracing procedure from several priors, and the check.

Each family reports how many runs it checked (``pytest -s``)."""
import sys
from pathlib import Path

import numpy as np
import pytest

import frozen
import lemke
from lemke import _core

sys.path.insert(0, str(Path(__file__).parent))
import test_games as tg  # noqa: E402  (the games and generators of the front's tests)

PARAMS = np.array([1e6, 1e-11, 1e-11, 1e-9])  # (max_pivots, pivot_tol, tie_tol, tol): defaults
#: The oracle's number for UNCHECKED (7, which is Status.TIME_LIMIT's number: the bug that
#: src/lemke/status.hpp's negative code ends); the frozen references record it.
ORACLE_UNCHECKED = 7


def as_recorded(r):
    """A kernel's returned numbers as the oracle returned them (its code for UNCHECKED)."""
    code = int(r[0])
    return (ORACLE_UNCHECKED if code == _core.GAMES_UNCHECKED else code, *(int(v) for v in r[1:]))


def slack_start(m, n):
    return np.r_[np.arange(m, m + n), np.arange(m)].astype(np.int64)


def lh(fn, A, B, k, start, params):
    m, n = A.shape
    buf = np.full(2 * (m + n) + 3 + _core.GAMES_STATE, np.nan)
    r = fn(A, B, k, start, params, buf)
    return as_recorded(r), buf.tobytes()


def same_lh(A, B, k, start=None, params=PARAMS):
    """The core's Lemke-Howson solve, checked against the frozen references: (True, its
    result, its buffer); a changed bit fails the test when it ends."""
    m, n = A.shape
    start = slack_start(m, n) if start is None else start
    b = lh(_core.lemke_howson, A, B, k, start, params)
    frozen.check(b, ("lemke_howson", m, n, k))
    return True, b


def tr(fn, A, B, p, q, mp, ptol, ttol, tol):
    m, n = A.shape
    fbuf = np.full(m + n + 3, np.nan)
    labels = np.full(m + n + 2, -7, dtype=np.int64)
    r = fn(A, B, p, q, mp, ptol, ttol, tol, fbuf[:m], fbuf[m:m + n], labels, fbuf[m + n:])
    return as_recorded(r), fbuf.tobytes(), labels.tobytes()


def same_trace(A, B, p, q, mp=10**6, ptol=1e-11, ttol=1e-11, tol=1e-9):
    b = tr(_core.games_trace, A, B, p, q, mp, ptol, ttol, tol)
    frozen.check(b, ("trace", A.shape, mp))
    return True, b


def as_game(A, B):
    return np.ascontiguousarray(A, dtype=float), np.ascontiguousarray(B, dtype=float)


class Tally:
    """Matches and mismatches of one family (asserted at the end, reported with -s)."""

    def __init__(self, name):
        self.name, self.runs, self.bad = name, 0, []

    def add(self, ok, what):
        self.runs += 1
        if not ok:
            self.bad.append(what)

    def done(self):
        print(f"\n{self.name}: {self.runs} runs checked")
        assert not self.bad, self.bad[:10]


def every_label(tally, A, B, params=PARAMS, tag=""):
    """Every label dropped, from the artificial equilibrium; returns the end bases."""
    m, n = A.shape
    bases = []
    for k in range(m + n):
        ok, (res, buf) = same_lh(A, B, k, params=params)
        tally.add(ok, (tag, m, n, k))
        if res[0] == 0:
            ibuf = np.frombuffer(buf, dtype=np.float64)[m + n + 3:].view(np.int64)
            bases.append(ibuf[: m + n].copy())
    return bases


def known_games():
    games = [(name, *as_game(A, B)) for name, (A, B, _) in sorted(tg.KNOWN.items())]
    games.append(("selten", *as_game([[1, 1], [0, 0], [0, 2]], [[1, 1], [2, 3], [2, 0]])))
    games.append(("one action", *as_game([[1.0, 2.0, 0.5]], [[0.0, 0.0, 1.0]])))
    games.append(("one column", *as_game([[1.0], [3.0], [3.0]], [[2.0], [0.0], [1.0]])))
    games.append(("constant", np.zeros((3, 4)), np.zeros((3, 4))))
    for seed in range(5):  # test_zero_sum_value_matches_lp
        rng = np.random.default_rng(seed)
        m, n = rng.integers(2, 25, 2)
        A = rng.standard_normal((m, n))
        games.append((f"zero-sum {seed}", A, -A))
    rng = np.random.default_rng(3)  # test_result_is_immutable_and_scale_invariant
    A, B = rng.random((6, 4)), rng.random((6, 4))
    games += [("scaled", A, B), ("scaled 2", 1e6 * A + 3, 1e-6 * B - 7)]
    rng = np.random.default_rng(1)  # test_degenerate_float_path_is_the_exact_lexicographic_path
    games.append(("int3 50x50", *as_game(rng.integers(0, 3, (50, 50)), rng.integers(0, 3, (50, 50)))))
    for seed in range(100):  # long_path_game
        games.append((f"int100 7x7 {seed}", *tg.family("int100", 7, 7, seed)))
    return games


SIZES = [(2, 2), (2, 3), (3, 2), (3, 3), (4, 4), (5, 3), (6, 6), (8, 8), (7, 12), (10, 10),
         (15, 15), (20, 20), (13, 30), (30, 30), (40, 25), (50, 50)]


def degenerate(m, n, seed):
    """Repeated payoffs: a few distinct values, duplicated rows and columns, ties between
    the players' payoffs."""
    rng = np.random.default_rng(seed)
    A = rng.choice([0.0, 1.0, 1.0, 2.0], (m, n))
    B = rng.choice([0.0, 0.5, 1.0], (m, n))
    if m > 1:
        A[rng.integers(m)] = A[rng.integers(m)]
        B[rng.integers(m)] = B[rng.integers(m)]
    if n > 1:
        A[:, rng.integers(n)] = A[:, rng.integers(n)]
        B[:, rng.integers(n)] = B[:, rng.integers(n)]
    if seed % 3 == 0:
        B = A.copy()  # a coordination game
    return A, B


def random_games(seeds):
    for m, n in SIZES:
        for seed in seeds:
            for kind in ("unif", "int100", "int3"):
                yield f"{kind} {m}x{n} {seed}", *tg.family(kind, m, n, seed)
            yield f"degenerate {m}x{n} {seed}", *degenerate(m, n, seed)


def test_constants_agree():
    assert (_core.GAMES_STATE, _core.GAMES_HISTORY, _core.GAMES_NOT_FINITE) \
        == (67, 64, -1)  # the oracle's (STATE, HISTORY, NOT_FINITE)
    # UNCHECKED: the oracle's 7 was Status.TIME_LIMIT's number; the core's own codes are
    # negative (status.hpp), so that none reads as a public status
    assert _core.GAMES_UNCHECKED < 0 and _core.GAMES_UNCHECKED != _core.GAMES_NOT_FINITE
    assert _core.GAMES_UNCHECKED not in {int(s) for s in lemke.Status}


def test_known_games_every_label_and_warm_starts():
    tally = Tally("test_games.py games, every label, then every label from each basis found")
    for name, A, B in known_games():
        for start in every_label(tally, A, B, tag=name):
            m, n = A.shape
            for k in range(m + n):
                ok, _ = same_lh(A, B, k, start)
                tally.add(ok, (name, "warm", k))
    tally.done()


@pytest.mark.parametrize("seeds", [range(0, 2), range(2, 4)])
def test_random_games_every_label(seeds):
    tally = Tally(f"random games 2x2..50x50 (unif, int100, int3, degenerate), seeds {list(seeds)}, every label")
    warm = Tally("  from each equilibrium basis found, every label (sizes <= 20)")
    for name, A, B in random_games(seeds):
        bases = every_label(tally, A, B, tag=name)
        m, n = A.shape
        if m + n <= 40:
            for start in {tuple(b) for b in bases}:
                for k in range(m + n):
                    ok, _ = same_lh(A, B, k, np.array(start, dtype=np.int64))
                    warm.add(ok, (name, start, k))
    tally.done()
    warm.done()


def test_tolerances_caps_and_restarts():
    """Exact ties, a larger tie tolerance, pivot caps (MAX_PIVOTS and the path state at any
    point), and a pivot tolerance so large that paths break down (every restart, the
    perturbed one included)."""
    tally = Tally("tie_tol 0 / 1e-9, pivot caps, breakdowns and restarts")
    restarts = set()
    for name, A, B in list(random_games([5]))[::2]:
        m, n = A.shape
        for params in ([1e6, 1e-11, 0.0, 1e-9], [1e6, 1e-11, 1e-9, 1e-9], [3.0, 1e-11, 1e-11, 1e-9],
                       [17.0, 1e-11, 1e-11, 1e-9], [1e6, 0.3, 1e-11, 1e-9], [1e6, 0.9, 0.0, 1e-9],
                       [1e6, 1e-11, 1e-11, 0.0], [0.0, 1e-11, 1e-11, 1e-9]):
            params = np.array(params)
            for k in range(0, m + n, max(1, (m + n) // 6)):
                ok, (res, _) = same_lh(A, B, k, params=params)
                tally.add(ok, (name, list(params), k))
                restarts.add(res[2])
    assert restarts >= {0, 1, 2}  # the restarts with exact ties and perturbed ran
    tally.done()


def test_singular_and_arbitrary_warm_starts():
    """Arbitrary start bases (random splits of the labels between the tableaux; some
    singular: the path fails at once).  (A start with a label basic in both tableaux is
    refused: the engine would read and write out of bounds.)"""
    tally = Tally("singular and arbitrary start bases")
    rng = np.random.default_rng(9)
    for name, A, B in [("constant", np.ones((4, 3)), np.ones((4, 3))),
                       *[(f"int3 {s}", *tg.family("int3", 5, 6, s)) for s in range(10)],
                       *[(f"unif {s}", *tg.family("unif", 6, 4, s)) for s in range(10)]]:
        m, n = A.shape
        L = m + n
        for trial in range(12):
            start = rng.permutation(L).astype(np.int64)
            for k in range(L):
                ok, _ = same_lh(A, B, k, start)
                tally.add(ok, (name, start.tolist(), k))
    tally.done()


def test_extreme_and_non_finite_payoffs():
    tally = Tally("extreme scales and non-finite payoffs")
    rng = np.random.default_rng(4)
    for m, n in [(3, 3), (5, 8), (12, 12)]:
        base = rng.random((m, n)), rng.random((m, n))
        for scale in (1e-300, 1e-150, 1e150, 1e300, -1.0):
            A, B = base[0] * scale, base[1] * scale + 1.0
            every_label(tally, A, B, tag=scale)
        A = np.full((m, n), -0.0)
        every_label(tally, A, A.copy(), tag="signed zeros")
        A = base[0] * 1e308
        A[0, 0] = -1.7e308  # a payoff range that overflows
        every_label(tally, A, base[1], tag="overflowing range")
        for bad in (np.nan, np.inf, -np.inf):
            A = base[0].copy()
            A[-1, -1] = bad
            ok, (res, _) = same_lh(A, base[1], 0)
            tally.add(ok and res[0] == _core.GAMES_NOT_FINITE, (m, n, bad))
            ok, (res, _) = same_lh(base[0], A, 0)
            tally.add(ok and res[0] == _core.GAMES_NOT_FINITE, (m, n, bad, "B"))
    tally.done()


def test_tracing_procedure():
    tally = Tally("tracing procedure: test_games.py games and random games, uniform and random priors")
    rng = np.random.default_rng(12)
    games = known_games()[::3] + list(random_games([0]))[::3]
    for seed in range(20):  # test_tracing_on_random_games's family
        r = np.random.default_rng(seed)
        m, n = r.integers(1, 12, 2)
        games.append((f"int5 {seed}", *as_game(r.integers(0, 5, (m, n)), r.integers(0, 5, (m, n)))))
    codes = set()
    for name, A, B in games:
        m, n = A.shape
        priors = [(np.full(m, 1.0 / m), np.full(n, 1.0 / n))]
        for _ in range(3):
            p, q = rng.random(m), rng.random(n)
            priors.append((p / p.sum(), q / q.sum()))
        e = np.zeros(m)
        e[-1] = 1.0
        f = np.zeros(n)
        f[0] = 1.0
        priors.append((e, f))
        for p, q in priors:
            for mp, ptol, ttol in ((10**6, 1e-11, 1e-11), (10**6, 1e-11, 0.0), (5, 1e-11, 1e-11)):
                ok, (res, _, _) = same_trace(A, B, p, q, mp, ptol, ttol)
                tally.add(ok, (name, mp, ttol))
                codes.add(res[0])
    assert {0, 1} <= codes
    tally.done()


def test_check():
    tally = Tally("the check (games_check) on equilibria and on random profiles")
    rng = np.random.default_rng(2)
    for name, A, B in known_games()[::4] + list(random_games([1]))[::5]:
        m, n = A.shape
        profiles = []
        ok, (res, buf) = same_lh(A, B, 0)
        v = np.frombuffer(buf, dtype=np.float64)
        profiles.append((v[:m].copy(), v[m:m + n].copy()))
        x, y = rng.random(m), rng.random(n)
        profiles += [(x / x.sum(), y / y.sum()), (x, y), (-x, y), (np.zeros(m), np.zeros(n))]
        for x, y in profiles:
            for tol in (1e-9, 0.0, 1.0):
                def run(fn):
                    out = np.full(3, np.nan)
                    return bool(fn(A, B, x, y, tol, out)), out.tobytes()
                frozen.check(run(_core.games_check), (name, tol))
                tally.add(True, (name, tol))
    tally.done()


def test_bad_arguments_raise():
    A = np.ones((2, 3))
    buf = np.empty(2 * 5 + 3 + _core.GAMES_STATE)
    start = slack_start(2, 3)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, np.ones((3, 2)), 0, start, PARAMS, buf)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, 5, start, PARAMS, buf)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, -1, start, PARAMS, buf)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, 0, start[:4], PARAMS, buf)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, 0, np.r_[start[:4], 5], PARAMS, buf)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, 0, np.r_[start[:4], start[0]], PARAMS, buf)  # basic twice
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, 0, start, PARAMS[:3], buf)
    with pytest.raises(ValueError):
        _core.lemke_howson(A, A, 0, start, PARAMS, buf[:-1])
    with pytest.raises(ValueError):
        _core.lemke_howson(np.ones((0, 3)), np.ones((0, 3)), 0, start[:3], PARAMS, buf)
    x, y, out, lab = np.empty(2), np.empty(3), np.empty(3), np.empty(7, dtype=np.int64)
    p, q = np.full(2, 0.5), np.full(3, 1 / 3)
    with pytest.raises(ValueError):
        _core.games_trace(A, A, q, p, 10, 1e-11, 1e-11, 1e-9, x, y, lab, out)
    with pytest.raises(ValueError):
        _core.games_trace(A, A, p, q, 10, 1e-11, 1e-11, 1e-9, x, y, lab[:6], out)
    with pytest.raises(ValueError):
        _core.games_check(A, A, y, x, 1e-9, out)
    assert _core.games_trace(A, A, p, q, 10, 1e-11, 1e-11, 1e-9, x, y, lab, out)[0] == 0
