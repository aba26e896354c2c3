"""Array-likes on the native fronts: an argument that is not a float64 C array (lists,
tuples, int / bool / float32 arrays, Fortran-ordered, strided, read-only or byte-swapped
float64 arrays, scalar box bounds) is converted once, as the validation converts it, and
the call then takes the native front: every public entry answers exactly (bit for bit) what
it answers for the float64 C arrays of the same values, never writes to the caller's
objects, and every input it refuses (NaN, infinities, shapes, ragged rows, str, complex,
object, sparse...) raises exactly the error the validation raised before, the conversion
off."""
import copy

import numpy as np
import pytest
import scipy.sparse as sp

import lemke
from lemke import _blcp_many, _core, _qp, _validate


def _f64(x):
    """The float64 C array the validation makes of x."""
    return np.ascontiguousarray(np.asarray(x).astype(np.float64))


def _forms(a, integral=False):
    """a in every form that converts cleanly: (name, form), the same names for every a."""
    out = [("list", a.tolist()), ("tuple", tuple(map(tuple, a)) if a.ndim == 2 else tuple(a.tolist())),
           ("float32", a.astype(np.float32)), ("swapped", a.astype(a.dtype.newbyteorder())),
           ("strided", np.repeat(a, 2, axis=-1)[..., ::2])]
    ro = np.asfortranarray(a).copy(order="F")  # (a 1-D one: a plain array, read-only)
    ro.setflags(write=False)
    out += [("fortran", np.asfortranarray(a)), ("read-only fortran", ro)]
    if integral:
        out += [("int list", a.astype(np.int64).tolist()), ("int32", a.astype(np.int32)),
                ("uint8" if (a >= 0).all() else "int8", a.astype(np.uint8 if (a >= 0).all() else np.int8))]
    return out


def _same(a, b, fields=None):
    """Every field bit for bit (fields None: the result's own bitwise key, all its fields)."""
    assert type(a) is type(b)
    if fields is None:
        assert a._keys() == b._keys()
        return
    for name in fields:
        x, y = getattr(a, name), getattr(b, name)
        assert type(x) is type(y), name
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name
        elif isinstance(x, float):
            assert x == y or (x != x and y != y), name
        else:
            assert x == y, name


def _untouched(objs, call):
    """call(), the objects compared before and after (values, dtypes, flags)."""
    before = [copy.deepcopy(o) for o in objs]
    flags = [o.flags.writeable if isinstance(o, np.ndarray) else None for o in objs]
    out = call()
    for o, b, f in zip(objs, before, flags):
        if isinstance(o, np.ndarray):
            assert o.dtype == b.dtype and o.tobytes() == b.tobytes() and o.flags.writeable == f
        else:
            assert o == b
    return out


@pytest.fixture
def no_validation(monkeypatch):
    """Make the validation path fail the test: a converted call must end in the front."""
    def refuse(*a, **k):
        raise AssertionError("the validation path was taken")
    for name in ("lcp", "blcp", "bimatrix", "qp"):
        monkeypatch.setattr(_validate, name, refuse)


def _old(monkeypatch):
    """The path of today's array-likes: no conversion (the validation does it all)."""
    for name in ("plain_lcp", "plain_blcp", "plain_all", "plain_many", "plain_islands"):
        monkeypatch.setattr(_validate, name, lambda *a: None)
    monkeypatch.setattr(_blcp_many, "_PACK", lambda *a: None)  # (solve_blcp_many's packing)
    # solve_qp's front on plain data only (its own conversion off: it declines the rest)
    front = _qp._QP_FRONT
    monkeypatch.setattr(_qp, "_QP_FRONT", lambda *a: front(*a) if _core.all_f64(
        a[:8] + a[10:], _qp._RANKS) is False else None)


LCP_FIELDS = ("z", "w", "status", "pivots", "residual", "ray", "z0", "covering", "warm_start",
              "row_scale", "col_scale", "recoveries")


def _lcp_data(n=5, seed=1):
    rng = np.random.default_rng(seed)
    A = rng.integers(-3, 4, (n, n))
    return (A @ A.T + np.eye(n, dtype=np.int64)).astype(np.float64), rng.integers(-9, 9, n).astype(np.float64)


@pytest.mark.parametrize("method", ["tableau", "unrevised"])
def test_lcp_forms_bit_for_bit(method, no_validation):
    M, q = _lcp_data()
    want = lemke.solve_lcp(M, q, method=method)
    assert want.success and want.pivots > 0
    ws = want.warm_start
    for (nm, Mx), (nq, qx) in zip(_forms(M, True), _forms(q, True)):
        for Mi, qi in ((Mx, qx), (Mx, q), (M, qx)):
            got = _untouched([Mi, qi], lambda: lemke.solve_lcp(Mi, qi, method=method))
            _same(got, lemke.solve_lcp(_f64(Mi), _f64(qi), method=method), LCP_FIELDS)
            # warm (from its own basis: 0 pivots; from another q: a restart)
            for qw in (qi, _f64(qi) - 3.0):
                got = lemke.solve_lcp(Mi, qw, method=method, warm_start=ws)
                _same(got, lemke.solve_lcp(_f64(Mi), _f64(qw), method=method, warm_start=ws),
                      LCP_FIELDS)


def test_lcp_bool_empty_and_rays(no_validation):
    Mb = np.array([[True, False], [False, True]])
    _same(lemke.solve_lcp(Mb, [-1, -2]), lemke.solve_lcp(np.eye(2), np.array([-1.0, -2.0])), LCP_FIELDS)
    _same(lemke.solve_lcp([], []), lemke.solve_lcp(np.zeros((0, 0)), np.zeros(0)), LCP_FIELDS)
    _same(lemke.solve_lcp((), np.zeros(0)), lemke.solve_lcp(np.zeros((0, 0)), np.zeros(0)), LCP_FIELDS)
    ray = lemke.solve_lcp([[-1, -2, 0], [1, 3, 1], [0, 1, 2]], [-1, 2, -3])
    assert ray.status == lemke.Status.RAY_TERMINATION
    _same(ray, lemke.solve_lcp(np.array([[-1.0, -2, 0], [1, 3, 1], [0, 1, 2]]), np.array([-1.0, 2, -3])),
          LCP_FIELDS)


BAD_LCP = [
    ([[1.0, np.nan], [0.0, 1.0]], [-1.0, -1.0]),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, np.inf]),
    ([[1, 0], [0, 1]], [-1, -1, -1]),
    ([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [-1.0, -1.0]),
    ([[1.0, 0.0], [0.0]], [-1.0, -1.0]),
    ([["1", "0"], ["0", "1"]], [-1.0, -1.0]),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0 + 1j, -1.0]),
    ([[1.0, None], [0.0, 1.0]], [-1.0, -1.0]),
    ([[1.0, 0.0], [0.0, 1.0]], [[-1.0, -1.0]]),
    ([], [-1.0]),
    (np.eye(2, dtype=np.float32), np.array([np.nan, 1.0], dtype=np.float32)),
    (np.asfortranarray([[1.0, 2.0], [np.inf, 1.0]]), [-1.0, -1.0]),
    ([[2 ** 64, 0], [0, 1]], [-1, -1]),
    (sp.csr_matrix(np.eye(2)), [-1.0, np.nan]),
]


def _error(call):
    try:
        call()
    except Exception as e:  # noqa: BLE001 (compared)
        return type(e), str(e)
    return None


def _errors(monkeypatch, call):
    """The error ``call`` raises (``_error``'s pair, or None) with the conversions on, and
    the one it raises with them off (``_old``): the two to compare."""
    got = _error(call)
    with monkeypatch.context() as m:
        _old(m)
        return got, _error(call)


@pytest.mark.parametrize("M, q", BAD_LCP)
def test_lcp_errors_as_before(M, q, monkeypatch):
    for kw in ({}, {"method": "unrevised"}, {"warm_start": lemke.WarmStart(2, ())}):
        got, want = _errors(monkeypatch, lambda: lemke.solve_lcp(M, q, **kw))
        assert got is not None
        assert got == want


def test_lcp_warm_start_errors_as_before(monkeypatch):
    M, q = _lcp_data(3)
    for ws in (lemke.WarmStart(2, ()), (0, 1), lemke.BoxWarmStart(3, (), ())):
        got, want = _errors(monkeypatch, lambda: lemke.solve_lcp(M.tolist(), q.tolist(), warm_start=ws))
        assert got is not None
        assert got == want


@pytest.mark.parametrize("B", [2, 9])
@pytest.mark.parametrize("method", ["tableau", "unrevised"])
def test_lcp_many_forms_bit_for_bit(B, method, monkeypatch):
    probs = [_lcp_data(1 + b % 4, seed=b) for b in range(B)]
    Ms, qs = [p[0] for p in probs], [p[1] for p in probs]
    want = lemke.solve_lcp_many(Ms, qs, method=method, workers=1)
    ws = want.warm_start
    monkeypatch.setattr(_validate, "lcp", lambda *a: (_ for _ in ()).throw(AssertionError("validated")))
    for i in range(len(_forms(Ms[0], True))):
        Mx = [_forms(M, True)[i][1] for M in Ms]
        qx = [_forms(q, True)[i][1] for q in qs]
        got = _untouched(Mx + qx, lambda: lemke.solve_lcp_many(Mx, qx, method=method, workers=1))
        assert len(got) == B
        for a, b in zip(got, want):
            _same(a, b, LCP_FIELDS)
        for name in ("z", "w", "status", "pivots", "residual"):
            assert np.asarray(getattr(got, name)).tobytes() == np.asarray(getattr(want, name)).tobytes()
        ref = ([_f64(M) for M in Mx], [_f64(q) for q in qx])
        for kw in ({}, {"warm_start": ws}):  # (no other keyword: the entry's own path)
            for a, b in zip(lemke.solve_lcp_many(Mx, qx, **kw), lemke.solve_lcp_many(*ref, **kw)):
                _same(a, b, LCP_FIELDS)
        again = lemke.solve_lcp_many(Mx, [q - 1.0 for q in qs], method=method, warm_start=ws)
        for a, b in zip(again, lemke.solve_lcp_many(Ms, [q - 1.0 for q in qs], method=method,
                                                    warm_start=ws)):
            _same(a, b, LCP_FIELDS)


@pytest.mark.parametrize("B", [2, 9])
def test_lcp_many_errors_as_before(B, monkeypatch):
    Ms = [np.eye(2).tolist() for _ in range(B)]
    qs = [[-1.0, -1.0] for _ in range(B)]
    cases = []
    for bad in ([np.nan, -1.0], [-1.0], [[-1.0, -1.0]], ["a", "b"], [1j, 0.0]):
        q2 = list(qs)
        q2[1] = bad
        cases.append((Ms, q2))
    cases.append((Ms, [[np.nan, -1.0]] + qs[1:]))
    M2 = list(Ms)
    M2[0] = [[1.0, 0.0], [0.0]]
    q2 = list(qs)
    q2[1] = [np.inf, 0.0]
    cases += [(M2, qs), (Ms, q2), (Ms[:1], qs)]
    bad_ws = [None] * (B - 1) + [lemke.WarmStart(3, ())]
    for M, q in cases:
        for kw in ({"workers": 1}, {}, {"warm_start": bad_ws}):
            got, want = _errors(monkeypatch, lambda: lemke.solve_lcp_many(M, q, **kw))
            assert got is not None
            assert got == want


def test_lcp_pack_converts_as_made_f64(monkeypatch):
    """solve_lcp_many's packing (_core.lcp_pack) takes every form made_f64 converts, mixed
    in one batch, and packs the values of the float64 arrays (NumPy's conversion); it
    declines (None) what made_f64 declines, and a NaN or an infinity anywhere once any
    problem needed converting (the Python path then raises at the first fault in order),
    while plain arrays alone are packed as they are (their finiteness the kernels')."""
    from lemke import _core
    probs = [_lcp_data(1 + b % 5, seed=b) for b in range(23)]
    Ms, qs = [p[0] for p in probs], [p[1] for p in probs]
    def forms(a):  # (a byte-swapped array is NumPy's to convert: made_f64 declines it)
        return [x for name, x in _forms(a, True) if name != "swapped"]
    k = len(forms(Ms[0]))
    Mx = [forms(M)[b % k] for b, M in enumerate(Ms)]  # (every form, mixed)
    qx = [forms(q)[(b + 3) % k] for b, q in enumerate(qs)]
    Mx[4], qx[5] = Ms[4], qs[5]  # (plain arrays among them)
    Ms[6], qs[6] = np.full((2, 2), 2.0 ** 40) + np.eye(2), np.array([-(2.0 ** 31), 2.0 ** 30 - 1])
    Mx[6], qx[6] = Ms[6].astype(np.int64).tolist(), [-2 ** 31, 2 ** 30 - 1]  # (ints of 1 and 2 digits)
    for M, q in ((Mx, qx), (tuple(Mx), tuple(qx))):
        got = _untouched(list(M) + list(q), lambda: _core.lcp_pack(M, q))
        want = np.concatenate([_f64(m).ravel() for m in M]), np.concatenate([_f64(v) for v in q])
        assert got is not None
        assert got[0].dtype == got[1].dtype == np.float64
        assert got[0].tobytes() == want[0].tobytes() and got[1].tobytes() == want[1].tobytes()
        assert got[2].dtype == np.int64 and got[2].tolist() == [len(v) for v in qs]
    declined = [[[1.0, 2.0], [3.0]], [["1", "2"], ["3", "4"]], [[np.int64(1), 0], [0, 1]],
                np.ones((2, 2), np.float16), np.ones((2, 2), np.uint64), [[2 ** 64, 0], [0, 1]],
                np.ones(4).tolist(), np.ones((2, 3)).tolist(), sp.eye(2), [[None, 1.0], [1.0, 1.0]]]
    for bad in declined:
        M2 = list(Mx[:3]) + [bad]
        q2 = list(qx[:3]) + [[-1.0, -1.0]]
        assert _core.lcp_pack(M2, q2) is None, bad
    swapped = np.eye(2).astype(">f8")
    assert _core.lcp_pack(Mx[:3] + [swapped], qx[:3] + [[-1.0, -1.0]]) is None
    for bad in ([np.nan, -1.0], [-1.0, np.inf], np.array([-np.inf, 1.0], np.float32)):
        assert _core.lcp_pack(Mx[:3] + [np.eye(2)], qx[:3] + [bad]) is None
    nan_plain = np.array([np.nan, -1.0])
    assert _core.lcp_pack(Mx[:3] + [np.eye(2)], qx[:3] + [nan_plain]) is None  # (converted ones)
    plain = _core.lcp_pack(Ms[:3] + [np.eye(2)], qs[:3] + [nan_plain])
    assert plain is not None and np.isnan(plain[1][-2])
    # the same answers bit for bit as the float64 arrays, through the packed path
    monkeypatch.setattr(_validate, "plain_many", lambda *a: (_ for _ in ()).throw(AssertionError("python path")))
    want = lemke.solve_lcp_many(Ms, qs, workers=1)
    got = lemke.solve_lcp_many(Mx, qx, workers=1)
    for a, b in zip(got, want):
        _same(a, b, LCP_FIELDS)
    for name in ("z", "w", "status", "pivots", "residual"):
        assert np.asarray(getattr(got, name)).tobytes() == np.asarray(getattr(want, name)).tobytes()


def test_lcp_many_nonfinite_order_as_before(monkeypatch):
    """A NaN or an infinity among converted problems raises what the Python path raised
    (the first fault in order, problem and entry named), wherever it sits among lists and
    plain arrays; among plain arrays alone the kernels find it (NOT_FINITE), as before."""
    B = 12
    Ms = [np.eye(2) for _ in range(B)]
    qs = [np.array([-1.0, -2.0]) for _ in range(B)]
    cases = []
    for at_M, at_q, lists in ((7, 3, "q"), (2, 9, "M"), (5, 5, "both"), (None, 6, "M"), (8, None, "q")):
        M2 = [m.tolist() if lists in ("M", "both") else m for m in Ms]
        q2 = [v.tolist() if lists in ("q", "both") else v for v in qs]
        if at_M is not None:
            M2[at_M] = np.array([[1.0, np.nan], [0.0, 1.0]]) if lists == "q" else [[1.0, np.inf], [0.0, 1.0]]
        if at_q is not None:
            q2[at_q] = np.array([np.inf, 0.0]) if lists == "M" else [np.nan, 0.0]
        cases.append((M2, q2))
    for M, q in cases:
        got, want = _errors(monkeypatch, lambda: lemke.solve_lcp_many(M, q, workers=1))
        assert got is not None and "problem" in got[1]
        assert got == want
    q2 = list(qs)
    q2[4] = np.array([np.nan, 0.0])
    got = _error(lambda: lemke.solve_lcp_many(Ms, q2, workers=1))  # (the kernels' NOT_FINITE)
    assert got == (ValueError, "problem 4: q has a NaN or infinite entry at index (0,)")


BLCP_FIELDS = ("z", "w", "status", "pivots", "residual", "ray", "z0", "covering", "warm_start",
               "lo", "hi", "row_scale", "col_scale", "recoveries")


def test_blcp_forms_bit_for_bit(no_validation):
    M, q = _lcp_data(4, seed=3)
    lo, hi = -np.ones(4), np.full(4, 2.0)
    want = lemke.solve_blcp(M, q, lo, hi)
    assert want.success
    ws = want.warm_start
    for (_, Mx), (_, qx), (_, lx), (_, hx) in zip(_forms(M, True), _forms(q, True),
                                                 _forms(lo, True), _forms(hi, True)):
        args = (Mx, qx, lx, hx)
        got = _untouched(list(args), lambda: lemke.solve_blcp(*args))
        ref = tuple(map(_f64, args))
        _same(got, lemke.solve_blcp(*ref), BLCP_FIELDS)
        _same(lemke.solve_blcp(*args, warm_start=ws), lemke.solve_blcp(*ref, warm_start=ws),
              BLCP_FIELDS)
    for lo_s, hi_s in ((-1.0, 2.0), (-1, 2), (-np.inf, 2.0), (0.0, np.inf)):
        got = lemke.solve_blcp(M.tolist(), q, lo_s, hi_s)
        _same(got, lemke.solve_blcp(M, q, np.full(4, float(lo_s)), np.full(4, float(hi_s))),
              BLCP_FIELDS)


def test_blcp_friction_index_forms(no_validation):
    from test_blcp import contacts
    M, q, lo, hi, findex, mu = contacts(2, 3)
    f64 = np.asarray(findex).astype(np.int64)
    want = lemke.solve_blcp(M, q, lo, hi, findex=f64)
    ws = want.warm_start
    for f in (f64.tolist(), f64.astype(np.int32), tuple(f64.tolist())):
        for args in ((M.tolist(), q.tolist(), lo.tolist(), hi.tolist()), (M, q, lo, hi)):
            got = _untouched([f, *args], lambda: lemke.solve_blcp(*args, findex=f))
            _same(got, want, BLCP_FIELDS)
            _same(lemke.solve_blcp(*args, findex=f, warm_start=ws),
                  lemke.solve_blcp(M, q, lo, hi, findex=f64, warm_start=ws), BLCP_FIELDS)


BAD_BLCP = [
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], [np.nan, 0.0], [1.0, 1.0], None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], np.nan, 1.0, None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], np.inf, 1.0, None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], 0.0, -np.inf, None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], [2.0, 0.0], [1.0, 1.0], None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, np.nan], 0.0, 1.0, None),
    ([[1, 0], [0, 1]], [-1, -1, -1], 0, 1, None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], [0.0, 0.0, 0.0], 1.0, None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], -1.0, 1.0, [1, 1]),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], -1.0, 1.0, [-1, 5]),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], [0.0, -1.0], [1.0, 1.0], [-1, 0.5]),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], [0.0, -1.0], [1.0, 1.0], [-1, 0, 0]),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], "0", 1.0, None),
    ([[1.0, 0.0], [0.0, 1.0]], [-1.0, -1.0], 2 ** 70, 2 ** 71, None),
]


@pytest.mark.parametrize("M, q, lo, hi, findex", BAD_BLCP)
def test_blcp_errors_as_before(M, q, lo, hi, findex, monkeypatch):
    got, want = _errors(monkeypatch, lambda: lemke.solve_blcp(M, q, lo, hi, findex=findex))
    assert got == want
    assert got is not None or findex is None


@pytest.mark.parametrize("B", [2, 4, 7])
def test_blcp_many_forms_bit_for_bit(B, monkeypatch):
    from test_blcp import contacts
    isl = [contacts(b, 1 + b % 2)[:5] for b in range(B)]
    Ms, qs, los, his = ([np.asarray(i[k], dtype=float) for i in isl] for k in range(4))
    fis = [np.asarray(i[4]).astype(np.int64) for i in isl]
    ws = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, workers=1).warm_start
    forms = []
    for i in range(len(_forms(Ms[0]))):
        args = [[_forms(x, False)[i][1] for x in xs] for xs in (Ms, qs, los, his)]
        ref = [[_f64(x) for x in xs] for xs in args]  # (float32: its values in float64)
        forms.append((args, ref, lemke.solve_blcp_many(*ref, findex=fis, workers=1),
                      lemke.solve_blcp_many(*ref, findex=fis, warm_start=ws),
                      lemke.solve_blcp_many(ref[0], ref[1], -1.0, 2.0)))
    fl = [f.tolist() for f in fis]
    with monkeypatch.context() as m:
        m.setattr(_validate, "blcp", lambda *a: (_ for _ in ()).throw(AssertionError("validated")))
        for args, ref, want, warm, cold in forms:
            got = _untouched(args[0] + args[1] + fl, lambda: lemke.solve_blcp_many(*args, findex=fl))
            assert len(got) == B
            for a, b in zip(got, want):
                _same(a, b)
            for a, b in zip(lemke.solve_blcp_many(*args, findex=fl, warm_start=ws), warm):
                _same(a, b)
            for a, b in zip(lemke.solve_blcp_many(args[0], args[1], -1.0, 2.0), cold):
                _same(a, b)


def test_blcp_many_errors_as_before(monkeypatch):
    M = [np.eye(2).tolist(), np.eye(2).tolist()]
    q = [[-1.0, -1.0], [-1.0, -1.0]]
    cases = [dict(M=M, q=[q[0], [np.nan, 1.0]], lo=0.0, hi=1.0),
             dict(M=M, q=q, lo=[[0.0, 0.0], [2.0, 0.0]], hi=[[1.0, 1.0], [1.0, 1.0]]),
             dict(M=M, q=[q[0], [1.0]], lo=0.0, hi=1.0),
             dict(M=M, q=q, lo=0.0, hi=1.0, findex=[[-1, -1], [1, 1]]),
             dict(M=M, q=q, lo=0.0, hi=1.0, warm_start=[None, lemke.BoxWarmStart(3, (), ())]),
             dict(M=M, q=[q[0], [np.nan, 1.0]], lo=0.0, hi=1.0,
                  warm_start=[None, lemke.BoxWarmStart(3, (), ())]),
             dict(M=M, q=q, lo=np.nan, hi=1.0), dict(M=M, q=q[:1], lo=0.0, hi=1.0)]
    for kw in cases:
        got, want = _errors(monkeypatch, lambda: lemke.solve_blcp_many(**kw))
        assert got is not None
        assert got == want


def _scene(B=23):
    """B contact islands (float64 arrays, int64 findex), a few without friction rows."""
    from test_blcp import contacts
    isl = [contacts(b, 1 + b % 3)[:5] for b in range(B)]
    Ms, qs, los, his = ([np.asarray(i[k], dtype=float) for i in isl] for k in range(4))
    fis = [np.asarray(i[4]).astype(np.int64) if b % 5 else None for b, i in enumerate(isl)]
    return Ms, qs, los, his, fis


def test_blcp_pack_converts_as_made_f64():
    """solve_blcp_many's packing (_core.blcp_pack) takes every form made_f64 converts (and
    Python numbers for bounds, int lists for findex), mixed in one batch, and packs the
    values the validation makes; it declines what made_f64 declines, and anything the
    validation refuses once any island needed converting; plain arrays alone are packed as
    they are (their data the kernels' to judge)."""
    from lemke import _core
    Ms, qs, los, his, fis = _scene()
    def forms(a):  # (a byte-swapped array is NumPy's to convert: made_f64 declines it)
        return [x for name, x in _forms(a, False) if name != "swapped"]
    k = len(forms(Ms[0]))
    Mx = [forms(M)[b % k] for b, M in enumerate(Ms)]
    qx = [forms(q)[(b + 2) % k] for b, q in enumerate(qs)]
    lx = [forms(v)[(b + 4) % k] for b, v in enumerate(los)]
    hx = [forms(v)[(b + 4) % k] for b, v in enumerate(his)]  # (lo's form: lo = -hi in float32 too)
    fx = [f if f is None or b % 2 else f.tolist() for b, f in enumerate(fis)]
    Mx[4], qx[5], lx[10] = Ms[4], qs[5], 0.0  # (plain arrays and a scalar bound among them)
    for M, q, lo, hi, f in ((Mx, qx, lx, hx, fx), (tuple(Mx), tuple(qx), lx, 2, None)):
        got = _untouched(list(M) + list(q) + [x for x in fx if x is not None],
                         lambda: _core.blcp_pack(M, q, lo, hi, f))
        assert got is not None
        def spread(xs):  # (a Python number: np.full(n_b, float(x)), as the validation spreads it)
            xs = [xs] * len(qs) if isinstance(xs, (int, float)) else xs
            return [np.full(len(v), float(x)) if isinstance(x, (int, float)) else _f64(x) for x, v in zip(xs, qs)]
        want = [np.concatenate([_f64(x).ravel() for x in xs]) for xs in (M, q, spread(lo), spread(hi))]
        for a, b in zip(got[:4], want):
            assert a.dtype == np.float64 and a.tobytes() == b.tobytes()
        if f is None:
            assert got[4] is None and got[5].tolist() == [0] * len(qs)
        else:
            wf = np.concatenate([np.full(len(v), -1) if x is None else np.asarray(x) for x, v in zip(f, qs)])
            assert got[4].dtype == np.int64 and got[4].tolist() == wf.tolist()
            assert got[5].tolist() == [int(x is not None) for x in f]
        assert got[6].dtype == np.int64 and got[6].tolist() == [len(v) for v in qs]
    def swap(b, **kw):
        args = dict(M=list(Mx), q=list(qx), lo=list(lx), hi=list(hx), findex=list(fx))
        for name, v in kw.items():
            args[name][b] = v
        return _core.blcp_pack(args["M"], args["q"], args["lo"], args["hi"], args["findex"])
    n = len(qs[3])
    declined = [dict(M=np.ones((n, n), np.float16)), dict(M=[[1.0] * n] * (n - 1) + [[1.0]]),
                dict(q=[np.int64(1)] * n), dict(q=np.ones(n).astype(">f8")), dict(lo=np.zeros(n + 1)),
                dict(lo=np.float64(0.0)), dict(hi=True), dict(hi=2 ** 64), dict(findex=[-1.0] * n),
                dict(findex=[True] * n), dict(findex=np.full(n, -1, np.int32)), dict(findex=[-1] * (n + 1)),
                dict(findex=[2 ** 63] + [-1] * (n - 1)),
                # what the validation refuses: NaN, infinities, lo > hi, friction rows
                dict(q=[np.nan] * n), dict(M=np.full((n, n), np.inf)), dict(lo=np.inf), dict(hi=-np.inf),
                dict(lo=np.nan), dict(lo=1.0, hi=0.0), dict(findex=[n] + [-1] * (n - 1)),
                dict(findex=[0] + [-1] * (n - 1)), dict(findex=[1, 0] + [-1] * (n - 2)),
                dict(findex=[1] + [-1] * (n - 1), lo=[-1.0] + [0.0] * (n - 1), hi=np.inf),
                dict(findex=[-1, 0] + [-1] * (n - 2), lo=[0.0, -1.0] + [0.0] * (n - 2), hi=[1.0, 2.0] + [1.0] * (n - 2)),
                dict(findex=[-1, 0] + [-1] * (n - 2), lo=[0.0, -np.inf] + [0.0] * (n - 2), hi=np.inf),
                dict(findex=[-1, 0] + [-1] * (n - 2), lo=[-1.0, -1.0] + [0.0] * (n - 2), hi=1.0)]
    for kw in declined:
        assert swap(3, **kw) is None, kw
    assert swap(3, findex=[-1, 0] + [-1] * (n - 2), lo=[0.0, -1.0] + [0.0] * (n - 2), hi=1.0) is not None
    nan_plain = np.full(len(qs[0]), np.nan)
    plain = _core.blcp_pack(Ms, [nan_plain] + qs[1:], los, his, fis)  # (plain: the kernels')
    assert plain is not None and np.isnan(plain[1][0])
    assert _core.blcp_pack(Ms, qs, los, his, fis[:-1]) is None
    assert _core.blcp_pack(Ms, qs, los, np.float64(1.0), None) is None


def test_blcp_many_lists_bit_for_bit(monkeypatch):
    """A scene of islands given as lists (and scalar bounds, int-list friction indices) is
    packed natively, never validated in Python, and answers bit for bit what the float64
    arrays answer: cold, warm and with one bound for all."""
    Ms, qs, los, his, fis = _scene(41)
    want = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, workers=1)
    warm = lemke.solve_blcp_many(Ms, qs, los, his, findex=fis, warm_start=want.warm_start)
    cold = lemke.solve_blcp_many(Ms, qs, -1.0, 2.0, workers=2)
    L = [[x.tolist() for x in xs] for xs in (Ms, qs, los, his)]
    fl = [None if f is None else f.tolist() for f in fis]
    refuse = lambda *a: (_ for _ in ()).throw(AssertionError("validated"))  # noqa: E731
    monkeypatch.setattr(_validate, "blcp", refuse)
    monkeypatch.setattr(_blcp_many, "_islands", refuse)
    for got, ref in ((lemke.solve_blcp_many(*L, findex=fl, workers=1), want),
                     (lemke.solve_blcp_many(*L, findex=fl, warm_start=want.warm_start), warm),
                     (lemke.solve_blcp_many(L[0], L[1], -1, 2.0, workers=2), cold)):
        assert len(got) == len(ref)
        for a, b in zip(got, ref):
            _same(a, b)
        for name in ("z", "w", "lo", "hi", "status", "pivots", "residual", "recoveries"):
            assert getattr(got, name).tobytes() == getattr(ref, name).tobytes(), name
        assert got.warm_start.state.tobytes() == ref.warm_start.state.tobytes()
    assert all(want.success)


def test_blcp_many_batch_errors_as_before(monkeypatch):
    """Faults among many islands given as lists (the batch's packing) raise what the Python
    path raised, the packing off: the first faulty island, the argument, NaN vs shape."""
    Ms, qs, los, his, fis = _scene(20)
    L = [[x.tolist() for x in xs] for xs in (Ms, qs, los, his)]
    fl = [None if f is None else f.tolist() for f in fis]
    def case(**kw):
        args = dict(M=list(L[0]), q=list(L[1]), lo=list(L[2]), hi=list(L[3]), findex=list(fl))
        for key, v in kw.items():
            name, b = key.rsplit("_", 1)
            args[name][int(b)] = v
        return args
    n7, n3 = len(qs[7]), len(qs[3])
    cases = [case(q_7=[np.nan] * n7), case(q_7=[np.nan] * n7, M_3=np.ones((n3 + 1, n3 + 1)).tolist()),
             case(M_7=np.full((n7, n7), np.inf).tolist(), q_3=[1.0] * (n3 + 1)),
             case(lo_7=[1.0] * n7, hi_7=[0.0] * n7), case(lo_3=np.nan, q_7=[np.nan] * n7),
             case(findex_6=[5] * len(qs[6])), case(findex_6=[-1.5] * len(qs[6])),
             case(lo_9=np.inf), case(hi_9=-np.inf), case(q_2=["a"] * len(qs[2])),
             dict(M=L[0], q=L[1], lo=L[2], hi=L[3], findex=fl, warm_start=[None] * 19 + [lemke.BoxWarmStart(9, (), ())]),
             dict(M=L[0], q=[[np.nan] * len(qs[0])] + L[1][1:], lo=L[2], hi=L[3], findex=fl,
                  warm_start=[None] * 19 + [lemke.BoxWarmStart(9, (), ())]),
             dict(M=L[0], q=L[1][:-1], lo=L[2], hi=L[3], findex=fl),
             dict(M=L[0], q=L[1], lo=L[2], hi=L[3], findex=fl[:-1]),
             dict(M=Ms, q=qs[:7] + [np.full(len(qs[7]), np.nan)] + qs[8:], lo=los, hi=his, findex=fis)]
    for kw in cases:
        got, want = _errors(monkeypatch, lambda: lemke.solve_blcp_many(**kw, workers=1))
        assert got is not None and ("problem" in got[1] or "warm_start" in got[1] or "M and" in got[1]), got
        assert got == want


def test_bimatrix_forms_bit_for_bit(no_validation):
    A = np.array([[3, 3], [2, 5], [0, 6]])
    B = np.array([[3, 2], [2, 6], [3, 1]])
    fields = None
    for k in (0, 2, 4):
        want = lemke.solve_bimatrix(A.astype(np.float64), B.astype(np.float64), init_label=k)
        for (_, Ax), (_, Bx) in zip(_forms(A.astype(np.float64), True), _forms(B.astype(np.float64), True)):
            got = _untouched([Ax, Bx], lambda: lemke.solve_bimatrix(Ax, Bx, init_label=k))
            _same(got, want, fields)
        _same(lemke.solve_bimatrix(A, B, init_label=k), want, fields)


BAD_GAMES = [
    ([[1.0, np.nan]], [[1.0, 0.0]]),
    ([[1.0, 0.0]], [[1.0, 0.0], [0.0, 1.0]]),
    ([[]], [[]]),
    ([1.0, 0.0], [1.0, 0.0]),
    ([[1.0, 0.0], [1.0]], [[1.0, 0.0], [0.0, 1.0]]),
    ([["1", "0"]], [[1.0, 0.0]]),
    ([[1 + 1j, 0.0]], [[1.0, 0.0]]),
    (np.array([[1.0, np.inf]], dtype=np.float32), [[1.0, 0.0]]),
]


@pytest.mark.parametrize("A, B", BAD_GAMES)
def test_bimatrix_errors_as_before(A, B, monkeypatch):
    got, want = _errors(monkeypatch, lambda: lemke.solve_bimatrix(A, B))
    if got is None:  # (str entries that NumPy reads as numbers: solved both ways)
        assert want is None
    else:
        assert got == want


QP_FIELDS = None


def _qp_data():
    P = np.array([[4.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 3.0]])
    q = np.array([1.0, 1.0, -2.0])
    G = np.array([[1.0, 1.0, 1.0], [-1.0, 0.0, 2.0]])
    h = np.array([1.0, 2.0])
    A = np.array([[1.0, -1.0, 0.0]])
    b = np.array([0.0])
    lb, ub = np.full(3, -2.0), np.full(3, 2.0)
    return P, q, G, h, A, b, lb, ub


def test_qp_forms_bit_for_bit(no_validation):
    data = _qp_data()
    want = lemke.solve_qp(*data)
    assert want.success
    ws = want.warm_start
    forms = [_forms(a, True) for a in data]
    for i in range(len(forms[0])):
        args = tuple(f[i][1] for f in forms)
        got = _untouched(list(args), lambda: lemke.solve_qp(*args))
        _same(got, want, QP_FIELDS)
        _same(lemke.solve_qp(*args, warm_start=ws), lemke.solve_qp(*data, warm_start=ws), QP_FIELDS)
        x0 = [0.1, 0.1, 0.0]
        _same(lemke.solve_qp(*args, initvals=x0), lemke.solve_qp(*data, initvals=np.array(x0)),
              QP_FIELDS)
        # Python-number bounds, spread over the rows (made_bound; with made_f64's forms,
        # which byte-swapped arrays are not: the validation takes those)
        for lo, up in () if forms[0][i][0] == "swapped" else ((-2, 2.0), (-2.0, 2), (-2, np.full(3, 2.0))):
            _same(lemke.solve_qp(*args[:6], lo, up), want, QP_FIELDS)
            _same(lemke.solve_qp(*args[:6], lo, up, warm_start=ws),
                  lemke.solve_qp(*data, warm_start=ws), QP_FIELDS)
    # subsets: no A, b; bounds only; no rows at all
    P, q, G, h, A, b, lb, ub = data
    for kw in ({"G": G, "h": h}, {"lb": lb, "ub": ub}, {}):
        lists = {k: v.tolist() for k, v in kw.items()}
        _same(lemke.solve_qp(P.tolist(), q.tolist(), **lists), lemke.solve_qp(P, q, **kw), QP_FIELDS)
    for lo, up in ((-2, None), (None, 2), (-np.inf, 2.0), (-1e20, 1e20), (-2, np.inf)):
        kw = {k: np.full(3, float(v)) for k, v in (("lb", lo), ("ub", up)) if v is not None}
        _same(lemke.solve_qp(P.tolist(), q, lb=lo, ub=up), lemke.solve_qp(P, q, **kw), QP_FIELDS)
        _same(lemke.solve_qp(P, q, G, h, lb=lo, ub=up), lemke.solve_qp(P, q, G, h, **kw), QP_FIELDS)


GO_ON_QP = [  # the front's kernels do not end solved and checked: the Python steps go on
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], G=[[1.0, 0.0], [-1.0, 0.0]], h=[-1, -1]),
    dict(P=np.zeros((3, 3), np.float32), q=[-1.0, -1.0, 0.0], G=[[1, 1, 0], [1, -1, 1]], h=(1.0, 2.0)),
    dict(P=[[0.0, 0.0], [0.0, 1.0]], q=[-1.0, 0.0], lb=0),
    dict(P=[[0.0, 0.0], [0.0, 1.0]], q=[-1.0, 0.0], lb=[0, 0], ub=1e20),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], A=[[1.0, 1.0], [1.0, 1.0]], b=[1.0, 2.0]),
    dict(P=[[2.0, 1.0], [1.0, 2.0]], q=[-5, -6], G=[[1.0, 1.0]], h=[-10.0], lb=0.0, ub=1),
]


@pytest.mark.parametrize("kw", GO_ON_QP)
def test_qp_converted_go_on_as_before(kw, monkeypatch):
    """A call whose arguments the front converted and whose kernels did not settle it goes on
    from the front's code with the converted arrays (no Python conversion, no second kernel
    call): the answer of the conversion-off path and of the float64 arrays, bit for bit."""
    with monkeypatch.context() as m:
        m.setattr(_validate, "plain_all", lambda *a: pytest.fail("the Python conversion ran"))
        got = lemke.solve_qp(**kw)
    assert _core.qp_front_codes() or "G" not in kw  # (the front ran a kernel)
    n = len(kw["q"])
    f64 = {k: np.full(n, float(v)) if np.ndim(v) == 0 else _f64(v) for k, v in kw.items()}
    _same(got, lemke.solve_qp(**f64), QP_FIELDS)
    with monkeypatch.context() as m:
        _old(m)
        _same(got, lemke.solve_qp(**kw), QP_FIELDS)


def test_qp_front_conversion_is_numpys():
    """qp_front's own conversion (pack_form / pack_into into its scratch vector; the arguments
    as converted come back with the kernels' code when they do not settle the call, here an
    infeasible QP) holds NumPy's values, np.asarray(x).astype(float64), for every dtype and
    stride it takes, lists of ints beyond 2**53 and Python-number bounds included."""
    rng = np.random.default_rng(8)
    base = rng.integers(-2 ** 62, 2 ** 62, (3, 6))
    unaligned = np.frombuffer(b"\0" + rng.standard_normal(9).tobytes(), dtype=np.float64,
                              offset=1).reshape(3, 3)
    odd_bool = np.array([[0, 1, 2], [255, 0, 7], [1, 1, 0]], dtype=np.uint8).view(np.bool_)
    mats = [base[:, :3], base[:, :3].astype(np.int32), base[:, :3].astype(np.int16),
            base[:, :3].astype(np.int8), np.abs(base[:, :3]).astype(np.uint8),
            np.abs(base[:, :3]).astype(np.uint16), np.abs(base[:, :3]).astype(np.uint32), odd_bool,
            np.array([[1e-45, -0.0, 3.4e38], [1.0, 2.0, 3.0], [0.5, -1.0, 7.0]], np.float32),
            np.asfortranarray(rng.standard_normal((3, 3))), rng.standard_normal((6, 9))[::2, 1::3],
            rng.standard_normal((3, 6))[::-1, ::-2], unaligned, np.asfortranarray(base[:, :3]),
            [[2 ** 62 + 1, -3, 0], [2 ** 63 - 1, 1, True], [0.1, -2 ** 63, 5]]]
    G, h = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]), np.array([-1.0, -1.0])  # x0 <= -1, >= 1
    P, q = np.eye(3), np.ones(3)
    for x in mats:
        vec = x[1] if isinstance(x, list) else x[:, 1]
        for args in ([x, q, G, h, None, None, None, None], [P, vec, G, h, None, None, vec, None],
                     [P, q, G, h, x, vec, -1e19, 2 ** 62 + 1], [P, q, G, h, x[:1], vec[:1], None, 3]):
            r = _core.qp_front(*args, 0, None, None)
            assert type(r) is tuple and r[0] != _core.QP_OK
            if all(a is None or (type(a) is np.ndarray and a.dtype == np.float64 and a.dtype.isnative
                                 and a.flags.c_contiguous and a.flags.aligned) for a in args):
                # (a Fortran matrix's column is plain: nothing to convert)
                assert len(r) == 4
                continue
            assert len(r) == 5
            for given, got in zip(args, r[4]):
                if given is None:
                    assert got is None
                    continue
                want = (np.full(3, float(given)) if np.ndim(given) == 0
                        else np.ascontiguousarray(np.asarray(given).astype(np.float64)))
                assert got.dtype == np.float64 and got.flags.c_contiguous and got.flags.writeable
                assert got.shape == want.shape and got.tobytes() == want.tobytes(), type(given)


BAD_QP = [
    dict(P=[[1.0, np.nan], [0.0, 1.0]], q=[1.0, 1.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0, 1.0]),
    dict(P=[[1.0, 2.0], [0.0, 1.0]], q=[1.0, 1.0]),
    dict(P=[[1.0, 0.0], [0.0, -1.0]], q=[1.0, 1.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], G=[[1.0, 1.0]], h=[np.nan]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], G=[[1.0, 1.0]], h=[1.0, 2.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], G=[[1.0, 1.0]]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=[2.0, 0.0], ub=[1.0, 1.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=[np.inf, 0.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], initvals=[np.nan, 0.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], initvals=[0.0, 0.0, 0.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], A=[[1.0, 1.0]], b=[1.0], G=[[1.0, 1.0]], h=[0.0],
         lb=[1.0, 1.0]),
    # Python-number bounds: NaN, the wrong side's infinity or 1e20, other types, lb > ub
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=np.nan),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], ub=np.nan),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=np.inf),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], ub=-np.inf),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=1e20),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], ub=-1e20),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=1e300, ub=[1e300, 1e300]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=2 ** 70),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=-2 ** 70, ub=True),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb="0"),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=1.0, ub=0),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=[0.0, 1.0], ub=0.5),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=0.0, ub=[0.5, -1.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], lb=0.0, ub=[0.5, 1.0, 2.0]),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0], lb=0.0),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], G=[1.0, 1.0], h=1.0, lb=0),
    dict(P=[[1.0, 0.0], [0.0, 1.0]], q=[1.0, 1.0], G=[[1.0, 1.0]], h=[1.0], initvals=(0, 2 ** 70)),
]


@pytest.mark.parametrize("kw", BAD_QP)
def test_qp_errors_as_before(kw, monkeypatch):
    got, want = _errors(monkeypatch, lambda: lemke.solve_qp(**kw))
    assert got == want
    if got is None:  # solved or refused by status both ways: the same answer
        with monkeypatch.context() as m:
            _old(m)
            old = lemke.solve_qp(**kw)
        new = lemke.solve_qp(**kw)
        assert new.status == old.status


def test_conversion_is_the_validations():
    """_validate.plain makes what float64_array + the kinds' checks make, or declines."""
    for x in ([[1, 2], [3, 4]], [[True, False], [False, True]], np.arange(4.0).reshape(2, 2).T,
              np.arange(4, dtype=np.float32).reshape(2, 2), [[2 ** 62 + 1, 0], [0, 1]]):
        a = _validate.plain(x, 2)
        want = _validate.square_matrix(x)
        assert a.dtype == np.float64 and a.flags.c_contiguous and a.tobytes() == want.tobytes()
    a = np.eye(2)
    assert _validate.plain(a, 2) is a
    for x in ([[1, 2], [3]], [["1", "2"]], [[1j, 0]], [[None, 1.0]], sp.eye(2), np.ma.array(np.eye(2)),
              [1.0, 2.0], 1.0, [[2 ** 64, 0]], np.zeros((2, 2), dtype=object)):
        assert _validate.plain(x, 2) is None, x


def test_native_list_conversion_is_numpys():
    """The entries' own conversion of lists (src/python_front.cpp, made_f64) holds the
    values np.asarray(x).astype(float64) holds, or declines (None)."""
    from lemke import _core
    big = 2 ** 63 - 1
    for x, nd in (([[2 ** 62 + 1, -3], [big, -2 ** 63]], 2), ([[1, 2.5], [True, False]], 2),
                  ([True, False, True], 1), ([np.float64(0.1), -0.0, 1e308, 5e-324], 1),
                  (((1, 2), [3, 4]), 2), ([2 ** 53 + 1, 0.5], 1), ([np.nan, np.inf, -np.inf], 1),
                  ([[1.0, 2.0, 3.0]], 2), ([7], 1),
                  ([0, -1, 1, 2 ** 30 - 1, 1 - 2 ** 30, 2 ** 30, -2 ** 30, 2 ** 31, -2 ** 60 - 1, -0], 1),
                  ([[-7, 0], [300, -300]], 2), ([[0]], 2)):
        a = _core.as_f64(x, nd)
        want = np.asarray(x).astype(np.float64)
        assert a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable
        assert a.shape == want.shape and a.tobytes() == want.tobytes(), x
    for x, nd in (([2 ** 63], 1), ([np.float32(1.0)], 1), ([np.int64(1)], 1), (["1"], 1),
                  ([None], 1), ([[1.0], [1.0, 2.0]], 2), ([], 1), ([[]], 2), ([[1.0]], 1),
                  ([1.0], 2), ([1 + 0j], 1), (np.zeros(2), 1)):
        assert _core.as_f64(x, nd) is None, x


def test_native_array_cast_is_numpys():
    """made_f64's cast of ndarrays that are not plain float64 is NumPy's astype (every
    dtype it takes, any strides), and it declines the others (None: NumPy converts them)."""
    from lemke import _core
    rng = np.random.default_rng(5)
    base = rng.integers(-2 ** 62, 2 ** 62, (4, 6))
    unaligned = np.frombuffer(b"\0" + rng.standard_normal(6).tobytes(), dtype=np.float64,
                              offset=1).reshape(2, 3)
    odd_bool = np.array([[0, 1], [2, 255]], dtype=np.uint8).view(np.bool_)
    arrays = [base, base.astype(np.int32), base.astype(np.int16), base.astype(np.int8),
              np.abs(base).astype(np.uint8), np.abs(base).astype(np.uint16),
              np.abs(base).astype(np.uint32), base > 0, odd_bool,
              rng.standard_normal((4, 6)).astype(np.float32), np.array([[1e-45, -0.0, np.nan]], np.float32),
              np.asfortranarray(rng.standard_normal((4, 6))), rng.standard_normal((6, 8))[::2, 1::3],
              rng.standard_normal((4, 6))[::-1, ::-2], unaligned, np.asfortranarray(base)]
    assert not unaligned.flags.aligned
    for a in arrays:
        for x, nd in ((a, 2), (a[0], 1), (a[:, 0], 1)):
            got = _core.as_f64(x, nd)
            if x.dtype == np.float64 and x.flags.c_contiguous and x.flags.aligned:
                assert got is None  # (plain already: nothing to convert)
                continue
            want = np.ascontiguousarray(x.astype(np.float64))
            assert got is not None and got.dtype == np.float64 and got.flags.c_contiguous, (x.dtype, x.strides)
            assert got.shape == want.shape and got.tobytes() == want.tobytes(), (x.dtype, x.strides)
    for x, nd in ((np.ones((2, 2), np.uint64), 2), (np.ones((2, 2), np.float16), 2),
                  (np.ones((2, 2), np.longdouble), 2), (np.ones((2, 2), np.complex128), 2),
                  (np.ones((2, 2), ">f8"), 2), (np.ones((2, 2), ">i4"), 2), (np.ones((2, 2), object), 2),
                  (np.zeros((0, 2)), 2), (np.zeros(0, np.float32), 1), (np.ones((2, 2)), 1),
                  (np.ones(3, np.float32), 2), (np.ma.array(np.ones(2, np.float32)), 1),
                  (np.eye(2), 2), (np.array(1.0, np.float32), 1)):
        assert _core.as_f64(x, nd) is None, (x.dtype, nd)
