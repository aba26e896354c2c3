"""MATLAB level-5 ``.mat`` files (read by :mod:`.matv5`, written by ``scipy.io.savemat``).

A QP in the Maros-Meszaros layout of qpbenchmark / osqp_benchmarks (see
``/work/shared/data/maros-meszaros/README.md``)::

    minimize 1/2 x'P x + q'x + r   subject to   l <= A x <= u

with ``P`` (n x n), ``q`` (n), ``r`` (optional), ``A`` (m x n), ``l``, ``u`` (m), and ``n``,
``m`` optional.  |value| > 9e19 is infinite.  When the last n rows of ``A`` are the identity
they are the variable bounds (lb, ub); the other rows become qpsolvers' form the way
qpbenchmark makes it: rows with ``u - l < 1e-10`` are equalities ``a x = u``, then every finite
``u`` gives ``a x <= u`` and every finite ``l`` gives ``-a x <= -l`` (all upper rows first).
``r`` is kept as the problem's ``objective_constant``.

Also read: an LCP as ``M``, ``q``; an MLCP as ``A, B, C, D, a, b`` (with a ``kind`` string
where the names are ambiguous).  Writing produces these layouts (a QP with its bounds as the
identity rows, infinities as +-1e20).
"""
from __future__ import annotations

import numpy as np

from .._problem import FIELDS, Problem
from . import matv5
from .common import BadFile, finite_or_none, infer_kind, make_problem

INFINITY = 1e20  # how the files write infinity
_IS_INFINITE = 9e19
_EQUAL = 1e-10

# KINDS, the kinds of problem this format holds with their readers and writers, is declared
# at the end of this file, after the functions it names.


def _array(d: dict, key: str, what: str) -> np.ndarray:
    """``d[key]`` as a float64 array (sparse matrices were made dense by the loader)."""
    if key not in d:
        raise BadFile(f"a {what} .mat file needs the variable '{key}'; found: {', '.join(sorted(d)) or 'nothing'}")
    a = d[key]
    if not isinstance(a, np.ndarray):
        found = "text" if isinstance(a, str) else f"MATLAB class {a.cls}"
        raise BadFile(f"'{key}' must be a numeric array, found {found}")
    return a


def _vector(d: dict, key: str, what: str) -> np.ndarray:
    a = _array(d, key, what)
    if a.ndim != 2 or min(a.shape) > 1:
        raise BadFile(f"'{key}' must be a vector, found shape {a.shape}")
    return a.ravel()


def _scalar(d: dict, key: str, default=None) -> float:
    if key not in d and default is not None:
        return default
    a = _vector(d, key, "QP")
    if a.size != 1:
        raise BadFile(f"'{key}' must be a single number, found {a.size} values")
    return float(a[0])


def _kind(d: dict) -> str:
    if "kind" in d:
        if isinstance(d["kind"], str):
            return d["kind"]
        raise BadFile("'kind' must be a string")
    try:
        return infer_kind(d)
    except BadFile:
        found = ", ".join(sorted(d)) or "nothing"
        raise BadFile(f"a .mat problem needs the Maros-Meszaros variables P, q, A, l, u (or M, q for an "
                      f"LCP; A, B, C, D, a, b for an MLCP); found: {found}") from None


def read(data: bytes, path) -> Problem:
    if data[512:520] == b"\x89HDF\r\n\x1a\n" or data[124:128] == b"\x00\x02IM":
        raise BadFile("MATLAB v7.3 (HDF5) files are not supported; save with -v7")
    d = matv5.load(data)
    kind = _kind(d)
    if kind not in KINDS:
        raise BadFile(f"'kind' must be one of {', '.join(map(repr, KINDS))}, found {kind!r}")
    return KINDS[kind][0](d, kind, path)


def _read_plain(d: dict, kind: str, path) -> Problem:
    """A kind stored as its own arrays, named as the solver's arguments."""
    arrays = {k: (_vector if k.islower() else _array)(d, k, kind.upper()) for k in FIELDS[kind]}
    return make_problem(kind, arrays, path, ".mat")


def _infinite(v: np.ndarray) -> np.ndarray:
    v = v.copy()
    v[v > _IS_INFINITE] = np.inf
    v[v < -_IS_INFINITE] = -np.inf
    return v


def _read_qp(d: dict, kind: str, path) -> Problem:
    P, q, A = _array(d, "P", "QP"), _vector(d, "q", "QP"), _array(d, "A", "QP")
    l, u = _infinite(_vector(d, "l", "QP")), _infinite(_vector(d, "u", "QP"))
    n = q.size
    if A.ndim != 2 or A.shape[1] != n or l.size != A.shape[0] or u.size != A.shape[0]:
        raise BadFile(f"A is {A.shape}, l has {l.size} and u {u.size} entries; expected m x {n}, m, m")
    for key, value in (("n", n), ("m", A.shape[0])):
        if key in d and _scalar(d, key) != value:
            raise BadFile(f"'{key}' says {_scalar(d, key):g}, the arrays say {value}")
    lb = ub = None
    if A.shape[0] >= n and np.array_equal(A[A.shape[0] - n:], np.eye(n)):
        A, lb, ub = A[: A.shape[0] - n], l[l.size - n:], u[u.size - n:]
        l, u = l[: l.size - n], u[: u.size - n]
        lb, ub = finite_or_none(lb, ub)
    with np.errstate(invalid="ignore"):
        eq = u - l < _EQUAL
    upper, lower = ~eq & (u < np.inf), ~eq & (l > -np.inf)
    G, h = np.vstack([A[upper], -A[lower]]), np.r_[u[upper], -l[lower]]
    return make_problem(kind, dict(P=P, q=q, G=G if h.size else None, h=h if h.size else None,
                                   A=A[eq] if eq.any() else None, b=u[eq] if eq.any() else None,
                                   lb=lb, ub=ub), path, "Maros-Meszaros .mat",
                        objective_constant=_scalar(d, "r", 0.0))


def write(problem: Problem, fh) -> None:
    out = {"kind": problem.kind}
    KINDS[problem.kind][1](problem, out)
    import scipy.io  # (here: it costs 80 ms to import, and reading needs none of it)

    scipy.io.savemat(fh, out, do_compression=True)


def _write_plain(problem: Problem, out: dict) -> None:
    for k, a in problem.arrays.items():
        out[k] = a.reshape(-1, 1) if a.ndim == 1 else a


def _write_qp(problem: Problem, out: dict) -> None:
    """Maros-Meszaros' layout: l <= [G; A; I] x <= u, with the objective constant r."""
    import scipy.sparse as sp

    n = problem.q.size
    G, h, A, b = problem.G, problem.h, problem.A, problem.b
    rows = [x for x in (G, A) if x is not None] + [np.eye(n)]
    lb = np.full(n, -np.inf) if problem.lb is None else problem.lb
    ub = np.full(n, np.inf) if problem.ub is None else problem.ub
    l = np.r_[np.full(0 if G is None else G.shape[0], -np.inf), [] if b is None else b, lb]
    u = np.r_[[] if h is None else h, [] if b is None else b, ub]
    out.update(n=float(n), m=float(l.size), P=sp.csc_matrix(problem.P), q=problem.q.reshape(-1, 1),
               r=float(problem.objective_constant), A=sp.csc_matrix(np.vstack(rows)),
               l=np.clip(l, -INFINITY, INFINITY).reshape(-1, 1), u=np.clip(u, -INFINITY, INFINITY).reshape(-1, 1))


#: The kinds of problem this format holds, each with its (reader, writer): a QP in
#: Maros-Meszaros' layout, the others as their own arrays.
KINDS = {"lcp": (_read_plain, _write_plain), "mlcp": (_read_plain, _write_plain), "qp": (_read_qp, _write_qp)}
