"""Property tests: random problem families that always have a solution must always be solved,
and infeasible ones must end on a checked ray."""
import numpy as np
from helpers import assert_lcp_solution, assert_ray
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lemke
from lemke import Status, problems

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
seeds = st.integers(0, 2**32 - 1)
sizes = st.integers(1, 40)
scales = st.sampled_from([1e-6, 1.0, 1e6])


def check_solved(M, q):
    """Both methods solve it, and their answers pass the independent check."""
    for method in lemke.METHODS:
        res = lemke.solve_lcp(M, q, method=method)
        assert res.status == Status.SOLVED, (method, res, res.message)
        assert_lcp_solution(M, q, res.z)
    res = lemke.solve_lcp(M, q)
    assert res.status == Status.SOLVED, (res, res.message)
    assert_lcp_solution(M, q, res.z)
    return res


@SETTINGS
@given(seeds, sizes, scales)
def test_psd_plus_skew_always_solved(seed, n, scale):
    # Monotone LCPs with a feasible point are solvable; q = w0 - M z0 with z0, w0 >= 0
    # makes one, with zeros in z0 and w0 for degeneracy.
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, max(1, n // 2)))  # rank deficient
    B = rng.standard_normal((n, n))
    M = scale * (A @ A.T + B - B.T)
    z0 = np.maximum(rng.standard_normal(n), 0.0)
    w0 = np.maximum(rng.standard_normal(n), 0.0)
    check_solved(M, w0 - M @ z0)


@SETTINGS
@given(seeds, sizes)
def test_p_matrix_always_solved(seed, n):
    rng = np.random.default_rng(seed)
    M, q = problems.random_p_matrix(n, rng)
    check_solved(M, q)


@SETTINGS
@given(seeds, st.integers(2, 40), st.integers(1, 4))
def test_contact_like_always_solved(seed, n, bodies):
    rng = np.random.default_rng(seed)
    M, q = problems.contact_like(n, rng, bodies=bodies)
    check_solved(M, q)


@SETTINGS
@given(seeds, sizes)
def test_integer_data_with_many_ties(seed, n):
    # Small integers make exact ties in the ratio test common.
    rng = np.random.default_rng(seed)
    A = rng.integers(-1, 2, (n, n)).astype(float)
    M = A @ A.T
    q = rng.integers(-2, 2, n).astype(float)
    z0 = rng.integers(0, 2, n).astype(float)
    q = np.maximum(q, 0.0) - M @ z0  # feasible by construction: z0 with w = q+
    check_solved(M, q)


@SETTINGS
@given(seeds, sizes)
def test_infeasible_row_ends_on_a_checked_ray(seed, n):
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    i = int(rng.integers(n))
    M[i] = -np.abs(M[i])  # row i: M_i <= 0 and q_i < 0, so w_i < 0 for every z >= 0
    q = rng.standard_normal(n)
    q[i] = -abs(q[i]) - 0.1
    for method in lemke.METHODS:
        res = lemke.solve_lcp(M, q, method=method)
        assert res.status == Status.RAY_TERMINATION, (method, res)
        assert_ray(M, q, res.covering, res.z, res.z0, res.ray)


@SETTINGS
@given(seeds, st.integers(1, 25))
def test_permutation_gives_the_same_solution_for_p_matrices(seed, n):
    rng = np.random.default_rng(seed)
    M, q = problems.random_p_matrix(n, rng)
    p = rng.permutation(n)
    a = check_solved(M, q)
    b = check_solved(M[np.ix_(p, p)], q[p])
    np.testing.assert_allclose(b.z, a.z[p], rtol=1e-7, atol=1e-9 * max(1.0, np.abs(a.z).max()))
