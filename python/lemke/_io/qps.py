"""QPS files: free MPS with a quadratic objective (the format of the Maros-Meszaros set).

Sections: ``NAME``, ``ROWS`` (``N`` objective, ``L``/``G``/``E`` constraints), ``COLUMNS``,
``RHS``, ``RANGES``, ``BOUNDS``, ``QUADOBJ`` (one triangle of the symmetric Q, the other being
implied) or ``QMATRIX`` (all of Q), ``OBJSENSE`` (only ``MIN``), ``ENDATA``; names hold no
spaces; lines starting with ``*`` are comments.  The problem is

    minimize 1/2 x'Q x + c'x + constant   subject to the rows and bounds,

where the constant is minus the RHS of the objective row.  Rows become qpsolvers' form in
file order: ``L`` rows ``a x <= rhs``, ``G`` rows ``-a x <= -rhs``, ``E`` rows ``a x = rhs``; a
RANGE R turns a row into ``lo <= a x <= hi`` (``L``: [rhs - |R|, rhs]; ``G``: [rhs, rhs + |R|];
``E``: [rhs, rhs + R] or [rhs + R, rhs] by the sign of R), written as two ``G`` rows.  Bounds
default to ``0 <= x < inf``; types ``UP, LO, FX, FR, MI, PL`` (an ``UP`` below 0 on a column with
no lower bound set makes that bound -inf, as in CPLEX and HiGHS).  Integer columns (markers,
``BV``, ``LI``, ``UI``, ``SC``) are refused.
"""
from __future__ import annotations

import numpy as np

from .._problem import Problem
from .common import BadFile, check_size, finite_or_none, make_problem

_SECTIONS = {"NAME", "ROWS", "COLUMNS", "RHS", "RANGES", "BOUNDS", "QUADOBJ", "QMATRIX", "QSECTION",
             "OBJSENSE", "ENDATA"}

KINDS = ("qp",)  # the kinds of problem this format holds
(QP,) = KINDS


class _Model:
    def __init__(self):
        self.objective = None
        self.rows: dict[str, int] = {}  # constraint name -> index
        self.types: list[str] = []
        self.cols: dict[str, int] = {}
        self.entries: dict[tuple[int, int], float] = {}  # (row, col) -> value
        self.cost: dict[int, float] = {}
        self.rhs: dict[int, float] = {}
        self.ranges: dict[int, float] = {}
        self.constant = 0.0
        self.lower: dict[int, float] = {}
        self.upper: dict[int, float] = {}
        self.quad: dict[tuple[int, int], float] = {}

    def col(self, name: str, line: int) -> int:
        if name not in self.cols:
            raise BadFile(f"line {line}: unknown column {name[:30]!r}")
        return self.cols[name]


def _number(word: str, line: int, bound: bool = False) -> float:
    """A finite number; in BOUNDS, |value| >= 1e30 (MPS's infinity) and inf are infinite."""
    try:
        value = float(word)
    except ValueError:
        raise BadFile(f"line {line}: {word[:30]!r} is not a number") from None
    if bound and abs(value) >= 1e30:
        return float(np.copysign(np.inf, value))
    if not np.isfinite(value):
        raise BadFile(f"line {line}: {word[:30]!r} is not a finite number")
    return value


def _pairs(words: list[str], line: int) -> list[tuple[str, float]]:
    """``name value [name value]`` after an optional set name (an odd count means it has one)."""
    if len(words) % 2:
        words = words[1:]
    if not words or len(words) > 4:
        raise BadFile(f"line {line}: expected one or two 'name value' pairs")
    return [(words[i], _number(words[i + 1], line)) for i in range(0, len(words), 2)]


def _row(model: _Model, words: list[str], line: int) -> None:
    if len(words) != 2:
        raise BadFile(f"line {line}: a ROWS line is a type and a name")
    kind, name = words[0].upper(), words[1]
    if kind not in ("N", "L", "G", "E"):
        raise BadFile(f"line {line}: row type {kind[:10]!r} is not N, L, G or E")
    if name in model.rows or name == model.objective:
        raise BadFile(f"line {line}: row {name[:30]!r} is defined twice")
    if kind == "N":
        if model.objective is None:
            model.objective = name  # later N rows are free rows, dropped
        return
    model.rows[name] = len(model.types)
    model.types.append(kind)


def _column(model: _Model, words: list[str], line: int) -> None:
    if len(words) >= 3 and words[1].strip("'\"").upper() == "MARKER":
        raise BadFile(f"line {line}: integer markers are not supported (continuous QPs only)")
    if len(words) not in (3, 5):
        raise BadFile(f"line {line}: a COLUMNS line is a column and one or two 'row value' pairs")
    j = model.cols.setdefault(words[0], len(model.cols))
    for row, value in _pairs(words[1:], line):
        if row == model.objective:
            model.cost[j] = value
        elif row in model.rows:
            if (model.rows[row], j) in model.entries:
                raise BadFile(f"line {line}: the entry ({words[0][:20]}, {row[:20]}) is given twice")
            model.entries[model.rows[row], j] = value
        else:
            raise BadFile(f"line {line}: unknown row {row[:30]!r}")


def _rhs_or_range(model: _Model, words: list[str], line: int, section: str) -> None:
    for row, value in _pairs(words, line):
        if row == model.objective:
            if section == "RHS":
                model.constant = -value
        elif row in model.rows:
            (model.rhs if section == "RHS" else model.ranges)[model.rows[row]] = value
        else:
            raise BadFile(f"line {line}: unknown row {row[:30]!r}")


_VALUED = {"UP", "LO", "FX"}
_FLAGS = {"FR", "MI", "PL"}


def _bound(model: _Model, words: list[str], line: int) -> None:
    kind = words[0].upper()
    if kind in ("BV", "LI", "UI", "SC"):
        raise BadFile(f"line {line}: bound type {kind} (integer) is not supported")
    if kind not in _VALUED | _FLAGS:
        raise BadFile(f"line {line}: unknown bound type {kind[:10]!r}")
    expect = 3 if kind in _VALUED else 2  # without the optional set name
    if len(words) not in (expect, expect + 1):
        raise BadFile(f"line {line}: a {kind} bound needs {'a column and a value' if kind in _VALUED else 'a column'}")
    words = words[len(words) - expect:]
    j = model.col(words[1], line)
    value = _number(words[2], line, bound=True) if kind in _VALUED else 0.0
    if kind in ("LO", "FX", "FR", "MI"):
        model.lower[j] = {"LO": value, "FX": value, "FR": -np.inf, "MI": -np.inf}[kind]
    if kind in ("UP", "FX", "FR", "PL"):
        if kind == "UP" and value < 0 and j not in model.lower:
            model.lower[j] = -np.inf
        model.upper[j] = {"UP": value, "FX": value, "FR": np.inf, "PL": np.inf}[kind]


def _quad(model: _Model, words: list[str], line: int, full: bool) -> None:
    if len(words) != 3:
        raise BadFile(f"line {line}: a QUADOBJ line is two columns and a value")
    i, j, value = model.col(words[0], line), model.col(words[1], line), _number(words[2], line)
    key = (i, j) if full else (min(i, j), max(i, j))
    if key in model.quad:
        raise BadFile(f"line {line}: the entry ({words[0][:20]}, {words[1][:20]}) of Q is given twice")
    model.quad[key] = value


def _parse(text: str) -> tuple[_Model, str]:
    model, section, name, done = _Model(), None, "", False
    for line, raw in enumerate(text.splitlines(), 1):
        if not raw.strip() or raw.lstrip().startswith("*"):
            continue
        words = raw.split()
        head = words[0].upper()
        if not raw[0].isspace() and head in _SECTIONS:
            section = head if head != "QSECTION" else "QMATRIX"
            if section == "NAME":
                name = " ".join(words[1:])
            elif section == "OBJSENSE" and len(words) > 1:
                _sense(words[1], line)
            elif section == "ENDATA":
                done = True
                break
            elif len(words) > 1 and section not in ("RHS", "RANGES", "BOUNDS"):
                raise BadFile(f"line {line}: unexpected text after {head}")
            continue
        if section in (None, "NAME"):
            raise BadFile(f"line {line}: {raw.strip()[:30]!r} is outside any section (not a QPS file?)")
        if section == "ROWS":
            _row(model, words, line)
        elif section == "COLUMNS":
            _column(model, words, line)
        elif section in ("RHS", "RANGES"):
            _rhs_or_range(model, words, line, section)
        elif section == "BOUNDS":
            _bound(model, words, line)
        elif section == "OBJSENSE":
            _sense(words[0], line)
        else:
            _quad(model, words, line, full=section == "QMATRIX")
    if not done:
        raise BadFile("the file ends without ENDATA (truncated?)")
    if model.objective is None and not model.cols:
        raise BadFile("no ROWS and no COLUMNS: not a QPS problem")
    return model, name


def _sense(word: str, line: int) -> None:
    if word.upper() not in ("MIN", "MINIMIZE"):
        raise BadFile(f"line {line}: OBJSENSE {word[:10]} is not supported (only MIN)")


def read(data: bytes, path) -> Problem:
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BadFile(f"not a QPS text file (a non-UTF-8 byte at {exc.start})") from None
    model, name = _parse(text)
    n, k = len(model.cols), len(model.types)
    check_size(n, n, "Q")
    check_size(k, n, "the constraint matrix")
    P = np.zeros((n, n))
    for (i, j), value in model.quad.items():
        P[i, j] = P[j, i] = value
    rows = np.zeros((k, n))
    for (i, j), value in model.entries.items():
        rows[i, j] = value
    q = np.zeros(n)
    q[list(model.cost)] = list(model.cost.values())
    G, h, A, b = [], [], [], []
    for i, kind in enumerate(model.types):
        rhs = model.rhs.get(i, 0.0)
        if i in model.ranges:
            r = model.ranges[i]
            lo, hi = {"L": (rhs - abs(r), rhs), "G": (rhs, rhs + abs(r)), "E": (min(rhs, rhs + r), max(rhs, rhs + r))}[kind]
            G += [rows[i], -rows[i]]
            h += [hi, -lo]
        elif kind == "E":
            A.append(rows[i])
            b.append(rhs)
        else:
            sign = 1.0 if kind == "L" else -1.0
            G.append(sign * rows[i])
            h.append(sign * rhs)
    lb, ub = np.zeros(n), np.full(n, np.inf)
    lb[list(model.lower)] = list(model.lower.values())
    ub[list(model.upper)] = list(model.upper.values())
    lb, ub = finite_or_none(lb, ub)
    return make_problem(QP, dict(P=P, q=q, G=np.array(G).reshape(-1, n) if G else None, h=np.array(h) if h else None,
                                   A=np.array(A).reshape(-1, n) if A else None, b=np.array(b) if b else None,
                                   lb=lb, ub=ub), path, "QPS", name=name, objective_constant=model.constant)


def _f(x: float) -> str:
    return repr(float(x))


def write(problem: Problem, fh) -> None:
    n = problem.q.size
    name = "".join(problem.name.split()) or "QP"
    cols = [f"x{j + 1}" for j in range(n)]
    blocks = [(problem.G, problem.h, "L", "g"), (problem.A, problem.b, "E", "e")]
    out = [f"NAME {name}", "ROWS", " N obj"]
    for mat, vec, kind, prefix in blocks:
        out += [f" {kind} {prefix}{i + 1}" for i in range(0 if vec is None else vec.size)]
    out.append("COLUMNS")
    for j in range(n):
        out.append(f" {cols[j]} obj {_f(problem.q[j])}")
        for mat, vec, kind, prefix in blocks:
            if mat is not None:
                out += [f" {cols[j]} {prefix}{i + 1} {_f(mat[i, j])}" for i in np.flatnonzero(mat[:, j])]
    out.append("RHS")
    if problem.objective_constant:
        out.append(f" rhs obj {_f(-problem.objective_constant)}")
    for mat, vec, kind, prefix in blocks:
        if vec is not None:
            out += [f" rhs {prefix}{i + 1} {_f(v)}" for i, v in enumerate(vec) if v]
    out.append("BOUNDS")
    lb = np.full(n, -np.inf) if problem.lb is None else problem.lb
    ub = np.full(n, np.inf) if problem.ub is None else problem.ub
    for j in range(n):
        out += _bounds(cols[j], lb[j], ub[j])
    out.append("QUADOBJ")
    P = (problem.P + problem.P.T) / 2  # the objective's symmetric part, as QUADOBJ holds it
    for i, j in zip(*np.nonzero(np.tril(P))):
        out.append(f" {cols[j]} {cols[i]} {_f(P[i, j])}")
    out.append("ENDATA")
    fh.write(("\n".join(out) + "\n").encode("utf-8"))


def _bounds(col: str, lo: float, hi: float) -> list[str]:
    if lo == hi:
        return [f" FX bnd {col} {_f(lo)}"]
    if lo == -np.inf:
        return [f" FR bnd {col}"] if hi == np.inf else [f" MI bnd {col}", f" UP bnd {col} {_f(hi)}"]
    out = [f" LO bnd {col} {_f(lo)}"] if lo != 0 or hi < 0 else []
    return out + ([f" UP bnd {col} {_f(hi)}"] if hi != np.inf else [])
