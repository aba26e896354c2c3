"""JSON problems.

One object; ``kind`` is ``"lcp"``, ``"mlcp"``, ``"qp"``, ``"blcp"`` or ``"bimatrix"``
(inferred from the arrays when left out), the arrays are named as the solver's arguments::

    {"kind": "lcp", "name": "cps-4.4.7", "source": "free text",
     "M": [[0, -1, 2], [2, 0, -2], [-1, 1, 0]], "q": [-3, 6, -1]}
    {"kind": "mlcp", "A": [[...]], "B": [[...]], "C": [[...]], "D": [[...]], "a": [...], "b": [...]}
    {"kind": "qp", "P": [[...]], "q": [...], "G": [[...]], "h": [...], "A": [[...]], "b": [...],
     "lb": [0, null], "ub": [null, 5], "objective_constant": -100}
    {"kind": "blcp", "M": [[...]], "q": [...], "lo": [0, -1], "hi": [null, 1], "findex": [-1, 0]}
    {"kind": "bimatrix", "A": [[...]], "B": [[...]]}

A matrix is a list of rows, or a sparse matrix in coordinates,
``{"shape": [rows, cols], "rows": [...], "cols": [...], "values": [...]}`` (0-based; repeated
positions add up).  In ``lb``/``ub`` (a box LCP's ``lo``/``hi``), ``null`` means no bound
(-inf / +inf); a box LCP's ``findex`` is a list of integers (-1: no friction).  Every number must
be finite (NaN and Infinity are refused).  Unknown keys are refused, so a typo is not ignored.
"""
from __future__ import annotations

import json
import math

import numpy as np

from .._kinds import KINDS as REGISTRY
from .._problem import FIELDS, Problem
from .common import BadFile, check_size, infer_kind, make_problem

_META = ("kind", "name", "source", "objective_constant")
_VECTORS = {"q", "a", "b", "h", "lb", "ub", "lo", "hi", "findex"}

KINDS = ("lcp", "mlcp", "qp", "bimatrix", "blcp")  # the kinds of problem this format holds


def _number(x, where: str, none=None) -> float:
    if x is None and none is not None:
        return none
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise BadFile(f"{where} must hold numbers, found {type(x).__name__} {json.dumps(x)[:40]}")
    try:
        return float(x)
    except OverflowError:  # an integer too large for a float
        raise BadFile(f"{where} has a number too large for a float") from None


def _vector(value, key: str) -> np.ndarray:
    if not isinstance(value, list):
        raise BadFile(f"'{key}' must be a list of numbers")
    none = {"lb": -math.inf, "ub": math.inf, "lo": -math.inf, "hi": math.inf}.get(key)
    return np.array([_number(x, f"'{key}'", none) for x in value], dtype=float)


def _matrix(value, key: str) -> np.ndarray:
    if isinstance(value, dict):
        return _coordinates(value, key)
    if not isinstance(value, list) or not all(isinstance(row, list) for row in value):
        raise BadFile(f"'{key}' must be a list of rows (lists of numbers) or a coordinate object")
    widths = sorted({len(row) for row in value})
    if len(widths) > 1:
        raise BadFile(f"'{key}' has rows of different lengths {widths[:4]}")
    width = widths[0] if widths else 0
    check_size(len(value), width, f"'{key}'")
    rows = [[_number(x, f"'{key}'") for x in row] for row in value]
    return np.array(rows, dtype=float).reshape(len(value), width)


def _coordinates(value: dict, key: str) -> np.ndarray:
    need = {"shape", "rows", "cols", "values"}
    if set(value) != need:
        raise BadFile(f"a coordinate matrix '{key}' must have exactly the keys {sorted(need)}")
    shape = value["shape"]
    if not (isinstance(shape, list) and len(shape) == 2 and all(type(s) is int for s in shape)):
        raise BadFile(f"'{key}.shape' must be two integers")
    check_size(shape[0], shape[1], f"'{key}'")
    parts = []
    for part in ("rows", "cols", "values"):
        if not isinstance(value[part], list):
            raise BadFile(f"'{key}.{part}' must be a list")
        parts.append(value[part])
    if not len(parts[0]) == len(parts[1]) == len(parts[2]):
        raise BadFile(f"'{key}.rows', '.cols' and '.values' must have the same length")
    out = np.zeros(shape)
    for i, j, x in zip(*parts):
        if type(i) is not int or type(j) is not int or not (0 <= i < shape[0] and 0 <= j < shape[1]):
            raise BadFile(f"'{key}' has a position ({i}, {j}) outside its shape {tuple(shape)}")
        out[i, j] += _number(x, f"'{key}.values'")
    return out


def _reject_constant(token: str):
    raise BadFile(f"{token} is not allowed (all numbers must be finite; use null for no bound)")


def read(data: bytes, path) -> Problem:
    try:
        doc = json.loads(data.decode("utf-8"), parse_constant=_reject_constant)
    except UnicodeDecodeError as exc:
        raise BadFile(f"not a UTF-8 text file ({exc.reason} at byte {exc.start})") from None
    except json.JSONDecodeError as exc:
        raise BadFile(f"not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    except RecursionError:
        raise BadFile("not valid JSON: nested too deeply") from None
    if not isinstance(doc, dict):
        raise BadFile(f"a JSON problem must be an object {{...}}, found {type(doc).__name__}")
    kind = doc.get("kind")
    if kind is None:
        kind = infer_kind(set(doc) - set(_META))
    if kind not in KINDS:
        raise BadFile(f"'kind' must be one of {', '.join(map(repr, KINDS))}, found {json.dumps(kind)[:40]}")
    unknown = sorted(set(doc) - set(_META) - set(FIELDS[kind]))
    if unknown:
        raise BadFile(f"unknown key(s) for a {kind} problem: {', '.join(map(repr, unknown))}")
    for key in ("name", "source"):
        if not isinstance(doc.get(key, ""), str):
            raise BadFile(f"'{key}' must be a string")
    arrays = {
        k: (_vector if k in _VECTORS else _matrix)(doc[k], k)
        for k in FIELDS[kind] if k in doc and doc[k] is not None
    }
    constant = doc.get("objective_constant", 0.0)
    if REGISTRY[kind].has_objective:
        constant = _number(constant, "'objective_constant'")
    return make_problem(kind, arrays, path, "JSON", name=doc.get("name", ""), source=doc.get("source", ""),
                        objective_constant=constant)


def _plain(a: np.ndarray):
    """Nested lists of floats, infinities as None (JSON has no infinity); a large matrix that
    is mostly zeros in coordinates."""
    nonzero = np.nonzero(a)
    if a.ndim == 2 and a.size > 64 and nonzero[0].size < a.size // 4:
        return {"shape": list(a.shape), "rows": nonzero[0].tolist(), "cols": nonzero[1].tolist(),
                "values": a[nonzero].tolist()}
    if not np.isfinite(a).all():
        return np.where(np.isfinite(a), a, None).tolist()
    return a.tolist()


def to_dict(problem: Problem) -> dict:
    doc = {"kind": problem.kind, "name": problem.name, "source": problem.source}
    if REGISTRY[problem.kind].has_objective:
        doc["objective_constant"] = problem.objective_constant
    for k, a in problem.arrays.items():
        doc[k] = _plain(a)
    return doc


def write(problem: Problem, fh) -> None:
    fh.write(json.dumps(to_dict(problem), allow_nan=False).encode("utf-8") + b"\n")
