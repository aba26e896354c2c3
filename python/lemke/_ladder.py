"""The recovery ladder (issue 31, item 2), the fronts' form: one mechanism for every kind.

A ladder is a named table of rungs, each a name, whether it applies (to the state the rungs
before it left) and its engine call (which runs, charges its pivots to the one cap and
leaves its answer in the state); one driver, :func:`climb`, tries them in order until the
kind's ``settled`` says the answer is accepted by the kind's check, a stop (TIME_LIMIT,
INTERRUPTED) came, or a rung ended the climb.  The same shape and vocabulary as the core's
``src/lemke/ladder.hpp`` (``rung``, ``climb``, ``Cap``), which runs the ladders in the core
(the LCP's ``solve_one``, ``boxed::batch``'s island, Lemke-Howson's paths); this one runs
those in the fronts, whose rungs are Python calls (``_mlcp.LADDER``, ``_blcp._finish``,
``_games._finish``, ``_qp._solve_definite``'s kernel order).  Two forms because a rung is an engine call in the language of the
code around it: a C++ table inlines into the kernels' hot paths (a Python driver there would
cost more than the LCP's whole 1 us solve), and the fronts' rungs are numpy and ``solve_lcp``
calls that a native driver could only call back.
"""
from __future__ import annotations

from typing import Callable, NamedTuple


class Rung(NamedTuple):
    """One rung: its name, whether it applies (``() -> bool``), its engine call (``() ->
    None``, leaving its answer in the state the ladder's closures share)."""

    name: str
    applies: Callable[[], bool]
    run: Callable[[], None]


def always() -> bool:
    """A rung that always applies."""
    return True


def climb(settled, *rungs) -> int:
    """Run each rung in order that applies; after each that ran, ``settled()`` (the answer
    accepted by the kind's check, a stop, or the climb ended by a rung) ends the climb.
    Returns the index of the last rung run (-1: none applied)."""
    last = -1
    for i, r in enumerate(rungs):
        if r.applies():
            r.run()
            last = i
            if settled():
                break
    return last


class Cap:
    """The one pivot cap of a climb: every rung's pivots are charged to it (a kernel's
    negative count charges nothing), and :meth:`left` is what the next rung may spend."""

    __slots__ = ("cap", "pivots")

    def __init__(self, cap, pivots=0):
        self.cap = cap
        self.pivots = pivots

    def left(self):
        return self.cap - self.pivots

    def charge(self, p):
        self.pivots += max(p, 0)
