"""Drake's LCP unit-test problems (tests/data/drake/cases.json), one test per case.

The numbers come from Drake's ``unrevised_lemke_solver_test.cc`` and
``moby_lcp_solver_test.cc`` (BSD-3-Clause); see tests/data/drake/README.md.
"""
import itertools
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

import lemke
from helpers import assert_lcp_solution, assert_ray

CASES = json.loads((Path(__file__).parent / "data" / "drake" / "cases.json").read_text())
BY_NAME = {case["name"]: case for case in CASES}


def _problem(case):
    n = case["n"]
    M = np.array(case["M"], dtype=float).reshape(n, n)  # row-major in the file
    q = np.array(case["q"], dtype=float)
    return M, q


def _is_solution(M, q, z):
    try:
        assert_lcp_solution(M, q, z)
    except AssertionError:
        return False
    return True


def _is_p_matrix(M):
    """All principal minors positive: then LCP(M, q) has exactly one solution for every q."""
    n = M.shape[0]
    for k in range(1, n + 1):
        idx = np.array(list(itertools.combinations(range(n), k)))
        minors = np.linalg.det(M[idx[:, :, None], idx[:, None, :]])
        if not np.all(minors > 0):
            return False
    return True


def _solution_is_unique(M, q, tol=1e-7):
    """Whether LCP(M, q) has exactly one solution, decided without the solver.

    A P-matrix settles it at once.  Otherwise (small n only) the solution set is the union
    over index sets a of the polyhedra {z_a >= 0, z_rest = 0, w_a = 0, w_rest >= 0}; the
    solution is unique when every non-empty piece is one and the same single point, which
    is checked by minimizing and maximizing each z_i over each piece with an LP.
    """
    n = q.size
    if _is_p_matrix(M):
        return True
    assert n <= 8, "piecewise uniqueness check is only meant for small problems"
    point = None
    for k in range(n + 1):
        for a in itertools.combinations(range(n), k):
            a = list(a)
            rest = [i for i in range(n) if i not in a]
            bounds = [(0, None) if i in a else (0, 0) for i in range(n)]
            A_eq, b_eq = (M[a], -q[a]) if a else (None, None)
            A_ub, b_ub = (-M[rest], q[rest]) if rest else (None, None)
            lo, hi = np.empty(n), np.empty(n)
            for i in range(n):
                for sign, out in ((1.0, lo), (-1.0, hi)):
                    c = np.zeros(n)
                    c[i] = sign
                    res = linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds)
                    if res.status == 2:  # empty piece
                        break
                    if res.status == 3:  # unbounded: a ray of solutions
                        return False
                    assert res.status == 0, res.message
                    out[i] = res.x[i]
                else:
                    continue
                break
            else:
                scale = max(1.0, np.abs(hi).max())
                if np.any(hi - lo > tol * scale):
                    return False
                if point is not None and np.abs(point - lo).max() > tol * scale:
                    return False
                point = lo
    return point is not None


def _is_feasible(M, q):
    """Whether {z >= 0, M z + q >= 0} is non-empty (an LP feasibility problem)."""
    res = linprog(np.zeros(q.size), A_ub=-M, b_ub=q, bounds=[(0, None)] * q.size)
    assert res.status in (0, 2), res.message
    return res.status == 0


@pytest.mark.parametrize("case", CASES, ids=[c["name"] for c in CASES])
def test_drake_case(case, method):
    M, q = _problem(case)
    n = case["n"]

    warm = None
    basis_still_solves = False
    if "warm_start_from" in case:
        # Drake solves the named case first on the same solver object; here the first
        # result's warm_start is passed explicitly.
        M1, q1 = _problem(BY_NAME[case["warm_start_from"]])
        first = lemke.solve_lcp(M1, q1, method=method)
        assert first.status == lemke.Status.SOLVED
        warm = first.warm_start
        # Does the old basis still give a solution of the new problem?  Then the warm
        # start must return it with 0 pivots (Drake counts that re-solve as 1 pivot; the
        # case's expected_num_pivots = 1 is Drake's convention, not ours).
        beta = list(warm.z_basic)
        z_old = np.zeros(n)
        try:
            if beta:
                z_old[beta] = np.linalg.solve(M[np.ix_(beta, beta)], -q[beta])
            basis_still_solves = _is_solution(M, q, z_old)
        except np.linalg.LinAlgError:  # singular M_bb: the old basis is no basis here
            basis_still_solves = False

    result = lemke.solve_lcp(M, q, warm_start=warm, method=method)

    if n == 0:
        assert result.status == lemke.Status.SOLVED
        assert result.z.shape == (0,)
        assert result.pivots == 0
        return

    if warm is not None:
        assert result.status == lemke.Status.SOLVED
        if basis_still_solves:
            assert result.pivots == 0
            np.testing.assert_allclose(result.z, z_old, rtol=1e-10, atol=1e-12)
    elif case.get("expected_num_pivots") == 0:
        assert result.pivots == 0

    if case["expect"] == "solution":
        assert result.status == lemke.Status.SOLVED, result.message
        assert_lcp_solution(M, q, result.z)
        expected = case.get("expected_z")
        if expected is None:
            expected = case.get("reference_z")
        # Compare with the peer's z only when the LCP has a single solution.  Cases with
        # several solutions (TestProblem2: (1,0), (0,1), (0.5,0.5), ...; TestPSD: every
        # (t, 1 + t) with t >= 0) are only checked to be solutions above: Drake pins one
        # of them, and any other is equally right.
        if expected is not None and _solution_is_unique(M, q):
            expected = np.array(expected, dtype=float)
            np.testing.assert_allclose(
                result.z, expected, rtol=1e-10, atol=1e-10 * max(1.0, np.abs(expected).max())
            )
    else:
        assert case["expect"] == "no_solution"
        # The data itself: a known solution must be one; without one the case is
        # Drake's *_TestFailure, which must be infeasible.
        if "known_solution" in case:
            assert_lcp_solution(M, q, np.array(case["known_solution"], dtype=float))
        else:
            assert not _is_feasible(M, q)
        if result.status == lemke.Status.SOLVED:
            # Finding (and verifying) a solution Drake's Lemke misses is no failure.
            assert_lcp_solution(M, q, result.z)
        else:
            # TestProblem4 (bimatrix game): Lemke with the covering vector of ones ends on
            # a ray at once although a solution exists; TestFailure is infeasible.
            assert result.status == lemke.Status.RAY_TERMINATION, result.message
            assert_ray(M, q, result.covering, result.z, result.z0, result.ray)
