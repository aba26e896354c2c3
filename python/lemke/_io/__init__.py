"""Reading and writing problems and results: :func:`read_problem`, :func:`write_problem`,
:func:`write_result`, :func:`result_to_dict` and :class:`ProblemFormatError`.

Formats (``format=``): ``"json"``, ``"npz"``, ``"dat"`` (Siconos LCP/MLCP), ``"mat"``
(Maros-Meszaros QP), ``"qps"`` (free MPS with QUADOBJ) and ``"nfg"`` (Gambit games); each module's docstring gives its
layout.  Reading never executes data (no pickle: ``np.load(allow_pickle=False)``), never writes
to the file, and refuses dense matrices over ``MAX_ENTRIES`` entries before allocating them.
Writing is atomic: a temporary file in the same directory, then ``os.replace``.
"""
from __future__ import annotations

import dataclasses
import enum
import json
import math
from fractions import Fraction
from pathlib import Path

import numpy as np

from .._kinds import KINDS
from .._problem import Problem
from . import jsonfile, matfile, nfg, npzfile, qps, siconos
from .common import MAX_ENTRIES, BadFile, ProblemFormatError, atomic_write, same_file

__all__ = ["FORMATS", "MAX_ENTRIES", "ProblemFormatError", "read_problem", "result_to_dict",
           "write_problem", "write_result"]

_MODULES = {"json": jsonfile, "npz": npzfile, "dat": siconos, "mat": matfile, "qps": qps, "nfg": nfg}
FORMATS = tuple(_MODULES)
#: File name extensions of each format (lower case).
EXTENSIONS = {".json": "json", ".npz": "npz", ".dat": "dat", ".mat": "mat", ".qps": "qps", ".mps": "qps", ".nfg": "nfg"}

_ZIP = (b"PK\x03\x04", b"PK\x05\x06")


def _sniff(data: bytes) -> str | None:
    """The format from the file's first bytes, or None."""
    if data.startswith(_ZIP):
        return "npz"
    if data.startswith(b"MATLAB") or data[512:520] == b"\x89HDF\r\n\x1a\n":
        return "mat"
    head = data[:4096].decode("utf-8", errors="replace")
    text = "\n".join(x for x in head.splitlines() if x.strip() and not x.lstrip().startswith("*"))
    stripped = text.lstrip("\ufeff \t\r\n")
    if stripped.startswith("{"):
        return "json"
    if stripped.startswith("NFG"):
        return "nfg"
    first = stripped.split(None, 1)[:1]
    if first and first[0].upper() in ("NAME", "ROWS") and text[:1] not in (" ", "\t"):
        return "qps"
    if first and first[0].lstrip("+-").isdigit():
        return "dat"
    return None


def _format_of(path: Path, data: bytes, format: str | None) -> str:
    if format is not None:
        if format not in _MODULES:
            raise BadFile(f"unknown format {format!r}; known: {', '.join(FORMATS)}")
        return format
    sniffed = _sniff(data)
    if sniffed in ("npz", "mat"):  # binary signatures are unambiguous
        return sniffed
    by_name = EXTENSIONS.get(path.suffix.lower())
    if by_name or sniffed:
        return by_name or sniffed
    raise BadFile(f"unknown format: the extension {path.suffix or '(none)'!r} is not one of "
                  f"{', '.join(sorted(EXTENSIONS))} and the contents are not recognized")


def read_problem(path, *, format: str | None = None) -> Problem:
    """Read the problem in the file ``path``.

    The format is ``format`` when given (one of ``FORMATS``), else read from the file's first
    bytes (zip -> ``npz``, MATLAB header -> ``mat``) and then its extension (``.json``,
    ``.npz``, ``.dat``, ``.mat``, ``.qps``/``.mps``), else from its text (``{`` -> JSON,
    ``NAME``/``ROWS`` -> QPS, an integer -> Siconos ``.dat``).  The problem's ``name`` is the
    file's stem unless the file names it.

    Raises
    ------
    ProblemFormatError
        For every failure (a ``ValueError``): the file is missing or unreadable, empty, not in
        the format, truncated, holds NaN/Inf, has wrong shapes, is too large for a dense
        solver...  The message is one line, ``"<path>: <what is wrong>"``.
    """
    try:
        path = Path(path)
    except TypeError:
        raise TypeError(f"path must be a str or os.PathLike, got {type(path).__name__}") from None
    try:
        data = path.read_bytes()
    except IsADirectoryError as exc:
        raise ProblemFormatError(path, "is a directory, not a file") from exc
    except OSError as exc:
        raise ProblemFormatError(path, f"cannot read: {exc.strerror or exc}") from exc
    try:
        if not data.strip():
            raise BadFile("the file is empty")
        return _MODULES[_format_of(path, data, format)].read(data, path)
    except BadFile as exc:
        raise ProblemFormatError(path, str(exc)) from None
    except (ValueError, TypeError) as exc:  # the problem's own checks (shapes, NaN, Inf)
        raise ProblemFormatError(path, str(exc)) from None


def _writer(path: Path, format: str | None):
    fmt = format or EXTENSIONS.get(path.suffix.lower())
    if fmt not in _MODULES:
        raise ValueError(f"cannot tell the format to write {str(path)!r}: give format= one of "
                         f"{', '.join(FORMATS)} or an extension {', '.join(sorted(EXTENSIONS))}")
    return _MODULES[fmt]


def write_problem(problem: Problem, path, *, format: str | None = None, overwrite: bool = True) -> None:
    """Write ``problem`` to ``path`` in ``format`` (default: by the extension), atomically.

    ``overwrite=False`` refuses an existing file (``FileExistsError``).  A format that cannot
    hold the problem's kind (a QP in ``.dat``, an LCP in QPS) raises ``ValueError``.
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a lemke.Problem, got {type(problem).__name__}")
    path = Path(path)
    module = _writer(path, format)
    if not overwrite and path.exists():
        raise FileExistsError(f"{path} exists (overwrite=False)")
    if problem.kind not in module.KINDS:
        fits = [f for f, m in _MODULES.items() if problem.kind in m.KINDS]
        fmt = next(f for f, m in _MODULES.items() if m is module)
        raise ValueError(f"a .{fmt} file cannot hold a {problem.kind} problem; "
                         f"use one of {', '.join(fits)}")
    atomic_write(path, lambda fh: module.write(problem, fh))


def _plain(value):
    """A result's field as JSON: arrays as lists, non-finite floats as None."""
    if isinstance(value, enum.Enum):
        return value.name
    if isinstance(value, Fraction):  # exact answers (games): "p/q", read back by Fraction()
        return str(value)
    if isinstance(value, np.ndarray):
        return [_plain(x) for x in value] if value.ndim > 1 else _plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [_plain(x) for x in value]
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, (np.integer, np.bool_)):
        return value.item()
    if dataclasses.is_dataclass(value):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    return value


def result_to_dict(result, problem: Problem | None = None, **extra) -> dict:
    """A result (``LCPResult``, ``MLCPResult``, ``QPResult``) as a JSON-ready dict: ``status``
    (name), ``status_code``, ``success``, ``message`` and every field of the result (arrays as
    lists, infinite or NaN values as null).  With ``problem``: its ``name``, ``kind`` and
    ``source`` first (and, for a QP, ``objective`` = ``obj`` + its constant); ``extra``
    keys (e.g. ``time_s``) are added."""
    out = {}
    if problem is not None:
        out.update(name=problem.name, kind=problem.kind, source=problem.source)
    out.update(status=result.status.name, status_code=int(result.status), success=bool(result.success),
               message=result.message)
    out.update({f.name: _plain(getattr(result, f.name)) for f in dataclasses.fields(result) if f.name != "status"})
    out.update({k: _plain(v) for k, v in _objective(result, problem).items()})
    out.update({k: _plain(v) for k, v in extra.items()})
    return out


def _result_arrays(result, problem, extra) -> dict:
    """The fields of a result as numpy arrays (for .npz; no object arrays, None left out)."""
    out = {}
    if problem is not None:
        out.update(name=problem.name, kind=problem.kind, source=problem.source)
    out.update(status=result.status.name, status_code=int(result.status), message=result.message)

    def put(key, value):
        if value is None:
            return
        if dataclasses.is_dataclass(value):
            for f in dataclasses.fields(value):
                put(f"{key}_{f.name}", getattr(value, f.name))
        elif isinstance(value, enum.Enum):
            out[key] = int(value)
        elif isinstance(value, Fraction) or (isinstance(value, tuple) and any(isinstance(v, Fraction) for v in value)):
            out[key] = np.array(_plain(value), dtype=str)  # exact answers as "p/q" strings
        else:
            out[key] = value

    for f in dataclasses.fields(result):
        if f.name != "status":
            put(f.name, getattr(result, f.name))
    for k, v in {**_objective(result, problem), **extra}.items():
        put(k, v)
    return {k: np.asarray(v) for k, v in out.items()}


def _objective(result, problem) -> dict:
    """``{"objective": obj + the problem's constant}`` for a QP, else nothing."""
    if problem is not None and KINDS[problem.kind].has_objective and getattr(result, "obj", None) is not None:
        return {"objective": result.obj + problem.objective_constant}
    return {}


def write_result(result, path, *, problem: Problem | None = None, protect=(), **extra) -> None:
    """Write a result atomically as ``.json`` (:func:`result_to_dict`) or ``.npz`` (the same
    fields: arrays as arrays, text as 0-d strings, absent values left out).  ``result`` may be
    a list of results for ``.json`` (``problem`` then a list too).  Refuses (``ValueError``)
    to write over any file in ``protect`` (e.g. the inputs)."""
    path = Path(path)
    for p in protect:
        if same_file(path, p):
            raise ValueError(f"refusing to write the result over the input file {p}")
    suffix = path.suffix.lower()
    if isinstance(result, (list, tuple)):
        if suffix != ".json":
            raise ValueError(f"several results can only be written as .json, not {suffix or 'no extension'}")
        probs = problem if problem is not None else [None] * len(result)
        doc = [r if isinstance(r, dict) else result_to_dict(r, p, **extra) for r, p in zip(result, probs)]
    else:
        doc = result if isinstance(result, dict) else result_to_dict(result, problem, **extra)
    if suffix == ".json":
        atomic_write(path, lambda fh: fh.write(json.dumps(doc, indent=1, allow_nan=False).encode() + b"\n"))
    elif suffix == ".npz":
        arrays = _result_arrays(result, problem, extra)
        atomic_write(path, lambda fh: np.savez_compressed(fh, **arrays))
    else:
        raise ValueError(f"a result is written as .json or .npz, not {suffix or 'a file without extension'}")
