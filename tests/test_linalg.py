"""The core's own dense factorizations and scaling (src/lemke/linalg.*, bound in
lemke._core): single-threaded replacements for LAPACK, so that no solve starts a BLAS
thread pool, checked against LAPACK, exact arithmetic and a numpy reference."""
import numpy as np
import pytest

import lemke
from helpers import assert_lcp_solution
from lemke import _core, problems

EQUILIBRATE_SWEEPS = 16  # the most sweeps of lemke::equilibrate (src/lemke/linalg.cpp)


def _matrix(rng, k, kind):
    H = rng.standard_normal((k, k))
    if kind == "sparse":
        H[np.abs(H) < 1.0] = 0.0
    elif kind == "zero diagonal":  # every pivot needs a row exchange
        np.fill_diagonal(H, 0.0)
    elif kind == "graded":
        H *= np.logspace(-6, 6, k)[:, None]
    elif kind == "banded":  # pivot rows with few non-zeros: refined_solve's sparse updates
        H = np.triu(np.tril(H, 2), -2)
    return H


KINDS = ["dense", "sparse", "zero diagonal", "graded", "banded"]


@pytest.mark.parametrize("kind", KINDS)
def test_invert_in_place_matches_lapack(kind):
    rng = np.random.default_rng(11)
    for k in [1, 2, 3, 4, 7, 16, 33, 64, 101]:
        H = _matrix(rng, k, kind)
        cond = np.linalg.cond(H)
        if cond > 1e10:
            continue
        pad = k % 3
        G = np.full((k + pad, k + pad), 7.0)
        G[:k, :k] = H
        assert _core.invert_in_place(G, k)
        assert (G[k:] == 7.0).all() and (G[:, k:] == 7.0).all()  # only the block is touched
        ref = np.linalg.inv(H)
        tol = 50 * k * cond * np.finfo(float).eps
        assert np.abs(G[:k, :k] - ref).max() <= tol * np.abs(ref).max()


def _systems(seed, sizes, kind):
    """``(k, H, b, x_lapack, tol)`` for random systems of each size with cond(H) <= 1e10,
    tol the allowed max |x - x_lapack|."""
    rng = np.random.default_rng(seed)
    for k in sizes:
        H = _matrix(rng, k, kind)
        cond = np.linalg.cond(H)
        if cond > 1e10:
            continue
        b = rng.standard_normal(k)
        ref = np.linalg.solve(H, b)
        yield k, H, b, ref, 50 * k * cond * np.finfo(float).eps * np.abs(ref).max()


@pytest.mark.parametrize("kind", KINDS)
def test_solve_matches_lapack(kind):
    for k, H, b, ref, tol in _systems(12, [1, 2, 3, 5, 16, 40, 101], kind):
        H0, b0 = H.copy(), b.copy()
        ok, x = _core.linalg_solve(H, b)
        assert ok
        assert (H == H0).all() and (b == b0).all()
        assert np.abs(x - ref).max() <= tol


def test_empty_and_non_contiguous():
    assert _core.invert_in_place(np.empty((0, 0)), 0)
    ok, x = _core.linalg_solve(np.empty((0, 0)), np.empty(0))
    assert ok and x.shape == (0,)
    H = np.random.default_rng(13).standard_normal((10, 10))
    ok, x = _core.linalg_solve(H[::2, ::2], np.ones(5))
    assert ok
    np.testing.assert_allclose(H[::2, ::2] @ x, 1.0, rtol=1e-10)


SINGULAR_OR_NOT_FINITE = [
    np.zeros((3, 3)),
    np.array([[1.0, 2.0], [2.0, 4.0]]),
    np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [1.0, 2.0, 3.0]]),  # repeated row
    np.array([[np.nan, 1.0], [1.0, 1.0]]),
    np.array([[np.inf, 1.0], [1.0, 1.0]]),
    np.array([[1.0, 1.0], [1.0, -np.inf]]),
    np.array([[1e-310, 0.0], [0.0, 1.0]]),  # 1 / a denormal overflows
]


@pytest.mark.parametrize("H", SINGULAR_OR_NOT_FINITE)
def test_singular_or_not_finite_is_false_never_raises(H):
    k = H.shape[0]
    with np.errstate(all="ignore"):
        assert not _core.invert_in_place(H.copy(), k)
        ok, _ = _core.linalg_solve(H, np.ones(k))
    assert not ok


def test_bad_sizes_are_false():
    assert not _core.invert_in_place(np.eye(3), 4)
    assert not _core.invert_in_place(np.eye(3), -1)
    assert not _core.linalg_solve(np.eye(3), np.ones(2))[0]
    assert not _core.linalg_solve(np.ones((2, 3)), np.ones(2))[0]
    assert not _core.linalg_solve(np.eye(2), np.array([np.nan, 1.0]))[0]


@pytest.mark.parametrize("kind", KINDS)
def test_refined_solve_refines_with_one_factorization(kind):
    """Step 0 is :func:`linalg.solve` bit for bit on a dense matrix (the factors are kept,
    then reused by the refinement, which must reproduce the first solve's operations; a
    sparse one takes the sparse row updates); refining never moves x away from the exact
    solution (entry by entry in the max norm; its exact residual can grow by a unit in the
    last place of x, which is not what refinement minimizes: seen at k = 3 once the LU lost
    its fused multiply-adds) and brings x to LAPACK's within cond(H) eps; H and b are
    untouched."""
    for k, H, b, ref, tol in _systems(14, [1, 2, 3, 5, 16, 40, 75], kind):
        H0, b0 = H.copy(), b.copy()
        ok, x_plain = _core.linalg_solve(H, b)
        x0, x2 = np.empty(k), np.empty(k)
        assert _core.refined_solve(H, b, 0, x0, np.empty(k))
        assert _core.refined_solve(H, b, 2, x2, np.empty(k))
        assert (H == H0).all() and (b == b0).all()
        if kind == "dense":  # no sparse updates: the very operations of solve
            assert np.array_equal(x0, x_plain)
        assert np.abs(x0 - ref).max() <= tol and np.abs(x2 - ref).max() <= tol
        if k <= 16:
            exact = _solve_exact(H, b)
            assert np.abs(x2 - exact).max() <= np.abs(x0 - exact).max()


def _solve_exact(H, b):
    """The exact solution of H x = b (fractions, Gauss-Jordan), each entry then rounded."""
    from fractions import Fraction
    k = len(b)
    T = [[Fraction(H[i, j]) for j in range(k)] + [Fraction(b[i])] for i in range(k)]
    for j in range(k):
        p = next(i for i in range(j, k) if T[i][j] != 0)
        T[j], T[p] = T[p], T[j]
        for i in range(k):
            if i != j and T[i][j] != 0:
                f = T[i][j] / T[j][j]
                T[i] = [u - f * v for u, v in zip(T[i], T[j])]
    return np.array([float(T[i][k] / T[i][i]) for i in range(k)])


def test_refined_solve_reaches_the_rounding_of_the_answer():
    """On a Hilbert matrix (cond 1.5e10 at k = 8) one solve is off by about cond(H) eps; the
    refined x is the exact solution of the same rounded system to a few units in its last
    place (the residuals in double-double make that possible)."""
    k = 8
    H = 1.0 / (np.arange(k)[:, None] + np.arange(k)[None, :] + 1.0)
    b = H @ np.arange(1.0, k + 1.0)
    exact = _solve_exact(H, b)
    x0, x3, lo = np.empty(k), np.empty(k), np.empty(k)
    assert _core.refined_solve(H, b, 0, x0, lo) and _core.refined_solve(H, b, 3, x3, lo)
    eps = np.finfo(float).eps
    assert np.abs(x0 - exact).max() > 1e4 * eps * np.abs(exact).max()
    assert np.abs(x3 - exact).max() <= 4 * eps * np.abs(exact).max()


@pytest.mark.parametrize("H", SINGULAR_OR_NOT_FINITE)
def test_refined_solve_singular_or_not_finite_is_false(H):
    k = H.shape[0]
    with np.errstate(all="ignore"):
        assert not _core.refined_solve(H, np.ones(k), 2, np.empty(k), np.empty(k))
    lo2 = np.empty(2)
    assert not _core.refined_solve(np.eye(2), np.array([1.0, np.inf]), 2, np.empty(2), lo2)
    assert not _core.refined_solve(np.eye(3), np.ones(2), 2, np.empty(2), lo2)
    assert not _core.refined_solve(np.eye(2), np.ones(2), 2, np.empty(3), lo2)
    assert not _core.refined_solve(np.eye(2), np.ones(2), 2, np.empty(2), np.empty(3))
    given_inf = np.array([0.0, 0.0, np.inf])
    assert not _core.refined_solve(np.ones((2, 3)), np.ones(2), 2, given_inf, lo2)


def test_refined_solve_with_given_unknowns_is_the_full_solve():
    """K = [K1 | K2] with x2 given: the same x1, bit for bit, as the square system with the
    rows x2 = given appended (both converge to the rounding of the exact solution), and
    x1 + lo is that exact solution (checked against fractions)."""
    rng = np.random.default_rng(16)
    for k, j in [(1, 1), (3, 2), (6, 5), (9, 1)]:
        K = rng.standard_normal((k, k + j))
        rhs = rng.standard_normal(k)
        given = rng.standard_normal(j) * 1e3
        x, lo = np.empty(k + j), np.empty(k)
        x[k:] = given
        assert _core.refined_solve(K, rhs, 3, x, lo)
        assert (x[k:] == given).all()
        full = np.zeros((k + j, k + j))
        full[:k] = K
        full[k:, k:] = np.eye(j)
        xf, lof = np.empty(k + j), np.empty(k + j)
        assert _core.refined_solve(full, np.concatenate([rhs, given]), 3, xf, lof)
        assert np.array_equal(x[:k], xf[:k])
        from fractions import Fraction
        for r in range(k):  # K (x + lo) = rhs to about eps^2 of its terms, in exact arithmetic
            terms = [Fraction(K[r, c]) * (Fraction(x[c]) + (Fraction(lo[c]) if c < k else 0))
                     for c in range(k + j)]
            size = sum(abs(t) for t in terms) + abs(Fraction(rhs[r]))
            assert abs(sum(terms) - Fraction(rhs[r])) <= size * Fraction(1, 2**90)


def test_refactorization_keeps_the_methods_together():
    """Past 200 pivots the unrevised method refactors its block (by invert_in_place): on
    rank-deficient contact problems that need that, both methods still take the same
    pivots to answers that check.  (Since the shared pivoting rule, near-ties on these
    rank-deficient problems can end the two methods on different, equally valid bases: the
    exception the README describes; issue 11 keeps it open.)"""
    for k in range(3):
        M, q = problems.contact_like(300, np.random.default_rng([5, k]))
        a = lemke.solve_lcp(M, q, method="tableau")
        b = lemke.solve_lcp(M, q, method="unrevised")
        assert a.success and b.success
        assert a.pivots > 200 and b.pivots > 200
        assert max(a.pivots, b.pivots) <= 2 * 301 * min(a.pivots, b.pivots)
        assert_lcp_solution(M, q, a.z)
        assert_lcp_solution(M, q, b.z)


def _pow2_scale_reference(x):
    """The power of two nearest 1 / x by frexp/ldexp, in plain Python (the definition)."""
    import math

    if not (x > 0.0 and x < math.inf):
        return 1.0
    m, e = math.frexp(x)
    try:
        return math.ldexp(1.0, 1 - e) if m < 0.7071067811865476 else math.ldexp(1.0, -e)
    except OverflowError:  # 1 / (a subnormal): C's ldexp, which the kernel calls, gives inf
        return math.inf


def _ruiz_reference(M, q, sweeps=EQUILIBRATE_SWEEPS):
    """equilibrate's documented iteration in numpy (whole-matrix maxima; the scales by
    math.frexp/ldexp as lemke::equilibrate applies them), independent of the kernels."""
    import math

    def pow2(x):
        if not (0.0 < x < np.inf):
            return 1.0
        m, e = math.frexp(x)
        return math.ldexp(1.0, 1 - e) if m < 0.7071067811865476 else math.ldexp(1.0, -e)

    n = len(q)
    R, C = np.ones(n), np.ones(n)
    cq = pow2(float(np.abs(q).max(initial=0.0)))
    with np.errstate(all="ignore"):
        for _ in range(sweeps):
            A = (np.abs(M) * R[:, None]) * C[None, :]
            aq = np.abs(q) * R * cq
            rmax = np.maximum(A.max(axis=1, initial=0.0), aq)
            cmax = A.max(axis=0, initial=0.0)
            qmax = float(aq.max(initial=0.0))
            off = lambda v: (v > 0) & ((v < 0.5) | (v > 2.0))  # noqa: E731
            if not (qmax > 0 and (qmax < 0.5 or qmax > 2.0)) and not off(rmax).any() and not off(cmax).any():
                break
            R *= [pow2(math.sqrt(v)) for v in rmax]
            C *= [pow2(math.sqrt(v)) for v in cmax]
            cq *= pow2(math.sqrt(qmax))
    return R, C


def test_equilibrate_both_sweeps_match_the_reference():
    """The SIMD sweep (n >= SIMD_FROM; llvm.maxnum under no-NaN flags) and the plain one
    give the reference's scales bit for bit: sparse and dense, badly scaled, with
    subnormal and huge entries (scales that over- or underflow switch to the plain sweep)."""
    rng = np.random.default_rng(21)
    for t in range(400):
        n = int(rng.integers(1, 70))
        M = rng.standard_normal((n, n)) * (rng.random((n, n)) < rng.choice([0.05, 0.3, 1.0]))
        M *= np.exp(rng.normal(0, 6, (n, 1))) * np.exp(rng.normal(0, 6, n))
        if t % 5 == 0:
            M[rng.integers(0, n), rng.integers(0, n)] = rng.choice([1e308, -1e300, 1e-310, -0.0, 5e-324])
        q = rng.standard_normal(n) * np.exp(rng.normal(0, 6)) * (rng.random(n) < 0.7)
        R, C = np.empty(n), np.empty(n)
        _core.equilibrate(M, q, R, C)
        R0, C0 = _ruiz_reference(M, q)
        assert np.array_equal(R, R0) and np.array_equal(C, C0), (t, n)
