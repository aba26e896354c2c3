"""Carrying a basis across a change of rows by integer labels (``WarmStart.relabel`` with
integer arrays): one kernel call, no Python object per row.

The old labels go into an open-addressing hash table (linear probing, Fibonacci hashing:
the label times 2^64 / golden ratio, its top bits; contact ids that share their low bits
still spread), each new label is looked up there, and a second table catches a new label
given twice.  O(n + m) for n old rows and m new rows, about a microsecond at n = 150.
"""
import numpy as np

from . import kernel

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


@kernel
def _table_bits(n):
    """log2 of a table size at least 2n (and 16): at most half full."""
    bits = 4
    while (1 << bits) < 2 * n:
        bits += 1
    return bits


@kernel
def _slot(label, bits):
    return np.int64((np.uint64(label) * _GOLDEN) >> np.uint64(64 - bits))


@kernel
def relabel_ids(old, new, basic, out):
    """New row j gets z basic when its label ``new[j]`` is ``old[i]`` for an old row i with z
    basic (``basic``: the old basic rows, in [0, n)).  Writes those j, ascending, into
    ``out[:count]`` (``out``: m entries) and returns count; -1 when ``old`` holds a label
    twice, -2 when ``new`` does."""
    n, m = old.shape[0], new.shape[0]
    bits = _table_bits(max(n, m))
    size = np.int64(1) << bits
    mask = size - 1
    # row[s]: the old row whose label is in slot s (-1: empty); seen[s]: the same for the
    # new rows (the duplicate check); flag[i]: old row i has z basic
    row = np.full(2 * size, -1, dtype=np.int64)
    seen = row[size:]
    flag = np.zeros(n + 1, dtype=np.bool_)
    for t in range(basic.shape[0]):
        flag[basic[t]] = True
    for i in range(n):
        s = _slot(old[i], bits)
        while row[s] >= 0:
            if old[row[s]] == old[i]:
                return -1
            s = (s + 1) & mask
        row[s] = i
    count = 0
    for j in range(m):
        label = new[j]
        s = _slot(label, bits)
        while seen[s] >= 0:
            if new[seen[s]] == label:
                return -2
            s = (s + 1) & mask
        seen[s] = j
        s = _slot(label, bits)
        i = n  # not found: a new row (flag[n] is False)
        while row[s] >= 0:
            if old[row[s]] == label:
                i = row[s]
                break
            s = (s + 1) & mask
        if flag[i]:
            out[count] = j
            count += 1
    return count
