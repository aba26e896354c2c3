"""Warm starts in the tableau method: the final basis handed back."""
import pickle

import numpy as np
import pytest
from helpers import assert_lcp_solution

import lemke
from lemke import problems


def test_same_basis_still_solves_gives_zero_pivots():
    rng = np.random.default_rng(5)
    M, q = problems.random_p_matrix(30, rng)
    cold = lemke.solve_lcp(M, q)
    assert cold.success and cold.pivots > 0
    warm = lemke.solve_lcp(M, q + 1e-9 * np.abs(q).max(), warm_start=cold.warm_start)
    assert warm.success and warm.pivots == 0
    assert_lcp_solution(M, q + 1e-9 * np.abs(q).max(), warm.z)


def test_stale_basis_falls_back_and_is_right():
    rng = np.random.default_rng(6)
    M, q = problems.random_psd(20, rng)
    cold = lemke.solve_lcp(M, q)
    other_q = rng.standard_normal(20)
    res = lemke.solve_lcp(M, other_q, warm_start=cold.warm_start)
    assert res.success
    assert_lcp_solution(M, other_q, res.z)


def test_warm_start_from_unrelated_singular_problem():
    ws = lemke.WarmStart(3, (0, 1, 2))
    M = np.zeros((3, 3))  # M_bb singular
    res = lemke.solve_lcp(M, [1.0, 2.0, 0.0], warm_start=ws)
    assert res.success and res.pivots == 0


def test_warm_start_is_a_plain_value():
    p = problems.cps_447()
    ws = lemke.solve_lcp(p.M, p.q).warm_start
    assert ws == pickle.loads(pickle.dumps(ws)) and hash(ws) == hash(lemke.WarmStart(3, ws.z_basic))
    assert ws.z_basic == (1, 2)
    with pytest.raises(AttributeError):
        ws.n = 4
    with pytest.raises(ValueError):
        lemke.WarmStart(3, (0, 3))
    with pytest.raises(ValueError):
        lemke.WarmStart(3, (1, 1))
