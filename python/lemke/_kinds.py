"""The registry of problem kinds: everything the rest of the package needs to know about a
kind, in one entry.

:class:`lemke.Problem`, the file formats (``infer_kind`` and each format's ``KINDS``), the
command line and ``result_to_dict`` read ``KINDS`` and never spell a kind themselves.  A new
kind (a box LCP, a bimatrix game) is one :class:`Kind` here, its validation in
``_validate.py``, its solver and, where it is solved through another kind, its reduction in
``_reductions/``.
"""
from __future__ import annotations

import importlib
from typing import Callable

from ._frozen import frozen
from . import _validate

#: The LCP's methods (``lemke.METHODS``; a test checks that they agree).
METHODS = ("tableau", "unrevised")


class _Solver:
    """A kind's solver, ``front.name``, imported at its first call: the registry (and with it
    the command line and the file formats) loads no front and no kernel until a problem of
    that kind is solved.  ``load()`` imports it without calling it."""

    def __init__(self, front: str, name: str, positional=None, keyword=()):
        self.front, self.name = front, name
        self.positional, self.keyword = positional, tuple(keyword)
        self._fn = None

    def load(self):
        if self._fn is None:
            self._fn = getattr(importlib.import_module("." + self.front, __package__), self.name)
        return self._fn

    def __call__(self, *args, **kwargs):
        # fields past the solver's positional arguments are its keyword arguments (a box
        # LCP's findex)
        if self.positional is not None and len(args) > self.positional:
            kwargs.update(zip(self.keyword, args[self.positional:]))
            args = args[:self.positional]
        return self.load()(*args, **kwargs)

    def __repr__(self):
        return f"<solver lemke.{self.front}.{self.name}>"


@frozen
class Kind:
    """One kind of problem.

    Attributes
    ----------
    name : str
        The kind's key (``Problem.kind``, the ``kind`` of a JSON or npz file).
    fields : tuple of str
        The arrays, in the order of the solver's positional arguments.
    required : tuple of str
        The fields a problem must have (the others may be None).
    signature : frozenset of str
        Arrays whose presence tells the kind of a file that does not name it.
    validate : callable
        ``validate(*fields) -> {name: float64 array}`` (the given fields only), raising
        ``ValueError``/``TypeError``; the solver validates with the same function.
    solve : callable
        The solver, ``solve(*fields, method=, options=, ...)`` (a :class:`_Solver`: its
        front is imported at the first call, or by ``solve.load()``).
    shape : callable
        ``shape(arrays) -> tuple`` of the problem's sizes.
    size_text : callable
        ``size_text(shape) -> str``, the size in words (``n = 3``).
    size_short : callable
        ``size_short(shape) -> str``, the size in a table cell (``3``, ``2+1``, ``4x3``).
    size_legend : str
        What ``size_short`` means, for the command line's table.
    answer : tuple of str
        The result's fields that hold the answer, shown by the command line.
    methods : tuple of str
        The solver's ``method`` values (the first is its default).
    residual : callable
        ``residual(result) -> float``: the one number the command line reports as the
        answer's error (an LCP's residual, a QP's largest KKT residual, a game's regret).
    has_objective : bool
        Whether the problem has an objective (and ``objective_constant``).
    example : dict
        The arrays of a tiny instance (the command line loads the kernels with it).
    solved : str
        What a SOLVED result of this kind guarantees, in one short line (the command line
        prints it; ``Status.SOLVED.message`` says it for every kind at once).
    """

    name: str
    fields: tuple
    required: tuple
    signature: frozenset
    validate: Callable
    solve: Callable
    shape: Callable
    size_text: Callable
    size_short: Callable
    size_legend: str
    answer: tuple
    methods: tuple = METHODS
    residual: Callable = lambda res: float(res.residual)
    has_objective: bool = False
    example: dict | None = None
    solved: str = "checked on the data within the tolerance"


def _plural(k: int, one: str, many: str) -> str:
    return f"{k} {one if k == 1 else many}"


LCP = Kind(
    name="lcp",
    fields=("M", "q"),
    required=("M", "q"),
    signature=frozenset({"M"}),
    validate=_validate.lcp_fields,
    solve=_Solver("_lcp", "solve_lcp"),
    shape=lambda a: (a["q"].size,),
    size_text=lambda s: f"n = {s[0]}",
    size_short=lambda s: str(s[0]),
    size_legend="n (LCP)",
    answer=("z",),
    example={"M": [[2.0, 1.0], [1.0, 2.0]], "q": [-5.0, -6.0]},
    solved="z >= 0, w = Mz + q >= 0 and z'w = 0, within the tolerance",
)

MLCP = Kind(
    name="mlcp",
    fields=("A", "B", "C", "D", "a", "b"),
    required=("A", "B", "C", "D", "a", "b"),
    signature=frozenset({"A", "B", "C", "D"}),
    validate=_validate.mlcp,
    solve=_Solver("_mlcp", "solve_mlcp"),
    shape=lambda a: (a["a"].size, a["b"].size),
    size_text=lambda s: f"n = {s[0]} free, m = {s[1]} complementary",
    size_short=lambda s: f"{s[0]}+{s[1]}",
    size_legend="free+complementary (MLCP)",
    answer=("u", "v"),
    example={"A": [[2.0]], "B": [[1.0]], "C": [[1.0]], "D": [[-1.0]], "a": [-1.0], "b": [-1.0]},
    solved="Au + Cv + a = 0, v >= 0, w = Du + Bv + b >= 0 and v'w = 0, within the tolerance",
)

QP = Kind(
    name="qp",
    fields=("P", "q", "G", "h", "A", "b", "lb", "ub"),
    required=("P", "q"),
    signature=frozenset({"P"}),
    validate=_validate.qp,
    solve=_Solver("_qp", "solve_qp"),
    shape=lambda a: (a["q"].size,) + tuple(a[k].shape[0] if k in a else 0 for k in ("G", "A")),
    size_text=lambda s: (f"n = {s[0]}, {_plural(s[1], 'inequality', 'inequalities')}, "
                         f"{_plural(s[2], 'equality', 'equalities')}"),
    size_short=lambda s: f"{s[0]}x{s[1] + s[2]}",
    size_legend="variables x constraint rows (QP)",
    answer=("x",),
    residual=lambda res: float(max(res.primal_residual, res.dual_residual)),
    has_objective=True,
    example={"P": [[2.0, 0.0], [0.0, 2.0]], "q": [-2.0, -5.0], "G": [[1.0, 1.0]], "h": [1.0]},
    solved="optimal: the KKT conditions hold within the tolerance",
)

BLCP = Kind(
    name="blcp",
    fields=("M", "q", "lo", "hi", "findex"),
    required=("M", "q", "lo", "hi"),
    signature=frozenset({"M", "lo", "hi"}),
    validate=_validate.blcp,
    solve=_Solver("_blcp", "solve_blcp", positional=4, keyword=("findex",)),
    shape=lambda a: (a["q"].size,),
    size_text=lambda s: f"n = {s[0]}, lo <= z <= hi",
    size_short=lambda s: str(s[0]),
    size_legend="n (box LCP)",
    answer=("z",),
    methods=("bounded",),
    example={"M": [[2.0, 1.0], [1.0, 2.0]], "q": [-5.0, 6.0], "lo": [-1.0, -1.0], "hi": [1.0, 1.0]},
    solved="lo <= z <= hi; w = Mz + q >= 0 at lo, <= 0 at hi, 0 between, within the tolerance",
)

BIMATRIX = Kind(
    name="bimatrix",
    fields=("A", "B"),
    required=("A", "B"),
    signature=frozenset({"A", "B"}),
    validate=_validate.bimatrix,
    solve=_Solver("_games", "solve_bimatrix"),
    shape=lambda a: a["A"].shape,
    size_text=lambda s: f"{s[0]} x {s[1]} actions",
    size_short=lambda s: f"{s[0]}x{s[1]}",
    size_legend="actions of the two players (game)",
    answer=("x", "y", "payoffs"),
    methods=("lemke-howson", "tracing"),
    residual=lambda res: float(res.regret),
    example={"A": [[3.0, 3.0], [2.0, 5.0], [0.0, 6.0]], "B": [[3.0, 2.0], [2.0, 6.0], [3.0, 1.0]]},
    solved="a Nash equilibrium: no player gains by deviating, within the tolerance",
)

#: Every kind, by name, in the order the documentation lists them.
KINDS: dict[str, Kind] = {k.name: k for k in (LCP, BLCP, MLCP, QP, BIMATRIX)}


def kind(name: str) -> Kind:
    """The registered kind ``name``; ``ValueError`` listing the kinds otherwise."""
    try:
        return KINDS[name]
    except (KeyError, TypeError):
        raise ValueError(f"kind must be one of {', '.join(map(repr, KINDS))}, got {name!r}") from None


#: The order in which a file's arrays are matched against the signatures (a QP also has
#: an ``A``; an LCP file has no ``P``).
_INFER_ORDER = (QP, BLCP, LCP, MLCP, BIMATRIX)


def infer(keys) -> Kind | None:
    """The first kind (in ``_INFER_ORDER``) whose signature arrays are all among ``keys``,
    or None."""
    keys = set(keys)
    return next((k for k in _INFER_ORDER if k.signature <= keys), None)
