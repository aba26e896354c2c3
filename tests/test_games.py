"""Bimatrix games: lemke.solve_bimatrix, lemke.lemke_paths and the .nfg reader.

Every answer is judged by the regret computed here in plain numpy (or exactly with
fractions), never by lemke's own check.  Convention: A is the row player's payoffs, B the
column player's, both m x n.
"""
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog

import lemke
from lemke import _core, _games, _games_exact
from lemke._io import ProblemFormatError
from lemke._io.nfg import read_nfg


def regret(A, B, x, y):
    """The larger of the two players' regrets (best reply payoff minus payoff obtained)."""
    A, B, x, y = (np.asarray(v, dtype=float) for v in (A, B, x, y))
    return max((A @ y).max() - x @ A @ y, (B.T @ x).max() - x @ B @ y)


def assert_equilibrium(A, B, res, rtol=1e-9):
    A, B = np.asarray(A, dtype=float), np.asarray(B, dtype=float)
    x, y = np.asarray(res.x, dtype=float), np.asarray(res.y, dtype=float)
    assert res.status == lemke.Status.SOLVED, res
    assert x.shape == (A.shape[0],) and y.shape == (A.shape[1],)
    assert x.min() >= 0 and y.min() >= 0
    assert abs(x.sum() - 1) <= 1e-12 * x.size and abs(y.sum() - 1) <= 1e-12 * y.size
    span = max(np.ptp(A), np.ptp(B), 1e-300)
    assert regret(A, B, x, y) <= rtol * span + 1e-15 * np.abs(A).max(initial=1)


def exact_regret(A, B, x, y):
    """Both players' regrets in rational arithmetic (A, B as exact Fractions of the floats)."""
    Af = [[Fraction(v) for v in row] for row in np.asarray(A, dtype=float)]
    Bf = [[Fraction(v) for v in row] for row in np.asarray(B, dtype=float)]
    m, n = len(Af), len(Af[0])
    Ay = [sum(Af[i][j] * y[j] for j in range(n)) for i in range(m)]
    Bx = [sum(Bf[i][j] * x[i] for i in range(m)) for j in range(n)]
    return (max(Ay) - sum(x[i] * Ay[i] for i in range(m)),
            max(Bx) - sum(y[j] * Bx[j] for j in range(n)))


def assert_exact_equilibrium(A, B, res):
    assert res.status == lemke.Status.SOLVED and res.exact
    assert all(isinstance(v, Fraction) for v in res.x + res.y)
    assert sum(res.x) == 1 and sum(res.y) == 1 and min(res.x) >= 0 and min(res.y) >= 0
    assert exact_regret(A, B, res.x, res.y) == (0, 0)
    assert res.regret == 0


# --- known games and their published equilibria -----------------------------------------------

# von Stengel (2002), "Computing equilibria for two-person games", Handbook of Game Theory
# vol. 3, the 3 x 2 example game (also the example of quantecon's lemke_howson docstring,
# BSD-3-Clause): three equilibria, the third (4/5, 1/5, 0) not reachable from the artificial
# equilibrium.
STENGEL_A = [[3, 3], [2, 5], [0, 6]]
STENGEL_B = [[3, 2], [2, 6], [3, 1]]
STENGEL_EQ = {((1, 0, 0), (1, 0)),
              ((0, Fraction(1, 3), Fraction(2, 3)), (Fraction(1, 3), Fraction(2, 3))),
              ((Fraction(4, 5), Fraction(1, 5), 0), (Fraction(2, 3), Fraction(1, 3)))}

# Textbook games (Osborne & Rubinstein 1994, "A Course in Game Theory", chapter 2-3;
# matching pennies is also the example of nashpy's documentation, MIT License).
KNOWN = {
    "matching pennies": ([[1, -1], [-1, 1]], [[-1, 1], [1, -1]],
                         {((Fraction(1, 2), Fraction(1, 2)), (Fraction(1, 2), Fraction(1, 2)))}),
    "battle of the sexes": ([[3, 0], [0, 2]], [[2, 0], [0, 3]],
                            {((1, 0), (1, 0)), ((0, 1), (0, 1)),
                             ((Fraction(3, 5), Fraction(2, 5)), (Fraction(2, 5), Fraction(3, 5)))}),
    "prisoner's dilemma": ([[3, 0], [5, 1]], [[3, 5], [0, 1]], {((0, 1), (0, 1))}),
    "rock paper scissors": ([[0, -1, 1], [1, 0, -1], [-1, 1, 0]], [[0, 1, -1], [-1, 0, 1], [1, -1, 0]],
                            {((Fraction(1, 3),) * 3, (Fraction(1, 3),) * 3)}),
    "von Stengel 3x2": (STENGEL_A, STENGEL_B, STENGEL_EQ),
}


def as_key(res):
    return (tuple(Fraction(v) for v in res.x), tuple(Fraction(v) for v in res.y))


@pytest.mark.parametrize("name", sorted(KNOWN))
def test_known_games_every_label(name):
    A, B, equilibria = KNOWN[name]
    m, n = np.shape(A)
    for k in range(m + n):
        res = lemke.solve_bimatrix(A, B, init_label=k)
        assert_equilibrium(A, B, res)
        exact = lemke.solve_bimatrix(A, B, init_label=k, exact=True)
        assert_exact_equilibrium(A, B, exact)
        assert as_key(exact) in equilibria
        np.testing.assert_allclose(res.x, [float(v) for v in exact.x], atol=1e-12)


@pytest.mark.parametrize("name", sorted(KNOWN))
def test_lemke_paths_finds_the_published_equilibria(name):
    A, B, equilibria = KNOWN[name]
    found = lemke.lemke_paths(A, B, exact=True)
    for res in found:
        assert_exact_equilibrium(A, B, res)
    # In all these games every equilibrium is reachable by Lemke paths.
    assert {as_key(r) for r in found} == equilibria


def test_stengel_labels_and_quantecon_convention():
    """The dropped label decides the equilibrium; labels as quantecon's init_pivot."""
    r0 = lemke.solve_bimatrix(STENGEL_A, STENGEL_B, init_label=0, exact=True)
    r1 = lemke.solve_bimatrix(STENGEL_A, STENGEL_B, init_label=1, exact=True)
    assert as_key(r0) == ((1, 0, 0), (1, 0))
    assert as_key(r1) == ((0, Fraction(1, 3), Fraction(2, 3)), (Fraction(1, 3), Fraction(2, 3)))
    assert r1.payoffs == (4, Fraction(8, 3))


def test_tracing_selects_the_equilibrium_of_the_prior():
    A, B, _ = KNOWN["battle of the sexes"]
    r = lemke.solve_bimatrix(A, B, method="tracing", prior=([1, 0], [1, 0]), exact=True)
    assert as_key(r) == ((1, 0), (1, 0))
    r = lemke.solve_bimatrix(A, B, method="tracing", prior=([0, 1], [0, 1]), exact=True)
    assert as_key(r) == ((0, 1), (0, 1))
    # The uniform prior: the column player (3 vs 2 on the diagonal) prefers the second
    # action, the row player the first; the linear tracing procedure ends at a pure one.
    r = lemke.solve_bimatrix(A, B, method="tracing")
    assert_equilibrium(A, B, r)


def test_tracing_on_random_games():
    rng = np.random.default_rng(7)
    for _ in range(20):
        m, n = rng.integers(1, 12, 2)
        A, B = rng.integers(0, 5, (m, n)), rng.integers(0, 5, (m, n))
        p, q = rng.random(m), rng.random(n)
        assert_equilibrium(A, B, lemke.solve_bimatrix(A, B, method="tracing", prior=(p, q)))
        assert_exact_equilibrium(A, B, lemke.solve_bimatrix(A, B, method="tracing", prior=(p, q), exact=True))


def test_selten_degenerate_game():
    """Selten (1975), Figure 2 in strategic form (Gambit's e02 example): a component of
    equilibria (x = e1, y2 <= 1/2); every label must still end at an equilibrium."""
    A = [[1, 1], [0, 0], [0, 2]]
    B = [[1, 1], [2, 3], [2, 0]]
    for k in range(5):
        assert_equilibrium(A, B, lemke.solve_bimatrix(A, B, init_label=k))
        assert_exact_equilibrium(A, B, lemke.solve_bimatrix(A, B, init_label=k, exact=True))
    for r in lemke.lemke_paths(A, B):
        assert_equilibrium(A, B, r)


def lp_value(A):
    """The value of the zero-sum game A (row player maximizes) from an LP."""
    m, n = A.shape
    c = np.r_[np.zeros(m), -1.0]
    A_ub = np.c_[-A.T, np.ones(n)]  # v - (A'x)_j <= 0
    res = linprog(c, A_ub=A_ub, b_ub=np.zeros(n), A_eq=np.r_[np.ones(m), 0.0][None],
                  b_eq=[1.0], bounds=[(0, None)] * m + [(None, None)], method="highs")
    assert res.status == 0
    return -res.fun


@pytest.mark.parametrize("seed", range(5))
def test_zero_sum_value_matches_lp(seed):
    rng = np.random.default_rng(seed)
    m, n = rng.integers(2, 25, 2)
    A = rng.standard_normal((m, n))
    res = lemke.solve_bimatrix(A, -A, init_label=int(seed) % (m + n))
    assert_equilibrium(A, -A, res)
    assert res.payoffs[0] == pytest.approx(lp_value(A), abs=1e-9 * np.ptp(A))
    assert res.payoffs[1] == pytest.approx(-res.payoffs[0], abs=1e-12 * np.ptp(A))


def test_warm_start_from_an_equilibrium_reaches_another():
    A, B = STENGEL_A, STENGEL_B
    r = lemke.solve_bimatrix(A, B, init_label=0)
    seen = set()
    for k in range(5):
        s = lemke.solve_bimatrix(A, B, init_label=k, warm_start=r.basis)
        if s.success:
            seen.add(tuple(np.round(s.x, 9)))
    assert (0.8, 0.2, 0.0) in seen  # the equilibrium Lemke-Howson cannot reach from 0


def test_degenerate_float_path_is_the_exact_lexicographic_path():
    """An int3 50 x 50 game on which quantecon's lemke_howson cycles to its pivot cap: the
    float path follows the exact (integer) lexicographic path pivot for pivot, no restart."""
    rng = np.random.default_rng(1)
    A, B = rng.integers(0, 3, (50, 50)).astype(float), rng.integers(0, 3, (50, 50)).astype(float)
    res = lemke.solve_bimatrix(A, B)
    assert_equilibrium(A, B, res)
    assert res.restarts == 0
    Ai, _ = _games_exact.dyadic(A)
    Bi, _ = _games_exact.dyadic(B)
    assert _games_exact.lemke_howson(Ai, Bi, 0, 10**5).pivots == res.pivots


def test_result_is_immutable_and_scale_invariant():
    rng = np.random.default_rng(3)
    A, B = rng.random((6, 4)), rng.random((6, 4))
    r = lemke.solve_bimatrix(A, B)
    with pytest.raises(Exception):
        r.x[0] = 1.0
    with pytest.raises(Exception):
        r.status = lemke.Status.MAX_PIVOTS
    s = lemke.solve_bimatrix(1e6 * A + 3, 1e-6 * B - 7)
    np.testing.assert_allclose(s.x, r.x, atol=1e-9)
    np.testing.assert_allclose(s.y, r.y, atol=1e-9)


def test_one_action_and_constant_games():
    assert_equilibrium([[1.0, 2.0, 0.5]], [[0.0, 0.0, 1.0]], lemke.solve_bimatrix([[1.0, 2.0, 0.5]], [[0.0, 0.0, 1.0]]))
    A = np.zeros((3, 4))
    for k in range(7):
        assert_equilibrium(A, A, lemke.solve_bimatrix(A, A, init_label=k))
        assert_exact_equilibrium(A, A, lemke.solve_bimatrix(A, A, init_label=k, exact=True))


# --- random games: the three families of the issue --------------------------------------------

def family(kind, m, n, seed):
    rng = np.random.default_rng(seed)
    if kind == "unif":
        return rng.random((m, n)), rng.random((m, n))
    top = 100 if kind == "int100" else 3
    return rng.integers(0, top, (m, n)).astype(float), rng.integers(0, top, (m, n)).astype(float)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=st.sampled_from(["unif", "int100", "int3"]), m=st.integers(1, 30), n=st.integers(1, 30),
       seed=st.integers(0, 2**32 - 1), label=st.integers(0, 59))
def test_random_games_always_solved(kind, m, n, seed, label):
    A, B = family(kind, m, n, seed)
    res = lemke.solve_bimatrix(A, B, init_label=label % (m + n))
    assert_equilibrium(A, B, res)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=st.sampled_from(["unif", "int100", "int3"]), m=st.integers(1, 12), n=st.integers(1, 12),
       seed=st.integers(0, 2**32 - 1), label=st.integers(0, 23))
def test_random_games_exact_regret_zero(kind, m, n, seed, label):
    A, B = family(kind, m, n, seed)
    assert_exact_equilibrium(A, B, lemke.solve_bimatrix(A, B, init_label=label % (m + n), exact=True))


@pytest.mark.parametrize("kind", ["int3", "int100", "unif"])
def test_random_games_100(kind):
    for seed in range(3):
        A, B = family(kind, 100, 100, seed)
        assert_equilibrium(A, B, lemke.solve_bimatrix(A, B))


def test_exact_continuation_when_the_float_basis_is_wrong(monkeypatch):
    """If the float path's basis is not exactly an equilibrium, exact Lemke-Howson takes
    over: simulated by a kernel that reports the artificial basis."""
    from lemke import _games

    def lying(A, B, k, start, params, buf):
        m, n = A.shape
        buf[:] = 0.0
        ibuf = buf[m + n + 3 :].view(np.int64)
        ibuf[: m + n] = np.r_[np.arange(m, m + n), np.arange(m)]
        ibuf[m + n : m + n + 3] = (k, 0, 1)  # one pivot made: no state to continue from
        return 0, 1, 0

    monkeypatch.setattr(_games, "_LEMKE_HOWSON", lying)
    A, B = STENGEL_A, STENGEL_B
    res = lemke.solve_bimatrix(A, B, init_label=1, exact=True)
    assert_exact_equilibrium(A, B, res)
    # The reported state is no state of a path dropping label 1: nothing to continue from.
    assert res.exact_from == "restart" and res.walked_back == 0
    assert res.basis == lemke.GameBasis(3, 2, (1, 2), (0, 3, 4))  # the exact path's end


def long_path_game(k=0):
    """A 7 x 7 game (integer payoffs) whose Lemke-Howson path dropping k has at least 8
    pivots, and that path's length in exact arithmetic."""
    for seed in range(100):
        A, B = family("int100", 7, 7, seed)
        P = _games_exact.lemke_howson(_games_exact.dyadic(A)[0], _games_exact.dyadic(B)[0], k, 10**4).pivots
        if P >= 8:
            return A, B, P
    raise AssertionError("no game with a long path")


def stopped_float_path(A, B, k, pivots):
    """The float kernel's path dropping k stopped after ``pivots`` pivots: its status and
    the state it reports (``_games._path_state``)."""
    m, n = A.shape
    buf = np.empty(2 * (m + n) + 3 + _core.GAMES_STATE)
    params = np.array([float(pivots), 1e-9, 1e-11, 1e-9])
    code, done, _ = _core.lemke_howson(A, B, k, np.r_[np.arange(m, m + n), np.arange(m)],
                                       params, buf)
    assert done == pivots
    return code, buf, _games._path_state(buf[m + n + 3 :].view(np.int64), m, n, k)


def exact_strategies(path, m, n):
    (S, xn, dx), (T, yn, dy) = path.xs, path.ys
    x, y = [Fraction(0)] * m, [Fraction(0)] * n
    for i, v in zip(S, xn):
        x[i] = Fraction(int(v), dx)
    for j, v in zip(T, yn):
        y[j] = Fraction(int(v), dy)
    return x, y


@pytest.mark.parametrize("before_end", [1, 3, 5])
def test_exact_continuation_from_a_state_on_the_path(before_end):
    """The float path stopped a few pivots before its end: exact Lemke-Howson continues
    from its state and needs only the pivots that were left (a restart needs them all)."""
    A, B, P = long_path_game()
    code, _, (labP, labQ, side, left) = stopped_float_path(A, B, 0, P - before_end)
    assert code == lemke.Status.MAX_PIVOTS
    Aint, Bint = _games_exact.dyadic(A)[0], _games_exact.dyadic(B)[0]
    run, walked = _games_exact.continuation(Aint, Bint, 0, labP, labQ, side, left, 10**4)
    assert run.status == "solved" and walked == 0
    assert run.pivots == before_end < P
    x, y = exact_strategies(run, 7, 7)
    assert sum(x) == 1 and sum(y) == 1 and min(x) >= 0 and min(y) >= 0
    assert exact_regret(A, B, x, y) == (0, 0)
    # The same through the front: the float path capped, the exact one takes over.
    res = lemke.solve_bimatrix(A, B, exact=True, options={"max_pivots": P})
    assert res.exact_from == "float basis" and res.pivots == P
    capped = lemke.solve_bimatrix(A, B, exact=True, options={"max_pivots": P - before_end})
    assert capped.status == lemke.Status.MAX_PIVOTS  # no pivot left for the exact path


def test_exact_continuation_through_the_front(monkeypatch):
    """solve_bimatrix(exact=True) after a float path that stopped early (a breakdown,
    simulated): the exact path continues from the stopped state, to the same equilibrium
    as a restart, with fewer exact pivots."""
    A, B, P = long_path_game()
    real = _games._LEMKE_HOWSON
    stop = P - 3

    def stopped(A, B, k, start, params, buf):
        short = params.copy()
        short[0] = stop
        code, pivots, restarts = real(A, B, k, start, short, buf)
        return int(lemke.Status.NUMERICAL_FAILURE), pivots, restarts

    monkeypatch.setattr(_games, "_LEMKE_HOWSON", stopped)
    res = lemke.solve_bimatrix(A, B, exact=True)
    assert_exact_equilibrium(A, B, res)
    assert res.exact_from == "continuation" and res.walked_back == 0
    assert res.pivots == stop + 3  # 3 exact pivots: the rest of the path
    monkeypatch.undo()
    restart = _games_exact.lemke_howson(_games_exact.dyadic(A)[0], _games_exact.dyadic(B)[0], 0, 10**4)
    assert restart.pivots == P > 3
    assert as_key(res) == as_key(lemke.solve_bimatrix(A, B, exact=True))


def test_exact_continuation_walks_back_from_a_wrong_pivot(monkeypatch):
    """A float path whose last pivot chose a wrong row (what rounding can do): its state is
    not a vertex pair in exact arithmetic, so the exact path undoes that pivot and continues
    from the state before it."""
    A, B, P = long_path_game()
    m, n = A.shape
    k = 0
    code, buf, (labP, labQ, side, left) = stopped_float_path(A, B, k, P - 1)
    entering = left[-1]
    # A wrong pivot in that state: ``entering`` replaces a basic label other than k, one
    # that leaves a non-singular basis (the right one, k, would end the path).
    P_, Q_ = _games_exact.tableaux(_games_exact.dyadic(A)[0], _games_exact.dyadic(B)[0])
    assert P_.place(list(labP)) and Q_.place(list(labQ))
    t = (P_, Q_)[side]
    s = t.column(entering)
    wrong = [lab for r, lab in enumerate(t.basis) if lab != k and t.D[r, s] != 0]
    assert wrong
    labels = [list(labP), list(labQ)]
    labels[side][labels[side].index(wrong[0])] = entering
    ibuf = buf[m + n + 3 :].view(np.int64)
    ibuf[:n], ibuf[n : m + n] = labels[0], labels[1]
    run = int(ibuf[m + n + 2])
    ibuf[m + n : m + n + 3] = (wrong[0], 1 - side, run + 1)
    ibuf[m + n + 3 + run % _core.GAMES_HISTORY] = wrong[0]

    def wrong_pivot(A, B, k, start, params, out):
        out[:] = buf
        return int(lemke.Status.NUMERICAL_FAILURE), P, 0

    monkeypatch.setattr(_games, "_LEMKE_HOWSON", wrong_pivot)
    res = lemke.solve_bimatrix(A, B, exact=True)
    assert_exact_equilibrium(A, B, res)
    assert res.exact_from == "continuation" and res.walked_back == 1
    assert res.pivots == P + 1  # the float path's P, then the one exact pivot that was left


# --- bad input ----------------------------------------------------------------------------

@pytest.mark.parametrize("A, B, words", [
    ([[1.0, np.nan]], [[1.0, 2.0]], "non-finite"),
    ([[1.0, 2.0]], [[1.0, np.inf]], "non-finite"),
    ([[1.0, 2.0]], [[1.0], [2.0]], "same shape"),
    (np.zeros((0, 3)), np.zeros((0, 3)), "empty strategy set"),
    (np.zeros((2, 0)), np.zeros((2, 0)), "empty strategy set"),
    ([1.0, 2.0], [1.0, 2.0], "2-D"),
    ([["a", "b"]], [[1, 2]], "real numbers"),
])
def test_bad_payoffs(A, B, words):
    with pytest.raises(ValueError, match=words):
        lemke.solve_bimatrix(A, B)


def test_bad_arguments():
    A, B = STENGEL_A, STENGEL_B
    with pytest.raises(ValueError, match="out of range"):
        lemke.solve_bimatrix(A, B, init_label=5)
    with pytest.raises(ValueError, match="out of range"):
        lemke.solve_bimatrix(A, B, init_label=-1)
    with pytest.raises(ValueError, match="init_label"):
        lemke.solve_bimatrix(A, B, init_label=True)
    with pytest.raises(ValueError, match="unknown method"):
        lemke.solve_bimatrix(A, B, method="simplex")
    with pytest.raises(ValueError, match="prior"):
        lemke.solve_bimatrix(A, B, method="tracing", prior=([1, 0], [1, 0]))
    with pytest.raises(ValueError, match="warm_start"):
        lemke.solve_bimatrix(A, B, warm_start=lemke.GameBasis(2, 2, (2, 3), (0, 1)))
    with pytest.raises(ValueError, match="exactly one"):  # label 0 basic in both polytopes
        lemke.solve_bimatrix(A, B, warm_start=lemke.GameBasis(3, 2, (0, 3), (0, 1, 2)))
    with pytest.raises(ValueError, match="non-finite"):
        lemke.solve_bimatrix(np.array([[np.nan, 1.0]]), np.array([[0.0, 1.0]]))  # the fast path


# --- Gambit .nfg files ----------------------------------------------------------------------

PAYOFF_NFG = """NFG 1 R "von Stengel's 3 x 2 example" { "Row" "Column" } { 3 2 }
"a comment"

3 3 2 2 0 3 3 2 5 6 6 1
"""

OUTCOME_NFG = """NFG 1 R "the same game, outcome version" { "Row" "Column" }

{ { "T" "M" "B" }
{ "L" "R" }
}
""

{
{ "" 3, 3 }
{ "" 2, 2 }
{ "" 0, 3 }
{ "a \\"quoted\\" name" 3, 2 }
{ "" 5, 6 }
{ "" 6, 1 }
}
1 2 3 4 5 6
"""


def test_read_nfg_both_versions(tmp_path):
    for text in (PAYOFF_NFG, OUTCOME_NFG):
        path = tmp_path / "game.nfg"
        path.write_text(text)
        A, B = read_nfg(path)
        np.testing.assert_array_equal(A, STENGEL_A)
        np.testing.assert_array_equal(B, STENGEL_B)
    path.write_text('NFG 1 R "" { "1" "2" } { { "a" "b" } { "c" } } 1/2 -1 .25 3e2')
    A, B = read_nfg(path)
    np.testing.assert_array_equal(A, [[0.5], [0.25]])
    np.testing.assert_array_equal(B, [[-1.0], [300.0]])
    path.write_text('NFG 1 R "" { "1" "2" } { { "a" } { "c" "d" } } "" { { "o" 1 2 } } 0 1')
    A, B = read_nfg(path)
    np.testing.assert_array_equal(A, [[0.0, 1.0]])
    np.testing.assert_array_equal(B, [[0.0, 2.0]])


@pytest.mark.parametrize("text, words", [
    ("", "does not start with 'NFG'"),
    ("EFG 2 R", "does not start"),
    ('NFG 1 R "t" { "1" "2" "3" } { 2 2 2 }', "3 players"),
    ('NFG 1 R "t" { "1" "2" } { 2 2 } 1 2 3', "ends where a payoff"),
    ('NFG 1 R "t" { "1" "2" } { 1 1 } 1 x', "not a number"),
    ('NFG 1 R "t" { "1" "2" } { 1 1 } 1 2 3', "unexpected"),
    ('NFG 1 R "t" { "1" "2" } { 0 1 }', "positive integer"),
    ('NFG 1 R "t { "1" "2" }', "not closed"),
    ('NFG 1 R "t" { "1" "2" } { { "a" } { "b" } } "" { { "" 1 2 } } 2', "outcome number"),
    ('NFG 1 R "t" { "1" "2" } { 1 1 } 1/0 2', "not a number"),
])
def test_read_nfg_malformed(tmp_path, text, words):
    path = tmp_path / "bad.nfg"
    path.write_text(text)
    with pytest.raises(ProblemFormatError, match=words) as err:
        read_nfg(path)
    assert str(path) in str(err.value) and "\n" not in str(err.value)


def test_read_nfg_missing_file(tmp_path):
    with pytest.raises(ProblemFormatError, match="cannot read"):
        read_nfg(tmp_path / "absent.nfg")


def test_lemke_paths_on_degenerate_random_games():
    """Every equilibrium found is one (checked exactly), none twice."""
    rng = np.random.default_rng(11)
    for _ in range(8):
        m, n = rng.integers(2, 7, 2)
        A, B = rng.integers(0, 3, (m, n)), rng.integers(0, 3, (m, n))
        found = lemke.lemke_paths(A, B, exact=True)
        assert found
        for r in found:
            assert_exact_equilibrium(A, B, r)
        assert len({as_key(r) for r in found}) == len(found)


# --- the native front (_core.games_front) ------------------------------------------------------

@pytest.mark.parametrize("kind, m, n", [("unif", 7, 5), ("int100", 12, 12), ("int3", 9, 11),
                                        ("unif", 30, 30), ("int100", 1, 4)])
def test_front_is_the_python_path(kind, m, n, monkeypatch):
    """solve_bimatrix's native front gives the Python path's result bit for bit (results are
    values: == compares every field's bits), and each is an equilibrium by the numpy check."""
    fronts, paths = [], []
    for seed in range(3):
        A, B = family(kind, m, n, seed)
        A, B = np.ascontiguousarray(A, dtype=float), np.ascontiguousarray(B, dtype=float)
        for k in sorted({0, m - 1, m, m + n - 1}):
            assert isinstance(_core.games_front(A, B, k), lemke.BimatrixResult)  # the front took it
            fronts.append(lemke.solve_bimatrix(A, B, init_label=k))
            assert_equilibrium(A, B, fronts[-1])
    monkeypatch.setattr(_games, "_FRONT", lambda A, B, k: None)
    for seed in range(3):
        A, B = family(kind, m, n, seed)
        A, B = np.ascontiguousarray(A, dtype=float), np.ascontiguousarray(B, dtype=float)
        for k in sorted({0, m - 1, m, m + n - 1}):
            paths.append(lemke.solve_bimatrix(A, B, init_label=k))
    assert fronts == paths
    for r in fronts + paths:  # read-only views of the kernel's buffer, as the lazy fields are
        assert not r.x.flags.writeable and not r.y.flags.writeable
        assert not r.x.flags.owndata and r.x.base is not None and r.x.base is r.y.base
        m, n = len(r.x), len(r.y)
        assert r.x.base.shape == (_games._layout(m, n)["length"],)
        assert np.shares_memory(r.x, r.x.base[:m]) and np.shares_memory(r.y, r.x.base[m : m + n])
        with pytest.raises(ValueError):
            r.x[0] = 2.0
    assert [(r.basis, r.payoffs, r.regret, r.init_label) for r in fronts] == [
        (r.basis, r.payoffs, r.regret, r.init_label) for r in paths]


def test_front_declines_other_arguments():
    """Anything but plain float64 payoffs (C-contiguous, writable or not) of one non-empty
    shape and an int label in range goes to the Python path (None), which then answers or
    names the error."""
    A, B = np.array(STENGEL_A, dtype=float), np.array(STENGEL_B, dtype=float)
    ro = A.copy()
    ro.flags.writeable = False
    assert _core.games_front(ro, B, 0) is not None  # read-only: taken (only read)
    for args in [(A.T, B.T), (np.asfortranarray(A), B), (A.astype(np.float32), B),
                 (A.astype(np.int64), B), (A[:, :1], B), (A.tolist(), B)]:
        assert _core.games_front(*args, 0) is None
        assert _core.games_front(args[1], args[0], 0) is None
    for k in (True, np.int64(0), 0.0, -1, A.shape[0] + A.shape[1], 2**70):
        assert _core.games_front(A, B, k) is None
    assert_equilibrium(A, B, lemke.solve_bimatrix(ro, B))
    assert lemke.solve_bimatrix(ro, B) == lemke.solve_bimatrix(A, B)


def test_solve_bimatrix_entry_is_the_python_function_to_its_callers(monkeypatch):
    """``lemke.solve_bimatrix`` is the core's entry (``_core.games_entry``,
    src/python_front.cpp): solve_bimatrix(A, B) and solve_bimatrix(A, B, init_label=k) go to
    ``_games._FRONT`` with no Python frame (a run it does not settle to
    ``_games._after_front``), everything else to the Python function it wraps; it reads
    ``_FRONT`` on each call and shows the function's name, docstring, signature and pickles
    by name."""
    import inspect
    import pickle

    f = lemke.solve_bimatrix
    assert f is _games.solve_bimatrix and f.__wrapped__ is _games._solve_bimatrix and f is not f.__wrapped__
    assert (f.__name__, f.__module__, f.__doc__) == ("solve_bimatrix", "lemke._games", _games._solve_bimatrix.__doc__)
    assert str(inspect.signature(f)) == str(inspect.signature(_games._solve_bimatrix))
    assert repr(f) == repr(_games._solve_bimatrix) and pickle.loads(pickle.dumps(f)) is f
    A, B = np.array(STENGEL_A, dtype=float), np.array(STENGEL_B, dtype=float)
    py = _games._solve_bimatrix
    for k in range(5):
        assert f(A, B, init_label=k) == py(A, B, init_label=k)
        assert_equilibrium(A, B, f(A, B, init_label=k))
    assert f(A, B) == py(A, B) and f(A, B).init_label == 0
    calls = []
    front = _games._FRONT
    monkeypatch.setattr(_games, "_FRONT", lambda *a: calls.append(a) or front(*a))
    assert f(A, B) == py(A, B) and f(A, B, init_label=3) == py(A, B, init_label=3)
    assert len(calls) == 4 and [c[2] for c in calls] == [0, 0, 3, 3]  # each through Python
    monkeypatch.undo()
    with pytest.raises(TypeError):
        f(A)
    with pytest.raises(TypeError):
        f(A, B, 1)  # keyword-only, as the Python function's
    with pytest.raises(ValueError, match="out of range"):
        f(A, B, init_label=5)
    with pytest.raises(ValueError, match="non-finite"):  # the front's code, then _after_front
        f(np.array([[1.0, np.inf], [0.0, 2.0]]), np.ones((2, 2)))
    # the entry's other calls: the Python function's (lists, options, exact, tracing)
    assert f(A.tolist(), B.tolist()) == f(A, B)
    assert f(A, B, options={"max_pivots": 100}) == f(A, B)
    assert f(A, B, method="tracing") == py(A, B, method="tracing")
    assert f(A, B, exact=True) == py(A, B, exact=True)


def test_front_hands_back_what_it_does_not_settle():
    """A payoff that is not finite: the front hands the kernel's code back and the Python
    path names the entry, as without the front."""
    A = np.array([[1.0, np.nan], [0.0, 2.0]])
    B = np.ones((2, 2))
    code, pivots, restarts, buf = _core.games_front(A, B, 0)
    assert code == _core.GAMES_NOT_FINITE and pivots == 0 and buf.shape == (_games._layout(2, 2)["length"],)
    with pytest.raises(ValueError, match="non-finite"):
        lemke.solve_bimatrix(A, B)


@pytest.mark.parametrize("m, n", [(1, 1), (3, 2), (2, 5), (8, 8)])
def test_the_games_layout_is_the_cores(m, n):
    """_games reads the buffer by the core's LHLayout (_core.games_layout); the kernel writes
    there: x and y are the strategies (checked here in numpy), the regret and payoffs theirs,
    the labels each label once, the path state's pivots the result's."""
    at = _games._layout(m, n)
    assert tuple(at.values()) == _core.games_layout(m, n)
    assert (at["x"], at["y"], at["regret"], at["payoffs"]) == (0, m, m + n, m + n + 1)
    assert at["labels"] == at["trace_floats"] == m + n + 3
    assert at["state"] == at["labels"] + m + n
    assert at["length"] == at["state"] + _core.GAMES_STATE == at["state"] + 3 + _core.GAMES_HISTORY
    assert at["trace_labels"] == m + n + 2
    A, B = family("unif", m, n, 3)
    A, B = np.ascontiguousarray(A, dtype=float), np.ascontiguousarray(B, dtype=float)
    buf = np.full(at["length"], np.nan)
    code, pivots, restarts = _core.lemke_howson(A, B, 0, _games._slack_start(m, n),
                                                _games._DEFAULT_PARAMS, buf)
    assert code == 0
    x, y = buf[at["x"] : at["x"] + m], buf[at["y"] : at["y"] + n]
    assert abs(x.sum() - 1) < 1e-12 and abs(y.sum() - 1) < 1e-12 and x.min() >= 0 and y.min() >= 0
    assert buf[at["regret"]] == pytest.approx(regret(A, B, x, y), abs=1e-12)
    assert buf[at["payoffs"]] == pytest.approx(x @ A @ y, rel=1e-12)
    assert buf[at["payoffs"] + 1] == pytest.approx(x @ B @ y, rel=1e-12)
    ints = buf.view(np.int64)
    assert sorted(ints[at["labels"] : at["labels"] + m + n]) == list(range(m + n))
    assert ints[at["state"] + 2] == pivots


# --- a path that ends at a point failing the check -------------------------------------------

UNCHECKED_GAME = Path(__file__).parent / "data" / "games" / "unchecked_36x39.npz"


def test_a_path_ending_unchecked_goes_on_to_the_re_solve_and_the_exact_fallback():
    """The 36 x 39 game of tests/data/games/ (payoffs 0..2), dropping label 0: the float
    Lemke-Howson path ends with every label present at a point that fails the check (the
    kernel's UNCHECKED).  That code was once Status.TIME_LIMIT's number, and the front took
    it for a stop: TIME_LIMIT with no time limit, and no re-solve or exact fallback even with
    exact=True.  Now the answer is an equilibrium by this module's own checks (numpy
    regrets; exact fractions), or an honest failure; never a stop without a budget."""
    d = np.load(UNCHECKED_GAME)
    A, B, k = d["A"].astype(float), d["B"].astype(float), int(d["k"])
    m, n = A.shape
    buf = np.empty(_games._layout(m, n)["length"])
    code = _core.lemke_howson(A, B, k, _games._slack_start(m, n), _games._DEFAULT_PARAMS, buf)[0]
    assert code == _core.GAMES_UNCHECKED  # the case this test is for
    assert code not in {int(s) for s in lemke.Status}
    assert _games._status(code) == lemke.Status.NUMERICAL_FAILURE
    res = lemke.solve_bimatrix(A, B, init_label=k)
    assert res.status not in (lemke.Status.TIME_LIMIT, lemke.Status.INTERRUPTED), res
    assert res.status in (lemke.Status.SOLVED, lemke.Status.NUMERICAL_FAILURE), res
    if res.status == lemke.Status.SOLVED:
        assert_equilibrium(A, B, res)
    ex = lemke.solve_bimatrix(A, B, init_label=k, exact=True)
    assert_exact_equilibrium(d["A"].tolist(), d["B"].tolist(), ex)
    # the float path's own fallback (the exact method when the re-solve fails) gives the
    # same kind of answer through the options' path too
    assert lemke.solve_bimatrix(A, B, init_label=k, options=lemke.Options()).status == res.status


@pytest.mark.parametrize("m, n, article", [(2, 2, "a"), (8, 3, "an"), (11, 2, "an"), (18, 1, "an"),
                                            (1, 8, "a"), (80, 2, "an"), (100, 2, "a")])
def test_warm_start_size_message_reads_right(m, n, article):
    """'a GameBasis of a 2 x 2 game', 'of an 8 x 3 game': the article the number takes."""
    basis = lemke.GameBasis(1, 1, (1,), (0,))
    with pytest.raises(ValueError) as err:
        lemke.solve_bimatrix(np.ones((m, n)), np.ones((m, n)), warm_start=basis)
    assert f"must be a GameBasis of {article} {m} x {n} game" in str(err.value)
