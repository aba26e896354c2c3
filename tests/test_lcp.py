"""The LCP solver on literature problems, degenerate cases, limits and its contract."""
import numpy as np
import pytest
from helpers import assert_lcp_solution, assert_ray

import lemke
from lemke import Status, problems


def solve_ok(M, q, **kw):
    M, q = np.asarray(M, float), np.asarray(q, float)
    res = lemke.solve_lcp(M, q, **kw)
    assert res.status == Status.SOLVED, res.message
    assert res.success
    assert_lcp_solution(M, q, res.z)
    w = np.asarray(M, float) @ res.z + np.asarray(q, float)
    scale = np.abs(q).max() + np.abs(M).max() * np.abs(res.z).max()
    np.testing.assert_allclose(res.w, w, rtol=1e-12, atol=1e-13 * scale)
    return res


def test_cps_447_running_example(method):
    p = problems.cps_447()
    res = solve_ok(p.M, p.q, method=method)
    np.testing.assert_allclose(res.z, [0.0, 1.0, 3.0], atol=1e-12)
    assert res.residual <= 1e-12


@pytest.mark.parametrize("n", range(3, 11))
def test_murty_takes_2_to_the_n_pivots(n, method):
    # Convention: every pivot counts, the first (z0 enters) and the last (z0 leaves).
    p = problems.murty(n)
    res = solve_ok(p.M, p.q, method=method)
    assert res.pivots == 2**n
    expected = np.zeros(n)
    expected[-1] = 2.0**n
    np.testing.assert_allclose(res.z, expected, atol=1e-9)


def test_murty_file_size_6_matches_generator():
    p = problems.murty(6)
    assert p.q.tolist() == [-126.0, -124.0, -120.0, -112.0, -96.0, -64.0]


def test_degenerate_example_from_the_issue(method):
    # The argmin ratio test ends on a false ray here; the solution is z = (0, 0.5).
    p = problems.degenerate()
    res = solve_ok(p.M, p.q, method=method)
    np.testing.assert_allclose(res.z, [0.0, 0.5], atol=1e-12)


@pytest.mark.parametrize(
    "M, q",
    [
        # repeated rows and a zero in q
        ([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [-1.0, -1.0, 0.0]),
        # all q equal: a 3-way tie on the first ratio test, cycles with lowest-index ties
        ([[1.0, 2.0, 0.0], [0.0, 1.0, 2.0], [2.0, 0.0, 1.0]], [-1.0, -1.0, -1.0]),
        # PSD with the artificial variable tied with an ordinary one (CPS 4.4.16)
        ([[1.0, -1.0], [-1.0, 1.0]], [1.0, -1.0]),
        # zero matrix block and zeros in q
        ([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [-1.0, -1.0, 0.0]], [0.0, -1.0, 2.0]),
        # four identical rows (redundant contacts)
        (np.ones((4, 4)), -np.ones(4)),
        # rank one, many ties
        (np.outer([1.0, 2.0, 1.0, 2.0], [1.0, 2.0, 1.0, 2.0]), [-1.0, -2.0, -1.0, -2.0]),
    ],
    ids=["repeated-rows", "cycling", "artificial-tie", "zero-block", "identical-rows", "rank-one"],
)
def test_degenerate_problems(M, q, method):
    solve_ok(M, q, method=method)


def test_q_nonnegative_is_answered_at_once(method):
    M = np.array([[1.0, 2.0], [3.0, -4.0]])
    res = solve_ok(M, [0.0, 2.0], method=method)
    assert res.pivots == 0 and np.all(res.z == 0)


def test_empty_problem(method):
    res = lemke.solve_lcp(np.zeros((0, 0)), np.zeros(0), method=method)
    assert res.status == Status.SOLVED and res.z.shape == (0,) and res.pivots == 0


def test_pivot_cap(method):
    p = problems.murty(10)
    res = lemke.solve_lcp(p.M, p.q, method=method, options={"max_pivots": 100})
    assert res.status == Status.MAX_PIVOTS and res.pivots == 100 and not res.success
    assert lemke.solve_lcp(p.M, p.q, options=lemke.Options(max_pivots=0)).pivots == 0
    assert lemke.Options().pivot_limit(10) == 1100


def test_covering_vector(method):
    rng = np.random.default_rng(3)
    M, q = problems.random_p_matrix(8, rng)
    ref = solve_ok(M, q, method=method)
    for d in (np.arange(1.0, 9.0), rng.uniform(0.01, 100.0, 8)):
        res = solve_ok(M, q, d=d, method=method)
        np.testing.assert_allclose(res.z, ref.z, atol=1e-9)  # P-matrix: unique solution
        assert np.array_equal(res.covering, d)


@pytest.mark.parametrize(
    "M, q",
    [
        ([[-1.0]], [-1.0]),  # -z - 1 >= 0 is impossible
        ([[0.0, 0.0], [1.0, 1.0]], [-1.0, 1.0]),  # row 0: 0 z - 1 >= 0
        ([[-1.0, -2.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]], [-1.0, 2.0, -3.0]),
    ],
)
def test_infeasible_problems_end_on_a_checked_ray(M, q, method):
    res = lemke.solve_lcp(M, q, method=method)
    assert res.status == Status.RAY_TERMINATION and not res.success
    assert res.ray is not None and res.ray.shape == (len(q) + 1,)
    assert_ray(M, q, res.covering, res.z, res.z0, res.ray)
    assert lemke.is_lcp_ray(M, q, res.covering, res.z, res.z0, res.ray)


@pytest.mark.parametrize("dz", [0.0, 1e-17], ids=["zero", "rounding"])
def test_the_primary_ray_is_no_certificate(dz):
    # (z, z0) = (0, 1) + t (dz, 1) with dz = 0 is the primary ray of LCP(1, -1): every LCP
    # has one, and it proves nothing (z = 1 solves this one).  A dz that is rounding next to
    # dz0 is the same ray.
    M, q, d = np.array([[1.0]]), np.array([-1.0]), np.ones(1)
    assert not lemke.is_lcp_ray(M, q, d, np.zeros(1), 1.0, np.array([dz, 1.0]))
    with pytest.raises(AssertionError, match="primary ray"):
        assert_ray(M, q, d, np.zeros(1), 1.0, np.array([dz, 1.0]))


def test_a_ray_with_z0_rounding_where_it_moves_is_no_certificate():
    # z = (1, 0) solves LCP(M, q); (z, z0) + t e_2 with z0 = 5e-16 satisfies every
    # condition of a ray within rounding, but in the row the ray moves w_2 = 0 (u_2 = z0 is
    # read as zero there): z0 is rounding where the infeasibility proof needs it.  On two
    # contact steps (issue 11) such a ray was accepted on problems with solutions.
    M, q, d = np.array([[1.0, 0.0], [0.0, 0.0]]), np.array([-1.0, 0.0]), np.ones(2)
    z, z0, ray = np.array([1.0, 0.0]), 5e-16, np.array([0.0, 1.0, 0.0])
    assert lemke.is_lcp_solution(M, q, z)
    assert not lemke.is_lcp_ray(M, q, d, z, z0, ray)
    with pytest.raises(AssertionError, match="z0 is rounding"):
        assert_ray(M, q, d, z, z0, ray)


def test_a_ray_in_a_zero_column_is_a_certificate():
    # LCP(0, -1) has no feasible point; z grows along the ray with w = -1 + z0 fixed.
    M, q, d = np.array([[0.0]]), np.array([-1.0]), np.ones(1)
    assert lemke.is_lcp_ray(M, q, d, np.zeros(1), 1.0, np.array([1.0, 0.0]))
    assert_ray(M, q, d, np.zeros(1), 1.0, np.array([1.0, 0.0]))


def test_psd_ray_is_a_farkas_certificate(method):
    # For PSD M a secondary ray proves infeasibility: y = dz >= 0 with M'y <= 0, q'y < 0.
    M = np.array([[1.0, -1.0], [-1.0, 1.0]])
    q = np.array([-1.0, -1.0])  # z1 - z2 >= 1 and z2 - z1 >= 1 cannot both hold
    res = lemke.solve_lcp(M, q, method=method)
    assert res.status == Status.RAY_TERMINATION
    y = res.ray[:2]
    assert np.all(y >= 0) and np.all(M.T @ y <= 1e-12) and q @ y < 0


def test_sparse_matrix_accepted():
    sp = pytest.importorskip("scipy.sparse")
    p = problems.cps_447()
    res = lemke.solve_lcp(sp.csr_matrix(p.M), p.q)
    assert res.success
    assert_lcp_solution(p.M, p.q, res.z)
    np.testing.assert_allclose(res.z, [0.0, 1.0, 3.0], atol=1e-12)


def test_integer_and_list_input():
    res = solve_ok([[2, 1], [1, 2]], [-5, -6])
    np.testing.assert_allclose(res.z, [4.0 / 3.0, 7.0 / 3.0])


def test_callers_arrays_are_not_modified(method):
    p = problems.murty(5)
    M, q, d = p.M.copy(), p.q.copy(), np.full(5, 2.0)
    for a in (M, q, d):
        a.setflags(write=False)  # any write would raise
    res = lemke.solve_lcp(M, q, d=d, method=method)
    assert res.success
    assert np.array_equal(M, p.M) and np.array_equal(q, p.q) and np.all(d == 2.0)


def test_result_is_immutable():
    p = problems.degenerate()
    res = lemke.solve_lcp(p.M, p.q)
    with pytest.raises(AttributeError):
        res.status = Status.MAX_PIVOTS
    with pytest.raises(ValueError):
        res.z[0] = 1.0


@pytest.mark.parametrize(
    "M, q, kw, exc, words",
    [
        (np.ones((2, 3)), np.ones(2), {}, ValueError, "square"),
        (np.ones(3), np.ones(3), {}, ValueError, "square"),
        (np.eye(2), np.ones(3), {}, ValueError, "shape (2,)"),
        (np.eye(2), np.ones((2, 1)), {}, ValueError, "shape (2,)"),
        ([[1.0, np.nan], [0.0, 1.0]], [1.0, 1.0], {}, ValueError, "NaN"),
        (np.eye(2), [1.0, np.inf], {}, ValueError, "q has a NaN or infinite"),
        ([["a", "b"], ["c", "d"]], [1.0, 1.0], {}, TypeError, "real numbers"),
        (np.eye(2), [1 + 2j, 0], {}, TypeError, "real numbers"),
        ([[1.0, 2.0], [3.0]], [1.0, 1.0], {}, TypeError, "numeric"),
        (np.eye(2), [-1.0, 1.0], {"d": [1.0, 0.0]}, ValueError, "positive"),
        (np.eye(2), [-1.0, 1.0], {"d": [1.0, -2.0]}, ValueError, "positive"),
        (np.eye(2), [-1.0, 1.0], {"method": "magic"}, ValueError, "unknown method"),
        (np.eye(2), [-1.0, 1.0], {"options": {"max_pivots": -1}}, ValueError, "max_pivots"),
        (np.eye(2), [-1.0, 1.0], {"options": {"maxpivots": 3}}, ValueError, "unknown option"),
        (np.eye(2), [-1.0, 1.0], {"options": {"tol": "small"}}, TypeError, "tol"),
        (np.eye(2), [-1.0, 1.0], {"options": 3}, TypeError, "options"),
        (np.eye(2), [-1.0, 1.0], {"warm_start": "basis"}, TypeError, "warm_start"),
        (np.eye(2), [-1.0, 1.0], {"warm_start": lemke.WarmStart(3, (0,))}, ValueError, "size 3"),
    ],
)
def test_bad_input_is_named(M, q, kw, exc, words):
    with pytest.raises(exc) as info:
        lemke.solve_lcp(M, q, **kw)
    assert words in str(info.value)


def test_status_messages():
    assert [int(s) for s in Status] == [0, 1, 2, 3, 4, 5, 6, 7, 8]
    for s in Status:
        assert len(s.message) > 40


def test_kernel_answer_is_rechecked(monkeypatch):
    """A kernel that claims success with a wrong point must not give SOLVED."""
    from lemke import _core, _lcp, _layout

    def with_solve(solve):
        """The core's solve_one (and first_run) as the front calls it, with its pivoting
        replaced by ``solve`` (the same check of the point, lcp_check)."""
        def solve_one(method, M, q, d, beta, k, max_pivots, pivot_tol, tie_tol, tol, buf, basic):
            n = q.shape[0]
            f = _layout.fields(n)
            buf[f["covering"]] = 1.0
            _core.equilibrate(M, q, buf[f["row_scale"]], buf[f["col_scale"]])
            x, ray, w = buf[:n + 1], buf[f["ray"]], buf[f["w"]]
            z_basic = np.empty(n, dtype=np.bool_)
            code, pivots = solve(x, ray, z_basic)
            ok, residual = _core.lcp_check(M, q, np.ascontiguousarray(x[:n]), tol, w)
            if basic is None or basic.size == 0:  # solve_lcp's one buffer, after the fields
                basic = buf[_layout.buffer_length(n):].view(np.int64)
            basic_z = np.flatnonzero(z_basic)
            basic[: basic_z.size] = basic_z
            return code, pivots, basic_z.size, ok, residual, 0, 2
        return solve_one

    def lying_kernel(x, ray, z_basic):
        x[:] = 1.0
        x[-1] = 0.0
        z_basic[:] = False  # all w basic: the basis point is z = 0, wrong too
        return 0, 7

    monkeypatch.setattr(_lcp, "_FRONT", lambda M, q, ws, beta: None)  # (the native front: its own kernel)
    monkeypatch.setattr(_lcp, "_SOLVE_ONE", with_solve(lying_kernel))
    monkeypatch.setattr(_lcp, "_FIRST_RUN", with_solve(lying_kernel))
    p = problems.cps_447()
    res = lemke.solve_lcp(p.M, p.q)
    assert res.status == Status.NUMERICAL_FAILURE and not res.success

    def lying_ray(x, ray, z_basic):
        x[:] = 0.0
        ray[:] = 0.0
        ray[0] = 1.0  # w = Mz + q decreases along this direction
        z_basic[:] = False
        return 2, 3

    monkeypatch.setattr(_lcp, "_SOLVE_ONE", with_solve(lying_ray))
    monkeypatch.setattr(_lcp, "_FIRST_RUN", with_solve(lying_ray))
    res = lemke.solve_lcp(p.M, p.q)
    assert res.status == Status.NUMERICAL_FAILURE and res.ray is None


def test_scale_invariance(method):
    rng = np.random.default_rng(11)
    M, q = problems.contact_like(12, rng)
    ref = solve_ok(M, q, method=method)
    for c in (1e-8, 1e-3, 1e4, 1e9):
        res = solve_ok(c * M, c * q, method=method)
        assert res.pivots == ref.pivots
        np.testing.assert_allclose(res.z, ref.z, rtol=1e-9, atol=1e-12 * np.abs(ref.z).max())


def test_tiny_data_is_not_declared_solved_by_absolute_tolerance(method):
    # With data of size 1e-12, z = 0 leaves w = q < 0: a bare absolute tolerance would pass it.
    M = 1e-12 * np.eye(3)
    q = -1e-12 * np.ones(3)
    assert not lemke.is_lcp_solution(M, q, np.zeros(3))
    res = solve_ok(M, q, method=method)
    np.testing.assert_allclose(res.z, np.ones(3))


def test_methods_agree(method):
    """Same z on problems with a unique solution, same pivots on nondegenerate ones."""
    rng = np.random.default_rng(21)
    for n in (1, 2, 5, 17, 40, 90):
        M, q = problems.random_p_matrix(n, rng)
        a = solve_ok(M, q, method="tableau")
        b = solve_ok(M, q, method=method)
        assert a.pivots == b.pivots
        np.testing.assert_allclose(b.z, a.z, rtol=1e-8, atol=1e-10 * max(1.0, np.abs(a.z).max()))
        assert a.warm_start == b.warm_start


def test_a_point_too_large_to_certify_is_no_solution():
    """z ~ 1e16 on data ~ 1 (what a pivot on rounding noise produces): the allowance for
    rounding in M z grows with |z| and would pass it, so such a z is never accepted."""
    M = np.array([[1.0, -1.0], [-1.0, 1.0]])
    q = np.array([-1.0, 1.0])
    z = np.array([1e16, 1e16])  # w = Mz + q = (-1, 1): not a solution
    assert not lemke.is_lcp_solution(M, q, z)
    assert lemke.is_lcp_solution(M, q, np.array([1.0, 0.0]))
    assert lemke.is_lcp_solution(1e-8 * M, 1e-8 * q, np.array([1.0, 0.0]))  # scale-free
