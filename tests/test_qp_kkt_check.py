"""The fused path's KKT check (``qp::kkt_check``, ``_core.qp_kkt_check``) and its rounding
floor: an answer computed in floating point passes, a wrong one is refused.

The rule (as ``qp::kkt_check`` applies it): with t = tol + 4 eps and
f = 4 (n + 2) eps, stationarity row j may be off by t s_j (its terms' sizes) plus
f (|P_.j|_1 max|x| + |A_.j|_1 max|y| + |G_.j|_1 max|z| + max|zb|).  Without the last part
the MPC benchmark's terminal velocities (exactly 0 at the optimum, computed as 1e-15) failed
on a third of the steps.  The floor is recomputed here in numpy, independently, and the
answers are checked by tests/helpers.assert_qp_kkt.
"""
import os
import sys
from types import SimpleNamespace

import numpy as np
import pytest

import frozen
import lemke
from lemke import Status, _core
from helpers import assert_qp_kkt

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import mpc_problem  # noqa: E402

EPS = np.finfo(float).eps
STRICT = 1e-12  # qp::STRICT_TOL, the fused path's tolerance


@pytest.fixture(scope="module")
def mpc():
    return mpc_problem.sequence(steps=100, seed=0)  # the benchmark's sequence


def fused(P, q, G, h, A, b, lb, ub):
    """The fused kernel's code and (x, y, z, zb)."""
    n, p, m = P.shape[0], A.shape[0], G.shape[0]
    out = np.empty(4 * n + p + 2 * m + 4)
    code, _, _, _ = _core.qp_solve(P, q, G, h, A, b, lb, ub, 0, -1, 1e-11, 1e-11, 1e-9, out)
    return code, [out[:n].copy(), out[n:n + p].copy(), out[n + p:n + p + m].copy(),
                  out[n + p + m:2 * n + p + m].copy()]


def kkt(data, pt, tol=STRICT):
    return bool(_core.qp_kkt_check(*data, *pt, tol, np.empty(4)))


def stationarity(data, pt):
    """(residual, allowance) of every stationarity row, in numpy: the rule above."""
    P, q, G, h, A, b, lb, ub = data
    x, y, z, zb = pt
    n = q.size
    t = STRICT + 4 * EPS
    f = 4 * (n + 2) * EPS
    res = P @ x + q + A.T @ y + G.T @ z + zb
    size = (np.abs(q) + np.abs(P) @ np.abs(x) + np.abs(A.T) @ np.abs(y) + np.abs(G.T) @ np.abs(z)
            + np.abs(zb))
    top = lambda v: np.abs(v).max(initial=0.0)  # noqa: E731
    floor = f * (np.abs(P).sum(0) * top(x) + np.abs(A).sum(0) * top(y) + np.abs(G).sum(0) * top(z)
                 + top(zb))
    return res, t * size, floor


def test_every_mpc_step_stays_on_the_fused_path(mpc):
    """Cold and warm, every step of the benchmark's loop ends solved and checked in the fused
    kernel (no KKT-MLCP fallback), and its answer passes the independent check."""
    (P, G, h, A, lb, ub), steps = mpc
    keep = np.isfinite(h)
    tight = 0
    ws = None
    for q, b in steps:
        data = (P, q, G, h, A, b, lb, ub)
        code, pt = fused(*data)
        assert code == 0
        res, own, floor = stationarity(data, pt)
        assert np.all(np.abs(res) <= own + floor)
        tight += np.any(np.abs(res) > own)  # a row that only the floor lets through
        r = lemke.solve_qp(*data, warm_start=ws)
        assert r.status == Status.SOLVED
        assert np.all(r.z[~keep] == 0.0)
        assert_qp_kkt(P, q, G[keep], h[keep], A, b, lb, ub,
                      SimpleNamespace(x=r.x, y=r.y, z=r.z[keep], z_box=r.z_box, obj=r.obj))
        np.testing.assert_allclose(r.x, pt[0], rtol=0, atol=1e-8)
        ws = r.warm_start
    assert tight > 10  # the steps that used to fall back (about a third)


def _floor_step(mpc):
    """A step whose answer passes only by the floor, with that row."""
    (P, G, h, A, lb, ub), steps = mpc
    for q, b in steps:
        data = (P, q, G, h, A, b, lb, ub)
        code, pt = fused(*data)
        res, own, floor = stationarity(data, pt)
        rows = np.flatnonzero(np.abs(res) > own)
        if code == 0 and rows.size:
            return data, pt, int(rows[0])
    raise AssertionError("no step needs the floor")


def test_the_floor_is_the_stated_one(mpc):
    """Moving q_j (the residual of row j alone) by the floor's margin: a little inside it
    passes, 2x outside it is refused."""
    data, pt, j = _floor_step(mpc)
    assert kkt(data, pt)
    res, own, floor = stationarity(data, pt)
    allow = own[j] + floor[j]
    for shift, ok in ((0.5 * allow, True), (2.0 * allow, False)):
        q = data[1].copy()
        q[j] -= res[j]  # the row's residual to about 0 (q_j is 0 here: a velocity)
        q[j] += shift
        moved = (data[0], q) + data[2:]
        assert kkt(moved, pt) is ok, (shift, allow)


def test_wrong_points_are_refused(mpc):
    """Perturbed points (one entry off by 1e-9 of its vector's size, x off by 1e-10
    relative), another step's point, multipliers with the wrong sign, a non-zero multiplier
    on a row with h = +inf: all refused at the fused path's tolerance (the gross errors at
    the default 1e-9 too), with the verdicts and statistics the frozen references record (tests/frozen.py),
    bit for bit."""
    data, pt, j = _floor_step(mpc)
    P, q, G, h, A, b, lb, ub = data
    x, y, z, zb = pt
    rng = np.random.default_rng(5)
    wrong = []
    for k, v in enumerate(pt):  # one entry off by 1e-9 of its vector's size
        if v.size:
            i = int(np.argmax(np.abs(v))) if k else j
            bad = [w.copy() for w in pt]
            bad[k][i] += 1e-9 * max(np.abs(v).max(), 1.0)
            wrong.append(bad)
    wrong.append([x * (1 + 1e-10 * rng.standard_normal(x.size)), y, z, zb])
    small = len(wrong)  # the errors above are small: refused at 1e-12, not always at 1e-9
    _, other = fused(P, mpc[1][60][0], G, h, A, mpc[1][60][1], lb, ub)  # another step's answer
    wrong.append(other)
    active = np.flatnonzero(np.isfinite(h) & (z > 0))
    bounds = np.flatnonzero(zb != 0)
    assert bounds.size
    for i in active[:1]:
        bad = [w.copy() for w in pt]
        bad[2][i] = -bad[2][i]
        wrong.append(bad)
    bad = [w.copy() for w in pt]
    bad[3][bounds[0]] = -bad[3][bounds[0]]
    wrong.append(bad)
    inactive = np.flatnonzero(np.isfinite(h) & (z == 0))
    bad = [w.copy() for w in pt]
    bad[2][inactive[0]] = -1e-300  # a negative multiplier, however small
    wrong.append(bad)
    off = np.flatnonzero(~np.isfinite(h))
    for val in (1e-3, -1e-3):
        bad = [w.copy() for w in pt]
        bad[2][off[0]] = val  # no constraint there: z must be 0
        wrong.append(bad)
    cases = [(data, bad) for bad in wrong]
    # stationarity made to hold with a multiplier on a row that is no constraint (q moved by
    # -z_i G_i): x is optimal only for the QP that has that row, not for this one
    bad = [w.copy() for w in pt]
    bad[2][off[0]] = 1e-3
    cases.append(((P, q - 1e-3 * G[off[0]]) + data[2:], bad))
    for k, (d, bad) in enumerate(cases):
        for tol in (STRICT, 1e-9):
            def run(fn):
                st = np.empty(4)
                return bool(fn(*d, *bad, tol, st)), st

            k2, _ = frozen.check(run(_core.qp_kkt_check), (k, tol))
            assert not k2 or (tol > STRICT and k < small), (tol, k)
    # and a z of a row with h = +inf that counts as zero (removing it moves no row by more
    # than its allowance) is no error
    bad = [w.copy() for w in pt]
    bad[2][off[0]] = 1e-30
    assert kkt(data, bad)


def test_floor_scales_with_the_data(mpc):
    """The QP scaled (P, q by 1e6; G, h by 1e-3; A, b by 1e4): the same point, its
    multipliers scaled, passes; so the floor does not depend on the units."""
    data, pt, _ = _floor_step(mpc)
    P, q, G, h, A, b, lb, ub = data
    x, y, z, zb = pt
    scaled = (P * 1e6, q * 1e6, G * 1e-3, h * 1e-3, A * 1e4, b * 1e4, lb, ub)
    spt = [x, y * 1e2, z * 1e9, zb * 1e6]  # exact powers of 2 would keep bits; these round
    assert kkt(data, pt) and kkt(scaled, spt)
    code, own = fused(*scaled)
    assert code == 0 and kkt(scaled, own)
