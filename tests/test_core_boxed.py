"""The C++ box LCP engine (src/lemke/boxed.*, bound as lemke._core.boxed) against its frozen
references (tests/frozen.py: the outputs of the kernels it was ported from), bit for bit:
every returned number (its type and its bits) and every byte of every array the call may
write.

Two ways in:

* **through the front**: ``_blcp.boxed`` (and ``_certify``'s box checks) is replaced by a
  tee that runs each call of the front (solve, front, box_check, check_scales, basis_point,
  friction_point, is_ray, extend)
  on copies of its arguments, checks the outputs and hands them on; then
  the box LCP tests' problems (tests/test_blcp.py: the Siconos relay files, the seeded
  family, degenerate ties, the small integer fuzz, extreme values, friction contacts, the
  pile of examples/box_pile.py cold and warm), the contact scenes of tests/contact_sim.py
  with a friction index, at several tie tolerances, are solved by ``solve_blcp`` on its
  fast path (arrays) and on its general path (lists);
* **directly**: random box LCPs with finite, one-sided, infinite and fixed bounds, every
  covering vector, several tie tolerances, pivot caps, warm starts (the final basis of a
  run on moved data, and random flags that make the warm basis singular), and the checks
  on random points and rays."""
from collections import Counter

import sys

import numpy as np
import pytest

import frozen
import lemke
from lemke import _blcp, _certify, _core

cboxed = _core.boxed
FUNCS = ("solve", "front", "box_check", "check_scales", "basis_point", "friction_point", "is_ray",
         "extend")
TIES = (1e-11, 0.0, 1e-9)


def compare(name, args):
    """Run kernel ``name`` of the core on copies of ``args`` and check its return value and
    every array argument afterwards against the frozen references: ``(True, the return
    value, the copies of the arguments)`` (a changed bit fails the test when it ends)."""
    a = [x.copy() if isinstance(x, np.ndarray) else x for x in args]
    r = getattr(cboxed, name)(*a)
    frozen.check((r, [x for x in a if isinstance(x, np.ndarray)]), name)
    return True, r, a


class Tee:
    """``_blcp.boxed`` for the comparison: each kernel call of the front run by
    :func:`compare` (its outputs checked against the frozen references), the outputs
    written back into the caller's arrays and the return value returned."""

    def __init__(self):
        self.counts = Counter()

    def __getattr__(self, name):
        if name == "friction_recover":
            return self.friction_recover
        if name not in FUNCS:
            return getattr(cboxed, name)

        def call(*args):
            _, rn, a = compare(name, args)
            self.counts[name] += 1
            for orig, new in zip(args, a):
                if isinstance(orig, np.ndarray) and orig.flags.writeable:
                    orig[...] = new
            return rn
        return call


    def friction_recover(self, M, q, lo, hi, FN, z, tol):
        """The core's FrictionBox check (recover, the coupled bounds, check_scales, box_check:
        ``_blcp``'s map back since branch frictionmap), its outputs checked against the
        frozen references as the kernel calls that the Python copy of the map made before
        (``check_scales(M, q, lo, hi, R, C)``, then ``box_check(M, q, lo_in, hi_in, z, tol, w,
        R, N)``; the re-checks of ``_solve_friction``'s dense re-solve ``zx2`` and of
        ``_caller_point`` reused the first check's R: box_check alone), in that order: the
        same bits, or the test fails."""
        caller = sys._getframe(1)
        got = cboxed.friction_recover(M, q, lo, hi, FN, z, tol)
        ok, residual, zc, w, lo_in, hi_in, R, C = got
        name = caller.f_code.co_name
        if name == "_judged" or (name == "_solve_friction" and caller.f_locals.get("zx2") is not z):
            frozen.check((None, [M, q, lo, hi, R, C]), "check_scales")
        frozen.check(((ok, residual), [M, q, lo_in, hi_in, zc, w, R]), "box_check")
        self.counts["friction_recover"] += 1
        return got


@pytest.fixture
def tee(monkeypatch):
    t = Tee()
    monkeypatch.setattr(_blcp, "boxed", t)
    # the checks the front calls through _certify (box_check, check_scales; is_box_ray's is_ray)
    monkeypatch.setattr(_certify, "boxed", t)
    monkeypatch.setattr(_certify, "box_check", t.box_check)
    monkeypatch.setattr(_certify, "check_scales", t.check_scales)
    # the native front (src/python_front_box.cpp) calls the kernels itself: off, so that
    # every call goes through the tee (tests/test_front_box.py compares the two fronts)
    monkeypatch.setattr(_blcp, "_FRONT", lambda *a: None)
    # the front's buffers with fixed bytes where no kernel writes (checked byte for byte)
    monkeypatch.setattr(_blcp, "np", frozen.FixedEmpty())
    yield t
    print(f"\n  kernel calls checked: {dict(t.counts)}")
    assert sum(t.counts.values()) > 0


def _test_blcp():
    import test_blcp  # tests/ is on sys.path under pytest
    return test_blcp


def solve_both_paths(M, q, lo, hi, findex=None, warm_start=None, options=None):
    """solve_blcp on the fast path (float64 arrays) and the general path (lists)."""
    fi = None if findex is None else np.asarray(findex, dtype=np.int64)
    r = lemke.solve_blcp(M, q, lo, hi, findex=fi, warm_start=warm_start, options=options)
    lemke.solve_blcp(M.tolist(), q.tolist(), lo.tolist(), hi.tolist(),
                     findex=None if fi is None else fi.tolist(), warm_start=warm_start,
                     options=options)
    return r


def test_front_on_the_blcp_tests_problems(tee):
    tb = _test_blcp()
    f64 = lambda *a: [np.ascontiguousarray(x, dtype=float) for x in a]
    for path in sorted(tb.RELAY.glob("*.dat")):
        M, q, lo, hi = f64(*tb.read_relay(path))
        for tie in TIES:
            r = solve_both_paths(M, q, lo, hi, options={"tie_tol": tie})
            solve_both_paths(M, q, lo, hi, warm_start=r.warm_start, options={"tie_tol": tie})
    for seed in range(240):
        M, q, lo, hi = f64(*tb.family(seed))
        for tie in TIES:
            r = solve_both_paths(M, q, lo, hi, options={"tie_tol": tie})
            if r.warm_start is not None:
                q2 = q + 0.1 * np.random.default_rng(seed).standard_normal(q.size)
                solve_both_paths(M, q2, lo, hi, warm_start=r.warm_start, options={"tie_tol": tie})
    n = 8
    M = np.eye(n) + np.ones((n, n))
    for lo, hi in ((np.zeros(n), np.ones(n)), (-np.ones(n), np.zeros(n) + 0.1),
                   (np.zeros(n), np.full(n, 1 / 9))):
        for tie in TIES:
            solve_both_paths(M, -np.ones(n), lo, hi, options={"tie_tol": tie})
    solve_both_paths(np.zeros((3, 3)), np.array([1.0, -1.0, 0.0]), -np.ones(3), np.ones(3))
    solve_both_paths(np.array([[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 2.0]]),
                     np.array([-1.0, 3.0, -2.0]), np.array([-np.inf, 0.5, 0.0]),
                     np.array([np.inf, 0.5, np.inf]))
    solve_both_paths(np.zeros((2, 2)), np.array([-1.0, 1.0]), np.zeros(2), np.full(2, np.inf))
    rng = np.random.default_rng(12)
    for _ in range(600):  # the small integer fuzz
        n = int(rng.integers(1, 7))
        M = rng.integers(-2, 3, (n, n)).astype(float)
        if rng.random() < 0.5:
            M = M @ M.T
        q = rng.integers(-2, 3, n).astype(float)
        lo = rng.choice([-np.inf, -2.0, -1.0, 0.0], n)
        hi = np.maximum(rng.choice([0.0, 1.0, 2.0, np.inf], n), lo)
        solve_both_paths(M, q, lo, hi)
    for M, q, lo, hi in (
        ([[1.0]], [1.0], [-1e308], [1e308]),
        ([[1e-300]], [-1.0], [-1e308], [1e308]),
        ([[1e300, -1e300], [1e300, 1e300]], [-1.0, 1.0], [-np.inf, 0.0], [np.inf, 5e-324]),
        ([[0.0]], [1.0], [-np.inf], [np.inf]),
        ([[1.0]], [1.0], [-np.inf], [1e300]),
        ([[1.0]], [1.0], [-1e300], [0.5]),
    ):
        solve_both_paths(*f64(M, q, lo, hi))


def test_front_with_friction_and_warm_starts(tee):
    tb = _test_blcp()
    # the pile's own solves (test_blcp.pile_steps runs examples/box_pile.py) run here, through
    # the tee, whatever ran before: the frozen references hold them in this order
    tb._PILES.clear()
    for seed in range(12):
        for k in (1, 2, 3, 5, 8):
            M, q, lo, hi, findex, mu = tb.contacts(seed, k)
            for tie in TIES:
                r = solve_both_paths(M, q, lo, hi, findex=findex, options={"tie_tol": tie})
                solve_both_paths(M, q, lo, hi, findex=findex, warm_start=r.warm_start,
                                 options={"tie_tol": tie})
                q2 = q + 0.05 * np.random.default_rng(seed).standard_normal(q.size)
                solve_both_paths(M, q2, lo, hi, findex=findex, warm_start=r.warm_start,
                                 options={"tie_tol": tie})
    for mu in (0.1, 0.5, 2.0):
        M = np.array([[2.0, 0.5], [0.5, 1.0]])
        for q in ([-1.0, 0.3], [-1.0, -2.0], [1.0, 0.5]):
            solve_both_paths(M, np.array(q), np.array([0.0, -mu]), np.array([np.inf, mu]),
                             findex=[-1, 0])
    # the pile of examples/box_pile.py, cold and warm across its steps, with and without
    # the friction index
    for friction in (True, False):
        ws = None
        for A, b, lo, hi, fi in tb.pile_steps():
            f = fi if friction else None
            N = b.size + 2 * np.count_nonzero(fi >= 0) if friction else b.size
            if ws is not None and ws.n != N:
                ws = None
            solve_both_paths(A, b, lo, hi, findex=f)
            r = solve_both_paths(A, b, lo, hi, findex=f, warm_start=ws)
            ws = r.warm_start
    bp = tb._example()
    for angle, mu in ((0.3, 0.5), (0.5, 0.3)):
        bp.slope(angle, mu, steps=10, h=0.01)


def test_front_on_contact_scenes(tee):
    import contact_sim

    count = 0
    for seed in (1, 2, 3):
        ws = None
        for M, q in contact_sim.step_lcps(seed, n_bodies=20, steps=40, boxes=True):
            if q.size == 0:
                continue
            m = q.size // 4
            rows = np.concatenate([np.arange(m), m + 2 * np.arange(m)])
            A = np.ascontiguousarray(M[np.ix_(rows, rows)])
            b = np.ascontiguousarray(q[rows])
            mu = M[3 * m + np.arange(m), np.arange(m)]
            lo = np.concatenate([np.zeros(m), -mu])
            hi = np.concatenate([np.full(m, np.inf), mu])
            findex = np.concatenate([-np.ones(m, dtype=np.int64), np.arange(m)])
            tie = TIES[count % 3]
            r = lemke.solve_blcp(A, b, lo, hi, findex=findex, options={"tie_tol": tie})
            if ws is not None and ws.n == r.warm_start.n:
                lemke.solve_blcp(A, b, lo, hi, findex=findex, warm_start=ws)
            ws = r.warm_start
            count += 1
    assert count > 100


# --------------------------------------------------------------------------- direct calls


def random_box(rng, n, kind):
    """A random box LCP: M of one of four kinds, bounds mixing finite, one-sided, free,
    far (beyond FAR) and fixed entries."""
    if kind == 0:
        A = rng.standard_normal((n, n))
        M = A @ A.T + 0.1 * np.eye(n)
    elif kind == 1:
        A = rng.standard_normal((n, max(1, n // 3)))
        M = A @ A.T
    elif kind == 2:
        A = rng.integers(-2, 3, (n, n)).astype(float)
        M = A @ A.T + np.eye(n)
    else:
        M = rng.standard_normal((n, n))  # not monotone: rays, failures, cycles
    q = rng.integers(-3, 4, n).astype(float) if kind == 2 else 3 * rng.standard_normal(n)
    lo = -rng.random(n) * 2
    hi = rng.random(n) * 2
    pick = rng.random(n)
    lo = np.where(pick < 0.25, -np.inf, lo)
    hi = np.where((pick > 0.15) & (pick < 0.4), np.inf, hi)
    lo = np.where(pick > 0.95, -1e25, lo)  # far
    hi = np.where(pick > 0.97, 1e21, hi)
    fix = (pick > 0.85) & (pick < 0.9)
    lo = np.where(fix, 0.3, lo)
    hi = np.where(fix, 0.3, hi)
    lo = np.where((pick > 0.4) & (pick < 0.5), 0.0, lo)  # LCP-like rows
    return np.ascontiguousarray(M), q, lo, hi


def solve_args(M, q, lo, hi, warm, mode, mp, tie):
    n = q.size
    buf = np.full(6 * n + 1, np.nan)
    final = np.full(n, -7, dtype=np.int64)
    return (M, q, lo, hi, warm, mode, mp, 1e-11, tie, 1e-9, buf, final)


def test_solve_directly():
    """boxed.solve on random box LCPs: every covering vector, tie tolerance and kind, pivot
    caps, warm starts from the final basis on moved data, random (often singular) warm
    flags, whole and kept in part (``PARTIAL``)."""
    counts = Counter()
    for n in list(range(1, 26)) + [31, 40, 48, 64, 90]:
        rng = np.random.default_rng([21, n])
        for trial in range(8 if n < 30 else 3):
            kind = trial % 4
            M, q, lo, hi = random_box(rng, n, kind)
            cold = np.zeros(2 * n, dtype=np.bool_)
            for mode in (0, 1, 2):
                for tie in TIES:
                    ok, out, a = compare("solve", solve_args(M, q, lo, hi, cold, mode, 100 * (n + 1), tie))
                    counts["cold", ok, out[0]] += 1
                    assert ok, (n, trial, mode, tie, out)
            # pivot caps
            for mp in (-1, 0, 1, 3, n):
                ok, out, _ = compare("solve", solve_args(M, q, lo, hi, cold, 0, mp, 1e-11))
                counts["capped", ok, out[0]] += 1
                assert ok
            # a warm start: the final basis of the cold run, on moved data
            ok, out, a = compare("solve", solve_args(M, q, lo, hi, cold, 0, 100 * (n + 1), 1e-11))
            final, k, m = a[11], out[5], out[6]
            warm = np.zeros(2 * n, dtype=np.bool_)
            warm[final[:k]] = True
            warm[n + final[k:m]] = True
            for move in (0.0, 1e-3, 0.3):
                q2 = q + move * rng.standard_normal(n)
                for mode in (1, 2, 1 | cboxed.PARTIAL, 2 | cboxed.PARTIAL):
                    ok, out, _ = compare("solve", solve_args(M, q2, lo, hi, warm, mode, 100 * (n + 1), 1e-11))
                    counts["warm", ok, out[0]] += 1
                    assert ok, (n, trial, move, mode, out)
            # random warm flags (basic, at hi; disjoint)
            flags = rng.random(n)
            warm = np.zeros(2 * n, dtype=np.bool_)
            warm[:n] = flags < 0.4
            warm[n:] = flags > 0.7
            ok, out, _ = compare("solve", solve_args(M, q, lo, hi, warm, 1, 100 * (n + 1), 1e-11))
            counts["random warm", ok, out[0]] += 1
            assert ok, (n, trial, out)
            # the same kept in part (PARTIAL: what the exchange cannot make basic stays at its
            # bound), as the fronts' warm runs make them
            for mode in (0, 1) if n < 30 else (1,):
                ok, out, _ = compare("solve", solve_args(M, q, lo, hi, warm, mode | cboxed.PARTIAL,
                                                         100 * (n + 1), 1e-11))
                counts["random warm, partial", ok, out[0]] += 1
                assert ok, (n, trial, mode, out)
                assert out[0] != cboxed.SINGULAR
    for n in (120, 200):  # larger sizes
        rng = np.random.default_rng([22, n])
        for kind in (0, 2):
            M, q, lo, hi = random_box(rng, n, kind)
            ok, out, _ = compare("solve", solve_args(M, q, lo, hi, np.zeros(2 * n, dtype=np.bool_), 0,
                                                     100 * (n + 1), 1e-11))
            counts["large", ok, out[0]] += 1
            assert ok, (n, kind, out)
    print("\n  solve:", dict(sorted(counts.items(), key=str)))
    statuses = {s for (_, _, s) in counts}
    assert {0, 2}.issubset(statuses)  # solved and rays at least


def test_solve_refusals():
    """Bad data: the kernel's own codes, the same from both."""
    n = 3
    M = np.eye(n)
    q = np.ones(n)
    cold = np.zeros(2 * n, dtype=np.bool_)
    cases = [
        (M, q, np.zeros(n), np.array([1.0, np.nan, 1.0])),
        (M, np.array([1.0, np.inf, 0.0]), np.zeros(n), np.ones(n)),
        (np.array([[1.0, np.nan, 0], [0, 1, 0], [0, 0, 1]]), q, np.zeros(n), np.ones(n)),
        (M, q, np.ones(n), np.zeros(n)),
        (M, q, np.full(n, np.inf), np.full(n, np.inf)),
        (M, q, np.full(n, -np.inf), np.full(n, -np.inf)),
    ]
    for M_, q_, lo, hi in cases:
        ok, out, _ = compare("solve", solve_args(M_, q_, lo, hi, cold, 0, 100, 1e-11))
        assert ok and out[0] in (cboxed.NOT_FINITE, cboxed.BAD_BOUNDS), out
    # the kernel's own size check (the front's arrays): NOT_FINITE, nothing written
    args = list(solve_args(M, q, np.zeros(n), np.ones(n), cold[:3], 0, 100, 1e-11))
    ok, out, _ = compare("solve", args)
    assert ok and out[0] == cboxed.NOT_FINITE
    # sizes the kernel would read past: ValueError
    with pytest.raises(ValueError):
        cboxed.solve(M, q, np.zeros(2), np.ones(n), cold, 0, 100, 1e-11, 1e-11, 1e-9,
                     frozen.empty(6 * n + 1), frozen.empty(n, dtype=np.int64))
    with pytest.raises((ValueError, TypeError)):
        cboxed.solve(M, q, np.zeros(n), np.ones(n), cold, 0, 100, 1e-11, 1e-11, 1e-9,
                     frozen.empty(6 * n + 1, dtype=np.float32), frozen.empty(n, dtype=np.int64))


def test_edge_cases():
    """n = 0 everywhere, odd covering modes, NaN tolerances: the same from both."""
    e, M0 = frozen.empty(0), frozen.empty((0, 0))
    no_b, no_i = np.zeros(0, dtype=np.bool_), frozen.empty(0, dtype=np.int64)
    calls = [
        ("solve", (M0, e, e, e, no_b, 0, 10, 1e-11, 1e-11, 1e-9, np.full(1, np.nan), no_i)),
        ("box_check", (M0, e, e, e, e, 1e-9, frozen.empty(0), e, 0)),
        ("check_scales", (M0, e, e, e, frozen.empty(0), frozen.empty(0))),
        ("basis_point", (M0, e, e, e, no_b, no_b, True, frozen.empty(0))),
        ("is_ray", (M0, e, e, e, e, e, 0.0, np.ones(1), 1e-9)),
        ("front", (0, M0, e, e, e, no_i, no_b, False, 1e-9, np.full(1, np.nan), no_i, e)),
        ("front", (1, M0, e, e, e, no_i, no_b, True, 1e-9, np.full(1, np.nan), no_i, e)),
    ]
    rng = np.random.default_rng(4)
    M, q, lo, hi = random_box(rng, 7, 3)
    for mode in (-3, 7):
        calls.append(("solve", solve_args(M, q, lo, hi, np.zeros(14, dtype=np.bool_), mode, 100, 1e-11)))
    calls.append(("solve", (M, q, lo, hi, np.zeros(14, dtype=np.bool_), 0, 100, np.nan, np.nan, np.nan,
                            np.full(43, np.nan), np.full(7, -1, dtype=np.int64))))
    for name, args in calls:
        ok, out, _ = compare(name, args)
        assert ok, (name, out)


def test_checks_directly():
    """box_check (with n_round), check_scales, basis_point (both rules) and is_ray on random
    points, bases and rays, and on the answers and rays of runs."""
    counts = Counter()
    for n in list(range(1, 20)) + [33, 60]:
        rng = np.random.default_rng([23, n])
        for trial in range(6):
            M, q, lo, hi = random_box(rng, n, trial % 4)
            R, C = frozen.empty(n), frozen.empty(n)
            ok, _, a = compare("check_scales", (M, q, lo, hi, R, C))
            counts["check_scales", ok] += 1
            R = a[4]
            for z in (np.clip(rng.standard_normal(n), lo, hi), np.zeros(n),
                      np.clip(rng.standard_normal(n), np.minimum(lo, 0), np.maximum(hi, 0)) * 1.5):
                for nr in (0, n + 7):
                    ok, _, _ = compare("box_check", (M, q, lo, hi, z, 1e-9, frozen.empty(n), R, nr))
                    counts["box_check", ok] += 1
            for rule in (True, False):
                zb = rng.random(n) < 0.5
                zh = (rng.random(n) < 0.5) & ~zb
                ok, _, _ = compare("basis_point", (M, q, lo, hi, zb, zh, rule, np.full(n, np.nan)))
                counts["basis_point", ok] += 1
            # a run's answer and ray
            ok, out, a = compare("solve", solve_args(M, q, lo, hi, np.zeros(2 * n, dtype=np.bool_),
                                                     0, 100 * (n + 1), 1e-11))
            buf = a[10]
            z, d, ray = buf[:n], buf[2 * n:3 * n], buf[5 * n:]
            for r in (ray, rng.standard_normal(n + 1), np.abs(rng.standard_normal(n + 1))):
                for z0 in (out[2], 0.0, 1.0):
                    ok, _, _ = compare("is_ray", (M, q, lo, hi, d, z, z0, r, 1e-9))
                    counts["is_ray", ok] += 1
    print("\n  checks:", dict(sorted(counts.items(), key=str)))
    assert all(ok for (_, ok) in counts)


def test_extend_and_front_directly():
    """extend's views and F, and front's phases and refusals, on contact problems."""
    tb = _test_blcp()
    for seed in range(6):
        for k in (1, 3, 6):
            M, q, lo, hi, findex, mu = tb.contacts(seed, k)
            findex = findex.astype(np.int64)
            n = q.size
            nf = int(np.count_nonzero(findex >= 0))
            N = n + 2 * nf
            ok, out, a = compare("extend", (M, q, lo, hi, findex, nf, np.full(N * N + 3 * N, 7.0),
                                            np.full(2 * nf, -9, dtype=np.int64)))
            assert ok
            assert out[0].base is not None  # views of work
            for has_warm in (False, True):
                warm = np.zeros(2 * N, dtype=np.bool_)
                if has_warm:
                    r = lemke.solve_blcp(M, q, lo, hi, findex=findex)
                    warm = r.warm_start._kernel_flags().copy()
                for phase in (cboxed.PREPARE, cboxed.SOLVED_RUN):
                    args = (phase, M, q, lo, hi, findex, warm, has_warm, 1e-9,
                            np.full(6 * N + 1 + 6 * n, np.nan),
                            np.concatenate([np.zeros(N, dtype=np.int64), a[7]]),
                            np.full(N * N + 3 * N, np.nan))
                    ok, out, _ = compare("front", args)
                    assert ok, (seed, k, phase, has_warm, out)
            # refusals: a bad friction index, bad bounds of a friction row, a bad size
            bad = findex.copy()
            bad[1] = 1
            for fi, lo_ in ((bad, lo), (findex, np.where(findex >= 0, -2 * hi, lo))):
                args = (cboxed.PREPARE, M, q, lo_, hi, fi, np.zeros(2 * N, dtype=np.bool_), False,
                        1e-9, frozen.empty(6 * N + 1 + 6 * n), frozen.empty(N + 2 * nf, dtype=np.int64),
                        frozen.empty(N * N + 3 * N))
                ok, out, _ = compare("front", args)
                assert ok and out[0] == cboxed.BAD_FINDEX
            args = (cboxed.PREPARE, M, q, lo, hi, findex, np.zeros(2 * N, dtype=np.bool_), False,
                    1e-9, frozen.empty(6 * N), frozen.empty(N + 2 * nf, dtype=np.int64), frozen.empty(N * N + 3 * N))
            ok, out, _ = compare("front", args)
            assert ok and out[0] == cboxed.BAD_FINDEX
    # a front call whose ints were not written by PREPARE: refused, never read past
    M, q, lo, hi, findex, mu = tb.contacts(0, 2)
    n, N = 4, 8
    code, _ = cboxed.front(cboxed.SOLVED_RUN, M, q, lo, hi, findex.astype(np.int64),
                           np.zeros(2 * N, dtype=np.bool_), False, 1e-9, frozen.empty(6 * N + 1 + 6 * n),
                           np.full(N + 4, 10**9, dtype=np.int64), frozen.empty(N * N + 3 * N))
    assert code == cboxed.BAD_FINDEX
    with pytest.raises(ValueError):
        cboxed.front(cboxed.PREPARE, M, q, lo, hi, np.zeros(3, dtype=np.int64),
                     np.zeros(2 * N, dtype=np.bool_), False, 1e-9, frozen.empty(6 * N + 1 + 6 * n),
                     frozen.empty(N + 4, dtype=np.int64), frozen.empty(N * N + 3 * N))
    with pytest.raises(ValueError):
        cboxed.extend(M, q, lo, hi, findex.astype(np.int64), 1, frozen.empty(N * N + 3 * N),
                      frozen.empty(4, dtype=np.int64))
