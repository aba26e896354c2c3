"""The C++ QP kernels (``lemke._core.qp_*``, src/lemke/qp.cpp) against the numba kernels
(``kernels.qp``) as their oracle, bit for bit: every returned number and every byte of the
output buffers of ``solve`` (both methods), ``solve_gram`` (definite and semidefinite),
``screen``, ``cholesky`` and ``kkt_check``, and of the pieces whose bits they depend on
(``_dot4`` as numba vectorizes it, ``forward_rows``, ``qr_rows``, ``gram_lcp`` and the
unrevised method in factored form), on the Maros-Meszaros files, the QP tests' generators
(tests/test_qp.py, test_qp_gram.py, test_qp_conventions.py) and random dense convex QPs:
equalities, inequalities, finite and infinite bounds, fixed variables, P definite and
semidefinite, and many inequalities (m >= 4n) for the factored path."""
import sys
from pathlib import Path

import numpy as np
import pytest

from lemke import _core, _qp
from lemke.kernels import kernel, linalg, qp as kqp, unrevised

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "maros-meszaros"
sys.path.insert(0, str(HERE.parent / "benchmarks"))
sys.path.insert(0, str(HERE))
from maros_meszaros import load  # noqa: E402

TOL = (1e-11, 1e-11, 1e-9)  # pivot_tol, tie_tol, tol: the defaults


def plain(problem):
    """The fused kernels' arguments (``_qp._plain_args``), or None."""
    return _qp._plain_args(*problem)


def _bytes_diff(name, a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.tobytes() != b.tobytes():
        return [f"{name}: numba {a.ravel()[:4]} core {b.ravel()[:4]}"]
    return []


def compare_solve(args, method, max_pivots=-1):
    """kqp.solve and _core.qp_solve on one problem: the mismatches (empty: the same bits)
    and numba's code."""
    n, p, m = args[1].shape[0], args[4].shape[0], args[2].shape[0]
    fill = np.random.default_rng(n + 7 * m + 31 * p).standard_normal(4 * n + p + 2 * m + 4)
    outs = []
    for run in (kqp.solve, _core.qp_solve):
        out = fill.copy()  # the same bytes where neither writes
        ret = run(*args, method, max_pivots, *TOL, out)
        outs.append((tuple(int(v) for v in ret), out))
    (r1, o1), (r2, o2) = outs
    diff = [] if r1 == r2 else [f"returns numba {r1} core {r2}"]
    return diff + _bytes_diff("out", o1, o2), r1[0]


def compare_gram(args, semidefinite, max_pivots=-1):
    n, p, m = args[1].shape[0], args[4].shape[0], args[2].shape[0]
    fill = np.random.default_rng(n + 5 * m + 17 * p).standard_normal(4 * n + p + 2 * m + 4)
    outs = []
    for run in (kqp.solve_gram, _core.qp_solve_gram):
        out = fill.copy()
        basic = out[2 * n + p + m + 4:].view(np.int64)  # as _qp: the basis in out's tail
        ret = run(*args, *([max_pivots] + list(TOL)), out, basic, semidefinite)
        outs.append((tuple(int(v) for v in ret), out))
    (r1, o1), (r2, o2) = outs
    diff = [] if r1 == r2 else [f"returns numba {r1} core {r2}"]
    return diff + _bytes_diff("out", o1, o2), r1[0]


def compare_pieces(args):
    """screen, cholesky and kkt_check (at the solve's point, and a perturbed one)."""
    diff = []
    s1, s2 = kqp.screen(*args), _core.qp_screen(*args)
    if bool(s1[0]) != bool(s2[0]):
        return [f"screen numba {s1[0]} core {s2[0]}"]
    if not s1[0]:
        return []
    for name, a, b in zip(("Ps", "lo", "up"), s1[1:], s2[1:]):
        diff += _bytes_diff(name, a, b)
    Ps, lo, up = s1[1:]
    L1, L2 = np.full_like(Ps, 7.0), np.full_like(Ps, 7.0)
    c1, c2 = kqp.cholesky(Ps, L1), _core.qp_cholesky(Ps, L2)
    if bool(c1) != bool(c2):
        diff.append(f"cholesky numba {c1} core {c2}")
    diff += _bytes_diff("L", L1, L2)
    n, p, m = args[1].shape[0], args[4].shape[0], args[2].shape[0]
    out = np.zeros(4 * n + p + 2 * m + 4)
    kqp.solve(*args, 0, -1, *TOL, out)
    x, y, z, zb = out[:n], out[n:n + p], out[n + p:n + p + m], out[n + p + m:2 * n + p + m]
    rng = np.random.default_rng(n)
    for pert in (0.0, 1e-9):
        pt = [v * (1.0 + pert * rng.standard_normal(v.shape)) for v in (x, y, z, zb)]
        st1, st2 = np.empty(4), np.empty(4)
        k1 = kqp.kkt_check(Ps, args[1], args[2], args[3], args[4], args[5], lo, up, *pt, 1e-9, st1)
        k2 = _core.qp_kkt_check(Ps, args[1], args[2], args[3], args[4], args[5], lo, up, *pt, 1e-9,
                                st2)
        if bool(k1) != bool(k2):
            diff.append(f"kkt_check numba {k1} core {k2}")
        diff += _bytes_diff("stats", st1, st2)
    return diff


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
    assert codes.get(kqp.OK, 0) > 80, codes


@pytest.mark.parametrize("semidefinite", [False, True])
def test_solve_gram_bit_for_bit(semidefinite):
    bad, codes = [], {}
    for name, args in CASES:
        diff, code = compare_gram(args, semidefinite)
        codes[code] = codes.get(code, 0) + 1
        if diff:
            bad.append(f"{name}: " + "; ".join(diff))
    assert not bad, f"{len(bad)} of {len(CASES)}:\n" + "\n".join(bad[:20])
    assert codes.get(kqp.OK, 0) > 20, codes


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
        assert not kqp.screen(*args)[0] and not _core.qp_screen(*args)[0]
        assert not compare_solve(args, 0)[0] and not compare_gram(args, False)[0]
    args = list(plain(base))
    args[3] = args[3][:-1]  # h one short
    assert not _core.qp_screen(*args)[0]
    assert not compare_solve(args, 0)[0]
    out = np.zeros(3)  # no room: BAD_INPUT, no write past the buffer
    assert _core.qp_solve(*plain(base), 0, -1, *TOL, out)[0] == kqp.BAD_INPUT
    with pytest.raises(ValueError):
        _core.qp_kkt_check(*plain(base), np.zeros(4), np.zeros(1), np.zeros(4), np.zeros(5), 1e-9,
                           np.zeros(4))


def test_dot4_as_numba_vectorizes_it():
    rng = np.random.default_rng(1)
    for k in list(range(0, 80)) + [95, 96, 97, 127, 128, 129, 255, 300]:
        a = rng.standard_normal(k) * 10.0 ** rng.integers(-3, 3, k)
        rs = [rng.standard_normal(k) for _ in range(4)]
        assert np.array(kqp._dot4(a, *rs)).tobytes() == np.array(_core.qp_dot4(a, *rs)).tobytes(), k


def test_forward_rows_and_qr_rows():
    rng = np.random.default_rng(2)
    for n in (1, 3, 7, 20, 40, 70, 130):
        L = np.tril(rng.standard_normal((n, n))) + 3.0 * np.eye(n)
        for k in (1, 4, 5, 9, 13):
            R = rng.standard_normal((k, n))
            R[:, :n // 3] = 0.0
            R1, R2 = R.copy(), R.copy()
            kqp.forward_rows(L, R1)
            _core.qp_forward_rows(L, R2)
            assert R1.tobytes() == R2.tobytes(), (n, k)
            if k <= n:
                W1, W2 = R.copy(), R.copy()
                V1, V2 = np.zeros((k, n)), np.zeros((k, n))
                b1, b2 = np.zeros(k), np.zeros(k)
                assert kqp.qr_rows(W1, V1, b1) == _core.qp_qr_rows(W2, V2, b2)
                for a, b in ((W1, W2), (V1, V2), (b1, b2)):
                    assert a.tobytes() == b.tobytes(), (n, k)


@kernel
def numba_factored(Fs, d, q, max_pivots, pivot_tol, tie_tol, x, ray, zb):
    return unrevised.lemke(d.reshape((d.shape[0], 1)), Fs, q, linalg.false_flags(q.shape[0]),
                           linalg.no_matrix(), max_pivots, pivot_tol, tie_tol, x, ray, zb)


def test_unrevised_factored_bit_for_bit():
    """The unrevised method on M = Fs Fs' (numba's unrevised.lemke with Fs) against the
    core's: status, pivots and the bytes of x, the ray and the basic z's."""
    count = 0
    for n in (1, 2, 5, 12, 30, 80, 200):
        for r in (1, 2, max(n // 4, 1), n, n + 3):
            for cap in (-1, 3):
                rng = np.random.default_rng([n, r, cap + 5])
                Fs = rng.standard_normal((n, r))
                q = rng.standard_normal(n) * 2.0 - 0.5
                d = np.ones(n) if n % 2 else rng.uniform(0.5, 2.0, n)
                mp = 100 * (n + 1) if cap < 0 else cap
                outs = []
                for run in (numba_factored, _core.unrevised_factored):
                    x, ray, zb = np.full(n + 1, np.nan), np.full(n + 1, np.nan), np.zeros(n, bool)
                    st, piv = run(Fs, d, q, mp, 1e-11, 1e-11, x, ray, zb)
                    outs.append(((int(st), int(piv)), x.tobytes(), ray.tobytes(), zb.tobytes()))
                assert outs[0] == outs[1], (n, r, cap)
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
            f1, f2 = np.ones(C.shape[0], bool), np.ones(C.shape[0], bool)
            r1 = kqp.gram_lcp(C, g, p, -1, 1e-11, 1e-11, f1)
            r2 = _core.qp_gram_lcp(C, g, p, -1, 1e-11, 1e-11, f2)
            bad += (tuple(map(int, r1)) != tuple(r2)) or f1.tobytes() != f2.tobytes()
            del m
    assert bad == 0
