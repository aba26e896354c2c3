"""solve_qp's native warm front (src/python_front_qp.cpp, ``_core.qp_front``): the warm call
(a WarmStart, or qpsolvers' initvals) on plain data in one native call.  Its answers are
the Python path's bit for bit (the front switched off by monkeypatching ``_qp._QP_FRONT``),
KKT-checked independently (tests/helpers.assert_qp_kkt); what it declines takes the Python
path unchanged.  No timings here (benchmarks/bench_mpc.py)."""
import os
import pickle
import sys

import numpy as np
import pytest

import lemke
from lemke import Status, WarmStart, _core, _qp
from lemke.problems import random_convex_qp

from test_qp_warm import _bits, check

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import mpc_problem  # noqa: E402

STAGE = mpc_problem.NU + mpc_problem.NX


@pytest.fixture
def no_front(monkeypatch):
    """A context in which solve_qp runs without the native front (its Python path)."""
    def off():
        monkeypatch.setattr(_qp, "_QP_FRONT", lambda *a: None)

    def on():
        monkeypatch.setattr(_qp, "_QP_FRONT", _core.qp_front)
    return off, on


def _both(no_front, *args, **kw):
    off, on = no_front
    on()
    a = lemke.solve_qp(*args, **kw)
    off()
    b = lemke.solve_qp(*args, **kw)
    on()
    return a, b


def test_front_is_on():
    assert _core.qp_front_on()


def test_mpc_warm_and_initvals_bit_for_bit(no_front):
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=40, seed=2)
    ws = ws_off = x_prev = None
    used = 0
    for q, b in steps:
        if ws is not None:
            used += type(_core.qp_front(P, q, G, h, A, b, lb, ub, ws.n, ws._beta, None)) is _qp.QPResult
        fr, py = _both(no_front, P, q, G, h, A, b, lb, ub, warm_start=ws)
        # the Python path from its own previous warm start (no _beta kept: built here)
        off, on = no_front
        off()
        py2 = lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=ws_off)
        on()
        check(P, q, G, h, A, b, lb, ub, fr)
        assert _bits(fr) == _bits(py) == _bits(py2)
        assert fr == py
        guess = None if x_prev is None else np.concatenate([x_prev[STAGE:], x_prev[-STAGE:]])
        fi, pi = _both(no_front, P, q, G, h, A, b, lb, ub, initvals=guess)
        check(P, q, G, h, A, b, lb, ub, fi)
        assert _bits(fi) == _bits(pi)
        ws = fr.warm_start
        ws_off = WarmStart(py2.warm_start.n, py2.warm_start.z_basic)
        assert ws._beta.tolist() == list(ws.z_basic)
        x_prev = fi.x
    assert used == len(steps) - 1


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("parts", ["all", "noG", "noA", "nolb", "noub", "nobounds"])
def test_structures_bit_for_bit(no_front, seed, parts):
    rng = np.random.default_rng(300 + seed)
    P, q, G, h, A, b, lb, ub = random_convex_qp(15, rng, 10, 3)
    h[::4] = np.inf
    if parts == "noG":
        G = h = None
    if parts == "noA":
        A = b = None
    if parts in ("nolb", "nobounds"):
        lb = None
    if parts in ("noub", "nobounds"):
        ub = None
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    assert cold.status == Status.SOLVED
    for k in range(3):
        q2 = q + 0.3 * k * rng.standard_normal(q.size)
        for kw in (dict(warm_start=cold.warm_start), dict(warm_start=WarmStart(cold.warm_start.n, cold.warm_start.z_basic)),
                   dict(initvals=cold.x + 0.1 * k * rng.standard_normal(q.size))):
            fr, py = _both(no_front, P, q2, G, h, A, b, lb, ub, **kw)
            assert _bits(fr) == _bits(py), (parts, k, kw.keys())
            assert fr.status == Status.SOLVED
            Gc = np.zeros((0, q.size)) if G is None else G
            hc = np.zeros(0) if h is None else h
            Ac = np.zeros((0, q.size)) if A is None else A
            bc = np.zeros(0) if b is None else b
            lbc = np.full(q.size, -np.inf) if lb is None else lb
            ubc = np.full(q.size, np.inf) if ub is None else ub
            check(P, q2, Gc, hc, Ac, bc, lbc, ubc, fr)


def test_declined_inputs_take_the_python_path(no_front):
    rng = np.random.default_rng(5)
    P, q, G, h, A, b, lb, ub = random_convex_qp(12, rng, 8, 2)
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    ws = cold.warm_start
    # not plain but made_f64's forms (lists, float32, a Fortran-ordered array, an initvals
    # list): the front converts them, the plain data's answer bit for bit
    Gt = np.asfortranarray(G)
    warm = _core.qp_front(P, q, G, h, A, b, lb, ub, ws.n, ws._beta, None)
    guess = _core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, cold.x)
    for r, want in ((_core.qp_front(P.tolist(), q, G, h, A, b, lb, ub, ws.n, ws._beta, None), warm),
                    (_core.qp_front(P, q.astype(np.float32), G, h, A, b, lb, ub, ws.n, ws._beta, None),
                     lemke.solve_qp(P, q.astype(np.float32).astype(float), G, h, A, b, lb, ub, warm_start=ws)),
                    (_core.qp_front(P, q, Gt, h, A, b, lb, ub, ws.n, ws._beta, None), warm),
                    (_core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, cold.x.tolist()), guess)):
        assert type(r) is lemke.QPResult and _bits(r) == _bits(want)
    # other kinds (byte-swapped, complex, a 1-D G, a scalar h, a bool bound): None
    for args in ((P, q.astype(">f8"), G, h, A, b, lb, ub), (P, q.astype(complex), G, h, A, b, lb, ub),
                 (P, q, G[0], h[:1], A, b, lb, ub), (P, q, G[:1], 1.0, A, b, lb, ub),
                 (P, q, G, h, A, b, True, ub)):
        assert _core.qp_front(*args, ws.n, ws._beta, None) is None
    bad = cold.x.copy()
    bad[3] = np.nan
    assert _core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, bad) is None
    assert _core.qp_front(P, q, G, None, A, b, lb, ub, ws.n, ws._beta, None) is None
    assert _core.qp_front(P, q, G[:, :-1], h, A, b, lb, ub, ws.n, ws._beta, None) is None
    for args, kw in (((P.tolist(), q, G, h, A, b, lb, ub), dict(warm_start=ws)),
                     ((P, q, Gt, h, A, b, lb, ub), dict(warm_start=ws)),
                     ((P, q, G, h, A, b, lb, ub), dict(initvals=cold.x.tolist()))):
        fr, py = _both(no_front, *args, **kw)
        assert _bits(fr) == _bits(py)
    with pytest.raises(ValueError, match="initvals has a non-finite entry at index 3"):
        lemke.solve_qp(P, q, G, h, A, b, lb, ub, initvals=bad)
    with pytest.raises(ValueError, match="warm_start has 3 pairs"):
        lemke.solve_qp(P, q, G, h, A, b, lb, ub, warm_start=WarmStart(3, (0,)))
    with pytest.raises(ValueError):
        lemke.solve_qp(P, q, G[:, :-1], h, A, b, lb, ub, warm_start=ws)


def test_kernel_declines_then_the_mlcp_path(no_front):
    """A P that is only semidefinite: the kernel's code is not OK, the front hands it back,
    and the KKT-MLCP path solves from the same start, as without the front."""
    rng = np.random.default_rng(9)
    P, q, G, h, A, b, lb, ub = random_convex_qp(10, rng, 6, 2)
    P = np.zeros_like(P)  # a linear program
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    assert cold.status == Status.SOLVED
    for kw in (dict(warm_start=cold.warm_start), dict(initvals=cold.x)):
        ws = cold.warm_start
        beta = np.array(ws.z_basic, dtype=np.int64)
        r = (_core.qp_front(P, q, G, h, A, b, lb, ub, ws.n, beta, None) if "warm_start" in kw
             else _core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, cold.x))
        assert type(r) is tuple and r[0] != _core.QP_OK
        fr, py = _both(no_front, P, q, G, h, A, b, lb, ub, **kw)
        assert _bits(fr) == _bits(py)
        assert fr.status == Status.SOLVED


def test_front_results_are_values(no_front):
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=3, seed=0)
    q, b = steps[1]
    cold = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
    fr, py = _both(no_front, P, q, G, h, A, b, lb, ub, warm_start=cold.warm_start)
    assert not fr.x.flags.writeable and not fr.y.flags.writeable
    assert fr == py and hash(fr) == hash(py)
    back = pickle.loads(pickle.dumps(fr))
    assert back == fr and _bits(back) == _bits(fr)
    assert pickle.loads(pickle.dumps(fr.warm_start)).__dict__.get("_beta") is None
    assert repr(fr) == repr(py)


def _cold_cases():
    """Cold QPs of every kind the front's cold lines choose between: mixed rows and bounds,
    no constraints, box-only below and at BOX_FIRST (the box kernel; None), many rows (at
    GRAM_RATIO n: the factored path first), a P semidefinite whose flat directions the
    equalities pin (the semidefinite step after the fused kernel's NOT_DEFINITE), a linear
    program (P = 0: a code handed back), an infeasible QP (the kernel's code, then the
    KKT-MLCP path's certificate)."""
    rng = np.random.default_rng(77)
    P, q, G, h, A, b, lb, ub = random_convex_qp(10, rng, 6, 2)
    yield "mixed", (P, q, G, h, A, b, lb, ub)
    yield "rows only", (P, q, G, h, None, None, None, None)
    yield "equalities only", (P, q, None, None, A, b, None, None)
    yield "unconstrained", (P, q, None, None, None, None, None, None)
    yield "lower bounds", (P, q, G, h, A, b, lb, None)
    yield "box", (P, q, None, None, None, None, lb, ub)
    yield "box upper", (P, q, None, None, None, None, None, ub)
    P2, q2, _, _, _, _, lb2, ub2 = random_convex_qp(_qp.BOX_FIRST, rng, 2, 1)
    yield "box at BOX_FIRST", (P2, q2, None, None, None, None, lb2, ub2)
    P3, q3, G3, h3, A3, b3, lb3, ub3 = random_convex_qp(5, rng, 25, 1)
    yield "many rows", (P3, q3, G3, h3, A3, b3, lb3, ub3)
    Ps = np.zeros_like(P)  # two variables out of P (zero rows and columns), three equalities
    Ps[:8, :8] = P[:8, :8]
    A4 = rng.standard_normal((3, 10))
    yield "semidefinite", (Ps, q, G, h, A4, A4 @ (0.1 * rng.standard_normal(10)), lb, ub)
    yield "semidefinite, many rows", (Ps, q, np.vstack([G] * 7), np.concatenate([h] * 7), A4,
                                      A4 @ np.zeros(10), None, None)
    yield "linear program", (np.zeros_like(P), q, G, h, A, b, lb, ub)
    # one flat direction (a linear variable with a lower bound) among more than SMALL_FLAT
    # variables, more rows of G than bound rows: step 8 relaxed, on solve's screen
    n5 = 40
    Pf = np.diag(rng.uniform(0.5, 2.0, n5))
    Pf[0, 0] = 0.0
    qf = rng.standard_normal(n5)
    qf[0] = abs(qf[0]) + 0.1
    Gf = rng.standard_normal((6, n5))
    lbf = np.full(n5, -np.inf)
    lbf[0] = 0.0
    yield "one flat direction", (Pf, qf, Gf, np.abs(rng.standard_normal(6)), None, None, lbf, None)
    g = rng.standard_normal(10)
    yield "infeasible", (P, q, np.vstack([G, g, -g]), np.concatenate([h, [-1.0, -1.0]]), A, b,
                         lb, ub)


@pytest.mark.parametrize("name, args", list(_cold_cases()))
def test_cold_calls_bit_for_bit(no_front, name, args):
    """The cold call through the front (src/python_front_qp.cpp's cold lines) against the
    Python path (the front off): the same status, bits, certificate and warm start, and a
    solved answer passes the independent KKT check."""
    fr, py = _both(no_front, *args)
    assert fr.status == py.status and _bits(fr) == _bits(py), name
    assert fr.certificate == py.certificate
    if fr.status == Status.SOLVED:
        P, q, G, h, A, b, lb, ub = args
        n = q.size
        check(P, q, np.zeros((0, n)) if G is None else G, np.zeros(0) if h is None else h,
              np.zeros((0, n)) if A is None else A, np.zeros(0) if b is None else b,
              np.full(n, -np.inf) if lb is None else lb, np.full(n, np.inf) if ub is None else ub,
              fr)
    else:
        assert name == "infeasible" and fr.status == Status.PRIMAL_INFEASIBLE
    P, q, G, h, A, b, lb, ub = args
    r = _core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, None)
    if name == "box at BOX_FIRST":
        assert r is None
    elif name in ("linear program", "infeasible"):
        assert type(r) is tuple and r[0] != _core.QP_OK
    else:
        assert type(r) is _qp.QPResult and _bits(r) == _bits(fr)
    # the result a second time from the same buffer and warm start: values, not views of
    # anything the caller holds
    if type(r) is _qp.QPResult:
        assert not r.x.flags.writeable and r == fr and repr(r) == repr(fr)
        warm = lemke.solve_qp(*args, warm_start=r.warm_start)
        assert warm.status == Status.SOLVED and warm.pivots == 0


def test_cold_declined_and_bad_inputs_say_the_same(no_front):
    """Data the cold front converts (lists, float32, a Fortran G: the plain data's answer),
    declines (mismatched shapes) or runs and hands back (a NaN: BAD_INPUT, with the
    arguments as converted when it converted them) takes the Python path, whose errors are
    as before, word for word."""
    rng = np.random.default_rng(6)
    P, q, G, h, A, b, lb, ub = random_convex_qp(8, rng, 5, 2)
    q32 = q.astype(np.float32)
    for args, want in (((P.tolist(), q, G, h, A, b, lb, ub), (P, q, G, h, A, b, lb, ub)),
                       ((P, q32, G, h, A, b, lb, ub), (P, q32.astype(float), G, h, A, b, lb, ub)),
                       ((P, q, np.asfortranarray(G), h, A, b, lb, ub), (P, q, G, h, A, b, lb, ub))):
        r = _core.qp_front(*args, 0, None, None)
        assert type(r) is _qp.QPResult and _bits(r) == _bits(_core.qp_front(*want, 0, None, None))
    assert _core.qp_front(P, q, G[:, :-1], h, A, b, lb, ub, 0, None, None) is None
    assert _core.qp_front(P, q, G, None, A, b, lb, ub, 0, None, None) is None
    for args in ((P.tolist(), q, G, h, A, b, lb, ub), (P, q.astype(np.float32), G, h, A, b, lb, ub)):
        fr, py = _both(no_front, *args)
        assert _bits(fr) == _bits(py)
    Pn = P.copy()
    Pn[1, 2] = np.nan
    assert _core.qp_front(Pn, q, G, h, A, b, lb, ub, 0, None, None)[0] == 5  # qp.hpp BAD_INPUT: the kernel's screen refuses a NaN
    off, on = no_front
    got = _core.qp_front(Pn.tolist(), q, G, h, A, b, lb, ub, 0, None, None)
    assert got[0] == 5 and len(got) == 5 and got[4][0].tobytes() == Pn.tobytes()  # (converted)
    for bad in ((Pn, q, G, h, A, b, lb, ub), (P, q, G[:, :-1], h, A, b, lb, ub),
                (P, q, G, None, A, b, lb, ub), (P[:, :-1], q, G, h, A, b, lb, ub),
                (Pn.tolist(), q, G, h, A, b, lb, ub), (P, q, G.tolist(), h[:-1].tolist(), A, b, lb, ub)):
        msgs = []
        for switch in (on, off):
            switch()
            with pytest.raises((ValueError, TypeError)) as e:
                lemke.solve_qp(*bad)
            msgs.append((type(e.value), str(e.value)))
        on()
        assert msgs[0] == msgs[1]
