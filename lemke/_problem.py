"""Validation and coercion of user input, done once at the boundary.

The arrays returned are float64; they are the caller's own arrays when those already are
float64 (no copy), so the solver treats them as read-only and never writes to them.
"""
from __future__ import annotations

import numpy as np


def _to_float_array(x, name: str) -> np.ndarray:
    if hasattr(x, "toarray") and hasattr(x, "nnz"):  # scipy.sparse: densified for now
        x = x.toarray()
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None
    if a.dtype.kind not in "fiub":  # float, int, unsigned, bool
        raise TypeError(f"{name} must hold real numbers, got dtype {a.dtype}")
    if a.dtype != np.float64:
        a = a.astype(np.float64)
    if not np.isfinite(a).all():
        bad = np.argwhere(~np.isfinite(a))[0]
        raise ValueError(f"{name} has a NaN or infinite entry at index {tuple(int(i) for i in bad)}")
    return a


def as_matrix(M, name: str = "M") -> np.ndarray:
    """A square float64 copy of ``M`` (dense or scipy.sparse)."""
    a = _to_float_array(M, name)
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ValueError(f"{name} must be a square 2-D matrix, got shape {a.shape}")
    return np.ascontiguousarray(a)


def as_vector(v, n: int, name: str) -> np.ndarray:
    """A float64 copy of ``v``, which must have shape (n,)."""
    a = _to_float_array(v, name)
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},) to match M, got shape {a.shape}")
    return a


def as_lcp(M, q, d=None):
    """Validate an LCP: returns float64 copies ``(M, q, d)``; ``d`` is None when not given."""
    M = as_matrix(M)
    n = M.shape[0]
    q = as_vector(q, n, "q")
    if d is not None:
        d = as_vector(d, n, "d")
        if n and not np.all(d > 0):
            raise ValueError(f"the covering vector d must be positive; d[{int(np.argmin(d))}] = {d.min()}")
    return M, q, d
