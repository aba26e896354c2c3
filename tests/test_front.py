"""The Python front of the LCP solvers on its fast paths: results read lazily from the kernels'
buffers are the values an eager build gives (q >= 0, rays, solved), their arrays are read-only
and alias nothing writable, and ``solve_lcp_many`` gives every problem exactly what
``solve_lcp`` gives it, whatever the outcome and the form of the input."""
import copy
import functools
import pickle

import numpy as np
import pytest
from helpers import assert_lcp_solution, assert_ray

import lemke
from lemke import LCPResult, Status, WarmStart, _core, _layout, _lcp, problems

FIELDS = ("z", "w", "status", "pivots", "residual", "ray", "z0", "covering", "warm_start",
          "row_scale", "col_scale", "recoveries")


def _eager(M, q, method="tableau"):
    """What the front built before results were lazy: the kernel run on (M, q), every field
    taken from its buffer at once (the former q >= 0 and solved branches of _lcp._outcome)."""
    n = len(q)
    buf, basic = np.empty(_layout.buffer_length(n)), np.empty(n, dtype=np.int64)
    code, pivots, k, ok, residual, recoveries, stage = _core.solve_one(
        _layout.METHODS[method], M, q, np.empty(0), np.zeros(0, dtype=np.int64), 0, 100 * (n + 1),
        1e-11, 1e-11, 1e-9, buf, basic)
    f = _layout.fields(n)
    z, w, cov, rs, cs = (buf[f[name]] for name in ("z", "w", "covering", "row_scale", "col_scale"))
    if code == _layout.TRIVIAL:
        return LCPResult(z, w, Status.SOLVED, 0, 0.0, None, 0.0, cov, WarmStart(n, ()), rs, cs, 0)
    assert ok and code in (0, int(Status.RAY_TERMINATION))
    ray, z0 = (None, 0.0) if code == 0 else (buf[f["ray"]], float(buf[f["z0"]]))
    return LCPResult(z, w, Status(code), pivots, residual, ray, z0, cov,
                     WarmStart(n, tuple(basic[:k].tolist())), rs, cs, recoveries)


def _same(a, b):
    """Every field bit for bit, type included (a float is a float, an int an int)."""
    assert a == b
    for name in FIELDS:
        x, y = getattr(a, name), getattr(b, name)
        assert type(x) is type(y), name
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name


TRIVIAL = [(np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([1.0, 0.0])),
           (np.array([[1e-8, 3.0, 0.0], [2.0, 1e8, 1.0], [0.0, 1.0, 5.0]]), np.array([0.0, 4.0, 1e-3])),
           (np.zeros((0, 0)), np.zeros(0))]
RAYS = [(np.array([[-1.0]]), np.array([-1.0])),
        (np.array([[-1.0, -2.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]]), np.array([-1.0, 2.0, -3.0]))]


@pytest.mark.parametrize("M, q", TRIVIAL)
def test_q_nonnegative_is_the_eager_value(M, q, method):
    res = lemke.solve_lcp(M, q, method=method)
    _same(res, _eager(M, q, method))
    assert res.success and res.pivots == 0 and res.residual == 0.0 and res.ray is None
    assert not res.z.any() and np.array_equal(res.w, q) and res.warm_start == WarmStart(len(q), ())


@pytest.mark.parametrize("M, q", RAYS)
def test_a_checked_ray_is_the_eager_value(M, q, method):
    res = lemke.solve_lcp(M, q, method=method)
    assert res.status == Status.RAY_TERMINATION
    _same(res, _eager(M, q, method))
    assert_ray(M, q, res.covering, res.z, res.z0, res.ray)


def test_solved_is_the_eager_value(method):
    M, q = problems.contact_like(9, np.random.default_rng(3))
    _same(lemke.solve_lcp(M, q, method=method), _eager(M, q, method))


def _arrays(res):
    return [a for a in (getattr(res, name) for name in FIELDS) if isinstance(a, np.ndarray)]


def _assert_read_only(res):
    for a in _arrays(res):
        assert not a.flags.writeable
        with pytest.raises(ValueError):
            a[...] = 0.0
        with pytest.raises(ValueError):
            a.setflags(write=True)


@pytest.mark.parametrize("M, q", TRIVIAL[:2] + RAYS + [(np.eye(2), -np.ones(2))])
def test_lazy_arrays_are_read_only(M, q):
    res = lemke.solve_lcp(M, q)
    _assert_read_only(res)
    many = lemke.solve_lcp_many([M, M], [q, q])
    for r in many:
        _assert_read_only(r)
        _same(r, res)
    assert not any(np.shares_memory(a, b) for a in _arrays(many[0]) for b in _arrays(many[1]))


def test_fields_read_one_at_a_time_or_all_at_once_agree():
    M, q = problems.contact_like(6, np.random.default_rng(4))
    a, b = lemke.solve_lcp(M, q), lemke.solve_lcp(M, q)
    assert a.warm_start == b.warm_start  # read first on one, last on the other
    assert [getattr(a, name) is None for name in FIELDS] == [getattr(b, name) is None for name in FIELDS]
    _same(a, b)
    with pytest.raises(AttributeError):
        a.nonsense  # noqa: B018
    assert not hasattr(lemke.solve_lcp(M, q), "_nonsense")
    built = LCPResult(*(getattr(a, name) for name in FIELDS))  # the dataclass __init__: eager
    _same(built, a)
    assert "_src" not in built.__dict__


def test_a_lazy_result_pickles_and_copies_as_a_value():
    Ms, qs = [np.eye(2), np.array([[-1.0]]), np.eye(3)], [-np.ones(2), -np.ones(1), np.ones(3)]
    for res in lemke.solve_lcp_many(Ms, qs) + [lemke.solve_lcp(Ms[0], qs[0])]:
        state = res.__getstate__()
        assert "_src" not in state  # the shared buffer stays behind
        back = pickle.loads(pickle.dumps(res))
        _same(back, res)
        _same(copy.copy(res), res)
        assert hash(back) == hash(res)


def _islands(seed, count=60):
    """Islands of 0..12 rows with every outcome: solved, q >= 0, rays."""
    rng = np.random.default_rng(seed)
    Ms, qs = [], []
    for b in range(count):
        n = int(rng.integers(0, 13))
        M, q = problems.contact_like(n, rng) if n >= 2 else (2.0 * np.eye(n), -np.ones(n))
        if b % 7 == 3:
            q = np.abs(q)  # q >= 0
        if b % 11 == 5:
            M, q = RAYS[b % 2]
        Ms.append(np.ascontiguousarray(M))
        qs.append(np.asarray(q, float))
    return Ms, qs


def test_many_is_each_one_for_every_outcome_and_warm_starts_carry_over(method):
    Ms, qs = _islands(5)
    first = lemke.solve_lcp_many(Ms, qs, method=method)
    kinds = {r.status for r in first} | {"trivial" for r in first if r.success and r.pivots == 0}
    assert kinds >= {Status.SOLVED, Status.RAY_TERMINATION, "trivial"}
    for a, M, q in zip(first, Ms, qs):
        _same(a, lemke.solve_lcp(M, q, method=method))
        if a.success:
            assert_lcp_solution(M, q, a.z)
    rng = np.random.default_rng(6)
    qs2 = [q + 1e-3 * rng.standard_normal(q.shape) for q in qs]
    ws = [r.warm_start for r in first]  # carrying their index arrays
    ws[1] = None
    ws[2] = WarmStart(ws[2].n, ws[2].z_basic)  # a user-made one, without
    second = lemke.solve_lcp_many(Ms, qs2, method=method, warm_start=ws)
    for b, (r, M, q, w) in enumerate(zip(second, Ms, qs2, ws)):
        one = lemke.solve_lcp(M, q, method=method, warm_start=w)
        _same(r, one)
        assert r.warm_start is w or w is None or r.pivots > 0 or r.warm_start == w
    assert any(r.pivots == 0 and r.warm_start is w for r, w in zip(second, ws))
    third = lemke.solve_lcp_many(Ms, qs2, method=method, warm_start=[r.warm_start for r in second])
    for r, M, q, w in zip(third, Ms, qs2, [r.warm_start for r in second]):
        _same(r, lemke.solve_lcp(M, q, method=method, warm_start=w))


def test_many_takes_any_form_of_input():
    """Non-contiguous, Fortran-ordered, read-only, integer and list input, side by side with
    the fast kind: the same bits as the float64 C-contiguous copies."""
    Ms, qs = _islands(7, count=12)
    odd = [np.asfortranarray(Ms[0]), Ms[1].T.copy().T, Ms[2].tolist(), Ms[3]]
    ro = Ms[4].copy()
    ro.setflags(write=False)
    odd.append(ro)
    q_odd = [qs[0], np.repeat(qs[1], 2)[::2], qs[2].tolist(), qs[3], qs[4]]
    ints = (np.array([[2, 1], [1, 2]]), np.array([-5, -6]))
    got = lemke.solve_lcp_many(odd + Ms[5:] + [ints[0]], q_odd + qs[5:] + [ints[1]])
    for r, M, q in zip(got, Ms + [ints[0].astype(float)], qs + [ints[1].astype(float)]):
        _same(r, lemke.solve_lcp(M, q))
    with pytest.raises(ValueError, match="problem 2"):
        lemke.solve_lcp_many(Ms[:2] + [np.eye(3)], qs[:2] + [np.ones(2)])
    with pytest.raises(ValueError, match="problem 1"):
        lemke.solve_lcp_many([np.eye(2), np.array([[np.nan]])], [np.ones(2), np.ones(1)])
    with pytest.raises(ValueError, match=r"warm_start\[1\]"):
        lemke.solve_lcp_many([np.eye(2), np.eye(1)], [-np.ones(2), -np.ones(1)],
                             warm_start=[None, WarmStart(2, ())])
    with pytest.raises(TypeError, match="WarmStart"):
        lemke.solve_lcp_many([np.eye(1)], [-np.ones(1)], warm_start=[(0,)])


def test_solve_lcp_fast_path_and_its_edges():
    """The fast path calls the kernel's compiled entry point; an unaligned, byte-swapped,
    read-only or strided M goes the validated way and gets the same bits."""
    M, q = problems.contact_like(5, np.random.default_rng(8))
    ref = lemke.solve_lcp(M, q)
    # (options given: the Python fast path; without them the native front solves it)
    lemke.solve_lcp(M, q, method="unrevised", options={"max_pivots": 100})
    assert _lcp._ENTRY.get("unrevised") is not None
    raw = np.zeros(M.size * 8 + 1, dtype=np.uint8)
    unaligned = raw[1:].view(np.float64).reshape(M.shape)
    unaligned[...] = M
    assert not unaligned.flags.aligned
    ro = M.copy()
    ro.setflags(write=False)
    for M2 in (unaligned, M.astype(">f8"), ro, np.asfortranarray(M)):
        _same(lemke.solve_lcp(M2, q), ref)
    with pytest.raises(ValueError, match="NaN"):
        lemke.solve_lcp(np.array([[np.nan]]), np.ones(1))
    with pytest.raises(ValueError, match="unknown method"):
        lemke.solve_lcp(M, q, method="simplex")
    with pytest.raises(ValueError, match="size"):
        lemke.solve_lcp(M, q, warm_start=WarmStart(2, ()))
    ws = ref.warm_start
    assert ws.__dict__["_beta"].tolist() == list(ws.z_basic)  # the index array, carried
    warm = lemke.solve_lcp(M, q, warm_start=ws)
    assert warm.pivots == 0 and warm.warm_start is ws
    back = pickle.loads(pickle.dumps(ws))  # a value: its fields only, no cached index array
    assert back == ws and "_beta" not in back.__dict__ and "_beta" not in copy.copy(ws).__dict__
    _same(lemke.solve_lcp(M, q, warm_start=back), warm)
    assert lemke.solve_lcp(M, q, options={"max_pivots": 1}).pivots <= 1


def test_arrays_of_another_float64_dtype_object_take_the_fast_path_with_the_same_answer():
    """An array can carry a float64 dtype object that is not numpy's own (``is`` fails,
    ``==`` holds; arrays made by some compiled extensions do):
    solve_lcp must accept it as it is and give the bits it gives for numpy's own arrays."""
    rng = np.random.default_rng(7)
    A = rng.standard_normal((5, 5))
    M = A @ A.T + np.eye(5)
    q = rng.standard_normal(5)
    Mk = M.copy().view(np.dtype(np.float64).newbyteorder("="))
    assert Mk.dtype == np.float64 and Mk.dtype is not np.dtype(np.float64)  # the case at hand
    r, rk = lemke.solve_lcp(M, q), lemke.solve_lcp(Mk, q)
    assert rk.status == lemke.Status.SOLVED
    assert rk.z.tobytes() == r.z.tobytes() and rk.pivots == r.pivots
    w = M @ rk.z + q
    assert rk.z.min() >= 0 and w.min() >= -1e-12 and abs(rk.z @ w) <= 1e-12


@pytest.mark.parametrize("method", ["tableau", "unrevised"])
def test_the_native_front_gives_the_python_fronts_results(monkeypatch, method):
    """solve_lcp's commonest call runs whole in src/python_front.cpp (it reads the ndarrays'
    fields itself, after checking NumPy's layout on probes): the same results, bit for bit,
    as the Python front's fast path, on the goldens' LCPs and on problems that need the
    driver's later stages (rays, cycles, failed checks), lazily built fields included; by
    either method (the tableau's first_run, or the unrevised method's solve_one)."""
    from lemke import _core
    import golden

    assert _core.lcp_front_on()
    cases = [(np.ascontiguousarray(M, float), np.ascontiguousarray(q, float))
             for _, M, q in golden.lcp_cases()]
    rng = np.random.default_rng(4)
    for n in (1, 3, 8, 20):
        cases.append((rng.standard_normal((n, n)), rng.standard_normal(n)))  # rays, failures
    cases.append((problems.degenerate().M, problems.degenerate().q))
    # (a warm start's restart from its basis: n >= RESTART_FROM)
    A = rng.standard_normal((_core.RESTART_FROM, _core.RESTART_FROM))
    cases.append((A @ A.T, rng.standard_normal(_core.RESTART_FROM)))
    solve = functools.partial(lemke.solve_lcp, method=method)
    native = [solve(M, q) for M, q in cases]
    # warm: from each answer's own basis on a moved q (0 pivots or a restart), and from
    # another problem's basis of the same size
    moved = [(M, q + 1e-9 * np.abs(q).max(initial=1.0)) for M, q in cases]
    warm = [solve(M, q2, warm_start=r.warm_start) for (M, q2), r in zip(moved, native)]
    others = [solve(M, q, warm_start=WarmStart(len(q), tuple(range(len(q) // 2))))
              for M, q in cases]
    calls = []
    front = _lcp._FRONT
    monkeypatch.setattr(_lcp, "_FRONT", lambda *a: calls.append(a) and None)
    python = [solve(M, q) for M, q in cases]
    python_warm = [solve(M, q2, warm_start=r.warm_start) for (M, q2), r in zip(moved, python)]
    python_others = [solve(M, q, warm_start=WarmStart(len(q), tuple(range(len(q) // 2))))
                     for M, q in cases]
    # (the Python function asked the front, for this method, and did it all itself)
    assert len(calls) == 3 * len(cases) and all(len(a) == (4 if method == "tableau" else 5) for a in calls)
    assert all(front(*a) is not None for a in calls[: len(cases)])
    assert sum(r.pivots == 0 and r.success for r in warm) >= len(cases) // 2
    native, python = native + warm + others, python + python_warm + python_others
    cases = cases + moved + cases
    fields = ("z", "w", "z0", "ray", "covering", "row_scale", "col_scale")
    for (M, q), a, b in zip(cases, native, python):
        assert (a.status, a.pivots, a.recoveries, a.residual) == (b.status, b.pivots, b.recoveries, b.residual)
        assert a.warm_start == b.warm_start
        for f in fields:
            x, y = getattr(a, f), getattr(b, f)
            assert (x is None) == (y is None) and (x is None or np.asarray(x).tobytes() == np.asarray(y).tobytes()), f
        if a.success:
            assert_lcp_solution(M, q, a.z)
            assert not a.z.flags.writeable
    # a checked ray is settled in the native call (lemke::solve goes on from first_run's
    # stage -1 there), not handed back as a tuple for the Python driver
    rays = [(M, q) for (M, q), r in zip(cases, python) if r.status == Status.RAY_TERMINATION]
    assert rays
    code = 0 if method == "tableau" else 1
    assert all(type(front(M, q, None, None, code)) is LCPResult for M, q in rays)


def test_the_native_front_declines_what_is_not_plain():
    """Lists, float32, the other byte order, Fortran order and mismatched shapes are the
    Python front's (which validates them and says what is wrong); a read-only array is
    the native front's (it only reads its inputs)."""
    from lemke import _core

    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-5.0, -6.0])
    ro = q.copy()
    ro.setflags(write=False)
    for a, b in ((M.tolist(), q), (M.astype(np.float32), q), (np.asfortranarray(M), q),
                 (M.astype(M.dtype.newbyteorder()), q), (M, q.astype(q.dtype.newbyteorder())),
                 (M, q[:1]), (M[:1], q), (M, q.reshape(2, 1))):
        assert _core.lcp_front(a, b, None, None) is None
    assert _core.lcp_front(M, ro, None, None).z.tolist() == lemke.solve_lcp(M, q).z.tolist()
    with pytest.raises(ValueError, match="q"):
        lemke.solve_lcp(M, q[:1])
    assert lemke.solve_lcp(np.asfortranarray(M), ro).z.tolist() == lemke.solve_lcp(M, q).z.tolist()


def test_solve_lcp_entry_is_the_python_function_to_its_callers(monkeypatch):
    """``lemke.solve_lcp`` is the core's entry (``_core.lcp_entry``, src/python_front.cpp):
    solve_lcp(M, q) and solve_lcp(M, q, warm_start=ws), each also with method="tableau" or
    "unrevised", go to ``_lcp._FRONT`` with no Python frame, everything else to the Python function it wraps; it reads ``_FRONT`` on each
    call (a test that switches the front off switches it off), takes only a warm start of
    q's size, and shows the function's name, docstring, signature and pickles by name."""
    import inspect

    f = lemke.solve_lcp
    assert f is _lcp.solve_lcp and f.__wrapped__ is _lcp._solve_lcp and f is not f.__wrapped__
    assert (f.__name__, f.__module__, f.__doc__) == ("solve_lcp", "lemke._lcp", _lcp._solve_lcp.__doc__)
    assert str(inspect.signature(f)) == str(inspect.signature(_lcp._solve_lcp))
    assert "warm_start=None" in str(inspect.signature(f)) and repr(f) == repr(_lcp._solve_lcp)
    assert pickle.loads(pickle.dumps(f)) is f
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-5.0, -6.0])
    r = f(M, q)
    ws = r.warm_start
    assert r == _lcp._solve_lcp(M, q) and f(M, q, warm_start=ws) == _lcp._solve_lcp(M, q, warm_start=ws)
    assert f(M, q, warm_start=ws).pivots == 0 and f(M, q, warm_start=None) == r
    calls = []
    monkeypatch.setattr(_lcp, "_FRONT", lambda *a: calls.append(a) or None)
    assert f(M, q) == r and f(M, q, warm_start=ws) == f(M, q, warm_start=ws)
    assert len(calls) == 3 and calls[0][2:] == (None, None) and calls[1][2] is ws
    # method= ("tableau" or "unrevised", in any order with warm_start=) is the front's too
    u = f(M, q, method="unrevised")
    assert f(M, q, warm_start=ws, method="unrevised") == f(M, q, method="unrevised", warm_start=ws)
    assert f(M, q, method="tableau") == r and len(calls) == 7
    assert calls[3][2:] == (None, None, 1) and calls[4][2:] == (ws, ws._beta, 1)
    assert calls[6][2:] == (None, None)
    monkeypatch.undo()
    assert f(M, q, method="unrevised") == u and u.pivots > 0
    assert f(M, q, method="unrevised", warm_start=ws).warm_start is ws
    with pytest.raises(ValueError, match="unknown method"):
        f(M, q, method="Tableau")  # (a str the entry does not know: the Python function's)
    # a warm start of another size whose basis is in range for q: the Python front refuses it
    with pytest.raises(ValueError, match="warm_start is for a problem of size 3, this one has n = 2"):
        f(M, q, warm_start=WarmStart(3, (0,)))
    with pytest.raises(TypeError):
        f(M, q, warm_start=(0,))
    with pytest.raises(TypeError):
        f(M)
    with pytest.raises(TypeError):
        f(M, q, None)  # keyword-only, as the Python function's
    # the entry's other calls: the Python function's (lists, options)
    assert f(M.tolist(), q.tolist()) == r
    assert f(M, q, method="unrevised") == _lcp._solve_lcp(M, q, method="unrevised")
    assert_lcp_solution(M, q, f(M, q, method="unrevised").z)
    assert f(M, q, options={"max_pivots": 10}) == r


def test_read_only_inputs_take_the_native_fronts_and_give_the_same_bits():
    """Read-only arrays (pandas' copy-on-write ``to_numpy()``, ``lemke.problems``' own
    arrays) are read in place by the native fronts: the same bits as writable copies, on
    solved, warm, ray, box, friction and game calls, and the inputs unchanged."""
    from lemke import _core

    def ro(*arrays):
        out = []
        for a in arrays:
            a = np.array(a, dtype=float)
            a.setflags(write=False)
            out.append(a)
        return out

    def same(a, b, fields):
        assert a.status == b.status and a.pivots == b.pivots
        for f in fields:
            x, y = getattr(a, f), getattr(b, f)
            assert (x is None) == (y is None)
            if x is not None:
                assert np.asarray(x).tobytes() == np.asarray(y).tobytes(), f

    rng = np.random.default_rng(31)
    murty = problems.murty(4)  # its arrays are read-only already
    assert not murty.M.flags.writeable
    cases = [problems.contact_like(6, rng), (murty.M, murty.q)]
    A = rng.standard_normal((5, 5))
    cases.append((A @ A.T + np.eye(5), rng.standard_normal(5)))
    cases.append((-np.eye(3), -np.ones(3)))  # a ray
    for M, q in cases:
        Mr, qr = ro(M, q)
        ref = lemke.solve_lcp(np.array(M), np.array(q))
        got = lemke.solve_lcp(Mr, qr)
        same(got, ref, ("z", "w", "ray"))
        if got.status == Status.SOLVED:
            assert_lcp_solution(np.array(M), np.array(q), got.z)
        assert _core.lcp_front(Mr, qr, None, None) is not None
        if ref.warm_start is not None:
            q2 = np.array(q) + 1e-9
            (q2r,) = ro(q2)
            same(lemke.solve_lcp(Mr, q2r, warm_start=ref.warm_start),
                 lemke.solve_lcp(np.array(M), q2, warm_start=ref.warm_start), ("z", "w"))
        assert not Mr.flags.writeable and Mr.tobytes() == np.array(M).tobytes()
    # box LCPs, with and without friction, cold and warm
    M, q = problems.contact_like(6, np.random.default_rng(5))
    lo, hi = -np.ones(6), np.ones(6)
    lo[[0, 3]], hi[[0, 3]] = 0.0, np.inf
    findex = np.array([-1, 0, 0, -1, 3, 3], dtype=np.int64)
    for kw in ({}, {"findex": findex}):
        Mr, qr, lor, hir = ro(M, q, lo, hi)
        ref = lemke.solve_blcp(M.copy(), q.copy(), lo.copy(), hi.copy(), **kw)
        same(lemke.solve_blcp(Mr, qr, lor, hir, **kw), ref, ("z", "w"))
        same(lemke.solve_blcp(Mr, qr, lor, hir, warm_start=ref.warm_start, **kw),
             lemke.solve_blcp(M.copy(), q.copy(), lo.copy(), hi.copy(), warm_start=ref.warm_start, **kw),
             ("z", "w"))
    # a bimatrix game
    Ag, Bg = rng.standard_normal((4, 3)), rng.standard_normal((4, 3))
    Agr, Bgr = ro(Ag, Bg)
    same(lemke.solve_bimatrix(Agr, Bgr), lemke.solve_bimatrix(Ag.copy(), Bg.copy()), ("x", "y"))
