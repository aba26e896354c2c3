"""Read Siconos numerics MLCP test files (``*_mlcp.dat``) for the tests.

Layout (``tests/data/siconos/README.md``): ``isStorageType1 isStorageType2 n m``; with storage
1, the cumulative block row offsets (read until one is >= n + m), one "is complementarity"
flag per block, a matrix M in the LCP files' format and its q; with storage 2, the blocks
A (n x n), B (m x m), C (n x m), D (m x n) each ROW-MAJOR, then a (n) and b (m).
"""
from __future__ import annotations

from siconos_dat import _matrix, _Tokens


def read_mlcp(path):
    """``(A, B, C, D, a, b)`` of the file's storage-2 part (every shared file has it)."""
    with open(path) as fh:
        tok = _Tokens(fh.read())
    storage1, storage2, n, m = (tok.integer() for _ in range(4))
    if storage1:
        offsets = [tok.integer()]
        while offsets[-1] < n + m:
            offsets.append(tok.integer())
        [tok.integer() for _ in range(len(offsets) - 1)]  # the blocks' complementarity flags
        M = _matrix(tok)
        tok.numbers(M.shape[1])
    if not storage2:
        raise ValueError(f"{path}: no storage-2 part (A, B, C, D, a, b)")
    A = tok.numbers(n * n).reshape(n, n)
    B = tok.numbers(m * m).reshape(m, m)
    C = tok.numbers(n * m).reshape(n, m)
    D = tok.numbers(m * n).reshape(m, n)
    a = tok.numbers(n)
    b = tok.numbers(m)
    return A, B, C, D, a, b
