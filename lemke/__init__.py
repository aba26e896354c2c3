"""lemke: linear complementarity problems by Lemke's complementary pivoting method.

Public API: :func:`solve_lcp` (methods in ``METHODS``), :class:`LCPResult`, :class:`Status`,
:class:`Options`, :class:`WarmStart`, :func:`pivot_column` (one step of the unrevised
method), the checks :func:`is_lcp_solution` and :func:`is_lcp_ray`; problems as values
(:class:`Problem`) and in files (:func:`read_problem`, :func:`write_problem`,
:func:`write_result`, :class:`ProblemFormatError`).
"""
from ._io import ProblemFormatError, read_problem, result_to_dict, write_problem, write_result
from ._certify import is_lcp_ray, is_lcp_solution, lcp_residual
from ._lcp import METHODS, solve_lcp
from ._options import Options
from ._pivot_column import pivot_column
from ._problem import Problem
from ._result import LCPResult, WarmStart
from ._status import Status

__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "LCPResult",
    "Options",
    "Problem",
    "ProblemFormatError",
    "Status",
    "WarmStart",
    "is_lcp_ray",
    "is_lcp_solution",
    "lcp_residual",
    "pivot_column",
    "read_problem",
    "result_to_dict",
    "solve_lcp",
    "write_problem",
    "write_result",
    "__version__",
]
