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
    # not plain: lists, float32, a non-contiguous view, an initvals list: None from the front
    assert _core.qp_front(P.tolist(), q, G, h, A, b, lb, ub, ws.n, ws._beta, None) is None
    assert _core.qp_front(P, q.astype(np.float32), G, h, A, b, lb, ub, ws.n, ws._beta, None) is None
    Gt = np.asfortranarray(G)
    assert _core.qp_front(P, q, Gt, h, A, b, lb, ub, ws.n, ws._beta, None) is None
    assert _core.qp_front(P, q, G, h, A, b, lb, ub, 0, None, cold.x.tolist()) is None
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
