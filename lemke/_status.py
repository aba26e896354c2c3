"""Outcome codes of every solver, each with one message saying what happened and what to do."""
from enum import IntEnum


class Status(IntEnum):
    """How a solve ended.  ``0`` is the only success; the numbering follows SciPy and quantecon
    (0 solved, 1 iteration limit, 2 ray)."""

    SOLVED = 0
    MAX_PIVOTS = 1
    RAY_TERMINATION = 2
    NUMERICAL_FAILURE = 3

    @property
    def message(self) -> str:
        return _MESSAGES[self]


_MESSAGES = {
    Status.SOLVED: (
        "Solved: z >= 0, w = Mz + q >= 0 and z'w = 0 hold for the caller's data within the "
        "tolerance."
    ),
    Status.MAX_PIVOTS: (
        "Stopped at the pivot limit before reaching a solution. Raise options.max_pivots "
        "(Lemke's method can need exponentially many pivots, e.g. on Murty's example)."
    ),
    Status.RAY_TERMINATION: (
        "Lemke's method ended on a secondary ray (checked on the caller's data): no solution "
        "was found. For copositive-plus M (positive semidefinite M included) this proves the "
        "LCP has no feasible point; for other M a solution may still exist (try another "
        "covering vector d)."
    ),
    Status.NUMERICAL_FAILURE: (
        "The final point failed the check against the caller's data (rounding or an "
        "ill-conditioned basis). Rescale the problem, or loosen options.tol if a larger "
        "residual is acceptable."
    ),
}
