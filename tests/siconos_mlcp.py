"""The Siconos MLCP files for the tests, read by the package's own reader
(:func:`lemke.read_problem`; the format is described in ``lemke/_io/siconos.py``)."""
from __future__ import annotations

import gzip
import tempfile
from pathlib import Path

import numpy as np

import lemke

DATA = Path(__file__).resolve().parent / "data" / "siconos"
# Siconos' two large MLCP files (3.2 MB each), kept gzip-compressed (16 KB each) in a folder
# of their own: the directory mlcp/ is solved as a whole by tests/test_cli.py.
LARGE_MLCP = sorted((DATA / "mlcp-large").glob("*.dat.gz"))


def unpacked(path, folder) -> Path:
    """``path`` itself, or for a ``.gz`` file its bytes written to ``folder`` under its stem."""
    path = Path(path)
    if path.suffix != ".gz":
        return path
    out = Path(folder) / path.stem
    out.write_bytes(gzip.decompress(path.read_bytes()))
    return out


def read_mlcp(path):
    """``(A, B, C, D, a, b)`` of the file (from its storage-2 part, which every shared file has);
    a ``.dat.gz`` file is read as the ``.dat`` file it holds."""
    with tempfile.TemporaryDirectory() as folder:
        p = lemke.read_problem(unpacked(path, folder), format="dat")
    assert p.kind == "mlcp", f"{path} holds an {p.kind}"
    return tuple(np.array(x) for x in p.arrays_in_order())
