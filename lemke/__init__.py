"""lemke: linear complementarity problems by Lemke's complementary pivoting method.

Public API: :func:`solve_lcp` (methods in ``METHODS``), :class:`LCPResult`,
:func:`solve_lcp_batch` (many problems in parallel threads), :class:`LCPBatchResult`, :class:`Status`,
:class:`Options`, :class:`WarmStart`, :func:`pivot_column` (one step of the unrevised
method), and the checks :func:`is_lcp_solution` and :func:`is_lcp_ray`.
"""
from ._batch import solve_lcp_batch
from ._certify import is_lcp_ray, is_lcp_solution, lcp_residual
from ._lcp import METHODS, solve_lcp
from ._options import Options
from ._pivot_column import pivot_column
from ._result import LCPBatchResult, LCPResult, WarmStart
from ._status import Status

__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "LCPBatchResult",
    "LCPResult",
    "Options",
    "Status",
    "WarmStart",
    "is_lcp_ray",
    "is_lcp_solution",
    "lcp_residual",
    "pivot_column",
    "solve_lcp",
    "solve_lcp_batch",
    "__version__",
]
