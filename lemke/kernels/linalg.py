"""Small dense kernels shared by the others.

Without permission to reorder a floating-point sum, a dot-product loop is one long
dependency chain and cannot use SIMD.  ``dot`` alone is compiled with the fastmath flags
``reassoc`` and ``contract`` (reordering and fused multiply-add; no flag that changes
comparisons, infinities or NaNs, which the pivoting rules depend on): about 5x faster, with
a different but equally accurate rounding order.
"""
import math

import numpy as np
from numba import njit

from . import kernel


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def dot(x, y, k):
    """sum_{j < k} x[j] * y[j]."""
    acc = 0.0
    for j in range(k):
        acc += x[j] * y[j]
    return acc


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def dot_and_size(x, y, k):
    """``(sum x[j] y[j], sum |x[j] y[j]|)`` over j < k: a row of M z and its size."""
    acc = 0.0
    size = 0.0
    for j in range(k):
        t = x[j] * y[j]
        acc += t
        size += abs(t)
    return acc, size


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def nan_probe(x, k):
    """sum_{j < k} 0 * x[j]: 0 when every x[j] is finite, NaN otherwise (reordering the sum
    changes neither)."""
    acc = 0.0
    for j in range(k):
        acc += 0.0 * x[j]
    return acc


@kernel
def finite_absmax(M):
    """``(finite, max|M|)`` in one pass over the rows of a square matrix."""
    n = M.shape[0]
    probe = 0.0
    m_max = 0.0
    for i in range(n):
        row = M[i]
        probe += nan_probe(row, n)
        m_max = max(m_max, absmax(row, n))
    return probe == 0.0, m_max


@kernel
def matvec(G, k, x, out):
    """out[:k] = G[:k, :k] x[:k]."""
    for r in range(k):
        out[r] = dot(G[r], x, k)


@kernel
def absmax(x, k):
    """max_{j < k} |x[j]| (0 for k = 0), with four running maxima (four short dependency
    chains instead of one long one)."""
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    j = 0
    while j + 4 <= k:
        m0 = max(m0, abs(x[j]))
        m1 = max(m1, abs(x[j + 1]))
        m2 = max(m2, abs(x[j + 2]))
        m3 = max(m3, abs(x[j + 3]))
        j += 4
    while j < k:
        m0 = max(m0, abs(x[j]))
        j += 1
    return max(max(m0, m1), max(m2, m3))


@kernel
def principal_block(M, idx):
    """The contiguous copy M[idx][:, idx]."""
    k = idx.shape[0]
    out = np.empty((k, k))
    for r in range(k):
        row = M[idx[r]]
        for c in range(k):
            out[r, c] = row[idx[c]]
    return out


@kernel
def axpy(y, a, x):
    """y += a x, over the length of y."""
    for j in range(y.shape[0]):
        y[j] += a * x[j]


@kernel
def pow2_scale(x):
    """The power of two nearest to 1 / x (x > 0), or 1 for x = 0 or x not finite: an exact
    scale factor (multiplying by it adds no rounding)."""
    if not (x > 0.0 and x < np.inf):
        return 1.0
    m, e = math.frexp(x)  # x = m 2**e, 0.5 <= m < 1
    return math.ldexp(1.0, 1 - e) if m < 0.7071067811865476 else math.ldexp(1.0, -e)


@kernel
def equilibrate(M, R, C):
    """Row and column scales of M, powers of two, so that every row and every column of
    diag(R) M diag(C) has its largest entry in [0.7, 1.42) (a zero row or column keeps
    scale 1): one pass for the rows, one for the columns (LAPACK's dgeequb recipe).  The
    scales are exact, and Lemke's path does not depend on them in exact arithmetic (every
    ratio and every lexicographic comparison is invariant under positive diagonal scaling);
    they make the kernels' relative tolerances mean the same in every row and column."""
    n = M.shape[0]
    for i in range(n):
        R[i] = pow2_scale(absmax(M[i], n))
    cmax = np.zeros(n)
    for i in range(n):
        r = R[i]
        row = M[i]
        for j in range(n):
            cmax[j] = max(cmax[j], abs(row[j]) * r)
    for j in range(n):
        C[j] = pow2_scale(cmax[j])


@kernel
def scaled_system(M, q, d, R, C):
    """``(A, qs, d_scale)``: A = [R M C | R d / d_scale] (n x (n + 1)) and qs = R q, the
    equilibrated system that every Lemke kernel works in (R, C from :func:`equilibrate`;
    d_scale = max |R d|, so that the artificial column has largest entry 1).  z' = z / C
    and z0' = z0 d_scale are its unknowns."""
    n = q.shape[0]
    d_scale = 0.0
    for i in range(n):
        d_scale = max(d_scale, abs(d[i]) * R[i])
    inv_d = 1.0 / d_scale
    A = np.empty((n, n + 1))
    qs = np.empty(n)
    for i in range(n):
        r = R[i]
        for j in range(n):
            A[i, j] = (M[i, j] * r) * C[j]
        A[i, n] = (d[i] * r) * inv_d
        qs[i] = q[i] * r
    return A, qs, d_scale
