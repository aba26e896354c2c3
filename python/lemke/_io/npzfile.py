"""``.npz`` problems (``numpy.savez``): one array per field, named as the solver's arguments,
plus optional 0-d string arrays ``kind``, ``name``, ``source`` and a 0-d ``objective_constant``.
Without ``kind`` the kind is inferred from the arrays present (``M`` -> LCP, ``P`` -> QP,
``A, B, C, D`` -> MLCP).  Read with ``allow_pickle=False``: object arrays are refused."""
from __future__ import annotations

import io
import zipfile

import numpy as np

from .._kinds import KINDS as REGISTRY
from .._problem import FIELDS, Problem
from .common import MAX_ENTRIES, BadFile, infer_kind, make_problem

_TEXT = ("kind", "name", "source")

KINDS = ("lcp", "mlcp", "qp", "bimatrix", "blcp")  # the kinds of problem this format holds


def _text(archive, key: str) -> str:
    a = archive[key]
    if not isinstance(a, np.ndarray) or a.ndim != 0 or a.dtype.kind != "U":
        raise BadFile(f"'{key}' must be a 0-d string array, found {a.dtype} of shape {a.shape}")
    return str(a)


def read(data: bytes, path) -> Problem:
    try:
        members = zipfile.ZipFile(io.BytesIO(data)).infolist()
    except Exception as exc:  # zipfile's errors for a damaged archive (BadZipFile, NotImplementedError...)
        raise BadFile(f"not a readable .npz (zip) file: {exc}") from None
    if sum(m.file_size for m in members) > 8 * MAX_ENTRIES * 4:
        raise BadFile("the arrays are too large once uncompressed")
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as archive:
            if not isinstance(archive, np.lib.npyio.NpzFile):
                raise BadFile("not an .npz archive")
            keys = set(archive.files)
            kind = _text(archive, "kind") if "kind" in keys else infer_kind(keys - {"objective_constant", *_TEXT})
            if kind not in KINDS:
                raise BadFile(f"'kind' must be one of {', '.join(map(repr, KINDS))}, found {kind!r}")
            unknown = sorted(keys - set(FIELDS[kind]) - {"objective_constant", *_TEXT})
            if unknown:
                raise BadFile(f"unknown array(s) for a {kind} problem: {', '.join(unknown)}")
            arrays = {k: archive[k] for k in FIELDS[kind] if k in keys}
            text = {k: _text(archive, k) for k in ("name", "source") if k in keys}
            constant = archive["objective_constant"] if "objective_constant" in keys else np.array(0.0)
    except BadFile:
        raise
    except Exception as exc:  # numpy's own errors for a damaged archive or array
        raise BadFile(f"not a readable .npz file: {type(exc).__name__}: {exc}") from None
    for k, a in arrays.items():
        if not isinstance(a, np.ndarray):
            raise BadFile(f"'{k}' is not a .npy array in the archive")
        if a.dtype.kind not in "fiu":
            raise BadFile(f"array '{k}' must hold real numbers, found dtype {a.dtype}")
    if not isinstance(constant, np.ndarray) or constant.shape != () or constant.dtype.kind not in "fiu":
        raise BadFile("'objective_constant' must be a 0-d number")
    return make_problem(kind, arrays, path, ".npz", objective_constant=float(constant), **text)


def write(problem: Problem, fh) -> None:
    arrays = dict(problem.arrays)
    arrays.update(kind=np.array(problem.kind), name=np.array(problem.name), source=np.array(problem.source))
    if REGISTRY[problem.kind].has_objective:
        arrays["objective_constant"] = np.array(problem.objective_constant)
    np.savez_compressed(fh, **arrays)
