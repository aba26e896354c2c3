"""QP warm starts in the fused kernel, qpsolvers' initvals, and the factor cache.

Every answer is checked by tests/helpers.assert_qp_kkt (plain numpy, not lemke's check) and
compared with a cold solve's; speed is benchmarks/bench_mpc.py's business, not asserted here.
"""
import os
import sys
from types import SimpleNamespace

import numpy as np
import pytest

import lemke
from lemke import Status
from lemke.problems import random_convex_qp
from helpers import assert_qp_kkt

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import mpc_problem  # noqa: E402

NU, NX = mpc_problem.NU, mpc_problem.NX


def check(P, q, G, h, A, b, lb, ub, res):
    """assert_qp_kkt on the rows of G whose h is finite (qpsolvers' +inf: no constraint,
    whose z must be 0)."""
    assert res.status == Status.SOLVED, res
    keep = np.isfinite(h)
    assert np.all(res.z[~keep] == 0.0)
    part = SimpleNamespace(x=res.x, y=res.y, z=res.z[keep], z_box=res.z_box, obj=res.obj)
    assert_qp_kkt(P, q, G[keep], h[keep], A, b, lb, ub, part)


@pytest.fixture(scope="module")
def mpc():
    return mpc_problem.sequence(steps=40, seed=1)


def test_mpc_warm_and_initvals_match_cold(mpc, method):
    """The MPC loop three ways (cold, the previous result's warm start, the previous x
    shifted by a stage as initvals): every step solved, KKT-checked, the same x as cold."""
    (P, G, h, A, lb, ub), steps = mpc
    ws, x_prev, zero = None, None, 0
    for q, b in steps:
        cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
        check(P, q, G, h, A, b, lb, ub, cold)
        warm = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, warm_start=ws)
        check(P, q, G, h, A, b, lb, ub, warm)
        guess = None if x_prev is None else np.concatenate([x_prev[NU + NX:], x_prev[-(NU + NX):]])
        init = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, initvals=guess)
        check(P, q, G, h, A, b, lb, ub, init)
        for r in (warm, init):
            np.testing.assert_allclose(r.x, cold.x, rtol=0, atol=1e-8)
        zero += warm.pivots == 0
        ws, x_prev = warm.warm_start, init.x
    assert zero > 0  # some steps keep their active set


def test_same_problem_again_takes_no_pivot(mpc):
    (P, G, h, A, lb, ub), steps = mpc
    q, b = steps[7]
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    again = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=cold.warm_start)
    assert again.pivots == 0
    check(P, q, G, h, A, b, lb, ub, again)
    assert again.warm_start == cold.warm_start
    # the primal answer as initvals: its active set, 0 pivots too
    init = lemke.solve_qp(P, q, G, h, A, b, lb, ub, initvals=cold.x)
    assert init.pivots == 0
    check(P, q, G, h, A, b, lb, ub, init)


@pytest.mark.parametrize("seed", range(6))
def test_a_wrong_warm_start_still_solves(seed, method):
    """Random bases of the right size (most of them wrong, some singular): every solve ends
    solved and checked, at the cold answer."""
    rng = np.random.default_rng(seed)
    P, q, G, h, A, b, lb, ub = random_convex_qp(25, rng, 15, 4)
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
    check(P, q, G, h, A, b, lb, ub, cold)
    npairs = cold.warm_start.n
    for _ in range(4):
        basic = np.flatnonzero(rng.random(npairs) < rng.random())
        ws = lemke.WarmStart(npairs, tuple(basic.tolist()))
        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, warm_start=ws)
        check(P, q, G, h, A, b, lb, ub, r)
        np.testing.assert_allclose(r.x, cold.x, atol=1e-8)
    # a wild guess for x
    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, initvals=10 * rng.standard_normal(q.size))
    check(P, q, G, h, A, b, lb, ub, r)
    np.testing.assert_allclose(r.x, cold.x, atol=1e-8)


def test_warm_start_of_another_structure_is_refused(mpc):
    (P, G, h, A, lb, ub), steps = mpc
    q, b = steps[0]
    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    with pytest.raises(ValueError, match="warm_start has 3 pairs, this QP has"):
        lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=lemke.WarmStart(3, (0,)))
    with pytest.raises(ValueError, match="warm_start has"):  # the bounds dropped: fewer pairs
        lemke.solve_qp(P, q, G, h, A, b, warm_start=r.warm_start)
    with pytest.raises(ValueError, match="warm_start has"):  # lists: the KKT-MLCP path's check
        lemke.solve_qp(P.tolist(), q.tolist(), G.tolist(), h.tolist(), A.tolist(), b.tolist(),
                       warm_start=r.warm_start)
    box = lemke.solve_blcp(np.eye(2), [-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]).warm_start
    with pytest.raises(ValueError, match="warm_start must be a lemke.WarmStart, got a lemke.BoxWarmStart"):
        lemke.solve_qp(np.eye(2), [1.0, 1.0], lb=[0.0, 0.0], warm_start=box)
    with pytest.raises(TypeError, match="warm_start"):
        lemke.solve_qp(np.eye(2), [1.0, 1.0], warm_start=(1, 2))


def test_initvals_bad_input():
    P, q = np.eye(3), np.array([1.0, -1.0, 0.5])
    for bad in ([1.0, 2.0], np.zeros((3, 2)), [[1.0, 2.0, 3.0]]):
        with pytest.raises(ValueError, match="initvals"):
            lemke.solve_qp(P, q, lb=np.zeros(3), initvals=bad)
    with pytest.raises(ValueError, match="initvals has a non-finite entry at index 1"):
        lemke.solve_qp(P, q, lb=np.zeros(3), initvals=[0.0, np.nan, 0.0])
    with pytest.raises(ValueError, match="initvals"):
        lemke.solve_qp(P, q, lb=np.zeros(3), initvals=["a", "b", "c"])
    with pytest.raises(ValueError, match="not both"):
        r = lemke.solve_qp(P, q, lb=np.zeros(3))
        lemke.solve_qp(P, q, lb=np.zeros(3), initvals=np.zeros(3), warm_start=r.warm_start)


def test_initvals_in_other_forms():
    """Lists, a column vector, h with +inf rows, bounds beyond 1e20: the guess's active set is
    read after qpsolvers' conventions."""
    P = [[2.0, 0.0], [0.0, 2.0]]
    q = [-2.0, -5.0]
    G = [[1.0, 1.0], [1.0, 0.0]]
    h = [1.0, np.inf]
    lb = [-1e21, 0.0]
    r = lemke.solve_qp(P, q, G, h, lb=lb, initvals=[[-0.25], [1.25]])
    check(np.array(P), np.array(q), np.array(G), np.array(h), np.zeros((0, 2)), np.zeros(0),
          np.array([-np.inf, 0.0]), None, r)
    assert r.pivots == 0
    np.testing.assert_allclose(r.x, [-0.25, 1.25], atol=1e-12)


def test_qpsolvers_style_code_runs_unchanged(mpc):
    """``solve_qp(P, q, G, h, A, b, lb, ub, initvals=x)``, qpsolvers' keyword, and
    solve_qpsolvers_problem with initvals."""
    qpsolvers = pytest.importorskip("qpsolvers")
    (P, G, h, A, lb, ub), steps = mpc
    q, b = steps[3]
    x = None
    for solve in (lemke.solve_qp,):
        res = solve(P, q, G, h, A, b, lb, ub, initvals=x)
        check(P, q, G, h, A, b, lb, ub, res)
        x = res.x
    problem = qpsolvers.Problem(P, q, G, h, A, b, lb, ub)
    sol = lemke.solve_qpsolvers_problem(problem, initvals=x)
    assert sol.found and sol.extras["lemke"].pivots == 0
    np.testing.assert_allclose(sol.x, x, atol=1e-10)


def _bits(r):
    return tuple(np.asarray(a).tobytes() for a in (r.x, r.y, r.z, r.z_box)) + (
        r.obj, r.pivots, r.primal_residual, r.dual_residual, r.duality_gap, r.warm_start)


def test_factor_cache_gives_the_same_bits_and_never_stale_data():
    """The kernel reuses the factors of the last P, A, G on its thread: a cold solve gives the
    same bits with the cache (the same data again) as without it (another QP in between),
    and arrays changed in place, another structure (a bound kind, a row of h made +inf) or
    another P are solved afresh, each checked."""
    rng = np.random.default_rng(11)
    P, q, G, h, A, b, lb, ub = random_convex_qp(20, rng, 12, 3)
    other = random_convex_qp(20, np.random.default_rng(12), 12, 3)
    first = _bits(lemke.solve_qp(P, q, G, h, A, b, lb, ub))
    again = _bits(lemke.solve_qp(P, q, G, h, A, b, lb, ub))  # factors reused
    lemke.solve_qp(*other)
    fresh = _bits(lemke.solve_qp(P, q, G, h, A, b, lb, ub))  # factors recomputed
    assert first == again == fresh
    # in place: the same objects, new contents
    for name, change in (("P", lambda: P.__setitem__((0, 0), P[0, 0] + 1.0)),
                         ("A", lambda: A.__setitem__((0, 1), A[0, 1] + 0.5)),
                         ("G", lambda: G.__setitem__((1, 2), G[1, 2] - 0.5)),
                         ("lb", lambda: lb.__setitem__(0, -np.inf)),
                         ("ub", lambda: ub.__setitem__(1, lb[1])),
                         ("h", lambda: h.__setitem__(2, np.inf))):
        lemke.solve_qp(P, q, G, h, A, b, lb, ub)  # the cache holds the current data
        change()
        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
        check(P, q, G, h, A, b, lb, ub, r)
        copies = [a.copy() for a in (P, q, G, h, A, b, lb, ub)]
        lemke.solve_qp(*other)
        assert _bits(r) == _bits(lemke.solve_qp(*copies)), name


@pytest.mark.parametrize("seed", range(4))
def test_initvals_rule_same_in_kernel_and_front(seed):
    """The kernel reads the rows active at x0 (qp::guess_rows) on plain data; the front's
    _initvals_start (for the KKT-MLCP path) states the same rule: the same active set, so the
    same solve, bit for bit."""
    from lemke import _qp
    rng = np.random.default_rng(100 + seed)
    P, q, G, h, A, b, lb, ub = random_convex_qp(20, rng, 14, 3)
    h[::5] = np.inf
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    check(P, q, G, h, A, b, lb, ub, cold)
    for scale in (0.0, 1e-3, 0.3):
        x0 = cold.x + scale * rng.standard_normal(q.size)
        via_kernel = lemke.solve_qp(P, q, G, h, A, b, lb, ub, initvals=x0)
        ws = _qp._initvals_start(x0, P, q, G, h, A, b, lb, ub)
        via_front = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws)
        check(P, q, G, h, A, b, lb, ub, via_kernel)
        assert _bits(via_kernel) == _bits(via_front)
        if scale == 0.0:
            assert via_kernel.pivots == 0


def test_time_limit_with_a_warm_start(mpc):
    """Options(time_limit=) reaches the warm and initvals paths: a limit already passed stops
    them (TIME_LIMIT), a generous one changes nothing."""
    (P, G, h, A, lb, ub), steps = mpc
    q, b = steps[5]
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    for kw in (dict(warm_start=cold.warm_start), dict(initvals=cold.x)):
        stopped = lemke.solve_qp(P, q, G, h, A, b, lb, ub, options={"time_limit": 1e-12}, **kw)
        assert stopped.status == Status.TIME_LIMIT
        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, options={"time_limit": 60.0}, **kw)
        check(P, q, G, h, A, b, lb, ub, r)
        assert r.pivots == 0


def _ends():
    from lemke import _core
    return np.array(_core.qp_warm_ends())


def test_failed_warm_steps_restart_from_their_set_and_pass_kkt(method):
    """The MPC loop warm from the previous step: where the old active set and its updates
    fail (warm_point), Lemke's method is restarted from the nearest set tried (qp.cpp's
    restart) instead of the cold LCP. Every step's answer passes the KKT conditions checked
    here and is cold's x; some steps end on the restart (lemke._core.qp_warm_ends counts it),
    none on the cold LCP."""
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=100, seed=0)
    ws = None
    before = _ends()
    for q, b in steps:
        cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
        warm = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, warm_start=ws)
        check(P, q, G, h, A, b, lb, ub, warm)
        np.testing.assert_allclose(warm.x, cold.x, rtol=0, atol=1e-8)
        ws = warm.warm_start
    kept, restarted, fell_back = _ends() - before
    assert kept + restarted + fell_back == len(steps) - 1
    assert restarted >= 5 and fell_back == 0, (kept, restarted, fell_back)


def test_a_warm_start_far_from_right_restarts_and_passes_kkt(method):
    """Warm starts far from the answer: another step's basis (20 steps away), the basis of
    the same QP with the reference and the state reversed, and the right basis with 3, 8, 15
    of its pairs flipped (the more flipped, the more bounds taken as active: beyond the free
    directions' count no set can be factored, and the cold LCP solves it): each solve passes
    the KKT conditions checked here, at cold's x; the far bases end on the restart."""
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=60, seed=2)
    rng = np.random.default_rng(7)
    before = _ends()
    solves = 0
    for t in range(0, 40, 4):
        q, b = steps[t]
        cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
        check(P, q, G, h, A, b, lb, ub, cold)
        q2, b2 = steps[t + 20]
        guesses = [lemke.solve_qp(P, q2, G, h, A, b2, lb, ub).warm_start,
                   lemke.solve_qp(P, -q, G, h, A, -b, lb, ub).warm_start]
        npairs = cold.warm_start.n
        right = np.zeros(npairs, bool)
        right[list(cold.warm_start.z_basic)] = True
        for size in (3, 8, 15):
            flip = right.copy()
            flip[rng.choice(npairs, size, replace=False)] ^= True
            guesses.append(lemke.WarmStart(npairs, tuple(np.flatnonzero(flip).tolist())))
        for ws in guesses:
            r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, warm_start=ws)
            check(P, q, G, h, A, b, lb, ub, r)
            np.testing.assert_allclose(r.x, cold.x, rtol=0, atol=1e-8)
            solves += 1
    kept, restarted, fell_back = _ends() - before
    assert kept + restarted + fell_back == solves
    assert restarted >= 20, (kept, restarted, fell_back)  # of 50 (20 far bases)


@pytest.mark.parametrize("seed", range(4))
def test_wrong_guesses_on_random_qps_pass_kkt(seed, method):
    """Random convex QPs (inequalities, equalities, bounds), warm starts from random pairs
    and wild initvals: every solve passes the KKT conditions checked here at cold's x,
    whichever way it ends (the old set, the restart, the cold LCP); the restart is among
    them."""
    rng = np.random.default_rng(300 + seed)
    before = _ends()
    for n, m, p in ((30, 20, 5), (40, 45, 10)):
        P, q, G, h, A, b, lb, ub = random_convex_qp(n, rng, m, p)
        cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method)
        check(P, q, G, h, A, b, lb, ub, cold)
        npairs = cold.warm_start.n
        for size in (1, 4, 10, 20):
            basic = np.sort(rng.choice(npairs, min(size, npairs), replace=False))
            ws = lemke.WarmStart(npairs, tuple(basic.tolist()))
            r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method, warm_start=ws)
            check(P, q, G, h, A, b, lb, ub, r)
            np.testing.assert_allclose(r.x, cold.x, rtol=0, atol=1e-8)
        for scale in (0.1, 10.0):
            r = lemke.solve_qp(P, q, G, h, A, b, lb, ub, method=method,
                               initvals=cold.x + scale * rng.standard_normal(n))
            check(P, q, G, h, A, b, lb, ub, r)
            np.testing.assert_allclose(r.x, cold.x, rtol=0, atol=1e-8)
    assert (_ends() - before)[1] > 0


def test_factor_cache_hit_test_is_exact_on_every_entry():
    """The cache's hit test (qp::same_matrices on its compact BitKey: the runs of entries that
    are not +0 and their bits) compares every entry of P, A and G bit for bit: a zero made
    -0.0 or nonzero, inside a run of nonzeros or in a long gap of zeros, misses (counted
    by _core.qp_cache_hits) and is solved afresh, with the bits of a solve from no cache; a
    NaN put in a zero's place misses too, and the kernel's screen refuses it.  (The MPC
    problem's A holds -0.0's, from -Bd and -Ad: a -0.0 made +0.0 must miss as well.)"""
    from lemke import _core, _qp

    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=2, seed=3)
    q, b = steps[1]
    n, p, m = P.shape[0], A.shape[0], G.shape[0]
    out = np.empty(_qp._layout(n, p, m)[-1])
    other = random_convex_qp(12, np.random.default_rng(5), 4, 2)

    def kernel(P, G, A):
        code = _core.qp_solve(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out)[0]
        return code, out.copy()

    def fresh(P, G, A):
        lemke.solve_qp(*other)  # (the cache now holds another QP's factors)
        return kernel(P.copy(), G.copy(), A.copy())

    base = kernel(P, G, A)
    hits = _core.qp_cache_hits()
    assert base[0] == 0
    again = kernel(P, G, A)
    assert _core.qp_cache_hits() == hits + 1  # the same bits: a hit
    assert again[0] == 0 and again[1].tobytes() == base[1].tobytes()
    rng = np.random.default_rng(0)
    picked = 0
    for name in ("P", "A", "G"):
        M = {"P": P, "A": A, "G": G}[name]
        zeros = np.argwhere(M == 0.0)
        nonzero = M != 0.0
        # zeros next to a nonzero in their row (inside a run) and far from any (a long gap)
        near = [z for z in zeros if nonzero[z[0], max(z[1] - 1, 0):z[1] + 2].any()]
        far = [z for z in zeros if not nonzero[z[0], max(z[1] - 9, 0):z[1] + 10].any()]
        assert near and far, name
        for i, j in [near[k] for k in rng.choice(len(near), 4, replace=False)] + \
                    [far[k] for k in rng.choice(len(far), 4, replace=False)]:
            was, was_t = M[i, j], M[j, i] if name == "P" else None
            for value in (-was, 1e-3, np.nan):  # (-was: the zero's sign flipped; A has -0.0's)
                kernel(P, G, A)  # the cache holds the data as it is
                hits = _core.qp_cache_hits()
                M[i, j] = value
                if name == "P" and value == value:  # (P stays symmetric)
                    M[j, i] = value
                got = kernel(P, G, A)
                assert _core.qp_cache_hits() == hits, (name, i, j, value)  # a miss
                if value != value:
                    assert got[0] == _core.QP_BAD_INPUT  # the screen's verdict, not stale factors
                else:
                    want = fresh(P, G, A)
                    assert got[0] == want[0] and got[1].tobytes() == want[1].tobytes()
                    r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
                    check(P, q, G, h, A, b, lb, ub, r)
                M[i, j] = was
                if name == "P":
                    M[j, i] = was_t
                picked += 1
    assert picked == 3 * 8 * 3
    kernel(P, G, A)
    hits = _core.qp_cache_hits()
    kernel(P, G, A)  # restored: a hit again
    assert _core.qp_cache_hits() == hits + 1
