"""The seam's basis systems (src/lemke/basis.hpp's LcpBasis, BoxBasis, FrictionBasis,
MlcpBasis and KktBasis, issue 31 item 2) through their private entries ``_core.lcp_basis(M,
q, z_basic, tol, rhs=None, transpose=False)``, ``_core.box_basis(M, q, lo, hi, zb, zh,
warm_rule, tol, rhs=None, transpose=False)``, ``_core.friction_basis(M, q, lo, hi, F, zb,
zh, tol, rhs=None, transpose=False)``, ``_core.mlcp_basis(E, e, n, redundant, undetermined,
v_basic, tol=None, rhs=None, transpose=False)`` (its point MLCPToLCP.basis_point's, bit for
bit against the routine it replaced) and ``_core.kkt_basis(P, q, G, h, A, b, lb, ub, basic,
tol=None, rhs=None, transpose=False)`` (its point _qp._polished's, bit for bit against the
numpy code it replaced, kept here as the oracle), and the QP kind's QpBasis (src/lemke/qp.cpp) through
``_core.qp_basis(P, q, G, h, A, b, lb, ub, active, tol, steps=2, z=None, rhs=None,
transpose=False)`` (its KKT solves against numpy, its point against a KKT check written
here, and the point of the fused path's warm start and of the factored path bit for bit the
seam's), checked
independently of the core: the solve and the transpose solve against numpy.linalg.solve on
the block built here (M[beta, beta] and its transpose), singular blocks reported, the point's
z and w against the LCP (box LCP) conditions computed here, and the engines' point of a
basis (a warm start solved by its old basis, 0 pivots) the seam's own, bit for bit."""
from __future__ import annotations

import numpy as np
import pytest

import lemke
from lemke import _core
from helpers import kkt_blocks

EPS = np.finfo(float).eps
TOL = 1e-9  # Options().tol


def _random_problem(n, rng, symmetric=False):
    A = rng.normal(size=(n, n))
    M = A @ A.T + np.eye(n) if symmetric else A + n ** 0.5 * np.eye(n)
    return M, rng.normal(size=n)


def _backward_ok(B, x, rhs):
    """|B x - rhs| within a small multiple of eps (|B| |x| + |rhs|), row by row (the
    backward error any pivoted LU meets on a block this size)."""
    k = B.shape[0]
    r = np.abs(B @ x - rhs)
    size = np.abs(B) @ np.abs(x) + np.abs(rhs)
    return bool(np.all(r <= 8 * (k + 1) * EPS * size))


def _close_to_numpy(B, x, rhs):
    ref = np.linalg.solve(B, rhs)
    bound = 64 * B.shape[0] * EPS * np.linalg.cond(B, 1) * (np.abs(ref).max() + 1e-300)
    return bool(np.max(np.abs(x - ref)) <= bound)


def _flags(n, indices):
    f = np.zeros(n, bool)
    f[list(indices)] = True
    return f


def _warm_hit(rw, got):
    """1 when the warm solve rw took 0 pivots (its point the old basis's), with the seam's
    answer got then passing and equal to it bit for bit (z and w); else 0."""
    if rw.pivots != 0 or rw.status != lemke.Status.SOLVED:
        return 0
    code, z, w = got[:3]
    assert code == 0
    assert z.tobytes() == np.asarray(rw.z).tobytes()
    assert w.tobytes() == np.asarray(rw.w).tobytes()
    return 1


SIZES = [1, 2, 3, 5, 8, 9, 16, 17, 31, 40]


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("transpose", [False, True])
def test_solves_match_numpy_on_random_bases(n, transpose):
    rng = np.random.default_rng(100 + n + 1000 * transpose)
    for t in range(6):
        M, q = _random_problem(n, rng, symmetric=t % 3 == 0)
        flags = rng.random(n) < (0.3 + 0.1 * t)
        if t == 5:
            flags[:] = True  # every z basic: B = M
        beta = np.flatnonzero(flags)
        k = beta.size
        rhs = rng.normal(size=k)
        code, z, w, residual, x = _core.lcp_basis(M, q, flags, TOL, rhs, transpose)
        assert code in (0, 1)
        B = M[np.ix_(beta, beta)]
        Bs = B.T if transpose else B
        assert x.shape == (k,)
        assert _backward_ok(Bs, x, rhs), (n, t)
        if k:
            assert _close_to_numpy(Bs, x, rhs), (n, t)
        # the other solve by the same factors
        code2, _, _, _, x2 = _core.lcp_basis(M, q, flags, TOL, rhs, not transpose)
        assert code2 == code
        assert _backward_ok(B if transpose else B.T, x2, rhs)


def test_transpose_differs_from_solve_on_nonsymmetric_blocks():
    # (a transpose solve that solved B instead would pass the symmetric cases)
    rng = np.random.default_rng(7)
    M, q = _random_problem(12, rng)
    flags = np.ones(12, dtype=np.uint8)
    rhs = rng.normal(size=12)
    x = _core.lcp_basis(M, q, flags, TOL, rhs, False)[4]
    xt = _core.lcp_basis(M, q, flags, TOL, rhs, True)[4]
    assert np.max(np.abs(x - xt)) > 1e-3
    np.testing.assert_allclose(M.T @ xt, rhs, rtol=0, atol=1e-10 * np.abs(rhs).max())


def test_pivoting_is_needed_and_taken():
    # zero diagonal: an LU without row exchanges would divide by zero
    M = np.array([[0.0, 2.0, 1.0], [3.0, 0.0, 1.0], [1.0, 1.0, 0.0]])
    q = np.array([-1.0, -1.0, -1.0])
    rhs = np.array([1.0, 2.0, 3.0])
    for transpose in (False, True):
        code, z, w, _, x = _core.lcp_basis(M, q, np.ones(3, bool), TOL, rhs, transpose)
        assert code in (0, 1)
        Bs = M.T if transpose else M
        np.testing.assert_allclose(Bs @ x, rhs, rtol=0, atol=1e-14)


@pytest.mark.parametrize("kind", ["duplicate", "zero", "rank1"])
def test_singular_blocks_are_reported(kind):
    rng = np.random.default_rng(3)
    n = 7
    M, q = _random_problem(n, rng)
    beta = np.array([1, 3, 4, 6])
    if kind == "duplicate":  # rows 3 and 4 of the block equal
        M[4, :] = M[3, :]
    elif kind == "zero":
        M[np.ix_(beta, beta)] = 0.0
    else:
        u, v = rng.normal(size=beta.size), rng.normal(size=beta.size)
        M[np.ix_(beta, beta)] = np.outer(u, v)
    flags = np.zeros(n, bool)
    flags[beta] = True
    B = M[np.ix_(beta, beta)]
    if kind != "rank1":
        assert np.linalg.matrix_rank(B) < beta.size
    for transpose in (False, True):
        code, z, w, residual, x = _core.lcp_basis(M, q, flags, TOL, np.ones(beta.size), transpose)
        if kind == "rank1" and code != 2:
            # rounding may leave a tiny pivot: then the answers must still be the LU's own
            # (finite), and the point's check decides
            assert code in (0, 1) and np.all(np.isfinite(z))
            continue
        assert code == 2
        assert z is None and w is None and x is None


def test_point_against_lcp_conditions():
    """The point of a basis: z_beta = max(-B^-1 q_beta, 0), 0 elsewhere, w = M z + q; its
    verdict agrees with the LCP conditions checked here."""
    rng = np.random.default_rng(11)
    seen = {0: 0, 1: 0}
    for t in range(60):
        n = int(rng.integers(1, 25))
        M, q = _random_problem(n, rng, symmetric=t % 2 == 0)
        if t % 3 == 0:  # a solution's basis (the engine's), usually passing
            flags = _flags(n, lemke.solve_lcp(M, q).warm_start.z_basic)
        else:
            flags = rng.random(n) < 0.5
        code, z, w, residual, x = _core.lcp_basis(M, q, flags, TOL)
        assert x is None
        beta = np.flatnonzero(flags)
        zref = np.zeros(n)
        if beta.size:
            zref[beta] = np.maximum(-np.linalg.solve(M[np.ix_(beta, beta)], q[beta]), 0.0)
        scale = np.abs(M) @ np.abs(zref) + np.abs(q) + 1.0
        assert np.all(z >= 0) and np.all(z[~flags] == 0)
        assert np.all(np.abs(z - zref) <= 1e-8 * scale)
        assert np.all(np.abs(w - (M @ z + q)) <= 1e-12 * scale)
        # the LCP conditions, here: w >= 0 and min(z, w) = 0 up to each row's size
        viol = np.maximum(-w, np.minimum(np.abs(z), np.abs(w))) / scale
        seen[code] += 1
        if code == 0:
            assert viol.max() <= 1e-8, (t, viol.max())
            assert residual <= 1e-8 * scale.max()
        else:
            assert code == 1 and viol.max() > 1e-12, (t, viol.max())
    assert seen[0] >= 10 and seen[1] >= 10  # both verdicts met


def test_degenerate_bases():
    # q = 0 on the basic rows: z_beta = 0 (a degenerate vertex), w = q off beta
    M = np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]])
    q = np.array([0.0, 0.0, 1.0])
    code, z, w, residual, x = _core.lcp_basis(M, q, np.array([1, 1, 0], np.uint8), TOL, np.array([1.0, 1.0]))
    assert code == 0 and np.all(z == 0) and np.array_equal(w, q)
    np.testing.assert_allclose(M[:2, :2] @ x, [1.0, 1.0], rtol=0, atol=1e-15)
    # no basic z: z = 0, w = q; an empty rhs gives an empty x
    for q2, want in ((np.array([1.0, 0.0, 2.0]), 0), (np.array([1.0, -1.0, 2.0]), 1)):
        code, z, w, residual, x = _core.lcp_basis(M, q2, np.zeros(3, bool), TOL, np.zeros(0), True)
        assert code == want and np.all(z == 0) and np.array_equal(w, q2)
        assert x.shape == (0,)
    # clipped: -B^-1 q_beta negative on a basic row gives z_i = 0 there
    q3 = np.array([1.0, -1.0, 1.0])
    code, z, w, _, _ = _core.lcp_basis(M, q3, np.array([1, 1, 0], bool), TOL)
    assert z[0] == 0.0 and z[1] > 0
    # the empty problem
    code, z, w, residual, x = _core.lcp_basis(np.zeros((0, 0)), np.zeros(0), np.zeros(0, bool), TOL, np.zeros(0))
    assert code == 0 and z.shape == w.shape == x.shape == (0,)


def test_engine_point_is_the_seams_bit_for_bit():
    """A warm start whose old basis solves the new q (0 pivots) answers the point of that
    basis: lcp.cpp's basis_point, now LcpBasis::point; the seam's entry gives the same bits
    (z and w), kept matrices or not."""
    rng = np.random.default_rng(5)
    hits = 0
    for t in range(40):
        n = int(rng.integers(2, 60))
        M, q = _random_problem(n, rng, symmetric=True)
        r = lemke.solve_lcp(M, q)
        flags = _flags(n, r.warm_start.z_basic)
        for s in range(3):
            q2 = q + 1e-6 * rng.normal(size=n)
            rw = lemke.solve_lcp(M, q2, warm_start=r.warm_start)
            hits += _warm_hit(rw, _core.lcp_basis(M, q2, flags, TOL))
    assert hits >= 60


def test_bad_arguments_refused_and_not_finite_reported():
    M, q = np.eye(3), -np.ones(3)
    f = np.ones(3, bool)
    with pytest.raises(ValueError):
        _core.lcp_basis(np.eye(4), q, f, TOL)
    with pytest.raises(ValueError):
        _core.lcp_basis(M, q, f[:2], TOL)
    with pytest.raises(ValueError):
        _core.lcp_basis(M, q, f, TOL, np.ones(2))
    with pytest.raises(TypeError):
        _core.lcp_basis(M, q, f.astype(np.int32), TOL)
    unaligned = np.frombuffer(b"\0" + M.tobytes(), dtype=float, offset=1).reshape(3, 3)
    with pytest.raises(TypeError):  # (read as doubles, an unaligned array is undefined behaviour)
        _core.lcp_basis(unaligned, q, f, TOL)
    Mn = M.copy()
    Mn[0, 2] = np.nan
    assert _core.lcp_basis(Mn, q, f, TOL)[0] == -1
    assert _core.lcp_basis(M, np.array([1.0, np.inf, 0.0]), f, TOL)[0] == -1
    code, z, w, _, x = _core.lcp_basis(M, q, f, TOL, np.array([1.0, np.nan, 0.0]))
    assert code == 0 and x is None  # the point stands; that solve is not finite


# --- the box kind (BoxBasis, no friction index): _core.box_basis(M, q, lo, hi, zb, zh,
# warm_rule, tol, rhs=None, transpose=False)

def _box_problem(n, rng):
    M, q = _random_problem(n, rng)
    lo = np.where(rng.random(n) < 0.7, -rng.random(n), -np.inf)
    hi = np.where(rng.random(n) < 0.7, rng.random(n), np.inf)
    return M, q, lo, hi


def _box_rows_and_fixed(lo, hi, zb, zh, warm_rule):
    """The block's rows and the fixed z's, by the rule stated in boxed.hpp (here in numpy)."""
    free = warm_rule & np.isneginf(lo) & np.isposinf(hi)
    if warm_rule:
        v = np.where(np.isfinite(hi), hi, 0.0)
        v = np.where(np.isfinite(lo), lo, v)
        v = np.where(zh & np.isfinite(hi), hi, v)
    else:
        v = np.where(zh, hi, lo)
        v = np.where(np.isfinite(v), v, 0.0)
    rows = np.flatnonzero(zb | free)
    v[rows] = 0.0
    return rows, v


def _box_violation(z, w, lo, hi):
    """The box LCP conditions, here, row by row: w >= 0 at lo, w <= 0 at hi, w = 0 strictly
    inside, lo <= z <= hi; each row's violation."""
    at_lo, at_hi = z <= lo, z >= hi
    viol = np.where(at_lo & at_hi, 0.0, np.where(at_lo, np.maximum(-w, 0.0),
                    np.where(at_hi, np.maximum(w, 0.0), np.abs(w))))
    return np.maximum(viol, np.maximum(lo - z, 0.0) + np.maximum(z - hi, 0.0))


@pytest.mark.parametrize("warm_rule", [False, True])
def test_box_point_solves_and_conditions(warm_rule):
    rng = np.random.default_rng(21 + warm_rule)
    seen = {0: 0, 1: 0}
    for t in range(80):
        n = int(rng.integers(1, 30))
        M, q, lo, hi = _box_problem(n, rng)
        if t % 3 == 0:  # a solution's basis (the engine's), usually passing
            ws = lemke.solve_blcp(M, q, lo, hi).warm_start
            zb, zh = _flags(n, ws.z_basic), _flags(n, ws.at_upper)
        else:
            zb = rng.random(n) < 0.5
            zh = ~zb & (rng.random(n) < 0.5)
        rows, fixed = _box_rows_and_fixed(lo, hi, zb, zh, warm_rule)
        k = rows.size
        rhs = rng.normal(size=k)
        transpose = bool(t % 2)
        code, z, w, residual, x = _core.box_basis(M, q, lo, hi, zb, zh, warm_rule, TOL, rhs, transpose)
        assert code in (0, 1)
        B = M[np.ix_(rows, rows)]
        Bs = B.T if transpose else B
        assert x.shape == (k,) and _backward_ok(Bs, x, rhs)
        if k:
            assert _close_to_numpy(Bs, x, rhs)
        zref = fixed.copy()
        if k:
            zref[rows] = np.linalg.solve(B, -(q + M @ fixed)[rows])
        if not warm_rule:
            zref = np.clip(zref, lo, hi)
        scale = np.abs(M) @ np.abs(zref) + np.abs(q) + 1.0
        assert np.all(np.abs(z - zref) <= 1e-8 * scale), t
        assert np.all(np.abs(w - (M @ z + q)) <= 1e-12 * scale)
        viol = _box_violation(z, w, lo, hi) / scale
        seen[code] += 1
        if code == 0:
            assert viol.max() <= 1e-8, (t, viol.max())
        else:
            assert viol.max() > 1e-12, (t, viol.max())
    assert seen[0] >= 5 and seen[1] >= 5


def test_box_singular_and_refused():
    rng = np.random.default_rng(4)
    M, q, lo, hi = _box_problem(6, rng)
    zb = np.array([1, 1, 0, 1, 0, 0], bool)
    zh = np.zeros(6, bool)
    M[1, :] = M[0, :]
    code, z, w, _, x = _core.box_basis(M, q, lo, hi, zb, zh, False, TOL, np.ones(3))
    assert code == 2 and z is None and w is None and x is None
    with pytest.raises(ValueError):
        _core.box_basis(M, q, lo, hi, zb, zh, False, TOL, np.ones(2))
    with pytest.raises(ValueError):
        _core.box_basis(M, q, lo[:5], hi, zb, zh, False, TOL)
    with pytest.raises(TypeError):
        _core.box_basis(M, q, lo, hi, zb.astype(np.int64), zh, False, TOL)
    lo2 = lo.copy()
    lo2[0] = np.nan
    assert _core.box_basis(M, q, lo2, hi, zb, zh, False, TOL)[0] == _core.boxed.NOT_FINITE
    lo2[0] = hi[0] + 1.0
    assert _core.box_basis(M, q, lo2, hi, zb, zh, False, TOL)[0] == _core.boxed.BAD_BOUNDS


def test_box_engine_point_is_the_seams_bit_for_bit():
    """A box warm start whose old basis still solves the moved q (0 pivots) answers the
    point of that basis by boxed::basis_point, now BoxBasis::point: the same bits as the
    seam's entry with the warm rule."""
    rng = np.random.default_rng(9)
    hits = 0
    for t in range(40):
        n = int(rng.integers(2, 40))
        M, q, lo, hi = _box_problem(n, rng)
        M = M @ M.T + np.eye(n)
        r = lemke.solve_blcp(M, q, lo, hi)
        ws = r.warm_start
        zb, zh = _flags(n, ws.z_basic), _flags(n, ws.at_upper)
        for s in range(3):
            q2 = q + 1e-7 * rng.normal(size=n)
            rw = lemke.solve_blcp(M, q2, lo, hi, warm_start=ws)
            hits += _warm_hit(rw, _core.box_basis(M, q2, lo, hi, zb, zh, True, TOL))
    assert hits >= 60


# --- the box kind with a friction index (FrictionBasis): _core.friction_basis(M, q, lo, hi,
# F, zb, zh, tol, rhs=None, transpose=False); F the friction rows then their normals, zb and
# zh the extended problem's flags (n + 2 nf: z, then β-, then λ)

def _friction_case(seed, k):
    from test_blcp import contacts  # tests/ is on sys.path under pytest
    M, q, lo, hi, fi, mu = contacts(seed, k)
    F = np.flatnonzero(fi >= 0)
    return M, q, lo, hi, fi.astype(np.int64), F, fi[F].astype(np.int64)


def _friction_system(M, q, lo, hi, F, normal, zb, zh):
    """The block, its rows and right-hand side, the fixed z's, by the rule stated in
    basis.hpp (here in numpy); None where the extended block is singular by its pattern."""
    n, nf = q.size, F.size
    zb, zh = zb.astype(bool), zh.astype(bool)
    hf, lf = hi < np.inf, lo > -np.inf
    eq = zb[:n] | (~lf & np.isposinf(hi))
    v = np.where(hf, hi, 0.0)
    v = np.where(lf, lo, v)
    v = np.where(zh[:n] & hf, hi, v)
    z = np.where(eq, 0.0, v)
    bp, bm, lam = zb[F], zb[n:n + nf], zb[n + nf:]
    if np.any(np.where(lam, ~(bp | bm), bp & bm)):
        return None
    slope = np.where(bp, hi[F], -hi[F])
    sliding = lam & (bp != bm)
    eq[F] = (bp | bm) & ~sliding
    z[F] = 0.0
    inside = sliding & eq[normal]
    out = sliding & ~eq[normal]
    z[F[out]] = slope[out] * z[normal[out]]
    rows = np.flatnonzero(eq)
    pos = np.full(n, -1)
    pos[rows] = np.arange(rows.size)
    B = M[np.ix_(rows, rows)].copy()
    for c in np.flatnonzero(inside):
        B[:, pos[normal[c]]] += slope[c] * M[rows, F[c]]
    rhs = -(q + M @ z)[rows]
    return rows, B, rhs, z, slope, inside


def _friction_flags(n, F, rng):
    """Random extended flags with a pattern each friction row may have (β+, β-, λ and β+,
    λ and β-, none basic)."""
    nf = F.size
    zb = rng.random(n + 2 * nf) < 0.5
    zh = ~zb & (rng.random(n + 2 * nf) < 0.5)
    for c in range(nf):
        s = rng.integers(5)
        zb[F[c]], zb[n + c], zb[n + nf + c] = [(1, 0, 0), (0, 1, 0), (1, 0, 1), (0, 1, 1),
                                               (0, 0, 0)][s]
    return zb, zh


def test_friction_point_solves_and_conditions():
    rng = np.random.default_rng(31)
    seen = {0: 0, 1: 0, "sliding": 0}
    for t in range(90):
        M, q, lo, hi, fi, F, normal = _friction_case(t, 1 + t % 6)
        n, nf = q.size, F.size
        if t % 3 == 0:  # a solution's basis (the engine's), q moved a little: usually passing
            flags = lemke.solve_blcp(M, q, lo, hi, findex=fi).warm_start._kernel_flags()
            zb, zh = flags[:n + 2 * nf], flags[n + 2 * nf:]
            q = q + 1e-4 * rng.normal(size=n)
        else:
            zb, zh = _friction_flags(n, F, rng)
        rows, B, b, zfix, slope, inside = _friction_system(M, q, lo, hi, F, normal, zb, zh)
        k = rows.size
        rhs = rng.normal(size=k)
        transpose = bool(t % 2)
        code, z, w, residual, x = _core.friction_basis(M, q, lo, hi, np.concatenate([F, normal]),
                                                       zb, zh, TOL, rhs, transpose)
        if code == 2:  # a singular block (rounding decides on these random ones)
            assert np.linalg.cond(B) > 1e10, t
            continue
        assert code in (0, 1), (t, code)
        Bs = B.T if transpose else B
        assert x.shape == (k,) and _backward_ok(Bs, x, rhs), t
        if k:
            assert _close_to_numpy(Bs, x, rhs), t
        zref = zfix.copy()
        if k:
            zref[rows] = np.linalg.solve(B, b)
        zref[F[inside]] = slope[inside] * zref[normal[inside]]
        seen["sliding"] += int(inside.sum())
        # the check's coupled bounds at the point, z clipped into them
        lo_c, hi_c = lo.copy(), hi.copy()
        lo_c[F], hi_c[F] = -hi[F] * zref[normal], hi[F] * zref[normal]
        zref = np.clip(zref, np.minimum(lo_c, hi_c), hi_c)
        scale = np.abs(M) @ np.abs(zref) + np.abs(q) + 1.0
        assert np.all(np.abs(z - zref) <= 1e-8 * scale), t
        assert np.all(np.abs(w - (M @ z + q)) <= 1e-12 * scale)
        # the friction conditions, here: the box LCP's with the bounds in force -+mu z_f
        lo_c[F], hi_c[F] = -hi[F] * z[normal], hi[F] * z[normal]
        viol = _box_violation(z, w, lo_c, hi_c) / scale
        seen[code] += 1
        if code == 0:
            assert viol.max() <= 1e-8, (t, viol.max())
            assert residual <= 1e-8 * scale.max()
        else:
            assert viol.max() > 1e-12, (t, viol.max())
    assert seen[0] >= 10 and seen[1] >= 10 and seen["sliding"] >= 5, seen


def test_friction_engine_point_is_the_seams_bit_for_bit():
    """A friction warm start answered with 0 pivots by its basis's point on the caller's
    rows (boxed::friction_point, now FrictionBasis::point, with the normals in their boxes
    and friction_check passing) is the seam's answer bit for bit (z, w, residual)."""
    rng = np.random.default_rng(33)
    hits = 0
    for t in range(60):
        M, q, lo, hi, fi, F, normal = _friction_case(t, 1 + t % 6)
        n, nf = q.size, F.size
        r = lemke.solve_blcp(M, q, lo, hi, findex=fi)
        ws = r.warm_start
        flags = ws._kernel_flags()
        zb, zh = flags[:n + 2 * nf], flags[n + 2 * nf:]
        for s in range(2):
            q2 = q + 1e-3 * np.abs(q) * rng.normal(size=n)
            rw = lemke.solve_blcp(M, q2, lo, hi, findex=fi, warm_start=ws)
            code, z, w, residual, x = _core.friction_basis(M, q2, lo, hi,
                                                           np.concatenate([F, normal]), zb, zh, TOL)
            if rw.pivots != 0 or code != 0 or np.any(z[normal] < lo[normal]):
                continue
            assert rw.status == lemke.Status.SOLVED
            assert z.tobytes() == np.asarray(rw.z).tobytes()
            assert w.tobytes() == np.asarray(rw.w).tobytes()
            assert residual == rw.residual
            hits += 1
    assert hits >= 40, hits


def test_friction_singular_patterns_and_refused():
    M, q, lo, hi, fi, F, normal = _friction_case(2, 3)
    n, nf = q.size, F.size
    Fn = np.concatenate([F, normal])
    zb, zh = _friction_flags(n, F, np.random.default_rng(1))
    for pattern in ((0, 0, 1), (1, 1, 0), (1, 1, 1)):  # (β+, β-, λ) singular by pattern
        bad = zb.copy()
        bad[F[0]], bad[n], bad[n + nf] = pattern
        if pattern == (1, 1, 1):  # λ with both: not singular by its pattern
            assert _core.friction_basis(M, q, lo, hi, Fn, bad, zh, TOL)[0] in (0, 1, 2)
            continue
        code, z, w, _, x = _core.friction_basis(M, q, lo, hi, Fn, bad, zh, TOL, np.ones(3))
        assert code == 2 and z is None and w is None and x is None
    with pytest.raises(ValueError):  # rhs of the wrong length
        k = _friction_system(M, q, lo, hi, F, normal, zb, zh)[0].size
        _core.friction_basis(M, q, lo, hi, Fn, zb, zh, TOL, np.ones(k + 1))
    with pytest.raises(ValueError):  # flags of n entries, not n + 2 nf
        _core.friction_basis(M, q, lo, hi, Fn, zb[:n], zh[:n], TOL)
    with pytest.raises(ValueError):  # odd F
        _core.friction_basis(M, q, lo, hi, Fn[:-1], zb, zh, TOL)
    for bad_F in (np.concatenate([F[:1], F[:1], normal[:2]]),  # a friction row twice
                  np.concatenate([F, F[::-1]]),                 # a normal that is a friction row
                  np.concatenate([F, normal + n])):             # out of range
        with pytest.raises(ValueError):
            _core.friction_basis(M, q, lo, hi, bad_F.astype(np.int64), zb[:n + 2 * (bad_F.size // 2)],
                                 zh[:n + 2 * (bad_F.size // 2)], TOL)
    # (an int32 F is converted by nanobind: the same answer)
    assert (_core.friction_basis(M, q, lo, hi, Fn.astype(np.int32), zb, zh, TOL)[1].tobytes()
            == _core.friction_basis(M, q, lo, hi, Fn, zb, zh, TOL)[1].tobytes())
    with pytest.raises(TypeError):
        _core.friction_basis(M, q, lo, hi, Fn, zb.astype(np.int64), zh, TOL)
    unaligned = np.frombuffer(b"\0" + M.tobytes(), dtype=float, offset=1).reshape(M.shape)
    with pytest.raises(TypeError):
        _core.friction_basis(unaligned, q, lo, hi, Fn, zb, zh, TOL)
    lo2 = lo.copy()
    lo2[0] = np.nan
    assert _core.friction_basis(M, q, lo2, hi, Fn, zb, zh, TOL)[0] == _core.boxed.NOT_FINITE
    hi2 = hi.copy()
    hi2[F[0]] = 2.0 * hi[F[0]] + 1.0  # not -+mu
    assert _core.friction_basis(M, q, lo, hi2, Fn, zb, zh, TOL)[0] == _core.boxed.BAD_FINDEX
    # no friction rows: the box kind's warm point (BoxBasis with the warm rule), the same
    # numbers once clipped into [lo, hi] as the friction check clips
    e = np.zeros(0, np.int64)
    b, h = zb[:n], zh[:n]
    got = _core.friction_basis(M, q, lo, hi, e, b, h, TOL)
    ref = _core.box_basis(M, q, lo, hi, b, h, True, TOL)
    assert got[0] == ref[0] and np.array_equal(got[1], np.clip(ref[1], lo, hi))


def test_friction_rows_refused_where_extend_would_not_write_them():
    """boxed.friction_point and friction_basis refuse an F that extend cannot write (a
    friction row given twice: as many coupled rows as F names, more than the work held)."""
    M, q, lo, hi, fi, F, normal = _friction_case(4, 2)
    n = q.size
    nf = 10 * n  # row F[0] given 10n times, each sliding on normal[0] (basic): past 3n ints
    Fb = np.concatenate([np.full(nf, F[0]), np.full(nf, normal[0])]).astype(np.int64)
    zb = np.zeros(n + 2 * nf, bool)
    zb[normal[0]] = zb[n:n + nf] = zb[n + nf:] = True  # β- and λ basic: sliding
    zh = np.zeros_like(zb)
    with pytest.raises(ValueError):
        _core.boxed.friction_point(M, q, lo, hi, Fb, zb, zh, np.empty(n))
    with pytest.raises(ValueError):
        _core.friction_basis(M, q, lo, hi, Fb, zb, zh, TOL)


# --- the MLCP kind (MlcpBasis, branch seam3): _core.mlcp_basis(E, e, n, redundant,
# undetermined, v_basic, tol=None, rhs=None, transpose=False) on the stacked system
# E x + e = (0, w), x = (u, v), the block E[rows, cols] of the kept equations and determined
# u and the basic v's.

def _old_mlcp_basis_point(E, e, n, v_basic, red):
    """MLCPToLCP.basis_point as it was before the seam (numpy's gathers, then the core's
    refined_solve through the Python wrapper): the reference of the seam's bits."""
    from lemke._reductions.mlcp_lcp import refined_solve
    N = e.size
    rows, cols = _mlcp_blocks(E, n, red, v_basic)
    if rows.size != cols.size:
        return None
    x = np.zeros(N)
    if rows.size:
        xb = refined_solve(E[np.ix_(rows, cols)], -e[rows])
        if xb is None:
            return None
        x[cols] = xb
    x[n:] = np.maximum(x[n:], 0.0)
    return x


def _random_mlcp(n, m, rng):
    N = n + m
    A = rng.normal(size=(N, N))
    E = A @ A.T + np.eye(N) if rng.random() < 0.5 else A + np.sqrt(N) * np.eye(N)
    return E, rng.normal(size=N)


def _mlcp_blocks(E, n, red, v_basic):
    keep_eq = np.setdiff1d(np.arange(n), red.redundant)
    keep_u = np.setdiff1d(np.arange(n), red.undetermined)
    vb = n + np.flatnonzero(v_basic)
    return np.concatenate([keep_eq, vb]), np.concatenate([keep_u, vb])


def _mlcp_call(E, e, n, red, v_basic, tol=None, rhs=None, transpose=False):
    return _core.mlcp_basis(E, e, n, red.redundant.astype(np.int64),
                            red.undetermined.astype(np.int64), v_basic, tol, rhs, transpose)


@pytest.mark.parametrize("transpose", [False, True])
def test_mlcp_solves_match_numpy_on_random_bases(transpose):
    from lemke._reductions.mlcp_lcp import MLCPToLCP
    rng = np.random.default_rng(31 + transpose)
    for n, m in [(0, 3), (1, 1), (2, 5), (3, 0), (4, 9), (7, 12), (12, 20)]:
        for t in range(4):
            E, e = _random_mlcp(n, m, rng)
            red = MLCPToLCP(E, e, n)
            assert red.code == _core.MLCP_OK
            v_basic = rng.random(m) < (0.0, 0.3, 0.7, 1.0)[t]
            rows, cols = _mlcp_blocks(E, n, red, v_basic)
            rhs = rng.normal(size=rows.size)
            code, x, y, residual, sol = _mlcp_call(E, e, n, red, v_basic, TOL, rhs, transpose)
            assert code in (0, 1)
            B = E[np.ix_(rows, cols)]
            Bs = B.T if transpose else B
            if rows.size:
                assert _backward_ok(Bs, sol, rhs) and _close_to_numpy(Bs, sol, rhs)
                # the point: x_cols = B^-1 (-e_rows), its v clipped at 0 (a clip moves no
                # entry farther from numpy's solution, so the same bound holds)
                ref = np.linalg.solve(B, -e[rows])
                ref = np.where(cols >= n, np.maximum(ref, 0.0), ref)
                bound = 64 * rows.size * EPS * np.linalg.cond(B, 1) * (np.abs(ref).max() + 1e-300)
                assert np.max(np.abs(x[cols] - ref)) <= bound
            else:
                assert sol.shape == (0,)
            off = np.setdiff1d(np.arange(n + m), cols)
            assert np.all(x[off] == 0.0) and np.all(x[n:] >= 0.0)
            assert not np.signbit(x[n:]).any()  # (numpy's maximum: -0.0 clipped to +0.0)
            # y = E x + e, and the verdict against the MLCP conditions computed here
            assert np.allclose(y, E @ x + e, rtol=0, atol=1e-12 * (np.abs(E).max() * np.abs(x).max() + np.abs(e).max()))
            eq, v, w = y[:n], x[n:], y[n:]
            scale = max(np.abs(E).max(), np.abs(e).max())
            holds = (np.all(np.abs(eq) <= 1e-7 * scale * max(1.0, np.abs(x).max()))
                     and np.all(w >= -1e-7 * scale * max(1.0, np.abs(x).max()))
                     and np.all(np.minimum(v, np.abs(w)) <= 1e-7 * scale * max(1.0, np.abs(x).max())))
            assert holds or code == 1  # (a pass holds at a looser tolerance, checked here)
            ok_ref = lemke._certify.check_mlcp(E, e, n, x, TOL)
            assert (code == 0) == ok_ref[1] and residual == ok_ref[2]
            assert y[n:].tobytes() == ok_ref[0].tobytes()
            # without tol: the point alone, the same bits, no w
            code2, x2, y2, _, _ = _mlcp_call(E, e, n, red, v_basic)
            assert code2 == 0 and y2 is None and x2.tobytes() == x.tobytes()


def test_mlcp_singular_and_not_square_reported():
    from lemke._reductions.mlcp_lcp import MLCPToLCP
    rng = np.random.default_rng(7)
    E, e = _random_mlcp(2, 4, rng)
    red = MLCPToLCP(E, e, 2)
    v_basic = np.array([1, 1, 0, 0], bool)
    E2 = E.copy()
    E2[:, 3] = 0.0  # v_1's column zero: the block singular (a zero pivot, exactly)
    code, x, y, _, sol = _mlcp_call(E2, e, 2, red, v_basic, TOL, np.ones(4))
    assert code == 2 and x is None and y is None and sol is None
    assert _old_mlcp_basis_point(E2, e, 2, v_basic, red) is None
    # a block not square: one u undetermined, no equation redundant
    red.undetermined = np.array([1])
    assert _mlcp_call(E, e, 2, red, v_basic, TOL)[0] == 2
    assert red.basis_point(E, e, v_basic) is None
    # bad arguments refused
    with pytest.raises(ValueError):
        _core.mlcp_basis(E, e, 2, np.array([2], np.int64), np.zeros(0, np.int64), v_basic)
    with pytest.raises(ValueError):
        _core.mlcp_basis(E, e, 2, np.zeros(0, np.int64), np.zeros(0, np.int64), v_basic[:3])
    with pytest.raises(ValueError):
        _core.mlcp_basis(E[:, :5], e, 2, np.zeros(0, np.int64), np.zeros(0, np.int64), v_basic)
    with pytest.raises(TypeError):
        _core.mlcp_basis(E, e, 2, np.zeros(0, np.int64), np.zeros(0, np.int64),
                         v_basic.astype(np.int64))
    with pytest.raises(ValueError):  # rhs of the wrong length
        _core.mlcp_basis(E, e, 2, np.zeros(0, np.int64), np.zeros(0, np.int64), v_basic,
                         TOL, np.ones(3))


def _siconos_mlcp_cases():
    from siconos_mlcp import read_mlcp
    from lemke._mlcp import _as_mlcp
    from pathlib import Path
    folder = Path(__file__).resolve().parent / "data" / "siconos" / "mlcp"
    for path in sorted(folder.glob("*.dat")):
        A, B, C, D, a, b = read_mlcp(path)
        yield path.name, _as_mlcp(A, B, C, D, a, b)


def test_mlcp_basis_point_is_the_old_one_bit_for_bit():
    """MLCPToLCP.basis_point through the seam against the routine it replaced, on the
    Siconos MLCP files' final bases (those solve_mlcp ends on) and on random bases of
    them, and on random problems."""
    from lemke._reductions.mlcp_lcp import MLCPToLCP
    rng = np.random.default_rng(2026)
    cases = list(_siconos_mlcp_cases())
    assert len(cases) >= 10
    for t in range(20):
        n, m = int(rng.integers(0, 8)), int(rng.integers(0, 12))
        E, e = _random_mlcp(n, m, rng)
        cases.append((f"random {t}", (E, e, n)))
    compared = solved_bases = 0
    for name, (E, e, n) in cases:
        m = e.size - n
        red = MLCPToLCP(E, e, n)
        if red.code != _core.MLCP_OK:
            continue
        bases = [rng.random(m) < p for p in (0.0, 0.25, 0.5, 1.0)]
        if name.endswith(".dat"):
            res = lemke.solve_mlcp(E[:n, :n], E[n:, n:], E[:n, n:], E[n:, :n], e[:n], e[n:])
            vb = np.zeros(m, bool)
            vb[list(res.warm_start.z_basic)] = True
            bases.append(vb)
            solved_bases += 1
        for vb in bases:
            new, old = red.basis_point(E, e, vb), _old_mlcp_basis_point(E, e, n, vb, red)
            assert (new is None) == (old is None), name
            if new is not None:
                assert new.tobytes() == old.tobytes(), name
                compared += 1
    assert solved_bases >= 10 and compared >= 60


# --- the games kind (branch gamesbasis): SupportBasis through _core.game_basis(A, B,
# x_basic, y_basic, tol=None, rhs=None, transpose=False) -> (code, x, y, out, v), the
# re-solve of _games._resolve_float. Checked here without the core: the two bordered blocks
# built from the labels, their solve and transpose solve against numpy, the point against a
# Nash check written here (each player's regret against every pure strategy), and the
# verdicts against the numpy routine it replaced.

def _game_blocks(A, B, x_basic, y_basic):
    """The bordered blocks of a vertex pair, built here: S (row actions basic in P), J
    (columns whose slack is not basic in P), T (columns basic in Q), I (rows whose slack
    is not basic in Q); x's block [B[S, J]' -1; 1 0], y's [A[I, T] -1; 1 0]. None when
    the sizes differ or a support is empty."""
    m, n = A.shape
    S = sorted(i for i in set(x_basic) if i < m)
    J = sorted(set(range(n)) - {v - m for v in x_basic if v >= m})
    T = sorted(v - m for v in set(y_basic) if v >= m)
    I = sorted(set(range(m)) - {v for v in y_basic if v < m})
    if len(S) != len(J) or len(T) != len(I) or not S or not T:
        return None

    def bordered(P):
        k = P.shape[0]
        K = np.zeros((k + 1, k + 1))
        K[:k, :k] = P
        K[:k, k] = -1.0
        K[k, :k] = 1.0
        return K

    return S, T, bordered(B[np.ix_(S, J)].T), bordered(A[np.ix_(I, T)])


def _nash_regrets(A, B, x, y):
    """Each player's regret against every pure strategy: max_i (A y)_i - x'A y and
    max_j (x'B)_j - x'B y (numpy, not the core's games::check)."""
    Ay, xB = A @ y, x @ B
    return Ay.max() - x @ Ay, xB.max() - xB @ y


def _assert_nash(A, B, x, y, tol=TOL):
    m, n = A.shape
    assert x.shape == (m,) and y.shape == (n,)
    assert x.min() >= 0 and y.min() >= 0
    assert abs(x.sum() - 1) <= 4 * m * EPS and abs(y.sum() - 1) <= 4 * n * EPS
    ra, rb = _nash_regrets(A, B, x, y)
    slack = 64 * EPS * (m + n)
    assert ra <= tol * np.ptp(A) + slack * np.abs(A).max(), (ra, np.ptp(A))
    assert rb <= tol * np.ptp(B) + slack * np.abs(B).max(), (rb, np.ptp(B))


def _final_bases(A, B, cap=None):
    """(kernel code, x_basic, y_basic) of Lemke-Howson's final basis dropping each label
    (with cap: the vertex pair where a path stopped after cap pivots)."""
    from lemke import _games
    m, n = A.shape
    at = _games._layout(m, n)
    params = _games._DEFAULT_PARAMS.copy()
    if cap is not None:
        params[0] = cap
    for k in range(m + n):
        buf = np.empty(at["length"])
        code = _core.lemke_howson(A, B, k, _games._slack_start(m, n), params, buf)[0]
        labels = buf[at["labels"]:].view(np.int64)
        yield code, tuple(labels[:n].tolist()), tuple(labels[n : n + m].tolist())


def _game_cases(rng, count, top, randoms, stopped=()):
    """count random games (1 to top - 1 actions a side; normal, integer and badly scaled
    payoffs in turn) with their vertex pairs: the kernels' final ones, `randoms` random
    splits of the labels and the pairs where paths stopped after each cap in `stopped`."""
    for t in range(count):
        m, n = (int(v) for v in rng.integers(1, top, 2))
        A, B = _random_game(rng, m, n, t % 3)
        bases = [b[1:] for b in _final_bases(A, B)]
        for cap in stopped:
            bases += [b[1:] for b in _final_bases(A, B, cap)]
        for _ in range(randoms):
            p = rng.permutation(m + n)
            bases.append((tuple(p[:n].tolist()), tuple(p[n:].tolist())))
        yield t, A, B, bases


def _numpy_resolve(A, B, x_basic, y_basic, tol):
    """main's _games._resolve_float before the seam (numpy.linalg.solve), its verdict and
    point: None, or (x, y)."""
    blocks = _game_blocks(A, B, x_basic, y_basic)
    if blocks is None:
        return None
    m, n = A.shape
    S, T, Kx, Ky = blocks
    x, y = np.zeros(m), np.zeros(n)
    try:
        for K, sup, v in ((Kx, S, x), (Ky, T, y)):
            rhs = np.zeros(K.shape[0])
            rhs[-1] = 1.0
            v[sup] = np.linalg.solve(K, rhs)[:-1]
    except np.linalg.LinAlgError:
        return None
    if x.min() < -1e-12 or y.min() < -1e-12:
        return None
    x, y = np.maximum(x, 0.0), np.maximum(y, 0.0)
    x /= x.sum()
    y /= y.sum()
    return (x, y) if _core.games_check(A, B, x, y, tol, np.empty(3)) else None


def _random_game(rng, m, n, kind):
    if kind == 0:
        return rng.normal(size=(m, n)), rng.normal(size=(m, n))
    if kind == 1:  # integer payoffs: degenerate games
        return rng.integers(0, 3, (m, n)).astype(float), rng.integers(0, 3, (m, n)).astype(float)
    return rng.normal(size=(m, n)) * 1e4, rng.random((m, n)) * 1e-3  # scales far apart


@pytest.mark.parametrize("transpose", [False, True])
def test_game_basis_solves_against_numpy(transpose):
    """The blocks of equilibrium bases (the kernels' final ones) and of random vertex pairs:
    v = diag(x's block, y's block)^-1 rhs (or of its transpose) against numpy on the blocks
    built here; the point's support weights against numpy's solution, clipped and
    normalized."""
    rng = np.random.default_rng(31)
    solved = 0
    for t, A, B, bases in _game_cases(rng, 60, 12, 5):
        for xb, yb in bases:
            blocks = _game_blocks(A, B, xb, yb)
            k = 0 if blocks is None else blocks[2].shape[0] + blocks[3].shape[0]
            rhs = rng.normal(size=k)
            code, x, y, out, v = _core.game_basis(A, B, xb, yb, TOL, rhs if k else None, transpose)
            if blocks is None:
                assert code == 2 and x is None and y is None and out is None and v is None
                continue
            S, T, Kx, Ky = blocks
            if min(np.linalg.svd(K, compute_uv=False)[-1] for K in (Kx, Ky)) < 1e-8:
                continue  # (near singular: the LU's answer and numpy's far apart)
            assert code in (0, 1, 3)
            Kb = np.zeros((k, k))
            kx = Kx.shape[0]
            Kb[:kx, :kx], Kb[kx:, kx:] = Kx, Ky
            Ks = Kb.T if transpose else Kb
            if code == 3:  # a weight below -1e-12: numpy's solution has one too
                assert x is None and y is None and v is None
                e = np.zeros(k)
                e[kx - 1] = e[k - 1] = 1.0
                ref = np.linalg.solve(Kb, e)
                assert min(ref[: kx - 1].min(), ref[kx:-1].min()) < -1e-12 + 1e-9
                continue
            # (normwise: the transpose solve by the LU of the block is backward stable in norm,
            # not row by row)
            r = np.abs(Ks @ v - rhs).max()
            assert r <= 8 * (k + 1) * EPS * (np.abs(Ks).sum(axis=1).max() * np.abs(v).max() + np.abs(rhs).max())
            assert _close_to_numpy(Ks, v, rhs)
            for K, sup, got in ((Kx, S, x), (Ky, T, y)):
                e = np.zeros(K.shape[0])
                e[-1] = 1.0
                ref = np.maximum(np.linalg.solve(K, e)[:-1], 0.0)
                ref /= ref.sum()
                bound = 64 * K.shape[0] * EPS * np.linalg.cond(K, 1)
                assert np.max(np.abs(got[sup] - ref)) <= bound
                assert np.all(np.delete(got, sup) == 0.0) and not np.signbit(got).any()
            solved += code == 0
    assert solved >= 300


def test_game_basis_point_is_a_nash_equilibrium():
    """On every final basis of random nondegenerate games the point passes, and it is an
    equilibrium by the Nash check written here; whatever passes (random vertex pairs of
    degenerate games included) is one too, and the verdict out = (regret, payoffs) is the
    core's games::check's."""
    rng = np.random.default_rng(32)
    passed = 0
    for t in range(80):
        m, n = (int(v) for v in rng.integers(1, 16, 2))
        A, B = _random_game(rng, m, n, t % 3)
        for code_k, xb, yb in _final_bases(A, B):
            code, x, y, out, _ = _core.game_basis(A, B, xb, yb, TOL)
            if t % 3 != 1:
                assert code_k == int(lemke.Status.SOLVED) and code == 0
            if code == 0:
                _assert_nash(A, B, x, y)
                ref = np.empty(3)
                assert _core.games_check(A, B, x, y, TOL, ref) and ref.tobytes() == out.tobytes()
                # without tol: the same point, unchecked
                code2, x2, y2, out2, _ = _core.game_basis(A, B, list(xb), np.array(yb))
                assert code2 == 0 and out2 is None
                assert x2.tobytes() == x.tobytes() and y2.tobytes() == y.tobytes()
                passed += 1
    assert passed >= 800


def test_game_basis_verdicts_are_the_numpy_routines():
    """The re-solve's verdict (an equilibrium or None) through the seam is the numpy
    routine's it replaced on equilibrium bases, random vertex pairs and the bases of paths
    stopped early, of random and degenerate games; the points agree to rounding (their
    bits may differ: numpy's LAPACK and the kernels' LU round differently)."""
    from lemke import _games
    rng = np.random.default_rng(33)
    seen = {True: 0, False: 0}
    for t, A, B, bases in _game_cases(rng, 150, 10, 6, (1, 3)):
        m, n = A.shape
        for xb, yb in bases:
            old = _numpy_resolve(A, B, xb, yb, TOL)
            new = _games._resolve_float(A, B, _games.GameBasis(m, n, tuple(sorted(xb)), tuple(sorted(yb))), TOL)
            assert (old is None) == (new is None), (t, xb, yb)
            if new is not None:
                assert np.max(np.abs(new[0] - old[0])) <= 1e-12 and np.max(np.abs(new[1] - old[1])) <= 1e-12
            seen[new is not None] += 1
    assert seen[True] >= 500 and seen[False] >= 300


def test_game_basis_degenerate_and_refused():
    """Degenerate games: a repeated column (a singular block), a weight below -1e-12
    (refused: code 3), supports of unequal sizes, empty supports; bad labels and payoffs
    refused; the 36 x 39 game whose path ends UNCHECKED re-solved by the seam into an
    equilibrium, the answer solve_bimatrix gives."""
    from pathlib import Path
    from lemke import _games
    # a repeated column: y's block [A[I, T] -1; 1 0] with T = {0, 1} and A[:, 0] == A[:, 1]
    A = np.array([[1.0, 1.0], [0.0, 0.0]])
    B = np.array([[1.0, 0.0], [0.0, 1.0]])
    assert _core.game_basis(A, B, (0, 1), (2, 3), TOL)[0] == 2  # S = {0, 1}, T = {0, 1}
    assert _numpy_resolve(A, B, (0, 1), (2, 3), TOL) is None
    # unequal sizes, an empty support: no square block
    assert _core.game_basis(A, B, (0, 2), (2, 3), TOL)[0] == 2  # S = {0}, J = {0, 1}
    assert _core.game_basis(A, B, (2, 3), (0, 1), TOL)[0] == 2  # S and T empty
    # a weight below -1e-12: matching pennies' supports with one payoff flipped
    A = np.array([[1.0, -1.0], [-1.0, 1.0]])
    B = np.array([[-1.0, 1.0], [1.0, -1.0]])
    code, x, y, out, _ = _core.game_basis(A, B, (0, 1), (2, 3), TOL)
    assert code == 0
    _assert_nash(A, B, x, y)
    assert np.array_equal(x, [0.5, 0.5]) and np.array_equal(y, [0.5, 0.5])
    # x's block: x_0 (b00 - b01) = x_1 (b11 - b10) and x_0 + x_1 = 1
    Bp = np.array([[-1.0, 3.0], [1.0, -1.0]])  # x = (1/3, 2/3): an equilibrium
    Bn = np.array([[1.0, 0.0], [2.0, 0.0]])    # x = (2, -1): refused
    code, x, y, out, _ = _core.game_basis(A, Bp, (0, 1), (2, 3), TOL)
    assert code == 0 and np.allclose(x, [1 / 3, 2 / 3], rtol=0, atol=4 * EPS)
    _assert_nash(A, Bp, x, y)
    code, x, y, out, v = _core.game_basis(A, Bn, (0, 1), (2, 3), TOL, np.ones(6))
    assert code == 3 and x is None and y is None and out is None and v is None
    assert _numpy_resolve(A, Bn, (0, 1), (2, 3), TOL) is None
    # bad arguments
    with pytest.raises(ValueError):
        _core.game_basis(A, B, (0, 1, 2), (2, 3), TOL)  # n labels of P
    with pytest.raises(ValueError):
        _core.game_basis(A, B, (0, 4), (2, 3), TOL)  # a label out of [0, m + n)
    with pytest.raises(ValueError):
        _core.game_basis(A, B, (0, -1), (2, 3), TOL)
    with pytest.raises(ValueError):
        _core.game_basis(A, B, (0, 1), (2, 3), TOL, np.ones(5))  # rhs: 3 + 3 rows
    with pytest.raises(ValueError):
        _core.game_basis(A, B[:, :1], (0, 1), (2, 3), TOL)
    with pytest.raises(ValueError):
        _core.game_basis(np.zeros((0, 2)), np.zeros((0, 2)), (0, 1), (), TOL)
    An = A.copy()
    An[1, 1] = np.nan
    assert _core.game_basis(An, B, (0, 1), (2, 3), TOL)[0] == _core.GAMES_NOT_FINITE
    # repeated labels: no square block (a label in both polytopes, or twice in one)
    assert _core.game_basis(A, B, (0, 0), (2, 3), TOL)[0] == 2
    # the path that ends UNCHECKED (tests/data/games/): its basis re-solved
    d = np.load(Path(__file__).parent / "data" / "games" / "unchecked_36x39.npz")
    A, B, k = d["A"].astype(float), d["B"].astype(float), int(d["k"])
    code_k, xb, yb = list(_final_bases(A, B))[k]
    assert code_k == _core.GAMES_UNCHECKED
    code, x, y, out, _ = _core.game_basis(A, B, xb, yb, TOL)
    assert code == 0
    _assert_nash(A, B, x, y)
    assert _numpy_resolve(A, B, xb, yb, TOL) is not None
    res = lemke.solve_bimatrix(A, B, init_label=k)
    assert res.status == lemke.Status.SOLVED and res.restarts >= 1
    assert np.asarray(res.x).tobytes() == x.tobytes() and np.asarray(res.y).tobytes() == y.tobytes()
    assert res.regret == out[0] and res.payoffs == (out[1], out[2])
# --- the QP's KKT rows of an active set (KktBasis, _qp._polished's system) ----------------

def _old_polished_candidate(qp, basis, tol):
    """_qp._polished's candidate point as its numpy code made it before the seam (the
    reference of the seam's bits): ``(new, ok, res)``, or None when singular."""
    from lemke._npc import absmax
    from lemke._qp import _data, kkt
    from lemke._reductions.mlcp_lcp import refined_solve
    n, p, mg = qp.n, qp.A.shape[0], qp.G.shape[0]
    F, B, S, bound, K, rhs = kkt_blocks(qp, basis.z_basic)
    GS = qp.G[S]
    f, s = F.size, F.size + p + S.size
    out = refined_solve(K, rhs, steps=3, given=bound[B], low=True)
    if out is None:
        return None
    sol, lo = out
    x = np.empty(n)
    x[F] = sol[:f]
    x[B] = bound[B]
    exact_lo = np.zeros(n + s - f)
    exact_lo[F] = lo[:f]
    exact_lo[n:] = lo[f:]
    KB = np.concatenate([qp.P[B], qp.A[:, B].T, GS[:, B].T], axis=1)
    zb = np.empty(B.size)
    _core.residual2(np.concatenate([KB, KB], axis=1), np.concatenate([x, sol[f:], exact_lo]),
                    qp.q[B], zb)
    mult = np.concatenate([sol[f:], -zb])
    mult[np.abs(mult) <= EPS * absmax(mult)] = 0.0
    z = np.zeros(mg)
    z[S] = mult[p:p + S.size]
    z_box = np.zeros(n)
    z_box[B] = mult[p + S.size:]
    new = (x, mult[:p].copy(), z, z_box)
    ok, *res = kkt(_data(qp), *new, tol)
    return new, ok, res


def _old_polished(qp, point, basis, tol):
    """_qp._polished before the seam, whole."""
    from lemke._qp import _data, kkt
    cand = _old_polished_candidate(qp, basis, tol)
    if cand is None or not cand[1]:
        return point, None
    new, _, res = cand
    res0 = kkt(_data(qp), *point, tol)[1:]
    return (new, res) if max(res[:3]) < max(res0[:3]) else (point, res0)


def _kkt_call(qp, beta, tol=None, rhs=None, transpose=False):
    c = lemke._validate.c_aligned
    return _core.kkt_basis(c(qp.P), qp.q, c(qp.G), qp.h, c(qp.A), qp.b, qp.lb, qp.ub,
                           np.asarray(beta, dtype=np.int64), tol, rhs, transpose)


def _random_qp(n, p, m, rng, rank=None):
    """A QP with every kind of variable (free, lower, upper, boxed, fixed), p equalities
    and m inequalities, P positive semidefinite of rank `rank` (n when None), feasible at a
    point x0 inside the bounds."""
    from lemke._qp import _QP
    r = n if rank is None else rank
    L = rng.normal(size=(n, r))
    P = L @ L.T
    q = rng.normal(size=n)
    kinds = rng.integers(0, 5, size=n)
    x0 = rng.normal(size=n)
    lb = np.where(np.isin(kinds, (1, 3, 4)), x0 - rng.random(n), -np.inf)
    ub = np.where(np.isin(kinds, (2, 3)), x0 + rng.random(n), np.inf)
    lb[kinds == 4] = ub[kinds == 4] = x0[kinds == 4]
    A = rng.normal(size=(p, n))
    G = rng.normal(size=(m, n))
    h = G @ x0 + rng.random(m) * (rng.random(m) < 0.7)
    return _QP(P, q, G if m else None, h if m else None, A if p else None, A @ x0 if p else None,
               lb, ub)


_QP_SHAPES = [(1, 0, 1), (2, 1, 0), (3, 0, 3), (4, 1, 2), (5, 2, 6), (6, 0, 0), (8, 3, 5),
              (10, 2, 12), (12, 4, 4), (16, 0, 20)]


def _captured_polish_calls(problems):
    """(qp, point, basis, tol) of every _qp._polished call while the KKT-MLCP path solves
    the problems (the final bases polishing runs on)."""
    from lemke import _qp
    from lemke._options import as_options
    calls, orig = [], _qp._polished

    def capture(qp, point, basis, tol):
        calls.append((qp, tuple(a.copy() for a in point), basis, tol))
        return orig(qp, point, basis, tol)

    _qp._polished = capture
    try:
        for qp in problems:
            _qp._solve(qp, "tableau", as_options(None), None, certify=True)
    finally:
        _qp._polished = orig
    return calls


def _same_bits(a, b):
    return all(np.asarray(u).tobytes() == np.asarray(v).tobytes() for u, v in zip(a, b))


def test_kkt_basis_is_the_old_polish_bit_for_bit():
    """_qp._polished through the seam (KktBasis) against its former numpy code: the
    candidate point, its verdict and statistics, and _polished's choice, bit for bit, on the
    final bases the KKT-MLCP path polishes (random QPs of every variable kind, P definite
    and semidefinite, and the 61 Maros-Meszaros problems solve_qp solves, each solved by
    that path here), and on random
    bases of the random QPs (singular systems among them)."""
    import sys
    from pathlib import Path
    from lemke import _qp
    rng = np.random.default_rng(2611)
    problems = []
    for t in range(3):
        for n, p, m in _QP_SHAPES:
            problems.append(_random_qp(n, p, m, rng, rank=None if t == 0 else max(1, n // 2)))
    calls = _captured_polish_calls(problems)
    here = Path(__file__).resolve().parent
    sys.path.insert(0, str(here.parent / "benchmarks"))
    try:
        from maros_meszaros import load
    finally:
        sys.path.pop(0)
    mm = []
    for path in sorted((here / "data" / "maros-meszaros").glob("*.mat")):
        if path.stem != "VALUES":  # (its P indefinite as stored)
            (P, q, G, h, A, b, lb, ub), _ = load(path)
            mm.append(_qp._QP(*_qp.qpsolvers_form(P, q, G, h, A, b, lb, ub)[0]))
    mm_calls = _captured_polish_calls(mm)
    assert len(calls) >= 20 and len(mm_calls) == 61
    kept = compared = 0
    for qp, point, basis, tol in calls + mm_calls:
        old = _old_polished(qp, point, basis, tol)
        new = _qp._polished(qp, point, basis, tol)
        assert _same_bits(old[0], new[0])
        assert (old[1] is None) == (new[1] is None)
        if old[1] is not None:
            assert _same_bits(old[1], new[1]) and list(old[1]) == list(new[1])
        kept += old[0][0] is not point[0]
        cand = _old_polished_candidate(qp, basis, tol)
        code, got, stats, _ = _kkt_call(qp, basis.z_basic, tol)
        assert (cand is None) == (code == 2)
        if cand is not None:
            assert _same_bits(cand[0], got) and (code == 0) == cand[1]
            assert np.array(cand[2]).tobytes() == stats.tobytes()
            compared += 1
    assert kept >= 30 and compared >= 80
    # random bases of the random QPs (the singular ones reported by both)
    singular = 0
    for qp in problems:
        pairs = qp.shifted.size + qp.G.shape[0] + qp.boxed.size
        for prob in (0.0, 0.3, 0.6, 1.0):
            basis = lemke.WarmStart(pairs, tuple(np.flatnonzero(rng.random(pairs) < prob)))
            cand = _old_polished_candidate(qp, basis, TOL)
            code, got, stats, _ = _kkt_call(qp, basis.z_basic, TOL)
            assert (cand is None) == (code == 2)
            if cand is None:
                singular += 1
                assert got is None and stats is None
            else:
                assert _same_bits(cand[0], got) and (code == 0) == cand[1]
                assert np.array(cand[2]).tobytes() == stats.tobytes()
    assert singular >= 5


def _qp_stats(qp, x, y, z, zb):
    """(primal, dual, gap, obj) by qpsolvers' formulas, in numpy (the infinite bounds' terms
    left out of the gap)."""
    P, q, G, h, A, b, lb, ub = qp.P, qp.q, qp.G, qp.h, qp.A, qp.b, qp.lb, qp.ub
    viol = [np.abs(A @ x - b), np.maximum(G @ x - h, 0.0), np.maximum(lb - x, 0.0),
            np.maximum(x - ub, 0.0)]
    primal = max([0.0] + [float(v.max()) for v in viol if v.size])
    dual = float(np.abs(P @ x + q + A.T @ y + G.T @ z + zb).max(initial=0.0))
    lo, up = np.isfinite(lb), np.isfinite(ub)
    gap = abs(x @ P @ x + q @ x + b @ y + h @ z + lb[lo] @ np.minimum(zb[lo], 0.0)
              + ub[up] @ np.maximum(zb[up], 0.0))
    return primal, dual, gap, 0.5 * x @ P @ x + q @ x


@pytest.mark.parametrize("transpose", [False, True])
def test_kkt_solves_match_numpy_and_the_point_solves_its_rows(transpose):
    """The KKT basis system's solve and transpose solve against numpy.linalg.solve on the
    block K[:, :s] built here (rows F, A, G_S; columns x_F, y, z_S), and its point checked
    here: x_B at its bounds, z and zb zero off S and B, A x = b, G_S x = h_S and every
    stationarity row (F's from the solve, B's by zb) to a backward-error bound, the
    statistics qpsolvers' formulas, and the verdict against the KKT conditions computed
    here (a point far from them fails it)."""
    from helpers import assert_qp_kkt
    rng = np.random.default_rng(91 + transpose)
    checked = singular = passed = failed = 0
    for n, p, m in _QP_SHAPES:
        for t in range(12):
            qp = _random_qp(n, p, m, rng)
            pairs = qp.shifted.size + qp.G.shape[0] + qp.boxed.size
            basis = tuple(np.flatnonzero(rng.random(pairs) < t / 11))
            F, B, S, bound, K, rhs0 = kkt_blocks(qp, basis)
            s = rhs0.size
            rhs = rng.normal(size=s)
            code, point, stats, sol = _kkt_call(qp, basis, TOL, rhs, transpose)
            if code == 2:
                singular += 1
                assert point is None and stats is None and sol is None
                continue
            Ks = K[:, :s]
            if s and np.linalg.cond(Ks) > 1e10:
                continue  # (singular to rounding: no bound to hold the solves to)
            checked += 1
            x, y, z, zb = point
            Kt = Ks.T if transpose else Ks
            if s:  # (normwise: a KKT block's zeros leave LU no row-wise bound)
                size = np.abs(Kt).sum(1).max() * np.abs(sol).max() + np.abs(rhs).max()
                assert np.abs(Kt @ sol - rhs).max() <= 8 * (s + 1) * EPS * size
                assert _close_to_numpy(Kt, sol, rhs)
            else:
                assert sol.shape == (0,)
            assert x[B].tobytes() == bound[B].tobytes()
            off_S = np.setdiff1d(np.arange(qp.G.shape[0]), S)
            assert np.all(z[off_S] == 0.0) and np.all(zb[F] == 0.0)
            # the rows: K (x_F, y, z_S, x_B) = rhs0, and B's stationarity rows with zb
            u = np.concatenate([x[F], y, z[S], x[B]])
            scale = np.abs(K) @ np.abs(u) + np.abs(rhs0)  # (refined: row-wise backward error)
            assert np.all(np.abs(K @ u - rhs0) <= 8 * (s + 1) * EPS * scale)
            g = qp.P @ x + qp.q + qp.A.T @ y + qp.G.T @ z
            mult = np.abs(np.concatenate([y, z, zb])).max(initial=0.0)
            size = np.abs(qp.P[B]) @ np.abs(x) + np.abs(qp.q[B]) + mult * (
                np.abs(qp.A[:, B]).sum(0) + np.abs(qp.G[:, B]).sum(0) + 1.0)
            assert np.all(np.abs(g[B] + zb[B]) <= 64 * (n + 1) * EPS * size)
            # the statistics, and the verdict
            ref = _qp_stats(qp, x, y, z, zb)
            big = max(1.0, np.abs(x).max(initial=0.0), mult) ** 2 * max(
                [1.0] + [np.abs(a).max() for a in (qp.P, qp.q, qp.A, qp.b, qp.G, qp.h) if a.size])
            assert np.allclose(stats, ref, rtol=1e-9, atol=1e-12 * big)
            if code == 0:
                passed += 1
                res = type("R", (), dict(x=x, y=y, z=z, z_box=zb, obj=stats[3]))
                assert_qp_kkt(qp.P, qp.q, qp.G, qp.h, qp.A, qp.b, qp.lb, qp.ub, res, rtol=1e-7)
            else:  # fails: a condition the point breaks beyond the check's tolerance
                fixed = qp.lb[B] == qp.ub[B]
                at_lo, at_up = (bound[B] == qp.lb[B]) & ~fixed, (bound[B] == qp.ub[B]) & ~fixed
                assert (max(ref[:3]) > 1e-9 * big or np.any(z < 0) or np.any(zb[B][at_lo] > 0)
                        or np.any(zb[B][at_up] < 0))
                failed += 1
    assert checked >= 40 and singular >= 10 and passed >= 5 and failed >= 30


def test_kkt_basis_final_bases_pass_and_bad_input_refused():
    """The final bases of the random QPs: the seam's point passes its check where
    _polished keeps it (and the tests' own KKT check there); bad arguments refused."""
    from helpers import assert_qp_kkt
    rng = np.random.default_rng(12)
    problems = [_random_qp(n, p, m, rng) for n, p, m in _QP_SHAPES]
    passed = 0
    for qp, point, basis, tol in _captured_polish_calls(problems):
        code, new, stats, _ = _kkt_call(qp, basis.z_basic, tol)
        if code == 0:
            passed += 1
            res = type("R", (), dict(x=new[0], y=new[1], z=new[2], z_box=new[3], obj=stats[3]))
            assert_qp_kkt(qp.P, qp.q, qp.G, qp.h, qp.A, qp.b, qp.lb, qp.ub, res, rtol=1e-8)
        # without tol: the same point, no verdict
        code2, new2, stats2, _ = _kkt_call(qp, basis.z_basic)
        assert stats2 is None and (code2 == 2) == (code == 2)
        if code != 2:
            assert code2 == 0 and _same_bits(new, new2)
    assert passed >= 7
    qp = problems[4]
    pairs = qp.shifted.size + qp.G.shape[0] + qp.boxed.size
    c = lemke._validate.c_aligned
    args = [c(qp.P), qp.q, c(qp.G), qp.h, c(qp.A), qp.b, qp.lb, qp.ub]
    for bad in ([pairs], [-1], [0, 0]):
        with pytest.raises(ValueError):
            _core.kkt_basis(*args, np.array(bad, np.int64))
    with pytest.raises(ValueError):  # P not n x n
        _core.kkt_basis(c(qp.P[:, :-1]), *args[1:], np.zeros(0, np.int64))
    with pytest.raises(ValueError):  # rhs of the wrong length
        s = kkt_blocks(qp, ())[5].size
        _core.kkt_basis(*args, np.zeros(0, np.int64), TOL, np.ones(s + 1))
# --- the QP kind (qp.cpp's QpBasis, _core.qp_basis) -----------------------------------------

def _random_qp_seam(n, p0, m0, rng, bounds=False, fixed=0):
    """A strictly convex QP (P = B B'/n + I/10) with p0 equalities and m0 inequalities that a
    random x0 satisfies (slack uniform in [0, 1]); with bounds, about a third of the
    variables bounded below, a third above (x0 inside), and `fixed` variables fixed at x0."""
    B = rng.normal(size=(n, n))
    P = B @ B.T / n + 0.1 * np.eye(n)
    x0 = rng.normal(size=n)
    A = rng.normal(size=(p0, n))
    G = rng.normal(size=(m0, n))
    lb, ub = np.full(n, -np.inf), np.full(n, np.inf)
    if bounds:
        u = rng.random(n)
        lb[u < 1 / 3] = x0[u < 1 / 3] - rng.random(int((u < 1 / 3).sum()))
        ub[u > 2 / 3] = x0[u > 2 / 3] + rng.random(int((u > 2 / 3).sum()))
        for j in rng.choice(n, size=fixed, replace=False):
            lb[j] = ub[j] = x0[j]
    return (P, 3 * rng.normal(size=n), G, G @ x0 + rng.random(m0), A, A @ x0, lb, ub)


def _qp_rows(G, h, A, lb, ub):
    """The KKT system's rows as the kernel numbers them (rows_of), built here: E (A, then a
    fixed variable's unit row) and C (G's rows with h finite, then x_j <= ub_j for the
    variables not fixed, then -x_j <= -lb_j)."""
    n = lb.size
    eye = np.eye(n)
    fixed = lb == ub
    E = np.vstack([A] + [eye[j][None] for j in np.flatnonzero(fixed)]).reshape(-1, n)
    C = np.vstack([G[np.isfinite(h)]] + [eye[j][None] for j in np.flatnonzero(~fixed & (ub < np.inf))]
                  + [-eye[j][None] for j in np.flatnonzero(~fixed & (lb > -np.inf))]).reshape(-1, n)
    return E, C


def _qp_kkt_matrix(P, E, CS):
    """K = [[P, E', C_S'], [E, 0, 0], [C_S, 0, 0]], built here."""
    n, p, k = P.shape[0], E.shape[0], CS.shape[0]
    K = np.zeros((n + p + k, n + p + k))
    K[:n, :n] = P
    K[:n, n:n + p] = E.T
    K[:n, n + p:] = CS.T
    K[n:n + p, :n] = E
    K[n + p:, :n] = CS
    return K


def _qp_kkt_ok(P, q, G, h, A, b, lb, ub, x, y, z, zb, tol=1e-9):
    """An independent KKT check (qpsolvers' convention P x + q + A'y + G'z + z_box = 0):
    each condition to tol relative to its terms' sizes."""
    big = np.abs(P) @ np.abs(x) + np.abs(q) + np.abs(A.T) @ np.abs(y) + np.abs(G.T) @ np.abs(z) + np.abs(zb) + 1.0
    stat = np.abs(P @ x + q + A.T @ y + G.T @ z + zb) <= tol * big
    gx = G @ x
    gsize = np.abs(G) @ np.abs(x) + np.abs(h) + 1.0
    primal = (np.all(np.abs(A @ x - b) <= tol * (np.abs(A) @ np.abs(x) + np.abs(b) + 1.0))
              and np.all(gx - h <= tol * gsize) and np.all(x >= lb - tol * (np.abs(lb) + 1.0))
              and np.all(x <= ub + tol * (np.abs(ub) + 1.0)))
    dual = (np.all(z >= 0) and np.all(zb[np.isneginf(lb)] >= 0) and np.all(zb[np.isposinf(ub)] <= 0))
    comp = np.all(np.abs(z * (h - gx)) <= tol * gsize * (np.abs(z) + 1.0))
    return bool(np.all(stat) and primal and dual and comp)


@pytest.mark.parametrize("transpose", [False, True])
def test_qp_solves_match_numpy_on_random_sets(transpose):
    """solve on random active sets of random QPs (equalities, inequalities, bounds, fixed
    variables) against numpy.linalg.solve on K built here; K is symmetric (so solve_transpose
    is solve: the same bits) and both match numpy's K' solve."""
    rng = np.random.default_rng(31)
    done = 0
    for t in range(60):
        n = int(rng.integers(2, 30))
        p0 = int(rng.integers(0, n // 2 + 1))
        m0 = int(rng.integers(0, 2 * n))
        data = _random_qp_seam(n, p0, m0, rng, bounds=t % 2 == 1, fixed=int(t % 4 == 3 and n > p0 + 1))
        P, q, G, h, A, b, lb, ub = data
        E, C = _qp_rows(G, h, A, lb, ub)
        p, m = E.shape[0], C.shape[0]
        active = np.zeros(m, dtype=bool)
        k = int(rng.integers(0, max(min(m, n - p), 0) + 1))
        active[rng.choice(m, size=k, replace=False)] = True
        K = _qp_kkt_matrix(P, E, C[active])
        assert np.array_equal(K, K.T)
        rhs = rng.normal(size=n + p + k)
        got = _core.qp_basis(*data, active, TOL, rhs=rhs, transpose=transpose)
        assert got[0] in (0, 1)
        sol = got[6]
        ref = np.linalg.solve(K.T if transpose else K, rhs)
        assert np.allclose(sol, ref, rtol=1e-7, atol=1e-7 * np.abs(ref).max())
        assert np.max(np.abs(K @ sol - rhs)) <= 1e-9 * (np.abs(K).max() * np.abs(sol).max() + np.abs(rhs).max())
        other = _core.qp_basis(*data, active, TOL, rhs=rhs, transpose=not transpose)[6]
        assert other.tobytes() == sol.tobytes()
        done += 1
    assert done == 60


def test_qp_point_against_kkt_conditions():
    """The refined point of the optimal active set passes the kernel's check (code 0) and a
    KKT check written here; the point of a set that misses an active row (the empty set
    where the unconstrained minimizer is infeasible) fails both."""
    rng = np.random.default_rng(32)
    seen = failed = 0
    for t in range(40):
        n = int(rng.integers(2, 25))
        data = _random_qp_seam(n, int(rng.integers(0, n // 3 + 1)), int(rng.integers(1, 2 * n)), rng,
                          bounds=t % 2 == 1)
        P, q, G, h, A, b, lb, ub = data
        r = lemke.solve_qp(*data)
        if r.status != lemke.Status.SOLVED:
            continue
        E, C = _qp_rows(G, h, A, lb, ub)
        fixed = lb == ub
        # the active set: rows of G with z > 0, the bounds with z_box of their sign
        zbs = np.asarray(r.z_box)
        active = np.concatenate([np.asarray(r.z)[np.isfinite(h)] > 0,
                                 zbs[~fixed & (ub < np.inf)] > 0, zbs[~fixed & (lb > -np.inf)] < 0])
        code, x, y, z, zb, stats, _ = _core.qp_basis(*data, active, TOL)
        assert code == 0
        assert _qp_kkt_ok(*data, x, y, z, zb)
        assert np.allclose(x, r.x, rtol=1e-8, atol=1e-8 * (1 + np.abs(r.x).max()))
        seen += 1
        if active.any():
            code, x, y, z, zb, stats, _ = _core.qp_basis(*data, np.zeros_like(active), TOL)
            if code == 1:  # (the set's point is a KKT point only by chance)
                assert not _qp_kkt_ok(*data, x, y, z, zb)
                failed += 1
    assert seen >= 35 and failed >= 25


def test_qp_warm_point_is_the_seams_bit_for_bit():
    """A warm solve_qp whose old active set solves the new q (0 pivots: warm_point's point
    of the set, QpBasis::point_given on the LCP's z) answers the seam's point of that set and
    z, bit for bit (x, y, z); the factored path (m0 >= 4n: gram, QpBasis::point refined
    twice) answers the seam's refined point of its final set bit for bit."""
    rng = np.random.default_rng(33)
    hits = grams = 0
    for t in range(40):
        n = int(rng.integers(3, 25))
        data = _random_qp_seam(n, int(rng.integers(0, n // 3 + 1)), int(rng.integers(1, 2 * n)), rng)
        P, q, G, h, A, b, lb, ub = data
        r = lemke.solve_qp(*data)
        if r.status != lemke.Status.SOLVED:
            continue
        for s in range(3):
            q2 = q + 1e-7 * rng.normal(size=n)
            rw = lemke.solve_qp(P, q2, G, h, A, b, lb, ub, warm_start=r.warm_start)
            if rw.status != lemke.Status.SOLVED or rw.pivots != 0:
                continue
            active = np.zeros(G.shape[0], dtype=bool)
            active[np.asarray(rw.warm_start.z_basic, dtype=np.int64)] = True
            code, x, y, z, zb, stats, _ = _core.qp_basis(P, q2, G, h, A, b, lb, ub, active, TOL,
                                                         z=np.asarray(rw.z))
            assert code == 0
            assert x.tobytes() == np.asarray(rw.x).tobytes()
            assert y.tobytes() == np.asarray(rw.y).tobytes()
            assert z.tobytes() == np.asarray(rw.z).tobytes()
            hits += 1
        m0 = 4 * n + int(rng.integers(0, n))
        dg = _random_qp_seam(n, int(rng.integers(0, n // 3 + 1)), m0, rng)
        _core.qp_front_codes()
        rg = lemke.solve_qp(*dg)
        if rg.status != lemke.Status.SOLVED or _core.qp_front_codes() != [("solve_gram", 0)]:
            continue
        active = np.zeros(m0, dtype=bool)
        active[np.asarray(rg.warm_start.z_basic, dtype=np.int64)] = True
        code, x, y, z, zb, stats, _ = _core.qp_basis(*dg, active, TOL)
        assert code == 0
        assert x.tobytes() == np.asarray(rg.x).tobytes()
        assert z.tobytes() == np.asarray(rg.z).tobytes()
        grams += 1
    assert hits >= 100 and grams >= 35


def test_qp_refused_sets_and_bad_arguments():
    """More active rows than free directions, or dependent ones (a row twice), are refused
    (code 2, no point); a P not definite is the kernel's NOT_DEFINITE; flags, z or rhs of
    the wrong length raise ValueError, flags of another dtype TypeError."""
    rng = np.random.default_rng(34)
    data = _random_qp_seam(6, 2, 8, rng)
    P, q, G, h, A, b, lb, ub = data
    code, x, *_ = _core.qp_basis(*data, np.ones(8, dtype=bool), TOL)
    assert code == 2 and x is None
    G2 = G.copy()
    G2[1] = G2[0]
    active = np.zeros(8, dtype=np.uint8)
    active[:2] = 1
    assert _core.qp_basis(P, q, G2, h, A, b, lb, ub, active, TOL)[0] == 2
    assert _core.qp_basis(-P, q, G, h, A, b, lb, ub, active, TOL)[0] == _core.QP_NOT_DEFINITE
    with pytest.raises(ValueError):
        _core.qp_basis(*data, np.zeros(7, dtype=bool), TOL)
    with pytest.raises(ValueError):
        _core.qp_basis(*data, active, TOL, z=np.zeros(7))
    with pytest.raises(ValueError):
        _core.qp_basis(*data, active, TOL, rhs=np.zeros(6 + 2 + 3))
    with pytest.raises(TypeError):
        _core.qp_basis(*data, active.astype(np.int64), TOL)
