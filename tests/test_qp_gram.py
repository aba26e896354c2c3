"""solve_qp when the inequalities far outnumber the variables (m >= 4n, the DUALC problems):
the fused kernel's path in factored form (src/lemke/qp.cpp, step 7: Lemke on the multiplier
LCP without forming M, the point from the final basis's active rows, refined and checked).

Every solved QP is checked by the tests' own KKT check (helpers.assert_qp_kkt), every
certificate by the tests' own Farkas / direction checks; ``gram_calls`` records which path
of the fused kernel answered."""
import sys
from pathlib import Path

import numpy as np
import pytest

import lemke
from lemke import Status, _core, _mlcp, _qp
from lemke.problems import random_convex_qp
from helpers import assert_farkas, assert_qp_kkt, assert_unbounded_direction

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "maros-meszaros"
sys.path.insert(0, str(HERE.parent / "benchmarks"))
from maros_meszaros import load, references  # noqa: E402

REFS = references(DATA / "README.md")
# the QP kernels' codes (src/lemke/qp.hpp)
QP_OK, QP_NOT_DEFINITE, QP_NOT_SOLVED, QP_CHECK_FAILED, QP_NOT_APPLICABLE = 0, 1, 3, 4, 6


@pytest.fixture
def kernel_codes(monkeypatch):
    """The codes the fused kernels returned during the test, in order, by kernel: the
    factored path's (``solve_gram``) and the dense one's (``solve``), called from Python
    (``_core.qp_solve_gram``, ``_core.qp_solve``) or run inside the native front
    (``_qp._QP_FRONT``, which says which it ran: ``_core.qp_front_codes``; not its box
    kernel)."""
    codes = {"solve_gram": [], "solve": []}
    for name, calls in codes.items():
        kernel = getattr(_core, "qp_" + name)

        def recording(*args, kernel=kernel, calls=calls):
            out = kernel(*args)
            calls.append(out[0])
            return out
        monkeypatch.setattr(_core, "qp_" + name, recording)
    front = _qp._QP_FRONT

    def front_recording(*args):
        r = front(*args)
        for name, code in _core.qp_front_codes():
            codes[name].append(code)
        return r
    monkeypatch.setattr(_qp, "_QP_FRONT", front_recording)
    return codes


@pytest.fixture
def gram_calls(kernel_codes):
    """The codes the kernel of the factored path (``qp_solve_gram``) returned during the
    test, in order; ``dense_calls`` those of the dense fused kernel (``qp_solve``)."""
    return kernel_codes["solve_gram"]


@pytest.fixture
def dense_calls(kernel_codes):
    return kernel_codes["solve"]


def check_solved(problem, res):
    assert res.status == Status.SOLVED, res
    assert_qp_kkt(*problem, res, rtol=1e-8)
    assert max(res.primal_residual, res.dual_residual, res.duality_gap) <= 1e-9


@pytest.mark.parametrize("name", ["DUALC1", "DUALC2", "DUALC5", "DUALC8"])
def test_dualc(name, method, gram_calls):
    """The four DUALC problems (n = 7..9, 214..502 rows of G, an equality, a box): answered
    by the factored path (DUALC2 and DUALC8 with the proximal term: their P is singular
    to rounding), at the reference optimum."""
    problem, r = load(DATA / f"{name}.mat")
    res = lemke.solve_qp(*problem, method=method)
    check_solved(problem, res)
    assert gram_calls == [QP_OK]
    assert abs(res.obj + r - REFS[name]) <= 1e-6 * abs(REFS[name])
    assert res.pivots <= 40


@pytest.mark.parametrize("n", [3, 6, 10])
@pytest.mark.parametrize("ratio", [10, 25, 50])
def test_random_many_inequalities(n, ratio, gram_calls):
    """Feasible strictly convex QPs with m = ratio n rows of G (and a box): the factored
    path answers, and its answer is a KKT point (checked independently) at quadprog's x."""
    rng = np.random.default_rng([ratio, n])
    for _ in range(3):
        problem = random_convex_qp(n, rng, m=ratio * n)
        res = lemke.solve_qp(*problem)
        check_solved(problem, res)
    assert gram_calls == [QP_OK] * 3


def test_random_without_equalities_or_bounds(gram_calls):
    """Only inequalities (p = 0, no box), also when the unconstrained minimum is feasible
    (no pivot)."""
    rng = np.random.default_rng(5)
    for shift in (0.0, 1e3):
        P, q, G, h, _, _, _, _ = random_convex_qp(8, rng, m=120)
        problem = (P, q, G, h + shift, None, None, None, None)
        res = lemke.solve_qp(*problem)
        check_solved(problem, res)
        if shift:
            assert res.pivots == 0 and not np.any(res.z)
    assert gram_calls == [QP_OK] * 2


@pytest.mark.parametrize("rank", [4, 6])
def test_random_semidefinite(rank, gram_calls):
    """P = B B' of rank < n (no identity added): the factored path solves with P + delta I
    and answers only when the refined point passes the check on the caller's P.  It does
    on most of these; where it does not, it declines (CHECK_FAILED) and the KKT-MLCP path
    answers.  Which ones pass depends on the CPU's rounding: on an AVX-512 host the third
    problem of rank 4 ends the factored path at another point of P's flat directions (7.6e-3
    away from the answer the fallback gives) whose check fails; on the host the test was
    written on, all three passed."""
    rng = np.random.default_rng(rank)
    for _ in range(3):
        problem = random_convex_qp(8, rng, m=160, rank=rank)
        res = lemke.solve_qp(*problem)
        check_solved(problem, res)
    assert gram_calls.count(QP_OK) >= 2 and set(gram_calls) <= {QP_OK, QP_CHECK_FAILED}, gram_calls


def test_degenerate_vertex_with_singular_p(gram_calls):
    """A singular P whose minimum is a vertex (DUALC8's situation): P has a null direction
    that the active bounds pin, and the proximal term's answer, refined on the caller's P,
    passes the check exactly."""
    rng = np.random.default_rng(3)
    n = 6
    B = rng.standard_normal((n, n - 2))
    P = B @ B.T
    q = 50.0 * rng.standard_normal(n)
    G = rng.standard_normal((40 * n, n))
    h = np.abs(G).sum(axis=1) + 1.0  # inactive within the box
    lb, ub = -np.ones(n), np.ones(n)
    problem = (P, q, G, h, None, None, lb, ub)
    res = lemke.solve_qp(*problem)
    check_solved(problem, res)
    assert gram_calls == [QP_OK]


@pytest.mark.parametrize("n", [4, 8])
def test_random_infeasible(n, gram_calls, dense_calls):
    """m = 30 n rows, two of which contradict each other: the factored LCP ends on a ray,
    the dense fused kernel ends NOT_SOLVED too, and the KKT-MLCP path certifies
    infeasibility as before (Farkas vector checked independently)."""
    rng = np.random.default_rng(n)
    P, q, G, h, A, b, lb, ub = random_convex_qp(n, rng, m=30 * n)
    g = rng.standard_normal(n)
    G = np.vstack([G, g, -g])
    h = np.concatenate([h, [-1.0, -1.0]])  # g x <= -1 and g x >= 1
    res = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    assert res.status == Status.PRIMAL_INFEASIBLE, res
    assert_farkas(G, h, A, b, lb, ub, res.certificate, n)
    assert gram_calls == [QP_NOT_SOLVED] and dense_calls == [QP_NOT_SOLVED]


def test_unbounded_semidefinite(gram_calls):
    """P singular with q descending along its null direction, which the many rows of G do
    not block: the proximal problem is bounded, but its answer fails the check on the
    caller's data, and the KKT-MLCP path finds the direction of unbounded descent."""
    rng = np.random.default_rng(9)
    n = 4
    P = np.diag([1.0, 2.0, 3.0, 0.0])
    q = np.array([0.5, -1.0, 0.0, -1.0])
    G = rng.standard_normal((25 * n, n))
    G[:, 3] = -np.abs(G[:, 3])  # x_3 -> +inf keeps every row satisfied
    h = rng.uniform(1.0, 2.0, 25 * n)
    res = lemke.solve_qp(P, q, G, h)
    assert res.status == Status.DUAL_INFEASIBLE, res
    assert_unbounded_direction(P, q, G, None, None, None, res.certificate)
    assert len(gram_calls) == 1 and gram_calls[0] != QP_OK


def test_not_taken_below_the_ratio(gram_calls, dense_calls):
    """Fewer than 4 n inequalities: the dense fused path answers, as before.  With m = n
    rows and a box (3n in all, bench_qp's family) the factored kernel is not even called;
    with 14 rows on 5 variables and only lower bounds (24 >= 4n rows before the kernel
    counts them, 19 after) it is called and declines."""
    rng = np.random.default_rng(1)
    for n in (5, 20):
        problem = random_convex_qp(n, rng)
        res = lemke.solve_qp(*problem)
        check_solved(problem, res)
    assert gram_calls == [] and dense_calls == [QP_OK, QP_OK]
    P, q, G, h, A, b, lb, ub = random_convex_qp(5, rng, m=14)
    problem = (P, q, G, h, A, b, lb, np.full(5, np.inf))
    check_solved(problem, lemke.solve_qp(*problem))
    assert gram_calls == [QP_NOT_APPLICABLE] and dense_calls[-1] == QP_OK


def test_warm_start_from_the_factored_path():
    """The factored path's basis, numbered as the KKT-MLCP's, warm-starts solve_qp."""
    rng = np.random.default_rng(12)
    problem = random_convex_qp(6, rng, m=90)
    res = lemke.solve_qp(*problem)
    check_solved(problem, res)
    again = lemke.solve_qp(*problem, warm_start=res.warm_start)
    check_solved(problem, again)
    assert again.pivots == 0
    np.testing.assert_allclose(again.x, res.x, atol=1e-9)


# --- step 8: a P that is not definite, with few rows -------------------------------------


@pytest.mark.parametrize("name", ["HS51", "HS52", "HS53", "GENHS28", "TAME", "LOTSCHD",
                                  "DPKLO1", "CVXQP1_S", "CVXQP2_S", "CVXQP3_S"])
def test_semidefinite_pinned_by_equalities(name, method, gram_calls, dense_calls):
    """Maros-Meszaros problems whose P is singular (1 to 56 flat directions) and whose
    equality rows outnumber them: the dense fused kernel finds P not definite, and the
    factored path with the proximal factor answers (step 8) at the reference optimum, a KKT
    point by the tests' own check."""
    problem, r = load(DATA / f"{name}.mat")
    P = problem[0]
    assert np.linalg.eigvalsh(P).min() <= 1e-12 * np.abs(P).max()  # not definite indeed
    res = lemke.solve_qp(*problem, method=method)
    check_solved(problem, res)
    assert dense_calls == [QP_NOT_DEFINITE]
    assert gram_calls == [QP_OK]
    assert abs(res.obj + r - REFS[name]) <= 1e-8 * max(1.0, abs(REFS[name]))


def _kernel_gram(problem, relaxed):
    """``(code, pivots)`` of the factored path's kernel called directly with ``semidefinite``
    (its own rule for flat directions, or with ``relaxed`` the fronts' ``flat_allowed``)."""
    P, q, G, h, A, b, lb, ub = _qp._plain_args(*problem)
    n, p, m = q.size, A.shape[0], G.shape[0]
    out = np.empty(_qp._layout(n, p, m)[-1])
    o = lemke.Options()
    code, pivots, _, _ = _core.qp_solve_gram(P, q, G, h, A, b, lb, ub, -1, o.pivot_tol, o.tie_tol,
                                             o.tol, out, _qp._basis_view(out, n, p, m), True,
                                             relaxed)
    return code, pivots


@pytest.mark.parametrize("name", ["PRIMALC1", "QADLITTL", "QSC205"])
def test_flat_directions_not_pinned(name, gram_calls, dense_calls):
    """Linear-program-like problems (P with more zero diagonal entries than equality rows,
    more than SMALL_FLAT variables, and more bound rows than rows of G or more than one flat
    direction beyond the equalities): step 8 is not even called (solve_qp counts them first),
    the KKT-MLCP path answers; the kernel itself, called directly, declines before any pivot
    (NOT_APPLICABLE), by its own rule and by the relaxed one."""
    problem, r = load(DATA / f"{name}.mat")
    res = lemke.solve_qp(*problem)
    check_solved(problem, res)
    assert dense_calls == [QP_NOT_DEFINITE]
    assert gram_calls == []
    assert abs(res.obj + r - REFS[name]) <= 1e-6 * max(1.0, abs(REFS[name]))
    assert _kernel_gram(problem, False) == (QP_NOT_APPLICABLE, 0)
    assert _kernel_gram(problem, True) == (QP_NOT_APPLICABLE, 0)


@pytest.mark.parametrize("name", ["QAFIRO", "ZECEVIC2", "PRIMAL1"])
def test_flat_directions_allowed(name, gram_calls, dense_calls):
    """Problems with more flat directions than equality rows that step 8 takes on all the
    same (``qp::flat_allowed``): at most SMALL_FLAT variables (QAFIRO, ZECEVIC2), or one flat
    direction beyond the equalities with more rows of G than bound rows (PRIMAL1: one linear
    variable among 325).  The kernel's own rule declines them (the frozen references' calls);
    relaxed, it answers, at the reference optimum and a KKT point by the tests' own check."""
    problem, r = load(DATA / f"{name}.mat")
    res = lemke.solve_qp(*problem)
    check_solved(problem, res)
    assert dense_calls == [QP_NOT_DEFINITE]
    assert gram_calls == [QP_OK]
    assert abs(res.obj + r - REFS[name]) <= 1e-8 * max(1.0, abs(REFS[name]))
    assert _kernel_gram(problem, False) == (QP_NOT_APPLICABLE, 0)


def test_check_failed_goes_to_step_8(gram_calls, dense_calls):
    """QPCBLEND (P definite): the dense fused kernel's point fails its KKT check, and step 8
    (the factored path, its active rows' point refined) answers before the KKT-MLCP path,
    at the reference optimum, a KKT point by the tests' own check."""
    problem, r = load(DATA / "QPCBLEND.mat")
    res = lemke.solve_qp(*problem)
    check_solved(problem, res)
    assert dense_calls == [QP_CHECK_FAILED]
    assert gram_calls == [QP_OK]
    assert abs(res.obj + r - REFS["QPCBLEND"]) <= 1e-8 * max(1.0, abs(REFS["QPCBLEND"]))


def test_flat_directions_counted_by_the_factor(gram_calls):
    """A P without a zero diagonal entry but with a two-dimensional null space (P = B B',
    B 4 x 2) and one equality: the proximal factor has two pivots of order delta, more than
    the one equality row, so the kernel's own rule declines (solve_qp's relaxed one takes
    any number at n <= SMALL_FLAT, and answers); with two equality rows both answer."""
    rng = np.random.default_rng(8)
    B = rng.standard_normal((4, 2))
    P = B @ B.T
    assert np.all(np.diag(P) > 0)
    q = rng.standard_normal(4)
    lb, ub = -np.ones(4), np.ones(4)
    A1 = rng.standard_normal((1, 4))
    one = (P, q, None, None, A1, np.zeros(1), lb, ub)
    assert _kernel_gram(one, False)[0] == QP_NOT_APPLICABLE
    gram_calls.clear()
    res = lemke.solve_qp(*one)
    assert gram_calls == [QP_OK]
    check_solved(one, res)
    gram_calls.clear()
    A2 = rng.standard_normal((2, 4))
    two = (P, q, None, None, A2, np.zeros(2), lb, ub)
    assert _kernel_gram(two, False)[0] == QP_OK
    gram_calls.clear()
    res = lemke.solve_qp(*two)
    assert gram_calls == [QP_OK]
    check_solved(two, res)

@pytest.mark.parametrize("name, at_most", [("QSCORPIO", 600), ("QBEACONF", 250)])
def test_ladder_step_ends_at_a_recovery_ray(name, at_most, monkeypatch):
    """The KKT-MLCP's first ladder step ends its recovery runs at their first ray
    (_mlcp._restarted's ray_stop, for a step with another after it: solve_lcp's private
    _ray_stop, the core's stop_at_ray): on these two that ray fails on the caller's data and
    M_clean's step solves, as it did after three more recovery runs (1065 and 388 pivots in
    all before, as without the argument)."""
    problem, _ = load(DATA / f"{name}.mat")
    res = lemke.solve_qp(*problem)
    check_solved(problem, res)
    assert res.pivots <= at_most
    restarted = _mlcp._restarted
    monkeypatch.setattr(_mlcp, "_restarted", lambda *a: restarted(*a[:9], False))
    every = lemke.solve_qp(*problem)
    check_solved(problem, every)
    assert every.pivots > at_most
