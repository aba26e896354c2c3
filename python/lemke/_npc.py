"""numpy's C entry points for the steps of ``solve_qp`` after its native front (the
KKT-MLCP path, the semidefinite step, the checks): the same results as ``np.flatnonzero``,
``np[ix_]``, ``np.all``, ``np.max`` and ``np.count_nonzero``, without their Python wrappers
(numeric.py, fromnumeric.py, _methods.py, index_tricks).  Warm, a wrapper costs a
microsecond; in a process forked after ``import lemke`` its first call writes the
reference counts of its function, code and module objects, a copy-on-write page fault per
page (a forked child's first ``solve_qp`` of ZECEVIC2 took ~590 minor faults, ~1 ms).
Exact: indices, copies, comparisons and maxima, no arithmetic."""
from __future__ import annotations

import numpy as np

_and = np.logical_and.reduce
_or = np.logical_or.reduce
_max = np.maximum.reduce
_min = np.minimum.reduce
_add = np.add.reduce


def nz(mask):
    """``np.flatnonzero(mask)`` of a 1-D ``mask``."""
    return mask.nonzero()[0]


def _run(idx):
    """``idx`` as a slice when it is ``i, i + 1, ..., j - 1`` (else None)."""
    k = idx.size
    if k and idx[k - 1] - idx[0] == k - 1 and (k == 1 or _and(idx[1:] - idx[:-1] == 1)):
        return slice(int(idx[0]), int(idx[0]) + k)
    return None


def sub(M, rows, cols):
    """``M[np.ix_(rows, cols)]`` (a copy) for 1-D integer index arrays: a block copied
    by slices where both are runs of consecutive indices (numpy's fancy index reads about
    5 ns an entry: 0.8 ms on PRIMAL1's 325 x 325 P), else the same fancy index, the rows
    as a column."""
    r, c = _run(rows), _run(cols)
    if r is not None and c is not None:
        return M[r, c].copy()
    return M[rows[:, None], cols]


def every(a) -> bool:
    """``np.all(a)`` (True when empty)."""
    return bool(_and(a, axis=None))


def some(a) -> bool:
    """``np.any(a)`` (False when empty)."""
    return bool(_or(a, axis=None))


def absmax(a) -> float:
    """``float(np.max(np.abs(a)))``, 0.0 for an empty ``a`` (NaN when it holds one), as the
    larger of ``max(a)`` and ``-min(a)`` (exact): no temporary of a's size, whose fresh pages
    cost a minor fault each (PRIMAL1's dictionary, 410 x 411: 330 per call)."""
    if not a.size:
        return 0.0
    return abs(float(np.maximum(_max(a, axis=None), -_min(a, axis=None))))


def count(mask, axis=None):
    """``np.count_nonzero(mask, axis)`` of a boolean ``mask``."""
    return _add(mask, axis=axis, dtype=np.intp)


def filled(n, value, dtype=float):
    """``np.full(n, value)`` (``dtype``: float, or int for an int64 value)."""
    a = np.empty(n, dtype=dtype)
    a.fill(value)
    return a
