"""Box LCPs like LCPs (issue 32): BoxWarmStart.take / .relabel across contact changes,
islands of box LCPs in one call (solve_blcp_many: bit for bit solve_blcp's answers, for any
number of workers), and the refusal of warm starts of the wrong kind, size or structure.
Every answer is also judged by the plain-numpy checks of test_blcp (not lemke's)."""
import pickle

import numpy as np
import pytest

import lemke
from lemke import BoxWarmStart, BoxWarmStartBatch
from helpers import native_fronts_off
from test_blcp import assert_box_solution, assert_friction_solution, contacts


def _check(M, q, lo, hi, findex, z):
    if findex is None:
        assert_box_solution(M, q, lo, hi, z, rtol=1e-7)
    else:
        assert_friction_solution(M, q, lo, hi, findex, z)


# --------------------------------------------------------------------------- take / relabel


def test_take_moves_row_states():
    # rows: 0 ordinary basic, 1 ordinary at hi, 2 ordinary at lo
    ws = BoxWarmStart(3, (0,), (1,))
    assert ws.row_states().tolist() == [2, 1, 0]
    t = ws.take([2, -1, 0, 1])  # old 2 -> 0, a new row 1, old 0 -> 2, old 1 -> 3
    assert t == BoxWarmStart(4, (2,), (3,))
    assert t.row_states().tolist() == [0, 0, 2, 1]
    assert ws.take([1]) == BoxWarmStart(1, (), (0,))  # rows 0 and 2 dropped
    assert ws.take([]) == BoxWarmStart(0, (), ())
    assert ws.relabel(["a", "b", "c"], ["c", "new", "a", "b"]) == t
    assert ws.relabel(np.array([10, 11, 12]), np.array([12, 99, 10, 11])) == t
    assert ws.relabel(np.array([10, 11, 12], dtype=np.uint32), np.array([12, 99, 10, 11])) == t


def test_take_with_friction_rows():
    # 2 rows: 0 a normal (basic), 1 its friction row: beta+ basic, beta- at lo, lambda basic
    n, nf = 2, 1
    ws = BoxWarmStart(n + 2 * nf, (0, 1, 3), (), (1,))
    assert ws.rows == 2
    assert ws.row_states().tolist() == [2, 3 + 9 * 2 + 3 * 0 + 2]
    # a new contact in front (rows 0, 1), the old one moved to rows 2, 3
    t = ws.take([-1, -1, 0, 1], findex=[-1, 0, -1, 2])
    assert t.friction == (1, 3) and t.n == 4 + 4
    # the extended layout: rows, then beta- of rows 1, 3, then lambda of rows 1, 3
    assert t == BoxWarmStart(8, (2, 3, 7), (), (1, 3))
    assert t.row_states().tolist() == [0, 3, 2, 3 + 9 * 2 + 2]
    assert BoxWarmStart.from_row_states(t.row_states()) == t
    assert ws.relabel([("c", 0), ("c", 1)], [("d", 0), ("d", 1), ("c", 0), ("c", 1)],
                      findex=np.array([-1, 0, -1, 2])) == t
    # a kept row must keep its kind; findex=None means no friction row
    with pytest.raises(ValueError, match="findex"):
        ws.take([0, 1])
    with pytest.raises(ValueError, match="findex"):
        ws.take([1, 0], findex=[-1, 0])
    with pytest.raises(ValueError, match="findex"):
        ws.take([0, 1], findex=[-1])


def test_take_refuses_bad_indices():
    ws = BoxWarmStart(3, (0,), (1,))
    with pytest.raises(ValueError, match="indices"):
        ws.take([3])
    with pytest.raises(ValueError, match="indices"):
        ws.take([-2])
    with pytest.raises(ValueError, match="twice"):
        ws.take([0, 0])
    with pytest.raises(TypeError, match="indices"):
        ws.take([0.5])
    with pytest.raises(ValueError, match="old_labels"):
        ws.relabel([1, 2], [1])
    with pytest.raises(ValueError, match="old_labels holds a label twice"):
        ws.relabel([1, 1, 2], [1])
    with pytest.raises(ValueError, match="new_labels holds a label twice"):
        ws.relabel([1, 2, 3], [1, 1])
    with pytest.raises(ValueError, match="old_labels holds a label twice"):
        ws.relabel(np.array([1, 1, 2]), np.array([1]))
    with pytest.raises(ValueError, match="new_labels holds a label twice"):
        ws.relabel(np.array([1, 2, 3]), np.array([4, 4]))
    with pytest.raises(ValueError, match="friction"):
        BoxWarmStart(3, (), (), (1,))  # one friction row needs n >= rows + 2 with rows > 1
    assert pickle.loads(pickle.dumps(ws)) == ws


def _scene(seed, k, idle):
    """k contacts (normal, friction row), and the same scene with contact ``idle`` made
    inactive (its rows pushed apart: q large and positive, so its impulses are 0)."""
    M, q, lo, hi, findex, mu = contacts(seed, k)
    q = q.copy()
    q[2 * idle] = 50.0
    return M, q, lo, hi, findex.astype(np.int64)


@pytest.mark.parametrize("seed", range(8))
def test_take_carries_a_solving_basis(seed):
    """A contact with no impulse vanishes: the kept rows' basis still solves the smaller
    problem, so the carried warm start (by take and by relabel) ends it with 0 pivots; a
    new contact appended starts cold, and the answer is checked independently."""
    k, idle = 4, seed % 4
    M, q, lo, hi, findex = _scene(seed, k, idle)
    r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
    assert r.success
    assert r.z[2 * idle] == 0.0 and r.z[2 * idle + 1] == 0.0
    keep = np.array([i for i in range(2 * k) if i // 2 != idle])
    fi2 = np.array([-1 if f < 0 else int(np.flatnonzero(keep == f)[0]) for f in findex[keep]])
    M2, q2, lo2, hi2 = M[np.ix_(keep, keep)], q[keep], lo[keep], hi[keep]
    ws2 = r.warm_start.take(keep, findex=fi2)
    labels = np.arange(2 * k) + 100
    assert r.warm_start.relabel(labels, labels[keep], findex=fi2) == ws2
    assert r.warm_start.relabel(list(labels), list(labels[keep]), findex=fi2) == ws2
    warm = lemke.solve_blcp(M2, q2, lo2, hi2, findex=fi2, warm_start=ws2)
    assert warm.success and warm.pivots == 0
    _check(M2, q2, lo2, hi2, fi2, warm.z)
    assert np.allclose(warm.z, r.z[keep], atol=1e-9)
    # without take, the old basis is refused (never a silent cold solve)
    with pytest.raises(ValueError, match="take or .relabel"):
        lemke.solve_blcp(M2, q2, lo2, hi2, findex=fi2, warm_start=r.warm_start)
    # a new contact (rows 2k-2, 2k-1 of a bigger scene) appended: cold rows, still solved
    M3, q3, lo3, hi3, fi3, _ = contacts(seed + 100, k)
    fi3 = fi3.astype(np.int64)
    idx = np.r_[keep, -1, -1]
    ws3 = r.warm_start.take(idx, findex=fi3)
    assert ws3.row_states()[-2:].tolist() == [0, 3]
    assert ws3.row_states()[:-2].tolist() == r.warm_start.row_states()[keep].tolist()
    w3 = lemke.solve_blcp(M3, q3, lo3, hi3, findex=fi3, warm_start=ws3)
    assert w3.success
    _check(M3, q3, lo3, hi3, fi3, w3.z)


# --------------------------------------------------------------------------- islands


def _islands(seed, B=24):
    """Islands of 1-4 contacts with friction, some without findex (their friction rows
    frozen at [-mu, mu]), one of 0 rows; and the next step's (q moved)."""
    rng = np.random.default_rng(seed)
    Ms, qs, los, his, fis = [], [], [], [], []
    for b in range(B):
        k = int(rng.integers(1, 5))
        M, q, lo, hi, findex, _ = contacts(1000 * seed + b, k)
        Ms.append(M)
        qs.append(q)
        los.append(lo)
        his.append(hi)
        fis.append(None if b % 5 == 3 else findex.astype(np.int64))
    Ms.append(np.zeros((0, 0)))
    qs.append(np.zeros(0))
    los.append(np.zeros(0))
    his.append(np.zeros(0))
    fis.append(np.zeros(0, dtype=np.int64))
    qs2 = [q + 1e-7 * rng.standard_normal(q.size) for q in qs]
    return Ms, qs, los, his, fis, qs2


def _same_as_one_by_one(res, Ms, qs, los, his, fis, wss=None):
    B = len(Ms)
    wss = [None] * B if wss is None else wss
    one = [lemke.solve_blcp(M, q, lo, hi, findex=f, warm_start=w)
           for M, q, lo, hi, f, w in zip(Ms, qs, los, his, fis, wss)]
    assert len(res) == B
    for b in range(B):
        assert res[b] == one[b], b
    for name in ("z", "w", "lo", "hi"):
        want = np.concatenate([getattr(o, name) for o in one])
        assert getattr(res, name).tobytes() == want.tobytes(), name
    assert res.status.tolist() == [int(o.status) for o in one]
    assert res.pivots.tolist() == [o.pivots for o in one]
    assert res.recoveries.tolist() == [o.recoveries for o in one]
    assert res.residual.tobytes() == np.array([o.residual for o in one]).tobytes()
    assert list(res.warm_start) == [o.warm_start for o in one]
    assert res.offsets.tolist() == np.cumsum([0] + [len(q) for q in qs]).tolist()
    for M, q, lo, hi, f, o in zip(Ms, qs, los, his, fis, one):
        if o.success and q.size:
            _check(M, q, lo, hi, None if f is None or not (f >= 0).any() else f, o.z)
    return one


@pytest.mark.parametrize("seed", range(3))
def test_many_is_solve_blcp_bit_for_bit(seed):
    Ms, qs, los, his, fis, qs2 = _islands(seed)
    cold = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, workers=1)
    assert cold.success.all() and cold.pivots.sum() > 0
    _same_as_one_by_one(cold, Ms, qs, los, his, fis)
    for workers in (2, 3):
        other = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, workers=workers)
        assert other == cold and other.z.tobytes() == cold.z.tobytes()
    # the next step, warm from the batch (as it is) and from a list of BoxWarmStart
    warm = lemke.solve_blcp_many(Ms, qs2, los, his, findex=fis, warm_start=cold.warm_start)
    assert warm.success.all() and warm.pivots.sum() < cold.pivots.sum()
    _same_as_one_by_one(warm, Ms, qs2, los, his, fis, list(cold.warm_start))
    listed = lemke.solve_blcp_many(Ms, qs2, los, his, findex=fis, warm_start=list(cold.warm_start),
                                   workers=2)
    assert listed == warm and listed.warm_start == warm.warm_start
    # some islands cold (None)
    mixed = [None if b % 3 else w for b, w in enumerate(cold.warm_start)]
    m = lemke.solve_blcp_many(Ms, qs2, los, his, findex=fis, warm_start=mixed, workers=2)
    _same_as_one_by_one(m, Ms, qs2, los, his, fis, mixed)


def test_many_packed_input():
    Ms, qs, los, his, fis, qs2 = _islands(7)
    fis = [np.full(q.size, -1, np.int64) if f is None else f for f, q in zip(fis, qs)]
    sizes = np.array([q.size for q in qs])
    packed = [np.concatenate([a.ravel() for a in x]) for x in (Ms, qs, los, his, fis)]
    a = lemke.solve_blcp_many(*packed[:4], findex=packed[4], sizes=sizes)
    b = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis)
    assert a == b and a.z.tobytes() == b.z.tobytes()
    _same_as_one_by_one(a, Ms, qs, los, his, fis)
    c = lemke.solve_blcp_many(packed[0], np.concatenate(qs2), *packed[2:4], findex=packed[4],
                              sizes=sizes, warm_start=a.warm_start, workers=2)
    _same_as_one_by_one(c, Ms, qs2, los, his, fis, list(a.warm_start))
    # scalar bounds, no friction index
    d = lemke.solve_blcp_many(packed[0], packed[1], 0.0, np.inf, sizes=sizes)
    _same_as_one_by_one(d, Ms, qs, [np.zeros(n) for n in sizes], [np.full(n, np.inf) for n in sizes],
                        [None] * len(Ms))
    for arrays in packed:  # the caller's arrays are not modified (nor made read-only)
        assert arrays.flags.writeable


def test_many_leaves_hard_islands_to_the_general_path():
    """An island with no solution (a checked ray) and one that needs lists converted go
    through solve_blcp itself: the same answers."""
    Ms, qs, los, his, fis, _ = _islands(3, B=6)
    Ms.append(-np.eye(2))
    qs.append(np.array([-1.0, -1.0]))
    los.append(np.zeros(2))
    his.append(np.full(2, np.inf))
    fis.append(None)
    Ms.append([[2.0, 1.0], [1.0, 2.0]])
    qs.append([-5, 1])
    los.append(0.0)
    his.append([2, 1])
    fis.append(None)
    res = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, workers=2)
    assert res.status[-2] == lemke.Status.RAY_TERMINATION and res[-2].ray is not None
    assert res[-1].z.tolist() == [2.0, 0.0]
    Ms[-1], qs[-1] = np.array(Ms[-1]), np.array(qs[-1], dtype=float)
    los[-1], his[-1] = np.zeros(2), np.array([2.0, 1.0])
    _same_as_one_by_one(res, Ms, qs, los, his, fis)


def test_many_refuses_bad_input():
    Ms, qs, los, his, fis, _ = _islands(4, B=4)
    r = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis)
    lcp = lemke.solve_lcp(np.eye(2), [-1.0, 1.0])
    with pytest.raises(ValueError, match=r"warm_start\[1\] must be a lemke.BoxWarmStart"):
        lemke.solve_blcp_many(Ms, qs, los, his, findex=fis,
                              warm_start=[None, lcp.warm_start, None, None, None])
    with pytest.raises(ValueError, match="WarmStartBatch"):
        lemke.solve_blcp_many(Ms, qs, los, his, findex=fis,
                              warm_start=lemke.solve_lcp_many([np.eye(1)], [[1.0]]).warm_start)
    with pytest.raises(ValueError, match="BoxWarmStartBatch"):
        lemke.solve_lcp_many([np.eye(1)], [[1.0]], warm_start=r.warm_start)
    with pytest.raises(ValueError, match="one basis per problem"):
        lemke.solve_blcp_many(Ms[:3], qs[:3], los[:3], his[:3], findex=fis[:3], warm_start=r.warm_start)
    # a changed number of rows without take / relabel
    Ms2 = Ms[:1] + [M[:-2, :-2] for M in Ms[1:2]] + Ms[2:]
    qs2 = qs[:1] + [q[:-2] for q in qs[1:2]] + qs[2:]
    los2 = los[:1] + [v[:-2] for v in los[1:2]] + los[2:]
    his2 = his[:1] + [v[:-2] for v in his[1:2]] + his[2:]
    fis2 = fis[:1] + [None if f is None else f[:-2] for f in fis[1:2]] + fis[2:]
    for ws in (r.warm_start, list(r.warm_start)):
        with pytest.raises(ValueError, match=r"warm_start\[1\] is for a problem of size"):
            lemke.solve_blcp_many(Ms2, qs2, los2, his2, findex=fis2, warm_start=ws)
    # carried over with take: accepted, solved, checked
    keep = np.arange(qs2[1].size)
    carried = list(r.warm_start)
    carried[1] = carried[1].take(keep, findex=fis2[1])
    ok = lemke.solve_blcp_many(Ms2, qs2, los2, his2, findex=fis2, warm_start=carried)
    _same_as_one_by_one(ok, Ms2, qs2, los2, his2, fis2, carried)
    # the same number of rows, other friction rows
    flipped = [None if f is None else np.full(f.size, -1, np.int64) for f in fis]
    with pytest.raises(ValueError, match=r"warm_start\[0\] is for other friction rows"):
        lemke.solve_blcp_many(Ms, qs, los, [np.full(q.size, np.inf) for q in qs], findex=flipped,
                              warm_start=r.warm_start)
    # bad data names the problem and the entry
    qbad = [q.copy() for q in qs]
    qbad[2][0] = np.nan
    with pytest.raises(ValueError, match="problem 2: q has a NaN"):
        lemke.solve_blcp_many(Ms, qbad, los, his, findex=fis)
    with pytest.raises(ValueError, match="problem 1"):
        lemke.solve_blcp_many(Ms, qs, los, his, findex=fis[:1] + [np.full(qs[1].size, 7)] + fis[2:])
    with pytest.raises(ValueError, match="same number"):
        lemke.solve_blcp_many(Ms, qs[:-1], los, his)
    with pytest.raises(ValueError, match="packed q"):
        lemke.solve_blcp_many(np.ones(4), np.ones(3), 0.0, 1.0, sizes=[2])


def test_single_solve_refuses_wrong_warm_starts():
    M, q, lo, hi, findex, _ = contacts(5, 3)
    findex = findex.astype(np.int64)
    r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
    lcp = lemke.solve_lcp(M, q)
    with pytest.raises(ValueError, match="warm_start must be a lemke.BoxWarmStart, got a lemke.WarmStart"):
        lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=lcp.warm_start)
    with pytest.raises(ValueError, match="warm_start must be a lemke.WarmStart, got a lemke.BoxWarmStart"):
        lemke.solve_lcp(M, q, warm_start=r.warm_start)
    with pytest.raises(ValueError, match="warm_start must be a lemke.WarmStart, got a lemke.BoxWarmStart"):
        lemke.solve_qp(M, q, warm_start=r.warm_start)
    with pytest.raises(ValueError, match="BoxWarmStart"):
        lemke.solve_lcp_many([M], [q], warm_start=[r.warm_start])
    # the same size, other friction rows: refused on both paths (plain data and lists)
    other = BoxWarmStart(r.warm_start.n, r.warm_start.z_basic, r.warm_start.at_upper,
                         tuple(f - 1 for f in r.warm_start.friction))
    for args in ((M, q, lo, hi), (M.tolist(), q.tolist(), lo.tolist(), hi.tolist())):
        with pytest.raises(ValueError, match="friction rows"):
            lemke.solve_blcp(*args, findex=findex, warm_start=other)
    nofric = BoxWarmStart(r.warm_start.n, (), ())
    with pytest.raises(ValueError, match="friction rows"):
        lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=nofric)
    big = np.eye(r.warm_start.n)
    with pytest.raises(ValueError, match="friction rows"):
        lemke.solve_blcp(big, np.ones(big.shape[0]), np.zeros(big.shape[0]), np.ones(big.shape[0]),
                         warm_start=r.warm_start)
    assert lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=r.warm_start).pivots == 0


def test_batch_take_relabel_across_islands():
    """The whole scene's bases carried at once into other islands (two islands merged into
    one): the same as each island's BoxWarmStart carried by take."""
    Ms, qs, los, his, fis, _ = _islands(9, B=3)
    r = lemke.solve_blcp_many(Ms[:3], qs[:3], los[:3], his[:3], findex=fis[:3])
    wb = r.warm_start
    n = wb.n.tolist()
    # new scene: island 0 = old island 2 then old island 0; island 1 = old island 1 and a new row
    o = np.cumsum([0] + n)
    idx = np.r_[np.arange(o[2], o[3]), np.arange(o[0], o[1]), np.arange(o[1], o[2]), -1]
    sizes = [n[2] + n[0], n[1] + 1]
    flat_f = [np.full(k, -1) if f is None else f for f, k in zip(fis[:3], n)]
    mask = np.r_[flat_f[2] >= 0, flat_f[0] >= 0, flat_f[1] >= 0, False]
    fnew = np.where(mask, 0, -1)
    t = wb.take(idx, sizes, findex=fnew)
    assert t.n.tolist() == sizes and len(t) == 2
    assert t.state.tolist() == np.r_[wb.state[o[2]:o[3]], wb.state[o[0]:o[1]], wb.state[o[1]:o[2]], 0].tolist()
    labels = np.arange(o[-1]) * 7 + 3
    new_labels = np.where(idx >= 0, labels[np.maximum(idx, 0)], -5)
    assert wb.relabel(labels, new_labels, sizes, findex=fnew) == t
    assert t[1] == wb[1].take(np.r_[np.arange(n[1]), -1], findex=fnew[n[2] + n[0]:])
    assert BoxWarmStartBatch.of(list(t)) == t
    assert pickle.loads(pickle.dumps(t)) == t
    with pytest.raises(ValueError, match="sizes"):
        wb.take(idx, [1, 2], findex=fnew)


def _fields(res):
    """Every flat field of a BLCPManyResult, as bytes, and its items."""
    return ([getattr(res, name).tobytes() for name in ("z", "w", "lo", "hi", "status", "pivots",
                                                         "recoveries", "residual", "offsets",
                                                         "success")]
            + [res.warm_start.n.tobytes(), res.warm_start.state.tobytes(), list(res)])


@pytest.mark.parametrize("seed", range(3))
def test_a_few_islands_one_by_one_are_the_batch_path(seed):
    """Up to FEW islands are solved one by one by solve_blcp (no batch set-up); the batch
    path (taken here by passing options) gives every field and item bit for bit, cold, warm
    from a BoxWarmStartBatch or a list, with rays and bad warm starts alike."""
    from lemke._batch import FEW
    Ms, qs, los, his, fis, qs2 = _islands(seed, B=FEW)
    Ms, qs, los, his, fis, qs2 = Ms[:FEW], qs[:FEW], los[:FEW], his[:FEW], fis[:FEW], qs2[:FEW]
    if seed == 2:  # an island with no solution: a checked ray
        Ms[1], qs[1], qs2[1] = -np.eye(2), np.array([-1.0, -1.0]), np.array([-1.0, -2.0])
        los[1], his[1], fis[1] = np.zeros(2), np.full(2, np.inf), None
    opts = lemke.Options()
    for B in range(1, FEW + 1):
        args = (Ms[:B], qs[:B], los[:B], his[:B])
        few = lemke.solve_blcp_many(*args, findex=fis[:B])
        assert few._qoff is None  # (the one-by-one path was taken)
        batch = lemke.solve_blcp_many(*args, findex=fis[:B], options=opts)
        assert batch._qoff is not None
        assert _fields(few) == _fields(batch)
        _same_as_one_by_one(few, *args, fis[:B])
        args2 = (Ms[:B], qs2[:B], los[:B], his[:B])
        for ws in (few.warm_start, list(few.warm_start), [None] + list(few.warm_start)[1:]):
            a = lemke.solve_blcp_many(*args2, findex=fis[:B], warm_start=ws, workers=1)
            b = lemke.solve_blcp_many(*args2, findex=fis[:B], warm_start=ws, options=opts)
            assert a._qoff is None and _fields(a) == _fields(b)
    # refused the same way (the general path says it, naming the island)
    lcp = lemke.solve_lcp(np.eye(2), [-1.0, 1.0])
    with pytest.raises(ValueError, match=r"warm_start\[1\] must be a lemke.BoxWarmStart"):
        lemke.solve_blcp_many(Ms[:2], qs[:2], los[:2], his[:2], findex=fis[:2],
                              warm_start=[None, lcp.warm_start])
    qbad = [q.copy() for q in qs[:3]]
    qbad[2][0] = np.nan
    with pytest.raises(ValueError, match="problem 2: q has a NaN"):
        lemke.solve_blcp_many(Ms[:3], qbad, los[:3], his[:3], findex=fis[:3])
    short = [M[:-1, :-1] for M in Ms[:2]], [q[:-1] for q in qs[:2]], [v[:-1] for v in los[:2]], \
        [v[:-1] for v in his[:2]]
    with pytest.raises(ValueError, match=r"warm_start\[0\] is for a problem of size"):
        lemke.solve_blcp_many(*short, warm_start=lemke.solve_blcp_many(
            Ms[:2], qs[:2], los[:2], his[:2]).warm_start)


@pytest.mark.parametrize("seed", range(3))
def test_a_few_islands_carried_step_to_step(seed):
    """Steps of a few islands, each warm from the last step's result.warm_start (a batch
    that keeps the items' own warm starts made from codes, passed back as they are): every
    field and item bit for bit the batch path's fed the same codes, and the batch's items
    the values that its codes give (a batch of the same n and state without them)."""
    from lemke._batch import FEW
    Ms, qs, los, his, fis, qs2 = _islands(seed, B=FEW)
    args = (Ms[:FEW], qs[:FEW], los[:FEW], his[:FEW])
    opts = lemke.Options()
    few = lemke.solve_blcp_many(*args, findex=fis[:FEW])
    kept_seen = False
    for step in range(4):
        ws = few.warm_start
        plain = BoxWarmStartBatch(ws.n, ws.state)  # (the same codes, nothing kept)
        assert ws == plain and list(ws) == list(plain)
        assert [ws[b] for b in range(len(ws))] == list(plain)
        kept_seen |= any(w is not None for w in ws.__dict__.get("_kept", ()))
        q = [qb * (1.0 + 1e-3 * step) for qb in (qs if step % 2 == 0 else qs2)[:FEW]]
        args = (Ms[:FEW], q, los[:FEW], his[:FEW])
        a = lemke.solve_blcp_many(*args, findex=fis[:FEW], warm_start=ws)
        b = lemke.solve_blcp_many(*args, findex=fis[:FEW], warm_start=plain, options=opts)
        assert a._qoff is None and b._qoff is not None
        assert _fields(a) == _fields(b)
        for r, Mb, qb, lb, hb, fb in zip(a, *args, fis[:FEW]):
            if r.success:
                _check(Mb, qb, lb, hb, fb, r.z)
        few = a
    assert kept_seen


@pytest.mark.parametrize("seed", range(3))
def test_a_few_islands_in_one_native_call_are_the_loop(seed, monkeypatch):
    """_core.blcp_front_many (every island's native front in one call) gives the items
    that the Python loop of _few gives (solve_blcp's front island by island: taken here by
    wrapping _blcp._FRONT), every field bit for bit, cold and warm; an island its front
    does not settle (a ray) sends the whole call to the loop."""
    from lemke import _blcp, _blcp_many, _core
    from lemke._batch import FEW
    Ms, qs, los, his, fis, qs2 = _islands(seed, B=FEW)
    args = (Ms[:FEW], qs[:FEW], los[:FEW], his[:FEW])
    args2 = (Ms[:FEW], qs2[:FEW], los[:FEW], his[:FEW])
    items = _core.blcp_front_many(*args, fis[:FEW], None)
    assert items is not None and len(items) == FEW
    native = lemke.solve_blcp_many(*args, findex=fis[:FEW])
    wss = (native.warm_start, list(native.warm_start))
    native_warm = [lemke.solve_blcp_many(*args2, findex=fis[:FEW], warm_start=w) for w in wss]
    ray = (Ms[:1] + [-np.eye(2)], qs[:1] + [np.array([-1.0, -1.0])], los[:1] + [np.zeros(2)],
           his[:1] + [np.full(2, np.inf)])
    assert _core.blcp_front_many(*ray, None, None) is None
    native_ray = lemke.solve_blcp_many(*ray)
    front = _blcp._FRONT
    monkeypatch.setattr(_blcp, "_FRONT", lambda *a: front(*a))
    loop = lemke.solve_blcp_many(*args, findex=fis[:FEW])
    assert _fields(native) == _fields(loop)
    for w, a in zip(wss, native_warm):
        b = lemke.solve_blcp_many(*args2, findex=fis[:FEW], warm_start=w)
        assert a._qoff is None and b._qoff is None and _fields(a) == _fields(b)
    assert _fields(native_ray) == _fields(lemke.solve_blcp_many(*ray))
    assert native_ray[1].status == lemke.Status.RAY_TERMINATION
    _same_as_one_by_one(native, *args, fis[:FEW])


@pytest.mark.parametrize("seed", range(3))
def test_more_small_islands_one_by_one_are_the_batch_path(seed):
    """More than FEW islands go one by one too when they are small (up to _FEW_SMALL of
    them, _SMALL_ROWS rows in all): every field and item bit for bit the batch path's, cold
    and warm from the result's batch (then from a batch made of the same codes, whose
    islands it makes and keeps); more rows than that go to the batch path."""
    from lemke._batch import FEW
    from lemke._blcp_many import _FEW_SMALL, _SMALL_ROWS
    Ms, qs, los, his, fis, qs2 = _islands(seed, B=24)
    take = []
    for b in range(24):  # (islands of rows > 0, as many as fit)
        if qs[b].size and sum(qs[c].size for c in take) + qs[b].size <= _SMALL_ROWS \
                and len(take) < _FEW_SMALL:
            take.append(b)
    assert len(take) > FEW
    pick = lambda v: [v[b] for b in take]  # noqa: E731
    args, args2, fi = (pick(Ms), pick(qs), pick(los), pick(his)), (pick(Ms), pick(qs2), pick(los), pick(his)), pick(fis)
    opts = lemke.Options()
    few = lemke.solve_blcp_many(*args, findex=fi)
    assert few._qoff is None
    assert _fields(few) == _fields(lemke.solve_blcp_many(*args, findex=fi, options=opts))
    _same_as_one_by_one(few, *args, fi)
    plain = BoxWarmStartBatch(few.warm_start.n, few.warm_start.state)
    for ws in (few.warm_start, plain, plain):  # (plain twice: its kept islands the second time)
        a = lemke.solve_blcp_many(*args2, findex=fi, warm_start=ws)
        b = lemke.solve_blcp_many(*args2, findex=fi, warm_start=ws, options=opts)
        assert a._qoff is None and _fields(a) == _fields(b)
        assert list(ws) == list(BoxWarmStartBatch(ws.n, ws.state))
    big = Ms[:4] * 5, qs[:4] * 5, los[:4] * 5, his[:4] * 5
    assert sum(q.size for q in big[1]) > _SMALL_ROWS
    assert lemke.solve_blcp_many(*big, findex=fis[:4] * 5)._qoff is not None


def test_from_codes_small_is_the_numpy_rule():
    """_blcp._from_codes (a Python loop for up to _FEW_ROWS rows, numpy above; z_basic and
    at_upper made when first read) gives the BoxWarmStart of the row-state rule computed
    here, friction rows included, on random row states; and one made lazily equals (and
    hashes as) the one built with its fields."""
    from lemke import _blcp
    rng = np.random.default_rng(31)
    for k in range(2000):
        n = int(rng.integers(0, 2 * _blcp._FEW_ROWS + 1))
        c = np.where(rng.random(n) < 0.3, rng.integers(3, 30, n), rng.integers(0, 3, n)).astype(np.int8)
        a = _blcp._from_codes(c)
        assert "z_basic" not in a.__dict__ and "at_upper" not in a.__dict__
        if k % 2:  # either field first
            a.at_upper
        F = np.flatnonzero(c >= 3)
        e = c[F].astype(np.int64) - 3
        states = np.concatenate([np.where(c >= 3, (c.astype(np.int64) - 3) // 9, c), (e // 3) % 3, e % 3])
        assert a.n == n + 2 * F.size
        assert a.z_basic == tuple(np.flatnonzero(states == 2).tolist())
        assert a.at_upper == tuple(np.flatnonzero(states == 1).tolist())
        assert a.friction == tuple(F.tolist())
        assert a.row_states().tobytes() == c.tobytes()
        b = lemke.BoxWarmStart(a.n, a.z_basic, a.at_upper, a.friction)
        assert a == b and hash(a) == hash(b) and repr(a) == repr(b)


def test_many_without_the_native_fronts():
    """Where lcp_front_init finds another NumPy layout the native fronts stay off: the box
    batch's flat z, w, lo, hi then come from numpy's gathers (BLCPManyResult._gather's
    fallback), bit for bit what many_field's native gathers (a per-island answer offset, the
    flat bounds of islands without a friction index) give; and every item and warm start
    the same."""
    from lemke import _core
    Ms, qs, los, his, fis, qs2 = _islands(11, B=30)
    Ms.append(-np.eye(2))  # a ray: an island of the general path (special)
    qs.append(np.array([-1.0, -1.0]))
    qs2.append(np.array([-1.0, -1.0]))
    los.append(np.zeros(2))
    his.append(np.full(2, np.inf))
    fis.append(None)

    def run():
        cold = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, workers=1)
        warm = lemke.solve_blcp_many(Ms, qs2, los, his, findex=fis, warm_start=cold.warm_start,
                                     workers=2)
        return [_fields(r) for r in (cold, warm)]

    on = run()
    assert on[0][0] != on[1][0]  # (z moved with q)
    with native_fronts_off():
        bufs = np.zeros(4)
        two = np.array([0, 4], dtype=np.int64)
        assert _core.many_field(bufs, two, two, 0, 0, np.zeros(1, np.int64)) is None
        off = run()
    assert off == on
    _same_as_one_by_one(lemke.solve_blcp_many(Ms, qs, los, his, findex=fis), Ms, qs, los, his, fis)


def test_batch_binding_refuses_what_it_cannot_read():
    """boxed.batch and boxed.islands called directly (solve_blcp_many's kernel calls): the
    islands' offsets, friction rows and warm row states are judged before any read, one pass
    over each island's rows (branch boxsmall), and solved islands match solve_blcp's."""
    from lemke._core import boxed
    (M1, q1, lo1, hi1, f1, _), (M2, q2, lo2, hi2, _, _) = contacts(5, 2), contacts(6, 1)
    Ms = np.concatenate([M1.ravel(), M2.ravel()])
    qs, los, his = (np.concatenate(p) for p in ((q1, q2), (lo1, lo2), (hi1, hi2)))
    n1, n2 = q1.size, q2.size
    qoff = np.array([0, n1, n1 + n2], dtype=np.int64)
    mstart = np.array([0, n1 * n1], dtype=np.int64)
    findex = np.concatenate([f1.astype(np.int64), np.full(n2, -1, np.int64)])
    fflag = np.array([1, 0], dtype=np.uint8)
    cold = lemke.solve_blcp(M1, q1, lo1, hi1, findex=f1.astype(np.int64))
    state = np.concatenate([cold.warm_start.row_states(), np.zeros(n2, np.int8)])
    wflag = np.array([1, 1], dtype=np.uint8)
    buff, ioff = np.empty(3, np.int64), np.empty(3, np.int64)
    answer, limits = np.empty(2, np.int64), np.empty(2, np.int64)
    assert boxed.islands(qoff, findex, fflag, state, wflag, -1, buff, ioff, answer, limits) == -1
    opts = lemke.Options()

    def run(state=state, findex=findex, mstart=mstart, qoff=qoff, Ms=Ms, buff=buff):
        bufs, ints = np.empty(int(buff[-1])), np.empty(int(ioff[-1]), np.int64)
        out_i, out_f, state_out = np.empty((2, 7), np.int64), np.empty(2), np.empty(n1 + n2, np.int8)
        boxed.batch(Ms, mstart, qs, los, his, qoff, findex, fflag, state, wflag, 0, 2, limits,
                    opts.pivot_tol, opts.tie_tol, opts.tol, bufs, buff, ints, ioff, state_out,
                    out_i, out_f)
        return bufs, out_i, state_out

    bufs, out_i, state_out = run()
    assert out_i[0, 5] == 0 and out_i[1, 5] >= 0  # island 0 from its own basis
    assert state_out[:n1].tolist() == state[:n1].tolist()
    z0 = bufs[buff[0] + answer[0]:buff[0] + answer[0] + n1]
    again = lemke.solve_blcp(M1, q1, lo1, hi1, findex=f1.astype(np.int64), warm_start=cold.warm_start)
    assert again.pivots == 0 and np.array_equal(z0, again.z)
    assert_friction_solution(M1, q1, lo1, hi1, f1, z0)
    z1 = bufs[buff[1] + answer[1]:buff[1] + answer[1] + n2]
    assert_box_solution(M2, q2, lo2, hi2, z1, rtol=1e-7)
    fr = int(np.flatnonzero(f1 >= 0)[0])  # a friction row of island 0
    for rows, code in (([n1], -1), ([n1], 30), ([n1], 3), ([fr], 0), ([0], 31)):
        bad = state.copy()
        bad[rows] = code
        with pytest.raises(ValueError, match="a warm row state does not fit its row"):
            run(state=bad)
    kinds = state.copy()
    kinds[n1 + 1] = 3  # a friction code on island 1's ordinary row: the first such row
    assert boxed.islands(qoff, findex, fflag, kinds, wflag, -1, *(np.empty_like(a) for a in
                         (buff, ioff, answer, limits))) == n1 + 1
    kinds[fr] = 0  # ... and one on island 0 before it
    assert boxed.islands(qoff, findex, fflag, kinds, wflag, -1, *(np.empty_like(a) for a in
                         (buff, ioff, answer, limits))) == fr
    for kw in ({"mstart": np.array([0, Ms.size], np.int64)},  # M past its array
               {"mstart": np.array([-1, 0], np.int64)},
               {"qoff": np.array([0, n1, n1 + n2 + 1], np.int64)},  # rows past the arrays
               {"qoff": np.array([0, 2 ** 40, n1 + n2], np.int64)},  # n * n past 2^63
               {"findex": findex[:n1 - 1]},
               {"Ms": Ms[:-1]},
               {"buff": np.array([0, buff[1], buff[2] - 1], np.int64)},
               {"buff": np.array([0, np.iinfo(np.int64).min, buff[2]], np.int64)}):  # (no overflow)
        with pytest.raises(ValueError, match="offsets"):
            run(**kw)
    for q_off in ([0, 2 ** 41], [0, -1], [np.iinfo(np.int64).min, 0], [5, 2]):  # (no overflow)
        with pytest.raises(ValueError, match="rows lie outside"):
            boxed.islands(np.array(q_off, np.int64), np.zeros(0, np.int64), np.zeros(1, np.uint8),
                          np.zeros(0, np.int8), np.zeros(1, np.uint8), -1,
                          *(np.empty(k, np.int64) for k in (2, 2, 1, 1)))
