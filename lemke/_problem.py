"""Validation and coercion of user input, done once at the boundary.

The arrays returned are float64; they are the caller's own arrays when those already are
float64 (no copy), so the solver treats them as read-only and never writes to them.
"""
from __future__ import annotations

import numpy as np


def _to_float_array(x, name: str, allow_inf: int = 0) -> np.ndarray:
    """float64 view or copy of ``x``; NaN is refused, and so is an infinite entry unless
    ``allow_inf`` is -1 (``-inf`` allowed: lower bounds) or +1 (``+inf``: upper bounds)."""
    if hasattr(x, "toarray") and hasattr(x, "nnz"):  # scipy.sparse: densified for now
        x = x.toarray()
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None
    if a.dtype.kind not in "fiub":  # float, int, unsigned, bool
        raise TypeError(f"{name} must hold real numbers, got dtype {a.dtype}")
    if a.dtype != np.float64:
        a = a.astype(np.float64)
    good = np.isfinite(a)
    if allow_inf:
        good |= a == allow_inf * np.inf
    if not good.all():
        bad = np.argwhere(~good)[0]
        what = "a NaN or infinite" if not allow_inf else f"a NaN or {'+' if allow_inf < 0 else '-'}inf"
        raise ValueError(f"{name} has {what} entry at index {tuple(int(i) for i in bad)}")
    return a


def as_matrix(M, name: str = "M") -> np.ndarray:
    """A square float64 copy of ``M`` (dense or scipy.sparse)."""
    a = _to_float_array(M, name)
    if a.ndim == 1 and a.size == 0:
        a = np.zeros((0, 0))  # [] is the empty matrix
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ValueError(f"{name} must be a square 2-D matrix, got shape {a.shape}")
    return np.ascontiguousarray(a)


def as_vector(v, n: int, name: str) -> np.ndarray:
    """A float64 copy of ``v``, which must have shape (n,)."""
    a = _to_float_array(v, name)
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},) to match M, got shape {a.shape}")
    return a


def as_lcp(M, q, d=None):
    """Validate an LCP: returns float64 copies ``(M, q, d)``; ``d`` is None when not given."""
    M = as_matrix(M)
    n = M.shape[0]
    q = as_vector(q, n, "q")
    if d is not None:
        d = as_vector(d, n, "d")
        if n and not np.all(d > 0):
            raise ValueError(f"the covering vector d must be positive; d[{int(np.argmin(d))}] = {d.min()}")
    return M, q, d


# --------------------------------------------------------------------------- the container

#: The arrays of each kind of problem, in the order of its solver's arguments.
FIELDS = {
    "lcp": ("M", "q"),
    "mlcp": ("A", "B", "C", "D", "a", "b"),
    "qp": ("P", "q", "G", "h", "A", "b", "lb", "ub"),
}
KINDS = tuple(FIELDS)


def _stored(x, name: str, shape: tuple, allow_inf: int = 0) -> np.ndarray:
    """A read-only float64 copy of ``x``, which must have ``shape``."""
    a = _to_float_array(x, name, allow_inf)
    if a.size == 0 and 0 in shape:
        # No entries either way: [] (or [[]]) stands for any empty matrix, e.g. a JSON file's
        # C of shape (0, m), which a list of no rows cannot spell.
        a = np.zeros(shape)
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got shape {a.shape}")
    a = np.array(a, dtype=np.float64, order="C", copy=True)
    a.flags.writeable = False
    return a


def _length(x, name: str) -> int:
    """The length of the vector ``x`` (which fixes a dimension of the problem)."""
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None
    if a.ndim != 1:
        raise ValueError(f"{name} must be a 1-D vector, got shape {a.shape}")
    return a.shape[0]


def _lcp_arrays(M, q):
    n = _length(q, "q")
    return {"M": _stored(M, "M", (n, n)), "q": _stored(q, "q", (n,))}


def _mlcp_arrays(A, B, C, D, a, b):
    n, m = _length(a, "a"), _length(b, "b")
    shapes = {"A": (n, n), "B": (m, m), "C": (n, m), "D": (m, n), "a": (n,), "b": (m,)}
    given = dict(zip(shapes, (A, B, C, D, a, b)))
    return {k: _stored(given[k], k, shape) for k, shape in shapes.items()}


def _qp_arrays(P, q, G, h, A, b, lb, ub):
    n = _length(q, "q")
    out = {"P": _stored(P, "P", (n, n)), "q": _stored(q, "q", (n,))}
    for mat, vec, (mname, vname) in ((G, h, ("G", "h")), (A, b, ("A", "b"))):
        if (mat is None) != (vec is None):
            raise ValueError(f"{mname} and {vname} must be given together")
        if mat is not None:  # one row may be given as a vector and a scalar
            rows = _length(np.atleast_1d(vec), vname)
            mat = _to_float_array(mat, mname)
            out[mname] = _stored(mat.reshape(1, -1) if mat.ndim == 1 else mat, mname, (rows, n))
            out[vname] = _stored(np.atleast_1d(vec), vname, (rows,))
    for vec, name, sign in ((lb, "lb", -1), (ub, "ub", 1)):
        if vec is not None:
            out[name] = _stored(vec, name, (n,), allow_inf=sign)
    if "lb" in out and "ub" in out and np.any(out["lb"] > out["ub"]):
        i = int(np.argmax(out["lb"] > out["ub"]))
        raise ValueError(f"lb[{i}] = {out['lb'][i]} is above ub[{i}] = {out['ub'][i]}")
    return out


_BUILD = {"lcp": _lcp_arrays, "mlcp": _mlcp_arrays, "qp": _qp_arrays}


class Problem:
    """One problem with its provenance: an LCP, an MLCP or a convex QP.

    Build one with :meth:`lcp`, :meth:`mlcp` or :meth:`qp` (or ``Problem(kind, arrays)``);
    :func:`lemke.read_problem` returns one.  The arrays are read-only float64 copies, checked
    for shapes and finiteness when the problem is made (``ValueError``/``TypeError``), and
    are attributes named as in the solver's arguments:

    * ``kind == "lcp"``: ``M, q`` -- find z >= 0 with w = M z + q >= 0, z'w = 0;
    * ``kind == "mlcp"``: ``A, B, C, D, a, b`` (Siconos' storage 2) -- u free, v >= 0 with
      A u + C v + a = 0 and 0 <= v _|_ w = D u + B v + b >= 0;
    * ``kind == "qp"``: ``P, q, G, h, A, b, lb, ub`` (qpsolvers' form; the last six may be
      None) -- minimize 1/2 x'P x + q'x + ``objective_constant`` subject to G x <= h,
      A x = b, lb <= x <= ub (``lb`` may hold -inf, ``ub`` +inf).

    ``name`` and ``source`` (where the problem comes from) are free text;
    ``objective_constant`` is the constant term of a QP's objective (0 otherwise).
    :meth:`solve` runs the solver for the kind.
    """

    __slots__ = ("kind", "name", "source", "objective_constant", "_arrays")

    def __init__(self, kind: str, arrays, *, name: str = "", source: str = "", objective_constant: float = 0.0):
        if kind not in FIELDS:
            raise ValueError(f"kind must be one of {', '.join(map(repr, KINDS))}, got {kind!r}")
        if not hasattr(arrays, "keys"):
            raise TypeError(f"arrays must be a mapping of array names, got {type(arrays).__name__}")
        unknown = sorted(set(arrays) - set(FIELDS[kind]))
        if unknown:
            raise ValueError(f"unknown array(s) for a {kind} problem: {', '.join(map(str, unknown))}")
        args = [arrays.get(k) for k in FIELDS[kind]]
        required = FIELDS[kind] if kind != "qp" else ("P", "q")
        missing = [k for k, v in zip(FIELDS[kind], args) if v is None and k in required]
        if missing:
            raise ValueError(f"a {kind} problem needs {', '.join(missing)}")
        c = objective_constant
        if isinstance(c, bool) or not isinstance(c, (int, float, np.integer, np.floating)) or not np.isfinite(c):
            raise ValueError(f"objective_constant must be a finite real number, got {c!r}")
        if kind != "qp" and c != 0:
            raise ValueError("objective_constant is for QPs only")
        for attr, value in (("name", name), ("source", source)):
            if not isinstance(value, str):
                raise TypeError(f"{attr} must be a string, got {type(value).__name__}")
        set_ = object.__setattr__
        set_(self, "kind", kind)
        set_(self, "name", name)
        set_(self, "source", source)
        set_(self, "objective_constant", float(c))
        set_(self, "_arrays", _BUILD[kind](*args))

    @classmethod
    def lcp(cls, M, q, *, name: str = "", source: str = "") -> "Problem":
        """The LCP (M, q)."""
        return cls("lcp", {"M": M, "q": q}, name=name, source=source)

    @classmethod
    def mlcp(cls, A, B, C, D, a, b, *, name: str = "", source: str = "") -> "Problem":
        """The MLCP A u + C v + a = 0, 0 <= v _|_ D u + B v + b >= 0 (u free)."""
        return cls("mlcp", dict(A=A, B=B, C=C, D=D, a=a, b=b), name=name, source=source)

    @classmethod
    def qp(cls, P, q, G=None, h=None, A=None, b=None, lb=None, ub=None, *, name: str = "",
           source: str = "", objective_constant: float = 0.0) -> "Problem":
        """The QP min 1/2 x'Px + q'x (+ constant) s.t. Gx <= h, Ax = b, lb <= x <= ub."""
        arrays = dict(P=P, q=q, G=G, h=h, A=A, b=b, lb=lb, ub=ub)
        return cls("qp", {k: v for k, v in arrays.items() if v is not None}, name=name,
                   source=source, objective_constant=objective_constant)

    def __getattr__(self, key):
        # Only reached when normal lookup fails: the arrays of this kind (None when absent).
        if not key.startswith("_") and key in FIELDS.get(object.__getattribute__(self, "kind"), ()):
            return self._arrays.get(key)
        raise AttributeError(f"a {self.kind} problem has no attribute {key!r}")

    def __setattr__(self, key, value):
        raise AttributeError("a Problem is immutable; make a new one")

    def __reduce__(self):
        return (_rebuild, (self.kind, self._arrays, self.name, self.source, self.objective_constant))

    @property
    def arrays(self) -> dict:
        """The arrays present, by name, in the solver's argument order (read-only)."""
        return {k: self._arrays[k] for k in FIELDS[self.kind] if k in self._arrays}

    @property
    def shape(self) -> tuple:
        """``(n,)`` for an LCP, ``(n, m)`` (free, complementary) for an MLCP, ``(n, rows of G,
        rows of A)`` for a QP."""
        if self.kind == "lcp":
            return (self.q.size,)
        if self.kind == "mlcp":
            return (self.a.size, self.b.size)
        return (self.q.size,) + tuple(0 if x is None else x.shape[0] for x in (self.G, self.A))

    def size_text(self) -> str:
        """The size in words, e.g. ``n = 3`` or ``n = 2, 1 inequality, 0 equalities``."""
        s = self.shape
        if self.kind == "lcp":
            return f"n = {s[0]}"
        if self.kind == "mlcp":
            return f"n = {s[0]} free, m = {s[1]} complementary"
        return f"n = {s[0]}, {s[1]} inequalit{'y' if s[1] == 1 else 'ies'}, {s[2]} equalit{'y' if s[2] == 1 else 'ies'}"

    def objective(self, x) -> float:
        """A QP's objective 1/2 x'Px + q'x + objective_constant at x."""
        if self.kind != "qp":
            raise ValueError(f"a {self.kind} problem has no objective")
        x = _stored(x, "x", (self.q.size,))
        return float(0.5 * x @ self.P @ x + self.q @ x + self.objective_constant)

    def solve(self, *, method: str = "tableau", options=None, **kwargs):
        """Solve with the solver for the kind: :func:`lemke.solve_lcp`, :func:`lemke.solve_mlcp`
        or :func:`lemke.solve_qp` (their keyword arguments pass through)."""
        import lemke

        solver = {"lcp": "solve_lcp", "mlcp": "solve_mlcp", "qp": "solve_qp"}[self.kind]
        if not hasattr(lemke, solver):
            raise NotImplementedError(f"this version of lemke has no {solver}")
        return getattr(lemke, solver)(*self.arrays_in_order(), method=method, options=options, **kwargs)

    def arrays_in_order(self) -> list:
        """The solver's positional arguments: every field of the kind, None where absent."""
        return [self._arrays.get(k) for k in FIELDS[self.kind]]

    def __repr__(self) -> str:
        name = f" {self.name!r}" if self.name else ""
        return f"<Problem {self.kind}{name}: {self.size_text()}>"


def _rebuild(kind, arrays, name, source, objective_constant):
    return Problem(kind, arrays, name=name, source=source, objective_constant=objective_constant)
