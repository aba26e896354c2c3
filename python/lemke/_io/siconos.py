"""Siconos numerics ``.dat`` files: LCP and MLCP (written from the format notes in
``tests/data/siconos/README.md``; no Siconos code).

A file is a stream of whitespace-separated tokens; line breaks mean nothing.

LCP::

    n
    <matrix M>          storage type, rows, columns, then the storage's part (below)
    q_1 ... q_n
    [free text]         ignored

MLCP (u free, v >= 0; storage 1: M [u; v] + q = [0; w]; storage 2: A u + C v + a = 0,
w = D u + B v + b, 0 <= v _|_ w >= 0)::

    isStorageType1 isStorageType2 n m
    [storage 1]  cumulative row offsets up to n + m, one 0/1 flag per block (0 = equalities),
                 <matrix M>, then q (as many numbers as M has columns)
    [storage 2]  A (n x n), B (m x m), C (n x m), D (m x n), each ROW BY ROW, then a, b
    [anything]   ignored

Matrix storage ``0`` (dense): rows and columns repeated, then the values in COLUMN-MAJOR order
(each printed line of a square matrix is a column).  Storage ``1`` (sparse block): block CSR
with dense, column-major blocks.  Storage 2 (sparse) is not supported.

An MLCP is read from its storage-2 part when the file has one (it is Lemke's form), else by
splitting M into [[A, C], [D, B]] (equality rows first).  Writing gives dense storage; MLCPs are
written with both storages, as Siconos does.
"""
from __future__ import annotations

import numpy as np

from .._problem import Problem
from .common import BadFile, check_size, make_problem

KINDS = ("lcp", "mlcp", "blcp")  # the kinds of problem this format holds
LCP, MLCP, BLCP = KINDS


class _Tokens:
    def __init__(self, text: str):
        self.items = text.split()
        self.at = 0

    def word(self, what: str) -> str:
        if self.at >= len(self.items):
            raise BadFile(f"the file ends early (truncated?): expected {what}")
        self.at += 1
        return self.items[self.at - 1]

    def integer(self, what: str) -> int:
        word = self.word(what)
        try:
            return int(word)
        except ValueError:
            raise BadFile(f"expected {what} (an integer), found {word[:30]!r}") from None

    def size(self, what: str) -> int:
        value = self.integer(what)
        if value < 0:
            raise BadFile(f"{what} is negative ({value})")
        return value

    def numbers(self, count: int, what: str) -> np.ndarray:
        if count > len(self.items) - self.at:
            raise BadFile(f"the file ends early (truncated?): {what} needs {count} numbers, "
                          f"{len(self.items) - self.at} left")
        words = self.items[self.at:self.at + count]
        self.at += count
        try:
            return np.array(words, dtype=float)
        except ValueError:
            bad = next(w for w in words if not _is_float(w))
            raise BadFile(f"{what}: {bad[:30]!r} is not a number") from None


def _is_float(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _dense(tok: _Tokens, rows: int, cols: int, what: str) -> np.ndarray:
    again = (tok.size(f"{what}'s row count"), tok.size(f"{what}'s column count"))
    if again != (rows, cols):
        raise BadFile(f"{what}: the dense sizes disagree, {rows} x {cols} then {again[0]} x {again[1]}")
    return tok.numbers(rows * cols, what).reshape((rows, cols), order="F")


def _offsets(tok: _Tokens, count: int, total: int, what: str) -> list[int]:
    """``count`` cumulative sizes ending at ``total``; returns the start offsets plus total."""
    ends = [tok.size(what) for _ in range(count)]
    if not ends or ends[-1] != total or any(b < a for a, b in zip([0] + ends, ends)):
        raise BadFile(f"{what}: the cumulative block sizes {ends[:6]} do not rise to {total}")
    return [0] + ends


def _sparse_block(tok: _Tokens, rows: int, cols: int, what: str) -> np.ndarray:
    M = np.zeros((rows, cols))
    nblocks = tok.size(f"{what}'s number of blocks")
    if nblocks == 0:
        return M
    block_rows, block_cols = tok.size(f"{what}'s block rows"), tok.size(f"{what}'s block columns")
    if block_rows > rows or block_cols > cols or nblocks > block_rows * block_cols:
        raise BadFile(f"{what}: {nblocks} blocks in a {block_rows} x {block_cols} block grid do not fit {rows} x {cols}")
    row_at = _offsets(tok, block_rows, rows, f"{what}'s block rows")
    col_at = _offsets(tok, block_cols, cols, f"{what}'s block columns")
    n_ptr, n_idx = tok.size(f"{what}'s row-pointer length"), tok.size(f"{what}'s index length")
    if n_ptr != block_rows + 1 or n_idx != nblocks:
        raise BadFile(f"{what}: block-CSR array lengths {n_ptr}, {n_idx} do not match {block_rows} block rows, {nblocks} blocks")
    ptr = [tok.size(f"{what}'s row pointer") for _ in range(n_ptr)]
    idx = [tok.size(f"{what}'s block column index") for _ in range(n_idx)]
    if ptr[0] != 0 or ptr[-1] != nblocks or any(b < a for a, b in zip(ptr, ptr[1:])):
        raise BadFile(f"{what}: the block row pointers {ptr[:6]} are not 0 ... {nblocks}, rising")
    if any(j >= block_cols for j in idx):
        raise BadFile(f"{what}: a block column index is {max(idx)}, beyond {block_cols - 1}")
    for bi in range(block_rows):
        for k in range(ptr[bi], ptr[bi + 1]):
            if tok.integer(f"the number of block {k}") != k:
                raise BadFile(f"{what}: block {k} is out of order")
            r0, r1, c0, c1 = row_at[bi], row_at[bi + 1], col_at[idx[k]], col_at[idx[k] + 1]
            M[r0:r1, c0:c1] = tok.numbers((r1 - r0) * (c1 - c0), f"{what}'s block {k}").reshape((r1 - r0, c1 - c0), order="F")
    return M


def _matrix(tok: _Tokens, what: str) -> np.ndarray:
    storage = tok.integer(f"{what}'s storage type")
    rows, cols = tok.size(f"{what}'s row count"), tok.size(f"{what}'s column count")
    check_size(rows, cols, what)
    if storage == 0:
        return _dense(tok, rows, cols, what)
    if storage == 1:
        return _sparse_block(tok, rows, cols, what)
    raise BadFile(f"{what}: matrix storage type {storage} is not supported (0 dense and 1 sparse-block are)")


def _rows(tok: _Tokens, rows: int, cols: int, what: str) -> np.ndarray:
    check_size(rows, cols, what)
    return tok.numbers(rows * cols, what).reshape((rows, cols))


def is_mlcp(text: str, name: str) -> bool:
    """Whether a .dat file holds an MLCP rather than an LCP, from its first integers (and the
    file's name where both readings fit, which needs a problem of size 0 or 1)."""
    head = text.split(None, 5)[:5]
    try:
        t = [int(w) for w in head]
    except ValueError:
        return MLCP in name.lower()  # Siconos names its MLCP files *_mlcp.dat
    if len(t) < 4:
        return False
    lcp = t[1] in (0, 1) and t[2] == t[0] and t[3] == t[0]
    mlcp = t[0] in (0, 1) and t[1] in (0, 1) and (t[0] or t[1]) and (not t[0] or (len(t) > 4 and t[4] == 0))
    if lcp and mlcp:
        return MLCP in name.lower()  # Siconos names its MLCP files *_mlcp.dat
    return bool(mlcp)


def read(data: bytes, path) -> Problem:
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError as exc:
        raise BadFile(f"not a Siconos .dat text file (a non-ASCII byte at {exc.start})") from None
    tok = _Tokens(text)
    if is_mlcp(text, str(path)):
        return make_problem(MLCP, _read_mlcp(tok), path, "Siconos MLCP .dat")
    n = tok.size("the problem size n")
    M = _matrix(tok, "M")
    if M.shape != (n, n):
        raise BadFile(f"M is {M.shape[0]} x {M.shape[1]}, expected {n} x {n}")
    q = tok.numbers(n, "q")
    rest = tok.items[tok.at:]
    if n and len(rest) == 2 * n and all(map(_is_float, rest)):  # a relay (box) file: lb, ub follow q
        lo, hi = tok.numbers(n, "lb"), tok.numbers(n, "ub")
        return make_problem(BLCP, {"M": M, "q": q, "lo": lo, "hi": hi}, path, "Siconos relay .dat")
    return make_problem(LCP, {"M": M, "q": q}, path, "Siconos LCP .dat")


def _read_mlcp(tok: _Tokens) -> dict:
    storage1, storage2 = tok.integer("isStorageType1"), tok.integer("isStorageType2")
    n, m = tok.size("n (free variables)"), tok.size("m (complementary variables)")
    if storage1 not in (0, 1) or storage2 not in (0, 1) or not (storage1 or storage2):
        raise BadFile(f"the storage flags must be 0/1 and not both 0, found {storage1} {storage2}")
    if storage1:
        offsets = [tok.size("the block row offsets")]
        while offsets[-1] < n + m:
            if len(offsets) > n + m + 1:
                raise BadFile("the block row offsets never reach n + m")
            offsets.append(tok.size("the block row offsets"))
        flags = [tok.integer("a block's equality/complementarity flag") for _ in offsets[1:]]
        M = _matrix(tok, "M")
        q = tok.numbers(M.shape[1], "q")
    if storage2:
        A, B = _rows(tok, n, n, "A"), _rows(tok, m, m, "B")
        C, D = _rows(tok, n, m, "C"), _rows(tok, m, n, "D")
        return dict(A=A, B=B, C=C, D=D, a=tok.numbers(n, "a"), b=tok.numbers(m, "b"))
    if (offsets, flags) != _standard_layout(n, m):
        raise BadFile(f"only the block layout [0, n, n+m] with flags [0, 1] is supported, found {offsets} {flags}")
    if M.shape != (n + m, n + m):
        raise BadFile(f"M is {M.shape[0]} x {M.shape[1]}, expected {n + m} x {n + m}")
    return dict(A=M[:n, :n], B=M[n:, n:], C=M[:n, n:], D=M[n:, :n], a=q[:n], b=q[n:])


def _standard_layout(n: int, m: int):
    """Siconos' block rows of an MLCP with the n equality rows first: offsets and flags."""
    return [0] + [n] * (n > 0) + [n + m] * (m > 0), [0] * (n > 0) + [1] * (m > 0)


def _fmt(values) -> str:
    return " ".join(repr(float(x)) for x in values)


def _dense_text(M: np.ndarray) -> list[str]:
    rows, cols = M.shape
    return ["0", str(rows), str(cols), f"{rows}\t{cols}"] + [_fmt(col) for col in M.T]


def write(problem: Problem, fh) -> None:
    if problem.kind == BLCP and problem.findex is not None:
        raise ValueError("a Siconos relay file has no friction index; write .json or .npz")
    if problem.kind in (LCP, BLCP):
        lines = [str(problem.q.size)] + _dense_text(problem.M) + [_fmt(problem.q)]
        if problem.kind == BLCP:
            lines += [_fmt(problem.lo), _fmt(problem.hi)]
    else:
        n, m = problem.shape
        M = np.block([[problem.A, problem.C], [problem.D, problem.B]])
        offsets, flags = _standard_layout(n, m)
        lines = ["1 1", f"{n} {m}", " ".join(map(str, offsets)), " ".join(map(str, flags))]
        lines += _dense_text(M) + [_fmt(np.r_[problem.a, problem.b])]
        lines += [_fmt(row) for key in "ABCD" for row in getattr(problem, key)]
        lines += [_fmt(problem.a), _fmt(problem.b)]
    fh.write(("\n".join(lines) + "\n").encode("ascii"))
