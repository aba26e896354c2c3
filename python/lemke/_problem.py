"""The problem container: one problem of any registered kind, with its provenance."""
from __future__ import annotations

import numpy as np

from . import _validate
from ._kinds import BIMATRIX, BLCP, KINDS, LCP, MLCP, QP, kind as _kind

#: The arrays of each kind of problem, in the order of its solver's arguments.
FIELDS = {name: k.fields for name, k in KINDS.items()}


def _stored(a: np.ndarray) -> np.ndarray:
    """A read-only, C-ordered copy: float64, or int64 for an index array (a box LCP's
    friction index)."""
    a = np.array(a, dtype=np.int64 if a.dtype.kind in "iu" else np.float64, order="C", copy=True)
    a.flags.writeable = False
    return a


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

    * ``kind == "blcp"``: ``M, q, lo, hi, findex`` (findex may be None) -- the box LCP
      lo <= z <= hi, w = M z + q, w >= 0 where z_i = lo_i, w <= 0 where z_i = hi_i, w = 0
      between (``lo`` may hold -inf, ``hi`` +inf);
    * ``kind == "bimatrix"``: ``A, B`` (both m x n) -- a Nash equilibrium (x, y) of the game
      where A pays the row player and B the column player.

    ``name`` and ``source`` (where the problem comes from) are free text;
    ``objective_constant`` is the constant term of a QP's objective (0 otherwise).
    :meth:`solve` runs the solver for the kind.
    """

    __slots__ = ("kind", "name", "source", "objective_constant", "_arrays")

    def __init__(self, kind: str, arrays, *, name: str = "", source: str = "", objective_constant: float = 0.0):
        k = _kind(kind)
        if not hasattr(arrays, "keys"):
            raise TypeError(f"arrays must be a mapping of array names, got {type(arrays).__name__}")
        unknown = sorted(set(arrays) - set(k.fields))
        if unknown:
            raise ValueError(f"unknown array(s) for a {kind} problem: {', '.join(map(str, unknown))}")
        args = [arrays.get(f) for f in k.fields]
        missing = [f for f, v in zip(k.fields, args) if v is None and f in k.required]
        if missing:
            raise ValueError(f"a {kind} problem needs {', '.join(missing)}")
        c = objective_constant
        if isinstance(c, bool) or not isinstance(c, (int, float, np.integer, np.floating)) or not np.isfinite(c):
            raise ValueError(f"objective_constant must be a finite real number, got {c!r}")
        if not k.has_objective and c != 0:
            raise ValueError(f"objective_constant is for problems with an objective, not a {kind}")
        for attr, value in (("name", name), ("source", source)):
            if not isinstance(value, str):
                raise TypeError(f"{attr} must be a string, got {type(value).__name__}")
        set_ = object.__setattr__
        set_(self, "kind", kind)
        set_(self, "name", name)
        set_(self, "source", source)
        set_(self, "objective_constant", float(c))
        set_(self, "_arrays", {f: _stored(a) for f, a in k.validate(*args).items()})

    @classmethod
    def lcp(cls, M, q, *, name: str = "", source: str = "") -> "Problem":
        """The LCP (M, q)."""
        return cls(LCP.name, {"M": M, "q": q}, name=name, source=source)

    @classmethod
    def mlcp(cls, A, B, C, D, a, b, *, name: str = "", source: str = "") -> "Problem":
        """The MLCP A u + C v + a = 0, 0 <= v _|_ D u + B v + b >= 0 (u free)."""
        return cls(MLCP.name, dict(A=A, B=B, C=C, D=D, a=a, b=b), name=name, source=source)

    @classmethod
    def qp(cls, P, q, G=None, h=None, A=None, b=None, lb=None, ub=None, *, name: str = "",
           source: str = "", objective_constant: float = 0.0) -> "Problem":
        """The QP min 1/2 x'Px + q'x (+ constant) s.t. Gx <= h, Ax = b, lb <= x <= ub."""
        arrays = dict(P=P, q=q, G=G, h=h, A=A, b=b, lb=lb, ub=ub)
        return cls(QP.name, {k: v for k, v in arrays.items() if v is not None}, name=name,
                   source=source, objective_constant=objective_constant)

    @classmethod
    def blcp(cls, M, q, lo, hi, findex=None, *, name: str = "", source: str = "") -> "Problem":
        """The box LCP lo <= z <= hi, w = M z + q (w >= 0 where z = lo, w <= 0 where z = hi,
        w = 0 between); ``findex`` couples friction rows to their normal rows."""
        arrays = {"M": M, "q": q, "lo": lo, "hi": hi}
        if findex is not None:
            arrays["findex"] = findex
        return cls(BLCP.name, arrays, name=name, source=source)

    @classmethod
    def bimatrix(cls, A, B, *, name: str = "", source: str = "") -> "Problem":
        """The bimatrix game with payoffs A (row player) and B (column player), both m x n."""
        return cls(BIMATRIX.name, {"A": A, "B": B}, name=name, source=source)

    def __getattr__(self, key):
        # Only reached when normal lookup fails: the arrays of this kind (None when absent).
        if not key.startswith("_") and key in KINDS[object.__getattribute__(self, "kind")].fields:
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
        """The sizes: ``(n,)`` for an LCP, ``(n, m)`` (free, complementary) for an MLCP,
        ``(n, rows of G, rows of A)`` for a QP."""
        return KINDS[self.kind].shape(self._arrays)

    def size_text(self) -> str:
        """The size in words, e.g. ``n = 3`` or ``n = 2, 1 inequality, 0 equalities``."""
        return KINDS[self.kind].size_text(self.shape)

    def objective(self, x) -> float:
        """A QP's objective 1/2 x'Px + q'x + objective_constant at x."""
        if not KINDS[self.kind].has_objective:
            raise ValueError(f"a {self.kind} problem has no objective")
        x = _stored(_validate.block(x, "x", (self.q.size,)))
        return float(0.5 * x @ self.P @ x + self.q @ x + self.objective_constant)

    def solve(self, *, method: str | None = None, options=None, **kwargs):
        """Solve with the solver for the kind (:func:`lemke.solve_lcp`,
        :func:`lemke.solve_mlcp`, :func:`lemke.solve_qp`, :func:`lemke.solve_bimatrix`);
        ``method`` (default: the solver's) and the other keyword arguments pass through."""
        if method is not None:
            kwargs["method"] = method
        return KINDS[self.kind].solve(*self.arrays_in_order(), options=options, **kwargs)

    def arrays_in_order(self) -> list:
        """The solver's positional arguments: every field of the kind, None where absent."""
        return [self._arrays.get(k) for k in FIELDS[self.kind]]

    def __repr__(self) -> str:
        name = f" {self.name!r}" if self.name else ""
        return f"<Problem {self.kind}{name}: {self.size_text()}>"


def _rebuild(kind, arrays, name, source, objective_constant):
    return Problem(kind, arrays, name=name, source=source, objective_constant=objective_constant)
