"""A reader for MATLAB level-5 ``.mat`` files, for the variables a problem needs: numeric
arrays (dense and sparse, any stored integer or float type) and character arrays.

Written from MathWorks' "MAT-File Format" description (version 5: a 128-byte header whose last
two bytes give the byte order, then data elements ``(type, size, payload)``, 8-byte aligned
inside a matrix; ``miCOMPRESSED`` elements hold one zlib-compressed element).  scipy's
``loadmat`` is not used to read: a damaged file can crash it, and this reader checks every
size and index before using it (cells, structs and objects are skipped).
"""
from __future__ import annotations

import struct
import zlib

import numpy as np

from .common import MAX_ENTRIES, BadFile, check_size

_NUMBERS = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 9: "f8", 12: "i8", 13: "u8"}
_TEXT = {16: "utf-8", 17: "utf-16", 18: "utf-32"}
_MATRIX, _COMPRESSED = 14, 15
_CHAR, _SPARSE = 4, 5
_NUMERIC_CLASSES = range(6, 16)
_MAX_BYTES = 8 * MAX_ENTRIES + (1 << 20)


class Unsupported:
    """A variable of a MATLAB class this reader does not load (cell, struct, object...)."""

    def __init__(self, cls: int):
        self.cls = cls


def _elements(buf: bytes, order: str, aligned: bool):
    """The data elements ``(type, payload)`` of ``buf``."""
    pos = 0
    while pos < len(buf):
        if len(buf) - pos < 8:
            raise BadFile("the .mat data ends inside an element tag (truncated?)")
        first, second = struct.unpack_from(order + "II", buf, pos)
        if first >> 16:  # a small element: size and type in one word, data in the next four bytes
            kind, size, start = first & 0xFFFF, first >> 16, pos + 4
            if size > 4:
                raise BadFile(f"a small .mat element claims {size} bytes")
            pos += 8
        else:
            kind, size, start = first, second, pos + 8
            pos = start + size + ((-size) % 8 if aligned else 0)
        if start + size > len(buf):
            raise BadFile("a .mat element runs past the end of the data (truncated?)")
        yield kind, buf[start:start + size]


def _numbers(kind: int, payload: bytes, order: str, what: str) -> np.ndarray:
    if kind not in _NUMBERS:
        raise BadFile(f"{what}: .mat data type {kind} is not a number type")
    dtype = np.dtype(_NUMBERS[kind]).newbyteorder(order)
    if len(payload) % dtype.itemsize:
        raise BadFile(f"{what}: {len(payload)} bytes are not a whole number of {dtype.name} values")
    return np.frombuffer(payload, dtype=dtype)


def _array(payload: bytes, order: str):
    """``(name, value)`` of one miMATRIX element."""
    parts = list(_elements(payload, order, aligned=True))
    if len(parts) < 3:
        raise BadFile("a .mat matrix lacks its flags, dimensions or name")
    flags = _numbers(parts[0][0], parts[0][1], order, "array flags")
    dims = _numbers(parts[1][0], parts[1][1], order, "dimensions").astype(np.int64)
    name = parts[2][1].decode("ascii", errors="replace")
    if flags.size < 1 or dims.size < 2 or (dims < 0).any():
        raise BadFile(f"variable {name!r}: bad array flags or dimensions")
    cls, is_complex = int(flags[0]) & 0xFF, bool(int(flags[0]) & 0x800)
    if cls not in _NUMERIC_CLASSES and cls not in (_CHAR, _SPARSE):
        return name, Unsupported(cls)
    if is_complex:
        raise BadFile(f"variable {name!r} is complex; a problem needs real numbers")
    if dims.size != 2:
        raise BadFile(f"variable {name!r} has {dims.size} dimensions, a problem needs at most 2")
    check_size(int(dims[0]), int(dims[1]), f"variable {name!r}")
    count = int(dims[0] * dims[1])
    if cls == _SPARSE:
        return name, _sparse(parts[3:], dims, order, name)
    if len(parts) < 4:
        raise BadFile(f"variable {name!r} has no data")
    kind, data = parts[3]
    if cls == _CHAR:
        text = data.decode(_TEXT[kind], errors="replace") if kind in _TEXT else \
            "".join(map(chr, _numbers(kind, data, order, name).astype(np.int64).clip(0, 0x10FFFF)))
        return name, text
    values = _numbers(kind, data, order, name)
    if values.size != count:
        raise BadFile(f"variable {name!r} holds {values.size} values for {dims[0]} x {dims[1]}")
    return name, values.astype(np.float64).reshape(tuple(dims), order="F")


def _sparse(parts, dims, order: str, name: str) -> np.ndarray:
    if len(parts) < 2:
        raise BadFile(f"sparse variable {name!r} lacks its indices")
    rows_, cols_ = int(dims[0]), int(dims[1])
    ir = _numbers(*parts[0], order, name).astype(np.int64)
    jc = _numbers(*parts[1], order, name).astype(np.int64)
    nnz = int(jc[-1]) if jc.size else -1
    if jc.size != cols_ + 1 or jc[0] != 0 or (np.diff(jc) < 0).any() or not 0 <= nnz <= ir.size:
        raise BadFile(f"sparse variable {name!r} has inconsistent column pointers")
    values = _numbers(*parts[2], order, name).astype(np.float64) if len(parts) > 2 else np.ones(nnz)
    if values.size < nnz or (ir[:nnz] < 0).any() or (ir[:nnz] >= rows_).any():
        raise BadFile(f"sparse variable {name!r} has row indices or values out of range")
    out = np.zeros((rows_, cols_))
    np.add.at(out, (ir[:nnz], np.repeat(np.arange(cols_), np.diff(jc))), values[:nnz])
    return out


def _inflate(payload: bytes) -> bytes:
    inflater = zlib.decompressobj()
    try:
        out = inflater.decompress(payload, _MAX_BYTES)
    except zlib.error as exc:
        raise BadFile(f"a compressed .mat variable is damaged ({exc})") from None
    if inflater.unconsumed_tail:
        raise BadFile("a compressed .mat variable is too large once uncompressed")
    return out


def load(data: bytes) -> dict:
    """The variables of a level-5 MAT file: name -> float64 array, str or Unsupported."""
    if len(data) < 128 or data[126:128] not in (b"IM", b"MI"):
        raise BadFile("not a MATLAB level-5 .mat file (no 128-byte header with a byte-order mark)")
    order = "<" if data[126:128] == b"IM" else ">"
    out = {}
    for kind, payload in _elements(data[128:], order, aligned=False):
        if kind == _COMPRESSED:
            inner = list(_elements(_inflate(payload), order, aligned=False))
            if len(inner) != 1:
                raise BadFile("a compressed .mat element must hold exactly one variable")
            kind, payload = inner[0]
        if kind != _MATRIX:
            raise BadFile(f"a top-level .mat element has type {kind}, not a matrix")
        name, value = _array(payload, order)
        out[name] = value
    return out
