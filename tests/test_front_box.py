"""solve_blcp's native front (``_core.blcp_front``, src/python_front_box.cpp): on plain
float64 arrays with the default options it gives, cold, with a friction index and/or a
warm start, exactly what the Python path gives (every field bit for bit, the same fields
built lazily, the same warm starts for the next step, the same errors), declines every
other input (None: the Python path does everything) and never writes to the caller's
arrays."""
import numpy as np
import pytest
from test_blcp import contacts, family, pile_steps

import lemke
from lemke import BoxWarmStart, _blcp, _core

FIELDS = ("z", "w", "status", "pivots", "residual", "ray", "z0", "covering", "warm_start",
          "lo", "hi", "row_scale", "col_scale", "recoveries")


def _python(*args, **kw):
    """The Python path's answer (the native front made to decline)."""
    saved = _blcp._FRONT
    _blcp._FRONT = lambda *a: None
    try:
        return _outcome(*args, **kw)
    finally:
        _blcp._FRONT = saved


def _outcome(*args, **kw):
    try:
        return lemke.solve_blcp(*args, **kw)
    except Exception as e:  # noqa: BLE001 (compared below)
        return (type(e), str(e))


def _same(a, b):
    """Every field bit for bit, type included; the same fields built before any is read."""
    if isinstance(a, tuple) or isinstance(b, tuple):
        assert a == b
        return
    assert type(a) is type(b)
    assert sorted(a.__dict__) == sorted(b.__dict__)  # the same lazy state
    for name in FIELDS:
        x, y = getattr(a, name), getattr(b, name)
        assert type(x) is type(y), name
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name
            assert x.flags.writeable == y.flags.writeable, name
        elif isinstance(x, float):
            assert x == y or (x != x and y != y), name
        elif isinstance(x, BoxWarmStart):
            assert x == y, name
            assert x.row_states().tobytes() == y.row_states().tobytes(), name
        else:
            assert x == y, name


def _both(*args, **kw):
    """The native front's answer and the Python path's, compared; the caller's arrays
    untouched."""
    copies = [a.copy() if isinstance(a, np.ndarray) else a for a in args]
    fi = kw.get("findex")
    fcopy = fi.copy() if isinstance(fi, np.ndarray) else None
    got = _outcome(*args, **kw)
    for a, c in zip(args, copies):
        if isinstance(a, np.ndarray):
            assert a.tobytes() == c.tobytes()
    if fcopy is not None:
        assert fi.tobytes() == fcopy.tobytes()
    want = _python(*args, **kw)
    _same(got, want)
    return got


def test_front_is_on():
    assert _core.blcp_front_on()


def test_family_cold_and_warm():
    kinds = set()
    for seed in range(240):
        M, q, lo, hi = family(seed)
        r = _both(M, q, lo, hi)
        if isinstance(r, tuple):
            continue
        kinds.add((r.status.name, r.recoveries > 0))
        ws = r.warm_start
        _both(M, q, lo, hi, warm_start=ws)  # its own basis: 0 pivots
        _both(M, q + 1e-9, lo, hi, warm_start=ws)
        _both(M, q + 0.5 * np.sin(np.arange(q.size) + seed), lo, hi, warm_start=ws)
        # another problem's basis of the same size, and one of another size (an error)
        M2, q2, lo2, hi2 = family(seed + 1000)
        if q2.size == q.size:
            _both(M2, q2, lo2, hi2, warm_start=ws)
        _both(M, q, lo, hi, warm_start=BoxWarmStart(q.size + 1, (), ()))
        # a friction index of ordinary rows only
        _both(M, q, lo, hi, findex=-np.ones(q.size, dtype=np.int64))
    assert ("SOLVED", False) in kinds


def test_contacts_with_friction_index():
    for seed in range(40):
        for k in (1, 2, 3, 5, 8):
            M, q, lo, hi, findex, mu = contacts(seed, k)
            findex = findex.astype(np.int64)
            r = _both(M, q, lo, hi, findex=findex)
            if isinstance(r, tuple) or r.warm_start is None:
                continue
            ws = r.warm_start
            _both(M, q, lo, hi, findex=findex, warm_start=ws)
            _both(M, q + 1e-9, lo, hi, findex=findex, warm_start=ws)
            _both(M, q - 0.3, lo, hi, findex=findex, warm_start=ws)
            # the same basis without the friction index, or with other friction rows
            _both(M, q, lo, hi, warm_start=ws)
            other = findex.copy()
            other[1], other[0] = -1, 1
            _both(M, q, lo, hi, findex=other, warm_start=ws)


def test_pile_steps_warm_chain():
    """A pile's steps, each warm-started from the previous answer (relabelled by size
    where the contact set changes), native and Python chains side by side."""
    ws = None
    for A, b, lo, hi, findex in pile_steps():
        findex = None if findex is None or findex.ndim == 0 else findex.astype(np.int64)
        if ws is not None and ws.rows != b.size:
            ws = None
        r = _both(A, b, lo, hi, findex=findex, warm_start=ws)
        _both(A, b, lo, hi, findex=findex)
        ws = None if isinstance(r, tuple) else r.warm_start


def test_rays_and_undecided_go_on_in_python():
    """A cold run that does not end solved (the tuple for _finish) and a one-call run left
    to the general path (False) give the Python path's answers."""
    M, q, lo, hi = np.array([[-1.0]]), np.array([-1.0]), np.array([0.0]), np.array([np.inf])
    assert type(_core.blcp_front(M, q, lo, hi, None, None)) is tuple
    _both(M, q, lo, hi)
    M = np.array([[-1.0, -2.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]])
    q, lo, hi = np.array([-1.0, 2.0, -3.0]), np.zeros(3), np.full(3, np.inf)
    _both(M, q, lo, hi)
    fi = np.full(3, -1, dtype=np.int64)
    assert _core.blcp_front(M, q, lo, hi, fi, None) is False
    _both(M, q, lo, hi, findex=fi)
    _both(M, q, lo, hi, warm_start=BoxWarmStart(3, (0,), ()))


@pytest.mark.parametrize("args, match", [
    (([[1.0]], [np.nan], [0.0], [1.0]), r"q has a NaN"),
    (([[np.inf]], [0.0], [0.0], [1.0]), r"M has"),
    (([[1.0]], [0.0], [np.nan], [0.0]), r"lo has a NaN"),
    (([[1.0]], [0.0], [1.0], [0.0]), r"lo"),
    (([[1.0]], [0.0], [np.inf], [np.inf]), r"lo has a NaN or \+inf"),
])
def test_bad_input_same_errors(args, match):
    a = [np.array(x, dtype=float) for x in args]
    assert _core.blcp_front(*a, None, None) is None
    for kw in ({}, {"findex": np.array([-1], dtype=np.int64)},
               {"warm_start": BoxWarmStart(1, (), ())}):
        with pytest.raises(ValueError, match=match):
            lemke.solve_blcp(*a, **kw)
        _both(*a, **kw)


def _plain(n=3):
    rng = np.random.default_rng(n)
    A = rng.standard_normal((n, n))
    return A @ A.T + np.eye(n), rng.standard_normal(n), -np.ones(n), np.ones(n)


def test_non_plain_inputs_declined():
    M, q, lo, hi = _plain()
    assert _core.blcp_front(M, q, lo, hi, None, None) is not None
    ro = [a.copy() for a in (M, q, lo, hi)]
    for a in ro:
        a.setflags(write=False)
    assert _core.blcp_front(*ro, None, None) is not None  # read-only: taken (only read)
    bad = {
        "list": q.tolist(), "float32": q.astype(np.float32), "swapped": q.astype(q.dtype.newbyteorder()),
        "strided": np.repeat(q, 2)[::2], "2-D": q[None, :], "short": q[:2],
        "int": np.arange(3), "subclass": np.ma.array(q),
        "scalar": 1.0, "empty": np.zeros(0),
    }
    for name, b in bad.items():
        for pos in range(1, 4):
            args = [M, q, lo, hi]
            args[pos] = b
            assert _core.blcp_front(*args, None, None) is None, (name, pos)
    for name, Mb in {"fortran": np.asfortranarray(M + np.triu(M, 1)), "float32": M.astype(np.float32),
                     "not square": np.zeros((3, 4)), "1-D": M.ravel(), "list": M.tolist()}.items():
        assert _core.blcp_front(Mb, q, lo, hi, None, None) is None, name
    fi = np.full(3, -1, dtype=np.int64)
    assert _core.blcp_front(M, q, lo, hi, fi, None) is not None
    ro_fi = fi.copy()
    ro_fi.setflags(write=False)
    for name, f in {"list": fi.tolist(), "int32": fi.astype(np.int32), "short": fi[:2],
                    "swapped": fi.astype(fi.dtype.newbyteorder()), "read-only": ro_fi,
                    "float": fi.astype(float), "2-D": fi[None, :]}.items():
        assert _core.blcp_front(M, q, lo, hi, f, None) is None, name
    ws = BoxWarmStart(3, (0,), (1,))
    assert _core.blcp_front(M, q, lo, hi, None, ws) is not None
    for name, w in {"size": BoxWarmStart(4, (), ()), "friction": BoxWarmStart(5, (), (), (0,)),
                    "type": lemke.WarmStart(3, ()), "tuple": (3, (), ())}.items():
        assert _core.blcp_front(M, q, lo, hi, None, w) is None, name
    # the cold fast path's sizes only (0 < n < 257); warm or with findex any n > 0
    for n in (0, 257):
        Mn, qn, lon, hin = (np.eye(n), np.zeros(n), -np.ones(n), np.ones(n))
        assert _core.blcp_front(Mn, qn, lon, hin, None, None) is None
    Mn, qn, lon, hin = (np.eye(257), -np.ones(257), -np.ones(257), np.ones(257))
    _both(Mn, qn, lon, hin)
    _both(Mn, qn, lon, hin, findex=np.full(257, -1, dtype=np.int64))


def test_declined_inputs_solve_as_before():
    M, q, lo, hi = _plain(4)
    for args in ([M.tolist(), q, lo, hi], [M, q.astype(np.float32), lo, hi],
                 [np.asfortranarray(M), q, lo, hi], [M, q, -1.0, 1.0]):
        _both(*args)
    r = lemke.solve_blcp(M, q, lo, hi, options={"max_pivots": 1000})
    _same(r, lemke.solve_blcp(M, q, lo, hi))


def test_results_are_read_only_and_alias_nothing():
    M, q, lo, hi = _plain(5)
    r = lemke.solve_blcp(M, q, lo, hi)
    assert r.lo is lo and r.hi is hi
    for name in ("z", "w", "covering", "row_scale", "col_scale"):
        a = getattr(r, name)
        assert not a.flags.writeable
        for x in (M, q, lo, hi):
            assert not np.shares_memory(a, x)
    r2 = lemke.solve_blcp(M, q, lo, hi, warm_start=r.warm_start)
    assert r2.pivots == 0 and r2.warm_start is r.warm_start


def test_carried_and_rebuilt_warm_starts():
    """Warm starts made by take, relabel, from_row_states and pickling (their row states
    computed, not the kernel's final basis) give the Python path's answers too."""
    import pickle
    for seed in range(12):
        M, q, lo, hi, findex, mu = contacts(seed, 4)
        findex = findex.astype(np.int64)
        r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
        ws = r.warm_start
        same = list(range(q.size))
        for w in (ws.take(same, findex), ws.relabel(same, same, findex),
                  BoxWarmStart.from_row_states(ws.row_states()), pickle.loads(pickle.dumps(ws))):
            assert w == ws
            _both(M, q + 1e-3, lo, hi, findex=findex, warm_start=w)
        # two contacts dropped, one new: the carried basis of the smaller problem
        keep = np.r_[0:4, 6:8]
        idx = np.r_[keep, -1, -1]
        M2 = M[np.ix_(keep, keep)]
        M2 = np.block([[M2, np.zeros((6, 2))], [np.zeros((2, 6)), np.eye(2)]])
        q2, lo2, hi2 = np.r_[q[keep], -1.0, 0.5], np.r_[lo[keep], 0.0, -0.3], np.r_[hi[keep], np.inf, 0.3]
        f2 = np.r_[findex[keep], -1, 6].astype(np.int64)
        f2[f2 == 6] = 6
        f2[5] = 4
        w2 = ws.take(idx, f2)
        _both(M2, q2, lo2, hi2, findex=f2, warm_start=w2)
        _both(M2, q2, lo2, hi2, findex=f2)
