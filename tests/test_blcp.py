"""Box LCPs (lemke.solve_blcp): Siconos relay files, a seeded family checked on the caller's
data by an independent check and against the 2n reformulation, bad input, warm starts and
the friction index."""
from pathlib import Path

from collections import Counter

import numpy as np
import pytest

import lemke
from lemke._blcp import is_box_ray

RELAY = Path(__file__).parent / "data" / "siconos" / "relay"


def assert_box_solution(M, q, lo, hi, z, rtol=1e-8):
    """Plain-numpy check (not lemke's): lo <= z <= hi and w = Mz + q with w_i >= 0 off hi,
    w_i <= 0 off lo, each row against its own size s_i = |M_i.||z| + |q_i| (plus the
    rounding of q's largest entry); a z_i counts as at a bound when moving it there changes
    no row by more than that row's tolerance."""
    M, q, lo, hi, z = (np.asarray(a, dtype=float) for a in (M, q, lo, hi, z))
    assert np.all(np.isfinite(z))
    w = M @ z + q
    # Each row's size, plus the rounding of q's largest entry (a row whose terms are all
    # rounding noise, as an idle contact's friction row, is held to that).
    s = np.abs(M) @ np.abs(z) + np.abs(q) + 10 * q.size * np.finfo(float).eps * np.abs(q).max(initial=0) / rtol + 1e-300
    slack = np.array([np.min(rtol * s[M[:, j] != 0] / np.abs(M[M[:, j] != 0, j]), initial=np.inf)
                      for j in range(q.size)])
    assert np.all(z >= lo - slack) and np.all(z <= hi + slack), "z is outside its box"
    off_lo = (z - lo) > slack
    off_hi = (hi - z) > slack
    fixed = lo == hi
    bad_hi = off_lo & (w > rtol * s) & ~fixed
    bad_lo = off_hi & (w < -rtol * s) & ~fixed
    assert not bad_hi.any(), f"w > 0 off the lower bound in rows {np.flatnonzero(bad_hi)[:5]}"
    assert not bad_lo.any(), f"w < 0 off the upper bound in rows {np.flatnonzero(bad_lo)[:5]}"


def read_relay(path):
    """A Siconos relay file (tests/data/siconos/README.md): n, a dense column-major
    NumericsMatrix block, q, lb, ub."""
    tok = Path(path).read_text().split()
    n = int(tok[0])
    assert int(tok[1]) == 0, "dense storage only"
    vals = [float(t) for t in tok[6:6 + n * n + 3 * n]]
    M = np.array(vals[: n * n]).reshape(n, n, order="F")
    q, lo, hi = (np.array(vals[n * n + k * n: n * n + (k + 1) * n]) for k in range(3))
    return M, q, lo, hi


def reformulated(M, q, lo, hi):
    """The 2n LCP of a box LCP with finite bounds: z = lo + x, x >= 0 complementary to
    M x + v + q + M lo >= 0, v >= 0 complementary to hi - lo - x >= 0."""
    n = q.size
    Mp = np.block([[M, np.eye(n)], [-np.eye(n), np.zeros((n, n))]])
    qp = np.concatenate([q + M @ lo, hi - lo])
    return Mp, qp


@pytest.mark.parametrize("name", sorted(p.name for p in RELAY.glob("*.dat")))
def test_siconos_relay(name):
    M, q, lo, hi = read_relay(RELAY / name)
    r = lemke.solve_blcp(M, q, lo, hi)
    assert r.status == lemke.Status.SOLVED, r
    assert_box_solution(M, q, lo, hi, r.z)
    ref = lemke.solve_lcp(*reformulated(M, q, lo, hi))
    assert ref.success
    z_ref = lo + ref.z[: q.size]
    # Symmetric positive definite M in every file: the solution is unique.
    assert np.allclose(r.z, z_ref, rtol=1e-6, atol=1e-6 * np.abs(hi - lo).max())


def test_relay_known_answers():
    M, q, lo, hi = read_relay(RELAY / "relay_2x2.dat")
    assert np.allclose(lemke.solve_blcp(M, q, lo, hi).z, [0.5, -0.5])
    M, q, lo, hi = read_relay(RELAY / "relay_4x4.dat")
    assert np.allclose(lemke.solve_blcp(M, q, lo, hi).z, [1.0, 0.5, -0.5, -1.0])


def family(seed):
    """One seeded box LCP: symmetric PSD M (sometimes rank-deficient, sometimes integer with
    ties), bounds mixing finite, -inf, +inf and fixed entries."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 14))
    kind = seed % 4
    if kind == 0:  # positive definite
        A = rng.standard_normal((n, n))
        M = A @ A.T + 0.1 * np.eye(n)
    elif kind == 1:  # rank-deficient PSD
        A = rng.standard_normal((n, max(1, n // 2)))
        M = A @ A.T
    elif kind == 2:  # integer data, ties in q and in the ratios
        A = rng.integers(-2, 3, (n, n)).astype(float)
        M = A @ A.T + np.eye(n)
    else:  # PSD plus skew part (monotone, non-symmetric)
        A = rng.standard_normal((n, n))
        B = rng.standard_normal((n, n))
        M = A @ A.T + (B - B.T)
    q = rng.integers(-3, 4, n).astype(float) if kind == 2 else 3 * rng.standard_normal(n)
    lo = np.where(rng.random(n) < 0.5, -rng.integers(0, 3, n).astype(float), -rng.random(n))
    hi = np.where(rng.random(n) < 0.5, rng.integers(0, 3, n).astype(float), rng.random(n))
    finite = seed % 3 != 0
    if not finite:
        lo = np.where(rng.random(n) < 0.3, -np.inf, lo)
        hi = np.where(rng.random(n) < 0.3, np.inf, hi)
    fix = rng.random(n) < 0.1
    hi = np.where(fix & np.isfinite(lo), lo, hi)
    return M, q, lo, hi


def test_seeded_family():
    solved = rays = 0
    for seed in range(240):
        M, q, lo, hi = family(seed)
        r = lemke.solve_blcp(M, q, lo, hi)
        if r.status == lemke.Status.SOLVED:
            solved += 1
            assert_box_solution(M, q, lo, hi, r.z)  # 0 false successes
            assert np.allclose(r.w, M @ r.z + q)
            mid = np.clip(r.z - r.w, lo, hi)
            assert r.residual == pytest.approx(np.abs(r.z - mid).max(), abs=1e-12)
            if np.all(np.isfinite(lo) & np.isfinite(hi)):
                ref = lemke.solve_lcp(*reformulated(M, q, lo, hi))
                assert ref.success
                z_ref = lo + ref.z[: q.size]
                # w is unique on a monotone problem; z too when M is definite.
                scale = 1 + np.abs(M).max() * np.abs(z_ref).max() + np.abs(q).max()
                assert np.allclose(M @ r.z + q, M @ z_ref + q, atol=1e-7 * scale), seed
        else:
            # Only unbounded boxes may lack a solution; the ray is checked independently.
            assert r.status == lemke.Status.RAY_TERMINATION, (seed, r)
            assert not np.all(np.isfinite(lo) & np.isfinite(hi))
            assert is_box_ray(M, q, lo, hi, r.covering, r.z, r.z0, r.ray)
            rays += 1
            # Clipping the infinite bounds far away: the answer runs to the clip.
            big = 1e5
            r2 = lemke.solve_blcp(M, q, np.maximum(lo, -big), np.minimum(hi, big))
            assert r2.success and np.abs(r2.z).max() >= big / 10
    assert solved >= 200


def test_degenerate_ties():
    n = 8
    M = np.eye(n) + np.ones((n, n))
    q = -np.ones(n)
    for lo, hi in ((np.zeros(n), np.ones(n)), (-np.ones(n), np.zeros(n) + 0.1), (np.zeros(n), np.full(n, 1 / 9))):
        r = lemke.solve_blcp(M, q, lo, hi)
        assert r.success
        assert_box_solution(M, q, lo, hi, r.z)
    M = np.zeros((3, 3))
    r = lemke.solve_blcp(M, [1.0, -1.0, 0.0], [-1, -1, -1], [1, 1, 1])
    assert r.success and np.allclose(r.z, [-1, 1, r.z[2]])


def test_lcp_is_a_box_lcp():
    rng = np.random.default_rng(3)
    A = rng.standard_normal((10, 10))
    M = A @ A.T + np.eye(10)
    q = rng.standard_normal(10)
    r = lemke.solve_blcp(M, q, np.zeros(10), np.full(10, np.inf))
    ref = lemke.solve_lcp(M, q)
    assert r.success and np.allclose(r.z, ref.z)
    assert r.pivots == ref.pivots


def test_free_and_fixed_variables():
    M = np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]])
    q = np.array([-1.0, 3.0, -2.0])
    lo = np.array([-np.inf, 0.5, 0.0])
    hi = np.array([np.inf, 0.5, np.inf])
    r = lemke.solve_blcp(M, q, lo, hi)
    assert r.success
    assert r.z[1] == 0.5
    assert_box_solution(M, q, lo, hi, r.z)
    assert abs(r.w[0]) < 1e-12


def test_scalar_bounds_and_infeasible():
    r = lemke.solve_blcp([[1.0]], [-2.0], 0.0, 1.0)
    assert r.success and r.z.tolist() == [1.0]
    # -z + q with z >= 0: w = -z - 1 < 0 wherever z >= 0 -- no solution, and a checked ray.
    r = lemke.solve_blcp([[0.0, 0.0], [0.0, 0.0]], [-1.0, 1.0], 0.0, np.inf)
    assert r.status == lemke.Status.RAY_TERMINATION
    assert r.ray is not None and np.all(np.isfinite(r.z))
    assert is_box_ray(np.zeros((2, 2)), np.array([-1.0, 1.0]), np.zeros(2), np.full(2, np.inf),
                      r.covering, r.z, r.z0, r.ray)


@pytest.mark.parametrize("args, match", [
    (([[1.0]], [0.0], [1.0], [0.0]), r"lo\[0\] = 1.0 > hi\[0\] = 0.0"),
    (([[1.0]], [0.0], [np.nan], [0.0]), r"lo has a NaN"),
    (([[1.0]], [0.0], [0.0], [np.nan]), r"hi has a NaN"),
    (([[1.0]], [0.0], [np.inf], [np.inf]), r"lo has a NaN or \+inf"),
    (([[1.0]], [0.0], [-np.inf], [-np.inf]), r"hi has a NaN or -inf"),
    (([[1.0]], [np.nan], [0.0], [1.0]), r"q has a NaN"),
    (([[1.0, 0], [0, 1]], [0.0, 0], [0.0], [1.0]), r"lo must be a scalar or have shape"),
])
def test_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        lemke.solve_blcp(*args)
    # the same through the fast path (float64 arrays)
    a = [np.asarray(x, dtype=float) for x in args]
    with pytest.raises(ValueError, match=match):
        lemke.solve_blcp(*a)


@pytest.mark.parametrize("findex, lo, hi, match", [
    ([-1, 2], [0, -1], [np.inf, 1], r"findex\[1\] = 2 is out of range"),
    ([-1, 1], [0, -1], [np.inf, 1], r"findex\[1\] = 1 points at its own row"),
    ([1, 0], [-1, -1], [1, 1], r"findex\[0\] = 1 points at another friction row"),
    ([-1, 0], [0, 1], [np.inf, -1], r"mu = hi\[1\] = -1.0 < 0"),
    ([-1, 0], [0, -np.nan], [np.inf, np.nan], r"NaN"),
    ([-1, 0], [0, -0.5], [np.inf, 1.0], r"lo\[1\] = -0.5 must be -mu"),
    ([-1, 0], [-1, -1], [np.inf, 1.0], r"lo\[0\] = -1.0 must be >= 0"),
    ([-1, 0.5], [0, -1], [np.inf, 1.0], r"findex must hold integers"),
])
def test_bad_findex(findex, lo, hi, match):
    with pytest.raises(ValueError, match=match):
        lemke.solve_blcp(np.eye(2), [0.0, 0.0], lo, hi, findex=findex)


def test_warm_start():
    rng = np.random.default_rng(7)
    n = 30
    A = rng.standard_normal((n, n))
    M = A @ A.T / n + np.eye(n)
    q = rng.standard_normal(n)
    lo, hi = -np.ones(n) * 0.3, np.ones(n) * 0.3
    hi[::5] = np.inf
    r = lemke.solve_blcp(M, q, lo, hi)
    assert r.success and r.pivots > 0
    same = lemke.solve_blcp(M, q, lo, hi, warm_start=r.warm_start)
    assert same.success and same.pivots == 0 and np.allclose(same.z, r.z)
    q2 = q + 0.05 * rng.standard_normal(n)
    cold = lemke.solve_blcp(M, q2, lo, hi)
    warm = lemke.solve_blcp(M, q2, lo, hi, warm_start=r.warm_start)
    assert warm.success and cold.success
    assert_box_solution(M, q2, lo, hi, warm.z)
    assert np.allclose(warm.z, cold.z, atol=1e-9)
    assert warm.pivots < cold.pivots
    # a bad warm start still ends solved (cold)
    bad = lemke.BoxWarmStart(n, tuple(range(n)), ())
    r3 = lemke.solve_blcp(M, q2, lo, hi, warm_start=bad)
    assert r3.success and np.allclose(r3.z, cold.z, atol=1e-9)
    with pytest.raises(ValueError, match="size"):
        lemke.solve_blcp(M, q2, lo, hi, warm_start=lemke.BoxWarmStart(3, (), ()))
    with pytest.raises(TypeError):
        lemke.solve_blcp(M, q2, lo, hi, warm_start=r)


def contacts(seed, k):
    """k 2-D contacts (normal and tangent rows), Delassus M = J W J' + eps I, findex."""
    rng = np.random.default_rng(seed)
    nb = max(1, k // 2)
    J = rng.standard_normal((2 * k, 3 * nb))
    M = J @ J.T + 1e-6 * np.eye(2 * k)
    q = rng.standard_normal(2 * k)
    mu = rng.uniform(0.0, 1.0, k)
    lo = np.zeros(2 * k)
    hi = np.full(2 * k, np.inf)
    findex = -np.ones(2 * k, dtype=int)
    for c in range(k):
        findex[2 * c + 1] = 2 * c
        lo[2 * c + 1], hi[2 * c + 1] = -mu[c], mu[c]
    return M, q, lo, hi, findex, mu


def test_friction_index_coupled():
    for seed in range(40):
        k = 1 + seed % 6
        M, q, lo, hi, findex, mu = contacts(seed, k)
        r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
        assert r.status == lemke.Status.SOLVED, (seed, r)
        z, w = r.z, M @ r.z + q
        zn, zt = z[0::2], z[1::2]
        lo_c, hi_c = lo.copy(), hi.copy()
        lo_c[1::2], hi_c[1::2] = -mu * zn, mu * zn
        assert np.allclose(r.lo, lo_c) and np.allclose(r.hi, hi_c)
        assert_box_solution(M, q, lo_c, hi_c, z, rtol=1e-7)
        assert np.all(np.abs(zt) <= mu * zn * (1 + 1e-9) + 1e-12)


def test_friction_stick_and_slide():
    # One contact: a unit mass, normal and tangent rows decoupled; q = -v (desired change).
    M = np.eye(2)
    for vt, mu, slides in ((0.3, 0.5, False), (2.0, 0.5, True)):
        q = np.array([-1.0, -vt])  # pressed with 1, pushed sideways by vt
        r = lemke.solve_blcp(M, q, [0.0, -mu], [np.inf, mu], findex=[-1, 0])
        assert r.success
        assert r.z[0] == pytest.approx(1.0)
        assert r.z[1] == pytest.approx(mu if slides else vt)
        assert (r.w[1] < 0) == slides


def test_friction_warm_start():
    M, q, lo, hi, findex, mu = contacts(5, 6)
    r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
    again = lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=r.warm_start)
    assert again.success and again.pivots == 0 and np.allclose(again.z, r.z, atol=1e-9)


def assert_friction_solution(M, q, lo, hi, findex, z, rtol=1e-7):
    """Plain-numpy check of a friction-index answer (not lemke's): the normal impulses of
    the friction rows are >= 0, |z_i| <= mu_i z_f, and z solves the box LCP whose friction
    rows have the bounds in force -mu_i z_f, mu_i z_f (``assert_box_solution``)."""
    M, q, lo, hi, z = (np.asarray(a, dtype=float) for a in (M, q, lo, hi, z))
    findex = np.asarray(findex)
    F = np.flatnonzero(findex >= 0)
    mu, zf = hi[F], z[findex[F]]
    assert np.all(zf >= 0), "a normal impulse is negative"
    assert np.all(np.abs(z[F]) <= mu * zf * (1 + 1e-9) + 1e-12), "outside the friction cone"
    lo_c, hi_c = lo.copy(), hi.copy()
    lo_c[F], hi_c[F] = -mu * zf, mu * zf
    assert_box_solution(M, q, lo_c, hi_c, z, rtol=rtol)


def test_a_warm_friction_basis_is_judged_on_the_callers_rows():
    """A warm basis whose point solves the caller's problem but not the extended one's
    own check (a sticking friction row with z_i < 0 given as β+ basic, β+ = z_i < 0, where
    the solver's own basis has β- basic) is accepted with 0 pivots: the check on the
    caller's rows with the coupled bounds decides, as it decides every answer.  Checked
    here: the extended check does refuse that point, the answer passes the plain-numpy
    friction check and equals the cold answer, and the general path (lists) and
    solve_blcp_many give the same bits."""
    from lemke import _blcp
    from lemke._options import _DEFAULT
    cboxed = _blcp.boxed
    found = 0
    for seed in range(120):
        M, q, lo, hi, fi, mu = contacts(seed, 1 + seed % 6)
        fi = fi.astype(np.int64)
        r = lemke.solve_blcp(M, q, lo, hi, findex=fi)
        assert r.success
        codes = r.warm_start.row_states().copy()
        flip = (codes == 3 + 3 * 2) & (np.asarray(r.z) < -1e-6 * np.abs(r.z).max())
        if not flip.any():
            continue
        codes[flip] = 3 + 9 * 2  # β+ basic in place of β-: the same row equation, w_i = 0
        ws = lemke.BoxWarmStart.from_row_states(codes)
        Mx, qx, lox, hix, F, normal = _blcp.friction_lcp(M, q, lo, hi, fi)
        N = qx.size
        flags = ws._kernel_flags()
        zx, R, C = np.empty(N), np.empty(N), np.empty(N)
        assert cboxed.basis_point(Mx, qx, lox, hix, flags[:N], flags[N:], True, zx)
        assert zx[np.flatnonzero(flip)].max() < 0.0
        cboxed.check_scales(Mx, qx, lox, hix, R, C)
        assert not cboxed.box_check(Mx, qx, lox, hix, zx, _DEFAULT.tol, np.empty(N), R)[0]
        warm = lemke.solve_blcp(M, q, lo, hi, findex=fi, warm_start=ws)
        assert warm.status == lemke.Status.SOLVED and warm.pivots == 0
        assert warm.warm_start is ws
        assert_friction_solution(M, q, lo, hi, fi, warm.z)
        assert np.allclose(warm.z, r.z, rtol=1e-9, atol=1e-12 * np.abs(r.z).max())
        lists = lemke.solve_blcp(M.tolist(), q.tolist(), lo.tolist(), hi.tolist(),
                                 findex=fi.tolist(), warm_start=ws)
        assert lists == warm
        many = lemke.solve_blcp_many([M, M], [q, q], [lo, lo], [hi, hi], findex=[fi, fi],
                                     warm_start=lemke.BoxWarmStartBatch.of([ws, ws]))
        for item in many:
            assert item.pivots == 0 and np.asarray(item.z).tobytes() == np.asarray(warm.z).tobytes()
        found += 1
    assert found >= 5, found


def test_a_warm_friction_point_is_solved_on_the_callers_rows():
    """A warm friction basis's point is solved on the caller's n rows (``boxed.friction_point``:
    a sliding row's z_i = +-mu z_f substituted into its normal's column, no extended
    matrix).  Checked with plain numpy: each row's own equation holds (w_i = 0 in the block's
    rows to their terms' rounding, a sliding row exactly on its cone's edge, a row at a
    bound at it); the point agrees with the refined solve of the same system
    (``_blcp._caller_point``); the bases whose extended block is singular by its pattern
    are refused; a 0-pivot warm answer is that point in the coupled bounds (the same
    numbers), passes the plain-numpy friction check, and is the general path's
    (``_warm_friction``) answer."""
    from lemke import _blcp
    from lemke._options import _DEFAULT
    cboxed = _blcp.boxed
    seen = Counter()
    for seed in range(60):
        M, q, lo, hi, fi, mu = contacts(seed, 1 + seed % 6)
        fi = fi.astype(np.int64)
        n = q.size
        r = lemke.solve_blcp(M, q, lo, hi, findex=fi)
        assert r.success
        q2 = q + 1e-3 * np.abs(q) * np.random.default_rng(seed).standard_normal(n)
        ws = r.warm_start
        F = np.flatnonzero(fi >= 0)
        normal = fi[F]
        nf, N = F.size, n + 2 * F.size
        flags = ws._kernel_flags()
        zb, zh = flags[:N], flags[N:]
        z = np.empty(n)
        assert cboxed.friction_point(M, q2, lo, hi, np.concatenate([F, normal]), zb, zh, z)
        bp, bm, lam = zb[F], zb[n:n + nf], zb[n + nf:]
        sliding = lam & (bp != bm)
        eq = np.zeros(n, dtype=bool)
        eq[:n] = zb[:n]
        eq[F] = (bp | bm) & ~sliding
        w = M @ z + q2
        size = np.abs(M) @ np.abs(z) + np.abs(q2)
        assert np.all(np.abs(w[eq]) <= 1e-9 * size[eq]), seed
        assert np.array_equal(z[F[sliding]], np.where(bp, mu, -mu)[sliding] * z[normal[sliding]])
        assert np.all(z[F[~(bp | bm)]] == 0.0)
        fixed = ~eq
        fixed[F] = False
        assert np.all(z[fixed] == np.where(zh[:n] & (hi < np.inf), hi, lo)[fixed])
        got = _blcp._caller_point(M, q2, lo, hi, F, normal, zb, zh, 1e-9)
        if got is not None:
            zr = got[0]
            assert np.abs(np.clip(z, got[3], got[4]) - zr).max() <= 1e-8 * np.abs(zr).max()
        warm = lemke.solve_blcp(M, q2, lo, hi, findex=fi, warm_start=ws)
        assert warm.success
        assert_friction_solution(M, q2, lo, hi, fi, warm.z)
        # the general path's same step (_warm_friction): the same verdict and point
        general = _blcp._warm_friction(M, q2, lo, hi, *_blcp.friction_lcp(M, q2, lo, hi, fi), ws,
                                       _DEFAULT)
        assert (general is not None) == (warm.pivots == 0)
        if warm.pivots == 0:
            lo_c, hi_c = lo.copy(), hi.copy()
            lo_c[F], hi_c[F] = -hi[F] * z[normal], hi[F] * z[normal]
            zc = np.clip(z, np.minimum(lo_c, hi_c), hi_c)
            assert np.array_equal(warm.z, zc)  # (numpy's clip makes a -0.0 +0.0: == here)
            assert np.array_equal(general.z, warm.z) and general.residual == warm.residual
            seen["0 pivots"] += 1
        seen["sliding"] += int(sliding.sum())
        # the patterns whose extended block is singular: refused
        for c in range(nf):
            bad = zb.copy()
            bad[F[c]] = bad[n + c] = False
            bad[n + nf + c] = True  # λ basic, β+ and β- at 0
            assert not cboxed.friction_point(M, q2, lo, hi, np.concatenate([F, normal]), bad, zh, z)
            bad[F[c]] = bad[n + c] = True
            bad[n + nf + c] = False  # β+ and β- basic, λ at 0
            assert not cboxed.friction_point(M, q2, lo, hi, np.concatenate([F, normal]), bad, zh, z)
    assert seen["0 pivots"] >= 30 and seen["sliding"] >= 20, seen


_PILES = {}


def pile_steps(n_disks=6, steps=120, mu=0.5):
    """The box LCPs ``(A, b, lo, hi, findex)`` of examples/box_pile.py's steps (disks falling
    into a bin and settling), as the example's warm-started run poses them."""
    key = (n_disks, steps, mu)
    if key not in _PILES:
        bp = _example()
        out = []
        real = lemke.solve_blcp

        def record(A, b, lo, hi, findex=None, warm_start=None):
            out.append(tuple(np.array(a) for a in (A, b, lo, hi, findex)))
            return real(A, b, lo, hi, findex=findex, warm_start=warm_start)

        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(bp.lemke, "solve_blcp", record)
            world = bp.pile_world(n_disks, mu=mu)
            ws = None
            for _ in range(steps):
                res = bp.step(world, 0.01, ws)[2]
                ws = res.warm_start if res is not None else None
        _PILES[key] = out
    return _PILES[key]


def test_pile_warm_starts_across_steps():
    """Every step of a small pile, cold and warm-started from the previous step's answer:
    both solved and checked independently, equal answers, fewer pivots warm (most steps
    take none), the caller's arrays untouched."""
    steps = pile_steps()
    ws = None
    pivots = {"cold": 0, "warm": 0}
    zero = failed = 0
    for A, b, lo, hi, fi in steps:
        before = [a.copy() for a in (A, b, lo, hi, fi)]
        cold = lemke.solve_blcp(A, b, lo, hi, findex=fi)
        if ws is not None and ws.n != cold.warm_start.n:
            ws = None
        warm = lemke.solve_blcp(A, b, lo, hi, findex=fi, warm_start=ws)
        assert warm.status == lemke.Status.SOLVED, warm
        assert_friction_solution(A, b, lo, hi, fi, warm.z)
        # Every step solves cold too.  Step 90 (n = 22, a resting contact whose row of the
        # data is all rounding) used to end NUMERICAL_FAILURE: every run stopped with that
        # contact's impulse at 0 and w_i = -6e-13 against terms of 6e-13; the last
        # recovery, a restart from the final basis (_blcp._from_final), solves it.
        assert cold.status == lemke.Status.SOLVED, cold
        assert_friction_solution(A, b, lo, hi, fi, cold.z)
        scale = np.abs(cold.z).max(initial=0.0)
        assert np.allclose(warm.z, cold.z, rtol=1e-6, atol=1e-8 * scale)
        failed += cold.recoveries > 2  # (the restart from the final basis is recovery 3)
        for a, a0 in zip((A, b, lo, hi, fi), before):
            assert np.array_equal(a, a0)
        pivots["cold"] += cold.pivots
        pivots["warm"] += warm.pivots
        zero += ws is not None and warm.pivots == 0
        if ws is not None and warm.pivots == 0:
            assert warm.warm_start is ws  # its own basis, passed on as it came
        ws = warm.warm_start
    assert pivots["warm"] < pivots["cold"] / 2 and zero > len(steps) / 2, (pivots, zero)
    assert failed <= 1  # step 90's restart; more would be news


@pytest.mark.parametrize("friction", [True, False])
def test_one_call_equals_the_general_path(friction):
    """solve_blcp's one-call path (boxed::front and the runs around it) against the
    general path that it stands for (_solve_friction / _solve run step by step, with their
    own basis points, checks and ladder), cold and warm-started across the steps of a pile:
    the same status, pivots, recoveries, final basis and bounds in force, z to 1e-12; and
    the same result, field for field, from lists (validated first) as from arrays."""
    from lemke import _blcp
    from lemke._options import _DEFAULT

    ws = None
    for A, b, lo, hi, fi in pile_steps():
        f = fi if friction else None
        if ws is not None and ws.n != (b.size + 2 * np.count_nonzero(fi >= 0) if friction else b.size):
            ws = None
        for start in (None, ws):
            fast = lemke.solve_blcp(A, b, lo, hi, findex=f, warm_start=start)
            with np.errstate(all="ignore"):
                if friction:
                    slow = _blcp._solve_friction(A, b, lo, hi, fi, _DEFAULT, start, tried=True)
                else:
                    slow = _blcp._solve(A, b, lo, hi, _DEFAULT, start, tried=True)
                slow = _blcp._from_final(slow, A, b, lo, hi, f, _DEFAULT)  # the last recovery
            assert (fast.status, fast.pivots, fast.recoveries) == (slow.status, slow.pivots, slow.recoveries)
            assert fast.warm_start == slow.warm_start
            assert np.allclose(fast.z, slow.z, rtol=1e-12, atol=1e-12 * np.abs(slow.z).max(initial=0.0))
            assert np.array_equal(fast.lo, slow.lo) and np.array_equal(fast.hi, slow.hi)
            lists = lemke.solve_blcp(A.tolist(), b.tolist(), lo.tolist(), hi.tolist(),
                                     findex=None if f is None else f.tolist(), warm_start=start)
            assert lists == fast
        ws = fast.warm_start


def test_friction_result_is_lazy_and_equals_the_full_build():
    """A friction-index result of the one-call path: built lazily, its arrays read-only
    (the bounds in force too), the caller's arrays neither kept nor modified, equal to the
    general path's result field for field and after pickling."""
    import pickle

    M, q, lo, hi, findex, mu = contacts(3, 5)
    findex = findex.astype(np.int64)
    args = [a.copy() for a in (M, q, lo, hi, findex)]
    r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
    again = lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=r.warm_start)
    for res in (r, again):
        assert "_src" in res.__dict__ and "z" not in res.__dict__
        for name in ("z", "w", "lo", "hi", "covering", "row_scale", "col_scale"):
            a = getattr(res, name)
            assert not a.flags.writeable, name
        assert res.lo is not lo and res.hi is not hi
        assert pickle.loads(pickle.dumps(res)) == res
        assert_friction_solution(M, q, lo, hi, findex, res.z)
    assert again.pivots == 0 and again.warm_start is r.warm_start
    assert r.covering.size == q.size + 2 * 5 and r.row_scale.size == q.size
    full = lemke.solve_blcp(M.tolist(), q.tolist(), lo.tolist(), hi.tolist(), findex=findex.tolist())
    assert full == r
    for a, a0 in zip((M, q, lo, hi, findex), args):
        assert np.array_equal(a, a0)


@pytest.mark.parametrize("findex, lo, hi, match", [
    ([-1, 2], [0, -1], [np.inf, 1], r"findex\[1\] = 2 is out of range"),
    ([-1, -2], [0, -1], [np.inf, 1], r"findex\[1\] = -2 is out of range"),
    ([-1, 1], [0, -1], [np.inf, 1], r"findex\[1\] = 1 points at its own row"),
    ([1, 0], [-1, -1], [1, 1], r"findex\[0\] = 1 points at another friction row"),
    ([-1, 0], [0, 1], [np.inf, -1], r"mu = hi\[1\] = -1.0 < 0"),
    ([-1, 0], [0, -np.inf], [np.inf, np.inf], r"mu = hi\[1\] must be finite"),
    ([-1, 0], [0, np.nan], [np.inf, np.nan], r"lo has a NaN"),
    ([-1, 0], [0, -1.0], [np.inf, np.nan], r"hi has a NaN"),
    ([-1, 0], [np.nan, -1.0], [np.inf, 1.0], r"lo has a NaN"),
    ([-1, 0], [0, -0.5], [np.inf, 1.0], r"lo\[1\] = -0.5 must be -mu"),
    ([-1, 0], [-1, -1], [np.inf, 1.0], r"lo\[0\] = -1.0 must be >= 0"),
])
def test_bad_findex_fast_path(findex, lo, hi, match):
    """The same refusals from the one-call path (float64 arrays, int64 findex), with and
    without a warm start: the kernel says the data are bad, validation says where."""
    M, q = np.eye(2), np.zeros(2)
    lo, hi, findex = np.array(lo, dtype=float), np.array(hi, dtype=float), np.array(findex, dtype=np.int64)
    ws = lemke.BoxWarmStart(4, (), ())
    for start in (None, ws):
        with pytest.raises(ValueError, match=match):
            lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=start)


def test_bad_data_with_a_warm_start():
    M, q, lo, hi, findex, mu = contacts(2, 3)
    findex = findex.astype(np.int64)
    r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
    M2 = M.copy()
    M2[1, 2] = np.nan
    with pytest.raises(ValueError, match=r"M has a NaN"):
        lemke.solve_blcp(M2, q, lo, hi, findex=findex, warm_start=r.warm_start)
    q2 = q.copy()
    q2[4] = np.inf
    with pytest.raises(ValueError, match=r"q has"):
        lemke.solve_blcp(M, q2, lo, hi, findex=findex, warm_start=r.warm_start)
    with pytest.raises(ValueError, match=r"warm_start is for a problem of size 6, this one has n = 12"):
        lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=lemke.BoxWarmStart(6, (), ()))
    with pytest.raises(ValueError, match=r"size 12, this one has n = 6"):
        lemke.solve_blcp(M, q, lo, hi, warm_start=r.warm_start)
    with pytest.raises(TypeError, match="BoxWarmStart"):
        lemke.solve_blcp(M, q, lo, hi, findex=findex, warm_start=r)
    # bad data and a warm start of the wrong size: the data's error comes first
    lo2 = lo.copy()
    lo2[0] = np.nan
    with pytest.raises(ValueError, match=r"lo has a NaN"):
        lemke.solve_blcp(M, q, lo2, hi, findex=findex, warm_start=lemke.BoxWarmStart(6, (), ()))
    with pytest.raises(ValueError, match=r"lo has a NaN"):
        lemke.solve_blcp(M, q, lo2, hi, warm_start=lemke.BoxWarmStart(6, (), ()))


# --------------------------------------------------------------------------- the example

def _example():
    """examples/box_pile.py as a module (examples/ is not a package)."""
    import importlib.util
    import sys

    if "box_pile" not in sys.modules:
        path = Path(__file__).parent.parent / "examples" / "box_pile.py"
        spec = importlib.util.spec_from_file_location("box_pile", path)
        mod = importlib.util.module_from_spec(spec)
        sys.modules["box_pile"] = mod  # dataclasses look their module up there
        spec.loader.exec_module(mod)
    return sys.modules["box_pile"]


@pytest.mark.slow
def test_example_writes_png(tmp_path):
    pytest.importorskip("matplotlib")
    bp = _example()
    out = tmp_path / "pile.png"
    bp.main(["--steps", "40", "--disks", "6", "--out", str(out)])
    assert out.stat().st_size > 10_000
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("angle, mu", [(0.3, 0.5), (0.5, 0.3), (0.2, 0.1), (0.6, 0.7)])
def test_box_on_slope(angle, mu):
    bp = _example()
    v = bp.slope(angle, mu, steps=30, h=0.01)
    if mu > np.tan(angle):  # sticks
        assert np.abs(v).max() < 1e-8
    else:  # slides with g (sin a - mu cos a)
        acc = np.diff(v) / 0.01
        assert np.allclose(acc, bp.G * (np.sin(angle) - mu * np.cos(angle)), rtol=1e-6)


def test_resting_pile_balances_gravity():
    bp = _example()
    hist = bp.simulate(n_disks=6, steps=150, h=0.01, mu=0.5, snapshots=2)
    weight = hist["world"].mass.sum() * bp.G * hist["h"]
    assert np.allclose(hist["env_vertical"][-10:], weight, rtol=1e-4)
    assert np.all(np.diff(hist["energy"]) <= 1e-9 * abs(hist["energy"][0]))  # never gains energy


def test_contact_scenes_with_friction_index():
    """The step LCPs of tests/contact_sim.py (disks and boxes in a bin, redundant contacts,
    duplicated rows) posed as box LCPs with a friction index: every one solved and checked
    on the coupled bounds."""
    import contact_sim  # tests/ is on sys.path under pytest, as for helpers

    count = 0
    for seed in (1, 2, 3):
        for M, q in contact_sim.step_lcps(seed, n_bodies=20, steps=40, boxes=True):
            if q.size == 0:
                continue
            m = q.size // 4
            rows = np.concatenate([np.arange(m), m + 2 * np.arange(m)])  # normals, +t rows
            A = M[np.ix_(rows, rows)]
            b = q[rows]
            mu = M[3 * m + np.arange(m), np.arange(m)]
            lo = np.concatenate([np.zeros(m), -mu])
            hi = np.concatenate([np.full(m, np.inf), mu])
            findex = np.concatenate([-np.ones(m, dtype=int), np.arange(m)])
            r = lemke.solve_blcp(A, b, lo, hi, findex=findex)
            assert r.success, (seed, m, r)
            lo_c, hi_c = lo.copy(), hi.copy()
            lo_c[m:], hi_c[m:] = -mu * r.z[:m], mu * r.z[:m]
            assert_box_solution(A, b, lo_c, hi_c, r.z, rtol=1e-7)
            count += 1
    assert count > 100


def test_fuzz_small_integer_problems():
    """Arbitrary small integer M (not monotone: Lemke may end on a ray or fail), bounds from
    {-inf, -2, -1, 0} x {0, 1, 2, +inf}: never an exception, never NaN, never a false
    success; the monotone ones with finite bounds always solved."""
    rng = np.random.default_rng(12)
    statuses = set()
    for _ in range(600):
        n = int(rng.integers(1, 7))
        M = rng.integers(-2, 3, (n, n)).astype(float)
        monotone = rng.random() < 0.5
        if monotone:
            M = M @ M.T
        q = rng.integers(-2, 3, n).astype(float)
        lo = rng.choice([-np.inf, -2.0, -1.0, 0.0], n)
        hi = np.maximum(rng.choice([0.0, 1.0, 2.0, np.inf], n), lo)
        r = lemke.solve_blcp(M, q, lo, hi)
        statuses.add(r.status)
        assert np.all(np.isfinite(r.z)) and np.all(np.isfinite(r.w))
        if r.success:
            assert_box_solution(M, q, lo, hi, r.z)
        elif monotone and np.all(np.isfinite(lo) & np.isfinite(hi)):
            raise AssertionError(f"a monotone box LCP with finite bounds was not solved: {r}")
        if r.status == lemke.Status.RAY_TERMINATION:
            assert is_box_ray(M, q, lo, hi, r.covering, r.z, r.z0, r.ray)
    assert lemke.Status.SOLVED in statuses and lemke.Status.RAY_TERMINATION in statuses


def test_extreme_values_do_not_crash():
    for M, q, lo, hi in (
        ([[1.0]], [1.0], [-1e308], [1e308]),
        ([[1e-300]], [-1.0], [-1e308], [1e308]),
        ([[1e300, -1e300], [1e300, 1e300]], [-1.0, 1.0], [-np.inf, 0.0], [np.inf, 5e-324]),
        ([[0.0]], [1.0], [-np.inf], [np.inf]),
    ):
        r = lemke.solve_blcp(M, q, lo, hi)
        assert r.status in tuple(lemke.Status) and np.all(np.isfinite(r.z))
        if r.success:
            assert_box_solution(M, q, lo, hi, r.z)


def test_docstring_example_runs():
    import doctest

    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    tests = doctest.DocTestFinder().find(lemke.solve_blcp, "solve_blcp", globs={})
    assert tests and tests[0].examples
    for t in tests:
        runner.run(t)
    assert runner.failures == 0


def test_huge_finite_bounds_count_as_far():
    for lo, hi, z in (([-1e308], [1e308], [-1.0]), ([-np.inf], [1e300], [-1.0]), ([-1e300], [0.5], [-1.0])):
        r = lemke.solve_blcp([[1.0]], [1.0], lo, hi)
        assert r.success and r.z.tolist() == z


def test_fast_path_result_is_lazy_and_equals_the_full_build():
    """solve_blcp's fast path (float64 arrays) builds its result's arrays and warm start
    when first read; every field must equal, bit for bit and in type, what the general
    path (lists in, validated and converted) builds at once, and survive pickling."""
    import pickle

    rng = np.random.default_rng(11)
    n = 9
    A = rng.standard_normal((n, n))
    M = A @ A.T + 0.5 * np.eye(n)
    q = rng.standard_normal(n)
    lo, hi = -np.ones(n), np.ones(n)
    fast = lemke.solve_blcp(M, q, lo, hi)
    full = lemke.solve_blcp(M.tolist(), q.tolist(), lo.tolist(), hi.tolist())
    assert "_src" in fast.__dict__ and "z" not in fast.__dict__  # nothing made yet
    assert fast.status == full.status == lemke.Status.SOLVED
    for name in ("z", "w", "covering", "row_scale", "col_scale", "lo", "hi"):
        a, b = getattr(fast, name), getattr(full, name)
        assert type(a) is type(b) and a.tobytes() == b.tobytes(), name
        assert not a.flags.writeable or name in ("lo", "hi"), name
    for name in ("pivots", "residual", "ray", "z0", "recoveries", "warm_start"):
        assert getattr(fast, name) == getattr(full, name), name
    again = pickle.loads(pickle.dumps(lemke.solve_blcp(M, q, lo, hi)))
    assert again.z.tobytes() == full.z.tobytes() and again.warm_start == full.warm_start
    # the answer itself, checked here: natural-map conditions on the caller's data
    z, w = fast.z, M @ fast.z + q
    assert np.all(z >= lo - 1e-12) and np.all(z <= hi + 1e-12)
    assert np.all(np.where(z <= lo + 1e-9, w >= -1e-9, True))
    assert np.all(np.where(z >= hi - 1e-9, w <= 1e-9, True))
    inner = (z > lo + 1e-9) & (z < hi - 1e-9)
    assert np.all(np.abs(w[inner]) <= 1e-9)


def test_solve_blcp_entry_is_the_python_function_to_its_callers(monkeypatch):
    """``lemke.solve_blcp`` is the core's entry (``_core.blcp_entry``, src/python_front.cpp):
    solve_blcp(M, q, lo, hi) with no keyword but findex= and/or warm_start= goes to
    ``_blcp._FRONT`` with no Python frame (a run it does not settle to
    ``_blcp._after_front``), everything else to the Python function it wraps; it reads
    ``_FRONT`` on each call and shows the function's name, docstring, signature and pickles
    by name.  Results equal the Python function's field by field (bit for bit), cold, warm
    and with friction."""
    import inspect
    import pickle

    from lemke import _blcp

    f = lemke.solve_blcp
    py = _blcp._solve_blcp
    assert f is _blcp.solve_blcp and f.__wrapped__ is py and f is not py
    assert (f.__name__, f.__module__, f.__doc__) == ("solve_blcp", "lemke._blcp", py.__doc__)
    assert str(inspect.signature(f)) == str(inspect.signature(py))
    assert repr(f) == repr(py) and pickle.loads(pickle.dumps(f)) is f
    for seed in range(6):
        M, q, lo, hi, fi, mu = contacts(seed, 1 + seed % 4)
        for findex in (None, fi):
            cold = f(M, q, lo, hi, findex=findex)
            assert cold == py(M, q, lo, hi, findex=findex) and cold.success
            if findex is None:
                assert cold == f(M, q, lo, hi) == py(M, q, lo, hi)
                assert_box_solution(M, q, lo, hi, cold.z, rtol=1e-7)
            else:
                assert_friction_solution(M, q, lo, hi, findex, cold.z)
            ws = cold.warm_start
            warm = f(M, q, lo, hi, warm_start=ws, findex=findex)  # (either keyword order)
            assert warm == py(M, q, lo, hi, findex=findex, warm_start=ws) and warm.pivots == 0
            q2 = q + 0.3
            assert f(M, q2, lo, hi, findex=findex, warm_start=ws) == py(M, q2, lo, hi, findex=findex, warm_start=ws)
    # no Python frame of solve_blcp's on the front's calls (the Python function's otherwise)
    import sys

    M, q, lo, hi, fi, mu = contacts(2, 3)
    ws = f(M, q, lo, hi, findex=fi).warm_start
    seen = []
    sys.setprofile(lambda frame, event, arg: event == "call" and seen.append(frame.f_code.co_name))
    try:
        f(M, q, lo, hi)
        f(M, q, lo, hi, findex=fi, warm_start=ws)
        py(M, q, lo, hi)
    finally:
        sys.setprofile(None)
    assert seen.count("solve_blcp") == 1  # py's own
    # a cold run the front does not settle (a ray: _after_front's _finish) and a warm start
    # it hands to the general path (another size: _after_front's _general raises)
    M, q = -np.eye(2), np.array([-1.0, -1.0])
    lo, hi = np.zeros(2), np.full(2, np.inf)
    ray = f(M, q, lo, hi)
    assert ray == py(M, q, lo, hi) and ray.status == lemke.Status.RAY_TERMINATION
    calls = []
    front = _blcp._FRONT
    monkeypatch.setattr(_blcp, "_FRONT", lambda *a: calls.append(a) or front(*a))
    M, q, lo, hi, fi, mu = contacts(3, 3)
    assert f(M, q, lo, hi) == py(M, q, lo, hi) and f(M, q, lo, hi, findex=fi) == py(M, q, lo, hi, findex=fi)
    assert len(calls) == 4 and [c[4] is fi for c in calls] == [False, False, True, True]  # each through Python
    monkeypatch.undo()
    with pytest.raises(TypeError):
        f(M, q, lo)
    with pytest.raises(TypeError):
        f(M, q, lo, hi, fi)  # keyword-only, as the Python function's
    with pytest.raises(TypeError):
        f(M, q, lo, hi, bogus=1)
    for call in (f, py):
        with pytest.raises(ValueError, match="NaN"):
            call(M, np.full(q.shape, np.nan), lo, hi)
        with pytest.raises(ValueError, match=r"findex\[1\] = 1 points at its own row"):
            call(M[:2, :2], q[:2], np.array([0.0, -1.0]), np.array([np.inf, 1.0]), findex=np.array([-1, 1]))
        with pytest.raises(TypeError):
            call(M, q, lo, hi, warm_start=object())
    # the entry's other calls: the Python function's (lists, options, method, progress)
    r = f(M, q, lo, hi, findex=fi)
    assert f(M.tolist(), q.tolist(), lo.tolist(), hi.tolist(), findex=fi.tolist()) == r
    assert f(M, q, lo, hi, findex=fi, options={"max_pivots": 1000}) == r
    assert f(M, q, lo, hi, findex=fi, method="bounded") == r
    with pytest.raises(ValueError, match="unknown method"):
        f(M, q, lo, hi, method="nope")


@pytest.mark.parametrize("stop", [lemke.Status.TIME_LIMIT, lemke.Status.INTERRUPTED])
def test_a_stop_ends_the_box_fronts_finish_ladder(monkeypatch, stop):
    """The box front's general ladder (_blcp._finish): when a rung's run stops (a time limit,
    an interrupt), the ladder ends there and says so; no later rung's fresh run (which an
    interrupt would not reach) is started.  Before, the exact-ties rung ran after a stopped
    covering-vector run, and the result carried the first run's failure."""
    from lemke import _blcp

    rng = np.random.default_rng(7)
    n = 6
    A = rng.standard_normal((n, n))
    M, q = A @ A.T + np.eye(n), rng.standard_normal(n)
    lo, hi = np.zeros(n), np.full(n, np.inf)
    opts = lemke.Options()
    first = _blcp._Run(n).go(M, q, lo, hi, np.zeros(2 * n, dtype=np.bool_), 0, opts, 10**6, opts.tie_tol)
    first.code, first.ok = int(lemke.Status.NUMERICAL_FAILURE), False  # a run that failed
    real, calls = _blcp._Run.go, []

    def stopped(self, *args):
        calls.append(args[5])  # the covering-vector mode of each rung's run
        real(self, *args)
        self.code, self.ok = int(stop), False
        return self

    monkeypatch.setattr(_blcp._Run, "go", stopped)
    res = _blcp._finish(M, q, lo, hi, opts, first)
    assert calls == [1]  # the other covering vectors' run only: no exact-ties run after it
    assert res.status == stop
