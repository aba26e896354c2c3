"""Tests of lemke.pivot_column: q' and one column of M' after a principal pivoting transform.

The reference values come from the Dai-Drumwright note (Drake documentation) and from the
pivot-step checks of Drake's unrevised Lemke solver tests (tests/data/drake/pivot_steps.json).
Everything is also compared with a brute-force transform that inverts the whole basis matrix.
"""
import doctest
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import lemke
from lemke import _pivot_column

DATA = Path(__file__).parent / "data" / "drake" / "pivot_steps.json"

# Cottle-Pang-Stone Example 4.4.7 with the covering vector of ones appended.
CPS_M = np.array([[0.0, -1.0, 2.0, 1.0], [2.0, 0.0, -2.0, 1.0], [-1.0, 1.0, 0.0, 1.0]])
CPS_Q = np.array([-3.0, 6.0, -1.0])
CPS_BASIC = ["z4", "w2", "z3"]
CPS_NONBASIC = ["w1", "w3", "z2", "z1"]


def brute_force(M, q, basic, nonbasic, driving):
    """q' and the driving column of M' from the full system [I | -M] (w, z) = q.

    With B the columns of the basic variables, x_B = B^{-1} q - B^{-1} N x_N, so
    q' = B^{-1} q and d x_B / d x_driving = -B^{-1} a_driving.
    """
    M = np.asarray(M, dtype=float)
    n = M.shape[0]
    A = np.hstack([np.eye(n), -M])

    def col(label):
        i = int(label[1:]) - 1
        return i if label[0] == "w" else n + i

    B = A[:, [col(v) for v in basic]]
    q_prime = np.linalg.solve(B, q)
    column = -np.linalg.solve(B, A[:, col(driving)])
    return q_prime, column


def to_one_based(label):
    """Drake's 0-based labels ('z0', 'w2') to this API's 1-based ones ('z1', 'w3')."""
    return f"{label[0]}{int(label[1:]) + 1}"


# --------------------------------------------------------------------------- running example


# Driving column for each of the four non-basic variables, in the order (z4, w2, z3), worked
# out by hand from eqs. 5-8 with M^(alpha beta) = [[2, 1], [0, 1]], M^(alpha-bar beta) = [-2, 1].
CPS_COLUMNS = {
    "w1": [0.0, -1.0, 0.5],
    "w3": [1.0, 2.0, -0.5],
    "z2": [-1.0, -3.0, 1.0],
    "z1": [1.0, 4.0, -0.5],
}


@pytest.mark.parametrize("driving", CPS_NONBASIC)
def test_running_example(driving):
    q_prime, column = lemke.pivot_column(CPS_M, CPS_Q, CPS_BASIC, CPS_NONBASIC, driving)
    # The note prints q' = (1, 5, 1): q'^(beta') = (1, 1) for (z3, z4) and q'^(alpha-bar') = 5.
    np.testing.assert_array_equal(q_prime, [1.0, 5.0, 1.0])
    np.testing.assert_allclose(column, CPS_COLUMNS[driving], rtol=0, atol=1e-15)
    bq, bc = brute_force(CPS_M, CPS_Q, CPS_BASIC, CPS_NONBASIC, driving)
    np.testing.assert_allclose(q_prime, bq, rtol=0, atol=1e-14)
    np.testing.assert_allclose(column, bc, rtol=0, atol=1e-14)
    assert q_prime.dtype == np.float64 and column.dtype == np.float64


def test_running_example_index_sets():
    """The note's index sets for the running example (it prints them 1-based)."""
    s = _pivot_column._index_sets(3, CPS_BASIC, CPS_NONBASIC)
    assert list(s.alpha + 1) == [1, 3]
    assert list(s.alpha_prime + 1) == [1, 2]
    assert list(s.beta + 1) == [3, 4]
    assert list(s.beta_prime + 1) == [3, 1]
    assert list(s.alpha_bar + 1) == [2]
    assert list(s.alpha_bar_prime + 1) == [2]
    assert list(s.beta_bar + 1) == [1, 2]
    assert list(s.beta_bar_prime + 1) == [4, 3]
    # The blocks the note prints.
    np.testing.assert_array_equal(CPS_M[np.ix_(s.alpha, s.beta)], [[2, 1], [0, 1]])
    np.testing.assert_array_equal(CPS_M[np.ix_(s.alpha_bar, s.beta)], [[-2, 1]])
    np.testing.assert_array_equal(CPS_Q[s.alpha], [-3, -1])
    np.testing.assert_array_equal(CPS_Q[s.alpha_bar], [6])
    # g for driving z2 (the note's second tableau, which has the correct +1 in row w3).
    np.testing.assert_array_equal(CPS_M[s.alpha, 1], [-1, 1])
    np.testing.assert_array_equal(CPS_M[s.alpha_bar, 1], [0])


def test_running_example_first_tableau_typo_matters():
    """The note's first tableau prints M[w3, z2] = -1; the column for z2 depends on it."""
    M_typo = CPS_M.copy()
    M_typo[2, 1] = -1.0
    _, column = lemke.pivot_column(M_typo, CPS_Q, CPS_BASIC, CPS_NONBASIC, "z2")
    assert not np.allclose(column, CPS_COLUMNS["z2"])
    np.testing.assert_allclose(column, brute_force(M_typo, CPS_Q, CPS_BASIC, CPS_NONBASIC, "z2")[1], atol=1e-14)


def test_docstring_example_runs():
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(lemke.pivot_column, "pivot_column", globs={})
    assert tests and tests[0].examples
    for t in tests:
        runner.run(t)
    assert runner.failures == 0


# --------------------------------------------------------------------------- Drake step checks


def _drake():
    with open(DATA) as f:
        return json.load(f)


def _augmented(data):
    M = np.array(data["M"], dtype=float)
    return np.hstack([M, np.ones((M.shape[0], 1))]), np.array(data["q"], dtype=float)


@pytest.mark.parametrize("step", range(len(_drake()["lemke_pivot"])))
def test_drake_pivot_steps(step):
    data = _drake()
    M, q = _augmented(data)
    case = data["lemke_pivot"][step]
    basic = [to_one_based(v) for v in case["dependent"]]
    nonbasic = [to_one_based(v) for v in case["independent"]]
    driving = to_one_based(case["driving"])
    q_prime, column = lemke.pivot_column(M, q, basic, nonbasic, driving)
    # Asserted values and the corrected (unchecked in Drake) ones alike.
    np.testing.assert_allclose(q_prime, case["q_prime"], rtol=0, atol=1e-14)
    if case["M_prime_driving"] is not None:
        np.testing.assert_allclose(column, case["M_prime_driving"], rtol=0, atol=1e-14)
    bq, bc = brute_force(M, q, basic, nonbasic, driving)
    np.testing.assert_allclose(q_prime, bq, rtol=0, atol=1e-13)
    np.testing.assert_allclose(column, bc, rtol=0, atol=1e-13)


def test_drake_final_step_gives_the_solution():
    """On the last step's complementary basis, q' holds z = (0, 1, 3) (asserted by Drake)."""
    data = _drake()
    M, q = _augmented(data)
    case = data["lemke_pivot"][2]
    basic = [to_one_based(v) for v in case["dependent"]]
    nonbasic = [to_one_based(v) for v in case["independent"]]
    q_prime, _ = lemke.pivot_column(M, q, basic, nonbasic, "z4")
    z = np.zeros(3)
    for label, value in zip(basic, q_prime):
        if label[0] == "z":
            z[int(label[1:]) - 1] = value
    np.testing.assert_allclose(z, [0.0, 1.0, 3.0], atol=1e-14)


def test_drake_index_sets():
    data = _drake()
    case = data["determine_index_sets"]
    basic = [to_one_based(v) for v in case["dependent"]]
    nonbasic = [to_one_based(v) for v in case["independent"]]
    s = _pivot_column._index_sets(len(data["q"]), basic, nonbasic)
    for name in ("alpha", "alpha_prime", "beta", "beta_prime", "alpha_bar", "alpha_bar_prime", "beta_bar", "beta_bar_prime"):
        assert list(getattr(s, name)) == case[name], name


# --------------------------------------------------------------------------- random partitions


def random_lemke_basis(rng, n):
    """A random complementary or almost-complementary basis, in random order."""
    almost = bool(rng.integers(2))
    basic, nonbasic = [], []
    both_out = int(rng.integers(n)) if almost else -1
    for i in range(1, n + 1):
        if i - 1 == both_out:
            nonbasic += [f"w{i}", f"z{i}"]
        elif rng.integers(2):
            basic.append(f"w{i}")
            nonbasic.append(f"z{i}")
        else:
            basic.append(f"z{i}")
            nonbasic.append(f"w{i}")
    (basic if almost else nonbasic).append(f"z{n + 1}")
    basic = [basic[k] for k in rng.permutation(len(basic))]
    nonbasic = [nonbasic[k] for k in rng.permutation(len(nonbasic))]
    return basic, nonbasic


def random_problem(rng, n):
    kind = rng.integers(3)
    if kind == 0:
        M = rng.standard_normal((n, n))
    elif kind == 1:
        M = rng.integers(-5, 6, size=(n, n)).astype(float)
    else:
        M = rng.standard_normal((n, n)) * 10.0 ** rng.uniform(-3, 3)
    d = np.ones(n) if rng.integers(2) else rng.uniform(0.1, 10.0, size=n)
    q = rng.standard_normal(n) * 10.0 ** rng.uniform(-2, 2)
    return np.hstack([M, d[:, None]]), q


def basis_condition(M, basic):
    """Condition number of the basis matrix B (columns of [I | -M] for the basic variables)."""
    n = M.shape[0]
    A = np.hstack([np.eye(n), -M])
    return np.linalg.cond(A[:, [int(v[1:]) - 1 + (0 if v[0] == "w" else n) for v in basic]])


def check_against_brute_force(M, q, basic, nonbasic, drivings, cond):
    tol = 1e-13 * cond  # observed errors stay below 3e-16 * cond
    for driving in drivings:
        q_prime, column = lemke.pivot_column(M, q, basic, nonbasic, driving)
        bq, bc = brute_force(M, q, basic, nonbasic, driving)
        np.testing.assert_allclose(q_prime, bq, rtol=tol, atol=tol * max(1.0, np.abs(bq).max()))
        np.testing.assert_allclose(column, bc, rtol=tol, atol=tol * max(1.0, np.abs(bc).max()))


def test_random_partitions_against_brute_force():
    rng = np.random.default_rng(20240603)
    done = 0
    while done < 400:
        n = int(rng.integers(1, 9))
        M, q = random_problem(rng, n)
        basic, nonbasic = random_lemke_basis(rng, n)
        cond = basis_condition(M, basic)
        if cond > 1e8:
            continue
        check_against_brute_force(M, q, basic, nonbasic, nonbasic, cond)
        done += 1


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 8))
def test_random_partitions_hypothesis(seed, n):
    rng = np.random.default_rng(seed)
    M, q = random_problem(rng, n)
    basic, nonbasic = random_lemke_basis(rng, n)
    cond = basis_condition(M, basic)
    if cond > 1e8:
        return
    driving = nonbasic[int(rng.integers(len(nonbasic)))]
    check_against_brute_force(M, q, basic, nonbasic, [driving], cond)


def test_initial_basis_needs_no_solve():
    """All w basic (m = 0): q' = q and the column of z_j is M[:, j]."""
    rng = np.random.default_rng(1)
    M, q = random_problem(rng, 4)
    basic = ["w3", "w1", "w4", "w2"]
    nonbasic = ["z1", "z2", "z3", "z4", "z5"]
    for j, driving in enumerate(nonbasic):
        q_prime, column = lemke.pivot_column(M, q, basic, nonbasic, driving)
        np.testing.assert_array_equal(q_prime, q[[2, 0, 3, 1]])
        np.testing.assert_array_equal(column, M[[2, 0, 3, 1], j])


def test_empty_problem():
    q_prime, column = lemke.pivot_column(np.zeros((0, 1)), np.zeros(0), [], ["z1"], "z1")
    assert q_prime.shape == (0,) and column.shape == (0,)


def test_accepts_lists_tuples_arrays_and_does_not_modify_input():
    M = CPS_M.copy()
    q = CPS_Q.copy()
    expected = lemke.pivot_column(M, q, CPS_BASIC, CPS_NONBASIC, "z1")
    for args in [
        (M.tolist(), q.tolist(), tuple(CPS_BASIC), tuple(CPS_NONBASIC), "z1"),
        (M.astype(int), q.astype(int), np.array(CPS_BASIC), np.array(CPS_NONBASIC), np.str_("z1")),
        (M, q, iter(CPS_BASIC), (v for v in CPS_NONBASIC), "z1"),
    ]:
        got = lemke.pivot_column(*args)
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_array_equal(got[1], expected[1])
    np.testing.assert_array_equal(M, CPS_M)
    np.testing.assert_array_equal(q, CPS_Q)


# --------------------------------------------------------------------------- errors


def call(basic=CPS_BASIC, nonbasic=CPS_NONBASIC, driving="z1", M=CPS_M, q=CPS_Q):
    return lemke.pivot_column(M, q, basic, nonbasic, driving)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        # counts
        ({"basic": ["z4", "w2"], "nonbasic": ["w1", "w3", "z2", "z1", "z3"]}, "basic must list n = 3"),
        ({"nonbasic": ["w1", "w3", "z2"]}, "nonbasic must list n \\+ 1 = 4"),
        # duplicates and overlap
        ({"basic": ["z4", "w2", "w2"], "nonbasic": ["w1", "w3", "z2", "z1"]}, "w2 appears more than once in basic"),
        ({"nonbasic": ["w1", "w1", "z2", "z1"]}, "w1 appears more than once in nonbasic"),
        ({"nonbasic": ["w1", "w3", "z3", "z1"]}, "z3 appears in both basic and nonbasic"),
        # a complementary pair both basic
        ({"basic": ["z4", "w2", "z2"], "nonbasic": ["w1", "w3", "z3", "z1"], "driving": "z1"}, "w2 and z2 are both basic"),
        ({"basic": ["w1", "w2", "z2"], "nonbasic": ["w3", "z1", "z3", "z4"], "driving": "z1"}, "w2 and z2 are both basic"),
        # malformed labels
        ({"basic": ["z4", "W2", "z3"]}, "basic\\[1\\] = 'W2' is not a variable label"),
        ({"basic": ["z4", "w02", "z3"]}, "is not a variable label"),
        ({"basic": ["z4", "w 2", "z3"]}, "is not a variable label"),
        ({"basic": ["z4", "x2", "z3"]}, "is not a variable label"),
        ({"basic": ["z4", 2, "z3"]}, "is not a variable label"),
        ({"nonbasic": ["w1", "w3", "z2", "z0"]}, "'z0' is not a variable label.*1-based"),
        ({"nonbasic": ["w1", "w3", "z2", "z5"]}, "'z5' is out of range"),
        ({"basic": ["z4", "w4", "z3"]}, "'w4' is out of range"),
        ({"basic": "z4w2z3"}, "not the single string"),
        ({"basic": None}, "must be a sequence of labels"),
        # driving
        ({"driving": "z3"}, "driving = 'z3' is not one of the non-basic variables"),
        ({"driving": "z9"}, "is not one of the non-basic"),
        ({"driving": 1}, "is not one of the non-basic"),
        ({"nonbasic": np.array(CPS_NONBASIC), "driving": "w2"}, "variables \\['w1', 'w3', 'z2', 'z1'\\]"),
        # shapes and values
        ({"M": CPS_M[:, :3]}, "M must be n x \\(n \\+ 1\\)"),
        ({"M": CPS_M.ravel()}, "M must be n x \\(n \\+ 1\\)"),
        ({"M": CPS_M.T}, "M must be n x \\(n \\+ 1\\)"),
        ({"q": CPS_Q[:2]}, "q must have shape \\(3,\\)"),
        ({"q": CPS_Q[:, None]}, "q must have shape \\(3,\\)"),
        ({"M": np.where(np.eye(3, 4) > 0, np.nan, CPS_M)}, "M has a NaN or infinite entry"),
        ({"q": np.array([-3.0, np.inf, -1.0])}, "q has a NaN or infinite entry"),
    ],
)
def test_value_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        call(**kwargs)


def test_non_numeric_data_is_a_type_error():
    with pytest.raises(TypeError, match="M must hold real numbers"):
        call(M=np.array([["a"] * 4] * 3))


def test_singular_block_raises_linalg_error():
    # z1 basic in place of w1: M^(alpha beta) = [M[w1, z1]] = [0] is singular.
    basic = ["w3", "z1", "w2"]
    nonbasic = ["z4", "w1", "z2", "z3"]
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        call(basic=basic, nonbasic=nonbasic, driving="z2")
    # LinAlgError is a ValueError, so a caller may catch either.
    with pytest.raises(ValueError, match="singular"):
        call(basic=basic, nonbasic=nonbasic, driving="w1")
    # A 2 x 2 singular block, with the artificial variable basic.
    M = CPS_M.copy()
    M[2, 0] = 0.0  # rows (w1, w3), columns (z1, z4): [[0, 1], [0, 1]]
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        lemke.pivot_column(M, CPS_Q, ["z4", "w2", "z1"], ["w1", "w3", "z2", "z3"], "z2")


def test_nearly_singular_block_raises_linalg_error():
    M = CPS_M.copy()
    M[2, 0] = 1e-18  # the block [[0, 1], [1e-18, 1]] is singular to working precision
    with pytest.raises(np.linalg.LinAlgError, match="working precision"):
        lemke.pivot_column(M, CPS_Q, ["z4", "w2", "z1"], ["w1", "w3", "z2", "z3"], "z2")
