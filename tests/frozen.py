"""Frozen references: the outputs of the former Python kernels, the oracles the C++ core was
ported from bit for bit (deleted since), kept as digests in ``tests/data/frozen/<test
module>.json`` so that the tests that compared the core with them go on doing so.

A test hands every output it compares to :func:`check` (``frozen.check(value, label)``):
the value's bits (its type; a float's IEEE bits; an array's dtype, shape and bytes; tuples
and lists element by element) are hashed, and the test's hashes, in the order it makes
them, must be the recorded ones.  One changed bit of one output fails the test, and the
message names the first call (its label) whose output changed.  A test records up to
``BLOCKS`` digests: with more calls, each digest covers a block of consecutive calls.
Buffers that a kernel may leave partly unwritten are made by :func:`empty` (fixed bytes),
so the digests do not depend on what ``np.empty`` happens to leave.

The references were recorded from the oracle itself while it existed: at commit 9d446dc,
``tools/freeze_oracle.py`` ran these tests with ``LEMKE_FREEZE=record``, every checked call
ran on both the oracle and the core, the same bits were asserted, and the digests were
written, with the platform ``golden.versions()`` names.  The test data is made by numpy
(random generators, matrix products), so the bits are compared where the platform is the
recorded one, as ``tests/test_golden.py`` compares its bits; on another platform the
comparison is not made (a warning says so) and each test's own checks (complementarity,
KKT and equilibrium conditions, codes) still run.  A change that is *meant* to change these
bits rewrites them from the core's outputs with ``LEMKE_FREEZE=update pytest
tests/test_core_*.py tests/test_qp_kkt_check.py`` and says why in its commit and in
``tests/GOLDEN-CHANGES.md``, as for ``tests/golden.py``.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import struct
import warnings
from pathlib import Path

import numpy as np

DATA = Path(__file__).parent / "data" / "frozen"
BLOCKS = 256
#: "update": store the core's outputs (a change meant to change them); else compare.
MODE = os.environ.get("LEMKE_FREEZE", "")


def _feed(h, v):
    if isinstance(v, np.ndarray):
        a = np.ascontiguousarray(v)
        h.update(f"a{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    elif isinstance(v, (tuple, list)):
        h.update(f"t{len(v)}(".encode())
        for u in v:
            _feed(h, u)
        h.update(b")")
    elif isinstance(v, (bool, np.bool_)):
        h.update(f"{type(v).__name__}:{bool(v)}".encode())
    elif isinstance(v, (int, np.integer)):
        h.update(f"{type(v).__name__}:{int(v)}".encode())
    elif isinstance(v, (float, np.floating)):
        h.update(f"{type(v).__name__}:".encode() + struct.pack("<d", float(v)))
    elif isinstance(v, (str, bytes)):
        h.update(b"s" + (v.encode() if isinstance(v, str) else v))
    elif v is None:
        h.update(b"N")
    else:
        raise TypeError(f"cannot freeze a {type(v)}")


def digest(value) -> str:
    """The value's bits as a hex digest (types included: 1 and 1.0 differ)."""
    h = hashlib.sha256()
    _feed(h, value)
    return h.hexdigest()


def _platform():
    import golden

    return golden.versions()


class Reference:
    """One test's outputs, in order: compared with (or stored as) its frozen digests."""

    def __init__(self, module: str, name: str):
        self.module, self.name = module, name
        self.labels: list = []
        self.digests: list = []

    def check(self, value, label=""):
        self.labels.append(label)
        self.digests.append(digest(value))
        return value

    def _blocks(self, size):
        out = []
        for i in range(0, len(self.digests), size):
            h = hashlib.sha256("".join(self.digests[i:i + size]).encode())
            out.append(h.hexdigest()[:16])
        return out

    def finish(self, store: dict):
        """Compare with the module's frozen data, or record into ``store``."""
        n = len(self.digests)
        if not n:
            if MODE == "" and (DATA / f"{self.module}.json").exists():
                assert self.name not in load(self.module)["tests"], \
                    f"{self.name} has a frozen reference but checked no output"
            return
        if MODE == "update":
            size = max(1, math.ceil(n / BLOCKS))
            store.setdefault(self.module, {})[self.name] = {"calls": n, "block": size,
                                                            "digests": self._blocks(size)}
            return
        data = load(self.module)
        assert self.name in data["tests"], f"no frozen reference for {self.module}::{self.name}"
        if data["versions"] != _platform():
            warnings.warn(f"frozen references of {self.module} were recorded on {data['versions']}, "
                          f"not this platform ({_platform()}): bits not compared")
            return
        ref = data["tests"][self.name]
        assert n == ref["calls"], (f"{self.name}: {n} outputs checked, {ref['calls']} recorded "
                                   "(the test no longer makes the recorded calls)")
        size = ref["block"]
        got = self._blocks(size)
        bad = [i for i, (a, b) in enumerate(zip(got, ref["digests"])) if a != b]
        assert not bad, (f"{self.name}: {len(bad)} of {len(got)} blocks of {size} outputs differ "
                         f"from the frozen references; the first from call {bad[0] * size}: "
                         f"{self.labels[bad[0] * size:(bad[0] + 1) * size][:3]}")


def empty(shape, dtype=float):
    """``np.empty`` with fixed bytes (NaN; -7 for integers, True for bools): what a kernel
    leaves unwritten is then the same on every run, and the digests cover every byte."""
    dtype = np.dtype(dtype)
    return np.full(shape, np.nan if dtype.kind in "fc" else -7, dtype=dtype)


class FixedEmpty:
    """numpy, with :func:`empty` for ``np.empty``: a module's ``np`` while its buffers are
    checked byte for byte (``monkeypatch.setattr(module, "np", FixedEmpty())``)."""

    empty = staticmethod(empty)

    def __getattr__(self, name):
        return getattr(np, name)


_cache: dict = {}


def load(module: str) -> dict:
    if module not in _cache:
        path = DATA / f"{module}.json"
        _cache[module] = json.loads(path.read_text()) if path.exists() else {"versions": None, "tests": {}}
    return _cache[module]


def write(store: dict):
    """Write the recorded tests of each module (the module's other tests stay)."""
    DATA.mkdir(parents=True, exist_ok=True)
    for module, tests in store.items():
        path = DATA / f"{module}.json"
        old = json.loads(path.read_text()) if path.exists() else {"tests": {}}
        merged = dict(old["tests"])
        merged.update(tests)
        lines = [f"{json.dumps(k)}: {json.dumps(v, separators=(',', ':'))}" for k, v in sorted(merged.items())]
        path.write_text('{"versions": ' + json.dumps(_platform()) + ',\n"tests": {\n' + ",\n".join(lines) + "\n}}\n")


_current: Reference | None = None


def check(value, label=""):
    """Check (or, with LEMKE_FREEZE=update, record) ``value`` in the running test's frozen
    reference; returns it."""
    assert _current is not None, "frozen.check outside a test"
    return _current.check(value, label)
