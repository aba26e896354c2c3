"""The Siconos MLCP files for the tests, read by the package's own reader
(:func:`lemke.read_problem`; the format is described in ``lemke/_io/siconos.py``)."""
from __future__ import annotations

import numpy as np

import lemke


def read_mlcp(path):
    """``(A, B, C, D, a, b)`` of the file (from its storage-2 part, which every shared file has)."""
    p = lemke.read_problem(path, format="dat")
    assert p.kind == "mlcp", f"{path} holds an {p.kind}"
    return tuple(np.array(x) for x in p.arrays_in_order())
