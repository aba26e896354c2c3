"""Read Siconos numerics LCP test files (``*.dat``) into dense numpy arrays.

Written for the tests from the format notes in ``tests/data/siconos/README.md``.  A file is a
stream of whitespace-separated tokens (line breaks mean nothing):

    n
    <matrix>            storage type, rows, columns, then the storage-specific part
    q_1 ... q_n
    [free text]         ignored

Two matrix storages occur in the LCP files:

* ``0`` dense: rows and columns repeated, then rows*columns values in COLUMN-MAJOR order
  (each printed line of a square matrix is a column of M, not a row);
* ``1`` sparse block: block-CSR whose blocks are dense and column-major.
"""
from __future__ import annotations

import numpy as np


class _Tokens:
    def __init__(self, text: str):
        self._items = text.split()
        self._at = 0

    def word(self) -> str:
        if self._at >= len(self._items):
            raise ValueError("unexpected end of file")
        item = self._items[self._at]
        self._at += 1
        return item

    def integer(self) -> int:
        return int(self.word())

    def numbers(self, count: int) -> np.ndarray:
        return np.array([float(self.word()) for _ in range(count)], dtype=float)


def _dense(tok: _Tokens, rows: int, cols: int) -> np.ndarray:
    again = (tok.integer(), tok.integer())
    if again != (rows, cols):
        raise ValueError(f"dense matrix sizes disagree: {(rows, cols)} then {again}")
    return tok.numbers(rows * cols).reshape((rows, cols), order="F")


def _sparse_block(tok: _Tokens, rows: int, cols: int) -> np.ndarray:
    M = np.zeros((rows, cols))
    nblocks = tok.integer()
    if nblocks == 0:
        return M
    block_rows, block_cols = tok.integer(), tok.integer()
    # cumulative sizes -> start offsets of each block row / block column
    row_end = [tok.integer() for _ in range(block_rows)]
    col_end = [tok.integer() for _ in range(block_cols)]
    if row_end[-1] != rows or col_end[-1] != cols:
        raise ValueError("block sizes do not add up to the matrix size")
    row_start = [0] + row_end[:-1]
    col_start = [0] + col_end[:-1]
    n_rowptr, n_colidx = tok.integer(), tok.integer()
    if n_rowptr != block_rows + 1 or n_colidx != nblocks:
        raise ValueError("block-CSR index array lengths do not match the block counts")
    rowptr = [tok.integer() for _ in range(n_rowptr)]
    colidx = [tok.integer() for _ in range(n_colidx)]
    for bi in range(block_rows):
        for k in range(rowptr[bi], rowptr[bi + 1]):
            if tok.integer() != k:
                raise ValueError(f"block {k} is out of order")
            bj = colidx[k]
            r0, r1 = row_start[bi], row_end[bi]
            c0, c1 = col_start[bj], col_end[bj]
            h, w = r1 - r0, c1 - c0
            M[r0:r1, c0:c1] = tok.numbers(h * w).reshape((h, w), order="F")
    return M


def _matrix(tok: _Tokens) -> np.ndarray:
    storage, rows, cols = tok.integer(), tok.integer(), tok.integer()
    if storage == 0:
        return _dense(tok, rows, cols)
    if storage == 1:
        return _sparse_block(tok, rows, cols)
    raise ValueError(f"matrix storage type {storage} is not supported")


def read_lcp(path) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(M, q)`` of the Siconos LCP file at ``path`` (dense float arrays)."""
    with open(path) as fh:
        tok = _Tokens(fh.read())
    n = tok.integer()
    M = _matrix(tok)
    if M.shape != (n, n):
        raise ValueError(f"M has shape {M.shape}, expected {(n, n)}")
    q = tok.numbers(n)
    return M, q
