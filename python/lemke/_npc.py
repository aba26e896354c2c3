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
_add = np.add.reduce


def nz(mask):
    """``np.flatnonzero(mask)`` of a 1-D ``mask``."""
    return mask.nonzero()[0]


def sub(M, rows, cols):
    """``M[np.ix_(rows, cols)]`` (a copy) for 1-D integer index arrays: the same fancy
    index, the rows as a column."""
    return M[rows[:, None], cols]


def every(a) -> bool:
    """``np.all(a)`` (True when empty)."""
    return bool(_and(a, axis=None))


def some(a) -> bool:
    """``np.any(a)`` (False when empty)."""
    return bool(_or(a, axis=None))


def absmax(a) -> float:
    """``float(np.max(np.abs(a)))``, 0.0 for an empty ``a`` (NaN when it holds one)."""
    return float(_max(np.abs(a), axis=None)) if a.size else 0.0


def count(mask, axis=None):
    """``np.count_nonzero(mask, axis)`` of a boolean ``mask``."""
    return _add(mask, axis=axis, dtype=np.intp)


def filled(n, value, dtype=float):
    """``np.full(n, value)`` (``dtype``: float, or int for an int64 value)."""
    a = np.empty(n, dtype=dtype)
    a.fill(value)
    return a
