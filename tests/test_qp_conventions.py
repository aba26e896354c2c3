"""solve_qp takes what qpsolvers.solve_qp takes (issue 15): column vectors, a 1-D P for
n = 1, h_i = +inf and infinite bounds as no constraint, qpsolvers' multiplier signs; and
its fused path for a positive definite P (src/lemke/qp.cpp) agrees with the KKT-MLCP path."""
import numpy as np
import pytest

import lemke
from helpers import assert_qp_kkt
from lemke import _qp


def _qp_problem(n=6, m=4, p=2, seed=0):
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, n))
    P = B @ B.T / n + 0.1 * np.eye(n)
    x0 = rng.standard_normal(n)
    G = rng.standard_normal((m, n))
    A = rng.standard_normal((p, n))
    return (P, 3.0 * rng.standard_normal(n), G, G @ x0 + rng.uniform(0.0, 1.0, m), A, A @ x0,
            x0 - 1.0, x0 + 1.0)


def _same(r1, r2, tol=1e-9):
    assert r1.status == r2.status == lemke.Status.SOLVED
    for a, b in ((r1.x, r2.x), (r1.y, r2.y), (r1.z, r2.z), (r1.z_box, r2.z_box)):
        assert a.shape == b.shape
        assert np.allclose(a, b, rtol=tol, atol=tol)


def test_column_vectors_are_flattened():
    P, q, G, h, A, b, lb, ub = _qp_problem()
    col = lambda v: v.reshape(-1, 1)  # noqa: E731
    _same(lemke.solve_qp(P, col(q), G, col(h), A, col(b), col(lb), col(ub)),
          lemke.solve_qp(P, q, G, h, A, b, lb, ub))


def test_column_vectors_on_the_mlcp_path():
    """A semidefinite P takes the KKT-MLCP path: the conventions hold there too."""
    P = np.zeros((2, 2))
    q = np.array([[-1.0], [-1.0]])
    r = lemke.solve_qp(P, q, G=np.array([[1.0, 1.0]]), h=np.array([[1.0]]), lb=np.zeros((2, 1)))
    assert r.status == lemke.Status.SOLVED
    assert r.obj == pytest.approx(-1.0)


@pytest.mark.parametrize("P", [[2.0], np.array([2.0]), 2.0])
def test_one_dimensional_p_for_one_variable(P):
    r = lemke.solve_qp(P, [-4.0], G=[[1.0]], h=[1.0])
    assert r.status == lemke.Status.SOLVED
    assert r.x.tolist() == pytest.approx([1.0])
    assert r.z.tolist() == pytest.approx([2.0])


@pytest.mark.parametrize("semidefinite", [False, True])
def test_infinite_h_drops_the_row(semidefinite):
    P, q, G, h, A, b, lb, ub = _qp_problem(seed=3)
    if semidefinite:
        P = np.zeros_like(P)  # an LP: the KKT-MLCP path
    h_inf = h.copy()
    h_inf[1] = np.inf
    r = lemke.solve_qp(P, q, G, h_inf, A, b, lb, ub)
    keep = [0, 2, 3]
    ref = lemke.solve_qp(P, q, G[keep], h[keep], A, b, lb, ub)
    assert r.z.shape == (4,) and r.z[1] == 0.0
    assert np.allclose(r.z[keep], ref.z, atol=1e-9)
    assert np.allclose(r.x, ref.x, atol=1e-9)
    assert r.primal_residual == pytest.approx(ref.primal_residual, abs=1e-12)


def test_every_h_infinite():
    P, q, G, h, A, b, lb, ub = _qp_problem(seed=4)
    r = lemke.solve_qp(P, q, G, np.full(4, np.inf))
    assert r.status == lemke.Status.SOLVED
    assert np.allclose(r.x, np.linalg.solve(P, -q)) and not r.z.any()


@pytest.mark.parametrize("big", [np.inf, 1e20, 1e30])
def test_infinite_bounds_are_no_bound(big):
    P, q, G, h, A, b, lb, ub = _qp_problem(seed=5)
    lb[::2] = -big
    ub[1::2] = big
    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    ref = lemke.solve_qp(P, q, G, h, A, b, np.where(lb <= -1e20, -np.inf, lb),
                         np.where(ub >= 1e20, np.inf, ub))
    _same(r, ref)
    assert_qp_kkt(P, q, G, h, A, b, lb, ub, r)


@pytest.mark.parametrize("value, match", [(-np.inf, r"h has an entry -inf .* at index 2"),
                                          (np.nan, r"h has a NaN at index 2")])
def test_bad_h_is_named(value, match):
    P, q, G, h, A, b, lb, ub = _qp_problem()
    h[2] = value
    with pytest.raises(ValueError, match=match):
        lemke.solve_qp(P, q, G, h, A, b, lb, ub)


def test_nan_elsewhere_still_raises():
    P, q, G, h, A, b, lb, ub = _qp_problem()
    G[1, 1] = np.nan
    h[0] = np.inf
    with pytest.raises(ValueError, match="G has a NaN"):
        lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    with pytest.raises(ValueError, match="b has a NaN"):
        lemke.solve_qp(P, q, A=A, b=[np.nan, 0.0])


def test_multiplier_signs_are_qpsolvers():
    qpsolvers = pytest.importorskip("qpsolvers")
    if "quadprog" not in qpsolvers.available_solvers:
        pytest.skip("quadprog not installed")
    P, q, G, h, A, b, lb, ub = _qp_problem(seed=7)
    sol = qpsolvers.solve_problem(qpsolvers.Problem(P, q, G, h, A, b, lb, ub), solver="quadprog")
    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    assert np.allclose(r.x, sol.x, atol=1e-8)
    assert np.allclose(r.y, sol.y, atol=1e-8)
    assert np.allclose(r.z, sol.z, atol=1e-8)
    assert np.allclose(r.z_box, sol.z_box, atol=1e-8)


def test_qpsolvers_problem_in_solution_out():
    qpsolvers = pytest.importorskip("qpsolvers")
    P, q, G, h, A, b, lb, ub = _qp_problem(seed=8)
    problem = qpsolvers.Problem(P, q, G, h, A, b, lb, ub)
    sol = lemke.solve_qpsolvers_problem(problem)
    assert isinstance(sol, qpsolvers.Solution) and sol.found and sol.is_optimal(1e-9)
    assert sol.extras["lemke"].status == lemke.Status.SOLVED
    assert np.allclose(sol.x, lemke.solve_qp(P, q, G, h, A, b, lb, ub).x)
    bad = qpsolvers.Problem(P, q, G=np.array([[1.0] + [0.0] * 5, [-1.0] + [0.0] * 5]),
                            h=np.array([-1.0, -1.0]))
    none = lemke.solve_qpsolvers_problem(bad)
    assert not none.found and none.x is None
    assert none.extras["lemke"].status == lemke.Status.PRIMAL_INFEASIBLE


# ---------------------------------------------------------------- the fused path

def _mlcp_path(*args):
    (P, q, G, h, A, b, lb, ub), keep = _qp.qpsolvers_form(*args)
    qp = _qp._QP(P, q, G, h, A, b, lb, ub)
    return _qp._restore_rows(_qp._solve(qp, "tableau", lemke.Options(), None, True), keep)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("shape", [(8, 4, 2), (12, 30, 0), (7, 0, 4), (10, 6, 3)])
def test_fused_path_agrees_with_the_mlcp_path(seed, shape):
    n, m, p = shape
    args = list(_qp_problem(n, m, p, seed))
    if seed % 2:
        args[6][0] = args[7][0] = args[6][0] + 0.5  # a fixed variable
    if seed % 3 == 2:
        args[6], args[7] = None, None
    plain = _qp._plain_args(*args)
    fast = _qp._solve_definite(plain, "tableau", lemke.Options())
    assert fast is not None
    slow = _mlcp_path(*args)
    _same(fast, slow, tol=1e-7)
    assert_qp_kkt(*args, fast)
    assert fast.warm_start.n == slow.warm_start.n
    # the fused path's basis, passed back, is a basis of the KKT-MLCP: no pivot needed
    again = lemke.solve_qp(*args, warm_start=fast.warm_start)
    assert again.status == lemke.Status.SOLVED and again.pivots == 0


def test_fused_path_falls_back():
    """Semidefinite P, dependent equalities, an infeasible QP: the KKT-MLCP path answers,
    with its certificate."""
    P, q, G, h, A, b, lb, ub = _qp_problem(seed=9)
    assert _qp._solve_definite(_qp._plain_args(np.zeros_like(P), q, G, h, A, b, lb, ub),
                               "tableau", lemke.Options()) is None
    A2 = np.vstack([A, A[:1]])
    b2 = np.concatenate([b, b[:1]])
    assert _qp._solve_definite(_qp._plain_args(P, q, G, h, A2, b2, lb, ub), "tableau",
                               lemke.Options()) is None
    r = lemke.solve_qp(P, q, G, h, A2, b2, lb, ub)
    assert r.status == lemke.Status.SOLVED
    assert_qp_kkt(P, q, G, h, A2, b2, lb, ub, r)
    bad = lemke.solve_qp(P, q, G=[[1.0] + [0.0] * 5, [-1.0] + [0.0] * 5], h=[-1.0, -1.0])
    assert bad.status == lemke.Status.PRIMAL_INFEASIBLE and bad.certificate is not None


def test_fused_result_is_a_value_when_deferred():
    """The fused path builds y, z, z_box, the residuals and the basis when first read: the
    result is still a value (equal, hashed, copied, pickled and replaced as if built at
    once), and the deferred fields are those of the kernel's output."""
    import copy
    import dataclasses
    import pickle

    args = _qp_problem(seed=3)
    r1, r2 = lemke.solve_qp(*args), lemke.solve_qp(*args)
    assert "_resolve" in r1.__dict__
    assert r1 == r2 and hash(r1) == hash(r2)  # reading the fields resolves both
    assert "_resolve" not in r1.__dict__
    r3 = lemke.solve_qp(*args)
    assert pickle.loads(pickle.dumps(r3)) == r1
    assert copy.copy(lemke.solve_qp(*args)) == r1
    assert "QPResult(status=SOLVED" in repr(lemke.solve_qp(*args))
    r4 = dataclasses.replace(lemke.solve_qp(*args), pivots=-1)
    assert r4.pivots == -1 and np.array_equal(r4.z, r1.z) and r4.warm_start == r1.warm_start
    assert not r1.z.flags.writeable and not r1.x.flags.writeable
    with pytest.raises(AttributeError):
        lemke.solve_qp(*args).no_such_field


def test_residuals_are_their_values_at_the_point():
    """The duality gap of a point whose gap terms are 1e8 is summed in double-double: it is
    the exact value of qpsolvers' formula at the point returned (in fractions), not the 1e-8 rounding of a float64 sum."""
    from fractions import Fraction

    rng = np.random.default_rng(4)
    n = 8
    B = rng.standard_normal((n, n))
    P = 1e6 * (B @ B.T / n + 0.1 * np.eye(n))
    q = 1e7 * rng.standard_normal(n)
    G = rng.standard_normal((4, n))
    h = rng.uniform(0.0, 1.0, 4)
    r = lemke.solve_qp(P, q, G, h)
    assert r.status == lemke.Status.SOLVED
    x, z = r.x, r.z
    F = Fraction
    exact = abs(sum(F(x[i]) * F(P[i, j]) * F(x[j]) for i in range(n) for j in range(n))
                + sum(F(q[j]) * F(x[j]) for j in range(n)) + sum(F(h[i]) * F(z[i]) for i in range(4)))
    size = float(np.abs(x) @ np.abs(P) @ np.abs(x) + np.abs(q) @ np.abs(x) + np.abs(h) @ z)
    # double-double: exact to far below a float64 sum's rounding (eps * size, about 1e-8 here)
    assert abs(F(r.duality_gap) - exact) <= F(1e-6) * F(np.finfo(float).eps) * F(size)
