"""solve_lcp_batch: every problem gets exactly what solve_lcp gives it, checked independently."""
import json
import pickle
from pathlib import Path

import numpy as np
import pytest
from helpers import assert_lcp_solution, assert_ray, native_fronts_off
from siconos_dat import read_lcp

import lemke
from lemke import Status, problems
from lemke._layout import RESTART_FROM

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


# --- the flat fields of solve_lcp_many and the WarmStartBatch --------------------------

def _rays_and_trivial(Ms, qs):
    """The islands with a ray (a copositive-plus M with an infeasible q) and a q >= 0 among
    them, so that every kind of result is in the batch."""
    Ms, qs = list(Ms), list(qs)
    Ms[5], qs[5] = np.array([[1.0, -1.0], [-1.0, 1.0]]), np.array([-1.0, -1.0])  # infeasible
    qs[6] = np.abs(qs[6])
    return Ms, qs


def _assert_flat_is_items(res, Ms, qs):
    """Every flat field of an LCPManyResult is its items' field, bit for bit; solved islands
    pass an independent numpy check on the flat z and w."""
    B = len(Ms)
    sizes = [len(q) for q in qs]
    assert len(res) == B and res.offsets.tolist() == np.concatenate([[0], np.cumsum(sizes)]).tolist()
    for name in ("offsets", "z", "w", "status", "success", "pivots", "recoveries", "residual"):
        a = getattr(res, name)
        assert not a.flags.writeable, name
        assert getattr(res, name) is a  # made once
    assert res.z.dtype == res.w.dtype == np.float64 and res.status.dtype == np.int64
    for b, (r, M, q) in enumerate(zip(res, Ms, qs)):
        lo, hi = res.offsets[b], res.offsets[b + 1]
        assert res.z[lo:hi].tobytes() == r.z.tobytes() and res.w[lo:hi].tobytes() == r.w.tobytes(), b
        assert (res.status[b], res.pivots[b], res.recoveries[b]) == (int(r.status), r.pivots, r.recoveries)
        assert res.residual[b].tobytes() == np.float64(r.residual).tobytes()
        assert res.success[b] == r.success
        assert res.warm_start[b] == r.warm_start
    # the independent check, on the flat arrays: w = M z + q recomputed, z >= 0, w >= 0, z'w = 0
    for b in np.flatnonzero(res.success):
        lo, hi = res.offsets[b], res.offsets[b + 1]
        z, M, q = res.z[lo:hi], np.asarray(Ms[b], float), np.asarray(qs[b], float)
        assert_lcp_solution(M, q, z)
        scale = max(1.0, np.abs(M).max(initial=0) * np.abs(z).max(initial=0), np.abs(q).max(initial=0))
        assert np.allclose(res.w[lo:hi], M @ z + q, rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("method", lemke.METHODS)
def test_many_flat_fields_are_the_items_and_one_by_one(method):
    Ms, qs, qs2 = _islands(3, count=50)
    Ms, qs = _rays_and_trivial(Ms, qs)
    res = lemke.solve_lcp_many(Ms, qs, method=method)
    assert isinstance(res, lemke.LCPManyResult)
    assert {Status.SOLVED, Status.RAY_TERMINATION} <= set(res.status.tolist())
    assert res.pivots[6] == 0 and res.success[6]  # q >= 0
    _assert_flat_is_items(res, Ms, qs)
    single = [lemke.solve_lcp(M, q, method=method) for M, q in zip(Ms, qs)]
    assert res == single  # every field of every item, bit for bit
    for b, (r, M, q) in enumerate(zip(single, Ms, qs)):
        if r.status == Status.RAY_TERMINATION:
            assert_ray(M, q, r.covering, r.z, r.z0, r.ray)
    for workers in (1, 2, 4):
        other = lemke.solve_lcp_many(Ms, qs, method=method, workers=workers)
        for name in ("z", "w", "status", "pivots", "residual", "offsets"):
            assert getattr(other, name).tobytes() == getattr(res, name).tobytes(), (workers, name)
        assert other.warm_start == res.warm_start


@pytest.mark.parametrize("method", lemke.METHODS)
def test_warm_start_batch_passed_back_is_each_warm_start(method):
    """A simulation's step: the last result's WarmStartBatch passed back whole gives what
    the list of its WarmStarts gives, and what solve_lcp gives each island, bit for bit."""
    Ms, qs, qs2 = _islands(4, count=50)
    Ms, qs = _rays_and_trivial(Ms, qs)
    qs2[5] = qs[5]
    first = lemke.solve_lcp_many(Ms, qs, method=method)
    batch = first.warm_start
    assert isinstance(batch, lemke.WarmStartBatch) and len(batch) == len(Ms)
    assert list(batch) == [r.warm_start for r in first]
    for workers in (1, 2):
        flat = lemke.solve_lcp_many(Ms, qs2, method=method, warm_start=batch, workers=workers)
        listed = lemke.solve_lcp_many(Ms, qs2, method=method, warm_start=list(batch), workers=workers)
        assert flat == listed
        _assert_flat_is_items(flat, Ms, qs2)
        for b, (r, M, q) in enumerate(zip(flat, Ms, qs2)):
            assert r == lemke.solve_lcp(M, q, method=method, warm_start=batch[b]), b
    assert (flat.pivots == 0).sum() > (first.pivots == 0).sum()  # the old bases still solve many
    assert flat.pivots.sum() < lemke.solve_lcp_many(Ms, qs2, method=method).pivots.sum()
    # a batch from problems of one size goes to solve_lcp_batch too
    M = 2.0 * np.eye(3) + 0.5
    Q = np.random.default_rng(5).standard_normal((6, 3))
    ws = lemke.solve_lcp_many([M] * 6, list(Q)).warm_start
    Q2 = Q + 1e-3
    a = lemke.solve_lcp_batch(M, Q2, method=method, warm_start=ws)
    b = lemke.solve_lcp_batch(M, Q2, method=method, warm_start=list(ws))
    assert a == b and (a.pivots == 0).all()


def test_many_result_is_a_sequence_of_results():
    Ms, qs, _ = _islands(6, count=12)
    res = lemke.solve_lcp_many(Ms, qs, workers=1)
    single = [lemke.solve_lcp(M, q) for M, q in zip(Ms, qs)]
    assert res[3] is res[3] and res[-1] == single[-1] and res[2:5] == single[2:5]
    with pytest.raises(IndexError):
        res[12]
    with pytest.raises(TypeError):
        res["a"]
    assert res + [single[0]] == single + [single[0]] and [single[0]] + res == [single[0]] + single
    assert res + res == single + single
    assert res == lemke.solve_lcp_many(Ms, qs, workers=2) and res != single[:-1] and res != "no"
    assert hash(res) == hash(lemke.solve_lcp_many(Ms, qs)) and single[4] in res and res.index(single[4]) == 4
    back = pickle.loads(pickle.dumps(res))
    assert back == res and not back.z.flags.writeable and back.z.tobytes() == res.z.tobytes()
    assert back.warm_start == res.warm_start
    assert "B=12" in repr(res) and "B=12" in repr(res.warm_start)
    empty = lemke.solve_lcp_many([], [])
    assert empty == [] and len(empty) == 0 and empty.z.size == 0 and empty.offsets.tolist() == [0]
    assert len(empty.warm_start) == 0
    assert lemke.solve_lcp_many([], [], warm_start=empty.warm_start) == []


def test_many_flat_fields_of_results_built_by_the_general_path():
    """Results that are not solved and checked (here MAX_PIVOTS), built by solve_lcp's own
    logic, are in the flat fields as their items hold them."""
    Ms, qs, _ = _islands(8, count=30)
    res = lemke.solve_lcp_many(Ms, qs, options={"max_pivots": 2})
    assert Status.MAX_PIVOTS in set(res.status.tolist())
    _assert_flat_is_items(res, Ms, qs)
    assert res == [lemke.solve_lcp(M, q, options={"max_pivots": 2}) for M, q in zip(Ms, qs)]


def test_warm_start_batch_is_a_checked_value():
    ws = lemke.WarmStartBatch([2, 3, 0], [1, 0, 2], [0, 1, 3, 3])
    assert list(ws) == [lemke.WarmStart(2, (1,)), lemke.WarmStart(3, (0, 2)), lemke.WarmStart(0, ())]
    assert ws == lemke.WarmStartBatch(np.array([2, 3, 0]), (1, 0, 2), [0, 1, 3, 3]) and len({ws, ws}) == 1
    assert pickle.loads(pickle.dumps(ws)) == ws and not pickle.loads(pickle.dumps(ws)).n.flags.writeable
    assert ws[-2] == ws[1] and ws.z_basic.dtype == np.int64 and not ws.offsets.flags.writeable
    for bad in (([2], [2], [0, 1]), ([2], [1, 0], [0, 2]), ([2], [1, 1], [0, 2]), ([2], [-1], [0, 1]),
                ([2, 2], [0], [0, 1]), ([2], [0], [1, 1]), ([2], [0], [0, 2]), ([-1], [], [0, 0])):
        with pytest.raises(ValueError):
            lemke.WarmStartBatch(*bad)
    with pytest.raises(TypeError):
        lemke.WarmStartBatch([2.5], [0], [0, 1])
    with pytest.raises(IndexError):
        ws[3]
    # it must fit the problems
    Ms, qs = [np.eye(2), np.eye(3), np.eye(2)], [-np.ones(2), -np.ones(3), -np.ones(2)]
    with pytest.raises(ValueError, match=r"warm_start\[2\] is for a problem of size 0"):
        lemke.solve_lcp_many(Ms, qs, warm_start=ws)
    with pytest.raises(ValueError, match="one basis per problem"):
        lemke.solve_lcp_many(Ms[:2], qs[:2], warm_start=ws)
    res = lemke.solve_lcp_many(Ms, qs, warm_start=lemke.WarmStartBatch([2, 3, 2], [0, 1, 0, 1, 2], [0, 2, 5, 5]))
    assert res.pivots[:2].tolist() == [0, 0] and res.pivots[2] > 0 and res.success.all()  # the last one cold


# --- packed problems: solve_lcp_many(M, q, sizes=...) -------------------------------------

def _pack(Ms, qs):
    """The islands packed by hand with numpy (independent of the front's own packing)."""
    sizes = np.array([len(q) for q in qs], dtype=np.int64)
    return (np.concatenate([np.asarray(M, float).ravel() for M in Ms] + [np.zeros(0)]),
            np.concatenate([np.asarray(q, float) for q in qs] + [np.zeros(0)]), sizes)


def test_lists_packed_natively_or_by_python_are_the_same():
    """_core.lcp_pack packs lists of ready arrays (float64 C arrays, writable or not: what
    _pack does by hand) or of array-likes made_f64 converts, and declines anything else (None: the Python path); both paths give the same results bit for bit."""
    from lemke import _core
    Ms, qs, qs2 = _islands(9, count=30)
    Ms, qs = _rays_and_trivial(Ms, qs)
    qs2[5] = qs[5]
    Ms = [np.ascontiguousarray(M, float) for M in Ms]
    qs = [np.asarray(q, float) for q in qs]
    Mf, qf, n_b = _core.lcp_pack(Ms, qs)
    Mp, qp, sizes = _pack(Ms, qs)
    assert Mf.tobytes() == Mp.tobytes() and qf.tobytes() == qp.tobytes()
    assert n_b.dtype == np.int64 and n_b.tolist() == sizes.tolist()
    assert _core.lcp_pack(tuple(Ms), tuple(qs))[0].tobytes() == Mp.tobytes()
    ro = Ms[3].copy()
    ro.setflags(write=False)
    taken = (Ms[:3] + [ro] + Ms[4:], qs)  # a read-only M: packed natively (only read)
    assert _core.lcp_pack(*taken)[0].tobytes() == Mp.tobytes()
    converted = [  # array-likes made_f64 converts: packed natively, the same values
        (Ms[:3] + [np.asfortranarray(Ms[3]) if len(qs[3]) > 1 else Ms[3].tolist()] + Ms[4:], qs),
        (Ms, qs[:3] + [qs[3].tolist()] + qs[4:]),  # a list
    ]
    for M, q in converted:
        got = _core.lcp_pack(M, q)
        assert got[0].tobytes() == Mp.tobytes() and got[1].tobytes() == qp.tobytes()
    declined = [  # each makes the native packing decline (the Python path then runs)
        (Ms, qs[:3] + [qs[3].astype(">f8" if np.little_endian else "<f8")] + qs[4:]),  # byte order
        (Ms, qs[:-1]),  # lengths differ
        (iter(Ms), qs),  # not a list or tuple
        ([], []),
    ]
    for M, q in declined:
        assert _core.lcp_pack(M, q) is None
    native = lemke.solve_lcp_many(Ms, qs)
    warm = lemke.solve_lcp_many(Ms, qs2, warm_start=native.warm_start)
    for M, q in [taken] + converted + declined[:1]:
        assert lemke.solve_lcp_many(M, q) == native
    assert warm == lemke.solve_lcp_many(taken[0], qs2, warm_start=native.warm_start)
    assert warm == [lemke.solve_lcp(M, q, warm_start=r.warm_start) for M, q, r in zip(Ms, qs2, native)]
    with pytest.raises(ValueError):
        lemke.solve_lcp_many(Ms, qs[:-1])


@pytest.mark.parametrize("method", lemke.METHODS)
def test_packed_problems_are_the_lists_bit_for_bit(method):
    Ms, qs, qs2 = _islands(9, count=50)
    Ms, qs = _rays_and_trivial(Ms, qs)
    qs2[5] = qs[5]
    Mp, qp, sizes = _pack(Ms, qs)
    Mp.setflags(write=False)  # a read-only caller's array is taken as well
    before = (Mp.tobytes(), qp.tobytes())
    listed = lemke.solve_lcp_many(Ms, qs, method=method)
    for workers in (1, 2, 4):
        packed = lemke.solve_lcp_many(Mp, qp, sizes=sizes, method=method, workers=workers)
        assert packed == listed  # every field of every item, bit for bit
        _assert_flat_is_items(packed, Ms, qs)
    assert (Mp.tobytes(), qp.tobytes()) == before  # nothing of the caller's is written
    # the next step, warm, packed: what the lists give, and each island one by one
    qp2 = np.concatenate(qs2)
    nxt = lemke.solve_lcp_many(Mp, qp2, sizes=list(sizes), method=method, warm_start=listed.warm_start)
    assert nxt == lemke.solve_lcp_many(Ms, qs2, method=method, warm_start=listed.warm_start)
    assert nxt == [lemke.solve_lcp(M, q, method=method, warm_start=r.warm_start)
                   for M, q, r in zip(Ms, qs2, listed)]
    assert (nxt.pivots == 0).sum() > (listed.pivots == 0).sum()
    # integer data are converted; an empty batch is allowed
    ints = lemke.solve_lcp_many(np.array([2, 1, 1, 2]), np.array([-5, -6]), sizes=[2])
    assert ints == [lemke.solve_lcp([[2.0, 1.0], [1.0, 2.0]], [-5.0, -6.0])]
    assert lemke.solve_lcp_many(np.zeros(0), np.zeros(0), sizes=[]) == []


def test_many_setup_is_the_python_steps():
    """_core.many_setup (ready packed arrays: int64 sizes, writable float64 M and q of the
    right lengths) gives the arrays the Python steps make (_batch._packed, _offsets summed,
    the pivot caps, the work), and declines (None) anything else, which the Python steps
    then check; either way the results are the same bit for bit."""
    from lemke import _batch, _core
    Ms, qs, qs2 = _islands(11, count=40)
    Ms, qs = _rays_and_trivial(Ms, qs)
    Mp, qp, sizes = _pack(Ms, qs)
    for cap, opts in ((-1, lemke.Options()), (3, lemke.Options(max_pivots=3))):
        off, limits, work, listed, bufs, basics, out_i, out_f = _core.many_setup(sizes, Mp, qp, cap)
        Mf, qf, want = _batch._packed(Mp, qp, sizes)
        assert Mf is Mp and qf is qp
        n_b = want[0, 1:].copy()
        assert work == _batch._cubes(n_b)
        np.cumsum(want, axis=1, out=want)
        assert off.dtype == np.int64 and off.tolist() == want.tolist()
        assert limits.dtype == np.int64 and limits.tolist() == [opts.pivot_limit(int(n)) for n in n_b]
        assert listed == n_b.tolist() and all(type(n) is int for n in listed)
        assert bufs.shape == (want[2, -1],) and bufs.dtype == np.float64
        assert basics.shape == (want[0, -1],) and basics.dtype == np.int64
        assert out_i.shape == (40, 5) and out_i.dtype == np.int64 and out_i.flags.c_contiguous
        assert out_f.shape == (40, 2) and out_f.dtype == np.float64 and out_f.flags.c_contiguous
        flat = lemke.solve_lcp_many(Mp, qp, sizes=sizes, options=opts)
        assert flat == lemke.solve_lcp_many(Mp, qp, sizes=sizes.astype(np.int32), options=opts)
        assert flat == [lemke.solve_lcp(M, q, options=opts) for M, q in zip(Ms, qs)]
    ro = Mp.copy()
    ro.setflags(write=False)
    bad = sizes.copy()
    bad[0] = -1
    for args in ((sizes.astype(np.int32), Mp, qp), (sizes.tolist(), Mp, qp), (sizes, ro, qp),
                 (sizes, Mp, qp.astype(np.float32)), (sizes, Mp[:-1], qp), (sizes, Mp, qp[1:]),
                 (bad, Mp, qp), (sizes[:, None], Mp, qp), (sizes[:0], Mp[:0], qp[:0]),
                 (sizes, Mp.reshape(1, -1), qp)):
        assert _core.many_setup(*args, -1) is None
    # the kernels' outputs read back natively: what numpy's gathers give
    rs = lemke.solve_lcp_many(Mp, qp, sizes=sizes)
    off, out_i, out_f, bufs = rs._off, rs._out_i, rs._out_f, rs._bufs
    code = out_i[:, 0]
    not_finite, unsettled = _core.many_unsettled(out_i, out_f)
    assert not_finite == np.flatnonzero(code == -1).tolist()
    assert unsettled == np.flatnonzero((out_f[:, 0] == 0.0) | ((code != 0) & (code != -2) & (code != 2))).tolist()
    assert unsettled == sorted(rs._special)
    qo, bo = off[0], off[2]
    for a, c in ((0, 0), (2, 2)):
        got = _core.many_field(bufs, bo, qo, a, c)
        assert got.tolist() == np.concatenate([bufs[bo[b] + a * n + c : bo[b] + a * n + c + n]
                                               for b, n in enumerate(np.diff(qo))]).tolist()
    z_basic, boff, n = _core.many_bases(rs._basics, qo, out_i)
    assert n.dtype == np.int64 and n.tolist() == np.diff(qo).tolist()
    assert boff.tolist() == [0] + np.cumsum(out_i[:, 2]).tolist()
    assert z_basic.tolist() == [i for b, k in enumerate(out_i[:, 2]) for i in rs._basics[qo[b] : qo[b] + k]]
    with pytest.raises(ValueError):
        _core.many_field(bufs, bo, qo, 7, 0)  # past the buffers' spans


def test_many_without_the_native_fronts():
    """Where lcp_front_init finds another NumPy layout the native fronts stay off: many_setup,
    many_unsettled, many_field and many_bases return None and the Python steps (numpy) make
    the same result, bit for bit."""
    from lemke import _core
    Ms, qs, qs2 = _islands(12, count=30)
    Ms, qs = _rays_and_trivial(Ms, qs)
    qs2[5] = qs[5]
    Mp, qp, sizes = _pack(Ms, qs)
    on = lemke.solve_lcp_many(Mp, qp, sizes=sizes)
    nxt = lemke.solve_lcp_many(Ms, qs2, warm_start=on.warm_start)
    flat = [(r.z, r.w, r.offsets, r.status, r.warm_start) for r in (on, nxt)]
    with native_fronts_off():
        assert _core.many_setup(sizes, Mp, qp, -1) is None
        assert _core.many_unsettled(on._out_i, on._out_f) is None
        assert _core.many_field(on._bufs, on._off[2], on._off[0], 0, 0) is None
        assert _core.many_bases(on._basics, on._off[0], on._out_i) is None
        off = lemke.solve_lcp_many(Mp, qp, sizes=sizes)
        nxt_off = lemke.solve_lcp_many(Ms, qs2, warm_start=off.warm_start)
        got = [(r.z, r.w, r.offsets, r.status, r.warm_start) for r in (off, nxt_off)]
    assert off == on and nxt_off == nxt
    for a, b in zip(got, flat):
        assert all(x.tobytes() == y.tobytes() for x, y in zip(a[:4], b[:4])) and a[4] == b[4]


def test_packed_problems_bad_input():
    Mp, qp, sizes = _pack([np.eye(2), 2.0 * np.eye(3)], [-np.ones(2), -np.ones(3)])
    for bad, exc, match in (([[2, 3]], TypeError, "1-D array of integers"),
                            ([2.0, 3.0], TypeError, "1-D array of integers"),
                            ([2, -3], ValueError, ">= 0"),
                            ([2, 2], ValueError, "packed M must be 1-D with 8 numbers"),
                            ([1, 4], ValueError, "packed M")):
        with pytest.raises(exc, match=match):
            lemke.solve_lcp_many(Mp, qp, sizes=bad)
        with pytest.raises(exc, match=match):  # an array: the native set-up declines it
            lemke.solve_lcp_many(Mp, qp, sizes=np.array(bad))
    with pytest.raises(ValueError, match="packed q"):
        lemke.solve_lcp_many(Mp, qp[:-1], sizes=sizes)
    with pytest.raises(ValueError, match="packed M"):
        lemke.solve_lcp_many(Mp.reshape(1, -1), qp, sizes=sizes)
    with pytest.raises(TypeError, match="real numbers"):
        lemke.solve_lcp_many(Mp.astype(complex), qp, sizes=sizes)
    bad = Mp.copy()
    bad[4 + 3 * 1 + 2] = np.inf  # problem 1, row 1, column 2
    with pytest.raises(ValueError, match=r"problem 1: M has a NaN or infinite entry at index \(1, 2\)"):
        lemke.solve_lcp_many(bad, qp, sizes=sizes)
    with pytest.raises(ValueError, match=r"warm_start\[0\] is for a problem of size 3"):
        lemke.solve_lcp_many(Mp, qp, sizes=sizes, warm_start=[lemke.WarmStart(3, ()), None])


def _batch_in_child(conn):
    rs = lemke.solve_lcp_batch(*_fork_problems(), workers=2)
    conn.send(rs.z.tolist())


def _fork_problems():
    """Four problems of 40 rows: work over _batch.INLINE_WORK, so that a batch of them is
    handed to the pool (a smaller one runs in the calling thread)."""
    from lemke import _batch
    rng = np.random.default_rng(7)
    A = rng.standard_normal((4, 40, 40))
    assert 4 * 40 ** 3 >= _batch.INLINE_WORK
    return A @ A.transpose(0, 2, 1) + np.eye(40), rng.standard_normal((4, 40))


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="fork is POSIX")
def test_a_forked_child_runs_parallel_batches():
    """The batch pool's threads are the parent's: a child made by fork after a parallel
    batch starts a pool of its own (before, its first parallel batch waited forever)."""
    import multiprocessing as mp
    M, q = _fork_problems()
    here = lemke.solve_lcp_batch(M, q, workers=2)  # the parent's pool exists now
    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe()
    p = ctx.Process(target=_batch_in_child, args=(child,))
    p.start()
    got = parent.recv() if parent.poll(30) else None
    p.join(5)
    if p.is_alive():
        p.kill()
    assert got is not None, "the forked child's batch did not finish"
    assert np.array_equal(np.array(got), here.z)
    for b in range(q.shape[0]):
        assert_lcp_solution(M[b], q[b], here.z[b])


# --- a few problems: solved one by one with solve_lcp (_batch.FEW) ----------------------

def _flat_fields(res):
    return [getattr(res, name).tobytes() for name in
            ("offsets", "z", "w", "status", "success", "pivots", "recoveries", "residual")]


@pytest.mark.parametrize("method", lemke.METHODS)
def test_a_few_problems_give_the_batch_paths_bits(method, monkeypatch):
    """Up to FEW problems ready for the kernels go through solve_lcp one by one: every item
    and every flat field (the final bases included) is what the batch path gives, bit for
    bit, cold, warm from a list and warm from a WarmStartBatch; rays and q >= 0 included."""
    from lemke import _batch
    Ms, qs, qs2 = _islands(7, count=48)
    Ms, qs = _rays_and_trivial(Ms, qs)
    qs2[5] = qs[5]
    keep = [b for b in range(len(Ms)) if len(qs[b])]  # (an empty problem takes the batch path)
    Ms, qs, qs2 = [Ms[b] for b in keep], [qs[b] for b in keep], [qs2[b] for b in keep]
    seen, FEW = set(), _batch.FEW
    for lo in range(0, len(Ms), FEW):
        M, q, q2 = Ms[lo : lo + FEW], qs[lo : lo + FEW], qs2[lo : lo + FEW]
        runs = {}
        for few in (FEW, 0):
            monkeypatch.setattr(_batch, "FEW", few)
            cold = lemke.solve_lcp_many(M, q, method=method)
            listed = lemke.solve_lcp_many(M, q2, method=method, warm_start=[r.warm_start for r in cold])
            flat = lemke.solve_lcp_many(tuple(M), q2, method=method, warm_start=cold.warm_start, workers=1)
            runs[few] = (cold, listed, flat)
            for res, qq in ((cold, q), (listed, q2), (flat, q2)):
                assert isinstance(res, lemke.LCPManyResult)
                _assert_flat_is_items(res, M, qq)
        for a, b in zip(runs[FEW], runs[0]):
            assert a._off is None and b._off is not None  # the two paths, taken
            assert a == b and list(a) == list(b)  # every field of every item, bit for bit
            assert _flat_fields(a) == _flat_fields(b)
            assert a.warm_start == b.warm_start
            seen |= set(a.status.tolist()) | {int(p == 0) for p in a.pivots.tolist()}
        monkeypatch.setattr(_batch, "FEW", FEW)
    assert {int(Status.SOLVED), int(Status.RAY_TERMINATION)} <= seen and {0, 1} <= seen


def test_a_few_problems_bad_input_says_what_the_batch_path_says(monkeypatch):
    from lemke import _batch
    FEW = _batch.FEW
    bad_M = np.eye(2)
    bad_M[1, 0] = np.nan
    cases = [
        ([np.eye(2), bad_M], [np.ones(2), -np.ones(2)], {}),
        ([np.eye(2), np.eye(2)], [-np.ones(2), np.array([np.inf, -1.0])], {}),
        ([np.eye(2)], [np.ones(2)], {"warm_start": [lemke.WarmStart(3, ())]}),
        ([np.eye(2)], [np.ones(2)], {"workers": 0}),
        ([np.eye(2)], [np.ones(2)], {"method": "nope"}),
        ([np.eye(2)], [np.ones(3)], {}),
    ]
    for i, (M, q, kw) in enumerate(cases):
        said = []
        for few in (FEW, 0):
            monkeypatch.setattr(_batch, "FEW", few)
            with pytest.raises((ValueError, TypeError)) as e:
                lemke.solve_lcp_many(M, q, **kw)
            said.append((e.type, str(e.value)))
        assert said[0] == said[1], said
        if i < 2:  # a NaN or an infinity: the problem and the argument named
            assert said[0][0] is ValueError and "problem 1" in said[0][1] and "MqMq"[i] in said[0][1]


def test_solve_lcp_many_entry_is_the_python_function_to_its_callers(monkeypatch):
    """``lemke.solve_lcp_many`` is the core's entry (``_core.lcp_many_entry``): a call of up to
    FEW plain problems is made there whole, as ``_batch._few`` makes it (the same items and
    flat fields), reading ``_batch.FEW`` and ``_lcp._FRONT`` on each call; every other call
    is the Python function's, whose name, docstring and signature it shows."""
    import inspect
    from lemke import _batch, _lcp

    f = lemke.solve_lcp_many
    assert f.__wrapped__ is _batch._solve_lcp_many and f.__doc__ == _batch._solve_lcp_many.__doc__
    assert str(inspect.signature(f)) == str(inspect.signature(_batch._solve_lcp_many))
    assert pickle.loads(pickle.dumps(f)) is f
    Ms, qs, qs2 = _islands(9, count=12)
    keep = [b for b in range(len(Ms)) if len(qs[b])]
    Ms, qs, qs2 = [Ms[b] for b in keep][:3], [qs[b] for b in keep][:3], [qs2[b] for b in keep][:3]
    cold = f(Ms, qs)
    ws = [r.warm_start for r in cold]
    warm = f(Ms, qs2, warm_start=ws)
    assert cold._off is None and warm._off is None and (warm.pivots == 0).any()
    for res, args in ((cold, (Ms, qs)), (warm, (Ms, qs2, ws))):
        kw = {"warm_start": args[2]} if len(args) > 2 else {}
        python = _batch._solve_lcp_many(*args[:2], **kw)  # (_few, through solve_lcp)
        assert res == python and _flat_fields(res) == _flat_fields(python)
        assert res.warm_start == python.warm_start
        _assert_flat_is_items(res, Ms, args[1])
    calls = []
    front = _lcp._FRONT
    monkeypatch.setattr(_lcp, "_FRONT", lambda *a: calls.append(a) or front(*a))
    assert f(Ms, qs) == cold and len(calls) == len(Ms)  # (through the Python path's solve_lcp)
    monkeypatch.setattr(_batch, "FEW", 2)
    assert f(Ms, qs)._off is not None  # 3 problems: the batch
    monkeypatch.undo()
    with pytest.raises(ValueError, match="problem 1"):
        f([np.eye(2), np.eye(2)], [np.ones(2), np.array([np.nan, 1.0])])
    with pytest.raises(ValueError, match="warm_start\\[0\\]"):
        f([np.eye(2)], [np.ones(2)], warm_start=[lemke.WarmStart(3, (0,))])
