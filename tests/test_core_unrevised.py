"""The C++ unrevised method (``lemke._core.unrevised_solve``, src/lemke/unrevised.cpp) against
its frozen references (tests/frozen.py: the outputs of the kernel it was ported from), bit for bit: the status, the
pivots and the bytes of x (z and z0), the ray and the final basic z's, on the goldens' LCPs,
seeded random families (PSD, P-matrix, integer, contact-like) at n = 1..150 with several
tie_tol values, runs stopped by the pivot cap, and restarts from a warm basis (the covering
vector of the driver's restart)."""
import sys
from pathlib import Path

import numpy as np
import pytest

import frozen
from lemke import _core, problems

sys.path.insert(0, str(Path(__file__).parent))
import golden  # noqa: E402

PIVOT_TOL = 1e-11
TIE_TOLS = (1e-11, 0.0, 1e-9)
SIZES = (1, 2, 3, 5, 8, 13, 24, 48, 100, 150)


def scales(M, q):
    R, C = np.empty(q.shape[0]), np.empty(q.shape[0])
    _core.equilibrate(M, q, R, C)
    return R, C


def _run(solve, M, q, d, R, C, flags, max_pivots, pivot_tol, tie_tol):
    n = q.shape[0]
    x, ray, zb = np.full(n + 1, np.nan), np.full(n + 1, np.nan), np.zeros(n, np.bool_)
    status, pivots = solve(M, q, d, R, C, flags, max_pivots, pivot_tol, tie_tol, x, ray, zb)
    return int(status), int(pivots), x, ray, zb


def both(M, q, d, R, C, z_start, max_pivots, tie_tol, core_flags=np.bool_,
         pivot_tol=PIVOT_TOL, label=""):
    """The core on one problem: (status, pivots, x, ray, z_basic), every output checked
    against the frozen references."""
    out = _run(_core.unrevised_solve, M, q, d, R, C, z_start.astype(core_flags), max_pivots,
               pivot_tol, tie_tol)
    return frozen.check(out, label)


def families():
    """(name, M, q) seeded random problems with q not >= 0."""
    for n in SIZES:
        rng = np.random.default_rng([11, n])
        yield f"psd/{n}", *problems.random_psd(n, rng)
        yield f"p_matrix/{n}", *problems.random_p_matrix(n, rng)
        M = rng.integers(-4, 5, (n, n)).astype(float)
        M += M.T.copy() * (n % 2)  # odd n: symmetric integer matrices, even n: general ones
        yield f"integer/{n}", M, rng.integers(-5, 3, n).astype(float)
        if n >= 4:
            M, q = problems.contact_like(n, rng)
            yield f"contact/{n}", M, q - 0.5 * np.abs(q).max()


def _cases():
    for name, M, q in golden.lcp_cases():
        yield "golden/" + name, M, q
    yield from families()


CASES = [(name, np.ascontiguousarray(M, float), np.ascontiguousarray(q, float))
         for name, M, q in _cases()]
CASES = [c for c in CASES if not (c[2] >= 0.0).all()]  # q >= 0: the driver never pivots


def test_cold_runs_are_bitwise_equal():
    runs = 0
    for name, M, q in CASES:
        n = q.shape[0]
        R, C = scales(M, q)
        for tie_tol in TIE_TOLS:
            status, pivots, *_ = both(M, q, np.ones(n), R, C, np.zeros(n, np.bool_),
                                      100 * (n + 1), tie_tol, label=(name, tie_tol))
            runs += 1
            if tie_tol == TIE_TOLS[0] and pivots > 2:  # stopped halfway by the pivot cap
                both(M, q, np.ones(n), R, C, np.zeros(n, np.bool_), pivots // 2,
                     tie_tol, np.uint8, label=(name, "cap", pivots // 2))
                runs += 1
    assert runs > 300


def _restart_covering(M, z_start):
    """The covering vector of the driver's restart (lcp.cpp): c e_alpha - M[:, beta] 1, c = max|M|."""
    m_max = np.abs(M).max() if M.size else 0.0
    m_scale = m_max if m_max > 0.0 else 1.0
    beta = np.flatnonzero(z_start)
    cov = np.empty(M.shape[0])
    for i in range(M.shape[0]):
        acc = 0.0 if z_start[i] else m_scale
        for j in beta:  # the order of the restart's sum
            acc -= M[i, j]
        cov[i] = acc
    return cov


def test_restarts_are_bitwise_equal():
    """From the final basis of a solved problem, on q perturbed (a warm start after a step),
    with the restart's covering vector; contact problems give singular starting blocks
    (NUMERICAL_FAILURE with no pivot) too."""
    runs, warm = 0, 0
    for name, M, q in CASES:
        n = q.shape[0]
        R, C = scales(M, q)
        status, _, _, _, basis = both(M, q, np.ones(n), R, C, np.zeros(n, np.bool_),
                                      100 * (n + 1), 1e-11, label=name)
        if not basis.any():
            continue
        rng = np.random.default_rng([5, n, int(status)])
        for step in range(2):
            q2 = q + 0.05 * (np.abs(q).max() + 1.0) * rng.standard_normal(n)
            R2, C2 = scales(M, q2)
            cov = _restart_covering(M, basis)
            for tie_tol in (1e-11, 0.0):
                both(M, q2, cov, R2, C2, basis, 100 * (n + 1), tie_tol,
                     np.uint8 if step else np.bool_, label=(name, "restart", step, tie_tol))
                runs += 1
                warm += 1
    assert warm > 100


def test_hard_paths_are_bitwise_equal():
    """The paths the families above rarely take: past REFACTOR_EVERY pivots (Murty's
    problem, 2^n - 1 pivots), tiny update pivots and singular blocks mid-run (near-singular
    matrices with pivot_tol = 0: refactorizations, NUMERICAL_FAILURE), no usable first row
    (a covering vector that is not positive), non-finite entries and n = 0."""
    runs = []

    def check(name, M, q, d=None, pivot_tol=PIVOT_TOL, max_pivots=None):
        n = q.shape[0]
        R, C = scales(M, q)
        for tie_tol in (1e-11, 0.0):
            status, pivots, *_ = both(
                M, q, np.ones(n) if d is None else d, R, C, np.zeros(n, np.bool_),
                100 * (n + 1) if max_pivots is None else max_pivots, tie_tol,
                pivot_tol=pivot_tol, label=(name, tie_tol))
            runs.append((name, status, pivots))

    p = problems.murty(10)
    check("murty/10", np.array(p.M, float), np.array(p.q, float))
    check("murty/11 (the pivot cap)", *(np.array(a, float) for a in (problems.murty(11).M,
                                                             problems.murty(11).q)))
    for seed in range(60):
        rng = np.random.default_rng([99, seed])
        n = int(rng.integers(2, 12))
        V = rng.standard_normal((n, int(rng.integers(1, n + 1))))
        M = V @ V.T + 10.0 ** -rng.uniform(12, 17) * rng.standard_normal((n, n))
        check(f"near_singular/{seed}", M, rng.standard_normal(n), pivot_tol=0.0)
        M = rng.integers(-2, 3, (n, n)).astype(float)
        M[:, -1] = M[:, 0] + 1e-14 * rng.standard_normal(n)
        check(f"near_dependent/{seed}", M, rng.standard_normal(n) - 0.5, pivot_tol=0.0)
    M, q = problems.random_psd(6, np.random.default_rng(1))
    check("negative d", M, q, d=-np.ones(6))
    for value in (np.nan, np.inf, 1e308):
        M2 = M.copy()
        M2[:, 2] = value
        check(f"column of {value}", M2, q)
    check("n = 0", np.zeros((0, 0)), np.zeros(0))
    assert sum(p for _, _, p in runs) > 5000
    assert {s for _, s, _ in runs} >= {0, 1, 2, 3}


def test_binding_checks_sizes():
    M, q = np.eye(3), -np.ones(3)
    R, C = np.ones(3), np.ones(3)
    x, ray, zb = np.empty(4), np.empty(4), np.empty(3, np.uint8)
    status, pivots = _core.unrevised_solve(M, q, np.ones(3), R, C, np.empty(0, np.uint8), 100,
                                           1e-11, 1e-11, x, ray, zb)
    assert (status, pivots) == (0, 4) and np.array_equal(x, [1, 1, 1, 0])
    with pytest.raises(ValueError):
        _core.unrevised_solve(M, q, np.ones(2), R, C, np.empty(0, np.uint8), 100, 1e-11,
                              1e-11, x, ray, zb)
    with pytest.raises(ValueError):
        _core.unrevised_solve(M, q, np.ones(3), R, C, np.empty(0, np.uint8), 100, 1e-11,
                              1e-11, np.empty(3), ray, zb)
    with pytest.raises(ValueError):
        _core.unrevised_solve(M, q, np.ones(3), R, C, np.zeros(3, np.int32), 100, 1e-11,
                              1e-11, x, ray, zb)
