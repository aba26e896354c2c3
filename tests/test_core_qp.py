"""The C++ QP kernels (``lemke._core.qp_*``, src/lemke/qp.cpp) against their frozen
references (tests/frozen.py: the outputs of the kernels they were ported from), bit for bit: every returned number and every byte of the
output buffers of ``solve`` (both methods), ``solve_gram`` (definite and semidefinite),
``solve_box`` (and ``box_basis``; on box-only QPs of fewer than BOX_FIRST variables),
``screen``, ``cholesky`` and ``kkt_check``, and of the pieces whose bits they depend on
(``dot4``, ``forward_rows``, ``qr_rows``, ``gram_lcp`` and the
unrevised method in factored form), on the Maros-Meszaros files, the QP tests' generators
(tests/test_qp.py, test_qp_gram.py, test_qp_conventions.py), steps of the MPC benchmark
(benchmarks/mpc_problem.py) and random dense convex QPs:
equalities, inequalities, finite and infinite bounds, fixed variables, P definite and
semidefinite, and many inequalities (m >= 4n) for the factored path."""
import sys
from pathlib import Path

import numpy as np
import pytest

import frozen
from lemke import _core, _qp

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "maros-meszaros"
sys.path.insert(0, str(HERE.parent / "benchmarks"))
sys.path.insert(0, str(HERE))
from maros_meszaros import load  # noqa: E402

TOL = (1e-11, 1e-11, 1e-9)  # pivot_tol, tie_tol, tol: the defaults
BAD_INPUT = _core.QP_BAD_INPUT  # the kernels' code for data they refuse
#: The oracle's numbers for the QP kernels' codes (qp.hpp's 1-6 and 9 then: MAX_PIVOTS ..
#: CYCLING's numbers among them; the core's are negative now, src/lemke/status.hpp); the
#: frozen references record them.
ORACLE_QP = {_core.QP_NOT_DEFINITE: 1, _core.QP_DEPENDENT_EQUALITIES: 2, _core.QP_NOT_SOLVED: 3,
             _core.QP_CHECK_FAILED: 4, _core.QP_BAD_INPUT: 5, _core.QP_NOT_APPLICABLE: 6,
             _core.QP_BAD_WARM: 9}


def as_recorded(ret):
    """A QP kernel's returned numbers as the oracle returned them (its codes)."""
    code = int(ret[0])
    return (ORACLE_QP.get(code, code), *(int(v) for v in ret[1:]))


def plain(problem):
    """The fused kernels' arguments (``_qp._plain_args``), or None."""
    return _qp._plain_args(*problem)


def compare_solve(args, method, max_pivots=-1):
    """_core.qp_solve on one problem, every returned number and the bytes of out checked
    against the frozen references: ([], the code)."""
    n, p, m = args[1].shape[0], args[4].shape[0], args[2].shape[0]
    fill = np.random.default_rng(n + 7 * m + 31 * p).standard_normal(4 * n + p + 2 * m + 4)

    def run(solve):
        out = fill.copy()  # the same bytes where nothing is written
        ret = solve(*args, method, max_pivots, *TOL, out)
        return as_recorded(ret), out, int(ret[0])

    *r, code = run(_core.qp_solve)
    frozen.check(tuple(r), ("solve", method, max_pivots))
    return [], code


def compare_gram(args, semidefinite, max_pivots=-1):
    n, p, m = args[1].shape[0], args[4].shape[0], args[2].shape[0]
    fill = np.random.default_rng(n + 5 * m + 17 * p).standard_normal(4 * n + p + 2 * m + 4)

    def run(solve):
        out = fill.copy()
        basic = out[2 * n + p + m + 4:].view(np.int64)  # as _qp: the basis in out's tail
        ret = solve(*args, *([max_pivots] + list(TOL)), out, basic, semidefinite)
        return as_recorded(ret), out, int(ret[0])

    *r, code = run(_core.qp_solve_gram)
    frozen.check(tuple(r), ("solve_gram", semidefinite, max_pivots))
    return [], code


def compare_pieces(args):
    """screen, cholesky and kkt_check (at the solve's point, and a perturbed one), checked
    against the frozen references."""
    def screen(fn):
        s = fn(*args)
        return (bool(s[0]),) + (tuple(np.asarray(a) for a in s[1:]) if s[0] else ())

    s = frozen.check(screen(_core.qp_screen), "screen")
    if not s[0]:
        return []
    Ps, lo, up = s[1:]

    def cholesky(fn):
        L = np.full_like(Ps, 7.0)
        return bool(fn(Ps, L)), L

    frozen.check(cholesky(_core.qp_cholesky), "cholesky")
    n, p, m = args[1].shape[0], args[4].shape[0], args[2].shape[0]
    out = np.zeros(4 * n + p + 2 * m + 4)
    _core.qp_solve(*args, 0, -1, *TOL, out)
    x, y, z, zb = out[:n], out[n:n + p], out[n + p:n + p + m], out[n + p + m:2 * n + p + m]
    rng = np.random.default_rng(n)
    for pert in (0.0, 1e-9):
        pt = [v * (1.0 + pert * rng.standard_normal(v.shape)) for v in (x, y, z, zb)]

        def kkt(fn):
            st = np.empty(4)
            return bool(fn(Ps, args[1], args[2], args[3], args[4], args[5], lo, up, *pt, 1e-9, st)), st

        frozen.check(kkt(_core.qp_kkt_check), ("kkt_check", pert))
    return []


# ----------------------------------------------------------------------------- problems

def random_qp(n, m, p, rng, rank=None, bounds="box", infinite=False, fixed=0, scale=1.0):
    """A random feasible QP (qpsolvers' form, plain arrays) around a point x0."""
    rank = n if rank is None else rank
    B = rng.standard_normal((n, rank))
    P = scale * (B @ B.T) + (0.1 * np.eye(n) if rank == n else 0.0)
    q = scale * rng.standard_normal(n)
    x0 = rng.standard_normal(n)
    G = rng.standard_normal((m, n))
    h = G @ x0 + rng.uniform(0.0, 1.0, m) * (rng.random(m) < 0.7)
    if infinite and m:
        h[rng.random(m) < 0.2] = np.inf
    A = rng.standard_normal((p, n))
    b = A @ x0
    lb, ub = np.full(n, -np.inf), np.full(n, np.inf)
    if bounds in ("box", "mixed", "lower"):
        lb = x0 - rng.uniform(0.1, 1.0, n)
        ub = x0 + rng.uniform(0.1, 1.0, n) if bounds != "lower" else ub
        if bounds == "mixed":
            lb[rng.random(n) < 0.4] = -np.inf
            ub[rng.random(n) < 0.4] = 1e20 if infinite else np.inf
    for j in rng.choice(n, min(fixed, n), replace=False):
        lb[j] = ub[j] = x0[j]
    return P, q, G, h, A, b, lb, ub


def families():
    """(name, problem) in qpsolvers' form."""
    for name in sorted(p.stem for p in DATA.glob("*.mat")):
        yield f"mm/{name}", load(DATA / f"{name}.mat")[0]
    import test_qp
    import test_qp_conventions
    from lemke.problems import random_convex_qp
    for seed in range(40):
        rng = np.random.default_rng(seed)
        n, m, p = int(rng.integers(1, 9)), int(rng.integers(0, 9)), int(rng.integers(0, 4))
        bounds = ("none", "lower", "box", "mixed")[seed % 4]
        scale = (1e-4, 1.0, 1e4)[seed % 3]
        yield f"fuzz/{seed}", test_qp._fuzz_case(n, m, p, int(rng.integers(0, 9)), seed, bounds,
                                                 scale)
    for seed in range(6):
        for shape in [(8, 4, 2), (12, 30, 0), (7, 0, 4), (10, 6, 3)]:
            yield f"conventions/{shape}/{seed}", test_qp_conventions._qp_problem(*shape, seed=seed)
    for n in (3, 6, 10):
        for ratio in (10, 25, 50):
            rng = np.random.default_rng([ratio, n])
            for t in range(3):
                yield f"gram/{n}/{ratio}/{t}", random_convex_qp(n, rng, m=ratio * n)
    for rank in (4, 6):
        rng = np.random.default_rng(rank)
        for t in range(3):
            yield f"gram_psd/{rank}/{t}", random_convex_qp(8, rng, m=160, rank=rank)
    import mpc_problem
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=85, seed=0)
    for t in (9, 45, 84):  # stationarity rows that pass by kkt_check's rounding floor only
        yield f"mpc/{t}", (P, steps[t][0], G, h, A, steps[t][1], lb, ub)
    for n in (1, 2, 5, 10, 20, 40):
        for kind in range(8):
            rng = np.random.default_rng([n, kind])
            m = (0, n // 2, n, 2 * n, 4 * n + 1, 6 * n, n, 3 * n)[kind]
            p = (0, 1, n // 3, 0, 1, n // 4, n + 1, n // 2)[kind]
            rank = n if kind % 3 else max(n // 2, 1)
            bounds = ("box", "mixed", "none", "lower")[kind % 4]
            yield f"random/{n}/{kind}", random_qp(n, m, p, rng, rank=rank, bounds=bounds,
                                                  infinite=kind % 2 == 1, fixed=kind % 3)


CASES = []
for _name, _problem in families():
    _args = plain(_problem)
    if _args is not None:
        CASES.append((_name, _args))


def test_families_are_there():
    assert len(CASES) > 200
    assert sum(1 for c in CASES if c[0].startswith("mm/")) == 62


@pytest.mark.parametrize("method", [0, 1])
def test_solve_bit_for_bit(method):
    bad, codes = [], {}
    for name, args in CASES:
        diff, code = compare_solve(args, method)
        codes[code] = codes.get(code, 0) + 1
        if diff:
            bad.append(f"{name}: " + "; ".join(diff))
    assert not bad, f"{len(bad)} of {len(CASES)}:\n" + "\n".join(bad[:20])
    assert codes.get(_core.QP_OK, 0) > 80, codes


@pytest.mark.parametrize("semidefinite", [False, True])
def test_solve_gram_bit_for_bit(semidefinite):
    bad, codes = [], {}
    for name, args in CASES:
        diff, code = compare_gram(args, semidefinite)
        codes[code] = codes.get(code, 0) + 1
        if diff:
            bad.append(f"{name}: " + "; ".join(diff))
    assert not bad, f"{len(bad)} of {len(CASES)}:\n" + "\n".join(bad[:20])
    assert codes.get(_core.QP_OK, 0) > 20, codes


def test_capped_runs_bit_for_bit():
    bad = []
    for name, args in CASES[::3]:
        for cap in (0, 1, 3):
            for diff, _ in (compare_solve(args, 0, cap), compare_gram(args, True, cap)):
                if diff:
                    bad.append(f"{name} cap {cap}: " + "; ".join(diff))
    assert not bad, "\n".join(bad[:20])


def test_screen_cholesky_kkt_bit_for_bit():
    bad = []
    for name, args in CASES:
        diff = compare_pieces(args)
        if diff:
            bad.append(f"{name}: " + "; ".join(diff))
    assert not bad, "\n".join(bad[:20])


def test_screen_refuses_alike():
    """Data that is not plainly valid (NaN, -inf in h, lb > ub, asymmetric P) or of
    mismatched shapes: screen says False on both, solve BAD_INPUT with the same bytes."""
    rng = np.random.default_rng(0)
    base = random_qp(5, 4, 1, rng)
    for k, bad in [(0, np.nan), (1, np.inf), (3, -np.inf), (3, np.nan), (5, np.nan), (6, np.inf),
                   (7, -np.inf), (0, 1.0)]:
        args = [np.array(a, dtype=float) for a in plain(base)]
        a = args[k]
        if a.ndim == 2:
            a[0, 1] += bad if k == 0 and bad == 1.0 else 0.0
            if not (k == 0 and bad == 1.0):
                a[0, 0] = bad
        else:
            a[0] = bad
        assert not _core.qp_screen(*args)[0]
        assert not compare_solve(args, 0)[0] and not compare_gram(args, False)[0]
    args = list(plain(base))
    args[3] = args[3][:-1]  # h one short
    assert not _core.qp_screen(*args)[0]
    assert not compare_solve(args, 0)[0]
    out = np.zeros(3)  # no room: BAD_INPUT, no write past the buffer
    assert _core.qp_solve(*plain(base), 0, -1, *TOL, out)[0] == BAD_INPUT
    with pytest.raises(ValueError):
        _core.qp_kkt_check(*plain(base), np.zeros(4), np.zeros(1), np.zeros(4), np.zeros(5), 1e-9,
                           np.zeros(4))


def test_dot4_in_a_fixed_order():
    """qp::dot4: each sum in linalg.cpp's dot's fixed order (eight lanes, no fused
    multiply-add), so its bits are the same on every host (recorded as the former
    linalg.dot gave them)."""
    rng = np.random.default_rng(1)
    for k in list(range(0, 80)) + [95, 96, 97, 127, 128, 129, 255, 300]:
        a = rng.standard_normal(k) * 10.0 ** rng.integers(-3, 3, k)
        rs = [rng.standard_normal(k) for _ in range(4)]
        frozen.check(np.array(_core.qp_dot4(a, *rs)), k)


def test_forward_rows_and_qr_rows():
    rng = np.random.default_rng(2)
    for n in (1, 3, 7, 20, 40, 70, 130):
        L = np.tril(rng.standard_normal((n, n))) + 3.0 * np.eye(n)
        for k in (1, 4, 5, 9, 13):
            R = rng.standard_normal((k, n))
            R[:, :n // 3] = 0.0

            def forward(fn):
                R1 = R.copy()
                fn(L, R1)
                return R1

            frozen.check(forward(_core.qp_forward_rows), ("forward_rows", n, k))
            if k <= n:
                def qr(fn):
                    W1, V1, b1 = R.copy(), np.zeros((k, n)), np.zeros(k)
                    return fn(W1, V1, b1), W1, V1, b1

                frozen.check(qr(_core.qp_qr_rows), ("qr_rows", n, k))


def test_unrevised_factored_bit_for_bit():
    """The unrevised method on M = Fs Fs' (M never formed): status, pivots and the bytes of
    x, the ray and the basic z's, as the frozen references record them."""
    count = 0
    for n in (1, 2, 5, 12, 30, 80, 200):
        for r in (1, 2, max(n // 4, 1), n, n + 3):
            for cap in (-1, 3):
                rng = np.random.default_rng([n, r, cap + 5])
                Fs = rng.standard_normal((n, r))
                q = rng.standard_normal(n) * 2.0 - 0.5
                d = np.ones(n) if n % 2 else rng.uniform(0.5, 2.0, n)
                mp = 100 * (n + 1) if cap < 0 else cap

                def run(solve):
                    x, ray, zb = np.full(n + 1, np.nan), np.full(n + 1, np.nan), np.zeros(n, bool)
                    st, piv = solve(Fs, d, q, mp, 1e-11, 1e-11, x, ray, zb)
                    return (int(st), int(piv)), x.tobytes(), ray.tobytes(), zb.tobytes()

                frozen.check(run(_core.unrevised_factored), (n, r, cap))
                count += 1
    assert count == 70


def test_gram_lcp_bit_for_bit():
    bad = 0
    for name, args in CASES:
        if not name.startswith(("gram", "random", "mm/DUALC")):
            continue
        n = args[1].shape[0]
        rng = np.random.default_rng(n)
        for p in (0, min(1, n - 1), n // 3):
            m = max(args[2].shape[0], 1)
            C = np.ascontiguousarray(np.vstack([args[2], rng.standard_normal((1, n))]))
            g = rng.standard_normal(C.shape[0]) - 0.2

            def run(fn):
                f = np.ones(C.shape[0], bool)
                r = fn(C, g, p, -1, 1e-11, 1e-11, f)
                return tuple(map(int, r)), f

            frozen.check(run(_core.qp_gram_lcp), (name, p))
            del m
    assert bad == 0


# ----------------------------------------------------------------------------- box-only QPs

def compare_box(args, warm=None, max_pivots=None):
    """_core.qp_solve_box on one box-only QP, every returned value and every byte of out and
    final checked against the frozen references: ([], the code)."""
    n = args[1].shape[0]
    warm = np.zeros(2 * n, bool) if warm is None else warm
    mp = 100 * (n + 1) if max_pivots is None else max_pivots
    rng = np.random.default_rng(n + 3)
    fill = rng.standard_normal(7 * n + 5)
    fill_final = rng.integers(-99, 99, 3 * n)

    def run(solve):
        out, final = fill.copy(), fill_final.copy()  # the same bytes where nothing is written
        ret = solve(*args, warm, mp, *TOL, out, final)
        return as_recorded(ret), out, final, int(ret[0])

    *r, code = run(_core.qp_solve_box)
    frozen.check(tuple(r), ("solve_box", mp))
    return [], code


def random_box(n, rng, kind, scale=1.0, definite=True):
    """A box-only QP of n variables: P definite (or of rank n // 2), bounds by kind (0 box,
    1 lower only, 2 upper only, 3 mixed with infinite and 1e20, 4 some fixed, 5 none)."""
    B = rng.standard_normal((n, n if definite else max(n // 2, 1)))
    P = scale * (B @ B.T / n + (0.05 * np.eye(n) if definite else 0.0))
    q = scale * 3.0 * rng.standard_normal(n)
    x0 = rng.standard_normal(n)
    lb, ub = x0 - rng.uniform(0.0, 1.0, n), x0 + rng.uniform(0.0, 1.0, n)
    if kind == 1:
        ub[:] = np.inf
    elif kind == 2:
        lb[:] = -np.inf
    elif kind == 3:
        lb[rng.random(n) < 0.4] = -np.inf
        ub[rng.random(n) < 0.3] = 1e20
        lb[rng.random(n) < 0.2] = -1e21
    elif kind == 4:
        fix = rng.random(n) < 0.3
        lb[fix] = ub[fix] = x0[fix]
    elif kind == 5:
        lb[:], ub[:] = -np.inf, np.inf
    return P, q, None, None, None, None, lb, ub


def box_families():
    """(name, box-only problem) with n < BOX_FIRST."""
    for n in range(1, _qp.BOX_FIRST):
        for kind in range(6):
            for t in range(3):
                rng = np.random.default_rng([n, kind, t])
                yield f"box/{n}/{kind}/{t}", random_box(n, rng, kind, scale=(1.0, 1e-3, 1e3)[t])
        rng = np.random.default_rng([n, 99])
        yield f"box_psd/{n}", random_box(n, rng, 0, definite=False)
    import test_qp
    for seed in range(60):  # test_qp's fuzz generator, without rows
        rng = np.random.default_rng(seed)
        n = int(rng.integers(1, _qp.BOX_FIRST))
        bounds = ("lower", "box", "mixed")[seed % 3]
        yield f"fuzz_box/{seed}", test_qp._fuzz_case(n, 0, 0, n if seed % 4 else n // 2, seed,
                                                     bounds, (1e-4, 1.0, 1e4)[seed % 3])
    for seed in range(12):  # test_qp.test_box_only_qps_through_the_box_kernel's QPs
        rng = np.random.default_rng(seed)
        n = int(rng.integers(1, 25))
        B = rng.standard_normal((n, n if seed % 3 else max(1, n // 2)))
        P = B @ B.T / n + (1e-2 * np.eye(n) if seed % 3 else 0.0)
        q = 3.0 * rng.standard_normal(n)
        lb = np.where(rng.random(n) < 0.8, -rng.uniform(0, 1, n), -np.inf)
        ub = np.where(rng.random(n) < 0.8, rng.uniform(0, 1, n), np.inf)
        lb[rng.random(n) < 0.1] = 0.0
        ub[lb == 0.0] = 0.0
        if seed % 3 == 0:
            lb[~np.isfinite(lb)] = -2.0
            ub[~np.isfinite(ub)] = 2.0
        if n < _qp.BOX_FIRST:
            yield f"test_qp_box/{seed}", (P, q, None, None, None, None, lb, ub)
    c = np.array([5.0, -5.0, 1.0, 2.0, 3.0, -4.0])  # test_upper_bounds_and_fixed_variables
    yield "fixed_and_one_sided", (np.eye(6), -c, None, None, None, None,
                                  np.array([0.0, -1.0, 0.5, -np.inf, -np.inf, -1e20]),
                                  np.array([1.0, 1.0, 0.5, np.inf, 2.0, 1e21]))
    yield "hs21_box", (np.diag([0.02, 2.0]), np.zeros(2), None, None, None, None,
                       np.array([2.0, -50.0]), np.array([50.0, 50.0]))
    for name, problem in families():  # the other families' box-only QPs
        P, q, G, h, A, b, lb, ub = problem
        if (G is None or np.size(G) == 0) and (A is None or np.size(A) == 0) and (
                lb is not None or ub is not None) and np.size(q) < _qp.BOX_FIRST:
            yield name, (P, q, None, None, None, None, lb, ub)


BOX_CASES = []
for _name, _problem in box_families():
    _args = plain(_problem)
    if _args is not None:
        BOX_CASES.append((_name, _args))


def test_solve_box_bit_for_bit():
    bad, codes = [], {}
    for name, args in BOX_CASES:
        diff, code = compare_box(args)
        codes[code] = codes.get(code, 0) + 1
        if diff:
            bad.append(f"{name}: " + "; ".join(diff))
    assert not bad, f"{len(bad)} of {len(BOX_CASES)}:\n" + "\n".join(bad[:20])
    assert len(BOX_CASES) > 300 and codes.get(_core.QP_OK, 0) > 250, codes
    assert codes.get(_core.QP_NOT_DEFINITE, 0) > 5, codes


def test_solve_box_warm_and_capped_bit_for_bit():
    """Warm starts (random basic and at-upper flags, and basic flags only) and pivot
    caps 0, 1, 3 (NOT_SOLVED runs: the bytes the run left)."""
    bad = 0
    count = 0
    for name, args in BOX_CASES[::2]:
        n = args[1].shape[0]
        rng = np.random.default_rng(n)
        warms = [rng.random(2 * n) < 0.3, np.concatenate([rng.random(n) < 0.5, np.zeros(n, bool)])]
        for cap in (0, 1, 3):
            diff, _ = compare_box(args, max_pivots=cap)
            bad += bool(diff)
            count += 1
        for warm in warms:
            diff, _ = compare_box(args, warm=warm)
            bad += bool(diff)
            count += 1
    assert bad == 0 and count > 200


def test_solve_box_refuses_alike():
    rng = np.random.default_rng(4)
    base = plain(random_box(5, rng, 0))
    for k, bad in [(0, np.nan), (1, np.inf), (6, np.nan), (6, np.inf), (7, -np.inf)]:
        args = [np.array(a, dtype=float) for a in base]
        if args[k].ndim == 2:
            args[k][0, 0] = bad
        else:
            args[k][0] = bad
        diff, code = compare_box(args)
        assert not diff and code == BAD_INPUT
    args = list(base)
    args[6] = args[6][:-1]  # lb one short: BAD_INPUT, nothing written
    diff, code = compare_box(args)
    assert not diff and code == BAD_INPUT
    with pytest.raises(ValueError):
        _core.qp_solve_box(*base, np.zeros(10, bool), 600, *TOL, np.empty(7 * 5 + 4),
                           np.empty(15, np.int64))


def test_box_basis_bit_for_bit():
    rng = np.random.default_rng(5)
    for n in (1, 3, 8, 15):
        for t in range(20):
            lo = np.where(rng.random(n) < 0.7, -rng.uniform(0, 1, n), -np.inf)
            up = np.where(rng.random(n) < 0.7, rng.uniform(0, 1, n), np.inf)
            fix = rng.random(n) < 0.15
            lo[fix] = up[fix] = 0.25
            perm = rng.permutation(n)
            m = int(rng.integers(0, n + 1))
            k = int(rng.integers(0, m + 1))
            final = np.concatenate([perm[:m], rng.integers(0, n, 3 * n - m)]).astype(np.int64)

            def run(fn):
                o = np.full(2 * n, -7, np.int64)
                return tuple(map(int, fn(lo, up, final, k, m, o))), o

            frozen.check(run(_core.qp_box_basis), (n, t))
