"""solve_qp: known answers, random QPs against quadprog, certificates, bad input, warm starts.

Every solved QP is checked by the tests' own KKT check (helpers.assert_qp_kkt), and every
certificate by the tests' own Farkas / direction checks."""
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import lemke
from lemke import Status
from lemke.problems import random_convex_qp
from helpers import assert_farkas, assert_qp_kkt, assert_unbounded_direction


def solve_checked(P, q, G=None, h=None, A=None, b=None, lb=None, ub=None, method="tableau", **kw):
    res = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, **kw)
    assert res.status == lemke.Status.SOLVED, res
    assert res.success and res.certificate is None
    assert_qp_kkt(P, q, G, h, A, b, lb, ub, res)
    assert max(res.primal_residual, res.dual_residual, res.duality_gap) < 1e-9
    return res


# ------------------------------------------------------------------ small QPs, known answers

def test_inequality_constrained(method):
    res = solve_checked(2 * np.eye(2), [-2.0, -5.0], G=[[1.0, 1.0]], h=[1.0], method=method)
    np.testing.assert_allclose(res.x, [-0.25, 1.25], atol=1e-12)
    np.testing.assert_allclose(res.z, [2.5], atol=1e-12)
    assert res.obj == pytest.approx(-4.125)


def test_equality_constrained_projection(method):
    """min |x|^2 / 2 s.t. sum x = 1: x = 1/n, y = -1/n; no bounds (all variables free)."""
    n = 5
    res = solve_checked(np.eye(n), np.zeros(n), A=np.ones((1, n)), b=[1.0], method=method)
    np.testing.assert_allclose(res.x, np.full(n, 0.2), atol=1e-13)
    np.testing.assert_allclose(res.y, [-0.2], atol=1e-13)
    assert res.z.size == 0 and np.all(res.z_box == 0)


def test_free_variables_with_equalities_and_an_lp_part(method):
    """An LP in free variables: min x1 + x2 s.t. x1 - x2 = 1, x1 >= -3."""
    res = solve_checked(np.zeros((2, 2)), [1.0, 1.0], G=[[-1.0, 0.0]], h=[3.0], A=[[1.0, -1.0]],
                        b=[1.0], method=method)
    np.testing.assert_allclose(res.x, [-3.0, -4.0], atol=1e-12)
    assert res.obj == pytest.approx(-7.0)


def test_lp_textbook(method):
    """max x1 + x2 s.t. x1 + 2 x2 <= 4, 3 x1 + x2 <= 6, x >= 0: the vertex (1.6, 1.2)."""
    res = solve_checked(np.zeros((2, 2)), [-1.0, -1.0], G=[[1.0, 2.0], [3.0, 1.0]], h=[4.0, 6.0],
                        lb=[0.0, 0.0], method=method)
    np.testing.assert_allclose(res.x, [1.6, 1.2], atol=1e-12)
    np.testing.assert_allclose(res.z, [0.4, 0.2], atol=1e-12)


def test_bounds_hs21(method):
    """Maros-Meszaros HS21: P = diag(0.02, 2), 10 x1 - x2 >= 10, 2 <= x1 <= 50,
    -50 <= x2 <= 50; optimum -99.96 with the constant -100."""
    res = solve_checked(np.diag([0.02, 2.0]), np.zeros(2), G=[[-10.0, 1.0]], h=[-10.0],
                        lb=[2.0, -50.0], ub=[50.0, 50.0], method=method)
    np.testing.assert_allclose(res.x, [2.0, 0.0], atol=1e-12)
    assert res.obj - 100.0 == pytest.approx(-99.96)
    assert res.z_box[0] < 0 and res.z_box[1] == 0  # active lower bound: negative multiplier


def test_upper_bounds_and_fixed_variables(method):
    """min (x - c)^2 / 2 with boxes that cut c: upper, lower, fixed, free and one-sided."""
    c = np.array([5.0, -5.0, 1.0, 2.0, 3.0, -4.0])
    lb = [0.0, -1.0, 0.5, -np.inf, -np.inf, -1e20]
    ub = [1.0, 1.0, 0.5, np.inf, 2.0, 1e21]  # |bound| >= 1e20 means none
    res = solve_checked(np.eye(6), -c, lb=lb, ub=ub, method=method)
    np.testing.assert_allclose(res.x, [1.0, -1.0, 0.5, 2.0, 2.0, -4.0], atol=1e-12)
    np.testing.assert_allclose(res.z_box, [4.0, -4.0, 0.5, 0.0, 1.0, 0.0], atol=1e-12)


def test_semidefinite_p(method):
    """P = diag(1, 0): quadratic in x1, linear in x2, x2 held by a constraint."""
    res = solve_checked(np.diag([1.0, 0.0]), [-1.0, 1.0], G=[[0.0, -1.0], [1.0, 1.0]],
                        h=[0.0, 3.0], method=method)
    np.testing.assert_allclose(res.x, [1.0, 0.0], atol=1e-12)


def test_redundant_equalities(method):
    """The same equality twice (and once scaled): the multipliers are not unique, x is."""
    A = [[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]]
    res = solve_checked(np.eye(3), [0.0, 0.0, -1.0], A=A, b=[2.0, 2.0, 4.0], method=method)
    np.testing.assert_allclose(res.x, [1.0, 1.0, 1.0], atol=1e-12)


def test_lp_with_free_variables_and_a_degenerate_vertex(method):
    """Three constraints through the optimum (1, 1) in the plane: degenerate."""
    G = [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [-1.0, 0.0]]
    res = solve_checked(np.zeros((2, 2)), [-1.0, -1.0], G=G, h=[1.0, 1.0, 2.0, 5.0], method=method)
    np.testing.assert_allclose(res.x, [1.0, 1.0], atol=1e-12)


def test_result_is_read_only_and_inputs_untouched():
    P = np.eye(2)
    q = np.array([-1.0, -1.0])
    G = np.array([[1.0, 1.0]])
    h = np.array([1.0])
    copies = [a.copy() for a in (P, q, G, h)]
    res = lemke.solve_qp(P, q, G, h)
    for a, c in zip((P, q, G, h), copies):
        np.testing.assert_array_equal(a, c)
    with pytest.raises(ValueError):
        res.x[0] = 1.0
    assert "SOLVED" in repr(res) and res.message == lemke.Status.SOLVED.message


# ------------------------------------------------------------------ random QPs vs quadprog

@pytest.mark.parametrize("n,m,p", [(5, 3, 1), (10, 8, 2), (30, 20, 5), (60, 40, 10)])
def test_random_strictly_convex_against_quadprog(n, m, p, method):
    quadprog = pytest.importorskip("quadprog")
    rng = np.random.default_rng(n * 100 + m)
    for _ in range(5):
        P, q, G, h, A, b, lb, ub = random_convex_qp(n, rng, m, p)
        res = solve_checked(P, q, G, h, A, b, lb, ub, method=method)
        # quadprog: min 1/2 x'Gx - a'x s.t. C'x >= b, the first meq equalities
        C = np.vstack([A, -G, np.eye(n), -np.eye(n)]).T
        bq = np.concatenate([b, -h, lb, -ub])
        x_ref, f_ref = quadprog.solve_qp(P, -q, C, bq, meq=p)[:2]
        np.testing.assert_allclose(res.x, x_ref, atol=1e-7 * max(1.0, np.abs(x_ref).max()))
        assert res.obj == pytest.approx(f_ref, rel=1e-9, abs=1e-9)


def test_random_semidefinite(method):
    rng = np.random.default_rng(7)
    for n in (4, 12, 25):
        for _ in range(5):
            P, q, G, h, A, b, lb, ub = random_convex_qp(n, rng, n // 2, 1, rank=max(1, n // 3))
            solve_checked(P, q, G, h, A, b, lb, ub, method=method)


def _fuzz_case(n, m, p, rank, seed, bounds, scale):
    """A random feasible QP: P of the given rank times scale, m inequalities (the last
    repeating the first), p equalities, some constraints active at the feasible point x0,
    and bounds of the given kind around x0."""
    rng = np.random.default_rng(seed)
    p = min(p, n)
    B = rng.standard_normal((n, min(rank, n)))
    P, q = scale * (B @ B.T), scale * rng.standard_normal(n)
    x0 = rng.standard_normal(n)
    G = rng.standard_normal((m, n))
    if m >= 2:
        G[-1] = G[0]
    h = G @ x0 + rng.uniform(0.0, 1.0, m) * (rng.random(m) < 0.7)
    A = rng.standard_normal((p, n))
    b = A @ x0
    mixed_lb = np.where(rng.random(n) < 0.5, x0 - 1.0, -np.inf)
    mixed_ub = np.where(rng.random(n) < 0.5, x0 + 1.0, np.inf)
    lb = {"none": None, "lower": x0 - 1.0, "box": x0 - 1.0, "mixed": mixed_lb}[bounds]
    ub = {"none": None, "lower": None, "box": x0 + 1.0, "mixed": mixed_ub}[bounds]
    return P, q, G if m else None, h if m else None, A if p else None, b if p else None, lb, ub


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(1, 8),
    m=st.integers(0, 8),
    p=st.integers(0, 3),
    rank=st.integers(0, 8),
    seed=st.integers(0, 2**32 - 1),
    bounds=st.sampled_from(["none", "lower", "box", "mixed"]),
    scale=st.sampled_from([1e-4, 1.0, 1e4]),
)
def test_property_feasible_qps_are_solved(n, m, p, rank, seed, bounds, scale):
    """Random feasible QPs with rank-deficient P (an LP when rank = 0), redundant rows and
    any mix of bounds: SOLVED, or DUAL_INFEASIBLE with a checked direction (an LP or
    semidefinite QP without enough constraints is unbounded)."""
    P, q, Gm, hm, Am, bm, lb, ub = _fuzz_case(n, m, p, rank, seed, bounds, scale)
    res = lemke.solve_qp(P, q, Gm, hm, Am, bm, lb, ub)
    assert res.status in (lemke.Status.SOLVED, lemke.Status.DUAL_INFEASIBLE), res
    if res.status == lemke.Status.SOLVED:
        assert_qp_kkt(P, q, Gm, hm, Am, bm, lb, ub, res, rtol=1e-7)
    else:
        assert_unbounded_direction(P, q, Gm, Am, lb, ub, res.certificate)
        assert bounds != "box"  # a bounded feasible set always has a minimum


# ------------------------------------------------------------------ certificates

def test_primal_infeasible_inequalities(method):
    res = lemke.solve_qp(np.eye(2), np.zeros(2), G=[[1.0, 0.0], [-1.0, 0.0]], h=[-1.0, -1.0], method=method)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE and not res.success
    assert res.certificate.kind == "primal_infeasible"
    assert_farkas([[1.0, 0.0], [-1.0, 0.0]], [-1.0, -1.0], None, None, None, None, res.certificate, 2)


def test_primal_infeasible_equalities(method):
    A = [[1.0, 1.0], [1.0, 1.0]]
    res = lemke.solve_qp(np.eye(2), np.zeros(2), A=A, b=[1.0, 2.0], method=method)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE
    assert_farkas(None, None, A, [1.0, 2.0], None, None, res.certificate, 2)


def test_primal_infeasible_bounds_against_constraint(method):
    """x1 + x2 >= 3 with 0 <= x <= 1."""
    G = [[-1.0, -1.0]]
    res = lemke.solve_qp(np.eye(2), np.zeros(2), G=G, h=[-3.0], lb=[0, 0], ub=[1, 1], method=method)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE
    assert_farkas(G, [-3.0], None, None, [0, 0], [1, 1], res.certificate, 2)


def test_unbounded_lp(method):
    G = [[-1.0, 0.0]]
    res = lemke.solve_qp(np.zeros((2, 2)), [-1.0, 0.0], G=G, h=[3.0], lb=[-np.inf, 0.0], method=method)
    assert res.status == lemke.Status.DUAL_INFEASIBLE
    assert_unbounded_direction(np.zeros((2, 2)), [-1.0, 0.0], G, None, [-np.inf, 0.0], None, res.certificate)


def test_unbounded_free_variable_in_no_constraint(method):
    """x2 appears only in the objective, linearly: the equations of the free variables are
    inconsistent at once (no ray); the certificate comes from the auxiliary LP."""
    res = lemke.solve_qp(np.diag([1.0, 0.0]), [0.0, 1.0], method=method)
    assert res.status == lemke.Status.DUAL_INFEASIBLE
    assert_unbounded_direction(np.diag([1.0, 0.0]), [0.0, 1.0], None, None, None, None, res.certificate)


def test_unbounded_semidefinite(method):
    """P singular along (1, -1), q descends along it, constraints do not stop it."""
    P = np.array([[1.0, 1.0], [1.0, 1.0]])
    q = np.array([1.0, -1.0])
    G = [[1.0, 1.0]]
    res = lemke.solve_qp(P, q, G=G, h=[1.0], method=method)
    assert res.status == lemke.Status.DUAL_INFEASIBLE
    assert_unbounded_direction(P, q, G, None, None, None, res.certificate)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(2, 7), m=st.integers(1, 6), seed=st.integers(0, 2**32 - 1))
def test_property_infeasible_qps_get_a_farkas_vector(n, m, seed):
    """Constraints built to contradict: a x <= -1 - s and -a x <= -1 together, plus noise."""
    rng = np.random.default_rng(seed)
    a = rng.standard_normal(n)
    G = np.vstack([a, -a, rng.standard_normal((m, n))])
    h = np.concatenate([[-1.0 - rng.uniform()], [-1.0], rng.uniform(1.0, 2.0, m)])
    B = rng.standard_normal((n, n // 2))
    res = lemke.solve_qp(B @ B.T, rng.standard_normal(n), G, h)
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE, res
    assert_farkas(G, h, None, None, None, None, res.certificate, n)


# ------------------------------------------------------------------ bad input

@pytest.mark.parametrize("kwargs,match", [
    (dict(P=np.eye(2), q=[1.0, 2.0, 3.0]), "shape"),
    (dict(P=np.eye(2), q=[1.0, np.nan]), "NaN"),
    (dict(P=np.eye(2), q=[1.0, 1.0], G=[[1.0, 0.0]]), "without"),
    (dict(P=np.eye(2), q=[1.0, 1.0], h=[1.0]), "without"),
    (dict(P=np.eye(2), q=[1.0, 1.0], A=[[1.0, 0.0]]), "without"),
    (dict(P=np.eye(2), q=[1.0, 1.0], G=[[1.0, 0.0, 0.0]], h=[1.0]), "columns"),
    (dict(P=np.eye(2), q=[1.0, 1.0], G=[[1.0, 0.0]], h=[1.0, 2.0]), "shape"),
    (dict(P=np.eye(2), q=[1.0, 1.0], G=[[1.0, 0.0]], h=[-np.inf]), "infinite"),  # +inf: no constraint (issue 15)
    (dict(P=np.eye(2), q=[1.0, 1.0], A=[[1.0, 0.0]], b=[np.inf]), "infinite"),
    (dict(P=[[1.0, 1.0], [0.0, 1.0]], q=[1.0, 1.0]), "not symmetric"),
    (dict(P=[[1.0, 0.0], [0.0, -1.0]], q=[1.0, 1.0]), "not positive semidefinite"),
    (dict(P=np.eye(2), q=[1.0, 1.0], lb=[0.0, 2.0], ub=[1.0, 1.0]), "exceeds"),
    (dict(P=np.eye(2), q=[1.0, 1.0], lb=[0.0, np.nan]), "NaN"),
    (dict(P=np.eye(2), q=[1.0, 1.0], lb=[np.inf, 0.0]), "lower bound"),
    (dict(P=np.eye(2), q=[1.0, 1.0], lb=[0.0]), "shape"),
    (dict(P=np.eye(3), q=[1.0, 1.0]), "shape"),
])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        lemke.solve_qp(**kwargs)


def test_bad_types():
    with pytest.raises(TypeError):
        lemke.solve_qp(np.eye(2), ["a", "b"])
    with pytest.raises(TypeError, match="warm_start"):
        lemke.solve_qp(np.eye(2), [1.0, 1.0], warm_start=(1, 2))
    with pytest.raises(ValueError, match="method"):
        lemke.solve_qp(np.eye(2), [1.0, 1.0], method="simplex")


def test_symmetric_up_to_rounding_is_accepted():
    P = np.array([[2.0, 1.0], [1.0 + 1e-14, 2.0]])
    solve_checked(P, [-1.0, -1.0])



def _lapack_has_cholesky(S, shift):
    try:
        np.linalg.cholesky(S + shift * np.eye(S.shape[0]))
    except np.linalg.LinAlgError:
        return False
    return True


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_psd_check_on_coupled_rows_agrees_with_lapack(seed):
    """_validate's convexity check factors only the rows with an off-diagonal non-zero (the
    others are 1 x 1 blocks): the same verdict as LAPACK's Cholesky of the whole shifted P,
    decoupled diagonals at, just above and below -shift included."""
    from lemke._validate import _has_cholesky
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 9))
    k = int(rng.integers(0, n + 1))
    coupled = rng.permutation(n)[:k]
    B = rng.standard_normal((k, k)) * rng.integers(0, 2, (k, k))
    S = np.zeros((n, n))
    S[np.ix_(coupled, coupled)] = B @ B.T - rng.choice([0.0, 0.0, 1e-3, 1.0]) * np.eye(k)
    shift = float(rng.choice([0.0, 1e-10, 1e-3]))
    if k:  # a coupled block at its rounding margin may go either way in either factorization
        lam = np.linalg.eigvalsh(S[np.ix_(coupled, coupled)] + shift * np.eye(k))
        assume(abs(lam[0]) > 1e-8 * max(1.0, abs(lam[-1])))
    for j in np.setdiff1d(np.arange(n), coupled):
        S[j, j] = rng.choice([0.0, 1.0, -shift, np.nextafter(-shift, 1.0),
                              np.nextafter(-shift, -1.0), -1.0])
    assert _has_cholesky(S, shift) == _lapack_has_cholesky(S, shift)


# ------------------------------------------------------------------ warm starts

def test_warm_start_sequence(method):
    """A moving target: each solve starts from the previous basis; the same problem again
    takes zero pivots, a nearby one a few."""
    rng = np.random.default_rng(3)
    P, q, G, h, A, b, lb, ub = random_convex_qp(30, rng, 20, 3)
    cold = solve_checked(P, q, G, h, A, b, lb, ub, method=method)
    again = solve_checked(P, q, G, h, A, b, lb, ub, method=method, warm_start=cold.warm_start)
    assert again.pivots == 0
    np.testing.assert_allclose(again.x, cold.x, atol=1e-10)
    ws = cold.warm_start
    total_warm = 0
    for step in range(5):
        q = q + 1e-3 * rng.standard_normal(q.size)
        res = solve_checked(P, q, G, h, A, b, lb, ub, method=method, warm_start=ws)
        total_warm += res.pivots
        ws = res.warm_start
    assert total_warm < cold.pivots * 5


# ------------------------------------------------------------------ regressions from fuzzing

@pytest.mark.parametrize("case,expected", [
    # the reduced LCP was pure rounding noise (~1e-13): Lemke pivoted on it
    ((2, 8, 2, 3, 2691688280, "none", 1.0), lemke.Status.SOLVED),
    # ... and reached x ~ 1e16, which an allowance growing with |x| once passed as SOLVED
    ((6, 3, 0, 1, 12842682, "mixed", 1e-4), lemke.Status.DUAL_INFEASIBLE),
    # a constant of -1e-14 that should be 0: a ray at once although the point solved it
    ((2, 7, 2, 2, 3001, "none", 1e-4), lemke.Status.SOLVED),
    # large but accurate multipliers (|y| ~ 1e7) must not be refused as uncertifiable
    ((4, 7, 3, 3, 1602336078, "none", 1e4), lemke.Status.SOLVED),
])
def test_fuzz_regressions(case, expected, method):
    P, q, G, h, A, b, lb, ub = _fuzz_case(*case)
    res = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
    assert res.status == expected, res
    if expected == lemke.Status.SOLVED:
        assert_qp_kkt(P, q, G, h, A, b, lb, ub, res, rtol=1e-7)
    else:
        assert_unbounded_direction(P, q, G, A, lb, ub, res.certificate)


# --- box-only QPs go to the bounded-variable kernel (solve_blcp) --------------------------

@pytest.mark.parametrize("seed", range(12))
def test_box_only_qps_through_the_box_kernel(seed):
    """A QP whose only constraints are bounds is the box LCP (P, q, lb, ub); the answer is
    checked here by the KKT conditions (helpers, plain numpy), and its warm start re-solves
    the same QP through the KKT-MLCP path in 0 pivots."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 25))
    B = rng.standard_normal((n, n if seed % 3 else max(1, n // 2)))  # every third: singular P
    P = B @ B.T / n + (1e-2 * np.eye(n) if seed % 3 else 0.0)
    q = 3.0 * rng.standard_normal(n)
    lb = np.where(rng.random(n) < 0.8, -rng.uniform(0, 1, n), -np.inf)
    ub = np.where(rng.random(n) < 0.8, rng.uniform(0, 1, n), np.inf)
    lb[rng.random(n) < 0.1] = 0.0
    ub[lb == 0.0] = 0.0  # a few fixed variables
    if seed % 3 == 0:  # singular P: keep it bounded in every direction
        lb[~np.isfinite(lb)] = -2.0
        ub[~np.isfinite(ub)] = 2.0
    res = lemke.solve_qp(P, q, lb=lb, ub=ub)
    assert res.status == Status.SOLVED, res
    assert_qp_kkt(P, q, None, None, None, None, lb, ub, res)
    again = lemke.solve_qp(P, q, lb=lb, ub=ub, warm_start=res.warm_start)
    assert again.success and again.pivots == 0
    np.testing.assert_allclose(again.x, res.x, atol=1e-9 * (1 + np.abs(res.x).max()))


def test_box_only_qp_without_optimum_keeps_its_certificate():
    # min -x0 with x0 >= 0 unbounded above: the box LCP ends on a ray, the KKT-MLCP path
    # then proves it (a direction of unbounded descent)
    res = lemke.solve_qp(np.zeros((2, 2)), [-1.0, 0.0], lb=[0.0, -1.0], ub=[np.inf, 1.0])
    assert res.status == Status.DUAL_INFEASIBLE and res.certificate.dx[0] > 0


def test_fused_path_gives_up_after_one_failed_run():
    """QPCBOEI1 (P = diag, cond 10; 971 inequalities on 375 free directions): the fused
    path's dual LCP is rank-deficient, and its first Lemke run stops after 2 pivots on a
    point that fails the LCP check.  The fused kernel then gives up at once (NOT_SOLVED,
    no recovery runs: these took 469 more pivots, over a second, only for the point to
    fail the KKT check), and solve_qp answers by the KKT-MLCP path, checked here."""
    import sys
    from pathlib import Path

    from lemke import _core, _qp
    from lemke._options import as_options

    here = Path(__file__).resolve().parent
    sys.path.insert(0, str(here.parent / "benchmarks"))
    from maros_meszaros import load

    problem, _ = load(here / "data" / "maros-meszaros" / "QPCBOEI1.mat")
    args = _qp._plain_args(*problem)
    n, p, m = args[1].size, args[4].shape[0], args[2].shape[0]
    opts = as_options(None)
    code, pivots, _, _ = _core.qp_solve(*args, _core.TABLEAU, -1, opts.pivot_tol,
                                        opts.tie_tol, opts.tol, np.empty(4 * n + p + 2 * m + 4))
    assert code == _core.QP_NOT_SOLVED and pivots <= 10
    res = lemke.solve_qp(*problem)
    assert res.status == Status.SOLVED, res
    assert_qp_kkt(*problem, res, rtol=1e-8)
    assert max(res.primal_residual, res.dual_residual) <= 1e-9


@pytest.mark.parametrize("n", [16, 40])
def test_box_path_defers_its_fields(n):
    """A box-only QP of at least BOX_FIRST variables with plain data takes the box kernel
    without the front's validation (qp.cpp's screen and cholesky instead, the same
    arrays); its residuals, objective and basis are built when first read, and are those
    of the point (KKT checked here; the warm start re-solves it in 0 pivots)."""
    import pickle

    rng = np.random.default_rng(n)
    B = rng.standard_normal((n, n))
    P = B @ B.T / n + 0.1 * np.eye(n)
    q = 3.0 * rng.standard_normal(n)
    lb, ub = -rng.uniform(0.1, 1.0, n), rng.uniform(0.1, 1.0, n)
    res = lemke.solve_qp(P, q, lb=lb, ub=ub)
    assert "_resolve" in res.__dict__  # deferred until read
    assert res.status == Status.SOLVED
    assert_qp_kkt(P, q, None, None, None, None, lb, ub, res)
    assert max(res.primal_residual, res.dual_residual, res.duality_gap) <= 1e-9 * (1 + np.abs(q).max())
    assert np.isclose(res.obj, 0.5 * res.x @ P @ res.x + q @ res.x)
    assert pickle.loads(pickle.dumps(res)) == res
    again = lemke.solve_qp(P, q, lb=lb, ub=ub, warm_start=res.warm_start)
    assert again.success and again.pivots == 0
