"""Empty problems (n = 0 LCPs and MLCPs, QPs with no variable or every variable fixed) and
QPs that are infeasible and unbounded at once (both certificates).

Every answer is judged by the tests' own checks (tests/helpers.py) or by the conditions
written out here, never by lemke's certify code."""
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import lemke
from lemke import _cli
from helpers import assert_farkas, assert_lcp_solution, assert_qp_kkt, assert_unbounded_direction

z0 = np.zeros


# ------------------------------------------------------------------ LCP, n = 0

@pytest.mark.parametrize("M,q", [(z0((0, 0)), z0(0)), ([], [])])
def test_lcp_of_size_zero(M, q, method):
    res = lemke.solve_lcp(M, q, method=method)
    assert res.status == lemke.Status.SOLVED and res.success
    assert res.z.shape == res.w.shape == (0,) and res.pivots == 0 and res.residual == 0.0
    assert res.ray is None and res.warm_start == lemke.WarmStart(0, ())
    again = lemke.solve_lcp(M, q, method=method, warm_start=res.warm_start)
    assert again.status == lemke.Status.SOLVED and again.z.shape == (0,)


def test_lcp_of_size_zero_with_a_covering_vector():
    res = lemke.solve_lcp(z0((0, 0)), z0(0), d=[])
    assert res.status == lemke.Status.SOLVED and res.covering.shape == (0,)


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("M,q", [
    (z0((3, 0, 0)), z0((3, 0))),       # n = 0, one M each
    (z0((0, 0)), z0((3, 0))),          # n = 0, M shared
    ([], z0((3, 0))),                  # n = 0, M written as []
    (z0((0, 2, 2)), z0((0, 2))),       # B = 0
    (np.eye(2), z0((0, 2))),           # B = 0, M shared
    (z0((0, 0, 0)), z0((0, 0))),       # B = 0 and n = 0
])
def test_batch_with_nothing_to_solve(M, q, workers, method):
    B, n = np.shape(q)
    res = lemke.solve_lcp_batch(M, q, method=method, workers=workers)
    assert res.z.shape == res.w.shape == (B, n)
    assert res.status.shape == res.pivots.shape == res.residual.shape == (B,)
    assert np.all(res.status == lemke.Status.SOLVED) and np.all(res.success)
    assert np.all(res.pivots == 0)


# ------------------------------------------------------------------ MLCP, n = 0 or m = 0

def test_mlcp_with_nothing(method):
    for blocks in ((z0((0, 0)),) * 4 + (z0(0), z0(0)), ([],) * 6):
        res = lemke.solve_mlcp(*blocks, method=method)
        assert res.status == lemke.Status.SOLVED and res.success
        assert res.u.shape == res.v.shape == res.w.shape == (0,)
        assert res.residual == 0.0 and res.ray is None and res.warm_start == lemke.WarmStart(0, ())
        again = lemke.solve_mlcp(*blocks, method=method, warm_start=res.warm_start)
        assert again.status == lemke.Status.SOLVED


def test_mlcp_without_free_variables_is_an_lcp(method):
    B = np.array([[2.0, 1.0], [1.0, 2.0]])
    b = np.array([-5.0, -6.0])
    res = lemke.solve_mlcp(z0((0, 0)), B, z0((0, 2)), z0((2, 0)), z0(0), b, method=method)
    assert res.status == lemke.Status.SOLVED and res.u.shape == (0,)
    assert_lcp_solution(B, b, res.v)
    np.testing.assert_allclose(res.w, B @ res.v + b, atol=1e-12)


def test_mlcp_without_pairs_is_linear_equations(method):
    A = np.array([[2.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]])
    a = np.array([1.0, -2.0, 0.5])
    res = lemke.solve_mlcp(A, [], z0((3, 0)), z0((0, 3)), a, [], method=method)
    assert res.status == lemke.Status.SOLVED and res.v.shape == res.w.shape == (0,)
    assert np.abs(A @ res.u + a).max() <= 1e-12 * max(1.0, np.abs(res.u).max())


def test_mlcp_without_pairs_redundant_and_inconsistent(method):
    """Two copies of one equation: consistent (solved), then contradicting (no u exists)."""
    A = np.array([[1.0, 1.0], [1.0, 1.0]])
    res = lemke.solve_mlcp(A, [], z0((2, 0)), z0((0, 2)), [-1.0, -1.0], [], method=method)
    assert res.status == lemke.Status.SOLVED
    assert np.abs(A @ res.u - 1.0).max() <= 1e-12
    res = lemke.solve_mlcp(A, [], z0((2, 0)), z0((0, 2)), [-1.0, -2.0], [], method=method)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE and not res.success
    # and indeed: (1, -1) A = 0 while (1, -1) a = 1, so A u + a = 0 has no solution
    assert np.all((np.array([1.0, -1.0]) @ A) == 0.0)


# ------------------------------------------------------------------ QPs with nothing to choose

def test_qpsolvers_fixed_variable_bound(method):
    """qpsolvers' test_fixed_variable_bound (qpsolvers/qpsolvers, tests/test_sip.py,
    LGPL-3.0-or-later; numbers only): P = [[1]], q = [-2], lb = ub = [1]; there x = [1],
    y has shape (0,) and z_box = [1]."""
    P, q, lb, ub = np.eye(1), np.array([-2.0]), np.array([1.0]), np.array([1.0])
    res = lemke.solve_qp(P, q, lb=lb, ub=ub, method=method)
    assert res.status == lemke.Status.SOLVED and res.certificate is None
    assert_qp_kkt(P, q, None, None, None, None, lb, ub, res)
    assert res.y.shape == (0,) and res.z.shape == (0,)
    np.testing.assert_allclose(res.x, [1.0], atol=1e-5)
    np.testing.assert_allclose(res.z_box, [1.0], atol=1e-5)


def test_every_variable_fixed(method):
    rng = np.random.default_rng(7)
    B = rng.standard_normal((4, 4))
    P, q = B @ B.T, rng.standard_normal(4)
    x0 = rng.standard_normal(4)
    res = lemke.solve_qp(P, q, lb=x0, ub=x0, method=method)
    assert res.status == lemke.Status.SOLVED
    assert_qp_kkt(P, q, None, None, None, None, x0, x0, res)
    assert np.array_equal(res.x, x0)
    assert max(res.primal_residual, res.dual_residual, res.duality_gap) < 1e-12


@pytest.mark.parametrize("h", [[5.0, 3.0], [3.0, 3.0]])  # slack, then one row exactly active
def test_fixed_variables_with_constant_rows_that_hold(h, method):
    """x = (1, 2) fixed: x1 + x2 <= h1, x1 <= h2... and x1 - x2 = -1 are constant rows."""
    P, q = np.eye(2), np.array([1.0, -1.0])
    G, A, b, x0 = np.array([[1.0, 1.0], [1.0, 0.0]]), np.array([[1.0, -1.0]]), np.array([-1.0]), np.array([1.0, 2.0])
    res = lemke.solve_qp(P, q, G, h, A, b, x0, x0, method=method)
    assert res.status == lemke.Status.SOLVED
    assert_qp_kkt(P, q, G, h, A, b, x0, x0, res)
    assert res.y.shape == (1,) and res.z.shape == (2,)


@pytest.mark.parametrize("kind", ["inequality", "equality"])
def test_fixed_variables_with_a_violated_constant_row(kind, method):
    P, q, x0 = np.eye(2), np.ones(2), np.array([1.0, 2.0])
    rows = dict(G=[[1.0, 1.0]], h=[0.0]) if kind == "inequality" else dict(A=[[1.0, 1.0]], b=[0.0])
    res = lemke.solve_qp(P, q, lb=x0, ub=x0, method=method, **rows)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE and not res.success
    assert res.certificate.kind == "primal_infeasible"
    assert_farkas(rows.get("G"), rows.get("h"), rows.get("A"), rows.get("b"), x0, x0, res.certificate, 2)
    assert res.certificate.dx is None  # nothing can move: no direction


def test_constant_rows_that_hold_up_to_rounding(method):
    """3 * 0.1 - 0.3 is 5.6e-17 in double: the row 3 x = 0.3 with x fixed at 0.1 holds."""
    P, q, x0 = np.eye(1), np.array([1.0]), np.array([0.1])
    assert 3.0 * 0.1 - 0.3 != 0.0
    for rows in (dict(A=[[3.0]], b=[0.3]), dict(G=[[3.0]], h=[0.3])):
        res = lemke.solve_qp(P, q, lb=x0, ub=x0, method=method, **rows)
        assert res.status == lemke.Status.SOLVED, rows
        assert_qp_kkt(P, q, rows.get("G"), rows.get("h"), rows.get("A"), rows.get("b"), x0, x0, res)
    # while a real violation is still one
    res = lemke.solve_qp(P, q, G=[[3.0]], h=[0.29], lb=x0, ub=x0, method=method)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE
    assert_farkas([[3.0]], [0.29], None, None, x0, x0, res.certificate, 1)


def test_some_fixed_some_free(method):
    """Fixed variables next to free and bounded ones, with rows that mix them."""
    rng = np.random.default_rng(11)
    B = rng.standard_normal((5, 5))
    P, q = B @ B.T + np.eye(5), rng.standard_normal(5)
    lb = np.array([0.5, -np.inf, 0.0, -1.0, 2.0])
    ub = np.array([0.5, np.inf, np.inf, -1.0, 3.0])
    G, h = rng.standard_normal((3, 5)), rng.uniform(5.0, 6.0, 3)
    A = np.array([[0.0, 1.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 1.0, 0.0]])  # the second is constant
    b = np.array([1.0, -0.5])
    res = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
    assert res.status == lemke.Status.SOLVED, res
    assert_qp_kkt(P, q, G, h, A, b, lb, ub, res)


@pytest.mark.parametrize("P,q", [(z0((0, 0)), z0(0)), ([], [])])
def test_qp_with_no_variables(P, q, method):
    res = lemke.solve_qp(P, q, method=method)
    assert res.status == lemke.Status.SOLVED and res.obj == 0.0
    assert res.x.shape == res.y.shape == res.z.shape == res.z_box.shape == (0,)
    assert_qp_kkt(z0((0, 0)), z0(0), None, None, None, None, None, None, res)


@pytest.mark.parametrize("h,b,feasible", [
    ([1.0, 0.0], [0.0], True),     # 0 <= 1, 0 <= 0, 0 = 0
    ([1.0, -2.0], [0.0], False),   # 0 <= -2
    ([1.0, 0.0], [3.0], False),    # 0 = 3
])
def test_qp_with_no_variables_and_constant_rows(h, b, feasible, method):
    G, A = z0((2, 0)), z0((1, 0))
    res = lemke.solve_qp(z0((0, 0)), z0(0), G, h, A, b, method=method)
    if feasible:
        assert res.status == lemke.Status.SOLVED
        assert_qp_kkt(z0((0, 0)), z0(0), G, h, A, b, None, None, res)
        assert res.z.shape == (2,) and res.y.shape == (1,)
    else:
        assert res.status == lemke.Status.PRIMAL_INFEASIBLE
        assert_farkas(G, h, A, b, None, None, res.certificate, 0)
        assert res.certificate.dx is None


# ------------------------------------------------------------------ the command line

EMPTY_FILES = {
    "lcp0.json": ({"kind": "lcp", "M": [], "q": []}, 0),
    "mlcp0.json": ({"kind": "mlcp", "A": [], "B": [], "C": [], "D": [], "a": [], "b": []}, 0),
    "mlcp_n0.json": ({"kind": "mlcp", "A": [], "B": [[1.0]], "C": [], "D": [], "a": [], "b": [-1.0]}, 0),
    "qp0.json": ({"kind": "qp", "P": [], "q": []}, 0),
    "qp_fixed.json": ({"kind": "qp", "P": [[1.0]], "q": [-2.0], "lb": [1.0], "ub": [1.0]}, 0),
    "qp_fixed_violated.json": ({"kind": "qp", "P": [[1.0, 0.0], [0.0, 1.0]], "q": [1.0, 1.0],
                                "G": [[1.0, 1.0]], "h": [0.0], "lb": [1.0, 2.0], "ub": [1.0, 2.0]}, 1),
}


@pytest.mark.parametrize("name", sorted(EMPTY_FILES))
def test_cli_solves_empty_problem_files(tmp_path, capsys, name):
    doc, expected = EMPTY_FILES[name]
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    code = _cli.main(["solve", "--json", str(path)])
    out, err = capsys.readouterr()
    assert code == expected, out + err
    assert "Traceback" not in err and "error" not in err
    result = json.loads(out)
    assert result["status"] == ("SOLVED" if expected == 0 else "PRIMAL_INFEASIBLE")


@pytest.mark.parametrize("fmt", ["json", "npz", "dat", "mat", "qps"])
def test_empty_problems_survive_a_file_round_trip(tmp_path, fmt, method):
    """Written and read back (a JSON [] must stand for C of shape (0, m))."""
    probs = [] if fmt == "qps" else [  # QPS files hold QPs only
        lemke.Problem.lcp(z0((0, 0)), z0(0)),
        lemke.Problem.mlcp(z0((0, 0)), z0((0, 0)), z0((0, 0)), z0((0, 0)), z0(0), z0(0)),
        lemke.Problem.mlcp(z0((0, 0)), np.eye(2), z0((0, 2)), z0((2, 0)), z0(0), [-1.0, 1.0]),
        lemke.Problem.mlcp(np.eye(2), z0((0, 0)), z0((2, 0)), z0((0, 2)), [1.0, -1.0], z0(0)),
    ]
    if fmt != "dat":  # Siconos files hold no QPs
        probs += [lemke.Problem.qp(z0((0, 0)), z0(0)),
                  lemke.Problem.qp([[1.0]], [-2.0], lb=[1.0], ub=[1.0]),
                  lemke.Problem.qp(np.eye(2), [1.0, 1.0], G=z0((0, 2)), h=z0(0))]
    for k, prob in enumerate(probs):
        path = tmp_path / f"p{k}.{fmt}"
        lemke.write_problem(prob, path)
        back = lemke.read_problem(path)
        assert back.kind == prob.kind and back.shape == prob.shape
        assert back.solve(method=method).status == lemke.Status.SOLVED


# ------------------------------------------------------------------ infeasible and unbounded

def check_both(P, q, G, h, A, b, lb, ub, res):
    """PRIMAL_INFEASIBLE, with a Farkas vector and a direction of descent, each checked here."""
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE, res
    cert = res.certificate
    assert cert.kind == "primal_infeasible"
    assert_farkas(G, h, A, b, lb, ub, cert, np.size(q))
    assert cert.dx is not None, "the direction of descent is missing"
    assert_unbounded_direction(P, q, G, A, lb, ub, cert)


def test_infeasible_and_unbounded_lp(method):
    """min -x1 s.t. x2 <= -1, x2 >= 0 (as rows of G), x1 free: no x, and x1 -> +inf would
    descend without bound."""
    P, q = z0((2, 2)), np.array([-1.0, 0.0])
    G, h = np.array([[0.0, 1.0], [0.0, -1.0]]), np.array([-1.0, 0.0])
    res = lemke.solve_qp(P, q, G, h, method=method)
    check_both(P, q, G, h, None, None, None, None, res)


def test_infeasible_and_unbounded_with_a_bound_and_an_equality(method):
    """The same with x2 >= 0 as a bound, in a QP: P acts on x3 only, and x3 = 0.5 is an
    equality; d = (1, 0, 0) still descends."""
    P = np.diag([0.0, 0.0, 2.0])
    q = np.array([-1.0, 0.0, 1.0])
    G, h = np.array([[0.0, 1.0, 0.0]]), np.array([-1.0])
    A, b = np.array([[0.0, 0.0, 1.0]]), np.array([0.5])
    lb = np.array([-np.inf, 0.0, -np.inf])
    res = lemke.solve_qp(P, q, G, h, A, b, lb, None, method=method)
    check_both(P, q, G, h, A, b, lb, None, res)


def test_infeasible_but_bounded_has_no_direction(method):
    """P positive definite: P d = 0 only for d = 0, so no direction of descent exists."""
    G, h = np.array([[1.0, 0.0], [-1.0, 0.0]]), np.array([-1.0, -1.0])
    res = lemke.solve_qp(np.eye(2), np.array([1.0, -3.0]), G, h, method=method)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE
    assert_farkas(G, h, None, None, None, None, res.certificate, 2)
    assert res.certificate.dx is None


def test_feasible_and_unbounded_stays_dual_infeasible(method):
    G, h = np.array([[0.0, 1.0]]), np.array([1.0])
    res = lemke.solve_qp(z0((2, 2)), np.array([-1.0, 0.0]), G, h, method=method)
    assert res.status == lemke.Status.DUAL_INFEASIBLE
    assert_unbounded_direction(z0((2, 2)), [-1.0, 0.0], G, None, None, None, res.certificate)
    assert res.certificate.y is None and res.certificate.z is None


@settings(max_examples=25, deadline=None)
@given(n=st.integers(3, 7), rank=st.integers(0, 2), m=st.integers(0, 4), seed=st.integers(0, 2**32 - 1))
def test_property_infeasible_and_unbounded_get_both(n, rank, m, seed):
    """A random QP built to be both: P = B B' (rank < n) with a null direction d that q
    descends along; rows with g'd <= 0 (so d stays a direction) and a contradicting pair."""
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, rank))
    P = B @ B.T
    # d: a unit vector orthogonal to B's columns, so P d = 0
    d = rng.standard_normal(n)
    if rank:
        Q, _ = np.linalg.qr(B)
        d -= Q @ (Q.T @ d)
    d /= np.linalg.norm(d)
    q = -d + P @ rng.standard_normal(n)  # q'd = -1
    a = rng.standard_normal(n)
    a -= (a @ d) * d  # a'd = 0: the contradicting pair does not block d
    noise = rng.standard_normal((m, n))
    noise -= np.outer(noise @ d, d) + np.outer(rng.uniform(0.0, 1.0, m), d)  # g'd <= 0
    G = np.vstack([a, -a, noise])
    h = np.concatenate([[-1.0 - rng.uniform()], [-1.0], rng.uniform(1.0, 2.0, m)])
    res = lemke.solve_qp(P, q, G, h)
    check_both(P, q, G, h, None, None, None, None, res)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(2, 7), m=st.integers(1, 5), rank=st.integers(0, 7), seed=st.integers(0, 2**32 - 1))
def test_property_direction_is_reported_exactly_when_one_exists(n, m, rank, seed):
    """Infeasible QPs (a contradicting pair of rows) with random q and a P of any rank: the
    Farkas vector always, and dx exactly when an LP solved by scipy's HiGHS (the judge
    here, on P's null space) finds a direction of descent."""
    from scipy.linalg import null_space
    from scipy.optimize import linprog

    rng = np.random.default_rng(seed)
    a = rng.standard_normal(n)
    G = np.vstack([a, -a, rng.standard_normal((m, n))])
    h = np.concatenate([[-1.0 - rng.uniform()], [-1.0], rng.uniform(1.0, 2.0, m)])
    B = rng.standard_normal((n, min(rank, n)))
    P, q = B @ B.T, rng.standard_normal(n)
    res = lemke.solve_qp(P, q, G, h)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE, res
    assert_farkas(G, h, None, None, None, None, res.certificate, n)
    N = null_space(P, rcond=1e-9) if rank else np.eye(n)
    exists = False
    if N.shape[1]:
        lp = linprog(N.T @ q, A_ub=G @ N, b_ub=np.zeros(G.shape[0]), bounds=[(-1.0, 1.0)] * N.shape[1],
                     method="highs")
        assert lp.status == 0
        exists = lp.fun < -1e-7
    assert (res.certificate.dx is not None) == exists
    if exists:
        assert_unbounded_direction(P, q, G, None, None, None, res.certificate)
