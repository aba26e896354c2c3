"""Outcome codes of every solver, each with one message saying what happened and what to do."""
from enum import IntEnum


class Status(IntEnum):
    """How a solve ended.  ``0`` is the only success; the numbering follows SciPy and quantecon
    (0 solved, 1 iteration limit, 2 ray); 4 and 5 are the QP verdicts with a certificate; 6
    says the method cycled; 7 and 8 say the solve was stopped before it ended: by
    ``Options(time_limit=...)`` or by an interrupt (Ctrl-C, ``lemke_interrupt``)."""

    SOLVED = 0
    MAX_PIVOTS = 1
    RAY_TERMINATION = 2
    NUMERICAL_FAILURE = 3
    PRIMAL_INFEASIBLE = 4
    DUAL_INFEASIBLE = 5
    CYCLING = 6
    TIME_LIMIT = 7
    INTERRUPTED = 8

    @property
    def message(self) -> str:
        return _MESSAGES[self]

    def __str__(self) -> str:  # the name, not the number (IntEnum's default)
        return self.name

    def __format__(self, spec: str) -> str:
        return format(self.name, spec)


#: The statuses of a solve stopped by its budget (``Options.time_limit``) or an interrupt:
#: fronts try no recovery after them.
STOPPED = frozenset({Status.TIME_LIMIT, Status.INTERRUPTED})

_MESSAGES = {
    Status.SOLVED: (
        "Solved, and checked on the caller's data within the tolerance: z >= 0, w = Mz + q >= 0 "
        "and z'w = 0 (for an MLCP also its equations; for a box LCP lo <= z <= hi with w >= 0 where "
        "z = lo, w <= 0 where z = hi and w = 0 in between, with a friction index at the bounds in "
        "force at the answer; for a QP its KKT conditions; for a game, no player gains by "
        "deviating, up to the tolerance relative to the payoffs)."
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
    Status.CYCLING: (
        "Lemke's method revisited a basis (it cycled, through rounding on a degenerate "
        "problem), and the restarts (exact ties only, then a perturbed covering vector) "
        "cycled too; result.recoveries counts them. Rescale or perturb the problem, or try "
        "the other method."
    ),
    Status.TIME_LIMIT: (
        "Stopped at options.time_limit before reaching a solution; result.pivots says how far "
        "it went and result.z is the unchecked point where it stopped. Raise the time limit."
    ),
    Status.INTERRUPTED: (
        "Interrupted (Ctrl-C or an interrupt from another thread) before reaching a solution; "
        "result.z is the unchecked point where it stopped."
    ),
    Status.PRIMAL_INFEASIBLE: (
        "No feasible point exists, and result.certificate proves it (for a QP, a Farkas "
        "vector: multipliers whose combination of the constraints reads 0 <= c with c < 0; for "
        "an MLCP, the equations contradict each other). Check the constraint data."
    ),
    Status.DUAL_INFEASIBLE: (
        "The objective is unbounded below along a direction that keeps every constraint "
        "(result.certificate: P d = 0, A d = 0, G d <= 0, d within the bounds' directions, "
        "q'd < 0), or the problem has no optimum for that reason. Add bounds or check q."
    ),
}
