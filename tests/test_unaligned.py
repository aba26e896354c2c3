"""Unaligned arrays (issue 31 item 7, branch align): nanobind passes a C-contiguous array to
a typed ``nb::ndarray`` argument whatever its address, and reading an unaligned one as
doubles or int64 is undefined behaviour.  Every ``_core`` entry that reads typed arrays takes
them through ``Aligned<...>`` (src/python_arrays.hpp) and refuses an unaligned one with
TypeError; every public entry copies such arrays first (or its native front declines them
and converts), so it answers exactly (bit for bit) what it answers for aligned copies.
``np.ascontiguousarray`` keeps an array unaligned: the arrays here are C-contiguous, native
float64 / int64, and start one byte into their buffer."""
import numpy as np
import pytest

import lemke
from lemke import _core, problems


def unaligned(a):
    """a's values in a C-contiguous array of a's dtype that starts one byte off alignment."""
    a = np.ascontiguousarray(a)
    u = np.frombuffer(b"\0" + a.tobytes(), dtype=a.dtype, offset=1).reshape(a.shape)
    assert not u.flags.aligned and u.flags.c_contiguous and np.ascontiguousarray(u) is u
    return u


def writable_unaligned(a):
    """unaligned(a), writable (a bytearray's buffer)."""
    a = np.ascontiguousarray(a)
    u = np.frombuffer(bytearray(b"\0" + a.tobytes()), dtype=a.dtype, offset=1).reshape(a.shape)
    assert not u.flags.aligned and u.flags.writeable
    return u


def _bits(x):
    """x's value, arrays by their bytes (dtype and shape too), results by their bitwise key."""
    if isinstance(x, np.ndarray):
        return ("array", x.dtype.str, x.shape, x.tobytes())
    if hasattr(x, "_keys"):
        return ("result", type(x).__name__, x._keys())
    if isinstance(x, (list, tuple)) or hasattr(x, "__iter__") and hasattr(x, "__getitem__"):
        return (type(x).__name__, *map(_bits, x))
    if isinstance(x, float):
        return ("float", np.float64(x).tobytes())
    return x


def same_both_ways(call, *arrays, writable=False):
    """call(*arrays) with every array unaligned (the ndarrays among them; one at a time and
    all at once) answers bit for bit what it answers with the aligned arrays."""
    make = writable_unaligned if writable else unaligned
    want = _bits(call(*arrays))
    idx = [i for i, a in enumerate(arrays) if isinstance(a, np.ndarray)]
    assert idx
    for pick in [[i] for i in idx] + [idx]:
        args = [make(a) if i in pick else a for i, a in enumerate(arrays)]
        assert _bits(call(*args)) == want, pick


def _lcp(n=6, seed=3):
    return problems.random_psd(n, np.random.default_rng(seed))


@pytest.mark.parametrize("method", lemke.METHODS)
def test_solve_lcp(method):
    M, q = _lcp()
    d = np.ones(len(q)) + np.arange(len(q)) / 7
    same_both_ways(lambda M, q: lemke.solve_lcp(M, q, method=method), M, q)
    same_both_ways(lambda M, q, d: lemke.solve_lcp(M, q, method=method, d=d), M, q, d)
    ws = lemke.solve_lcp(M, q, method=method).warm_start
    same_both_ways(lambda M, q: lemke.solve_lcp(M, q - 0.5, method=method, warm_start=ws), M, q)
    ray_M = -np.eye(3)
    same_both_ways(lambda M, q: lemke.solve_lcp(M, q, method=method), ray_M, -np.ones(3))


def test_solve_lcp_many_and_batch():
    rng = np.random.default_rng(5)
    pairs = [problems.random_psd(n, rng) for n in (3, 5, 4)]
    Ms, qs = [p[0] for p in pairs], [p[1] for p in pairs]
    want = lemke.solve_lcp_many(Ms, qs, workers=1)
    got = lemke.solve_lcp_many([unaligned(M) for M in Ms], [unaligned(q) for q in qs], workers=1)
    assert _bits(got) == _bits(want)
    ws = want.warm_start
    again = lemke.solve_lcp_many([unaligned(M) for M in Ms], [unaligned(q - 0.25) for q in qs], warm_start=ws)
    assert _bits(again) == _bits(lemke.solve_lcp_many(Ms, [q - 0.25 for q in qs], warm_start=ws))
    B3 = np.stack([problems.random_psd(4, rng)[0] for _ in range(3)])
    Q = rng.normal(size=(3, 4))
    same_both_ways(lambda M, q: lemke.solve_lcp_batch(M, q, workers=1), B3, Q)
    same_both_ways(lambda M, q: lemke.solve_lcp_many(M, q, sizes=np.array([4, 4, 4])),
                   B3.reshape(-1), Q.reshape(-1))


def test_solve_blcp_with_friction_and_warm_start():
    from test_blcp import contacts
    M, q, lo, hi, findex, mu = contacts(2, 3)
    f64 = np.asarray(findex).astype(np.int64)
    same_both_ways(lambda M, q, lo, hi: lemke.solve_blcp(M, q, lo, hi), M, q, lo, hi)
    same_both_ways(lambda M, q, lo, hi, f: lemke.solve_blcp(M, q, lo, hi, findex=f), M, q, lo, hi, f64)
    ws = lemke.solve_blcp(M, q, lo, hi, findex=f64).warm_start
    same_both_ways(lambda M, q, lo, hi, f: lemke.solve_blcp(M, q * 0.9, lo, hi, findex=f, warm_start=ws),
                   M, q, lo, hi, f64)
    same_both_ways(lambda M, q, lo, hi: lemke.solve_blcp(M, q, lo, hi), M, q,
                   np.zeros(len(q)), np.full(len(q), np.inf))


def test_solve_blcp_many():
    from test_blcp import contacts
    scenes = [contacts(s, 2) for s in (1, 2, 3)]
    args = [[s[i] for s in scenes] for i in range(4)]
    fis = [np.asarray(s[4]).astype(np.int64) for s in scenes]
    want = lemke.solve_blcp_many(*args, findex=fis, workers=1)
    got = lemke.solve_blcp_many(*[[unaligned(a) for a in arg] for arg in args],
                                findex=[unaligned(f) for f in fis], workers=1)
    assert _bits(got) == _bits(want)
    ws = want.warm_start
    got = lemke.solve_blcp_many(*[[unaligned(a) for a in arg] for arg in args],
                                findex=[unaligned(f) for f in fis], warm_start=ws)
    assert _bits(got) == _bits(lemke.solve_blcp_many(*args, findex=fis, warm_start=ws))


def test_solve_mlcp():
    rng = np.random.default_rng(9)
    M, q = problems.random_psd(6, rng)
    A, B, C, D = M[:2, :2] + 3 * np.eye(2), M[2:, 2:], M[:2, 2:], M[2:, :2]
    a, b = q[:2], q[2:]
    same_both_ways(lambda *x: lemke.solve_mlcp(*x), A, B, C, D, a, b)
    same_both_ways(lambda *x: lemke.solve_mlcp(*x, method="unrevised"), A, B, C, D, a, b)


def test_solve_qp():
    rng = np.random.default_rng(11)
    P, q, G, h, A, b, lb, ub = problems.random_convex_qp(5, rng)
    args = [P, q] + [x for x in (G, h, A, b, lb, ub)]
    present = [i for i, x in enumerate(args) if x is not None]

    def call(*xs):
        full = list(args)
        for i, x in zip(present, xs):
            full[i] = x
        return lemke.solve_qp(*full)
    xs = [args[i] for i in present]
    same_both_ways(call, *xs)
    want = call(*xs)
    same_both_ways(lambda *y: lemke.solve_qp(*[y[present.index(i)] if i in present else None
                                               for i in range(8)], warm_start=want.warm_start), *xs)
    x0 = np.zeros(len(q)) + 0.125
    same_both_ways(lambda P, q, x0: lemke.solve_qp(P, q, G, h, A, b, lb, ub, initvals=x0), P, q, x0)
    same_both_ways(lambda P, q, lb, ub: lemke.solve_qp(P, q, lb=lb, ub=ub), P, q,
                   -np.ones(len(q)), np.ones(len(q)))


def test_games():
    rng = np.random.default_rng(2)
    A, B = rng.normal(size=(3, 4)), rng.normal(size=(3, 4))
    for k in (0, 5):
        same_both_ways(lambda A, B: lemke.solve_bimatrix(A, B, init_label=k), A, B)
    same_both_ways(lambda A, B: lemke.lemke_paths(A, B), A, B)
    r = lemke.solve_bimatrix(A, B)
    same_both_ways(lambda A, B: lemke.solve_bimatrix(A, B, warm_start=r.basis), A, B)
    same_both_ways(lambda A, B, p, q: lemke.solve_bimatrix(A, B, method="tracing", prior=(p, q)),
                   A, B, np.array([0.5, 0.25, 0.25]), np.full(4, 0.25))


def test_checks():
    M, q = _lcp()
    r = lemke.solve_lcp(M, q)
    same_both_ways(lambda M, q, z: lemke.is_lcp_solution(M, q, z), M, q, r.z)
    assert lemke.is_lcp_solution(unaligned(M), unaligned(q), unaligned(r.z))
    same_both_ways(lambda z, w: lemke.lcp_residual(z, w), r.z, r.w)
    R = lemke.solve_lcp(-np.eye(3), -np.ones(3))
    assert R.ray is not None
    d = np.ones(3) if R.covering is None else R.covering
    same_both_ways(lambda M, q, d, z, ray: lemke.is_lcp_ray(M, q, d, z, R.z0, ray),
                   -np.eye(3), -np.ones(3), d, R.z, R.ray)


def test_pivot_column():
    M, q = _lcp(3)
    Md = np.hstack([M, np.ones((3, 1))])
    basic, nonbasic = ["z4", "w2", "z3"], ["w1", "w3", "z2", "z1"]
    for driving in ("w1", "z2"):
        same_both_ways(lambda M, q: lemke.pivot_column(M, q, basic, nonbasic, driving), Md, q)


def test_problem_solve():
    M, q = _lcp()
    same_both_ways(lambda M, q: lemke.Problem.lcp(M, q).solve(), M, q)
    same_both_ways(lambda M, q: lemke.Problem.blcp(M, q, -np.ones(len(q)), np.ones(len(q))).solve(), M, q)


def test_result_arrays_writable_unaligned():
    """Writable unaligned arrays (a bytearray's buffer) as well."""
    M, q = _lcp()
    same_both_ways(lambda M, q: lemke.solve_lcp(M, q), M, q, writable=True)
    same_both_ways(lambda M, q, z: lemke.is_lcp_solution(M, q, z), M, q, lemke.solve_lcp(M, q).z,
                   writable=True)


def test_core_refuses_unaligned():
    """A _core entry (private) refuses an unaligned array with TypeError, and takes an
    aligned copy of it."""
    M, q = _lcp(4)
    z = lemke.solve_lcp(M, q).z
    w = np.empty(4)
    ok = _core.lcp_check(M, q, z, 1e-9, w)
    for i, a in enumerate((M, q, z)):
        args = [M, q, z]
        args[i] = unaligned(a)
        with pytest.raises(TypeError):
            _core.lcp_check(*args, 1e-9, w)
    with pytest.raises(TypeError):
        _core.lcp_check(M, q, z, 1e-9, writable_unaligned(w))
    assert _core.lcp_check(M, q, z, 1e-9, np.empty(4)) == ok
    with pytest.raises(TypeError):
        _core.linalg_solve(unaligned(M), q)
    with pytest.raises(TypeError):
        _core.principal_block(M, unaligned(np.array([0, 2], dtype=np.int64)))
    assert _bits(_core.principal_block(M, np.array([0, 2], dtype=np.int64))) == _bits(M[np.ix_([0, 2], [0, 2])])


def test_warm_start_and_sizes_int64():
    """int64 inputs: a WarmStart's / BoxWarmStart's index arrays, the many solves' sizes."""
    M, q = _lcp()
    ws = lemke.solve_lcp(M, q).warm_start
    zb = np.array(ws.z_basic, dtype=np.int64)
    for method in lemke.METHODS:
        same_both_ways(lambda zb: lemke.solve_lcp(M, q - 0.5, method=method,
                                                  warm_start=lemke.WarmStart(len(q), zb)), zb)
    from test_blcp import contacts
    Mb, qb, lo, hi, findex, mu = contacts(2, 3)
    f64 = np.asarray(findex).astype(np.int64)
    bw = lemke.solve_blcp(Mb, qb, lo, hi, findex=f64).warm_start
    arrays = [np.array(x, dtype=np.int64) for x in (bw.z_basic, bw.at_upper, bw.friction)]
    full = [i for i, a in enumerate(arrays) if a.size]  # (an empty array is aligned)
    assert full

    def box_warm(*xs):
        got = list(arrays)
        for i, x in zip(full, xs):
            got[i] = x
        return lemke.solve_blcp(Mb, qb * 0.9, lo, hi, findex=f64, warm_start=lemke.BoxWarmStart(bw.n, *got))
    same_both_ways(box_warm, *[arrays[i] for i in full])
    rng = np.random.default_rng(4)
    pairs = [problems.random_psd(n, rng) for n in (3, 5)]
    Mflat = np.concatenate([p[0].ravel() for p in pairs])
    qflat = np.concatenate([p[1] for p in pairs])
    same_both_ways(lambda M, q, s: lemke.solve_lcp_many(M, q, sizes=s), Mflat, qflat,
                   np.array([3, 5], dtype=np.int64))


def test_qpsolvers_problem():
    qpsolvers = pytest.importorskip("qpsolvers")
    P, q, G, h, A, b, lb, ub = problems.random_convex_qp(4, np.random.default_rng(12))
    def solve(P, q):
        s = lemke.solve_qpsolvers_problem(qpsolvers.Problem(P, q, G, h, A, b, lb, ub))
        return [s.found, s.x, s.y, s.z, s.z_box]
    same_both_ways(solve, P, q)


def test_every_typed_core_entry_refuses_unaligned():
    """Every _core entry whose signature takes float64 / int64 ndarrays (read from the
    signatures: sanitized_fuzz.typed_entries) refuses each such argument unaligned with
    TypeError, before its body reads anything (the sanitized child makes the same calls under
    UBSan and also takes the aligned answer)."""
    from sanitized_fuzz import typed_entries, unaligned_calls
    entries = typed_entries()
    assert len(entries) >= 50
    answered = 0
    for name, fn, params in entries:
        calls = unaligned_calls(fn, params)
        answered += not isinstance(calls[0][1], str)
        assert [g for _, g in calls[1:]] == ["refused TypeError"] * (len(calls) - 1), name
    assert answered >= 25  # (most aligned calls get through to the body: the refusal is the alignment's)
