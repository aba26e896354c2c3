"""solve_lcp_batch: every problem gets exactly what solve_lcp gives it, checked independently."""
import json
from pathlib import Path

import numpy as np
import pytest
from helpers import assert_lcp_solution, assert_ray
from siconos_dat import read_lcp

import lemke
from lemke import Status, problems
from lemke.kernels.cold import RESTART_FROM

DATA = Path(__file__).parent / "data"


def assert_same_as_one_by_one(M, q, method, **kw):
    """Row b of the batch result is solve_lcp's answer for problem b, bit for bit; every
    solved row also passes the independent check."""
    M = np.asarray(M, float)
    q = np.asarray(q, float)
    res = lemke.solve_lcp_batch(M, q, method=method, **kw)
    B, n = q.shape
    assert res.z.shape == res.w.shape == (B, n)
    assert res.status.shape == res.pivots.shape == res.residual.shape == (B,)
    for b in range(B):
        Mb = M if M.ndim == 2 else M[b]
        one = lemke.solve_lcp(Mb, q[b], method=method, options=kw.get("options"))
        assert res.status[b] == one.status and res.pivots[b] == one.pivots, b
        assert np.array_equal(res.z[b], one.z) and np.array_equal(res.w[b], one.w), b
        assert res.residual[b] == one.residual
        if one.status == Status.SOLVED:
            assert_lcp_solution(Mb, q[b], res.z[b])
        elif one.status == Status.RAY_TERMINATION:
            assert_ray(Mb, q[b], one.covering, one.z, one.z0, one.ray)
    assert np.array_equal(res.success, res.status == Status.SOLVED)
    return res


@pytest.mark.parametrize("workers", [1, 3])
def test_random_families(method, workers):
    rng = np.random.default_rng(5)
    for gen in (problems.random_psd, problems.random_p_matrix, problems.contact_like):
        for n in (1, 4, 13, 40):
            pairs = [gen(n, rng) for _ in range(7)]
            M = np.stack([p[0] for p in pairs])
            q = np.stack([p[1] for p in pairs])
            q[2] = np.abs(q[2])  # q >= 0: z = 0 with no pivot
            res = assert_same_as_one_by_one(M, q, method, workers=workers)
            assert res.success.all()


def test_shared_M_many_q(method):
    rng = np.random.default_rng(8)
    M, _ = problems.random_psd(25, rng)
    q = rng.standard_normal((50, 25))
    assert_same_as_one_by_one(M, q, method)


def test_every_outcome_in_one_batch(method):
    """Solved, ray, pivot limit and q >= 0, side by side, with non-contiguous input."""
    rows = [
        (problems.murty(4).M, problems.murty(4).q),  # 16 pivots: MAX_PIVOTS with a cap of 10
        (np.array([[-1.0, 0.0], [0.0, 1.0]]), np.array([-1.0, -1.0])),  # ray
        (problems.degenerate().M, problems.degenerate().q),
        (np.eye(2), np.array([1.0, 0.0])),
    ]
    M = np.zeros((4, 4, 4))
    q = np.zeros((4, 4))
    for b, (Mb, qb) in enumerate(rows):  # pad to n = 4 with an identity block and q = 1
        k = len(qb)
        M[b] = np.eye(4)
        M[b, :k, :k] = Mb
        q[b] = 1.0
        q[b, :k] = qb
    Mt = np.asfortranarray(M)
    res = assert_same_as_one_by_one(Mt, q[:, ::1], method, options={"max_pivots": 10})
    assert res.status.tolist() == [Status.MAX_PIVOTS, Status.RAY_TERMINATION, Status.SOLVED, Status.SOLVED]


def test_peer_problems_of_one_size(method):
    """The Drake and Siconos problems, grouped by size."""
    by_n = {}
    for case in json.loads((DATA / "drake" / "cases.json").read_text()):
        n = case["n"]
        by_n.setdefault(n, []).append((np.array(case["M"], float).reshape(n, n), np.array(case["q"], float)))
    for path in sorted((DATA / "siconos" / "lcp").glob("*.dat")):
        M, q = read_lcp(path)
        by_n.setdefault(q.size, []).append((M, q))
    for group in by_n.values():
        assert_same_as_one_by_one(np.stack([m for m, _ in group]), np.stack([v for _, v in group]), method)


def test_inputs_are_not_modified_and_results_are_read_only():
    rng = np.random.default_rng(3)
    M = np.stack([problems.random_psd(6, rng)[0] for _ in range(5)])
    q = rng.standard_normal((5, 6))
    M0, q0 = M.copy(), q.copy()
    res = lemke.solve_lcp_batch(M, q)
    assert np.array_equal(M, M0) and np.array_equal(q, q0)
    for a in (res.z, res.w, res.status, res.pivots, res.residual):
        assert not a.flags.writeable
    assert "B=5" in repr(res)


def test_integer_input_and_empty_batches():
    res = lemke.solve_lcp_batch([[2, 1], [1, 2]], [[-5, -6]])
    np.testing.assert_allclose(res.z, [[4 / 3, 7 / 3]])
    empty = lemke.solve_lcp_batch(np.eye(3), np.zeros((0, 3)))
    assert empty.z.shape == (0, 3) and empty.status.shape == (0,)
    zero = lemke.solve_lcp_batch(np.zeros((2, 0, 0)), np.zeros((2, 0)))
    assert zero.success.all() and zero.z.shape == (2, 0)


@pytest.mark.parametrize(
    "M, q, exc, words",
    [
        (np.eye(3), np.zeros(3), ValueError, "q must have shape (B, n)"),
        (np.eye(3), np.zeros((2, 4)), ValueError, "shared M"),
        (np.ones((2, 3, 3)), np.zeros((3, 3)), ValueError, "M must have shape (3, 3, 3)"),
        (np.ones((2, 3, 4)), np.zeros((2, 3)), ValueError, "M must have shape"),
        (np.ones(3), np.zeros((2, 3)), ValueError, "M must have shape"),
        (np.eye(2), [[0.0, np.nan]], ValueError, "q has a NaN"),
        (np.full((1, 2, 2), np.inf), np.zeros((1, 2)), ValueError, "M has a NaN or infinite"),
        (np.array([["a"]]), np.zeros((1, 1)), TypeError, "M must hold real numbers"),
        (np.eye(1), np.array([[1j]]), TypeError, "q must hold real numbers"),
    ],
)
def test_bad_input_names_the_argument(M, q, exc, words):
    with pytest.raises(exc, match=words.replace("(", r"\(").replace(")", r"\)")):
        lemke.solve_lcp_batch(M, q)


def test_bad_method_options_and_workers():
    with pytest.raises(ValueError, match="unknown method"):
        lemke.solve_lcp_batch(np.eye(2), np.zeros((1, 2)), method="simplex")
    with pytest.raises(ValueError, match="unknown option"):
        lemke.solve_lcp_batch(np.eye(2), np.zeros((1, 2)), options={"speed": 1})
    for bad in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match="workers"):
            lemke.solve_lcp_batch(np.eye(2), np.zeros((1, 2)), workers=bad)


# --- warm starts in a batch, and problems of different sizes (solve_lcp_many) -------------

def _islands(seed, count=40):
    """Contact-like islands of 1..14 rows (tests/contact_sim-like rank-deficient LCPs) and a
    nearby problem for each (q moved a little), as a simulation's next step."""
    rng = np.random.default_rng(seed)
    Ms, qs, qs2 = [], [], []
    for _ in range(count):
        n = int(rng.integers(0, 15))
        M, q = problems.contact_like(n, rng) if n >= 2 else (np.eye(n) * 2.0, -np.ones(n))
        Ms.append(M)
        qs.append(q)
        qs2.append(q + 1e-3 * rng.standard_normal(n))
    return Ms, qs, qs2


@pytest.mark.parametrize("method", lemke.METHODS)
def test_many_is_bit_identical_to_one_by_one_for_any_workers(method):
    Ms, qs, qs2 = _islands(1)
    first = [lemke.solve_lcp(M, q, method=method) for M, q in zip(Ms, qs)]
    ws = [r.warm_start for r in first]
    ws[3] = None  # a cold one among the warm
    single = [lemke.solve_lcp(M, q, method=method, warm_start=w) for M, q, w in zip(Ms, qs2, ws)]
    for workers in (1, 2, 4):
        many = lemke.solve_lcp_many(Ms, qs2, method=method, warm_start=ws, workers=workers)
        assert len(many) == len(single)
        for a, b in zip(many, single):
            assert a == b  # every field, bit for bit (results are values)
    for r, M, q in zip(single, Ms, qs2):
        if r.success:
            assert_lcp_solution(M, q, r.z)
    assert sum(r.pivots for r in single) < sum(lemke.solve_lcp(M, q).pivots for M, q in zip(Ms, qs2))


@pytest.mark.parametrize("method", lemke.METHODS)
@pytest.mark.parametrize("n, move", [(10, 1e-3), (30, 0.3), (RESTART_FROM, 1e-3), (RESTART_FROM, 0.3)])
def test_batch_with_warm_starts_is_bit_identical(method, n, move):
    """solve_lcp (whose tableau warm starts go through the lean first_run, then solve_one
    for a restart at n >= RESTART_FROM) gives the batch's bits (solve_one alone)."""
    rng = np.random.default_rng(2)
    B = 30
    A = rng.standard_normal((n, n))
    M = A @ A.T + 0.1 * np.eye(n)
    Q = rng.standard_normal((B, n))
    ws = [lemke.solve_lcp(M, q, method=method).warm_start for q in Q]
    Q2 = Q + move * rng.standard_normal((B, n))
    for workers in (1, 2, 4):
        r = lemke.solve_lcp_batch(M, Q2, method=method, warm_start=ws, workers=workers)
        for b in range(B):
            one = lemke.solve_lcp(M, Q2[b], method=method, warm_start=ws[b])
            assert r.z[b].tobytes() == one.z.tobytes()
            assert (r.status[b], r.pivots[b]) == (one.status, one.pivots)


def test_many_bad_input():
    with pytest.raises(ValueError, match="same number"):
        lemke.solve_lcp_many([np.eye(2)], [])
    with pytest.raises(ValueError, match="problem 1"):
        lemke.solve_lcp_many([np.eye(2), np.eye(2)], [[1.0, 1.0], [1.0]])
    with pytest.raises(ValueError, match="warm_start"):
        lemke.solve_lcp_many([np.eye(2)], [[1.0, 1.0]], warm_start=[lemke.WarmStart(3, ())])
    with pytest.raises(ValueError, match="one WarmStart"):
        lemke.solve_lcp_batch(np.eye(2), [[1.0, 1.0]], warm_start=[])
    assert lemke.solve_lcp_many([], []) == []
