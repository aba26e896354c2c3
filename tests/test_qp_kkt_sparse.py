"""The KKT check over the matrices' nonzeros (``qp::kkt_check_sparse``, the sums the fused
kernel runs on its cached P, A, G: ``_core.qp_kkt_check(..., sparse=True)``) against the
dense check (``qp::kkt_check``): the same verdict and the same four statistics, bit for bit
(signed zeros included), on solved points, wrong points, points with zeros, -0.0, NaN and
Inf entries, data with -0.0 in q and exact cancellations, dense matrices as well as sparse
ones; and the fused kernel's own statistics (computed that way on its cache) against the
dense check of its answer.
"""
import os
import sys

import numpy as np
import pytest

from lemke import _core

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import mpc_problem  # noqa: E402

STRICT = 1e-12


def both(data, pt, tol):
    """(verdict, stats as int64 bits) of the dense and of the sparse check."""
    out = []
    for sparse in (False, True):
        st = np.full(4, np.nan)
        ok = bool(_core.qp_kkt_check(*data, *pt, tol, st, sparse=sparse))
        out.append((ok, st.view(np.int64).tolist()))
    return out


def fused(data, warm=None):
    """The fused kernel's code, (x, y, z, zb) and its stats (cold, or warm from a basis)."""
    P, q, G, h, A, b, lb, ub = data
    n, p, m = P.shape[0], A.shape[0], G.shape[0]
    out = np.empty(4 * n + p + 2 * m + 4)
    if warm is None:
        r = _core.qp_solve(*data, 0, -1, 1e-11, 1e-11, 1e-9, out)
    else:
        r = _core.qp_solve_warm(*data, 0, -1, 1e-11, 1e-11, 1e-9, out, *warm)
    o = np.cumsum([0, n, p, m, n, 4])
    return r, [out[o[k]:o[k + 1]].copy() for k in range(4)], out[o[4]:o[5]].copy()


def sparse_qp(rng, n, m, p, density):
    """A random strictly convex QP with sparse P (banded), G and A, bounds on some
    variables, some rows of G with h = +inf."""
    P = np.diag(rng.uniform(0.5, 2.0, n))
    for k in range(1, 3):
        off = 0.1 * rng.standard_normal(n - k) * (rng.random(n - k) < 0.5)
        P += np.diag(off, k) + np.diag(off, -k)
    mask = lambda r, c: rng.random((r, c)) < density  # noqa: E731
    G = rng.standard_normal((m, n)) * mask(m, n)
    A = rng.standard_normal((p, n)) * mask(p, n)
    for i in range(p):
        A[i, rng.integers(n)] = 1.0  # no empty equality
    x0 = rng.standard_normal(n)
    h = G @ x0 + rng.uniform(0.0, 1.0, m) * (rng.random(m) < 0.6)
    h[rng.random(m) < 0.15] = np.inf
    b = A @ x0
    lb = np.where(rng.random(n) < 0.5, x0 - rng.uniform(0.0, 1.0, n), -np.inf)
    ub = np.where(rng.random(n) < 0.5, x0 + rng.uniform(0.0, 1.0, n), np.inf)
    q = rng.standard_normal(n) * (rng.random(n) < 0.7)
    q[rng.random(n) < 0.2] = -0.0
    return P, q, G, h, A, b, lb, ub


def variants(pt, rng):
    """The point, and points with entries zeroed, negated to -0.0, moved, NaN or Inf."""
    yield pt
    for k in range(4):
        v = pt[k]
        if not v.size:
            continue
        for change in ("zero", "negzero", "move", "nan", "inf"):
            bad = [w.copy() for w in pt]
            i = int(rng.integers(v.size))
            bad[k][i] = {"zero": 0.0, "negzero": -0.0, "move": v[i] + 1e-3,
                         "nan": np.nan, "inf": np.inf}[change]
            yield bad
    yield [np.zeros_like(w) for w in pt]
    yield [-np.zeros_like(w) for w in pt]


def test_sparse_check_is_the_dense_one_bit_for_bit():
    rng = np.random.default_rng(11)
    count = 0
    for t in range(60):
        n = int(rng.integers(3, 30))
        data = sparse_qp(rng, n, int(rng.integers(0, 2 * n)), int(rng.integers(0, n // 2 + 1)),
                         (0.05, 0.3, 1.0)[t % 3])
        code, pt, _ = fused(data)
        for bad in variants(pt, rng):
            for tol in (STRICT, 1e-9):
                dense, sparse = both(data, bad, tol)
                assert dense == sparse, (t, tol)
                count += 1
        if code == 0:
            assert both(data, pt, STRICT)[0][0]
    assert count > 1000


def test_zero_stationarity_sums_after_P():
    """q_j = -0.0 and x_j = 0 (or x_j P_jj cancelling q_j exactly): the sums of the P pass end
    zero, where skipping terms can change a zero's sign (-0.0 kept where the dense sums
    reach +0.0); the gap and the objective that add them up, and the verdict, still agree
    bit for bit."""
    n = 6
    P = np.diag([2.0, 1.0, 4.0, 1.0, 1.0, 3.0])
    P[0, 1] = P[1, 0] = 0.5
    G = np.zeros((2, n))
    G[0, 2], G[1, 4] = 1.0, -1.0
    A = np.zeros((1, n))
    A[0, 5] = 1.0
    data = (P, np.array([-0.0, -0.0, -4.0, 0.0, -0.0, -0.0]), G, np.array([1.0, 0.0]), A,
            np.array([0.0]), np.full(n, -np.inf), np.full(n, np.inf))
    for x in ([0.0, 0.0, 1.0, 0.0, 0.0, 0.0], [-0.0, 0.0, 1.0, -0.0, 0.0, -0.0],
              [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]):
        for y in ([0.0], [-0.0], [1.0]):
            for z in ([0.0, 0.0], [0.0, -0.0], [1e-3, 0.0]):
                pt = [np.array(x), np.array(y), np.array(z), np.zeros(n)]
                for tol in (STRICT, 1e-9):
                    dense, sparse = both(data, pt, tol)
                    assert dense == sparse


def test_the_kernels_stats_are_the_dense_checks():
    """Every MPC step, cold and warm from the previous step's basis: the kernel's statistics
    (its check over the cached matrices' nonzeros) are the dense check's of its answer, bit
    for bit, and the answer passes."""
    (P, G, h, A, lb, ub), steps = mpc_problem.sequence(steps=40, seed=0)
    prev = None
    for q, b in steps:
        data = (P, q, G, h, A, b, lb, ub)
        for warm in (None, prev):
            r, pt, stats = fused(data, warm)
            assert r[0] == 0
            st = np.empty(4)
            assert _core.qp_kkt_check(*data, *pt, STRICT, st)
            assert st.view(np.int64).tolist() == stats.view(np.int64).tolist()
        n, p, m = P.shape[0], A.shape[0], G.shape[0]
        out = np.empty(4 * n + p + 2 * m + 4)
        code, _, k, pairs = _core.qp_solve(*data, 0, -1, 1e-11, 1e-11, 1e-9, out)
        basis = out[2 * n + p + m + 4:].view(np.int64)[:k].copy()
        prev = (basis, pairs)
