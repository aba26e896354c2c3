"""The core's three reductions as apply/recover pairs (src/lemke/reductions.hpp), each alone:
applied to random problems through its private _core ends, its reduced problem solved by
lemke's public solvers, the answer mapped back by its recover, and the recovered answer
checked on the caller's problem here, with plain numpy (the box LCP's conditions with the
coupled bounds for the friction index's extension; the QP's KKT conditions, helpers'
assert_qp_kkt, for the box-only QP's box LCP and the fused path's multiplier LCP). Where a
kernel composes the same pair (qp_solve_box), its answer is the pair's bit for bit."""
from types import SimpleNamespace

import numpy as np
import pytest

import lemke
from helpers import assert_qp_kkt
from test_reductions import _random_qp
from lemke import _core

TOL, PIVOT_TOL, TIE_TOL = 1e-9, 1e-11, 1e-11  # Options' defaults


def _box_conditions(M, q, lo, hi, z, rtol=1e-7):
    """Plain numpy: lo <= z <= hi and w = M z + q with w_i >= 0 off hi and w_i <= 0 off lo,
    each row against its own size |M_i.| |z| + |q_i| plus the rounding of q's largest entry
    (z_i at a bound within that size)."""
    w = M @ z + q
    s = np.abs(M) @ np.abs(z) + np.abs(q) + 10 * q.size * np.finfo(float).eps * np.abs(q).max(initial=0) / rtol
    col = np.abs(M).max(axis=0) + 1e-300
    slack = rtol * s.max() / col
    assert np.all(np.isfinite(z))
    assert np.all(z >= lo - slack) and np.all(z <= hi + slack), "z is outside its box"
    off_lo, off_hi = z - lo > slack, hi - z > slack
    assert not np.any(off_lo & (w > rtol * s)), "w > 0 off the lower bound"
    assert not np.any(off_hi & (w < -rtol * s)), "w < 0 off the upper bound"
    return w


# ----------------------------------------------------------------------------- FrictionBox

def _contacts(rng, k):
    """k 2-D contacts (normal and tangent rows, shuffled), M = J J' + eps I, and a free row."""
    nb = max(1, k // 2)
    n = 2 * k + 1
    J = rng.standard_normal((n, 3 * nb))
    M = J @ J.T + 1e-6 * np.eye(n)
    q = rng.standard_normal(n)
    perm = rng.permutation(n)
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    findex = -np.ones(n, dtype=np.int64)
    for c in range(k):
        normal, tangent = perm[2 * c], perm[2 * c + 1]
        mu = rng.uniform(0.0, 1.0)
        lo[normal] = 0.0
        findex[tangent] = normal
        lo[tangent], hi[tangent] = -mu, mu
    return M, q, lo, hi, findex


def _extend(M, q, lo, hi, findex):
    n, nf = q.size, int(np.count_nonzero(findex >= 0))
    N = n + 2 * nf
    F = np.empty(2 * nf, dtype=np.int64)
    Mx, qx, lox, hix = _core.boxed.extend(M, q, lo, hi, findex, nf, np.empty(N * N + 3 * N), F)
    return F, Mx.copy(), qx.copy(), lox.copy(), hix.copy()


@pytest.mark.parametrize("seed", range(30))
def test_friction_box_apply_recover(seed):
    rng = np.random.default_rng(seed)
    k = 1 + seed % 5
    M, q, lo, hi, findex = _contacts(rng, k)
    n = q.size
    F, Mx, qx, lox, hix = _extend(M, q, lo, hi, findex)
    nf = F.size // 2
    fr, normal = F[:nf], F[nf:]
    assert np.array_equal(fr, np.flatnonzero(findex >= 0)) and np.array_equal(normal, findex[fr])
    # apply: the extended rows as the module docstring states them (β+ the caller's variable,
    # β- at n + c, λ at n + nf + c; z_i = β+ - β-)
    assert np.array_equal(Mx[:n, :n], M) and np.array_equal(Mx[:n, n:n + nf], -M[:, fr])
    assert np.array_equal(Mx[n:n + nf, :n], -M[fr]) and np.array_equal(qx[n:n + nf], -q[fr])
    for c in range(nf):
        lam = np.zeros(n + 2 * nf)
        lam[normal[c]], lam[fr[c]], lam[n + c] = hi[fr[c]], -1.0, -1.0
        assert np.array_equal(Mx[n + nf + c], lam) and qx[n + nf + c] == 0.0
    assert np.all(lox[fr] == 0) and np.all(hix[fr] == np.inf) and np.all(lox[n:] == 0)
    # the extended problem solved as a plain box LCP, then recovered
    r = lemke.solve_blcp(Mx, qx, lox, hix)
    assert r.status == lemke.Status.SOLVED
    _box_conditions(Mx, qx, lox, hix, r.z)
    passed, residual, z, w, lo_in, hi_in, R, C = _core.boxed.friction_recover(M, q, lo, hi, F, r.z, TOL)
    # recover is the map z_i = β+ - β- (z then clipped into the coupled bounds by the check)
    z_map = r.z[:n].copy()
    z_map[fr] = r.z[fr] - r.z[n:n + nf]
    assert np.allclose(z, z_map, rtol=0, atol=1e-12 * (1 + np.abs(z_map).max()))
    # the recovered answer on the caller's data, checked here: the normals >= 0, the friction
    # rows in the cone, z a box solution with the coupled bounds -mu z_f, mu z_f
    mu, zf = hi[fr], z[normal]
    assert np.all(zf >= -1e-12)
    assert np.array_equal(lo_in[fr], -mu * zf) and np.array_equal(hi_in[fr], mu * zf)
    lo_c, hi_c = lo.copy(), hi.copy()
    lo_c[fr], hi_c[fr] = -mu * zf, mu * zf
    w_here = _box_conditions(M, q, lo_c, hi_c, z)
    assert np.allclose(w, w_here, rtol=0, atol=1e-9 * (1 + np.abs(w_here).max()))
    assert passed and residual <= 1e-6


def test_friction_box_recover_inverts_the_split():
    """A caller's point, split into β+, β- (and any λ), comes back as itself; a point that
    is not a solution fails the check both here and in the core."""
    rng = np.random.default_rng(7)
    for k in range(1, 6):
        M, q, lo, hi, findex = _contacts(rng, k)
        n = q.size
        F, *_ = _extend(M, q, lo, hi, findex)
        nf = F.size // 2
        fr, normal = F[:nf], F[nf:]
        z = rng.uniform(0.1, 1.0, n)
        z[fr] = rng.uniform(-1, 1, nf) * hi[fr] * z[normal]
        zx = np.concatenate([z, np.zeros(2 * nf)])
        zx[fr], zx[n:n + nf] = np.maximum(z[fr], 0), np.maximum(-z[fr], 0)
        zx[n + nf:] = rng.random(nf)
        passed, _, z_back, w, _, _, _, _ = _core.boxed.friction_recover(M, q, lo, hi, F, zx, TOL)
        assert np.array_equal(z_back, z)
        assert np.array_equal(w, M @ z + q) or np.allclose(w, M @ z + q, rtol=0, atol=1e-12 * np.abs(M).sum())
        with pytest.raises(AssertionError):
            lo_c, hi_c = lo.copy(), hi.copy()
            lo_c[fr], hi_c[fr] = -hi[fr] * z[normal], hi[fr] * z[normal]
            _box_conditions(M, q, lo_c, hi_c, z)
        assert not passed


def test_friction_box_recover_refuses_bad_rows():
    M, q = np.eye(3), np.ones(3)
    lo, hi = np.array([0.0, -1.0, 0.0]), np.array([np.inf, 1.0, np.inf])
    for F in ([1, 1], [3, 0], [1, -1], [0, 0]):
        with pytest.raises(ValueError):
            _core.boxed.friction_recover(M, q, lo, hi, np.array(F, np.int64), np.zeros(5), TOL)
    with pytest.raises(ValueError):
        _core.boxed.friction_recover(M, q, lo, hi, np.array([1, 0], np.int64), np.zeros(4), TOL)


@pytest.mark.parametrize("seed", range(10))
def test_friction_box_recover_alone_and_on_the_callers_z(seed):
    """``boxed.friction_z`` is FrictionBox's recover alone (z_i = β+ - β-, unclipped);
    ``friction_recover`` given the caller's z (n entries) is the check alone, the same
    verdict and bits as on the extended answer; R and C are the caller's check_scales."""
    rng = np.random.default_rng(100 + seed)
    M, q, lo, hi, findex = _contacts(rng, 1 + seed % 5)
    n = q.size
    F, Mx, qx, lox, hix = _extend(M, q, lo, hi, findex)
    nf = F.size // 2
    fr, normal = F[:nf], F[nf:]
    r = lemke.solve_blcp(Mx, qx, lox, hix)
    assert r.status == lemke.Status.SOLVED
    for zx in (np.asarray(r.z), np.abs(rng.standard_normal(n + 2 * nf))):
        z = np.full(n, np.nan)
        _core.boxed.friction_z(F, zx, z)
        want = zx[:n].copy()
        want[fr] = zx[fr] - zx[n:n + nf]
        assert np.array_equal(z, want)
        a = _core.boxed.friction_recover(M, q, lo, hi, F, zx, TOL)
        b = _core.boxed.friction_recover(M, q, lo, hi, F, z, TOL)
        assert a[:2] == b[:2]
        for u, v in zip(a[2:], b[2:]):
            assert np.asarray(u).tobytes() == np.asarray(v).tobytes()
        R, C = np.empty(n), np.empty(n)
        _core.boxed.check_scales(M, q, lo, hi, R, C)
        assert np.array_equal(a[6], R) and np.array_equal(a[7], C)
        # z clipped into the coupled bounds at it (checked here with plain numpy)
        lo_c, hi_c = lo.copy(), hi.copy()
        lo_c[fr], hi_c[fr] = -hi[fr] * z[normal], hi[fr] * z[normal]
        assert np.array_equal(a[4], lo_c) and np.array_equal(a[5], hi_c)
        assert np.array_equal(a[2], np.clip(z, np.minimum(lo_c, hi_c), hi_c))
        assert np.allclose(a[3], M @ a[2] + q, rtol=0, atol=1e-12 * (1 + np.abs(M).sum()))
    assert not a[0]  # a random extended point is no solution
    with pytest.raises(ValueError):
        _core.boxed.friction_z(F, np.zeros(n + 2 * nf - 1), np.empty(n))
    with pytest.raises(ValueError):
        _core.boxed.friction_z(F, np.zeros(n + 2 * nf), np.empty(n - 1 if nf else n + 1))


# ----------------------------------------------------------------------------- BoxQp

def _box_qp(rng, n):
    B = rng.standard_normal((n, n))
    P = B @ B.T + 0.1 * np.eye(n)
    P[0, -1] += 1e-12 * abs(P[0, -1])  # (screen's Ps is (P + P')/2: P symmetric to 1e-10)
    q = rng.standard_normal(n) * 3
    lb = np.where(rng.random(n) < 0.6, -rng.uniform(0, 1, n), -np.inf)
    ub = np.where(rng.random(n) < 0.6, rng.uniform(0, 1, n), np.inf)
    fixed = rng.random(n) < 0.1
    ub[fixed] = lb[fixed] = np.where(np.isfinite(lb[fixed]), lb[fixed], 0.25)
    lb[rng.random(n) < 0.1] = -2e20  # (infinite by screen's rule)
    return P, q, np.zeros((0, n)), np.zeros(0), np.zeros((0, n)), np.zeros(0), lb, ub


@pytest.mark.parametrize("seed", range(30))
def test_box_qp_apply_recover(seed):
    rng = np.random.default_rng(100 + seed)
    n = 1 + seed % 12
    data = _box_qp(rng, n)
    P, q, G, h, A, b, lb, ub = data
    ok, Ms, lo, up = _core.qp_box_apply(*data)
    assert ok
    assert np.allclose(Ms, (P + P.T) / 2, rtol=1e-15, atol=0) and np.array_equal(Ms, Ms.T)
    assert np.array_equal(lo, np.where(lb <= -1e20, -np.inf, lb))
    assert np.array_equal(up, np.where(ub >= 1e20, np.inf, ub))
    buf, final = np.empty(6 * n + 1), np.empty(n, np.int64)
    code, pivots, z0, run_ok, residual, k, m = _core.boxed.solve(
        Ms, q, lo, up, np.zeros(2 * n, bool), 0, 100 * (n + 1), PIVOT_TOL, TIE_TOL, TOL, buf, final)
    assert code == 0 and run_ok
    z, w = buf[:n], buf[n:2 * n]
    _box_conditions(Ms, q, lo, up, z)
    got = _core.qp_box_recover(*data, z, w, final, k, m, TOL)
    passed, zb, stats, basis, count, pairs = got
    assert np.array_equal(zb, -w)
    res = SimpleNamespace(x=z, y=np.zeros(0), z=np.zeros(0), z_box=zb, obj=stats[3])
    assert_qp_kkt(P, q, None, None, None, None, lb, ub, res, rtol=1e-7)
    assert passed
    # qp_solve_box is this pair around one run: the same bits
    L = _core.qp_box_layout(n)
    out = np.empty(L[-1])
    fin = out[L[3]:].view(np.int64)
    code2, pivots2, k2, pairs2 = _core.qp_solve_box(*data, np.zeros(2 * n, bool), 100 * (n + 1),
                                                    PIVOT_TOL, TIE_TOL, TOL, out, fin)
    assert (code2, pivots2, k2, pairs2) == (0, pivots, count, pairs)
    assert out[:n].tobytes() == z.tobytes() and out[L[1]:L[2]].tobytes() == zb.tobytes()
    assert out[L[2]:L[3]].tobytes() == stats.tobytes()
    assert np.array_equal(fin[n:n + k2], basis)


def test_box_qp_recover_refuses():
    rng = np.random.default_rng(3)
    data = _box_qp(rng, 4)
    n = 4
    G1, h1 = np.ones((1, n)), np.ones(1)
    P, q, G, h, A, b, lb, ub = data
    assert not _core.qp_box_apply(P, q, G1, h1, A, b, lb, ub)[0]
    z, w, final = np.zeros(n), np.zeros(n), np.arange(n, dtype=np.int64)
    assert _core.qp_box_recover(P, q, G1, h1, A, b, lb, ub, z, w, final, 2, 3, TOL) is None
    for k, m, fin in ((3, 2, final), (0, 5, final), (0, 2, np.array([0, 9, 0, 0], np.int64))):
        with pytest.raises(ValueError):
            _core.qp_box_recover(*data, z, w, fin, k, m, TOL)
    with pytest.raises(ValueError):
        _core.qp_box_recover(*data, z[:3], w, final, 0, 0, TOL)


# ----------------------------------------------------------------------------- MultiplierLcp

def _qp(seed, n, m, p):
    """test_reductions' random QP with some variables fixed and some rows of G at h = inf."""
    P, q, G, h, A, b, lb, ub = _random_qp(seed, n, m, p)
    rng = np.random.default_rng(seed)
    rng.standard_normal((n, n))
    x0 = rng.standard_normal(n)  # (_random_qp's feasible point, drawn again)
    assert np.array_equal(A @ x0, b)
    fixed = rng.random(n) < 0.15
    lb[fixed] = ub[fixed] = x0[fixed]
    h[rng.random(m) < 0.1] = np.inf  # (a row that does not count)
    return P, q * 3, G, h, A, b, lb, ub


@pytest.mark.parametrize("seed", range(30))
def test_multiplier_lcp_apply_recover(seed):
    n = 2 + seed % 9
    data = _qp(200 + seed, n, (3 * seed) % (2 * n), seed % (n // 2 + 1))
    P, q, G, h, A, b, lb, ub = data
    code, M, g = _core.qp_multiplier_lcp(*data)
    assert code == _core.QP_OK
    m = g.size
    assert M.shape == (m, m)
    # apply: M = C2 C2' is symmetric positive semidefinite
    assert np.allclose(M, M.T, rtol=0, atol=1e-12 * (1 + np.abs(M).max(initial=0)))
    assert np.linalg.eigvalsh((M + M.T) / 2).min(initial=0) >= -1e-9 * (1 + np.abs(M).max(initial=0))
    r = lemke.solve_lcp(M, g)
    assert r.status == lemke.Status.SOLVED
    L = _core.qp_layout(n, A.shape[0], G.shape[0])
    out = np.full(L[-1], np.nan)
    basic = np.empty(G.shape[0] + 2 * n, np.int64)
    lcp_basic = np.array(r.warm_start.z_basic, np.int64)
    code, passed, count, pairs = _core.qp_multiplier_recover(*data, r.z, lcp_basic, TOL, out, basic)
    assert code == _core.QP_OK
    x, y, z, zb = out[L[0]:L[1]], out[L[1]:L[2]], out[L[2]:L[3]], out[L[3]:L[4]]
    counted = np.isfinite(h)  # (a row with h = inf is no constraint: its z is 0)
    assert np.all(z[~counted] == 0)
    res = SimpleNamespace(x=x, y=y, z=z[counted], z_box=zb, obj=out[L[4] + 3])
    assert_qp_kkt(P, q, G[counted], h[counted], A, b, lb, ub, res, rtol=1e-7)
    assert passed
    # the fused kernel (this pair around its own LCP run) answers the same point
    out2 = np.empty(L[-1])
    code2, _, k2, pairs2 = _core.qp_solve(*data, 0, -1, PIVOT_TOL, TIE_TOL, TOL, out2)
    assert code2 == _core.QP_OK and pairs2 == pairs
    scale = 1e-7 * (1 + np.abs(out2[:L[4]]).max())
    assert np.allclose(out[:L[4]], out2[:L[4]], rtol=0, atol=scale)


def test_multiplier_lcp_codes():
    data = list(_qp(5, 4, 3, 1))
    code, M, g = _core.qp_multiplier_lcp(*data)
    m = g.size
    L = _core.qp_layout(4, 1, 3)
    out, basic = np.empty(L[-1]), np.empty(3 + 8, np.int64)
    # zz of another length, basic z's out of range: BAD_INPUT, nothing recovered
    for zz, lb_ in ((np.zeros(m + 1), np.zeros(0, np.int64)), (np.zeros(m), np.array([m], np.int64)),
                    (np.zeros(m), np.array([-1], np.int64))):
        got = _core.qp_multiplier_recover(*data, zz, lb_, TOL, out, basic)
        assert got == (_core.QP_BAD_INPUT, False, 0, 0)
    # P not definite; equalities dependent
    bad = list(data)
    bad[0] = -np.eye(4)
    assert _core.qp_multiplier_lcp(*bad)[0] == _core.QP_NOT_DEFINITE
    bad = list(data)
    bad[4], bad[5] = np.vstack([data[4], data[4]]), np.concatenate([data[5], data[5]])
    assert _core.qp_multiplier_lcp(*bad)[0] == _core.QP_DEPENDENT_EQUALITIES
    with pytest.raises(ValueError):
        _core.qp_multiplier_recover(*data, np.zeros(m), np.zeros(0, np.int64), TOL, out[:5], basic)
    with pytest.raises(ValueError):
        _core.qp_multiplier_recover(*data, np.zeros(m), np.zeros(0, np.int64), TOL, out, basic[:3])
