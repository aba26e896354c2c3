"""The QP kernels' Cholesky factor and substitutions on matrices with leading zeros (P's
profile: diagonal, banded, arrow-shaped, with -0.0 entries): ``_core.qp_cholesky`` and
``_core.qp_forward_rows`` skip the eight-lane blocks left of a row's first nonzero, and
must give the bits of the plain row-by-row loops, which this file states in Python (IEEE
double arithmetic, no fused multiply-add: linalg's dot order of eight lanes, the tail in
lane 0, the pairwise sum)."""
import math

import numpy as np
import pytest

from lemke import _core

DEFINITE_TOL = 1e-12  # qp.hpp


def dot_lanes(x, y, k):
    a = [0.0] * 8
    j = 0
    while j + 8 <= k:
        for lane in range(8):
            a[lane] += x[j + lane] * y[j + lane]
        j += 8
    while j < k:
        a[0] += x[j] * y[j]
        j += 1
    return ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))


def cholesky_reference(P):
    """(ok, L) of the row-by-row loop: every entry from the whole dot, no skipping."""
    n = P.shape[0]
    Pl = P.tolist()
    top = max(Pl[j][j] for j in range(n))
    floor = DEFINITE_TOL * top
    L = [[0.0] * n for _ in range(n)]
    for i in range(n):
        for j in range(i):
            L[i][j] = (Pl[i][j] - dot_lanes(L[i], L[j], j)) / L[j][j]
        d = Pl[i][i] - dot_lanes(L[i], L[i], i)
        if not d > floor:
            return False, None
        L[i][i] = math.sqrt(d)
    return True, np.array(L)


def forward_rows_reference(L, R):
    """forward_rows' loops: rows by fours from their common first nonzero column s (each
    entry times 1 / L_jj), the rows left over one by one (divided by L_jj)."""
    n, k = L.shape[0], R.shape[0]
    Ll = L.tolist()
    rows = [list(r) for r in R.tolist()]
    i = 0
    while i + 4 <= k:
        block = rows[i:i + 4]
        s = 0
        while s < n and all(r[s] == 0.0 for r in block):
            s += 1
        for j in range(s, n):
            inv = 1.0 / Ll[j][j]
            for r in block:
                r[j] = (r[j] - dot_lanes(Ll[j][s:], r[s:], j - s)) * inv
        i += 4
    for r in rows[i:]:
        s = 0
        while s < n and r[s] == 0.0:
            s += 1
        for j in range(s, n):
            r[j] = (r[j] - dot_lanes(Ll[j][s:], r[s:], j - s)) / Ll[j][j]
    return np.array(rows).reshape(R.shape)


def bits(a):
    return np.asarray(a, dtype=np.float64).tobytes()


def profiled(kind, n, rng):
    """A positive definite P with leading zeros in its rows, some of them -0.0."""
    if kind == "diagonal":
        P = np.diag(rng.uniform(0.5, 3.0, n))
    elif kind == "banded":
        B = np.zeros((n, n))
        for i in range(n):
            lo = max(0, i - 3)
            B[i, lo:i + 1] = rng.standard_normal(i + 1 - lo)
        P = B @ B.T + np.eye(n)
    elif kind == "arrow":  # diagonal but for the last rows, dense
        P = np.diag(rng.uniform(1.0, 2.0, n))
        k = min(3, n - 1)
        if k:
            W = rng.standard_normal((k, n)) * 0.1
            P[-k:, :] += W
            P[:, -k:] += W.T
            P[-k:, -k:] = W[:, -k:] @ W[:, -k:].T + 4.0 * n * np.eye(k)
    else:  # blocks: rows whose nonzeros start at varying columns
        P = np.eye(n) * 2.0
        for i in range(n):
            start = int(rng.integers(0, i + 1))
            v = rng.standard_normal(i - start) * 0.2 / max(1, i - start)
            P[i, start:i] += v
            P[start:i, i] += v
        P += n * 0.05 * np.eye(n)
    zeros = np.argwhere((P == 0.0) & (rng.random(P.shape) < 0.3))
    for i, j in zeros:  # some zeros negative, symmetrically
        P[i, j] = P[j, i] = -0.0
    return P


@pytest.mark.parametrize("kind", ["diagonal", "banded", "arrow", "blocks"])
@pytest.mark.parametrize("n", [1, 5, 9, 17, 40, 71])
def test_cholesky_with_leading_zeros(kind, n):
    rng = np.random.default_rng([n, len(kind)])
    P = profiled(kind, n, rng)
    ok, L_ref = cholesky_reference(P)
    assert ok
    L = np.full_like(P, 7.0)
    assert _core.qp_cholesky(P, L)
    assert bits(L) == bits(L_ref), kind
    assert np.array_equal(np.signbit(L), np.signbit(L_ref))  # the zeros' signs too
    np.testing.assert_allclose(L @ L.T, P, rtol=1e-12, atol=1e-12)  # a factor indeed


@pytest.mark.parametrize("kind", ["diagonal", "banded", "arrow", "blocks"])
@pytest.mark.parametrize("n, k", [(9, 5), (17, 9), (40, 13), (71, 4)])
def test_forward_rows_with_leading_zeros(kind, n, k):
    rng = np.random.default_rng([n, k, len(kind)])
    P = profiled(kind, n, rng)
    L = np.full_like(P, 7.0)
    assert _core.qp_cholesky(P, L)
    R = rng.standard_normal((k, n))
    R[:, : n // 3] = 0.0
    R[0, n // 3:n // 2] = -0.0
    ref = forward_rows_reference(L, R)
    out = R.copy()
    _core.qp_forward_rows(L, out)
    assert bits(out) == bits(ref), kind
    np.testing.assert_allclose(L @ out.T, R.T, rtol=1e-9, atol=1e-9)  # L^-1 R indeed


def test_cholesky_fails_where_the_loop_fails():
    """A zero diagonal entry after rows with leading zeros: not definite, as the loop says."""
    P = np.diag([1.0, 2.0, 0.0, 3.0])
    assert not cholesky_reference(P)[0]
    assert not _core.qp_cholesky(P, np.empty_like(P))
