"""The Siconos LCP files for the tests, read by the package's own reader
(:func:`lemke.read_problem`; the format is described in ``lemke/_io/siconos.py``)."""
from __future__ import annotations

import numpy as np

import lemke


def read_lcp(path) -> tuple[np.ndarray, np.ndarray]:
    """``(M, q)`` of the Siconos LCP file at ``path`` (dense float arrays)."""
    p = lemke.read_problem(path, format="dat")
    assert p.kind == "lcp", f"{path} holds an {p.kind}"
    return np.array(p.M), np.array(p.q)
