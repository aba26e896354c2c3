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
def scaled_system(M, q, d, m_scale):
    """``(A, qs, d_scale)``: A = [M / m_scale | d / d_scale] (n x (n + 1)) and
    qs = q / m_scale, in the units where max|M| = 1 and max|d| = 1 that every Lemke kernel
    works in (so the relative tolerances compare like with like, and multiplying M and q
    by a constant changes nothing).  ``m_scale`` is max|M|, or 1 when M = 0.  The divisions
    are multiplications by the reciprocal (a division costs ten times more)."""
    n = q.shape[0]
    d_scale = absmax(d, n)
    inv_m = 1.0 / m_scale
    inv_d = 1.0 / d_scale
    A = np.empty((n, n + 1))
    qs = np.empty(n)
    for i in range(n):
        for j in range(n):
            A[i, j] = M[i, j] * inv_m
        A[i, n] = d[i] * inv_d
        qs[i] = q[i] * inv_m
    return A, qs, d_scale
