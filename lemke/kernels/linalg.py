"""Small dense kernels shared by the others.

Without permission to reorder a floating-point sum, a dot-product loop is one long
dependency chain and cannot use SIMD.  ``dot`` alone is compiled with the fastmath flags
``reassoc`` and ``contract`` (reordering and fused multiply-add; no flag that changes
comparisons, infinities or NaNs, which the pivoting rules depend on): about 5x faster, with
a different but equally accurate rounding order.
"""
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
def axpy4(y, a0, x0, a1, x1, a2, x2, a3, x3):
    """Four axpy's in one pass over y, with the roundings of four in a row: each y[j] is
    loaded and stored once instead of four times."""
    for j in range(y.shape[0]):
        y[j] = (((y[j] + a0 * x0[j]) + a1 * x1[j]) + a2 * x2[j]) + a3 * x3[j]


@kernel
def scaled_system(M, q, d):
    """``(A, qs, m_scale, d_scale)``: A = [M / m_scale | d / d_scale] (n x (n + 1)) and
    qs = q / m_scale, in the units where max|M| = 1 and max|d| = 1 that every Lemke kernel
    works in (so the relative tolerances compare like with like, and multiplying M and q
    by a constant changes nothing)."""
    n = q.shape[0]
    m_scale = 0.0
    for i in range(n):
        m_scale = max(m_scale, absmax(M[i], n))
    if m_scale == 0.0:
        m_scale = 1.0
    d_scale = absmax(d, n)
    A = np.empty((n, n + 1))
    qs = np.empty(n)
    for i in range(n):
        for j in range(n):
            A[i, j] = M[i, j] / m_scale
        A[i, n] = d[i] / d_scale
        qs[i] = q[i] / m_scale
    return A, qs, m_scale, d_scale
