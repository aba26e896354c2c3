"""lemke: linear complementarity problems by Lemke's complementary pivoting method.

Public API: :func:`solve_lcp` (methods in ``METHODS``), :func:`solve_lcp_batch` (many LCPs
of one size in parallel threads), :func:`solve_mlcp` (mixed LCPs), :func:`solve_qp` (convex
QPs, with :class:`Certificate` when there is no optimum), their results :class:`LCPResult`,
:class:`LCPBatchResult`, :class:`MLCPResult`, :class:`QPResult`, :class:`Status`,
:class:`Options`, :class:`WarmStart`, :func:`pivot_column` (one step of the unrevised
method), and the checks :func:`is_lcp_solution` and :func:`is_lcp_ray`.
"""
from ._batch import solve_lcp_batch
from ._certify import is_lcp_ray, is_lcp_solution, lcp_residual
from ._lcp import METHODS, solve_lcp
from ._mlcp import MLCPResult, solve_mlcp
from ._options import Options
from ._pivot_column import pivot_column
from ._qp import Certificate, QPResult, solve_qp
from ._result import LCPBatchResult, LCPResult, WarmStart
from ._status import Status

__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "Certificate",
    "LCPBatchResult",
    "LCPResult",
    "MLCPResult",
    "Options",
    "QPResult",
    "Status",
    "WarmStart",
    "is_lcp_ray",
    "is_lcp_solution",
    "lcp_residual",
    "pivot_column",
    "solve_lcp",
    "solve_lcp_batch",
    "solve_mlcp",
    "solve_qp",
    "__version__",
]
